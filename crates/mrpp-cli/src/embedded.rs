//! The papers' small instance files, embedded in the binary so that `mrpp experiment ...` runs
//! from any directory with an installed `mrpp` (`cargo install --path crates/mrpp-cli`): without
//! `--data`, an experiment reads a copy of its bundle written to a fresh temporary folder, which
//! is removed when the experiment has read it. `--data DIR` reads DIR instead (e.g. edited
//! instances). The bundles are the repository's `data/hstar-paper` (H* paper, CC BY-NC-SA 4.0,
//! licence included), `data/polygon-maps` (CTU polygon maps and seeded stand-ins) and
//! `data/continuous` (the HBMO paper's 6-robot world); a test checks each bundle lists every
//! file of its folder.

use std::path::{Path, PathBuf};

use crate::output::Fail;

/// A folder of files compiled into the binary.
pub(crate) struct Bundle {
    /// The folder's name under the repository's `data/`.
    pub(crate) name: &'static str,
    /// `(path relative to the folder, bytes)`.
    pub(crate) files: &'static [(&'static str, &'static [u8])],
}

/// A bundle written out to a temporary folder, removed on drop.
pub(crate) struct Unpacked {
    dir: PathBuf,
}

impl Unpacked {
    pub(crate) fn path(&self) -> &Path {
        &self.dir
    }
}

impl Drop for Unpacked {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// The folder an experiment reads: `given`, or `bundle` unpacked into a fresh temporary folder
/// (kept alive by the returned guard).
pub(crate) fn data_dir(
    given: Option<PathBuf>,
    bundle: &Bundle,
) -> Result<(PathBuf, Option<Unpacked>), Fail> {
    if let Some(dir) = given {
        // An output folder may not be this folder or lie inside it.
        crate::output::declare_inputs([dir.as_path()]);
        return Ok((dir, None));
    }
    let unpacked = unpack(bundle)?;
    Ok((unpacked.path().to_path_buf(), Some(unpacked)))
}

fn unpack(bundle: &Bundle) -> Result<Unpacked, Fail> {
    let base = std::env::temp_dir();
    let fail = |p: &Path, e: std::io::Error| {
        Fail(format!(
            "{}: cannot unpack the embedded `{}` files ({e}); pass --data DIR instead",
            p.display(),
            bundle.name
        ))
    };
    // A fresh folder: the name has the process id and a counter, and creation fails if it exists.
    let dir = (0u32..1000)
        .map(|k| base.join(format!("mrpp-{}-{}-{k}", bundle.name, std::process::id())))
        .find(|d| std::fs::create_dir(d).is_ok())
        .ok_or_else(|| fail(&base, std::io::Error::other("no fresh folder name")))?;
    let unpacked = Unpacked { dir };
    for (rel, bytes) in bundle.files {
        let path = unpacked.dir.join(rel);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(|e| fail(parent, e))?;
        }
        std::fs::write(&path, bytes).map_err(|e| fail(&path, e))?;
    }
    Ok(unpacked)
}

/// `data/hstar-paper` of the repository.
pub(crate) static HSTAR_PAPER: Bundle = Bundle {
    name: "hstar-paper",
    files: &[
        (
            "LICENSE-CC-BY-NC-SA-4.0.txt",
            include_bytes!("../../../data/hstar-paper/LICENSE-CC-BY-NC-SA-4.0.txt"),
        ),
        (
            "README.md",
            include_bytes!("../../../data/hstar-paper/README.md"),
        ),
        (
            "table2-paper.csv",
            include_bytes!("../../../data/hstar-paper/table2-paper.csv"),
        ),
        (
            "scenario1/10coordinates.txt",
            include_bytes!("../../../data/hstar-paper/scenario1/10coordinates.txt"),
        ),
        (
            "scenario1/11coordinates.txt",
            include_bytes!("../../../data/hstar-paper/scenario1/11coordinates.txt"),
        ),
        (
            "scenario1/12coordinates.txt",
            include_bytes!("../../../data/hstar-paper/scenario1/12coordinates.txt"),
        ),
        (
            "scenario1/13coordinates.txt",
            include_bytes!("../../../data/hstar-paper/scenario1/13coordinates.txt"),
        ),
        (
            "scenario1/14coordinates.txt",
            include_bytes!("../../../data/hstar-paper/scenario1/14coordinates.txt"),
        ),
        (
            "scenario1/15coordinates.txt",
            include_bytes!("../../../data/hstar-paper/scenario1/15coordinates.txt"),
        ),
        (
            "scenario1/3coordinates.txt",
            include_bytes!("../../../data/hstar-paper/scenario1/3coordinates.txt"),
        ),
        (
            "scenario1/4coordinates.txt",
            include_bytes!("../../../data/hstar-paper/scenario1/4coordinates.txt"),
        ),
        (
            "scenario1/5coordinates.txt",
            include_bytes!("../../../data/hstar-paper/scenario1/5coordinates.txt"),
        ),
        (
            "scenario1/6coordinates.txt",
            include_bytes!("../../../data/hstar-paper/scenario1/6coordinates.txt"),
        ),
        (
            "scenario1/7coordinates.txt",
            include_bytes!("../../../data/hstar-paper/scenario1/7coordinates.txt"),
        ),
        (
            "scenario1/8coordinates.txt",
            include_bytes!("../../../data/hstar-paper/scenario1/8coordinates.txt"),
        ),
        (
            "scenario1/9coordinates.txt",
            include_bytes!("../../../data/hstar-paper/scenario1/9coordinates.txt"),
        ),
        (
            "scenario1/scenery.txt",
            include_bytes!("../../../data/hstar-paper/scenario1/scenery.txt"),
        ),
        (
            "scenario2/3robots-per-room.txt",
            include_bytes!("../../../data/hstar-paper/scenario2/3robots-per-room.txt"),
        ),
        (
            "scenario2/4robots-per-room.txt",
            include_bytes!("../../../data/hstar-paper/scenario2/4robots-per-room.txt"),
        ),
        (
            "scenario2/5robots-per-room.txt",
            include_bytes!("../../../data/hstar-paper/scenario2/5robots-per-room.txt"),
        ),
        (
            "scenario2/6robots-per-room.txt",
            include_bytes!("../../../data/hstar-paper/scenario2/6robots-per-room.txt"),
        ),
        (
            "scenario2/scenery_4rooms.txt",
            include_bytes!("../../../data/hstar-paper/scenario2/scenery_4rooms.txt"),
        ),
        (
            "scenario2/scenery_4rooms_B.txt",
            include_bytes!("../../../data/hstar-paper/scenario2/scenery_4rooms_B.txt"),
        ),
        (
            "scenario3/10warehouse",
            include_bytes!("../../../data/hstar-paper/scenario3/10warehouse"),
        ),
        (
            "scenario3/15warehouse",
            include_bytes!("../../../data/hstar-paper/scenario3/15warehouse"),
        ),
        (
            "scenario3/20warehouse",
            include_bytes!("../../../data/hstar-paper/scenario3/20warehouse"),
        ),
        (
            "scenario3/25warehouse",
            include_bytes!("../../../data/hstar-paper/scenario3/25warehouse"),
        ),
        (
            "scenario3/30warehouse",
            include_bytes!("../../../data/hstar-paper/scenario3/30warehouse"),
        ),
        (
            "scenario3/35warehouse",
            include_bytes!("../../../data/hstar-paper/scenario3/35warehouse"),
        ),
        (
            "scenario3/40warehouse",
            include_bytes!("../../../data/hstar-paper/scenario3/40warehouse"),
        ),
        (
            "scenario3/scenery_warehouse.txt",
            include_bytes!("../../../data/hstar-paper/scenario3/scenery_warehouse.txt"),
        ),
    ],
};

/// `data/polygon-maps` of the repository.
pub(crate) static POLYGON_MAPS: Bundle = Bundle {
    name: "polygon-maps",
    files: &[
        (
            "README.md",
            include_bytes!("../../../data/polygon-maps/README.md"),
        ),
        (
            "gaps.txt",
            include_bytes!("../../../data/polygon-maps/gaps.txt"),
        ),
        (
            "gen-dense.txt",
            include_bytes!("../../../data/polygon-maps/gen-dense.txt"),
        ),
        (
            "gen-staggered-brick-wall.txt",
            include_bytes!("../../../data/polygon-maps/gen-staggered-brick-wall.txt"),
        ),
        (
            "gen-var-density.txt",
            include_bytes!("../../../data/polygon-maps/gen-var-density.txt"),
        ),
        (
            "gen-var-density3.txt",
            include_bytes!("../../../data/polygon-maps/gen-var-density3.txt"),
        ),
        (
            "potholes.txt",
            include_bytes!("../../../data/polygon-maps/potholes.txt"),
        ),
        (
            "var_density2.txt",
            include_bytes!("../../../data/polygon-maps/var_density2.txt"),
        ),
    ],
};

/// `data/continuous` of the repository.
pub(crate) static CONTINUOUS: Bundle = Bundle {
    name: "continuous",
    files: &[
        (
            "README.md",
            include_bytes!("../../../data/continuous/README.md"),
        ),
        (
            "circle-16.json",
            include_bytes!("../../../data/continuous/circle-16.json"),
        ),
        (
            "six-robots-four-obstacles.json",
            include_bytes!("../../../data/continuous/six-robots-four-obstacles.json"),
        ),
    ],
};

#[cfg(test)]
mod tests {
    use super::*;

    /// Every bundle holds exactly its repository folder's files, byte for byte, and unpacks to
    /// them; the temporary folder goes away with the guard.
    #[test]
    fn bundles_are_the_repository_folders() {
        let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data");
        for bundle in [&HSTAR_PAPER, &POLYGON_MAPS, &CONTINUOUS] {
            let root = data.join(bundle.name);
            let mut on_disk = Vec::new();
            let mut stack = vec![root.clone()];
            while let Some(d) = stack.pop() {
                for e in std::fs::read_dir(&d).unwrap() {
                    let p = e.unwrap().path();
                    if p.is_dir() {
                        stack.push(p);
                    } else {
                        on_disk.push(p.strip_prefix(&root).unwrap().to_path_buf());
                    }
                }
            }
            on_disk.sort();
            let mut listed: Vec<PathBuf> = bundle.files.iter().map(|(r, _)| r.into()).collect();
            listed.sort();
            assert_eq!(
                listed, on_disk,
                "embedded.rs must list every file of data/{}",
                bundle.name
            );
            let (dir, guard) = data_dir(None, bundle).unwrap_or_else(|f| panic!("{}", f.0));
            for (rel, bytes) in bundle.files {
                assert_eq!(std::fs::read(dir.join(rel)).unwrap(), *bytes, "{rel}");
            }
            drop(guard);
            assert!(!dir.exists());
        }
        let (dir, guard) =
            data_dir(Some("elsewhere".into()), &CONTINUOUS).unwrap_or_else(|f| panic!("{}", f.0));
        assert_eq!((dir, guard.is_none()), (PathBuf::from("elsewhere"), true));
    }
}
