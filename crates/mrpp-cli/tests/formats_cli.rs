//! Issue 31, item 3 end to end: `mrpp convert --plan` takes a solved grid plan through the
//! field's result formats (plan envelope -> MAPF Tracker CSV -> PlanViz JSON -> LaCAM text ->
//! envelope) with the same paths; `mrpp validate` reads each; the independent checkers
//! (`tools/check/tracker.py`, `tools/check/planviz.py`) accept the converted files and reject
//! tampered ones, as `mrpp` does (exit 1 naming file and rule, nothing written, inputs never
//! overwritten).

mod common;

use common::{mrpp, root};
use std::path::Path;
use std::process::Command;

const MAP: &str = "data/movingai/random-32-32-20.map";
const SCEN: &str = "data/movingai/random-32-32-20-random-1.scen";

/// A checker's verdict, or `None` without python3 (CI has it).
fn checker(script: &str, args: &[&Path]) -> Option<serde_json::Value> {
    let o = Command::new("python3")
        .arg(script)
        .args(args)
        .current_dir(root())
        .output()
        .ok()?;
    Some(
        serde_json::from_slice(&o.stdout)
            .unwrap_or_else(|e| panic!("{script}: {e}: {}", String::from_utf8_lossy(&o.stdout))),
    )
}

/// Each agent's cells with trailing repeats dropped.
fn paths(envelope: &Path) -> Vec<Vec<serde_json::Value>> {
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(envelope).unwrap()).unwrap();
    v["agents"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| {
            let mut p = a["path"].as_array().unwrap().clone();
            while p.len() >= 2 && p[p.len() - 1] == p[p.len() - 2] {
                p.pop();
            }
            p
        })
        .collect()
}

fn convert(plan: &Path, to: &str, out: &Path) -> (Option<i32>, String) {
    let (code, _, err) = mrpp(&[
        "convert",
        "-m",
        MAP,
        "-i",
        SCEN,
        "--plan",
        plan.to_str().unwrap(),
        "--to",
        to,
        "--out",
        out.to_str().unwrap(),
    ]);
    (code, err)
}

#[test]
fn plans_round_trip_through_every_format_and_pass_the_checkers() {
    let dir = std::env::temp_dir().join(format!("mrpp-formats-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = |name: &str| dir.join(name);
    let (code, _, err) = mrpp(&[
        "solve",
        "-m",
        MAP,
        "-i",
        SCEN,
        "-N",
        "60",
        "-P",
        "lacam",
        "-q",
        "-o",
        f("plan.json").to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{err}");
    for (from, to, out) in [
        ("plan.json", "tracker", "plan.csv"),
        ("plan.csv", "planviz", "planviz.json"),
        ("planviz.json", "lacam", "plan.lacam"),
        ("plan.lacam", "envelope", "back.json"),
    ] {
        let (code, err) = convert(&f(from), to, &f(out));
        assert_eq!(code, Some(0), "{from} -> {to}: {err}");
        let (code, stdout, err) = mrpp(&[
            "validate",
            "-m",
            MAP,
            "-i",
            SCEN,
            "--plan",
            f(out).to_str().unwrap(),
        ]);
        assert_eq!(code, Some(0), "validate {out}: {err}");
        assert!(stdout.contains("valid: 60 agents"), "{stdout}");
    }
    assert_eq!(paths(&f("plan.json")), paths(&f("back.json")));
    let csv = std::fs::read_to_string(f("plan.csv")).unwrap();
    assert!(csv.starts_with(
        "map_name,scen_type,type_id,agents,lower_cost,solution_cost,solution_plan\nrandom-32-32-20,random,1,60,"
    ));

    let (map, scen) = (root().join(MAP), root().join(SCEN));
    if let Some(v) = checker("tools/check/tracker.py", &[&map, &scen, &f("plan.csv")]) {
        assert_eq!(v["valid"], true, "{v}");
    }
    if let Some(v) = checker("tools/check/planviz.py", &[&map, &f("planviz.json"), &scen]) {
        assert_eq!(v["valid"], true, "{v}");
    }

    // Tampered: the stated solution_cost one more than the plan's, and in the PlanViz file an
    // agent's first move turned around.
    let fields: Vec<&str> = csv.lines().nth(1).unwrap().split(',').collect();
    let cost: u64 = fields[5].parse().unwrap();
    let tampered = csv.replacen(&format!(",{cost},\""), &format!(",{},\"", cost + 1), 1);
    assert_ne!(tampered, csv);
    std::fs::write(f("bad.csv"), &tampered).unwrap();
    let (code, err) = convert(&f("bad.csv"), "planviz", &f("never.json"));
    assert_eq!(code, Some(1));
    assert!(
        err.contains("bad.csv:2") && err.contains("solution_cost"),
        "{err}"
    );
    assert!(!f("never.json").exists());
    if let Some(v) = checker("tools/check/tracker.py", &[&map, &scen, &f("bad.csv")]) {
        assert_eq!(v["valid"], false, "{v}");
    }
    let mut pv: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(f("planviz.json")).unwrap()).unwrap();
    let first = pv["actualPaths"][0].as_str().unwrap().to_string();
    let flipped = match first.chars().next() {
        Some('U') => first.replacen('U', "D", 1),
        Some('D') => first.replacen('D', "U", 1),
        Some('L') => first.replacen('L', "R", 1),
        Some('R') => first.replacen('R', "L", 1),
        _ => format!("R{}", &first[1..]),
    };
    pv["actualPaths"][0] = flipped.into();
    std::fs::write(f("bad.json"), pv.to_string()).unwrap();
    let (code, err) = convert(&f("bad.json"), "tracker", &f("never.csv"));
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("bad.json"), "{err}");
    assert!(!f("never.csv").exists());
    if let Some(v) = checker("tools/check/planviz.py", &[&map, &f("bad.json"), &scen]) {
        assert_eq!(v["valid"], false, "{v}");
    }

    // Never overwrite an input; a tracker CSV needs its scenario.
    let before = std::fs::read(f("plan.csv")).unwrap();
    let (code, err) = convert(&f("plan.csv"), "tracker", &f("plan.csv"));
    assert_eq!(code, Some(1));
    assert!(err.contains("overwrite the input"), "{err}");
    assert_eq!(std::fs::read(f("plan.csv")).unwrap(), before);
    let (code, _, err) = mrpp(&[
        "validate",
        "-m",
        MAP,
        "--plan",
        f("plan.csv").to_str().unwrap(),
    ]);
    assert_eq!(code, Some(1));
    assert!(err.contains("give --scen"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_checkers_self_tests_pass() {
    for script in ["tools/check/tracker.py", "tools/check/planviz.py"] {
        let Ok(o) = Command::new("python3")
            .arg(script)
            .arg("--self-test")
            .current_dir(root())
            .output()
        else {
            return;
        };
        assert!(
            o.status.success(),
            "{script}: {}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        );
    }
}
