//! Issue 29, item 3 end to end: `mrpp execute` runs a grid plan under seeded delays with the ADG
//! executor (no collision) or naively (collisions, exit 3), writes the executed record, and
//! refuses bad delay specs, absurd options and a plan of another map: exit 1, nothing written.

mod common;

use common::{mrpp, root};
use std::path::Path;
use std::process::Command;

const MAP: &str = "data/movingai/random-32-32-20.map";

/// `tools/check/execution.py`'s verdict, or `None` without python3 (CI has it).
fn checker(plan: &Path, trace: &Path) -> Option<serde_json::Value> {
    let o = Command::new("python3")
        .arg("tools/check/execution.py")
        .arg(MAP)
        .arg(plan)
        .arg(trace)
        .current_dir(root())
        .output()
        .ok()?;
    Some(
        serde_json::from_slice(&o.stdout)
            .unwrap_or_else(|e| panic!("checker: {e}: {}", String::from_utf8_lossy(&o.stdout))),
    )
}

fn execute(plan: &Path, out: &Path, extra: &[&str]) -> (Option<i32>, String) {
    let mut args = vec![
        "execute",
        "-m",
        MAP,
        "--plan",
        plan.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let (code, _, err) = mrpp(&args);
    (code, err)
}

#[test]
fn a_plan_runs_late_safely_with_the_adg_and_collides_naively() {
    let dir = std::env::temp_dir().join(format!("mrpp-execute-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let plan = dir.join("plan.json");
    let (code, _, err) = mrpp(&[
        "solve",
        "-m",
        MAP,
        "-i",
        "data/movingai/random-32-32-20-random-1.scen",
        "-N",
        "60",
        "-P",
        "lacam",
        "-o",
        plan.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{err}");
    let delays = [
        "--delays",
        "bernoulli:p=0.02,min=1,max=4",
        "--ticks-per-move",
        "3",
        "-s",
        "5",
    ];
    let adg = dir.join("adg.json");
    let (code, err) = execute(
        &plan,
        &adg,
        &[&delays[..], &["--agent-size", "0.5"]].concat(),
    );
    assert_eq!(code, Some(0), "{err}");
    let record: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&adg).unwrap()).unwrap();
    assert_eq!(record["format"], "mrpp-execution/1");
    assert_eq!(record["executor"], "adg");
    assert_eq!(record["ending"], "finished");
    assert_eq!(record["agents"].as_array().unwrap().len(), 60);
    let m = &record["metrics"];
    assert_eq!(m["collisions"], 0);
    assert!(m["ticks_lost_to_delays"].as_u64().unwrap() > 0, "{m}");
    assert!(m["makespan_ratio"].as_f64().unwrap() >= 1.0, "{m}");
    // The same delays, the plan's timing: collisions, exit 3, the record still written.
    let naive = dir.join("naive.json");
    let (code, err) = execute(
        &plan,
        &naive,
        &[&delays[..], &["--agent-size", "0.5", "--executor", "naive"]].concat(),
    );
    assert_eq!(code, Some(3), "{err}");
    assert!(err.contains("collided"), "{err}");
    assert!(naive.exists());
    // The League's executor stops for good at the plan's rings (LaCAM's plan has some here).
    let tpg = dir.join("tpg.json");
    let (code, err) = execute(
        &plan,
        &tpg,
        &[&delays[..], &["--agent-size", "0.5", "--executor", "tpg"]].concat(),
    );
    assert_eq!(code, Some(3), "{err}");
    assert!(err.contains("deadlock at tick"), "{err}");
    // The independent checker (Python, standard library) replays both records and agrees on
    // their collisions and costs; a record with one move made a tick faster is refused.
    for (trace, collided) in [(&adg, false), (&naive, true)] {
        if let Some(v) = checker(&plan, trace) {
            assert_eq!(v["valid"], true, "{v}");
            let record: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(trace).unwrap()).unwrap();
            assert_eq!(v["collisions"], record["metrics"]["collisions"]);
            assert_eq!(v["makespan"], record["metrics"]["makespan"]);
            assert_eq!(v["collisions"].as_u64().unwrap() > 0, collided);
        }
    }
    let mut tampered = record.clone();
    let moved = tampered["agents"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .find(|a| !a["moves"].as_array().unwrap().is_empty())
        .unwrap();
    let end = moved["moves"][0][1].as_u64().unwrap();
    moved["moves"][0][1] = serde_json::json!(end - 1);
    let bad_trace = dir.join("tampered.json");
    std::fs::write(&bad_trace, tampered.to_string()).unwrap();
    if let Some(v) = checker(&plan, &bad_trace) {
        assert_eq!(v["valid"], false, "{v}");
    }
    // Bad inputs: named, exit 1, nothing written.
    let bad = dir.join("bad.json");
    for (extra, says) in [
        (
            vec!["--delays", "bernoulli:p=0.1,min=4,max=2"],
            "min=4 is above max=2",
        ),
        (
            vec!["--delays", "uniform:p=0.1,min=1,max=2"],
            "unknown model",
        ),
        (
            vec!["--ticks-per-move", "0"],
            "must be a whole number from 1",
        ),
        (vec!["--agent-size", "1.5"], "--agent-size 1.5"),
        (vec!["--executor", "fast"], "--executor fast"),
    ] {
        let (code, err) = execute(&plan, &bad, &extra);
        assert_eq!(code, Some(1), "{extra:?}: {err}");
        assert!(err.contains(says), "{extra:?}: {err}");
        assert!(!bad.exists());
    }
    let (code, _, err) = mrpp(&[
        "execute",
        "-m",
        "data/movingai/empty-8-8.map",
        "--plan",
        plan.to_str().unwrap(),
        "-o",
        bad.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(1), "{err}");
    assert!(!bad.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_execution_experiment_sweeps_delays_and_executors() {
    let dir = std::env::temp_dir().join(format!("mrpp-execution-exp-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = dir.join("exp");
    let (code, _, err) = mrpp(&[
        "experiment",
        "execution",
        "--instance",
        "data/movingai/random-32-32-20.map:data/movingai/random-32-32-20-random-1.scen:40",
        "--planners",
        "lacam,pibt",
        "--delays",
        "0,0.05",
        "--runs",
        "3",
        "--replan",
        "0,20",
        "--jobs",
        "1",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{err}");
    for f in [
        "results.csv",
        "execution.md",
        "execution.svg",
        "manifest.json",
    ] {
        assert!(out.join(f).exists(), "{f}");
    }
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    // planner, p, executor, k, replan_drift, replans, status, collisions: columns 2, 3, 4, 5,
    // 6, 7, 10, 11.
    assert_eq!(
        rows.len(),
        2 * 2 * 2 * 2 * 2 * 3,
        "planners x p x k x re-planning x executors x runs"
    );
    for r in &rows {
        assert_eq!(r[10], "finished", "{r:?}");
        if r[4] == "adg" || r[3] == "0" {
            assert_eq!(r[11], "0", "adg, or no delay at all, never collides: {r:?}");
        }
        if r[6] == "0" || r[3] == "0" {
            assert_eq!(r[7], "0", "no re-planning without drift: {r:?}");
        }
    }
    let replans: usize = rows
        .iter()
        .filter(|r| r[4] == "adg" && r[3] == "0.05" && r[6] == "20")
        .map(|r| r[7].parse::<usize>().unwrap())
        .sum();
    assert!(replans > 0, "drift of 20 ticks at p = 0.05 re-plans");
    let collisions = |k: &str| -> usize {
        rows.iter()
            .filter(|r| r[4] == "naive" && r[3] == "0.05" && r[5] == k && r[6] == "0")
            .map(|r| r[11].parse::<usize>().unwrap())
            .sum()
    };
    assert!(
        collisions("0") > 0,
        "the naive executor collides under delays"
    );
    assert!(
        collisions("2") < collisions("0"),
        "2-robust plans collide less when executed naively"
    );
    let (code, _, err) = mrpp(&[
        "experiment",
        "execution",
        "--executors",
        "adg,fast",
        "-o",
        dir.join("bad").to_str().unwrap(),
    ]);
    assert_eq!(code, Some(1));
    assert!(err.contains("fast is not adg, tpg or naive"), "{err}");
    assert!(!dir.join("bad").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_k_robust_plan_collides_less_when_executed_naively() {
    let dir = std::env::temp_dir().join(format!("mrpp-execute-robust-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let plan = dir.join("plan.json");
    let (code, _, err) = mrpp(&[
        "solve",
        "-m",
        MAP,
        "-i",
        "data/movingai/random-32-32-20-random-1.scen",
        "-N",
        "60",
        "-P",
        "lacam",
        "-o",
        plan.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{err}");
    let mut collisions = Vec::new();
    for k in ["0", "3"] {
        let out = dir.join(format!("k{k}.json"));
        let (code, err) = execute(
            &plan,
            &out,
            &[
                "--executor",
                "naive",
                "--delays",
                "bernoulli:p=0.005,min=1,max=6",
                "--ticks-per-move",
                "3",
                "--agent-size",
                "0.5",
                "--k-robust",
                k,
                "-s",
                "4",
            ],
        );
        assert!(code == Some(0) || code == Some(3), "{err}");
        let record: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        assert_eq!(record["k_robust"], k.parse::<u64>().unwrap());
        collisions.push(record["metrics"]["collisions"].as_u64().unwrap());
        if let Some(v) = checker(&plan, &out) {
            assert_eq!(v["valid"], true, "{v}");
            assert_eq!(v["collisions"], record["metrics"]["collisions"], "{v}");
        }
    }
    assert!(collisions[1] < collisions[0], "{collisions:?}");
    let (code, err) = execute(&plan, &dir.join("bad.json"), &["--k-robust", "-1"]);
    assert_eq!(code, Some(1));
    assert!(err.contains("--k-robust -1: expected 0 to 1000"), "{err}");
    assert!(!dir.join("bad.json").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn replanning_on_drift_takes_over_and_the_checker_accepts_the_record() {
    let dir = std::env::temp_dir().join(format!("mrpp-execute-replan-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let plan = dir.join("plan.json");
    let scen = "data/movingai/random-32-32-20-random-1.scen";
    let (code, _, err) = mrpp(&[
        "solve",
        "-m",
        MAP,
        "-i",
        scen,
        "-N",
        "60",
        "-P",
        "lacam",
        "-o",
        plan.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{err}");
    let delays = [
        "--delays",
        "bernoulli:p=0.02,min=1,max=10",
        "--ticks-per-move",
        "3",
    ];
    let out = dir.join("replanned.json");
    let mut args = delays.to_vec();
    args.extend([
        "--agent-size",
        "0.5",
        "--replan-drift",
        "20",
        "--replan-planner",
        "eecbs",
    ]);
    let (code, err) = execute(&plan, &out, &args);
    assert_eq!(code, Some(0), "{err}");
    let record: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(record["replan_drift"], 20);
    let replans = record["replans"].as_array().unwrap();
    assert!(!replans.is_empty(), "{record}");
    assert_eq!(record["metrics"]["replans"], replans.len());
    assert_eq!(record["metrics"]["collisions"], 0);
    if let Some(v) = checker(&plan, &out) {
        assert_eq!(v["valid"], true, "{v}");
        assert_eq!(v["makespan"], record["metrics"]["makespan"], "{v}");
    }
    // An unknown re-planner: exit 1, nothing written.
    let bad = dir.join("bad.json");
    let mut args = delays.to_vec();
    args.extend(["--replan-drift", "20", "--replan-planner", "fastest"]);
    let (code, err) = execute(&plan, &bad, &args);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("--replan-planner fastest: not a grid planner"),
        "{err}"
    );
    assert!(!bad.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
