//! Helpers shared by the CLI test files (each includes this module with `mod common;`).

use std::path::{Path, PathBuf};
use std::process::Command;

/// The repository's root: the tests run `mrpp` from there so that `data/...` paths resolve.
#[allow(dead_code)]
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Runs `mrpp args` from the repository's root: its exit code, stdout and stderr.
#[allow(dead_code)]
pub fn mrpp(args: &[&str]) -> (Option<i32>, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_mrpp"))
        .args(args)
        .current_dir(root())
        .output()
        .unwrap();
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// Runs `mrpp args` from the repository's root, asserts that it exits with `code` and returns
/// its stdout and stderr.
#[allow(dead_code)]
pub fn mrpp_exits(args: &[&str], code: i32) -> (String, String) {
    let (got, out, err) = mrpp(args);
    assert_eq!(got, Some(code), "mrpp {args:?}\n{out}\n{err}");
    (out, err)
}

/// Every `.svg` in `dir` (and its subfolders) parses and rasterises to a PNG with something drawn
/// on it: the experiments' figures are what a person will look at (issue 12). Returns how many
/// were checked.
#[allow(dead_code)]
pub fn every_svg_rasterises(dir: &Path) -> usize {
    let mut opt = resvg::usvg::Options::default();
    opt.fontdb_mut().load_system_fonts();
    let mut checked = 0;
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            if path.extension().is_none_or(|e| e != "svg") {
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            let tree = resvg::usvg::Tree::from_str(&text, &opt)
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            let size = tree.size().to_int_size();
            let mut pixmap = resvg::tiny_skia::Pixmap::new(size.width(), size.height()).unwrap();
            resvg::render(
                &tree,
                resvg::tiny_skia::Transform::default(),
                &mut pixmap.as_mut(),
            );
            // More than a background: at least 3 colours on the picture.
            let mut colours = std::collections::HashSet::new();
            for p in pixmap.pixels() {
                colours.insert((p.red(), p.green(), p.blue(), p.alpha()));
                if colours.len() >= 3 {
                    break;
                }
            }
            assert!(colours.len() >= 3, "{}: nothing drawn", path.display());
            assert!(!pixmap.encode_png().unwrap().is_empty());
            checked += 1;
        }
    }
    checked
}

/// Issue 30, item 11, for any family: solves `inputs` (absolute paths) with `planner` in `dir`,
/// rewrites the plan file to say `solved: false`, then checks that `render` and `view` of it
/// exit 0 with "holds no plan (solved=false" on stderr and a non-empty picture (`check` gets the
/// verb, the stderr and the picture's path for more), and that `validate` refuses it (exit 1).
#[allow(dead_code)]
pub fn unsolved_plan_file_is_drawn(
    dir: &Path,
    inputs: &[&str],
    planner: &str,
    check: impl Fn(&str, &str, &Path),
) {
    let run = |args: &[&str]| {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_mrpp"))
            .args(args)
            .args(inputs)
            .current_dir(dir)
            .output()
            .expect("run mrpp");
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    std::fs::create_dir_all(dir).unwrap();
    let solved = dir.join("solved.json");
    let (code, err) = run(&["solve", "-P", planner, "-o", solved.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{err}");
    let text = std::fs::read_to_string(&solved).unwrap();
    assert!(text.contains("\"solved\": true"), "{text}");
    let unsolved = dir.join("unsolved.json");
    std::fs::write(
        &unsolved,
        text.replace("\"solved\": true", "\"solved\": false")
            .replace("\"status\": \"solved\"", "\"status\": \"time_limit\""),
    )
    .unwrap();
    let u = unsolved.to_str().unwrap();
    for (verb, name) in [("render", "unsolved.svg"), ("view", "unsolved.html")] {
        let pic = dir.join(name);
        let (code, err) = run(&[verb, "--plan", u, "-o", pic.to_str().unwrap()]);
        assert_eq!(code, Some(0), "{verb}: {err}");
        assert!(err.contains("holds no plan (solved=false"), "{verb}: {err}");
        assert!(std::fs::metadata(&pic).unwrap().len() > 0, "{verb}");
        check(verb, &err, &pic);
    }
    let (code, err) = run(&["validate", "--plan", u]);
    assert_eq!(code, Some(1), "{err}");
}
