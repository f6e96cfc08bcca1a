//! The one progress adapter: a planner's [`mrpp_core::Progress`] reports become an indicatif bar
//! on stderr (hidden when stderr is not a terminal, so scripts and tests see only real messages).

use std::sync::Arc;

use indicatif::{ProgressBar, ProgressStyle};

use mrpp_core::{Progress, ProgressFn};

/// A bar with no length yet (set by the first report).
pub(crate) fn bar() -> ProgressBar {
    if crate::output::verbosity() == 0 {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(0);
    bar.set_style(
        ProgressStyle::with_template(
            "{bar:40} {pos}/{len} {prefix}  {elapsed_precise} (eta {eta})  {msg}",
        )
        .expect("static template"),
    );
    bar
}

/// The callback that drives `bar` from a planner's reports.
pub(crate) fn callback(bar: &ProgressBar) -> ProgressFn {
    let bar = bar.clone();
    Arc::new(move |p: &Progress| {
        if p.total > 0 {
            bar.set_length(p.total);
        }
        bar.set_position(p.done);
        bar.set_prefix(format!("{}s", p.stage));
        bar.set_message(p.note.clone());
    })
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
