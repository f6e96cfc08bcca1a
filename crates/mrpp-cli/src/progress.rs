//! The one progress adapter: a planner's [`mrpp_core::Progress`] reports become an indicatif bar
//! on stderr (hidden when stderr is not a terminal, so scripts and tests see only real messages).

use std::sync::Arc;

use indicatif::{ProgressBar, ProgressStyle};

use mrpp_core::{Progress, ProgressFn};

/// A bar with no length yet (set by the first report).
pub(crate) fn bar() -> ProgressBar {
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
