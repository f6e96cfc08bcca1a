//! Issue 27, item 2, end to end: a League of Robot Runners agents file with two robots on one
//! start cell was accepted by `info`, made H* panic, LaCAM and PIBT report "invalid plan (a bug
//! in mrpp)" and CBS/EECBS "no solution". Now every verb refuses it as the `.scen` and H* robot
//! readers refuse the same mistake: exit 1, one line naming the file, the line and the rule, and
//! nothing written.

use std::path::PathBuf;
use std::process::Command;

#[test]
fn a_lorr_start_shared_by_two_robots_is_refused_by_every_verb_and_planner() {
    let kit = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/robot-runners/lorr2023-warehouse_small");
    let dir = std::env::temp_dir().join(format!("mrpp-readers-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("agents")).unwrap();
    for sub in ["maps", "tasks"] {
        std::fs::create_dir_all(dir.join(sub)).unwrap();
        for e in std::fs::read_dir(kit.join(sub)).unwrap() {
            let e = e.unwrap();
            std::fs::copy(e.path(), dir.join(sub).join(e.file_name())).unwrap();
        }
    }
    std::fs::copy(
        kit.join("warehouse_small_10.json"),
        dir.join("warehouse_small_10.json"),
    )
    .unwrap();
    // The kit's agents with the third robot moved onto the first one's start.
    let agents = std::fs::read_to_string(kit.join("agents/warehouse_small_10.agents")).unwrap();
    let mut lines: Vec<&str> = agents.lines().collect();
    lines[3] = lines[1];
    std::fs::write(
        dir.join("agents/warehouse_small_10.agents"),
        lines.join("\n") + "\n",
    )
    .unwrap();
    let problem = dir.join("warehouse_small_10.json");
    let p = problem.to_str().unwrap();
    let run = |args: &[&str]| {
        let o = Command::new(env!("CARGO_BIN_EXE_mrpp"))
            .args(args)
            .current_dir(&dir)
            .output()
            .unwrap();
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    let says = "warehouse_small_10.agents:4: start";
    let (code, err) = run(&["info", "--lorr", p]);
    assert_eq!(code, Some(1), "info: {err}");
    assert!(
        err.contains(says) && err.contains("is also the start on line 2"),
        "{err}"
    );
    for planner in ["hstar", "lacam", "pibt", "cbs", "eecbs", "whca", "nsga3"] {
        let (code, err) = run(&[
            "solve",
            "--lorr",
            p,
            "-P",
            planner,
            "-t",
            "5",
            "-o",
            "plan.json",
        ]);
        assert_eq!(code, Some(1), "{planner}: {err}");
        assert!(err.contains(says), "{planner}: {err}");
        assert!(
            !err.contains("bug in mrpp") && !err.contains("panicked"),
            "{err}"
        );
        assert!(!dir.join("plan.json").exists(), "{planner} wrote a plan");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
