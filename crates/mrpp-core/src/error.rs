//! Typed errors. The library never prints: the CLI turns these into one-line messages and exit codes.

use std::path::PathBuf;

/// Everything that can go wrong while reading inputs or setting up a planner.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A file is malformed at a given (1-based) line.
    #[error("{}:{line}: {msg}", path.display())]
    Parse {
        path: PathBuf,
        line: usize,
        msg: String,
    },
    /// A file is well formed but its content is unusable (e.g. no free cell, too few agents).
    #[error("{}: {msg}", path.display())]
    Invalid { path: PathBuf, msg: String },
    /// A parameter is out of range or inconsistent.
    #[error("invalid parameter: {0}")]
    Param(String),
    /// A bug in mrpp caught by a check (e.g. a plan the validator rejects): never the user's fault.
    #[error("internal error: {0}")]
    Internal(String),
}

pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// A parse error at a 1-based `line` of `path`.
    pub fn parse(path: &std::path::Path, line: usize, msg: impl Into<String>) -> Self {
        Error::Parse {
            path: path.to_path_buf(),
            line,
            msg: msg.into(),
        }
    }
    /// A well-formed `path` whose content is unusable.
    pub fn invalid(path: &std::path::Path, msg: impl Into<String>) -> Self {
        Error::Invalid {
            path: path.to_path_buf(),
            msg: msg.into(),
        }
    }
}

/// Reads a whole file as UTF-8 text, naming it in the error; a leading byte-order mark (which
/// some editors write) is dropped, so every parser reads such files like any other. The file is
/// noted in [`crate::files_read`] (when recording is on), so no output of the process replaces it.
pub fn read_file(path: &std::path::Path) -> Result<String> {
    let bytes = std::fs::read(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    crate::files_read::note(path);
    let mut text = String::from_utf8(bytes)
        .map_err(|e| Error::invalid(path, format!("not UTF-8 text ({e})")))?;
    if text.starts_with('\u{feff}') {
        text.drain(..'\u{feff}'.len_utf8());
    }
    Ok(text)
}
