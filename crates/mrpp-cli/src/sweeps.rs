//! Running a sweep from the command line: the one driver behind `mrpp experiment ...` and
//! `mrpp bench run`, and `mrpp bench merge`, which rebuilds the sweep from the command its parts
//! recorded and joins them.

use std::path::{Path, PathBuf};

use mrpp_bench::harness::{
    Manifest, Numbered, merge_parts, outputs, progress_file, progress_line, read_progress,
    run_shard, threads,
};
use mrpp_bench::{Shard, Sweep};

use crate::output::{Fail, check_output_folder, say, write_atomic};
use crate::progress::Jobs;

/// Run the whole sweep or one shard, or merge parts; every mode writes into `out`.
pub(crate) enum Mode {
    Run {
        shard: Shard,
        out: PathBuf,
    },
    Merge {
        parts: Vec<PathBuf>,
        manifest: Box<Manifest>,
        out: PathBuf,
    },
}

impl Mode {
    /// A run of `shard` (the whole sweep when `None`) into `out`.
    pub(crate) fn run(shard: Option<Shard>, out: PathBuf) -> Mode {
        Mode::Run {
            shard: shard.unwrap_or(Shard::ALL),
            out,
        }
    }
}

/// [`drive`] on `jobs` worker threads (`None`: one per core).
///
/// # Errors
/// `jobs` outside 1..=1024, or what [`drive`] returns.
pub(crate) fn drive_on<S: Sweep>(
    sweep: &S,
    mode: &Mode,
    seed: u64,
    unit: &'static str,
    jobs: Option<usize>,
) -> Result<u8, Fail> {
    match jobs {
        Some(n) if (1..=1024).contains(&n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| Fail(format!("cannot start {n} worker threads: {e}")))?
            .install(|| drive(sweep, mode, seed, unit)),
        Some(n) => Err(Fail(format!("--jobs must be between 1 and 1024, got {n}"))),
        None => drive(sweep, mode, seed, unit),
    }
}

/// Runs `sweep` as `mode` says, writes its files atomically (all computed first), prints the
/// summary of a whole sweep and what was written.
pub(crate) fn drive<S: Sweep>(
    sweep: &S,
    mode: &Mode,
    seed: u64,
    unit: &'static str,
) -> Result<u8, Fail> {
    let (rows, manifest, shard, out) = match mode {
        Mode::Run { shard, out } => {
            let (rows, manifest) = run_jobs(sweep, *shard, seed, unit, out)?;
            (rows, manifest, *shard, out)
        }
        Mode::Merge {
            parts,
            manifest,
            out,
        } => {
            check_output_folder(out)?;
            let rows = merge_parts(sweep, parts)?;
            say!(
                "mrpp {} | merged {} jobs of {} from {} folder(s)",
                env!("CARGO_PKG_VERSION"),
                rows.len(),
                sweep.name(),
                parts.len()
            );
            (rows, (**manifest).clone(), Shard::ALL, out)
        }
    };
    let files = outputs(sweep, &rows, shard, &manifest)?;
    write_files(out, &files)?;
    if shard.is_all() {
        let in_order: Vec<&S::Row> = rows.iter().map(|(_, r)| r).collect();
        say!("{}", sweep.summary(&in_order));
    }
    let names: Vec<&str> = files
        .iter()
        .map(|f| f.0.as_str())
        .filter(|n| !n.starts_with("plans/"))
        .collect();
    let plans = files.len() - names.len();
    let extra = if plans > 0 {
        format!(", plans/ ({plans} plans)")
    } else {
        String::new()
    };
    say!("wrote {}/{{{}}}{extra}", out.display(), names.join(", "));
    Ok(0)
}

/// Runs the jobs of `shard` with a progress reporter; returns the rows and the folder's manifest.
/// Each finished job is appended to the folder's progress file at once (created, with the
/// folder, before any job runs, so an unwritable `--out` fails first); jobs already in that file
/// (an interrupted run of the same sweep) are not run again.
fn run_jobs<S: Sweep>(
    sweep: &S,
    shard: Shard,
    seed: u64,
    unit: &'static str,
    out: &Path,
) -> Result<(Numbered<S::Row>, Manifest), Fail> {
    use std::io::Write as _;
    let total = sweep.jobs().len();
    let mine = (0..total).filter(|&j| shard.owns(j)).count();
    check_output_folder(out)?;
    let progress = out.join(progress_file(sweep, seed, shard));
    let previous = read_progress(sweep, shard, &progress)?;
    cut_partial_line(&progress)?;
    let log = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(&progress)
        .map_err(|e| Fail(format!("{}: cannot write: {e}", progress.display())))?;
    let log = std::sync::Mutex::new(log);
    say!(
        "mrpp {} | {} | seed {seed} | {total} jobs | shard {shard}: {mine} jobs | threads {}",
        env!("CARGO_PKG_VERSION"),
        sweep.name(),
        threads()
    );
    if !previous.is_empty() {
        say!(
            "resuming: {} of {mine} jobs already done in {}",
            previous.len(),
            progress.display()
        );
    }
    let jobs = Jobs::new(mine - previous.len(), unit);
    let sink = |j: usize, row: &S::Row| -> mrpp_core::Result<()> {
        // After Ctrl-C a job's row may come from a cut-short run: not recorded, so that the
        // rerun runs that job again.
        if mrpp_core::stop_requested() {
            return Err(mrpp_core::Error::Param("interrupted".into()));
        }
        // A peer whose command failed is said at once, not only in records.csv.
        for r in sweep
            .records(row)
            .iter()
            .filter(|r| r.status == "peer_failed")
        {
            jobs.suspend(|| {
                eprintln!(
                    "mrpp: warning: peer `{}` failed on {} (run {}): {}",
                    r.planner, r.instance, r.run, r.note
                )
            });
        }
        let line = progress_line(sweep, j, row);
        let mut f = log.lock().unwrap_or_else(|e| e.into_inner());
        f.write_all(line.as_bytes())
            .and_then(|()| f.flush())
            .map_err(|e| mrpp_core::Error::Io {
                path: progress.clone(),
                source: e,
            })
    };
    let (rows, wall) =
        run_shard(sweep, shard, previous, &|t| jobs.tick(t.key), &sink).map_err(|e| {
            if mrpp_core::stop_requested() {
                jobs.finish();
                Fail(format!(
                    "interrupted: the jobs finished before Ctrl-C are kept in {}; run the same command again to resume",
                    progress.display()
                ))
            } else {
                Fail::from(e)
            }
        })?;
    jobs.finish();
    let manifest = Manifest {
        sweep: sweep.name().to_string(),
        mrpp_version: env!("CARGO_PKG_VERSION").into(),
        command: std::env::args().skip(1).collect(),
        seed,
        config: sweep.config(),
        shard: shard.to_string(),
        jobs: total,
        threads: threads(),
        wall_seconds: wall,
    };
    Ok((rows, manifest))
}

/// Cuts a last line that an interruption left without its newline (read_progress skipped it), so
/// that appended lines start on a line of their own.
fn cut_partial_line(path: &Path) -> Result<(), Fail> {
    let Ok(bytes) = std::fs::read(path) else {
        return Ok(());
    };
    if bytes.is_empty() || bytes.ends_with(b"\n") {
        return Ok(());
    }
    let keep = bytes.iter().rposition(|&b| b == b'\n').map_or(0, |k| k + 1);
    std::fs::OpenOptions::new()
        .write(true)
        .open(path)
        .and_then(|f| f.set_len(keep as u64))
        .map_err(|e| Fail(format!("{}: cannot repair: {e}", path.display())))
}

/// Writes every file under `out` (creating folders), each atomically.
fn write_files(out: &Path, files: &[(String, String)]) -> Result<(), Fail> {
    for (name, text) in files {
        let path = out.join(name);
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir)
                .map_err(|e| Fail(format!("{}: cannot create: {e}", dir.display())))?;
        }
        write_atomic(&path, text)?;
    }
    Ok(())
}
