//! Issue 27, item 1: no output of any verb ever replaces a file the command reads, however that
//! file is named (its own name, a relative path through `..`, a symbolic link, a hard link) and
//! whether it was named on the command line or only referred to by another input (a League of
//! Robot Runners problem's map, agents and tasks; a formation file's polygon map). Every refusal
//! is exit 1, comes before any work, and leaves the file byte-identical.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A fresh folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("mrpp-outputs-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Copies the repository's `data/<rel>` (a file or a folder) into `dir`; returns the copy.
fn copy(rel: &str, dir: &Path) -> PathBuf {
    let from = root().join("data").join(rel);
    let to = dir.join(from.file_name().unwrap());
    copy_tree(&from, &to);
    to
}

fn copy_tree(from: &Path, to: &Path) {
    if from.is_dir() {
        std::fs::create_dir_all(to).unwrap();
        for e in std::fs::read_dir(from).unwrap() {
            let e = e.unwrap();
            copy_tree(&e.path(), &to.join(e.file_name()));
        }
    } else {
        std::fs::copy(from, to).unwrap();
    }
}

/// Runs `mrpp args` in `cwd`: `(exit code, stderr)`.
fn mrpp(cwd: &Path, args: &[&str]) -> (Option<i32>, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_mrpp"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("run mrpp");
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// The ways to name `file` from `cwd` besides its own path: through `..`, a symbolic link and a
/// hard link (both made in `cwd`).
fn spellings(file: &Path, cwd: &Path) -> Vec<String> {
    let parent = file.parent().unwrap();
    let dotdot = parent
        .join("..")
        .join(parent.file_name().unwrap())
        .join(file.file_name().unwrap());
    let stem = file.file_name().unwrap().to_string_lossy().into_owned();
    let link = cwd.join(format!("link-to-{stem}.json"));
    let hard = cwd.join(format!("hard-{stem}.json"));
    let _ = std::fs::remove_file(&link);
    let _ = std::fs::remove_file(&hard);
    std::os::unix::fs::symlink(file, &link).unwrap();
    std::fs::hard_link(file, &hard).unwrap();
    [file.to_path_buf(), dotdot, link, hard]
        .iter()
        .map(|p| p.to_string_lossy().into_owned())
        .collect()
}

/// Runs `args` with `out` appended after `flag` for every spelling of each of `files`: each must
/// be refused (exit 1, a message naming an input) and leave the file byte-identical.
fn refused_for_each(cwd: &Path, args: &[&str], flag: &str, files: &[PathBuf]) {
    for file in files {
        let before = std::fs::read(file).unwrap();
        for out in spellings(file, cwd) {
            let mut a = args.to_vec();
            a.extend([flag, out.as_str()]);
            let (code, err) = mrpp(cwd, &a);
            assert_eq!(code, Some(1), "{a:?}: {err}");
            assert!(
                err.contains("would overwrite the input") || err.contains("input folder"),
                "{a:?}: {err}"
            );
            assert_eq!(
                std::fs::read(file).unwrap(),
                before,
                "{a:?} changed {}",
                file.display()
            );
        }
    }
}

#[test]
fn lorr_problems_refuse_outputs_onto_the_files_they_name() {
    let dir = scratch("lorr");
    let kit = copy("robot-runners/lorr2023-warehouse_small", &dir);
    let problem = kit.join("warehouse_small_10.json");
    let named = [
        kit.join("maps/warehouse_small.map"),
        kit.join("agents/warehouse_small_10.agents"),
        kit.join("tasks/warehouse_small.tasks"),
        problem.clone(),
    ];
    let p = problem.to_string_lossy().into_owned();
    for planner in ["lacam", "pibt"] {
        refused_for_each(
            &dir,
            &[
                "solve", "--lorr", &p, "-P", planner, "--format", "json", "-t", "5",
            ],
            "--out",
            &named,
        );
    }
    // The same problem, planned into a fresh file, still works afterwards.
    let (code, err) = mrpp(
        &dir,
        &["solve", "--lorr", &p, "-P", "lacam", "-o", "plan.json"],
    );
    assert_eq!(code, Some(0), "{err}");
    // view and render may not replace them either.
    for verb in ["view", "render"] {
        let picture = if verb == "render" { ".svg" } else { ".html" };
        let named_svg: Vec<PathBuf> = named
            .iter()
            .map(|f| {
                let g = f.with_extension(&picture[1..]);
                std::fs::copy(f, &g).unwrap();
                g
            })
            .collect();
        // Symbolic links to inputs with a picture's extension.
        for (input, alias) in named.iter().zip(&named_svg) {
            std::fs::remove_file(alias).unwrap();
            std::os::unix::fs::symlink(input, alias).unwrap();
            let (code, err) = mrpp(
                &dir,
                &[
                    verb,
                    "--lorr",
                    &p,
                    "--plan",
                    "plan.json",
                    "--out",
                    alias.to_str().unwrap(),
                ],
            );
            assert_eq!(code, Some(1), "{verb} {}: {err}", alias.display());
            assert!(err.contains("would overwrite the input"), "{err}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn formation_files_refuse_outputs_onto_their_polygon_map() {
    let dir = scratch("formation");
    let maps = copy("polygon-maps", &dir);
    let forms = copy("formation", &dir);
    let f = forms.join("gaps-3.json");
    let fs = f.to_string_lossy().into_owned();
    let named = [maps.join("gaps.txt"), f.clone()];
    refused_for_each(
        &dir,
        &["solve", "--formation", &fs, "-P", "sequential"],
        "--out",
        &named,
    );
    // `gen formation` reads the polygon map: its output may not replace it.
    let m = maps.join("gaps.txt").to_string_lossy().into_owned();
    refused_for_each(
        &dir,
        &[
            "gen",
            "formation",
            "--map",
            &m,
            "--robots",
            "2",
            "--seed",
            "1",
        ],
        "--out",
        &[maps.join("gaps.txt")],
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn grid_tree_and_continuous_inputs_are_refused_however_named() {
    let dir = scratch("families");
    let movingai = copy("movingai", &dir);
    let map = movingai.join("random-32-32-20.map");
    let scen = movingai.join("random-32-32-20-random-1.scen");
    let (m, s) = (
        map.to_string_lossy().into_owned(),
        scen.to_string_lossy().into_owned(),
    );
    refused_for_each(
        &dir,
        &[
            "solve", "-m", &m, "-i", &s, "-N", "10", "-P", "pibt", "--format", "json",
        ],
        "--out",
        &[map.clone(), scen.clone()],
    );
    refused_for_each(
        &dir,
        &["convert", "-m", &m, "--out-map", "x.map", "-i", &s],
        "--out-scen",
        std::slice::from_ref(&scen),
    );

    let trees = copy("trees", &dir);
    let instance = trees.join("example.json");
    let program = trees.join("example-program.gp");
    let (i, p) = (
        instance.to_string_lossy().into_owned(),
        program.to_string_lossy().into_owned(),
    );
    refused_for_each(
        &dir,
        &["trees", "run", "--program", &p, "--instance", &i],
        "--out",
        &[instance.clone(), program.clone()],
    );
    refused_for_each(
        &dir,
        &[
            "trees",
            "solve",
            "--instance",
            &i,
            "-P",
            "gp",
            "--generations",
            "1",
            "--population",
            "4",
            "-o",
            "tree-plan.json",
        ],
        "--save-program",
        std::slice::from_ref(&instance),
    );

    let continuous = copy("continuous", &dir);
    let world = continuous.join("six-robots-four-obstacles.json");
    let w = world.to_string_lossy().into_owned();
    refused_for_each(
        &dir,
        &["solve", "--world", &w, "-P", "orca"],
        "--out",
        std::slice::from_ref(&world),
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn output_folders_refuse_to_hold_or_sit_inside_inputs() {
    let dir = scratch("folders");
    let movingai = copy("movingai", &dir);
    let map = movingai.join("random-32-32-20.map");
    let scen = movingai.join("random-32-32-20-random-1.scen");
    let (m, s) = (
        map.to_string_lossy().into_owned(),
        scen.to_string_lossy().into_owned(),
    );
    let before = std::fs::read(&map).unwrap();
    // A bench whose output folder holds its map, or is the map's folder.
    for out in [
        dir.to_string_lossy().into_owned(),
        movingai.to_string_lossy().into_owned(),
    ] {
        let (code, err) = mrpp(
            &dir,
            &[
                "bench",
                "run",
                "-m",
                &m,
                "-i",
                &s,
                "-N",
                "5",
                "--planners",
                "pibt",
                "-o",
                &out,
            ],
        );
        assert_eq!(code, Some(1), "{err}");
        assert!(err.contains("holds the input"), "{err}");
    }
    // An experiment writing into (a folder inside) its --data folder.
    let hstar = copy("hstar-paper", &dir);
    let h = hstar.to_string_lossy().into_owned();
    for out in [h.clone(), format!("{h}/results"), format!("{h}/scenario1")] {
        let (code, err) = mrpp(
            &dir,
            &[
                "experiment",
                "hstar-table2",
                "--runs",
                "1",
                "--data",
                &h,
                "-o",
                &out,
            ],
        );
        assert_eq!(code, Some(1), "{out}: {err}");
        assert!(err.contains("input folder"), "{out}: {err}");
    }
    assert!(!hstar.join("results").exists());
    assert_eq!(std::fs::read(&map).unwrap(), before);
    let _ = std::fs::remove_dir_all(&dir);
}
