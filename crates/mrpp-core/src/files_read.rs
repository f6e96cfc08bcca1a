//! The files a process has read, so that its outputs can refuse to overwrite any of them.
//!
//! Every reader in mrpp reads through [`crate::error::read_file`], which notes the file here once
//! recording has been switched on ([`start_recording`]; the `mrpp` binary does, a library user
//! need not). A file is kept by its identity (device and inode on Unix), so the same file is found
//! however it was named: a relative path, `..`, a symbolic link or a hard link. The binary adds
//! the files and folders a command will read before it reads them ([`note`]), and checks every
//! output against the list ([`find`]) before any work and again when it writes.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// One input: the path as given, and its identity when it exists.
#[derive(Debug, Clone)]
struct Entry {
    path: PathBuf,
    id: Option<FileId>,
    folder: bool,
}

/// A file's identity: device and inode on Unix; its canonical path elsewhere.
#[derive(Debug, Clone, PartialEq, Eq)]
enum FileId {
    #[cfg(unix)]
    Inode(u64, u64),
    #[cfg_attr(unix, allow(dead_code))]
    Canonical(PathBuf),
}

/// `None` until [`start_recording`].
static READ: Mutex<Option<Vec<Entry>>> = Mutex::new(None);

/// Switches recording on for the rest of the process (idempotent).
pub fn start_recording() {
    let mut read = READ.lock().unwrap_or_else(|e| e.into_inner());
    read.get_or_insert_with(Vec::new);
}

/// Notes `path` (a file or a folder) as an input of this process, when recording is on. A path
/// that does not exist yet is kept by name only (it cannot be the same file as an output until
/// it exists, and then its name is compared).
pub fn note(path: &Path) {
    let mut read = READ.lock().unwrap_or_else(|e| e.into_inner());
    let Some(list) = read.as_mut() else {
        return;
    };
    let id = identity(path);
    if list
        .iter()
        .any(|e| e.path == path || (id.is_some() && e.id == id))
    {
        return;
    }
    list.push(Entry {
        path: path.to_path_buf(),
        id,
        folder: path.is_dir(),
    });
}

/// The inputs noted so far, as given: `(path, is a folder)`.
pub fn inputs() -> Vec<(PathBuf, bool)> {
    let read = READ.lock().unwrap_or_else(|e| e.into_inner());
    read.iter()
        .flatten()
        .map(|e| (e.path.clone(), e.folder))
        .collect()
}

/// The noted input file that `out` would replace: the same file (however named), or `None`.
/// Folders noted as inputs are not matched here (see [`inputs`]).
pub fn find(out: &Path) -> Option<PathBuf> {
    let id = identity(out)?;
    let read = READ.lock().unwrap_or_else(|e| e.into_inner());
    read.iter()
        .flatten()
        .find(|e| !e.folder && e.id.as_ref() == Some(&id))
        .map(|e| e.path.clone())
}

/// The identity of an existing file or folder (following symbolic links).
fn identity(path: &Path) -> Option<FileId> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt as _;
        let m = std::fs::metadata(path).ok()?;
        Some(FileId::Inode(m.dev(), m.ino()))
    }
    #[cfg(not(unix))]
    {
        std::fs::canonicalize(path).ok().map(FileId::Canonical)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_is_found_however_it_is_named() {
        start_recording();
        let dir = std::env::temp_dir().join(format!("mrpp-files-read-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        let file = dir.join("input.txt");
        std::fs::write(&file, "x").unwrap();
        note(&dir.join("sub/../input.txt"));
        assert!(find(&file).is_some());
        #[cfg(unix)]
        {
            let link = dir.join("link.txt");
            let hard = dir.join("hard.txt");
            let _ = std::fs::remove_file(&link);
            let _ = std::fs::remove_file(&hard);
            std::os::unix::fs::symlink(&file, &link).unwrap();
            std::fs::hard_link(&file, &hard).unwrap();
            assert!(find(&link).is_some(), "symbolic link");
            assert!(find(&hard).is_some(), "hard link");
        }
        let other = dir.join("other.txt");
        std::fs::write(&other, "y").unwrap();
        assert!(find(&other).is_none());
        assert!(find(&dir.join("missing.txt")).is_none());
        // A folder is an input but never "the same file" as an output file.
        note(&dir.join("sub"));
        assert!(find(&dir.join("sub")).is_none());
        assert!(
            inputs()
                .iter()
                .any(|(p, folder)| *folder && p.ends_with("sub"))
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
