//! The one progress adapter: a planner's [`mrpp_core::Progress`] reports become an indicatif bar
//! on stderr (hidden when stderr is not a terminal, so scripts and tests see only real messages).

use std::sync::Arc;

use indicatif::{ProgressBar, ProgressStyle};

use mrpp_core::{Progress, ProgressFn};

/// How a planner's progress is shown (`--progress`).
#[derive(Clone, Copy, PartialEq, Eq, Debug, clap::ValueEnum)]
pub(crate) enum Mode {
    /// A bar or spinner on a terminal, nothing otherwise.
    Auto,
    /// One plain line on stderr every half second (logs, CI, tests).
    Plain,
    /// Nothing.
    None,
}

static MODE: std::sync::Mutex<Mode> = std::sync::Mutex::new(Mode::Auto);

/// Sets the mode from `--progress`.
pub(crate) fn set_mode(mode: Mode) {
    *MODE.lock().unwrap_or_else(|e| e.into_inner()) = mode;
}

/// The mode [`set_mode`] set.
pub(crate) fn mode() -> Mode {
    *MODE.lock().unwrap_or_else(|e| e.into_inner())
}

/// The live progress of one planner run: from the start a spinner with the elapsed time (so no
/// planner is silent, whether or not it reports), a bar once the planner reports a total, its
/// count and note (e.g. the best cost so far) otherwise; with `--progress plain` a line every
/// half second instead. Finish it with [`Live::finish`].
pub(crate) struct Live {
    bar: ProgressBar,
    last: Arc<std::sync::Mutex<Option<Progress>>>,
    ticker: Option<(
        Arc<std::sync::atomic::AtomicBool>,
        std::thread::JoinHandle<()>,
    )>,
}

const SPINNER: &str = "{spinner} {elapsed_precise} {prefix} {pos} {msg}";
const BAR: &str = "{bar:40} {pos}/{len} {prefix}  {elapsed_precise} (eta {eta})  {msg}";

impl Live {
    /// Progress of planner `name`, shown as [`Mode`] says (nothing under `--quiet`).
    pub(crate) fn start(name: &str) -> Self {
        let last = Arc::new(std::sync::Mutex::new(None::<Progress>));
        let quiet = crate::output::verbosity() == 0;
        let mode = if quiet { Mode::None } else { mode() };
        let terminal = std::io::IsTerminal::is_terminal(&std::io::stderr());
        let bar = if mode == Mode::Auto && terminal {
            let bar = ProgressBar::new_spinner();
            bar.set_style(ProgressStyle::with_template(SPINNER).expect("static template"));
            bar.set_prefix(name.to_string());
            bar.enable_steady_tick(std::time::Duration::from_millis(120));
            bar
        } else {
            ProgressBar::hidden()
        };
        let ticker = (mode == Mode::Plain).then(|| {
            let stop = Arc::new(std::sync::atomic::AtomicBool::new(false));
            let (stop2, last2, name) = (stop.clone(), last.clone(), name.to_string());
            let started = std::time::Instant::now();
            let handle = std::thread::spawn(move || {
                let tick = std::time::Duration::from_millis(500);
                let mut next = started + tick;
                while !stop2.load(std::sync::atomic::Ordering::Relaxed) {
                    std::thread::sleep(std::time::Duration::from_millis(20));
                    if std::time::Instant::now() < next {
                        continue;
                    }
                    next += tick;
                    let report = last2.lock().unwrap_or_else(|e| e.into_inner()).clone();
                    let what = report.map_or_else(String::new, |p| describe(&p));
                    eprintln!(
                        "[{:.1} s] {name}{}{what}",
                        started.elapsed().as_secs_f64(),
                        if what.is_empty() { "" } else { ": " }
                    );
                }
            });
            (stop, handle)
        });
        Live { bar, last, ticker }
    }

    /// The callback that planners report to.
    pub(crate) fn callback(&self) -> ProgressFn {
        let (bar, last) = (self.bar.clone(), self.last.clone());
        Arc::new(move |p: &Progress| {
            if p.total > 0 && bar.length() != Some(p.total) {
                bar.set_style(ProgressStyle::with_template(BAR).expect("static template"));
                bar.set_length(p.total);
            }
            bar.set_position(p.done);
            bar.set_message(format!("{}s {}", p.stage, p.note));
            *last.lock().unwrap_or_else(|e| e.into_inner()) = Some(p.clone());
        })
    }

    /// Clears the bar or stops the plain lines.
    pub(crate) fn finish(self) {
        self.bar.finish_and_clear();
        if let Some((stop, handle)) = self.ticker {
            stop.store(true, std::sync::atomic::Ordering::Relaxed);
            let _ = handle.join();
        }
    }
}

/// A report in words: `generation 40/250 best 12` or `configurations 6692 cost 6062`.
fn describe(p: &Progress) -> String {
    let count = if p.total > 0 {
        format!("{} {}/{}", p.stage, p.done, p.total)
    } else {
        format!("{} {}", p.stage, p.done)
    };
    if p.note.is_empty() {
        count
    } else {
        format!("{count} {}", p.note)
    }
}

/// Progress of a sweep on stderr: an indicatif bar on a terminal; otherwise (a log file, CI, a
/// Slurm job) one plain line per finished job, so long batch runs still show where they are.
pub(crate) struct Jobs {
    bar: ProgressBar,
    plain: bool,
    len: usize,
    unit: &'static str,
    done: std::sync::atomic::AtomicUsize,
    started: std::time::Instant,
}

impl Jobs {
    pub(crate) fn new(len: usize, unit: &'static str) -> Self {
        let bar = if crate::output::verbosity() == 0 {
            ProgressBar::hidden()
        } else {
            ProgressBar::new(len as u64)
        };
        bar.set_style(
            ProgressStyle::with_template(&format!(
                "{{bar:40}} {{pos}}/{{len}} {unit}  {{elapsed_precise}} (eta {{eta}})  {{msg}}"
            ))
            .expect("static template"),
        );
        Jobs {
            bar,
            plain: !std::io::IsTerminal::is_terminal(&std::io::stderr())
                || crate::output::verbosity() >= 2,
            len,
            unit,
            done: std::sync::atomic::AtomicUsize::new(0),
            started: std::time::Instant::now(),
        }
    }

    /// One job finished (`key` names it).
    pub(crate) fn tick(&self, key: &str) {
        let k = self.done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        if crate::output::verbosity() == 0 {
            return;
        }
        if self.plain {
            eprintln!(
                "[{:.0} s] {k}/{} {}: {key}",
                self.started.elapsed().as_secs_f64(),
                self.len,
                self.unit
            );
        } else {
            self.bar.set_message(key.to_string());
            self.bar.inc(1);
        }
    }

    pub(crate) fn finish(&self) {
        self.bar.finish_and_clear();
    }

    /// Runs `f` (which prints a line) with the bar hidden, so the line is not drawn over.
    pub(crate) fn suspend<R>(&self, f: impl FnOnce() -> R) -> R {
        self.bar.suspend(f)
    }
}
