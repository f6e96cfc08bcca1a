//! The run harness: a sweep is a fixed list of jobs; the harness runs them (all, or one shard),
//! in parallel with rayon, and turns their rows into the sweep's outputs.
//!
//! - **Order and seeds.** Jobs are numbered in the sweep's fixed order; each job draws its seeds
//!   from the user's seed and the job's key (never from a thread or an execution order), so rows
//!   do not depend on the thread count or on the sharding.
//! - **Shards.** `--shard i/N` runs the jobs whose number is `i - 1` modulo `N` (round robin, so
//!   each shard gets a fair mix of cheap and costly jobs) and writes `part-i-of-N.jsonl` (one line
//!   per job: its number, key and row) beside `manifest-i-of-N.json`. The N shards can run as
//!   Slurm array tasks or with GNU parallel, into one folder or several.
//! - **Merge.** [`merge_parts`] reads the parts back, checks that they come from one sweep (same
//!   command apart from `--shard`/`--out`, same N) and cover every job exactly once, and returns
//!   the rows in job order: the outputs built from them equal those of the unsharded run (apart
//!   from wall-clock times).
//! - **Records.** Every sweep also writes `records.csv`, one validated run per line in one schema
//!   for all sweeps ([`RunRecord`]), and `manifest.json`: the command, seed, version, shard and
//!   thread count that made the folder.
//!
//! The harness never prints and never writes: it returns files for the binary to write.

use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::time::Instant;

use rayon::prelude::*;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use mrpp_core::error::{Error, Result, read_file};

/// A shard `index` of `count` (1-based); `1/1` is the whole sweep.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl Shard {
    /// The whole sweep.
    pub const ALL: Shard = Shard { index: 1, count: 1 };

    /// Whether job number `job` (0-based) belongs to this shard.
    pub fn owns(&self, job: usize) -> bool {
        job % self.count == self.index - 1
    }

    /// `true` for `1/1`.
    pub fn is_all(&self) -> bool {
        self.count == 1
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for Shard {
    type Err = String;
    /// `i/N` with `1 <= i <= N <= 100000`.
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let bad = || format!("expected a shard i/N with 1 <= i <= N (e.g. 2/8), got `{s}`");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count): (usize, usize) = (
            i.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        if index == 0 || index > count || count > 100_000 {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

/// One validated run in the schema every sweep shares (`records.csv`). The columns after `note`
/// were added later (issue 31): files written before read them as empty.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct RunRecord {
    /// The job's number in its sweep.
    pub job: usize,
    /// The job's key (also the key its seeds derive from).
    pub key: String,
    pub family: String,
    /// The instance, as the sweep names it (e.g. `sc1/6`, `random-32-32-20/a50`).
    pub instance: String,
    pub planner: String,
    /// `key=value` parameters, `;`-separated, in key order.
    pub params: String,
    pub run: usize,
    pub seed: u64,
    /// `solved`, `time_limit`, `memory_limit`, `gave_up`; for peers also `invalid` (a plan
    /// mrpp's validator refuses) and `peer_failed` (the command did not run or exited non-zero
    /// without a result). An invalid plan of mrpp's own stops the sweep.
    pub status: String,
    pub sum_of_costs: Option<u64>,
    pub makespan: Option<u64>,
    pub sum_of_moves: Option<u64>,
    /// Wall time of the planner (machine-dependent).
    pub runtime_ms: f64,
    /// Why a peer failed (`peer_failed`): its exit status and the first lines of its stderr;
    /// empty otherwise. The columns after it were added later, each with a default, so older
    /// `records.csv` files still read.
    #[serde(default)]
    pub note: String,
    /// Milliseconds to the first plan: the planner's own count when it reports one (LaCAM\*'s
    /// `first_solution_ms`, a peer's `comp_time_initial_solution`), else `runtime_ms` of a
    /// solved run; empty when unsolved or where a sweep does not measure it.
    #[serde(default)]
    pub first_solution_ms: Option<f64>,
    /// Sum of loss of the plan ([`mrpp_core::mapf::plan::path_loss`] summed; MAPF sweeps).
    #[serde(default)]
    pub sum_of_loss: Option<u64>,
    /// The sum of every agent's shortest-path distance to its goal, alone on the map: a lower
    /// bound of both the sum of costs and the sum of loss (MAPF sweeps).
    #[serde(default)]
    pub lower_bound: Option<u64>,
    /// The longest of those distances: a lower bound of the makespan (MAPF sweeps).
    #[serde(default)]
    pub makespan_lower_bound: Option<u64>,
    /// `sum_of_costs / lower_bound` (1 = optimal for every agent alone).
    #[serde(default)]
    pub sum_of_costs_ratio: Option<f64>,
    /// `sum_of_loss / lower_bound`.
    #[serde(default)]
    pub sum_of_loss_ratio: Option<f64>,
    /// Peak memory of the run in MB (10^6 bytes): for mrpp's planners the most heap bytes live
    /// during the run above those live at its start ([`mrpp_core::memory::peak_bytes`]; recorded
    /// only with `--jobs 1`, as the count is process-wide); for a peer the peak resident set
    /// of its process (`ru_maxrss`). Empty where a sweep does not measure it.
    #[serde(default)]
    pub peak_memory_mb: Option<f64>,
}

/// A sweep: a fixed list of jobs, how to run one, and what its outputs are.
pub trait Sweep: Sync {
    type Job: Sync;
    type Row: Serialize + DeserializeOwned + Send;
    /// The sweep's name, e.g. `hstar-table2`.
    fn name(&self) -> &str;
    /// Every job, in the sweep's fixed order.
    fn jobs(&self) -> &[Self::Job];
    /// A job's key: unique in the sweep, stable across versions (seeds derive from it).
    fn key(&self, job: &Self::Job) -> String;
    /// Runs one job; every plan it makes goes through `mrpp_core::solve`/`accept`. An error
    /// (e.g. an invalid plan, a bug) stops the sweep.
    fn run(&self, job: &Self::Job) -> Result<Self::Row>;
    /// The row as records of the shared schema (`job` and `key` are filled in by the harness).
    fn records(&self, row: &Self::Row) -> Vec<RunRecord>;
    /// The sweep's own files (relative path, contents) made from all its rows in job order:
    /// `results.csv`, a Markdown page beside the paper's numbers, SVG figures, ...
    fn pages(&self, rows: &[&Self::Row], manifest: &Manifest) -> Result<Vec<(String, String)>>;
    /// A few lines for the terminal once the sweep is done.
    fn summary(&self, rows: &[&Self::Row]) -> String;
    /// The sweep's whole configuration as text (recorded in the manifest beside the command).
    fn config(&self) -> String;
}

/// What made an output folder.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    pub sweep: String,
    pub mrpp_version: String,
    /// The command line, as given (argv without the program name).
    pub command: Vec<String>,
    pub seed: u64,
    /// The sweep's whole configuration ([`Sweep::config`]).
    pub config: String,
    /// `i/N` of the shard this folder holds, or `merged i/N` for a merge.
    pub shard: String,
    pub jobs: usize,
    pub threads: usize,
    /// Wall time of the jobs this folder ran (a merge adds its parts').
    pub wall_seconds: f64,
}

impl Manifest {
    /// The command without `--shard X` and `--out X`: what every part of one sweep shares.
    pub fn sweep_command(&self) -> Vec<String> {
        let mut out = Vec::new();
        let mut skip = false;
        for a in &self.command {
            if skip {
                skip = false;
                continue;
            }
            if a == "--shard" || a == "--out" {
                skip = true;
                continue;
            }
            if a.starts_with("--shard=") || a.starts_with("--out=") {
                continue;
            }
            out.push(a.clone());
        }
        out
    }
}

/// What the progress reporter is told after each job.
pub struct Tick<'a> {
    pub done: usize,
    pub total: usize,
    /// The key of the job just finished.
    pub key: &'a str,
}

/// Rows with their job numbers, in job order.
pub type Numbered<R> = Vec<(usize, R)>;

/// The number of threads rayon uses (what the manifest records).
pub fn threads() -> usize {
    rayon::current_num_threads()
}

/// Runs the jobs of `shard` in parallel, except those already in `previous` (rows of an
/// interrupted run, see [`read_progress`]), which are kept as they are. `tick` is called after
/// each job and `sink` receives each new row as soon as it exists (from any thread; e.g. to
/// append it to a progress file). Returns every row of the shard, `(job number, row)` in job
/// order, and the wall time in seconds of the jobs run now.
pub fn run_shard<S: Sweep>(
    sweep: &S,
    shard: Shard,
    previous: Numbered<S::Row>,
    tick: &(dyn Fn(Tick) + Sync),
    sink: &(dyn Fn(usize, &S::Row) -> Result<()> + Sync),
) -> Result<(Numbered<S::Row>, f64)> {
    let started = Instant::now();
    let have: std::collections::BTreeSet<usize> = previous.iter().map(|(j, _)| *j).collect();
    let mine: Vec<usize> = (0..sweep.jobs().len())
        .filter(|&j| shard.owns(j) && !have.contains(&j))
        .collect();
    let done = std::sync::atomic::AtomicUsize::new(0);
    let mut rows = mine
        .par_iter()
        .map(|&j| {
            let job = &sweep.jobs()[j];
            let row = sweep.run(job)?;
            sink(j, &row)?;
            let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
            tick(Tick {
                done: n,
                total: mine.len(),
                key: &sweep.key(job),
            });
            Ok((j, row))
        })
        .collect::<Result<Vec<_>>>()?;
    rows.extend(previous);
    rows.sort_by_key(|(j, _)| *j);
    Ok((rows, started.elapsed().as_secs_f64()))
}

/// The progress file of a shard's run in its output folder: one line per finished job, written
/// as the job finishes, so an interrupted run keeps its work and resumes from it. Its name holds
/// a hash of the sweep's whole configuration and seed, so a rerun with other settings (seed,
/// time limit, a peer's command, ...) starts afresh instead of reusing rows made with the old
/// ones.
pub fn progress_file<S: Sweep>(sweep: &S, seed: u64, shard: Shard) -> String {
    let tag = mrpp_core::seeds::derive_seed(seed, &format!("{}\n{}", sweep.name(), sweep.config()));
    format!(
        "progress-{}-of-{}-{tag:016x}.jsonl",
        shard.index, shard.count
    )
}

/// One line of a progress file.
pub fn progress_line<S: Sweep>(sweep: &S, job: usize, row: &S::Row) -> String {
    json(&PartLine {
        job,
        key: sweep.key(&sweep.jobs()[job]),
        row,
    }) + "\n"
}

/// The rows of an earlier run of `shard` recorded in `path` (empty when the file does not
/// exist). A last line cut short by an interruption is dropped.
///
/// # Errors
/// [`Error::Parse`] naming the line when a line belongs to another sweep or shard (its job
/// number and key disagree with this sweep's) or is repeated.
pub fn read_progress<S: Sweep>(sweep: &S, shard: Shard, path: &Path) -> Result<Numbered<S::Row>> {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => {
            return Err(Error::Io {
                path: path.to_path_buf(),
                source: e,
            });
        }
    };
    let lines: Vec<&str> = text.lines().collect();
    let mut rows = Vec::new();
    let mut seen = std::collections::BTreeSet::new();
    for (k, line) in lines.iter().enumerate() {
        let parsed: std::result::Result<PartLine<S::Row>, _> = serde_json::from_str(line);
        let part = match parsed {
            Ok(p) => p,
            // A line cut short by an interruption (only the last one can be).
            Err(_) if k + 1 == lines.len() && !text.ends_with('\n') => break,
            Err(e) => return Err(Error::parse(path, k + 1, e.to_string())),
        };
        let expected = sweep.jobs().get(part.job).map(|j| sweep.key(j));
        if expected.as_deref() != Some(part.key.as_str()) || !shard.owns(part.job) {
            return Err(Error::parse(
                path,
                k + 1,
                format!(
                    "job {} `{}` is not job {} of this sweep's shard {shard}: the folder holds another sweep (use another --out)",
                    part.job, part.key, part.job
                ),
            ));
        }
        if !seen.insert(part.job) {
            return Err(Error::parse(
                path,
                k + 1,
                format!("job {} is recorded twice", part.job),
            ));
        }
        rows.push((part.job, part.row));
    }
    Ok(rows)
}

/// One line of a part file.
#[derive(Serialize, Deserialize)]
struct PartLine<R> {
    job: usize,
    key: String,
    row: R,
}

/// The files of a finished run: for the whole sweep, its pages, `records.csv` and
/// `manifest.json`; for a shard, `part-i-of-N.jsonl` and `manifest-i-of-N.json`.
pub fn outputs<S: Sweep>(
    sweep: &S,
    rows: &[(usize, S::Row)],
    shard: Shard,
    manifest: &Manifest,
) -> Result<Vec<(String, String)>> {
    if !shard.is_all() {
        let mut part = String::new();
        for (j, row) in rows {
            let line = PartLine {
                job: *j,
                key: sweep.key(&sweep.jobs()[*j]),
                row,
            };
            part.push_str(&json(&line));
            part.push('\n');
        }
        let tag = format!("{}-of-{}", shard.index, shard.count);
        return Ok(vec![
            (format!("part-{tag}.jsonl"), part),
            (format!("manifest-{tag}.json"), json(manifest) + "\n"),
        ]);
    }
    let in_order: Vec<&S::Row> = rows.iter().map(|(_, r)| r).collect();
    let mut files = sweep.pages(&in_order, manifest)?;
    files.push(("records.csv".into(), records_csv(sweep, rows)?));
    files.push(("manifest.json".into(), json(manifest) + "\n"));
    Ok(files)
}

/// `records.csv` of rows in job order.
fn records_csv<S: Sweep>(sweep: &S, rows: &[(usize, S::Row)]) -> Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    for (j, row) in rows {
        for mut r in sweep.records(row) {
            r.job = *j;
            r.key = sweep.key(&sweep.jobs()[*j]);
            w.serialize(r).map_err(|e| Error::Internal(e.to_string()))?;
        }
    }
    let bytes = w.into_inner().map_err(|e| Error::Internal(e.to_string()))?;
    String::from_utf8(bytes).map_err(|e| Error::Internal(e.to_string()))
}

/// The part files (`part-*-of-N.jsonl`) in `dirs`, with their manifests.
fn find_parts(dirs: &[PathBuf]) -> Result<Vec<(PathBuf, Manifest)>> {
    let mut parts = Vec::new();
    for dir in dirs {
        let entries = std::fs::read_dir(dir).map_err(|source| Error::Io {
            path: dir.clone(),
            source,
        })?;
        let mut names: Vec<String> = entries
            .filter_map(|e| e.ok()?.file_name().into_string().ok())
            .filter(|n| n.starts_with("part-") && n.ends_with(".jsonl"))
            .collect();
        names.sort();
        // A folder without parts beside folders with them is a wrong argument (a typo, a part
        // that never ran), not something to merge around.
        if names.is_empty() {
            return Err(Error::invalid(
                dir,
                "no part-i-of-N.jsonl files in this folder: give only folders that hold parts",
            ));
        }
        for name in names {
            let tag = &name["part-".len()..name.len() - ".jsonl".len()];
            let mpath = dir.join(format!("manifest-{tag}.json"));
            let manifest: Manifest = serde_json::from_str(&read_file(&mpath)?)
                .map_err(|e| Error::parse(&mpath, e.line().max(1), e.to_string()))?;
            parts.push((dir.join(name), manifest));
        }
    }
    if parts.is_empty() {
        return Err(Error::Param(
            "bench merge: give the folders that hold the parts".into(),
        ));
    }
    Ok(parts)
}

/// The manifest of the merged sweep: every part must record the same sweep, configuration, seed,
/// job count and shard count (the commands may differ in flag order or paths).
pub fn merged_manifest(dirs: &[PathBuf]) -> Result<Manifest> {
    let parts = find_parts(dirs)?;
    let first = &parts[0].1;
    let count = |m: &Manifest| m.shard.split('/').nth(1).map(str::to_string);
    for (path, m) in &parts {
        let same = m.sweep == first.sweep
            && m.config == first.config
            && m.seed == first.seed
            && m.jobs == first.jobs
            && count(m) == count(first);
        if !same {
            return Err(Error::invalid(
                path,
                format!(
                    "comes from another sweep than the first part (sweep, configuration, seed, job \
                     count or shard count differ): `mrpp {}` vs `mrpp {}`",
                    m.sweep_command().join(" "),
                    first.sweep_command().join(" ")
                ),
            ));
        }
    }
    let mut merged = first.clone();
    merged.wall_seconds = parts.iter().map(|(_, m)| m.wall_seconds).sum();
    merged.shard = format!("merged from {} parts ({})", parts.len(), first.shard);
    Ok(merged)
}

/// Reads every part in `dirs` and returns the rows of the whole sweep in job order, after
/// checking that they come from one sweep and cover each of its jobs exactly once.
pub fn merge_parts<S: Sweep>(sweep: &S, dirs: &[PathBuf]) -> Result<Numbered<S::Row>> {
    let parts = find_parts(dirs)?;
    let total = sweep.jobs().len();
    let mut rows: Vec<Option<S::Row>> = (0..total).map(|_| None).collect();
    for (path, _) in &parts {
        for (i, line) in read_file(path)?.lines().enumerate() {
            let p: PartLine<S::Row> =
                serde_json::from_str(line).map_err(|e| Error::parse(path, i + 1, e.to_string()))?;
            check_line(sweep, &p, path, i + 1, rows.get(p.job).map(Option::is_some))?;
            rows[p.job] = Some(p.row);
        }
    }
    let missing: Vec<usize> = (0..total).filter(|&j| rows[j].is_none()).collect();
    if let Some(&j) = missing.first() {
        let dir = dirs.first().cloned().unwrap_or_default();
        return Err(Error::invalid(
            &dir,
            format!(
                "{} of {total} jobs are in no part (first: job {j}, `{}`); run the missing shards first",
                missing.len(),
                sweep.key(&sweep.jobs()[j])
            ),
        ));
    }
    Ok(rows
        .into_iter()
        .enumerate()
        .map(|(j, r)| (j, r.expect("checked above")))
        .collect())
}

fn check_line<S: Sweep>(
    sweep: &S,
    p: &PartLine<S::Row>,
    path: &Path,
    line: usize,
    seen: Option<bool>,
) -> Result<()> {
    match seen {
        None => Err(Error::parse(
            path,
            line,
            format!("job {} is not a job of this sweep", p.job),
        )),
        Some(true) => Err(Error::parse(
            path,
            line,
            format!("job {} is in two parts", p.job),
        )),
        Some(false) if sweep.key(&sweep.jobs()[p.job]) != p.key => Err(Error::parse(
            path,
            line,
            format!("job {} has key `{}`, not this sweep's", p.job, p.key),
        )),
        Some(false) => Ok(()),
    }
}

/// `key=value;...` of parameters (what [`RunRecord::params`] holds).
pub fn params_text<'a>(params: impl IntoIterator<Item = (&'a str, &'a str)>) -> String {
    params
        .into_iter()
        .map(|(k, v)| format!("{k}={v}"))
        .collect::<Vec<_>>()
        .join(";")
}

/// One line of JSON (rows and manifests always serialise).
fn json<T: Serialize>(v: &T) -> String {
    serde_json::to_string(v).expect("sweep rows and manifests serialise")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sweep of 10 jobs whose rows are their squares.
    struct Squares(Vec<u64>);

    impl Sweep for Squares {
        type Job = u64;
        type Row = u64;
        fn name(&self) -> &str {
            "squares"
        }
        fn jobs(&self) -> &[u64] {
            &self.0
        }
        fn key(&self, job: &u64) -> String {
            format!("n{job}")
        }
        fn run(&self, job: &u64) -> Result<u64> {
            Ok(job * job)
        }
        fn records(&self, _: &u64) -> Vec<RunRecord> {
            Vec::new()
        }
        fn pages(&self, rows: &[&u64], _: &Manifest) -> Result<Vec<(String, String)>> {
            Ok(vec![("rows.txt".into(), format!("{rows:?}"))])
        }
        fn summary(&self, rows: &[&u64]) -> String {
            format!("{} rows", rows.len())
        }
        fn config(&self) -> String {
            format!("{:?}", self.0)
        }
    }

    fn manifest(shard: &str) -> Manifest {
        Manifest {
            sweep: "squares".into(),
            mrpp_version: "0".into(),
            command: vec![
                "x".into(),
                "--shard".into(),
                shard.into(),
                "--out".into(),
                "d".into(),
            ],
            seed: 0,
            config: String::new(),
            shard: shard.into(),
            jobs: 10,
            threads: 1,
            wall_seconds: 1.0,
        }
    }

    #[test]
    fn shards_cover_every_job_once_and_merge_to_the_whole() {
        let sweep = Squares((0..10).collect());
        let (whole, _) =
            run_shard(&sweep, Shard::ALL, Vec::new(), &|_| {}, &|_, _| Ok(())).unwrap();
        let dir = std::env::temp_dir().join(format!("mrpp-harness-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for i in 1..=3 {
            let shard: Shard = format!("{i}/3").parse().unwrap();
            let (rows, _) = run_shard(&sweep, shard, Vec::new(), &|_| {}, &|_, _| Ok(())).unwrap();
            assert!(rows.iter().all(|(j, _)| j % 3 == i - 1));
            for (name, text) in
                outputs(&sweep, &rows, shard, &manifest(&shard.to_string())).unwrap()
            {
                std::fs::write(dir.join(name), text).unwrap();
            }
        }
        let merged = merge_parts(&sweep, std::slice::from_ref(&dir)).unwrap();
        assert_eq!(merged, whole);
        let m = merged_manifest(std::slice::from_ref(&dir)).unwrap();
        assert_eq!(m.wall_seconds, 3.0);
        assert_eq!(m.sweep_command(), vec!["x".to_string()]);
        std::fs::remove_file(dir.join("part-2-of-3.jsonl")).unwrap();
        let e = merge_parts(&sweep, std::slice::from_ref(&dir))
            .unwrap_err()
            .to_string();
        assert!(e.contains("jobs are in no part"), "{e}");
        assert!("0/3".parse::<Shard>().is_err() && "4/3".parse::<Shard>().is_err());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn an_interrupted_run_resumes_from_its_progress_file() {
        let sweep = Squares((0..10).collect());
        let (whole, _) =
            run_shard(&sweep, Shard::ALL, Vec::new(), &|_| {}, &|_, _| Ok(())).unwrap();
        let path = std::env::temp_dir().join(format!("mrpp-progress-{}.jsonl", std::process::id()));
        // Jobs 0..4 finished; the line of job 4 was cut short.
        let mut text: String = whole[..4]
            .iter()
            .map(|(j, r)| progress_line(&sweep, *j, r))
            .collect();
        text.push_str(&progress_line(&sweep, 4, &whole[4].1)[..5]);
        std::fs::write(&path, &text).unwrap();
        let previous = read_progress(&sweep, Shard::ALL, &path).unwrap();
        assert_eq!(previous.len(), 4);
        let ran = std::sync::Mutex::new(Vec::new());
        let (rows, _) = run_shard(&sweep, Shard::ALL, previous, &|_| {}, &|j, _| {
            ran.lock().unwrap().push(j);
            Ok(())
        })
        .unwrap();
        assert_eq!(rows, whole);
        let mut ran = ran.into_inner().unwrap();
        ran.sort();
        assert_eq!(ran, (4..10).collect::<Vec<_>>());
        // A file of another sweep is refused, naming its line.
        std::fs::write(&path, progress_line(&Squares(vec![7, 8]), 1, &64)).unwrap();
        let e = read_progress(&sweep, Shard::ALL, &path)
            .unwrap_err()
            .to_string();
        assert!(e.contains(":1:") && e.contains("another sweep"), "{e}");
        let _ = std::fs::remove_file(&path);
    }
}

/// A path (or any word) quoted for `sh -c`.
pub fn shell_quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', "'\\''"))
}

/// What a peer's command did ([`run_peer_command`]).
#[derive(Debug)]
pub enum PeerRun {
    /// It could not start, exited non-zero, or wrote no result: the command is broken, not the
    /// peer's answer. `note` gives the exit status and the first lines of its stderr.
    Failed { note: String, wall_ms: f64 },
    /// Killed at the limit (with everything it started).
    Killed { wall_ms: f64 },
    /// It exited 0 and wrote `text` to its result file. `peak_rss_kb`: the largest resident set
    /// of any process of the command, in KiB ([`PeakRss`]).
    Done {
        text: String,
        wall_ms: f64,
        peak_rss_kb: Option<u64>,
    },
}

/// Runs a peer's `command` with `sh -c` in its own process group (stdin and stdout closed,
/// stderr to `stderr_path`) until it ends or `limit` passes, when the whole group is killed;
/// it must write its result to `out`.
pub fn run_peer_command(
    command: &str,
    out: &std::path::Path,
    stderr_path: &std::path::Path,
    limit: std::time::Duration,
) -> PeerRun {
    use std::os::unix::process::CommandExt as _;
    let started = std::time::Instant::now();
    let mut peak = PeakRss::new();
    // `Ok(Some((status, peak kB)))` when it ended, `Ok(None)` when it was killed at the limit.
    let finished: std::io::Result<Option<Reaped>> = (|| {
        let stderr = std::fs::File::create(stderr_path)?;
        std::process::Command::new("sh")
            .arg("-c")
            .arg(command)
            .process_group(0)
            .stdin(std::process::Stdio::null())
            .stdout(std::process::Stdio::null())
            .stderr(stderr)
            .spawn()
            .and_then(|mut child| {
                loop {
                    peak.sample(child.id());
                    match reap(&child)? {
                        Some(done) => break Ok(Some(done)),
                        None if started.elapsed() < limit => {
                            std::thread::sleep(std::time::Duration::from_millis(5))
                        }
                        None => {
                            let _ = std::process::Command::new("kill")
                                .args(["-KILL", "--", &format!("-{}", child.id())])
                                .status();
                            let _ = child.kill();
                            let _ = reap_blocking(&child);
                            break Ok(None);
                        }
                    }
                }
            })
    })();
    let wall_ms = started.elapsed().as_secs_f64() * 1e3;
    let text = std::fs::read_to_string(out).ok();
    let stderr = std::fs::read_to_string(stderr_path).unwrap_or_default();
    let status = match finished {
        Err(e) => {
            return PeerRun::Failed {
                note: format!("cannot start or wait for `sh -c {command}`: {e}"),
                wall_ms,
            };
        }
        Ok(None) => return PeerRun::Killed { wall_ms },
        Ok(Some(done)) => done,
    };
    let (status, waited_kb) = status;
    let peak_rss_kb = peak.result(waited_kb);
    match text.filter(|_| status.success()) {
        Some(text) => PeerRun::Done {
            text,
            wall_ms,
            peak_rss_kb,
        },
        None => {
            let what = match status.code() {
                Some(c) => format!("exit {c}"),
                None => "killed by a signal".into(),
            };
            let first: Vec<&str> = stderr
                .lines()
                .filter(|l| !l.trim().is_empty())
                .take(3)
                .collect();
            PeerRun::Failed {
                note: format!(
                    "{what}{}{}",
                    if status.success() {
                        ", no result file"
                    } else {
                        ""
                    },
                    if first.is_empty() {
                        String::new()
                    } else {
                        format!(": {}", first.join(" / "))
                    }
                ),
                wall_ms,
            }
        }
    }
}

/// A peer command's peak resident set. `ru_maxrss` of `wait4(2)` alone is wrong after mrpp's
/// own jobs have grown the bench process: on Linux a process started from it inherits the
/// bench's high-water mark when it calls `exec` (the kernel keeps the old memory's peak across
/// `exec`), so every peer run after a 1.7 GB CBS job read 1,774 MB, even one of 40 ms. So on
/// Linux the command's process tree is sampled (`VmHWM` in `/proc/PID/status`, children from
/// `/proc/PID/task/TID/children`) each time its end is polled (every 5 ms), and `ru_maxrss` is
/// taken only where it exceeds the bench's own high-water mark read after the command was reaped
/// (the mark only grows, so this covers growth between the start and the fork; then it cannot be
/// the inherited one). A process that lives less than one poll may be missed: a peak below the
/// bench's own is then unknown. Elsewhere (macOS) `ru_maxrss` is used as it is.
struct PeakRss {
    /// The bench process's own high-water mark when the command started, KiB (a floor for the
    /// one read in [`PeakRss::result`]).
    own_kb: Option<u64>,
    /// The largest `VmHWM` sampled, KiB.
    sampled_kb: Option<u64>,
}

impl PeakRss {
    fn new() -> Self {
        PeakRss {
            own_kb: vm_hwm_kb("self"),
            sampled_kb: None,
        }
    }

    /// Samples the process tree under `pid` (Linux; nothing elsewhere).
    fn sample(&mut self, pid: u32) {
        if !cfg!(target_os = "linux") {
            return;
        }
        let mut stack = vec![pid];
        let mut seen = 0;
        while let Some(p) = stack.pop() {
            seen += 1;
            if seen > 4096 {
                break;
            }
            if let Some(kb) = vm_hwm_kb(&p.to_string()) {
                self.sampled_kb = Some(self.sampled_kb.map_or(kb, |m| m.max(kb)));
            }
            let Ok(tasks) = std::fs::read_dir(format!("/proc/{p}/task")) else {
                continue;
            };
            for task in tasks.flatten() {
                let children =
                    std::fs::read_to_string(task.path().join("children")).unwrap_or_default();
                stack.extend(
                    children
                        .split_whitespace()
                        .filter_map(|c| c.parse::<u32>().ok()),
                );
            }
        }
    }

    /// The peak: the sampled one, or `ru_maxrss` (`waited_kb`) where it can be trusted.
    fn result(&self, waited_kb: Option<u64>) -> Option<u64> {
        if !cfg!(target_os = "linux") {
            return waited_kb;
        }
        // The bench's own mark after reaping: it may have grown after `new` and before the fork,
        // and the inherited `ru_maxrss` is then above the first reading.
        let own = vm_hwm_kb("self").max(self.own_kb);
        let trusted = waited_kb.filter(|&w| own.is_some_and(|own| w > own));
        match (self.sampled_kb, trusted) {
            (Some(a), Some(b)) => Some(a.max(b)),
            (a, b) => a.or(b),
        }
    }
}

/// `VmHWM` (peak resident set, KiB) of `/proc/{pid}/status`, if readable.
fn vm_hwm_kb(pid: &str) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
}

/// `waitpid(WNOHANG)` on `child` with its resource usage: `Ok(None)` while it runs, else its
/// exit status and peak resident set in KiB (the shell's and every process it waited for, so
/// the peer's own when `sh -c` runs it).
fn reap(child: &std::process::Child) -> std::io::Result<Option<Reaped>> {
    wait4(child, libc::WNOHANG)
}

/// As [`reap`], waiting until the child ends.
fn reap_blocking(child: &std::process::Child) -> std::io::Result<Option<Reaped>> {
    wait4(child, 0)
}

/// A child's exit status and peak resident set in KiB.
type Reaped = (std::process::ExitStatus, Option<u64>);

fn wait4(child: &std::process::Child, options: libc::c_int) -> std::io::Result<Option<Reaped>> {
    use std::os::unix::process::ExitStatusExt as _;
    let pid = libc::pid_t::try_from(child.id()).map_err(std::io::Error::other)?;
    let mut status: libc::c_int = 0;
    // SAFETY: `rusage` is plain old data that `wait4` fills in; all-zero is a valid value.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    loop {
        // SAFETY: `pid` is our own child (not yet reaped: only this function waits for it) and
        // both out-pointers point to live locals of the right types.
        let got = unsafe { libc::wait4(pid, &mut status, options, &mut usage) };
        match got {
            0 => return Ok(None),
            p if p == pid => {
                // Linux reports `ru_maxrss` in KiB, macOS in bytes.
                let unit = if cfg!(target_os = "macos") { 1024 } else { 1 };
                let kb = u64::try_from(usage.ru_maxrss)
                    .ok()
                    .map(|v| v / unit)
                    .filter(|&kb| kb > 0);
                return Ok(Some((std::process::ExitStatus::from_raw(status), kb)));
            }
            _ => {
                let e = std::io::Error::last_os_error();
                if e.kind() != std::io::ErrorKind::Interrupted {
                    return Err(e);
                }
            }
        }
    }
}

#[cfg(all(test, target_os = "linux"))]
mod peak_rss_tests {
    use super::{PeerRun, run_peer_command};

    fn peak_mb(command: &str) -> f64 {
        let dir = std::env::temp_dir().join(format!("mrpp-peak-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let out = dir.join("out.txt");
        let command = command.replace("{out}", &out.to_string_lossy());
        let ran = run_peer_command(
            &command,
            &out,
            &dir.join("stderr.txt"),
            std::time::Duration::from_secs(30),
        );
        let _ = std::fs::remove_dir_all(&dir);
        match ran {
            PeerRun::Done { peak_rss_kb, .. } => peak_rss_kb.expect("a peak") as f64 / 1024.0,
            other => panic!("{other:?}"),
        }
    }

    /// A peer's peak is its own: about the 64 MB it touches, and a small peer started after this
    /// process grew by 400 MB does not read this process's peak (`ru_maxrss` alone read at least
    /// that: the kernel keeps the old memory's peak across `exec`).
    #[test]
    fn a_peers_peak_is_its_own_not_the_bench_process() {
        let hog = "python3 -c \"import time; x = bytearray(64 << 20); time.sleep(0.2); open('{out}', 'w').write('solved=0')\"";
        let big = peak_mb(hog);
        assert!((64.0..64.0 + 80.0).contains(&big), "{big} MB");
        let grown: Vec<u8> = vec![1; 400 << 20];
        let small = peak_mb("sh -c \"sleep 0.05; echo solved=0 > '{out}'\"");
        assert!(
            small < 100.0,
            "{small} MB after this process grew by {} MB",
            grown.len() >> 20
        );
        drop(grown);
    }
}
