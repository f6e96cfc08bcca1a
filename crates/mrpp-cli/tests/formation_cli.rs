//! The formation family from the command line: every planner's plan on a bundled formation is
//! valid for `mrpp validate` and for the independent checker (`tools/check/formation.py`), with
//! the same c_max; `exact` is never worse than `ga`, nor `ga` than `sequential`; malformed polygon
//! maps are one-line errors naming file and line.

mod common;

use common::{mrpp, root};
use std::path::{Path, PathBuf};
use std::process::Command;

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("mrpp-formation-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// `c_max` of `validate -v`'s `metrics: {...}` line (every digit; the summary line rounds).
fn c_max(out: &str) -> f64 {
    let json = out
        .lines()
        .find_map(|l| l.strip_prefix("metrics: "))
        .unwrap_or_else(|| panic!("no metrics line in `{out}`"));
    let v: serde_json::Value = serde_json::from_str(json).unwrap();
    v["c_max"]
        .as_f64()
        .unwrap_or_else(|| panic!("no c_max in `{json}`"))
}

#[test]
fn planners_plans_validate_and_agree_with_the_checker() {
    let f = "data/formation/var_density2-3.json";
    let mut costs = Vec::new();
    for planner in ["sequential", "ga", "exact"] {
        let out = tmp(&format!("{planner}.json"));
        let (code, stdout, err) = mrpp(&[
            "solve",
            "--formation",
            f,
            "--planner",
            planner,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, Some(0), "{planner}: {stdout}{err}");
        let (code, valid, err) = mrpp(&[
            "validate",
            "-v",
            "--formation",
            f,
            "--plan",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, Some(0), "{planner}: {err}");
        let ours = c_max(&valid);
        let o = Command::new("python3")
            .arg(root().join("tools/check/formation.py"))
            .arg(&out)
            .output()
            .unwrap();
        let line = String::from_utf8_lossy(&o.stdout).trim().to_string();
        let v: serde_json::Value = serde_json::from_str(&line).unwrap();
        assert!(
            o.status.success() && v["valid"] == true,
            "{planner}: {line}"
        );
        let theirs = v["c_max"].as_f64().unwrap();
        assert!(
            (ours - theirs).abs() < 1e-9 * ours,
            "{planner}: mrpp {ours} checker {theirs}"
        );
        costs.push(ours);
    }
    assert!(
        costs[2] <= costs[1] + 1e-9 && costs[1] <= costs[0] + 1e-9,
        "{costs:?}"
    );
    let svg = tmp("plan.svg");
    let plan = tmp("ga.json");
    let (code, _, err) = mrpp(&[
        "render",
        "--formation",
        f,
        "--plan",
        plan.to_str().unwrap(),
        "--out",
        svg.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{err}");
    assert!(std::fs::read_to_string(&svg).unwrap().contains("<polyline"));
}

#[test]
fn malformed_polygon_maps_are_one_line_errors() {
    let border = "[BORDER]\n0 0\n10 0\n10 10\n0 10\n";
    let cases = [
        (
            format!("{border}[OBSTACLE]\n1 1\n2 2\n"),
            ":6:",
            "at least 3",
        ),
        (
            format!("{border}[OBSTACLE]\n1 1\n3 1\n1 3\n3 3\n"),
            ":6:",
            "intersects itself",
        ),
        (
            format!("{border}[OBSTACLE]\n1 1\n20 1\n1 3\n"),
            ":6:",
            "outside the border",
        ),
        (format!("{border}[HOLE]\n1 1\n"), ":6:", "unknown section"),
        (format!("{border}[OBSTACLE]\n1 x\n"), ":7:", "not a number"),
        (
            format!("{border}[OBSTACLE]\n1 1\n1 1\n3 3\n"),
            ":6:",
            "coincide",
        ),
    ];
    for (i, (text, line, needle)) in cases.iter().enumerate() {
        let map = tmp(&format!("bad{i}.txt"));
        std::fs::write(&map, text).unwrap();
        let f = tmp(&format!("bad{i}.json"));
        std::fs::write(
            &f,
            format!(
                r#"{{"map": "{}", "robots": 2, "start": [0.5, 0.5], "goal": [9, 9]}}"#,
                map.file_name().unwrap().to_str().unwrap()
            ),
        )
        .unwrap();
        let (code, _, err) = mrpp(&["info", "--formation", f.to_str().unwrap()]);
        assert_eq!(code, Some(1), "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(
            err.contains(&format!("bad{i}.txt{line}")) && err.contains(needle),
            "{err}"
        );
        assert!(!err.contains("panicked"));
    }
    // A start inside an obstacle of gaps.txt (x 7.84..11.52, y 0..8.32 after scaling).
    let f = tmp("walled.json");
    let map = root().join("data/polygon-maps/gaps.txt");
    let text = format!(
        r#"{{"map": {:?}, "robots": 2, "start": [9, 2], "goal": [30, 30]}}"#,
        map.to_str().unwrap()
    );
    std::fs::write(&f, text).unwrap();
    let (code, _, err) = mrpp(&[
        "solve",
        "--formation",
        f.to_str().unwrap(),
        "--planner",
        "ga",
    ]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("walled.json") && err.contains("not in free space"),
        "{err}"
    );
    assert!(Path::new(&map).exists());
}

#[test]
fn ga_formation_experiment_writes_its_page() {
    let out = tmp("gaf");
    let (code, stdout, err) = mrpp(&[
        "experiment",
        "ga-formation",
        "--pairs",
        "1",
        "--robots",
        "1,3",
        "--save-plans",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{stdout}{err}");
    assert!(
        stdout.contains("| all | 14 |") && stdout.contains("| paper |"),
        "{stdout}"
    );
    assert!(common::every_svg_rasterises(&out) >= 2);
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 7 * 2, "{csv}");
    // On every configuration: optimum <= GA <= sequential.
    for line in csv.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let (seq, ga, opt): (f64, f64, f64) = (
            f[7].parse().unwrap(),
            f[8].parse().unwrap(),
            f[9].parse().unwrap(),
        );
        assert!(opt <= ga + 1e-6 && ga <= seq + 1e-6, "{line}");
        // Every plan of the configuration passes the independent checker with the same c_max.
        let name =
            |planner: &str| out.join(format!("plans/{}-{}-r{}-{planner}.json", f[0], f[1], f[2]));
        let plans = [("sequential", seq), ("ga", ga), ("exact", opt)];
        let o = Command::new("python3")
            .arg(root().join("tools/check/formation.py"))
            .args(plans.iter().map(|(p, _)| name(p)))
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(o.status.success(), "{line}: {text}");
        for ((planner, c), verdict) in plans.iter().zip(text.lines()) {
            let v: serde_json::Value = serde_json::from_str(verdict).unwrap();
            let theirs = v["c_max"].as_f64().unwrap();
            assert!(
                (theirs - c).abs() < 1e-5 * c.max(1.0),
                "{line} {planner}: {verdict}"
            );
        }
    }
    for f in [
        "ga-formation.md",
        "fig4.svg",
        "fig5.svg",
        "records.csv",
        "manifest.json",
    ] {
        assert!(out.join(f).exists(), "{f}");
    }
}

/// `--cost` picks the corridor cost model (issue 32, item 3). Under `hard` a corridor's
/// capacity is a wall, so some three-robot formations fit no plan: the GA then has none (an
/// infinite c_max in results.csv) and the experiment goes on instead of failing.
#[test]
fn ga_formation_experiment_takes_a_cost_model() {
    let out = tmp("gaf-hard");
    let (code, stdout, err) = mrpp(&[
        "experiment",
        "ga-formation",
        "--pairs",
        "2",
        "--robots",
        "3",
        "--cost",
        "hard",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{stdout}{err}");
    let page = std::fs::read_to_string(out.join("ga-formation.md")).unwrap();
    assert!(page.contains("cost model hard"), "{page}");
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let ga: Vec<f64> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(8).unwrap().parse().unwrap())
        .collect();
    assert_eq!(ga.len(), 7 * 2, "{csv}");
    assert!(
        ga.iter().any(|c| c.is_infinite()),
        "no formation over capacity: {csv}"
    );
    assert!(ga.iter().any(|c| c.is_finite()), "{csv}");
    let (code, _, err) = mrpp(&[
        "experiment",
        "ga-formation",
        "--cost",
        "lanes",
        "--kappa",
        "-1",
        "--out",
        tmp("gaf-bad").to_str().unwrap(),
    ]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("--kappa must be between 0 and 10"), "{err}");
    assert!(!tmp("gaf-bad").exists());
}

/// Issue 30, item 11 for formations: a plan file that says solved=false shows Q_ini, Q_goal and
/// the roadmap (before: exit 1, "the file says solved=false: it holds no plan"); validate still
/// refuses it.
#[test]
fn an_unsolved_formation_plan_file_shows_its_start_and_goal() {
    let formation = root().join("data/formation/gaps-3.json");
    common::unsolved_plan_file_is_drawn(
        &tmp("unsolved-formation"),
        &["--formation", formation.to_str().unwrap()],
        "ga",
        |verb, _, pic| {
            let drawn = std::fs::read_to_string(pic).unwrap();
            assert!(drawn.contains("Q_goal"), "{verb}");
        },
    );
}
