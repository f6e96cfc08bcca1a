//! What every command shares on the way out: the one error type (exit 1, one line), atomic file
//! writes, time limits, and the one-line summaries of metrics.

use std::path::Path;
use std::time::Duration;

use serde_json::{Map, Value};

/// How much commands print: 0 = `--quiet` (errors only, on stderr, and what a command exists to
/// print: `planners`, `info`, `completions`), 1 = the default summaries, 2 and more = `-v`.
static VERBOSITY: std::sync::atomic::AtomicU8 = std::sync::atomic::AtomicU8::new(1);

/// Sets the level from `--quiet` and the number of `-v`.
pub(crate) fn set_verbosity(quiet: bool, verbose: u8) {
    let level = if quiet { 0 } else { 1 + verbose.min(2) };
    VERBOSITY.store(level, std::sync::atomic::Ordering::Relaxed);
}

/// The level [`set_verbosity`] set (1 when it was not called).
pub(crate) fn verbosity() -> u8 {
    VERBOSITY.load(std::sync::atomic::Ordering::Relaxed)
}

/// One line on stdout, always: what a command exists to print (`planners`, `info`). A closed
/// stdout (`mrpp planners | head`) is not an error: the command still finishes its work.
macro_rules! out {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout().lock(), $($t)*);
    }};
}
pub(crate) use out;

/// One line on stdout unless `--quiet`: the summaries and "written to" lines of every command.
macro_rules! say {
    ($($t:tt)*) => {
        if $crate::output::verbosity() >= 1 {
            $crate::output::out!($($t)*);
        }
    };
}
pub(crate) use say;

/// One line on stdout with `-v` only: resolved parameters, load times, a planner's full notes.
macro_rules! detail {
    ($($t:tt)*) => {
        if $crate::output::verbosity() >= 2 {
            $crate::output::out!($($t)*);
        }
    };
}
pub(crate) use detail;

/// A failure that ends the command with exit code 1 and one message.
pub(crate) struct Fail(pub(crate) String);

impl<E: std::fmt::Display> From<E> for Fail {
    fn from(e: E) -> Self {
        Fail(e.to_string())
    }
}

/// Largest accepted `--time-limit`, in seconds (about 115 days), shared by every command.
pub(crate) const MAX_TIME_LIMIT: f64 = 1e7;

/// A `--time-limit` in seconds, checked: positive, finite, at most [`MAX_TIME_LIMIT`].
pub(crate) fn time_limit(value: f64) -> Result<Duration, Fail> {
    seconds("time-limit", value)
}

/// The value of the flag `--<flag>` in seconds, checked: positive, finite, at most
/// [`MAX_TIME_LIMIT`] (the one cap every duration flag shares).
pub(crate) fn seconds(flag: &str, value: f64) -> Result<Duration, Fail> {
    if !(value.is_finite() && value > 0.0 && value <= MAX_TIME_LIMIT) {
        return Err(Fail(format!(
            "--{flag} must be more than 0 and at most {MAX_TIME_LIMIT:e} seconds (about 115 \
             days), got {value:?}"
        )));
    }
    Ok(Duration::from_secs_f64(value))
}

/// Writes `contents` to `path`, the one way every command writes a file:
///
/// - `-`: to stdout;
/// - an existing FIFO, device or other special file (`/dev/null`, `/dev/stdout`): in place, so it
///   stays what it is;
/// - a symbolic link: through to the file it names (the link stays);
/// - otherwise through a temporary file in the same folder renamed over `path`, so a reader
///   never sees half a file and an interrupted write leaves the old file.
///
/// A file this command read (or declared it would read) is never written: the check of
/// [`check_output`] is made again here, after the work, for every file written.
pub(crate) fn write_atomic(path: &Path, contents: impl AsRef<[u8]>) -> Result<(), Fail> {
    use std::io::Write as _;
    let cannot = |e: std::io::Error| Fail(format!("{}: cannot write: {e}", path.display()));
    if path.as_os_str() == "-" {
        let mut out = std::io::stdout().lock();
        return out
            .write_all(contents.as_ref())
            .and_then(|()| out.flush())
            .map_err(cannot);
    }
    if std::fs::metadata(path).is_ok_and(|m| m.is_dir()) {
        return Err(Fail(format!("{}: is a folder, not a file", path.display())));
    }
    if !in_place(path)
        && let Some(why) = harms_an_input(path)
    {
        return Err(Fail(why));
    }
    if in_place(path) {
        // Truncated when it is a regular file behind `/dev/stdout` (a shell redirection).
        let regular = std::fs::metadata(path).is_ok_and(|m| m.is_file());
        return std::fs::OpenOptions::new()
            .write(true)
            .truncate(regular)
            .open(path)
            .and_then(|mut f| f.write_all(contents.as_ref()))
            .map_err(cannot);
    }
    let target = match std::fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => std::fs::canonicalize(path).map_err(cannot)?,
        _ => path.to_path_buf(),
    };
    let dir = target
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = target
        .file_name()
        .ok_or_else(|| Fail(format!("{}: not a file name", path.display())))?;
    let tmp = dir.join(format!(
        ".{}.tmp{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    std::fs::write(&tmp, contents.as_ref()).map_err(cannot)?;
    std::fs::rename(&tmp, &target).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        cannot(e)
    })
}

/// Whether `path` is written in place rather than replaced: a device, FIFO or socket
/// (`/dev/null`), and the process's own streams (`/dev/stdout`, `/dev/fd/N`, `/proc/self/fd/N`),
/// which may name a pipe or a file the shell opened (replacing that file would lose the output).
fn in_place(path: &Path) -> bool {
    path.starts_with("/dev/")
        || path.starts_with("/proc/self/fd/")
        || std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// Notes `paths` (files or folders) as inputs of this command before it reads them, with the
/// files they refer to when the caller lists those too (a League of Robot Runners problem's map,
/// agents and tasks, a formation file's polygon map: see [`crate::family::Inputs::read_set`]).
/// Every file read later through `mrpp_core::error::read_file` is added by the library itself
/// ([`mrpp_core::files_read`]). [`check_output`], [`check_output_folder`] and [`write_atomic`]
/// refuse all of them: the one rule every verb's outputs follow.
pub(crate) fn declare_inputs<'a>(paths: impl IntoIterator<Item = &'a Path>) {
    mrpp_core::files_read::start_recording();
    for p in paths {
        mrpp_core::files_read::note(p);
    }
}

/// The one guard of every verb's outputs, called before any work: declares `inputs` (files or
/// folders, with the files they refer to; see [`declare_inputs`]) and checks each of `outs` as a
/// file ([`check_output`]).
pub(crate) fn guard<'a>(
    inputs: impl IntoIterator<Item = &'a Path>,
    outs: &[&Path],
) -> Result<(), Fail> {
    declare_inputs(inputs);
    outs.iter().try_for_each(|o| check_output(o))
}

/// The input that writing `out` would harm, as a message: the same file as an input (however it
/// is named: relative paths, `..`, symbolic and hard links), or a file inside an input folder.
fn harms_an_input(out: &Path) -> Option<String> {
    if let Some(input) = mrpp_core::files_read::find(out) {
        return Some(format!(
            "{}: the output would overwrite the input {}; choose another output",
            out.display(),
            input.display()
        ));
    }
    let target = resolved(out);
    mrpp_core::files_read::inputs()
        .into_iter()
        .filter(|(_, folder)| *folder)
        .find(|(dir, _)| std::fs::canonicalize(dir).is_ok_and(|d| target.starts_with(d)))
        .map(|(dir, _)| {
            format!(
                "{}: the output would be written inside the input folder {}; choose another output",
                out.display(),
                dir.display()
            )
        })
}

/// `path` with its longest existing prefix canonicalised (symbolic links and `..` resolved) and
/// the rest appended as given: where a file or folder not made yet would go.
fn resolved(path: &Path) -> std::path::PathBuf {
    let mut rest = Vec::new();
    let mut head = path;
    loop {
        if let Ok(c) = std::fs::canonicalize(if head.as_os_str().is_empty() {
            Path::new(".")
        } else {
            head
        }) {
            return rest.iter().rev().fold(c, |acc, part| acc.join(part));
        }
        match (head.parent(), head.file_name()) {
            (Some(parent), Some(name)) => {
                rest.push(name.to_os_string());
                head = parent;
            }
            _ => return path.to_path_buf(),
        }
    }
}

/// Checks, before any work, that `out` can be written and harms no input of the command (see
/// [`declare_inputs`]): an input file, however it is named, is refused, as are a missing or
/// read-only folder, a folder given as a file, and a special file that cannot be opened for
/// writing. `-` (stdout) and FIFOs pass without a probe (opening a FIFO would wait for a reader).
pub(crate) fn check_output(out: &Path) -> Result<(), Fail> {
    if out.as_os_str() == "-" {
        return Ok(());
    }
    if !in_place(out)
        && let Some(why) = harms_an_input(out)
    {
        return Err(Fail(why));
    }
    if in_place(out) {
        #[cfg(unix)]
        if std::fs::metadata(out)
            .is_ok_and(|m| std::os::unix::fs::FileTypeExt::is_fifo(&m.file_type()))
        {
            return Ok(());
        }
        return std::fs::OpenOptions::new()
            .write(true)
            .open(out)
            .map(|_| ())
            .map_err(|e| Fail(format!("{}: cannot write: {e}", out.display())));
    }
    let target = std::fs::canonicalize(out).unwrap_or_else(|_| out.to_path_buf());
    match std::fs::metadata(&target) {
        Ok(m) if m.is_dir() => {
            return Err(Fail(format!("{}: is a folder, not a file", out.display())));
        }
        // An existing file must be writable itself (e.g. not /proc/version); opening it for
        // writing without truncating leaves it as it is.
        Ok(_) => {
            std::fs::OpenOptions::new()
                .write(true)
                .open(&target)
                .map_err(|e| Fail(format!("{}: cannot write: {e}", out.display())))?;
        }
        Err(_) => {}
    }
    let dir = target
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    probe_folder(dir).map_err(|e| {
        Fail(format!(
            "{}: cannot write: no file can be made in {} ({e})",
            out.display(),
            dir.display()
        ))
    })
}

/// Checks, before any work, that the output folder `dir` exists or can be made, that files can
/// be written in it, and that it harms no input (see [`declare_inputs`]): it may not be an input
/// folder or lie inside one (an experiment's `--data`), and may not hold an input file or folder.
pub(crate) fn check_output_folder(dir: &Path) -> Result<(), Fail> {
    let fail =
        |e: std::io::Error| Fail(format!("{}: cannot write output here: {e}", dir.display()));
    if dir.exists() && !dir.is_dir() {
        return Err(Fail(format!("{}: is a file, not a folder", dir.display())));
    }
    let target = resolved(dir);
    for (input, folder) in mrpp_core::files_read::inputs() {
        let Ok(at) = std::fs::canonicalize(&input) else {
            continue;
        };
        if folder && target.starts_with(&at) {
            return Err(Fail(format!(
                "{}: the output folder is (inside) the input folder {}; choose another output folder",
                dir.display(),
                input.display()
            )));
        }
        if at.starts_with(&target) {
            return Err(Fail(format!(
                "{}: the output folder holds the input {}; choose another output folder",
                dir.display(),
                input.display()
            )));
        }
    }
    std::fs::create_dir_all(dir).map_err(fail)?;
    probe_folder(dir).map_err(fail)
}

/// Creates and removes a probe file in `dir`.
fn probe_folder(dir: &Path) -> std::io::Result<()> {
    if !dir.is_dir() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::NotFound,
            format!("no folder {}", dir.display()),
        ));
    }
    let probe = dir.join(format!(".mrpp-probe{}", std::process::id()));
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)?;
    std::fs::remove_file(&probe)
}

/// The plan format an `--out` path asks for by its extension: `.json` (or stdout `-`, a device,
/// FIFO or stream such as `/dev/null` or `/dev/stdout`, or no `--out`) the plan envelope, `.txt` or `.lacam` LaCAM text;
/// any other extension is refused (name the format with `--format`).
pub(crate) fn format_of(out: Option<&Path>) -> Result<crate::family::Format, Fail> {
    use crate::family::Format;
    let Some(out) = out.filter(|o| o.as_os_str() != "-" && !in_place(o)) else {
        return Ok(Format::Json);
    };
    let ext = out
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    match ext.as_str() {
        "json" => Ok(Format::Json),
        "txt" | "lacam" => Ok(Format::Lacam),
        _ => Err(Fail(format!(
            "{}: cannot tell the plan format from `{}`: use .json (plan envelope), .txt or .lacam \
             (LaCAM text), or --format json|lacam",
            out.display(),
            if ext.is_empty() {
                "no extension".to_string()
            } else {
                format!(".{ext}")
            }
        ))),
    }
}

/// `--agents` and other counts: a whole number from 1 (clap's parser for them, so that `-5` is
/// named as a bad value of its option rather than an unknown flag).
pub(crate) fn parse_count(s: &str) -> Result<usize, String> {
    match s.trim().parse::<i128>() {
        Ok(n) if n >= 1 && n <= usize::MAX as i128 => Ok(n as usize),
        Ok(n) => Err(format!("must be a whole number from 1, got {n}")),
        Err(_) => Err(format!("must be a whole number from 1, got `{s}`")),
    }
}

/// Counts that may be 0 (e.g. `gen continuous --obstacles`): a whole number from 0.
pub(crate) fn parse_whole(s: &str) -> Result<usize, String> {
    match s.trim().parse::<i128>() {
        Ok(n) if n >= 0 && n <= usize::MAX as i128 => Ok(n as usize),
        Ok(n) => Err(format!("must be a whole number from 0, got {n}")),
        Err(_) => Err(format!("must be a whole number from 0, got `{s}`")),
    }
}

/// `--seed`: a whole number from 0 to 2^64 - 1.
pub(crate) fn parse_seed(s: &str) -> Result<u64, String> {
    match s.trim().parse::<i128>() {
        Ok(n) if (0..=u64::MAX as i128).contains(&n) => Ok(n as u64),
        Ok(n) => Err(format!(
            "must be a whole number from 0 to 2^64 - 1, got {n}"
        )),
        Err(_) => Err(format!(
            "must be a whole number from 0 to 2^64 - 1, got `{s}`"
        )),
    }
}

/// The last component of `path` (what outputs record).
pub(crate) fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// `key value | key value ...` of a JSON object's short values (strings over 40 characters,
/// arrays and objects left out), in the object's order; numbers as [`number`] writes them.
pub(crate) fn pairs(values: &Map<String, Value>) -> String {
    values
        .iter()
        .filter_map(|(k, v)| match v {
            Value::String(s) if s.len() <= 40 => Some(format!("{k} {s}")),
            Value::Number(n) => Some(format!("{k} {}", number(n.as_f64()?))),
            Value::Bool(_) => Some(format!("{k} {v}")),
            _ => None,
        })
        .collect::<Vec<_>>()
        .join(" | ")
}

/// A number for a person: whole numbers as they are, others with 1 decimal from 100 on, 2 from
/// 1 on and 3 below (files keep every digit; summaries need no 16).
pub(crate) fn number(v: f64) -> String {
    if v.fract() == 0.0 && v.abs() < 1e15 {
        format!("{v:.0}")
    } else if v.abs() >= 100.0 {
        format!("{v:.1}")
    } else if v.abs() >= 1.0 {
        format!("{v:.2}")
    } else {
        format!("{v:.3}")
    }
}

/// [`pairs`] of a solved plan's metrics, each with its lower bound and the excess over it where
/// the problem knows one (`sum_of_costs 2892 (lower bound 2185, +32.4%)`).
pub(crate) fn metrics_with_bounds(metrics: &Map<String, Value>, bounds: &[(&str, f64)]) -> String {
    metrics
        .iter()
        .filter_map(|(k, v)| {
            let text = pairs(&Map::from_iter([(k.clone(), v.clone())]));
            if text.is_empty() {
                return None;
            }
            let bound = bounds.iter().find(|(name, _)| name == k).map(|b| b.1);
            Some(match (bound, v.as_f64()) {
                (Some(b), Some(x)) if b > 0.0 => format!(
                    "{text} (lower bound {}, +{:.1}%)",
                    number(b),
                    (x / b - 1.0) * 100.0
                ),
                (Some(b), Some(_)) => format!("{text} (lower bound {})", number(b)),
                _ => text,
            })
        })
        .collect::<Vec<_>>()
        .join(" | ")
}

/// The metrics of a problem family as a JSON object (field order kept).
pub(crate) fn metrics_object<M: serde::Serialize>(m: &M) -> Map<String, Value> {
    match serde_json::to_value(m) {
        Ok(Value::Object(o)) => o,
        _ => Map::new(),
    }
}

/// A value parser that accepts any text (the command checks it, with its own message) but offers
/// `names` to shell completion (`mrpp completions`), so `--planner <TAB>` lists the planners
/// instead of file names.
#[derive(Clone)]
pub(crate) struct Offer(pub(crate) fn() -> Vec<&'static str>);

impl clap::builder::TypedValueParser for Offer {
    type Value = String;
    fn parse_ref(
        &self,
        _cmd: &clap::Command,
        _arg: Option<&clap::Arg>,
        value: &std::ffi::OsStr,
    ) -> Result<String, clap::Error> {
        Ok(value.to_string_lossy().into_owned())
    }
    fn possible_values(
        &self,
    ) -> Option<Box<dyn Iterator<Item = clap::builder::PossibleValue> + '_>> {
        Some(Box::new(
            (self.0)()
                .into_iter()
                .map(|n| clap::builder::PossibleValue::new(n).hide(false)),
        ))
    }
}

/// Every planner name of every family (for [`Offer`]).
pub(crate) fn planner_names() -> Vec<&'static str> {
    crate::family::FAMILIES
        .iter()
        .flat_map(|f| f.planners().into_iter().map(|(name, _, _)| name))
        .collect()
}

/// Every family name (for [`Offer`]).
pub(crate) fn family_names() -> Vec<&'static str> {
    crate::family::FAMILIES.iter().map(|f| f.name()).collect()
}
