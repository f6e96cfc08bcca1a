//! End-to-end tests of the `mrpp` binary: exit codes, one-line errors naming the file, plans that
//! `mrpp validate` and the independent Python checker (`tools/check/grid.py`) both accept with the
//! same metrics, and injected conflicts that both reject.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn data(rel: &str) -> String {
    root().join("data").join(rel).to_string_lossy().into_owned()
}

/// Runs `mrpp` from a folder outside the repository (as an installed binary would be), so no
/// test leans on `data/` being the working directory's: paths passed in are absolute.
fn mrpp(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mrpp"))
        .args(args)
        .current_dir(std::env::temp_dir())
        .output()
        .expect("run mrpp")
}

fn text(o: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("mrpp-cli-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Plans `scen` on `map` with LaCAM into `plan`, then validates the plan on `check_map`.
fn solve_then_validate(map: &str, scen: &str, plan: &Path, check_map: &str) {
    let p = plan.to_str().unwrap();
    let o = mrpp(&[
        "solve",
        "--map",
        map,
        "--scen",
        scen,
        "--planner",
        "lacam",
        "--out",
        p,
    ]);
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
    let o = mrpp(&["validate", "--map", check_map, "--plan", p]);
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
}

/// Runs the independent checker; returns (valid, parsed JSON line).
fn check(map: &str, plan: &Path) -> (bool, serde_json::Value) {
    let o = Command::new("python3")
        .arg(root().join("tools/check/grid.py"))
        .arg(map)
        .arg(plan)
        .output()
        .expect("python3 is required for the independent checker");
    let line = String::from_utf8_lossy(&o.stdout)
        .lines()
        .last()
        .unwrap_or("")
        .to_string();
    let v: serde_json::Value =
        serde_json::from_str(&line).unwrap_or_else(|e| panic!("checker said `{line}`: {e}"));
    (o.status.success(), v)
}

/// `mrpp validate`'s metrics line parsed into (soc, makespan, moves).
fn validate(map: &str, plan: &Path) -> (i32, Option<(u64, u64, u64)>, String) {
    let o = mrpp(&["validate", "--map", map, "--plan", plan.to_str().unwrap()]);
    let (out, err) = text(&o);
    let value = |key: &str| -> Option<u64> {
        out.split(" | ")
            .find_map(|part| part.trim().strip_prefix(key)?.trim().parse().ok())
    };
    let metrics = out.starts_with("valid:").then(|| {
        (
            value("sum_of_costs").unwrap(),
            value("makespan").unwrap(),
            value("sum_of_moves").unwrap(),
        )
    });
    (o.status.code().unwrap(), metrics, err)
}

#[test]
fn every_planner_plan_is_valid_for_both_checkers() {
    let cases = [
        (
            "hstar-paper/scenario1/scenery.txt",
            "hstar-paper/scenario1/12coordinates.txt",
            None,
        ),
        (
            "hstar-paper/scenario3/scenery_warehouse.txt",
            "hstar-paper/scenario3/20warehouse",
            None,
        ),
        (
            "movingai/empty-8-8.map",
            "movingai/empty-8-8-random-1.scen",
            Some("10"),
        ),
        (
            "movingai/random-32-32-20.map",
            "movingai/random-32-32-20-random-1.scen",
            Some("20"),
        ),
    ];
    for (map, scen, agents) in cases {
        let (map, scen) = (data(map), data(scen));
        for planner in mrpp_grid::PLANNERS.iter().map(|e| e.name) {
            let out = tmp(&format!("{planner}.json"));
            let mut args = vec![
                "solve",
                "--map",
                &map,
                "--scen",
                &scen,
                "--planner",
                planner,
                "--out",
            ];
            let out_s = out.to_string_lossy().into_owned();
            args.push(&out_s);
            if let Some(n) = agents {
                args.extend(["--agents", n]);
            }
            let o = mrpp(&args);
            let code = o.status.code().unwrap();
            assert!(
                code == 0 || code == 3,
                "{planner} on {map}: exit {code}: {:?}",
                text(&o)
            );
            let (ok, verdict) = check(&map, &out);
            if code == 3 {
                let json: serde_json::Value =
                    serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
                assert_eq!(json["solved"], false);
                continue;
            }
            let (vcode, metrics, err) = validate(&map, &out);
            assert_eq!(vcode, 0, "{planner} on {map}: {err}");
            assert!(ok, "checker rejects {planner} on {map}: {verdict}");
            let (soc, mk, mv) = metrics.unwrap();
            assert_eq!(verdict["sum_of_costs"], soc, "{planner} on {map}");
            assert_eq!(verdict["makespan"], mk, "{planner} on {map}");
            assert_eq!(verdict["sum_of_moves"], mv, "{planner} on {map}");
        }
    }
}

#[test]
fn injected_conflicts_are_rejected_by_both_checkers() {
    let map = data("movingai/empty-8-8.map");
    let scen = data("movingai/empty-8-8-random-1.scen");
    let out = tmp("base.json");
    let o = mrpp(&[
        "solve",
        "--map",
        &map,
        "--scen",
        &scen,
        "--agents",
        "6",
        "--planner",
        "hstar",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
    let base: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();

    // Vertex conflict: keep two agents; agent 0 waits on its start (made its goal) and agent 1
    // walks onto that cell along grid edges.
    let mut vertex = base.clone();
    vertex["agents"] = serde_json::Value::Array(base["agents"].as_array().unwrap()[..2].to_vec());
    let s0 = base["agents"][0]["start"].clone();
    assert_ne!(base["agents"][0]["start"], base["agents"][1]["start"]);
    vertex["agents"][0]["path"] = serde_json::json!([s0.clone()]);
    vertex["agents"][0]["goal"] = s0.clone();
    let (sx, sy) = (s0[0].as_i64().unwrap(), s0[1].as_i64().unwrap());
    let s1 = base["agents"][1]["start"].clone();
    let (mut x, mut y) = (s1[0].as_i64().unwrap(), s1[1].as_i64().unwrap());
    let mut walk = vec![serde_json::json!([x, y])];
    while (x, y) != (sx, sy) {
        if x != sx {
            x += (sx - x).signum();
        } else {
            y += (sy - y).signum();
        }
        walk.push(serde_json::json!([x, y]));
    }
    // ... and one step beyond it (empty-8-8 is open), so its goal differs from agent 0's.
    let prev = walk[walk.len() - 2].clone();
    let beyond = [(1, 0), (-1, 0), (0, 1), (0, -1)]
        .into_iter()
        .map(|(dx, dy)| serde_json::json!([sx + dx, sy + dy]))
        .find(|c| {
            *c != prev
                && (0..8).contains(&c[0].as_i64().unwrap())
                && (0..8).contains(&c[1].as_i64().unwrap())
        })
        .unwrap();
    walk.push(beyond.clone());
    vertex["agents"][1]["path"] = serde_json::Value::Array(walk);
    vertex["agents"][1]["goal"] = beyond;
    vertex["metrics"] = serde_json::json!({"sum_of_costs": null, "makespan": null, "sum_of_moves": null, "runtime_ms": 0.0});
    let vpath = tmp("vertex.json");
    std::fs::write(&vpath, vertex.to_string()).unwrap();
    let (code, _, err) = validate(&map, &vpath);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("conflict") && err.contains("agents 0 and 1"),
        "{err}"
    );
    assert!(!check(&map, &vpath).0);

    // Swap conflict: two agents on adjacent cells exchange them.
    let swap = serde_json::json!({
        "map_file": "empty-8-8.map", "planner": "hand", "seed": 0, "solved": true, "goal_semantics": "stay",
        "metrics": {"sum_of_costs": null, "makespan": null, "sum_of_moves": null, "runtime_ms": 0.0},
        "agents": [
            {"start": [2, 2], "goal": [3, 2], "path": [[2, 2], [3, 2]]},
            {"start": [3, 2], "goal": [2, 2], "path": [[3, 2], [2, 2]]}
        ]
    });
    let spath = tmp("swap.json");
    std::fs::write(&spath, swap.to_string()).unwrap();
    let (code, _, err) = validate(&map, &spath);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("swap conflict"), "{err}");
    assert!(!check(&map, &spath).0);
}

#[test]
fn bad_inputs_exit_1_with_one_line_naming_the_file() {
    let dir = tmp("bad");
    std::fs::create_dir_all(&dir).unwrap();
    let truncated = dir.join("truncated.map");
    std::fs::write(
        &truncated,
        "type octile\nheight 8\nwidth 8\nmap\n........\n........\n",
    )
    .unwrap();
    let off_map = dir.join("off.scen");
    std::fs::write(
        &off_map,
        "version 1\n0\tempty-8-8.map\t8\t8\t1\t1\t9\t3\t5\n",
    )
    .unwrap();
    let wall_robots = dir.join("wall.txt");
    std::fs::write(&wall_robots, "1,1;3,3\n0,0;5,5\n").unwrap();
    let dup = dir.join("dup.txt");
    std::fs::write(&dup, "1,1;3,3\n1,1;5,5\n").unwrap();
    let empty88 = data("movingai/empty-8-8.map");
    let scen88 = data("movingai/empty-8-8-random-1.scen");
    let sc1 = data("hstar-paper/scenario1/scenery.txt");
    let missing = dir.join("missing.map");
    let cases: Vec<(Vec<String>, String)> = vec![
        (
            vec![truncated.display().to_string(), scen88.clone()],
            "truncated.map".into(),
        ),
        (
            vec![empty88.clone(), off_map.display().to_string()],
            "off.scen:2".into(),
        ),
        (
            vec![sc1.clone(), wall_robots.display().to_string()],
            "wall.txt:2".into(),
        ),
        (
            vec![sc1.clone(), dup.display().to_string()],
            "dup.txt:2".into(),
        ),
        (
            vec![missing.display().to_string(), scen88.clone()],
            "missing.map".into(),
        ),
    ];
    for (files, needle) in cases {
        let o = mrpp(&[
            "solve",
            "--map",
            &files[0],
            "--scen",
            &files[1],
            "--planner",
            "hstar",
        ]);
        let (_, err) = text(&o);
        assert_eq!(o.status.code(), Some(1), "{needle}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{needle}: {err}");
        assert!(err.contains(&needle), "expected `{needle}` in `{err}`");
        assert!(!err.contains("panicked"), "{err}");
    }
    // Absurd parameters and unknown planners are usage errors (exit 1), not panics.
    for args in [
        vec!["--planner", "hstar", "--time-limit", "-1"],
        vec!["--planner", "nope"],
        vec!["--planner", "hstar", "--agents", "0"],
        vec!["--planner", "hstar", "--agents", "100000"],
    ] {
        let mut full = vec!["solve", "--map", &empty88, "--scen", &scen88];
        full.extend(args.iter());
        let o = mrpp(&full);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {:?}", text(&o));
    }
}

#[test]
fn unsolved_exits_3_and_lacam_and_svg_outputs_are_written() {
    let map = data("movingai/empty-8-8.map");
    let scen = data("movingai/empty-8-8-random-1.scen");
    let out = tmp("plan.lacam");
    let o = mrpp(&[
        "solve",
        "--map",
        &map,
        "--scen",
        &scen,
        "--agents",
        "8",
        "--planner",
        "hstar",
        "--format",
        "lacam",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
    let lacam = std::fs::read_to_string(&out).unwrap();
    assert!(lacam.starts_with("agents=8\n"), "{lacam}");
    assert!(lacam.contains("solution=\n0:("), "{lacam}");
    assert_eq!(validate(&map, &out).0, 0);
    let svg = tmp("plan.svg");
    let o = mrpp(&[
        "render",
        "--map",
        &map,
        "--plan",
        out.to_str().unwrap(),
        "--out",
        svg.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
    assert!(std::fs::read_to_string(&svg).unwrap().contains("<svg"));

    // The paper-only H* gives up on SC3 with 15 robots (the greedy stage cycles with two robots
    // short of their goals): exit 3, and the JSON says so.
    let jout = tmp("unsolved.json");
    let sc2 = data("hstar-paper/scenario3/scenery_warehouse.txt");
    let robots = data("hstar-paper/scenario3/15warehouse");
    let o = mrpp(&[
        "solve",
        "--map",
        &sc2,
        "--scen",
        &robots,
        "--planner",
        "hstar",
        "--variant",
        "paper",
        "--out",
        jout.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(3), "{:?}", text(&o));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&jout).unwrap()).unwrap();
    assert_eq!(json["solved"], false);
    assert_eq!(validate(&sc2, &jout).0, 1);
}

#[test]
fn info_reports_lower_bounds() {
    // Scenario 3 with 15 robots: the robots' shortest distances add up to 522 (and the longest is
    // 62), so no valid plan has a smaller sum of costs; the H* paper reports 509 for this row.
    let o = mrpp(&[
        "info",
        "--map",
        &data("hstar-paper/scenario3/scenery_warehouse.txt"),
        "--scen",
        &data("hstar-paper/scenario3/15warehouse"),
    ]);
    let (out, err) = text(&o);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(
        out.contains("sum_of_costs >= 522 | makespan >= 62"),
        "{out}"
    );
}

/// Issue 32: the paper's steps fail SC1 with 9 robots under the first-neighbour tie-break, and
/// one seeded random tie-break (seed 2) reproduces the paper's H* cell exactly, Max 38 and Sum
/// 196 (docs/reproduction/hstar.md, "Ties").
#[test]
fn a_random_tie_break_of_the_papers_steps_reproduces_its_sc1_9_cell() {
    let out = tmp("ties");
    std::fs::create_dir_all(&out).unwrap();
    let plan = out.join("plan.json");
    let solve = |tie: &str, seed: &str| {
        mrpp(&[
            "-q",
            "solve",
            "--map",
            &data("hstar-paper/scenario1/scenery.txt"),
            "--scen",
            &data("hstar-paper/scenario1/9coordinates.txt"),
            "--planner",
            "hstar",
            "-p",
            "variant=paper",
            "-p",
            &format!("tie_break={tie}"),
            "-s",
            seed,
            "--out",
            plan.to_str().unwrap(),
        ])
    };
    assert_eq!(solve("first", "0").status.code(), Some(3));
    let o = solve("random", "2");
    assert_eq!(o.status.code(), Some(0), "{}", text(&o).1);
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&plan).unwrap()).unwrap();
    assert_eq!(v["metrics"]["makespan"], 38);
    assert_eq!(v["metrics"]["sum_of_costs"], 196);
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn hstar_table2_experiment_writes_its_files() {
    let out = tmp("table2");
    let o = mrpp(&[
        "experiment",
        "hstar-table2",
        "--runs",
        "1",
        "--planners",
        "hstar,whca,hstar-paper",
        "--out",
        out.to_str().unwrap(),
        "--save-plans",
    ]);
    let (stdout, err) = text(&o);
    assert_eq!(o.status.code(), Some(0), "{stdout}\n{err}");
    assert!(
        stdout.contains("seed 0") && stdout.contains(env!("CARGO_PKG_VERSION")),
        "{stdout}"
    );
    assert!(common::every_svg_rasterises(&out) >= 1);
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines[0],
        "scenario,robots,planner,run,seed,solved,max,sum,runtime_ms"
    );
    assert_eq!(lines.len(), 1 + 19 * 3);
    // H* solves every row; each of its saved plans passes both checkers.
    let hstar: Vec<&str> = lines
        .iter()
        .copied()
        .filter(|l| l.contains(",hstar,"))
        .collect();
    assert_eq!(hstar.len(), 19);
    assert!(hstar.iter().all(|l| l.contains(",true,")), "{csv}");
    // H* as published (the paper's steps only) reproduces the paper's Sum 120 on SC1 with 6
    // robots and says why it stops where its steps leave conflicts.
    let paper: Vec<&str> = lines
        .iter()
        .copied()
        .filter(|l| l.contains(",hstar-paper,"))
        .collect();
    assert_eq!(paper.len(), 19);
    assert!(
        paper.iter().any(|l| l.starts_with("1,6,hstar-paper,0,")
            && l.contains(",true,")
            && l.contains(",120,")),
        "{csv}"
    );
    let table = std::fs::read_to_string(out.join("table2.md")).unwrap();
    assert!(
        table.contains("| H* paper steps ours | H* paper |"),
        "{table}"
    );
    assert!(table.contains("— paper steps leave conflicts"), "{table}");
    assert_eq!(
        table.lines().filter(|l| l.starts_with("| 1 |")).count(),
        20,
        "{table}"
    );
    assert!(
        std::fs::read_to_string(out.join("fig5.svg"))
            .unwrap()
            .starts_with("<svg")
    );
    for (map, file) in [
        ("hstar-paper/scenario1/scenery.txt", "1-15-hstar-0.json"),
        (
            "hstar-paper/scenario2/scenery_4rooms_B.txt",
            "2-24-hstar-0.json",
        ),
        (
            "hstar-paper/scenario3/scenery_warehouse.txt",
            "3-30-hstar-0.json",
        ),
    ] {
        let plan = out.join("plans").join(file);
        assert_eq!(validate(&data(map), &plan).0, 0, "{file}");
        assert!(check(&data(map), &plan).0, "{file}");
    }
    // Unknown planners and absurd run counts are usage errors.
    let o = mrpp(&[
        "experiment",
        "hstar-table2",
        "--runs",
        "0",
        "--data",
        &data("hstar-paper"),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let o = mrpp(&[
        "experiment",
        "hstar-table2",
        "--planners",
        "nope",
        "--data",
        &data("hstar-paper"),
    ]);
    assert_eq!(o.status.code(), Some(1));
}

#[test]
fn view_writes_one_self_contained_page_with_the_plan_and_its_verdict() {
    let dir = std::env::temp_dir().join(format!("mrpp-view-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let plan = dir.join("plan.json");
    let map = "data/movingai/random-32-32-20.map";
    let scen = "data/movingai/random-32-32-20-random-1.scen";
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_mrpp"))
            .args(args)
            .current_dir(env!("CARGO_MANIFEST_DIR").to_string() + "/../..")
            .output()
            .unwrap()
    };
    let p = plan.to_str().unwrap();
    let o = run(&[
        "solve",
        "--map",
        map,
        "--scen",
        scen,
        "--agents",
        "12",
        "--planner",
        "lacam",
        "--out",
        p,
    ]);
    assert!(o.status.success(), "{o:?}");
    let o = run(&["view", "--map", map, "--plan", p]);
    assert!(o.status.success(), "{o:?}");
    let html = std::fs::read_to_string(dir.join("plan.html")).unwrap();
    assert!(html.contains("\"family\":\"grid\"") && html.contains("\"valid\":true"));
    assert!(
        !html.contains("__MRPP_SCENE__") && !html.contains("http://") && !html.contains("https://")
    );
    // An invalid plan (agent 1 jumps onto agent 0): the page carries the validator's verdict.
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&plan).unwrap()).unwrap();
    let first = v["agents"][0]["path"][0].clone();
    v["agents"][1]["path"] = serde_json::json!([v["agents"][1]["start"].clone(), first]);
    v["metrics"] = serde_json::Value::Null;
    let bad = dir.join("bad.json");
    std::fs::write(&bad, v.to_string()).unwrap();
    let out = dir.join("bad.html");
    let o = run(&[
        "view",
        "--map",
        map,
        "--plan",
        bad.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{o:?}");
    let html = std::fs::read_to_string(&out).unwrap();
    assert!(html.contains("\"valid\":false"), "no verdict");
    // --out equal to the plan is refused and the plan is left alone.
    let before = std::fs::read_to_string(&plan).unwrap();
    let o = run(&["view", "--map", map, "--plan", p, "--out", p]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(std::fs::read_to_string(&plan).unwrap(), before);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn render_writes_png_and_animated_gif_by_extension_and_refuses_others() {
    let dir = std::env::temp_dir().join(format!("mrpp-render-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_mrpp"))
            .args(args)
            .current_dir(env!("CARGO_MANIFEST_DIR").to_string() + "/../..")
            .output()
            .unwrap()
    };
    let map = "data/movingai/random-32-32-20.map";
    let plan = dir.join("plan.json");
    let p = plan.to_str().unwrap();
    let o = run(&[
        "solve",
        "--map",
        map,
        "--scen",
        "data/movingai/random-32-32-20-random-1.scen",
        "--agents",
        "10",
        "--planner",
        "lacam",
        "--out",
        p,
    ]);
    assert!(o.status.success(), "{o:?}");
    let render = |out: &std::path::Path, extra: &[&str]| {
        let mut args = vec![
            "render",
            "--map",
            map,
            "--plan",
            p,
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        run(&args)
    };
    let png = dir.join("plan.png");
    assert!(render(&png, &[]).status.success());
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let (w, h) = (
        u32::from_be_bytes(bytes[16..20].try_into().unwrap()),
        u32::from_be_bytes(bytes[20..24].try_into().unwrap()),
    );
    assert!(w > 100 && h > 100, "{w}x{h}");
    let gif = dir.join("plan.gif");
    assert!(render(&gif, &["--gif"]).status.success());
    let bytes = std::fs::read(&gif).unwrap();
    assert_eq!(&bytes[..6], b"GIF89a");
    // One graphic control block per frame: at least the plan's steps + 1 (capped at 300).
    let frames = bytes
        .windows(3)
        .filter(|w| *w == [0x21, 0xf9, 0x04])
        .count();
    let steps = serde_json::from_str::<serde_json::Value>(&std::fs::read_to_string(&plan).unwrap())
        .unwrap()["metrics"]["makespan"]
        .as_u64()
        .unwrap() as usize;
    assert!(
        frames >= (steps + 1).min(300),
        "{frames} frames for {steps} steps"
    );
    for bad in ["plan.jpg", "plan"] {
        let out = dir.join(bad);
        let o = render(&out, &[]);
        assert_eq!(o.status.code(), Some(1), "{bad}");
        assert!(String::from_utf8_lossy(&o.stderr).contains("unknown picture format"));
        assert!(!out.exists());
    }
    let o = render(&png, &["--gif"]);
    assert_eq!(o.status.code(), Some(1));
    // Trees: the static picture comes from the viewer's scene (tidy layout, routes).
    let tree_plan = dir.join("tree.json");
    let tp = tree_plan.to_str().unwrap();
    let inst = "data/trees/example.json";
    assert!(
        run(&[
            "trees",
            "solve",
            "--instance",
            inst,
            "--planner",
            "psw",
            "--out",
            tp
        ])
        .status
        .success()
    );
    let svg = dir.join("tree.svg");
    assert!(
        run(&[
            "render",
            "--instance",
            inst,
            "--plan",
            tp,
            "--out",
            svg.to_str().unwrap()
        ])
        .status
        .success()
    );
    let text = std::fs::read_to_string(&svg).unwrap();
    let robots =
        serde_json::from_str::<serde_json::Value>(&std::fs::read_to_string(&tree_plan).unwrap())
            .unwrap()["agents"]
            .as_array()
            .unwrap()
            .len();
    assert_eq!(text.matches("<polyline").count(), robots);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn gen_map_then_scen_then_lacam_gives_a_valid_plan_and_bad_maps_are_refused() {
    let map = tmp("gen-20x10.map");
    let scen = tmp("gen-20x10.scen");
    let plan = tmp("gen-20x10.json");
    let m = map.to_str().unwrap();
    let o = mrpp(&[
        "gen",
        "map",
        "--width",
        "20",
        "--height",
        "10",
        "--obstacles",
        "0.2",
        "--seed",
        "4",
        "--out",
        m,
    ]);
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
    let first = std::fs::read_to_string(&map).unwrap();
    assert!(first.starts_with("type octile\nheight 10\nwidth 20\nmap\n"));
    let o = mrpp(&[
        "gen",
        "scen",
        "--map",
        m,
        "--agents",
        "30",
        "--seed",
        "1",
        "--out",
        scen.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
    solve_then_validate(m, scen.to_str().unwrap(), &plan, m);
    // Absurd parameters: one line, exit 1, the existing file untouched.
    for (w, h, p) in [
        ("0", "10", "0.1"),
        ("20", "10", "0.95"),
        ("20", "10", "NaN"),
    ] {
        let o = mrpp(&[
            "gen",
            "map",
            "--width",
            w,
            "--height",
            h,
            "--obstacles",
            p,
            "--out",
            m,
        ]);
        let (_, err) = text(&o);
        assert_eq!(o.status.code(), Some(1), "{err}");
        assert!(
            err.contains("gen map:") && err.lines().count() == 1,
            "{err}"
        );
        assert_eq!(std::fs::read_to_string(&map).unwrap(), first);
    }
}

#[test]
fn lacam_text_carries_lacam3_keys_with_the_bounds_of_info() {
    let (map, scen) = (
        data("movingai/random-32-32-20.map"),
        data("movingai/random-32-32-20-random-1.scen"),
    );
    let out = tmp("lacam3-keys.txt");
    let o = mrpp(&[
        "solve",
        "--map",
        &map,
        "--scen",
        &scen,
        "--agents",
        "60",
        "--planner",
        "lacam",
        "--seed",
        "7",
        "--format",
        "lacam",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
    let body = std::fs::read_to_string(&out).unwrap();
    let keys: Vec<&str> = body
        .lines()
        .take_while(|l| !l.starts_with("starts="))
        .map(|l| l.split('=').next().unwrap())
        .collect();
    assert_eq!(
        keys,
        [
            "agents",
            "map_file",
            "solver",
            "solved",
            "soc",
            "soc_lb",
            "makespan",
            "makespan_lb",
            "sum_of_loss",
            "sum_of_loss_lb",
            "comp_time",
            "seed"
        ]
    );
    let value = |k: &str| -> u64 {
        body.lines()
            .find_map(|l| l.strip_prefix(&format!("{k}=")))
            .unwrap()
            .parse()
            .unwrap()
    };
    let o = mrpp(&["info", "--map", &map, "--scen", &scen, "--agents", "60"]);
    let (info, _) = text(&o);
    let lb = format!(
        "sum_of_costs >= {} | makespan >= {}",
        value("soc_lb"),
        value("makespan_lb")
    );
    assert!(info.contains(&lb), "{info} lacks {lb}");
    assert_eq!(value("sum_of_loss_lb"), value("soc_lb"));
    assert_eq!(value("seed"), 7);
    // Sum of loss recounted from the steps: every step but a stay on the goal.
    let cells = |l: &str| -> Vec<String> {
        l.split_once(':')
            .unwrap()
            .1
            .split("),")
            .filter(|c| !c.trim().is_empty())
            .map(|c| c.trim().to_string())
            .collect()
    };
    let steps: Vec<Vec<String>> = body
        .lines()
        .skip_while(|l| *l != "solution=")
        .skip(1)
        .map(cells)
        .collect();
    let goals = steps.last().unwrap();
    let loss: usize = steps
        .windows(2)
        .map(|w| {
            (0..60)
                .filter(|&i| !(w[0][i] == goals[i] && w[1][i] == goals[i]))
                .count()
        })
        .sum();
    assert_eq!(value("sum_of_loss"), loss as u64);
    assert!(value("soc_lb") <= value("sum_of_loss") && value("sum_of_loss") <= value("soc"));
}

#[test]
fn convert_writes_every_hstar_map_as_movingai_that_reads_back_the_same() {
    let pairs = [
        ("scenario1/scenery.txt", "scenario1/15coordinates.txt"),
        (
            "scenario2/scenery_4rooms.txt",
            "scenario2/6robots-per-room.txt",
        ),
        (
            "scenario2/scenery_4rooms_B.txt",
            "scenario2/3robots-per-room.txt",
        ),
        ("scenario3/scenery_warehouse.txt", "scenario3/30warehouse"),
    ];
    // `mrpp info` without its first field (the map's name).
    let info = |map: &str, scen: &str| {
        let o = mrpp(&["info", "--map", map, "--scen", scen]);
        assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
        let (out, _) = text(&o);
        out.split_once(' ')
            .unwrap()
            .1
            .split_once(' ')
            .unwrap()
            .1
            .to_string()
    };
    for (k, (map, agents)) in pairs.iter().enumerate() {
        let (map, agents) = (
            data(&format!("hstar-paper/{map}")),
            data(&format!("hstar-paper/{agents}")),
        );
        let (out_map, out_scen) = (
            tmp(&format!("conv-{k}.map")),
            tmp(&format!("conv-{k}.scen")),
        );
        let (om, os) = (out_map.to_str().unwrap(), out_scen.to_str().unwrap());
        let o = mrpp(&[
            "convert",
            "--map",
            &map,
            "--scen",
            &agents,
            "--out-map",
            om,
            "--out-scen",
            os,
        ]);
        assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
        // Read back by mrpp: the same cells, agents and bounds.
        assert_eq!(info(om, os), info(&map, &agents), "{map}");
        // Read by the independent MovingAI checker.
        let o = Command::new("python3")
            .arg(root().join("tools/check/movingai.py"))
            .args([om, os])
            .output()
            .unwrap();
        let (out, err) = text(&o);
        assert_eq!(o.status.code(), Some(0), "{out}{err}");
        assert!(out.contains("\"valid\": true"), "{out}");
        // A plan made on the paper's file is valid on the converted one.
        let plan = tmp(&format!("conv-{k}.json"));
        solve_then_validate(&map, &agents, &plan, om);
    }
    // Never over an input.
    let map = data("hstar-paper/scenario1/scenery.txt");
    let before = std::fs::read(&map).unwrap();
    let o = mrpp(&["convert", "--map", &map, "--out-map", &map]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o).1.contains("would overwrite the input"),
        "{:?}",
        text(&o)
    );
    assert_eq!(std::fs::read(&map).unwrap(), before);
}

#[test]
fn the_movingai_checker_refuses_broken_files() {
    let check = |map: &str, scen: Option<&str>| {
        let m = tmp("chk.map");
        std::fs::write(&m, map).unwrap();
        let mut args = vec![m.to_str().unwrap().to_string()];
        if let Some(s) = scen {
            let p = tmp("chk.scen");
            std::fs::write(&p, s).unwrap();
            args.push(p.to_str().unwrap().to_string());
        }
        let o = Command::new("python3")
            .arg(root().join("tools/check/movingai.py"))
            .args(&args)
            .output()
            .unwrap();
        (o.status.code(), text(&o).0)
    };
    let good = "type octile\nheight 2\nwidth 3\nmap\n..@\n.T.\n";
    assert_eq!(check(good, None).0, Some(0));
    let scen = |line: &str| format!("version 1\n{line}\n");
    assert_eq!(
        check(good, Some(&scen("0\tm.map\t3\t2\t0\t0\t2\t1\t3"))).0,
        Some(0)
    );
    for (map, s, why) in [
        (
            "type octile\nheight 2\nwidth 3\nmap\n..@\n.T\n",
            None,
            "row of 2",
        ),
        (
            "type octile\nheight 2\nwidth 3\nmap\n..@\n.X.\n",
            None,
            "terrain",
        ),
        ("type octile\nwidth 3\nmap\n..@\n...\n", None, "height"),
        (good, Some(scen("0\tm.map\t3\t2\t1\t1\t2\t1\t3")), "on `T`"),
        (
            good,
            Some(scen("0\tm.map\t3\t3\t0\t0\t2\t1\t3")),
            "map size",
        ),
        (good, Some(scen("0 m.map 3 2 0 0 2 1 3")), "fields"),
        (
            good,
            Some("0\tm.map\t3\t2\t0\t0\t2\t1\t3\n".into()),
            "version",
        ),
    ] {
        let (code, out) = check(map, s.as_deref());
        assert_eq!(code, Some(1), "{why}: {out}");
        assert!(out.contains(why), "{why}: {out}");
    }
}

#[test]
fn completions_cover_every_subcommand_and_bash_parses_its_script() {
    for shell in ["bash", "zsh", "fish"] {
        let o = mrpp(&["completions", shell]);
        let (out, err) = text(&o);
        assert_eq!(o.status.code(), Some(0), "{shell}: {err}");
        for sub in ["solve", "validate", "convert", "bench", "view", "render"] {
            assert!(out.contains(sub), "{shell} script lacks {sub}");
        }
    }
    let script = tmp("mrpp.bash");
    std::fs::write(&script, mrpp(&["completions", "bash"]).stdout).unwrap();
    let o = Command::new("bash")
        .arg("-n")
        .arg(&script)
        .output()
        .unwrap();
    assert!(o.status.success(), "{:?}", text(&o));
    assert_ne!(mrpp(&["completions", "tcsh"]).status.code(), Some(0));
}

/// Both League of Robot Runners examples (2023 and 2026 start-kit layouts) load, solve with a
/// valid plan, and the independent checker, reading the problem JSON itself, agrees on starts,
/// goals and metrics; a plan is refused against the other problem, and `info`/`render` take
/// `--lorr` too.
#[test]
fn robot_runners_problems_solve_with_plans_both_checkers_accept() {
    let problems = [
        data("robot-runners/lorr2023-warehouse_small/warehouse_small_10.json"),
        data("robot-runners/lorr2026-maze/maze-example_40.json"),
    ];
    for (k, problem) in problems.iter().enumerate() {
        let plan = tmp(&format!("lorr-{k}.json"));
        let p = plan.to_str().unwrap();
        let o = mrpp(&["solve", "--lorr", problem, "--planner", "lacam", "--out", p]);
        let (out, err) = text(&o);
        assert_eq!(o.status.code(), Some(0), "{out}{err}");
        assert!(out.contains("one-shot: goal = first task"), "{out}");
        if k == 1 {
            assert!(out.contains("1 task(s) passed over"), "{out}");
        }
        let o = mrpp(&["validate", "--lorr", problem, "--plan", p]);
        let (out, err) = text(&o);
        assert_eq!(o.status.code(), Some(0), "{out}{err}");
        let agents = [10, 40][k];
        assert!(out.starts_with(&format!("valid: {agents} agents")), "{out}");
        let (ok, v) = check(problem, &plan);
        assert!(ok, "{v}");
        let soc: u64 = out
            .split("sum_of_costs ")
            .nth(1)
            .and_then(|s| s.split_whitespace().next())
            .and_then(|s| s.parse().ok())
            .unwrap();
        assert_eq!(v["sum_of_costs"].as_u64(), Some(soc));
        let other = &problems[1 - k];
        let o = mrpp(&["validate", "--lorr", other, "--plan", p]);
        assert_eq!(o.status.code(), Some(1), "{:?}", text(&o));
        let (ok, _) = check(other, &plan);
        assert!(!ok, "the checker must refuse a plan for another problem");
    }
    let o = mrpp(&["info", "--lorr", &problems[0]]);
    let (out, err) = text(&o);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(out.contains("map warehouse_small.map 57x33"), "{out}");
    let o = mrpp(&[
        "solve",
        "--lorr",
        &problems[0],
        "--map",
        &problems[0],
        "--planner",
        "lacam",
    ]);
    let (_, err) = text(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("'--lorr <LORR>' cannot be used with '--map <MAP>'"),
        "{err}"
    );
}

/// `-q` prints nothing on success (exit code and files only; errors still go to stderr), `-v`
/// adds the resolved parameters and the planner's notes; short flags work end to end.
#[test]
fn quiet_and_verbose_levels() {
    let plan = tmp("quiet.json");
    let (m, i) = (
        data("movingai/random-32-32-20.map"),
        data("movingai/random-32-32-20-random-1.scen"),
    );
    let args = |level: &str| -> Vec<String> {
        let mut v: Vec<String> = ["solve", "-m", &m, "-i", &i, "-N", "20", "-P", "lacam"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        v.extend(["-o".into(), plan.to_string_lossy().into_owned()]);
        if !level.is_empty() {
            v.push(level.into());
        }
        v
    };
    let run = |level: &str| {
        let a = args(level);
        let o = mrpp(&a.iter().map(String::as_str).collect::<Vec<_>>());
        assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
        text(&o)
    };
    let (out, err) = run("-q");
    assert_eq!((out.as_str(), err.as_str()), ("", ""));
    assert!(plan.exists());
    let (normal, _) = run("");
    assert!(normal.contains("solved: sum_of_costs") && !normal.contains("parameters:"));
    let (verbose, _) = run("-v");
    assert!(verbose.contains("parameters: anytime=false"), "{verbose}");
    assert!(verbose.contains("lacam notes: {"), "{verbose}");
    let o = mrpp(&["validate", "-q", "-m", &m, "--plan", plan.to_str().unwrap()]);
    assert_eq!((o.status.code(), text(&o).0.as_str()), (Some(0), ""));
    let o = mrpp(&["validate", "-q", "-m", &m, "--plan", &m]);
    let (out, err) = text(&o);
    assert_eq!((o.status.code(), out.as_str()), (Some(1), ""));
    assert!(err.starts_with("mrpp: error: "), "{err}");
}

/// `mrpp validate` holds a LaCAM result's claims (soc, makespan, sum_of_loss) against its paths,
/// as it does a JSON plan's metrics (issue 14, kind 3).
#[test]
fn lacam_claims_that_disagree_with_the_paths_are_refused() {
    let (m, i) = (
        data("movingai/random-32-32-20.map"),
        data("movingai/random-32-32-20-random-1.scen"),
    );
    let plan = tmp("claims.txt");
    let p = plan.to_str().unwrap();
    let o = mrpp(&[
        "solve", "-m", &m, "-i", &i, "-N", "30", "-P", "lacam", "--format", "lacam", "-o", p,
    ]);
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
    let good = std::fs::read_to_string(&plan).unwrap();
    let o = mrpp(&["validate", "-m", &m, "--plan", p]);
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
    for key in ["soc", "makespan", "sum_of_loss"] {
        let line = good
            .lines()
            .find(|l| l.starts_with(&format!("{key}=")))
            .unwrap();
        let value: u64 = line[key.len() + 1..].parse().unwrap();
        std::fs::write(&plan, good.replace(line, &format!("{key}={}", value + 1))).unwrap();
        let o = mrpp(&["validate", "-m", &m, "--plan", p]);
        let (_, err) = text(&o);
        assert_eq!(o.status.code(), Some(1), "{key}: {err}");
        assert!(
            err.contains(&format!(
                "the result claims {key}={} but its paths give {value}",
                value + 1
            )),
            "{err}"
        );
    }
}

/// Issue 14, kind 5: outputs are checked before any work and written without harming what they
/// name. LaCAM* with a 30 s limit would plan for 30 s, so a refusal well under that shows the
/// check came first.
#[test]
fn outputs_are_checked_before_planning_and_never_harm_inputs_or_devices() {
    let (m, i) = (
        data("movingai/random-32-32-20.map"),
        data("movingai/random-32-32-20-random-1.scen"),
    );
    let map = tmp("safety.map");
    std::fs::copy(&m, &map).unwrap();
    let map_s = map.to_str().unwrap();
    let long = |out: &str, extra: &[&str]| {
        let mut a = vec!["solve", "-m", map_s, "-i", &i, "-N", "200", "-P", "lacam"];
        a.extend(["-p", "anytime=true", "-t", "30", "-o", out]);
        a.extend(extra);
        let started = std::time::Instant::now();
        let o = mrpp(&a);
        (o.status.code(), text(&o).1, started.elapsed().as_secs_f64())
    };
    // The map itself, by its own name or through a symbolic link: refused, the map untouched.
    let link = tmp("safety-link.json");
    let _ = std::fs::remove_file(&link);
    std::os::unix::fs::symlink(&map, &link).unwrap();
    for out in [map_s, link.to_str().unwrap()] {
        let (code, err, secs) = long(out, &["--format", "json"]);
        assert_eq!(code, Some(1), "{err}");
        assert!(err.contains("would overwrite the input"), "{err}");
        assert!(secs < 10.0, "refused after {secs} s: planning ran first");
    }
    assert_eq!(std::fs::read(&map).unwrap(), std::fs::read(&m).unwrap());
    // A folder that does not exist, and a file under /proc: refused at once.
    for (out, says) in [
        ("/nonexistent-mrpp/plan.json", "no folder /nonexistent-mrpp"),
        ("/proc/version", "no file can be made in /proc"),
    ] {
        let (code, err, secs) = long(out, &["--format", "json"]);
        assert_eq!(code, Some(1), "{err}");
        assert!(err.contains(says), "{err}");
        assert!(secs < 10.0, "refused after {secs} s");
    }
    // Unknown extensions are refused; .txt is LaCAM text.
    let (code, err, _) = long("plan.out", &[]);
    assert_eq!(code, Some(1));
    assert!(
        err.contains("cannot tell the plan format from `.out`"),
        "{err}"
    );
    // /dev/null stays a character device; `-` writes the plan alone on stdout.
    let o = mrpp(&[
        "solve",
        "-m",
        &m,
        "-i",
        &i,
        "-N",
        "5",
        "-P",
        "lacam",
        "-o",
        "/dev/null",
    ]);
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
    use std::os::unix::fs::FileTypeExt as _;
    assert!(
        std::fs::metadata("/dev/null")
            .unwrap()
            .file_type()
            .is_char_device()
    );
    let o = mrpp(&[
        "solve", "-m", &m, "-i", &i, "-N", "5", "-P", "lacam", "-o", "-",
    ]);
    let (out, _) = text(&o);
    let env: serde_json::Value = serde_json::from_str(&out).expect("stdout is the plan alone");
    assert_eq!(env["format"], "mrpp-plan/1");
    // `/dev/stdout` redirected by the caller to a file: written in place (replacing the file
    // would lose the output), the plan alone.
    let redirected = tmp("redirected.json");
    let o = Command::new(env!("CARGO_BIN_EXE_mrpp"))
        .args([
            "solve",
            "-m",
            &m,
            "-i",
            &i,
            "-N",
            "5",
            "-P",
            "lacam",
            "-o",
            "/dev/stdout",
        ])
        .stdout(std::fs::File::create(&redirected).unwrap())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
    let env: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&redirected).unwrap()).unwrap();
    assert_eq!(env["agents"].as_array().map(Vec::len), Some(5));
    let o = mrpp(&[
        "solve", "-m", &m, "-i", &i, "-N", "5", "-P", "lacam", "--format", "lacam",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o).1.contains("--format lacam writes a file"),
        "{:?}",
        text(&o)
    );
    // A symbolic link to a plan file is followed: the link stays a link.
    let target = tmp("safety-target.txt");
    std::fs::write(&target, "old").unwrap();
    let link = tmp("safety-plan-link.txt");
    let _ = std::fs::remove_file(&link);
    std::os::unix::fs::symlink(&target, &link).unwrap();
    let o = mrpp(&[
        "solve",
        "-m",
        &m,
        "-i",
        &i,
        "-N",
        "5",
        "-P",
        "lacam",
        "-o",
        link.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert!(
        std::fs::read_to_string(&target)
            .unwrap()
            .starts_with("agents=5")
    );
}

/// Issue 14, kind 6: every bad number names its option and the rule, a byte-order mark is
/// tolerated, a map of neither format says what was tried, and a scenario shorter than the plan
/// says so.
#[test]
fn messages_name_the_option_the_rule_and_the_formats_tried() {
    let (m, i) = (
        data("movingai/random-32-32-20.map"),
        data("movingai/random-32-32-20-random-1.scen"),
    );
    let err_of = |args: &[&str]| {
        let o = mrpp(args);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {:?}", text(&o));
        text(&o).1
    };
    let solve = |extra: &[&str]| {
        let mut a = vec!["solve", "-m", m.as_str(), "-i", i.as_str(), "-P", "lacam"];
        a.extend(extra);
        err_of(&a)
    };
    let e = solve(&["--agents", "-5"]);
    assert!(
        e.contains("'--agents <AGENTS>': must be a whole number from 1, got -5"),
        "{e}"
    );
    let e = solve(&["--seed", "-1"]);
    assert!(
        e.contains("'--seed <SEED>': must be a whole number from 0 to 2^64 - 1"),
        "{e}"
    );
    for t in ["-1", "0", "1e30", "nan"] {
        let e = solve(&["--time-limit", t]);
        assert!(
            e.contains("--time-limit must be more than 0 and at most 1e7 seconds"),
            "{t}: {e}"
        );
    }
    let e = err_of(&["experiment", "hbmo", "-t", "-2"]);
    assert!(e.contains("--time-limit must be more than 0"), "{e}");
    // A BOM before a MovingAI header reads like the file without it.
    let bom = tmp("bom.map");
    let mut bytes = vec![0xef, 0xbb, 0xbf];
    bytes.extend(std::fs::read(&m).unwrap());
    std::fs::write(&bom, bytes).unwrap();
    let o = mrpp(&["info", "-m", bom.to_str().unwrap(), "-i", &i, "-N", "5"]);
    assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
    // Neither format: both named.
    let bad = tmp("neither.map");
    std::fs::write(&bad, "hello\n").unwrap();
    let e = err_of(&["info", "-m", bad.to_str().unwrap(), "-i", &i]);
    assert!(
        e.contains("neither.map:1: not a MovingAI map") && e.contains("and not an H* paper map"),
        "{e}"
    );
    // A plan of 30 agents against a 10-agent scenario.
    let plan = tmp("thirty.json");
    let o = mrpp(&[
        "solve",
        "-m",
        &m,
        "-i",
        &i,
        "-N",
        "30",
        "-P",
        "lacam",
        "-o",
        plan.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0));
    let short = tmp("ten.scen");
    let scen_text = std::fs::read_to_string(&i).unwrap();
    let ten: Vec<&str> = scen_text.lines().take(11).collect();
    std::fs::write(&short, ten.join("\n")).unwrap();
    let e = err_of(&[
        "validate",
        "-m",
        &m,
        "-i",
        short.to_str().unwrap(),
        "--plan",
        plan.to_str().unwrap(),
    ]);
    assert!(
        e.contains("the plan has 30 agents but") && e.contains("ten.scen has only 10"),
        "{e}"
    );
    // An unsolved plan: nothing to check, said as such (its starts and goals can still be
    // drawn: first_hour.rs, an_unsolved_grid_plan_file_shows_its_starts_and_goals).
    let unsolved = tmp("unsolved.json");
    let o = mrpp(&[
        "solve",
        "-m",
        &m,
        "-i",
        &i,
        "-N",
        "3",
        "-P",
        "lacam",
        "-t",
        "0.000001",
        "-o",
        unsolved.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(3), "{:?}", text(&o));
    let e = err_of(&["validate", "-m", &m, "--plan", unsolved.to_str().unwrap()]);
    assert!(
        e.contains("holds no plan (nothing to check or draw)"),
        "{e}"
    );
}
