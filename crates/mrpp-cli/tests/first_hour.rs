//! A newcomer's first hour (issue 30): the README renders as written (item 6: a blank line after
//! the GP row turned the eleven rows after it into raw `|` text), and shell completion offers
//! planner, family and world-kind names rather than file names (item 4).

use std::path::PathBuf;

#[test]
fn the_readme_command_table_is_one_unbroken_table() {
    let readme =
        std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../README.md"))
            .unwrap();
    let lines: Vec<&str> = readme.lines().collect();
    let header = lines
        .iter()
        .position(|l| l.starts_with("| command |"))
        .expect("the README has its command table");
    // Rows run from the header to the first line that is not a row; after it, no line of the
    // section may look like a stray row.
    let end = (header..lines.len())
        .find(|&i| !lines[i].starts_with('|'))
        .unwrap_or(lines.len());
    let section_end = (end..lines.len())
        .find(|&i| lines[i].starts_with("## "))
        .unwrap_or(lines.len());
    let stray: Vec<&str> = lines[end..section_end]
        .iter()
        .copied()
        .filter(|l| l.starts_with("| `mrpp"))
        .collect();
    assert!(stray.is_empty(), "rows cut off from the table: {stray:?}");
    // Every row has the header's two columns (`\|` inside a cell is not a separator).
    for row in &lines[header..end] {
        let separators = row.replace("\\|", "").matches('|').count();
        assert_eq!(separators, 3, "not a two-column row: {row}");
    }
    assert!(end - header > 20, "the table has all its commands");
}

#[test]
fn completion_offers_planner_family_and_kind_names() {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_mrpp"))
        .args(["completions", "bash"])
        .output()
        .unwrap();
    let script = String::from_utf8_lossy(&o.stdout);
    for words in [
        "hstar ca hca whca coevolution nsga3 pibt lacam cbs eecbs psw gp sequential ga exact hbmo de pso orca",
        "grid trees formation continuous",
        "gen-dense gen-staggered-brick-wall gen-var-density gen-var-density3",
        "random circle",
    ] {
        assert!(script.contains(words), "completion lacks `{words}`");
    }
}

/// Item 7: files of two families at once are refused (before, `--map --scen --world` planned the
/// grid and silently dropped the world); a planner given too few files says which are missing;
/// negative numbers are bad values of their option, not unknown flags.
#[test]
fn mixed_or_missing_inputs_and_negative_numbers_are_named() {
    let data = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data");
    let d = |rel: &str| data.join(rel).to_string_lossy().into_owned();
    let run = |args: &[&str]| {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_mrpp"))
            .args(args)
            .current_dir(std::env::temp_dir())
            .output()
            .unwrap();
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    let (map, scen, world) = (
        d("movingai/random-32-32-20.map"),
        d("movingai/random-32-32-20-random-1.scen"),
        d("continuous/circle-16.json"),
    );
    for verb in [&["solve", "-P", "lacam", "-o", "-"][..], &["info"][..]] {
        let mut a = verb.to_vec();
        a.extend(["--map", &map, "--scen", &scen, "--world", &world]);
        let (code, err) = run(&a);
        assert_eq!(code, Some(1), "{err}");
        assert!(
            err.contains("problems of 2 families: --map --scen (grid) and --world (continuous)"),
            "{err}"
        );
    }
    let (code, err) = run(&["solve", "-P", "lacam", "--scen", &scen, "-o", "-"]);
    assert_eq!(code, Some(1));
    assert!(
        err.contains("need --map M --scen S") && err.contains("--scen alone is not enough"),
        "{err}"
    );
    let (code, err) = run(&["solve", "-P", "hbmo", "--map", &map, "-o", "-"]);
    assert_eq!(code, Some(1));
    assert!(
        err.contains("need --world W.json") && err.contains("--map names a grid problem"),
        "{err}"
    );
    for (args, says) in [
        (
            &[
                "gen",
                "map",
                "--width",
                "5",
                "--height",
                "5",
                "--obstacles",
                "-0.1",
                "-o",
                "m.map",
            ][..],
            "obstacles must be a fraction from 0 to 0.9, got -0.1",
        ),
        (
            &["experiment", "hbmo", "--runs", "-1", "-o", "h"][..],
            "'--runs <RUNS>': must be a whole number from 1, got -1",
        ),
        (
            &[
                "gen", "map", "--width", "-3", "--height", "5", "-o", "m.map",
            ][..],
            "'--width <WIDTH>': must be a whole number from 0, got -3",
        ),
    ] {
        let (code, err) = run(args);
        assert_eq!(code, Some(1), "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
        assert!(!err.contains("unexpected argument"), "{err}");
    }
}
