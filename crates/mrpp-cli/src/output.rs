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
            "--{flag} must be a positive number of seconds, at most {MAX_TIME_LIMIT}, got {value}"
        )));
    }
    Ok(Duration::from_secs_f64(value))
}

/// Writes `contents` to `path` through a temporary file in the same directory, so a reader never
/// sees half a file.
pub(crate) fn write_atomic(path: &Path, contents: impl AsRef<[u8]>) -> Result<(), Fail> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .ok_or_else(|| Fail(format!("{}: not a file name", path.display())))?;
    let tmp = dir.join(format!(
        ".{}.tmp{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    std::fs::write(&tmp, contents.as_ref())
        .map_err(|e| Fail(format!("{}: cannot write: {e}", path.display())))?;
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        Fail(format!("{}: cannot write: {e}", path.display()))
    })
}

/// The last component of `path` (what outputs record).
pub(crate) fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// `key value | key value ...` of a JSON object's short values (strings over 40 characters,
/// arrays and objects left out), in the object's order.
pub(crate) fn pairs(values: &Map<String, Value>) -> String {
    values
        .iter()
        .filter_map(|(k, v)| match v {
            Value::String(s) if s.len() <= 40 => Some(format!("{k} {s}")),
            Value::Number(_) | Value::Bool(_) => Some(format!("{k} {v}")),
            _ => None,
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
