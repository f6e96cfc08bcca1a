//! `mrpp data get movingai`: puts the MovingAI MAPF benchmark (33 maps, 25 random and 25 even
//! scenarios each) where `mrpp bench` configs find it, from movingai.com's archives or from
//! archives or folders the user already has, every file checked against the SHA-256 manifest in
//! the repository (`crates/mrpp-cli/movingai-manifest.tsv`, embedded).
//!
//! Rules, each an error naming the archive and file (exit 1) unless said otherwise:
//! - a file whose bytes match none of the manifest's checksums for its name;
//! - a file the manifest lists without a checksum (not verifiable): installed, with a warning;
//! - a `.map` or `.scen` file the manifest does not name (not part of the benchmark): skipped,
//!   with a warning; other entries (folders, READMEs) are ignored;
//! - an archive that is not a readable zip, or a download that fails (the hint: `--from`);
//! - two inputs with different bytes for one name;
//! - an existing file in `--into` with other bytes (skipped when identical; replaced with
//!   `--force`).
//!
//! Everything is read and checked before anything is written, so a failure writes nothing; each
//! file is then written through a temporary file renamed into place.

use std::collections::BTreeMap;
use std::io::Read as _;
use std::path::{Path, PathBuf};

use sha2::Digest as _;

use crate::output::{Fail, say};

/// The manifest: file, sha256 (`-` when unknown), bytes, sources; `#` lines are comments.
const MANIFEST: &str = include_str!("../movingai-manifest.tsv");

/// Where movingai.com keeps the benchmark's archives.
pub(crate) const DEFAULT_URL: &str = "https://movingai.com/benchmarks/mapf/";

/// The archives a download fetches, in order.
pub(crate) const ARCHIVES: [&str; 3] =
    ["mapf-map.zip", "mapf-scen-random.zip", "mapf-scen-even.zip"];

#[derive(clap::Subcommand)]
pub(crate) enum Data {
    /// Download (or unpack from --from) a benchmark and check every file against the checksums
    /// in the repository; files go flat into --into, where the bundled bench configs look.
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp data get movingai\n  mrpp data get movingai --from mapf-map.zip --from mapf-scen-random.zip --into data/movingai"
    )]
    Get(GetArgs),
}

/// The benchmarks `mrpp data get` knows.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub(crate) enum Dataset {
    /// The MovingAI MAPF benchmark (Stern et al., SoCS 2019).
    Movingai,
}

#[derive(clap::Args)]
pub(crate) struct GetArgs {
    /// The benchmark.
    dataset: Dataset,
    /// The folder the files go to (flat: NAME.map, NAME-random-K.scen, NAME-even-K.scen).
    #[arg(long, default_value = "data/movingai")]
    into: PathBuf,
    /// Unpack these instead of downloading: zip archives, or folders searched for .map, .scen
    /// and .zip files (repeatable).
    #[arg(long, value_name = "FILE.zip|DIR")]
    from: Vec<PathBuf>,
    /// Where the archives are downloaded from (their names are appended).
    #[arg(long, value_name = "BASE", default_value = DEFAULT_URL, conflicts_with = "from")]
    url: String,
    /// Replace existing files whose bytes differ (they are an error otherwise).
    #[arg(long)]
    force: bool,
}

/// One manifest line's claim on a name: its checksum (None: unknown).
type Manifest = BTreeMap<String, Vec<Option<String>>>;

fn manifest() -> Manifest {
    let mut m = Manifest::new();
    for line in MANIFEST
        .lines()
        .filter(|l| !l.starts_with('#') && !l.is_empty())
    {
        let mut f = line.split('\t');
        let (Some(name), Some(sha)) = (f.next(), f.next()) else {
            continue;
        };
        m.entry(name.to_string())
            .or_default()
            .push((sha != "-").then(|| sha.to_string()));
    }
    m
}

/// A file found in an input: its name (no folders), its bytes, and where it came from.
struct Found {
    name: String,
    bytes: Vec<u8>,
    origin: String,
}

/// `mrpp data get`.
pub(crate) fn run(args: GetArgs) -> Result<u8, Fail> {
    let Dataset::Movingai = args.dataset;
    let mut found = Vec::new();
    if args.from.is_empty() {
        for archive in ARCHIVES {
            let url = format!("{}/{archive}", args.url.trim_end_matches('/'));
            let bytes = download(&url)?;
            unzip(&url, &bytes, &mut found)?;
        }
    } else {
        for from in &args.from {
            read_input(from, &mut found)?;
        }
    }
    install(found, &args.into, args.force)
}

/// Reads a zip archive or a folder (recursively: .map, .scen, .zip).
fn read_input(path: &Path, found: &mut Vec<Found>) -> Result<(), Fail> {
    let meta = std::fs::metadata(path)
        .map_err(|e| Fail(format!("{}: cannot read: {e}", path.display())))?;
    if meta.is_dir() {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(path)
            .map_err(|e| Fail(format!("{}: cannot read the folder: {e}", path.display())))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .collect();
        entries.sort();
        for p in entries {
            let ext = p.extension().and_then(|e| e.to_str()).unwrap_or("");
            if p.is_dir() || ext == "zip" {
                read_input(&p, found)?;
            } else if ext == "map" || ext == "scen" {
                let bytes = std::fs::read(&p)
                    .map_err(|e| Fail(format!("{}: cannot read: {e}", p.display())))?;
                found.push(Found {
                    name: file_name(&p),
                    bytes,
                    origin: p.display().to_string(),
                });
            }
        }
        return Ok(());
    }
    let bytes =
        std::fs::read(path).map_err(|e| Fail(format!("{}: cannot read: {e}", path.display())))?;
    unzip(&path.display().to_string(), &bytes, found)
}

fn file_name(p: &Path) -> String {
    p.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// The .map and .scen files of a zip archive (`archive` names it in messages).
fn unzip(archive: &str, bytes: &[u8], found: &mut Vec<Found>) -> Result<(), Fail> {
    let bad = |e: &dyn std::fmt::Display| {
        Fail(format!(
            "{archive}: not a readable zip archive ({e}); download it again"
        ))
    };
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(bytes)).map_err(|e| bad(&e))?;
    let mut stage = Stage::new(
        zip.len() as u64,
        &format!("unpack {}", short(archive)),
        Some("entries"),
    );
    for i in 0..zip.len() {
        stage.inc(1);
        let mut entry = zip.by_index(i).map_err(|e| bad(&e))?;
        if entry.is_dir() {
            continue;
        }
        let entry_name = entry.name().map_err(|e| bad(&e))?.into_owned();
        let path = PathBuf::from(&entry_name);
        let name = file_name(&path);
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        // macOS resource forks (`__MACOSX/._NAME.map`) are not files of the benchmark.
        if !(ext == "map" || ext == "scen") || name.starts_with("._") {
            continue;
        }
        let mut data = Vec::with_capacity(entry.size().min(1 << 26) as usize);
        entry.read_to_end(&mut data).map_err(|e| {
            Fail(format!(
                "{archive}: {entry_name}: cannot unpack ({e}); the archive is damaged: download \
                 it again"
            ))
        })?;
        found.push(Found {
            origin: format!("{archive}: {entry_name}"),
            name,
            bytes: data,
        });
    }
    stage.finish();
    Ok(())
}

/// The last part of a path or URL, for progress lines.
fn short(s: &str) -> &str {
    s.rsplit(['/', '\\']).next().unwrap_or(s)
}

/// The progress of one stage (a download, an archive unpacked, the files verified, the files
/// written) on stderr: an indicatif bar on a terminal under `--progress auto`; under `--progress
/// plain`, a line every half second while it runs and one when it ends (`[0.4 s] unpack
/// mapf-map.zip: 34/34 entries`); nothing under `--quiet`, `--progress none` or when stderr is
/// not a terminal (auto), or for a stage of no files.
struct Stage {
    bar: indicatif::ProgressBar,
    plain: Option<Plain>,
}

/// `--progress plain`'s state of a [`Stage`].
struct Plain {
    what: String,
    /// `None`: bytes.
    unit: Option<&'static str>,
    len: u64,
    done: u64,
    started: std::time::Instant,
    next: std::time::Instant,
    /// `done` when the last line was printed.
    printed: Option<u64>,
}

impl Plain {
    fn line(&mut self) {
        let count = match self.unit {
            Some(unit) => format!("{}/{} {unit}", self.done, self.len),
            // A download without a Content-Length: its size unknown.
            None if self.len == 0 => format!("{}", indicatif::HumanBytes(self.done)),
            None => format!(
                "{}/{}",
                indicatif::HumanBytes(self.done),
                indicatif::HumanBytes(self.len)
            ),
        };
        eprintln!(
            "[{:.1} s] {}: {count}",
            self.started.elapsed().as_secs_f64(),
            self.what
        );
        self.printed = Some(self.done);
    }
}

impl Stage {
    /// A stage of `len` `unit`s (`None`: bytes) that `what` names.
    fn new(len: u64, what: &str, unit: Option<&'static str>) -> Self {
        use crate::progress::{Mode, mode};
        use indicatif::{ProgressBar, ProgressStyle};
        let wanted = crate::output::verbosity() >= 1 && (len > 0 || unit.is_none());
        let plain = (wanted && mode() == Mode::Plain).then(|| {
            let started = std::time::Instant::now();
            Plain {
                what: what.to_string(),
                unit,
                len,
                done: 0,
                started,
                next: started + PLAIN_EVERY,
                printed: None,
            }
        });
        let shown =
            wanted && mode() == Mode::Auto && std::io::IsTerminal::is_terminal(&std::io::stderr());
        if !shown {
            return Stage {
                bar: ProgressBar::hidden(),
                plain,
            };
        }
        let bar = ProgressBar::new(len);
        let template = match unit {
            None => "{bar:40} {bytes}/{total_bytes} {prefix}  {elapsed_precise} (eta {eta})",
            Some(_) => "{bar:40} {pos}/{len} {prefix}  {elapsed_precise}",
        };
        bar.set_style(ProgressStyle::with_template(template).expect("static template"));
        bar.set_prefix(what.to_string());
        Stage { bar, plain }
    }

    /// `n` more done.
    fn inc(&mut self, n: u64) {
        self.bar.inc(n);
        if let Some(p) = &mut self.plain {
            p.done += n;
            let now = std::time::Instant::now();
            if now >= p.next {
                p.next = now + PLAIN_EVERY;
                p.line();
            }
        }
    }

    /// Clears the bar; the final plain line.
    fn finish(self) {
        self.bar.finish_and_clear();
        if let Some(mut p) = self.plain
            && p.printed != Some(p.done)
        {
            p.line();
        }
    }
}

/// How often `--progress plain` reports a running stage.
const PLAIN_EVERY: std::time::Duration = std::time::Duration::from_millis(500);

/// A reader that counts what it reads into a [`Stage`].
#[cfg(feature = "download")]
struct Counting<'a, R> {
    inner: R,
    stage: &'a mut Stage,
}

#[cfg(feature = "download")]
impl<R: std::io::Read> std::io::Read for Counting<'_, R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.stage.inc(n as u64);
        Ok(n)
    }
}

/// The bytes at `url`.
#[cfg(feature = "download")]
fn download(url: &str) -> Result<Vec<u8>, Fail> {
    let failed = |e: &dyn std::fmt::Display| {
        Fail(format!(
            "{url}: cannot download ({e}); on a machine without internet access, download the \
             archives elsewhere ({}) and unpack them with --from FILE.zip",
            ARCHIVES.join(", ")
        ))
    };
    say!("downloading {url}");
    let mut response = ureq::get(url).call().map_err(|e| failed(&e))?;
    let len = response.body().content_length().unwrap_or(0);
    let mut stage = Stage::new(len, &format!("download {}", short(url)), None);
    let mut reader = Counting {
        inner: response.body_mut().as_reader(),
        stage: &mut stage,
    };
    let mut bytes = Vec::with_capacity(len.min(1 << 30) as usize);
    reader.read_to_end(&mut bytes).map_err(|e| failed(&e))?;
    stage.finish();
    Ok(bytes)
}

/// Without the `download` feature: only `--from`.
#[cfg(not(feature = "download"))]
fn download(url: &str) -> Result<Vec<u8>, Fail> {
    Err(Fail(format!(
        "{url}: this mrpp was built without downloads (cargo feature `download` of mrpp-cli, on \
         by default); build it with `--features download`, or unpack archives you have with \
         --from FILE.zip"
    )))
}

fn sha256_hex(bytes: &[u8]) -> String {
    sha2::Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Checks every file, then writes those that are new or differ (with `force`).
fn install(found: Vec<Found>, into: &Path, force: bool) -> Result<u8, Fail> {
    let manifest = manifest();
    // name -> (bytes, origin), the first input that gave it.
    let mut chosen: BTreeMap<String, (Vec<u8>, String)> = BTreeMap::new();
    let (mut unknown, mut unverified) = (Vec::new(), 0usize);
    let mut stage = Stage::new(found.len() as u64, "verify", Some("files"));
    for f in found {
        stage.inc(1);
        let Some(sums) = manifest.get(&f.name) else {
            unknown.push(f.origin);
            continue;
        };
        let sha = sha256_hex(&f.bytes);
        if sums.iter().any(Option::is_none) {
            unverified += 1;
        } else if !sums.iter().flatten().any(|s| *s == sha) {
            return Err(Fail(format!(
                "{}: checksum mismatch: SHA-256 {sha}, the manifest expects {} (the file is \
                 damaged or not the benchmark's; nothing was written)",
                f.origin,
                sums.iter()
                    .flatten()
                    .cloned()
                    .collect::<Vec<_>>()
                    .join(" or ")
            )));
        }
        if let Some((bytes, origin)) = chosen.get(&f.name) {
            if *bytes != f.bytes {
                return Err(Fail(format!(
                    "{}: differs from {origin}, which has the same name (nothing was written)",
                    f.origin
                )));
            }
            continue;
        }
        chosen.insert(f.name, (f.bytes, f.origin));
    }
    stage.finish();
    for origin in &unknown {
        eprintln!("mrpp: warning: {origin}: not a file of the benchmark's manifest: skipped");
    }
    if chosen.is_empty() {
        return Err(Fail(
            "no file of the benchmark was found in the inputs (.map and .scen files, in zip \
             archives or folders)"
                .into(),
        ));
    }
    // Existing files: identical ones are skipped, differing ones refused unless --force.
    let mut write = Vec::new();
    let mut same = 0usize;
    for (name, (bytes, origin)) in &chosen {
        let target = into.join(name);
        match std::fs::read(&target) {
            Ok(old) if old == *bytes => same += 1,
            Ok(_) if !force => {
                return Err(Fail(format!(
                    "{}: exists with other bytes than {origin} (nothing was written; --force \
                     replaces it)",
                    target.display()
                )));
            }
            _ => write.push((target, bytes)),
        }
    }
    if !write.is_empty() {
        std::fs::create_dir_all(into)
            .map_err(|e| Fail(format!("{}: cannot create the folder: {e}", into.display())))?;
    }
    let mut stage = Stage::new(write.len() as u64, "write", Some("files"));
    for (target, bytes) in &write {
        write_new(target, bytes)?;
        stage.inc(1);
    }
    stage.finish();
    if unverified > 0 {
        eprintln!(
            "mrpp: warning: {unverified} file(s) have no checksum in the manifest (see its \
             header) and were installed unverified"
        );
    }
    let present = manifest
        .keys()
        .filter(|n| into.join(n.as_str()).is_file())
        .count();
    say!(
        "{} file(s) written, {same} already there, {} skipped; {present} of the benchmark's {} \
         files are in {}",
        write.len(),
        unknown.len(),
        manifest.len(),
        into.display()
    );
    Ok(0)
}

/// Writes `bytes` to `target` through a temporary file in the same folder renamed into place.
fn write_new(target: &Path, bytes: &[u8]) -> Result<(), Fail> {
    let cannot = |e: std::io::Error| Fail(format!("{}: cannot write: {e}", target.display()));
    let dir = target.parent().unwrap_or(Path::new("."));
    let tmp = dir.join(format!(".{}.tmp{}", file_name(target), std::process::id()));
    std::fs::write(&tmp, bytes).map_err(cannot)?;
    std::fs::rename(&tmp, target).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        cannot(e)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The manifest names the whole benchmark: 33 maps, 25 random and 25 even scenarios each,
    /// every checksum 64 hex digits or `-`.
    #[test]
    fn manifest_covers_the_benchmark() {
        let m = manifest();
        assert_eq!(m.len(), 33 * 51);
        assert_eq!(m.keys().filter(|n| n.ends_with(".map")).count(), 33);
        for (name, sums) in &m {
            for s in sums.iter().flatten() {
                assert!(
                    s.len() == 64 && s.bytes().all(|b| b.is_ascii_hexdigit()),
                    "{name}: {s}"
                );
            }
        }
        let unknown = m.values().filter(|s| s.iter().any(Option::is_none)).count();
        assert_eq!(unknown, 74);
    }
}
