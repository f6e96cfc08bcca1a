//! The continuous family from the command line: every planner's plan on the bundled 6-robot /
//! 4-obstacle world is valid for `mrpp validate` and for the independent checker
//! `tools/check/continuous.py`, with the same metrics; bad worlds are one-line errors naming the
//! file and the item; a deadlock is reported as such, exit 3, never as a solved plan.

mod common;

use common::{mrpp, root};
use std::path::PathBuf;
use std::process::Command;

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("mrpp-continuous-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// The value after `key ` in a `a 1 | b 2` summary line.
/// A metric of `validate -v`'s `metrics: {...}` line (every digit; the summary line rounds).
fn metric(out: &str, key: &str) -> f64 {
    let json = out
        .lines()
        .find_map(|l| l.strip_prefix("metrics: "))
        .unwrap_or_else(|| panic!("no metrics line in `{out}`"));
    let v: serde_json::Value = serde_json::from_str(json).unwrap();
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("no {key} in `{json}`"))
}

#[test]
fn planners_plans_validate_and_render() {
    let w = "data/continuous/six-robots-four-obstacles.json";
    let checker = root().join("tools/check/continuous.py");
    for planner in ["hbmo", "de", "pso", "orca"] {
        let out = tmp(&format!("{planner}.json"));
        let (code, stdout, err) = mrpp(&[
            "solve",
            "--world",
            w,
            "--planner",
            planner,
            "--seed",
            "4",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, Some(0), "{planner}: {stdout}{err}");
        let (code, valid, err) = mrpp(&[
            "validate",
            "-v",
            "--world",
            w,
            "--plan",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, Some(0), "{planner}: {err}");
        assert!(valid.contains("valid: 6 agents"), "{valid}");
        {
            let o = Command::new("python3")
                .arg(&checker)
                .arg(w)
                .arg(&out)
                .current_dir(root())
                .output()
                .unwrap();
            let line = String::from_utf8_lossy(&o.stdout).trim().to_string();
            let v: serde_json::Value = serde_json::from_str(&line).unwrap();
            assert!(
                o.status.success() && v["valid"] == true,
                "{planner}: {line}"
            );
            for key in ["total_path", "mean_utd"] {
                let (ours, theirs) = (metric(&valid, key), v[key].as_f64().unwrap());
                assert!(
                    (ours - theirs).abs() < 1e-6 * ours.abs().max(1.0),
                    "{planner} {key}: {ours} vs {theirs}"
                );
            }
            assert_eq!(metric(&valid, "steps") as u64, v["steps"].as_u64().unwrap());
        }
    }
    let svg = tmp("plan.svg");
    let plan = tmp("hbmo.json");
    let (code, _, err) = mrpp(&[
        "render",
        "--world",
        w,
        "--plan",
        plan.to_str().unwrap(),
        "--out",
        svg.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{err}");
    assert!(std::fs::read_to_string(&svg).unwrap().contains("<polyline"));
    // A tampered plan (one robot teleported through an obstacle) is refused with exit 1.
    let text = std::fs::read_to_string(&plan).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["agents"][0]["path"][1] = serde_json::json!([250.0, 200.0]);
    let bad = tmp("bad-plan.json");
    std::fs::write(&bad, v.to_string()).unwrap();
    let (code, out, err) = mrpp(&["validate", "--world", w, "--plan", bad.to_str().unwrap()]);
    assert_eq!(code, Some(1), "{out}{err}");
    assert!(err.contains("robot 0"), "{err}");
}

#[test]
fn bad_worlds_are_one_line_errors_naming_the_item() {
    let base = r#"{"workspace": [0, 0, 100, 100], "obstacles": [[[40, 40], [60, 40], [60, 60], [40, 60]]], "robots": [{"start": [10, 10], "goal": [90, 90], "radius": 5, "speed": 4}ROBOT]}"#;
    let cases = [
        (
            r#", {"start": [12, 12], "goal": [80, 20], "radius": 5, "speed": 4}"#,
            "robots[0] and robots[1]: starts overlap",
        ),
        (
            r#", {"start": [50, 50], "goal": [80, 20], "radius": 5, "speed": 4}"#,
            "robots[1]: start [50.0, 50.0] inside or touching obstacles[0]",
        ),
        (
            r#", {"start": [80, 20], "goal": [20, 80], "radius": -2, "speed": 4}"#,
            "robots[1]: radius must be > 0",
        ),
        ("BROKEN", "not a continuous world"),
    ];
    for (i, (robot, needle)) in cases.iter().enumerate() {
        let text = if *robot == "BROKEN" {
            "{\"workspace\": [0, 0,".to_string()
        } else {
            base.replace("ROBOT", robot)
        };
        let f = tmp(&format!("bad{i}.json"));
        std::fs::write(&f, text).unwrap();
        let out = tmp(&format!("never{i}.json"));
        let (code, _, err) = mrpp(&[
            "solve",
            "--world",
            f.to_str().unwrap(),
            "--planner",
            "de",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, Some(1), "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(
            err.contains(&format!("bad{i}.json")) && err.contains(needle),
            "{err}"
        );
        assert!(!err.contains("panicked") && !out.exists());
    }
}

#[test]
fn a_deadlock_is_reported_as_such_with_exit_3() {
    // A robot behind a wall across the whole corridor: its goal is unreachable.
    let f = tmp("walled.json");
    std::fs::write(&f, r#"{"workspace": [0, 0, 100, 40], "obstacles": [[[45, 0], [55, 0], [55, 40], [45, 40]]],
        "robots": [{"start": [10, 20], "goal": [90, 20], "radius": 5, "speed": 4}], "step_limit": 300}"#).unwrap();
    let out = tmp("walled-plan.json");
    let (code, stdout, err) = mrpp(&[
        "solve",
        "--world",
        f.to_str().unwrap(),
        "--planner",
        "pso",
        "-p",
        "deadlock_steps=20",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(3), "{stdout}{err}");
    assert!(
        stdout.contains("deadlock") || err.contains("deadlock"),
        "{stdout}{err}"
    );
}

/// `mrpp experiment hbmo` on a small slice: its page, tables and pictures, and the same
/// trajectories and metrics with 1 and with 2 threads.
#[test]
fn hbmo_experiment_writes_its_page_and_ignores_the_thread_count() {
    let mut csvs = Vec::new();
    for threads in ["1", "2"] {
        let out = tmp(&format!("hbmo-{threads}"));
        let o = Command::new(env!("CARGO_BIN_EXE_mrpp"))
            .args([
                "experiment",
                "hbmo",
                "--runs",
                "2",
                "--planners",
                "de,orca",
                "--out",
                out.to_str().unwrap(),
            ])
            .env("RAYON_NUM_THREADS", threads)
            .current_dir(root())
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert!(
            o.status.success(),
            "{stdout}{}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(
            stdout.contains("| de | 2/2 |") && stdout.contains("paper steps"),
            "{stdout}"
        );
        for f in [
            "hbmo.md",
            "fig5-6-autd.svg",
            "fig7-11-metrics.svg",
            "fig12-de.svg",
            "fig12-orca.svg",
            "manifest.json",
        ] {
            assert!(out.join(f).exists(), "{f}");
        }
        assert!(common::every_svg_rasterises(&out) >= 4);
        let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
        // 16 worlds x 2 methods x 2 runs, without the machine-dependent runtime column.
        assert_eq!(csv.lines().count(), 1 + 16 * 2 * 2, "{csv}");
        let stable: Vec<String> = csv
            .lines()
            .map(|l| l.rsplit_once(',').unwrap().0.to_string())
            .collect();
        csvs.push(stable);
    }
    assert_eq!(csvs[0], csvs[1]);
}

/// Issue 32, item 4: `--sweep-worlds fixed` (one world, obstacles added), `-p preset=paper` for
/// the planners that have it and `-p hbmo:key=value` for one planner; the tables carry the
/// per-run UTD total beside the per-step AUTD.
#[test]
fn hbmo_experiment_takes_fixed_sweep_worlds_presets_and_per_planner_params() {
    let out = tmp("hbmo-fixed");
    let o = Command::new(env!("CARGO_BIN_EXE_mrpp"))
        .args([
            "experiment",
            "hbmo",
            "--runs",
            "1",
            "--planners",
            "hbmo,orca",
            "-p",
            "preset=paper",
            "-p",
            "hbmo:flights=2",
            "--sweep-worlds",
            "fixed",
            "--out",
            out.to_str().unwrap(),
        ])
        .current_dir(root())
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let page = std::fs::read_to_string(out.join("hbmo.md")).unwrap();
    assert!(page.contains("sweep worlds `fixed`"), "{page}");
    assert!(page.contains("UTD total (per run)"), "{page}");
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    assert!(
        csv.lines().next().unwrap().contains(",autd,utd_total,"),
        "{csv}"
    );
    // A key no chosen planner has is refused, naming it; so is a bad --sweep-worlds.
    for (args, word) in [
        (
            &["-p", "mating=absolute", "--planners", "de,orca"][..],
            "mating",
        ),
        (&["--sweep-worlds", "new"][..], "new"),
    ] {
        let o = Command::new(env!("CARGO_BIN_EXE_mrpp"))
            .args(["experiment", "hbmo", "--runs", "1", "-o"])
            .arg(tmp("hbmo-refused"))
            .args(args)
            .current_dir(root())
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(word), "{err}");
    }
}

/// Issue 30, item 11 for continuous worlds: a plan file that says solved=false shows the world
/// with every robot's start and goal (before: exit 1, "the file says solved=false: it holds no
/// plan"); validate still refuses it.
#[test]
fn an_unsolved_continuous_plan_file_shows_its_starts_and_goals() {
    let world = root().join("data/continuous/six-robots-four-obstacles.json");
    common::unsolved_plan_file_is_drawn(
        &tmp("unsolved-continuous"),
        &["--world", world.to_str().unwrap()],
        "orca",
        |_, _, _| {},
    );
}
