//! Issue 28 end to end: `mrpp solve --lorr P.json -P lifelong-pibt` runs a League of Robot
//! Runners problem lifelong and writes LoRR's output JSON; `mrpp validate` and the independent
//! checker (`tools/check/lifelong.py`) agree on it; malformed problems are refused naming file,
//! line and rule, exit 1, nothing written.

mod common;

use common::{mrpp, root};
use std::path::{Path, PathBuf};
use std::process::Command;

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("mrpp-lifelong-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const MAZE: &str = "data/robot-runners/lorr2026-maze/maze-example_40.json";
const WAREHOUSE: &str = "data/robot-runners/lorr2023-warehouse_small/warehouse_small_10.json";

/// The checker's verdict on a run, `(valid, tasks finished)`, or `None` without python3 (CI
/// has it).
fn checker(problem: &str, run: &Path) -> Option<(bool, u64)> {
    let o = Command::new("python3")
        .arg("tools/check/lifelong.py")
        .args(["--json", problem])
        .arg(run)
        .current_dir(root())
        .output()
        .ok()?;
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap_or_else(|e| {
        panic!(
            "checker output: {e}: {}",
            String::from_utf8_lossy(&o.stdout)
        )
    });
    Some((v["valid"].as_bool()?, v["tasks_finished"].as_u64()?))
}

#[test]
fn a_lifelong_run_is_written_validated_and_checked_independently() {
    let dir = tmp("runs");
    for problem in [MAZE, WAREHOUSE] {
        for model in ["MAPF_T", "MAPF"] {
            for scheduler in ["greedy", "hungarian"] {
                let out = dir.join(format!("{model}-{scheduler}.json"));
                let o = out.to_str().unwrap();
                let what = format!("{problem} {model} {scheduler}");
                let (code, stdout, err) = mrpp(&[
                    "solve",
                    "--lorr",
                    problem,
                    "-P",
                    "lifelong-pibt",
                    "-p",
                    &format!("scheduler={scheduler}"),
                    "--steps",
                    "300",
                    "--action-model",
                    model,
                    "-s",
                    "1",
                    "-o",
                    o,
                ]);
                assert_eq!(code, Some(0), "{what}: {stdout}{err}");
                let run: serde_json::Value =
                    serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
                let finished = run["numTaskFinished"].as_u64().unwrap();
                assert!(finished > 0, "{what}: no task finished");
                assert_eq!(run["actionModel"], model);
                assert_eq!(run["mrpp"]["metrics"]["tasks_finished"], finished);
                let (code, stdout, err) = mrpp(&["validate", "--lorr", problem, "--plan", o]);
                assert_eq!(code, Some(0), "{what}: {stdout}{err}");
                assert!(
                    stdout.contains(&format!("tasks_finished {finished}")),
                    "{stdout}"
                );
                if let Some((valid, tasks)) = checker(problem, &out) {
                    assert!(valid, "{what}: the checker refuses mrpp's run");
                    assert_eq!(tasks, finished, "{what}");
                }
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_tampered_run_is_refused_by_validate_and_the_checker() {
    let dir = tmp("tampered");
    let out = dir.join("run.json");
    let o = out.to_str().unwrap();
    let (code, _, err) = mrpp(&[
        "solve",
        "--lorr",
        MAZE,
        "-P",
        "lifelong-pibt",
        "--steps",
        "100",
        "-o",
        o,
    ]);
    assert_eq!(code, Some(0), "{err}");
    let mut run: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let honest = run["numTaskFinished"].as_u64().unwrap();
    // A claim of one more task.
    run["numTaskFinished"] = (honest + 1).into();
    let claims = dir.join("claims.json");
    std::fs::write(&claims, run.to_string()).unwrap();
    let (code, _, err) = mrpp(&[
        "validate",
        "--lorr",
        MAZE,
        "--plan",
        claims.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("tasks_finished"), "{err}");
    if let Some((valid, _)) = checker(MAZE, &claims) {
        assert!(!valid);
    }
    // Robot 1 drives forward at every step: off the map or into a wall, or into another robot.
    run["numTaskFinished"] = honest.into();
    let steps = run["actualPaths"][1].as_str().unwrap().split(',').count();
    run["actualPaths"][1] = vec!["F"; steps].join(",").into();
    let moves = dir.join("moves.json");
    std::fs::write(&moves, run.to_string()).unwrap();
    let (code, _, err) = mrpp(&[
        "validate",
        "--lorr",
        MAZE,
        "--plan",
        moves.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("unallowed move") || err.contains("conflict"),
        "{err}"
    );
    if let Some((valid, _)) = checker(MAZE, &moves) {
        assert!(!valid);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn malformed_lifelong_problems_name_file_line_and_rule() {
    let dir = tmp("malformed");
    std::fs::write(
        dir.join("m.map"),
        "type octile\nheight 3\nwidth 4\nmap\n....\n.@..\n....\n",
    )
    .unwrap();
    let write = |agents: &str, tasks: &str, reveal: &str| {
        std::fs::write(dir.join("a.agents"), agents).unwrap();
        std::fs::write(dir.join("t.tasks"), tasks).unwrap();
        std::fs::write(
            dir.join("p.json"),
            format!(
                r#"{{"mapFile": "m.map", "agentFile": "a.agents", "taskFile": "t.tasks", "teamSize": 2, "numTasksReveal": {reveal}}}"#
            ),
        )
        .unwrap();
    };
    let p = dir.join("p.json");
    let out = dir.join("run.json");
    let solve = || {
        mrpp(&[
            "solve",
            "--lorr",
            p.to_str().unwrap(),
            "-P",
            "lifelong-pibt",
            "--steps",
            "20",
            "-o",
            out.to_str().unwrap(),
        ])
    };
    write("2\n0\n3\n", "2\n2,11\n8\n", "1");
    let (code, _, err) = solve();
    assert_eq!(code, Some(0), "the well-formed one runs: {err}");
    std::fs::remove_file(&out).unwrap();
    for (agents, tasks, reveal, says) in [
        (
            "2\n0\n3\n",
            "2\n2,5\n8\n",
            "1",
            "t.tasks:2: location 5 is cell (1,1), a wall",
        ),
        (
            "2\n5\n3\n",
            "2\n2\n8\n",
            "1",
            "a.agents:2: location 5 is cell (1,1), a wall",
        ),
        (
            "2\n3\n3\n",
            "2\n2\n8\n",
            "1",
            "a.agents:3: start (3,0) is also the start on line 2",
        ),
        (
            "2\n0\n3\n",
            "2\n2,12\n8\n",
            "1",
            "t.tasks:2: location 12 is off the map (0..12)",
        ),
        (
            "2\n0\n3\n",
            "2\n2,x\n8\n",
            "1",
            "t.tasks:2: `x` is not a location",
        ),
        (
            "2\n0\n3\n",
            "3\n2\n8\n",
            "1",
            "t.tasks:1: count line says 3 but 2 entries follow",
        ),
        ("2\n0\n3\n", "2\n2\n8\n", "0", "`numTasksReveal` is 0"),
    ] {
        write(agents, tasks, reveal);
        let (code, _, err) = solve();
        assert_eq!(code, Some(1), "{says}: {err}");
        assert!(err.contains(says), "expected `{says}` in: {err}");
        assert!(!out.exists(), "{says}: nothing is written");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_lifelong_run_can_be_watched() {
    let dir = tmp("view");
    let run = dir.join("run.json");
    let page = dir.join("run.html");
    let (code, _, err) = mrpp(&[
        "solve",
        "--lorr",
        MAZE,
        "-P",
        "lifelong-pibt",
        "--steps",
        "30",
        "-o",
        run.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{err}");
    let (code, _, err) = mrpp(&[
        "view",
        "--lorr",
        MAZE,
        "--plan",
        run.to_str().unwrap(),
        "-o",
        page.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{err}");
    let html = std::fs::read_to_string(&page).unwrap();
    assert!(html.contains(r#""family":"lifelong""#));
    assert!(
        !html.contains(r#""unit":"#),
        "a run in steps is counted in steps"
    );
    assert!(
        html.contains(r#""valid":true"#),
        "the run is shown as valid"
    );
    // 40 robots, 31 positions each (start and 30 steps).
    let start = html.find(r#""agents":"#).unwrap();
    assert_eq!(html[start..].matches(r#""cells":["#).count(), 40);
    // The throughput figure: its title recounts the run's tasks, a panel per view of them.
    let finished =
        serde_json::from_str::<serde_json::Value>(&std::fs::read_to_string(&run).unwrap()).unwrap()
            ["numTaskFinished"]
            .clone();
    let figure = dir.join("throughput.svg");
    let (code, _, err) = mrpp(&[
        "render",
        "--lorr",
        MAZE,
        "--plan",
        run.to_str().unwrap(),
        "-o",
        figure.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{err}");
    let svg = std::fs::read_to_string(&figure).unwrap();
    assert!(
        svg.contains(&format!(
            "40 robots | {finished} tasks finished in 30 steps"
        )),
        "{}",
        &svg[..svg.len().min(600)]
    );
    assert!(svg.contains("tasks finished so far") && svg.contains("tasks finished per step"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_run_cut_by_the_time_limit_keeps_its_steps_and_says_so() {
    let dir = tmp("cut");
    let run = dir.join("run.json");
    let (code, _, err) = mrpp(&[
        "solve",
        "--lorr",
        MAZE,
        "-P",
        "lifelong-pibt",
        "--steps",
        "10000000",
        "--time-limit",
        "0.2",
        "-o",
        run.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("stopped at the time limit after"), "{err}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&run).unwrap()).unwrap();
    let steps = v["mrpp"]["metrics"]["steps"].as_u64().unwrap();
    assert!(steps > 0 && steps < 10_000_000, "{steps}");
    assert!(
        v["mrpp"]["status"]
            .as_str()
            .unwrap()
            .starts_with("stopped after"),
        "{}",
        v["mrpp"]["status"]
    );
    let (code, _, err) = mrpp(&["validate", "--lorr", MAZE, "--plan", run.to_str().unwrap()]);
    assert_eq!(code, Some(0), "the steps done are a valid run: {err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_experiment_runs_lifelong_problems_beside_a_peer_and_reports_a_broken_one() {
    let dir = tmp("experiment");
    // The peer is mrpp itself writing the League's output JSON, run as an external command; a
    // second, broken peer must show up as peer_failed with its exit status, never as a result.
    let exe = env!("CARGO_BIN_EXE_mrpp");
    for (peer, out) in [
        (
            format!(
                "self={exe} -q solve --lorr {{problem}} -P lifelong-pibt --steps {{steps}} -s 9 -o {{out}}"
            ),
            "ok",
        ),
        (
            "broken=sh -c 'echo no such kit >&2; exit 3' {problem} {out}".to_string(),
            "broken",
        ),
    ] {
        let out_dir = dir.join(out);
        let (code, _, err) = mrpp(&[
            "experiment",
            "lorr",
            MAZE,
            WAREHOUSE,
            "--steps",
            "40",
            "--schedulers",
            "greedy",
            "--runs",
            "2",
            "--peer",
            &peer,
            "-o",
            out_dir.to_str().unwrap(),
        ]);
        assert_eq!(code, Some(0), "{err}");
        let csv = std::fs::read_to_string(out_dir.join("results.csv")).unwrap();
        let rows: Vec<Vec<&str>> = csv
            .lines()
            .skip(1)
            .map(|l| l.split(',').collect())
            .collect();
        // Per problem: the peer once, lifelong-pibt greedy twice.
        assert_eq!(rows.len(), 6, "{csv}");
        for r in &rows {
            let (program, status, tasks) = (r[3], r[8], r[9]);
            if program == "lifelong-pibt" || out == "ok" {
                assert_eq!(status, "valid", "{csv}");
                assert!(tasks.parse::<u64>().unwrap() > 0, "{csv}");
            } else {
                assert_eq!(status, "peer_failed", "{csv}");
                assert!(r[17..].join(",").contains("exit 3: no such kit"), "{csv}");
            }
        }
        let page = std::fs::read_to_string(out_dir.join("lorr.md")).unwrap();
        assert!(page.contains("| maze-example_40 | 40 |"), "{page}");
        assert!(
            std::fs::read_to_string(out_dir.join("throughput.svg"))
                .unwrap()
                .contains("<svg")
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn gen_lorr_writes_a_problem_the_start_kit_layout_reads_and_mrpp_runs() {
    let dir = tmp("gen");
    let out = dir.join("maze-25.json");
    let args = |seed: &str| {
        vec![
            "gen".to_string(),
            "lorr".into(),
            "-m".into(),
            "data/robot-runners/lorr2026-maze/maps/maze-32-32-2.map".into(),
            "--robots".into(),
            "25".into(),
            "--tasks".into(),
            "200".into(),
            "--errands".into(),
            "3".into(),
            "-s".into(),
            seed.into(),
            "-o".into(),
            out.to_str().unwrap().into(),
        ]
    };
    let run = |a: Vec<String>| mrpp(&a.iter().map(String::as_str).collect::<Vec<_>>());
    let (code, _, err) = run(args("4"));
    assert_eq!(code, Some(0), "{err}");
    let tasks = std::fs::read_to_string(dir.join("tasks/maze-25.tasks")).unwrap();
    let lines: Vec<&str> = tasks.lines().collect();
    assert_eq!(lines[1], "200");
    assert_eq!(lines.len(), 202);
    assert!(lines[2..].iter().all(|l| l.split(',').count() == 3));
    // Seeded: the same seed writes the same files.
    let (code, _, err) = run(args("4"));
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(
        std::fs::read_to_string(dir.join("tasks/maze-25.tasks")).unwrap(),
        tasks
    );
    // It reads as a lifelong problem and runs valid.
    let runf = dir.join("run.json");
    let (code, _, err) = mrpp(&[
        "solve",
        "--lorr",
        out.to_str().unwrap(),
        "-P",
        "lifelong-pibt",
        "--steps",
        "50",
        "-o",
        runf.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{err}");
    if let Some((valid, _)) = checker(out.to_str().unwrap(), &runf) {
        assert!(valid);
    }
    // More robots than free cells, and an --out that is not JSON: refused, nothing written.
    let mut too_many = args("4");
    too_many[5] = "100000".into();
    let (code, _, err) = run(too_many);
    assert_eq!(code, Some(1));
    assert!(err.contains("cannot place 100000 robots"), "{err}");
    let mut not_json = args("4");
    not_json[13] = dir.join("p.txt").to_str().unwrap().into();
    let (code, _, err) = run(not_json);
    assert_eq!(code, Some(1));
    assert!(err.contains("must end in .json"), "{err}");
    assert!(!dir.join("p.txt").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_run_in_ticks_under_delays_is_written_validated_and_bad_settings_are_refused() {
    let dir = tmp("ticks");
    let out = dir.join("ticks.json");
    let o = out.to_str().unwrap();
    let (code, stdout, err) = mrpp(&[
        "solve",
        "--lorr",
        MAZE,
        "-P",
        "lifelong-pibt",
        "--ticks",
        "400",
        "--delays",
        "bernoulli:p=0.01,min=2,max=6",
        "-o",
        o,
    ]);
    assert_eq!(code, Some(0), "{stdout}{err}");
    assert!(stdout.contains("400 ticks, 3 per action"), "{stdout}");
    let run: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(run["version"], "2026 LoRR");
    assert_eq!(run["makespan"], 400);
    assert_eq!(run["agentMaxCounter"], 3);
    let finished = run["numTaskFinished"].as_u64().unwrap();
    assert!(finished > 0);
    let delays: usize = run["delayIntervals"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| d.as_array().unwrap().len())
        .sum();
    assert!(delays > 0, "p = 0.01 over 400 ticks delays someone");
    assert_eq!(run["mrpp"]["execution"]["executor"], "tpg");
    let (code, stdout, err) = mrpp(&["validate", "--lorr", MAZE, "--plan", o]);
    assert_eq!(code, Some(0), "{stdout}{err}");
    assert!(
        stdout.contains(&format!("tasks_finished {finished}")),
        "{stdout}"
    );
    // The viewer marks delays (a red ring while a delay holds a robot).
    let page = dir.join("ticks.html");
    let (code, stdout, err) = mrpp(&[
        "view",
        "--lorr",
        MAZE,
        "--plan",
        o,
        "--out",
        page.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{stdout}{err}");
    let html = std::fs::read_to_string(&page).unwrap();
    assert!(html.contains("\"held\":[["), "no delay marked in the page");
    // The page counts the run's time in ticks: its info line says "400 ticks", not "400 steps".
    assert!(
        html.contains(r#""unit":"tick""#),
        "the scene is not in ticks"
    );
    assert!(
        html.contains("const unit = scene.unit || \"step\";")
            && html.contains("${steps} ${unit}s |"),
        "the page does not name its unit"
    );
    // Robots are drawn part way along their moves (3 ticks an action: a third of a cell a
    // tick), not on cells only.
    assert!(
        html.contains("\"path\":[["),
        "no per-tick points in the page"
    );
    assert!(
        html.contains(".8333333333333") || html.contains(".1666666666666"),
        "no point a third of a cell along a move"
    );
    // A delayed robot that turns anyway: refused, naming the tick and the robot.
    let mut bad = run.clone();
    let (agent, start) = run["delayIntervals"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
        .find_map(|(i, d)| Some((i, d.get(0)?.get(0)?.as_u64()?)))
        .unwrap();
    // The robot's own ticks, with one action changed.
    let mut ticks: Vec<char> = Vec::new();
    for seg in run["actualPaths"][agent].as_str().unwrap().split(']') {
        let Some((_, body)) = seg.split_once("):(") else {
            continue;
        };
        for pair in body.trim_end_matches(')').split(',') {
            let (l, k) = pair.split_once(' ').unwrap();
            let k: usize = k.parse().unwrap();
            ticks.extend(std::iter::repeat_n(l.chars().next().unwrap(), k));
        }
    }
    assert_eq!(ticks[start as usize], 'W', "a delayed robot waits");
    ticks[start as usize] = 'R';
    let segs: String = ticks
        .chunks(100)
        .enumerate()
        .map(|(k, c)| {
            let body: Vec<String> = c.iter().map(|l| format!("{l} 1")).collect();
            format!("[({},0,0,0,0):({})]", k * 100, body.join(","))
        })
        .collect();
    bad["actualPaths"][agent] = serde_json::Value::String(segs);
    let tampered = dir.join("tampered.json");
    std::fs::write(&tampered, bad.to_string()).unwrap();
    let (code, stdout, err) = mrpp(&[
        "validate",
        "--lorr",
        MAZE,
        "--plan",
        tampered.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(1), "{stdout}{err}");
    assert!(
        err.contains(&format!(
            "tick {}: robot {agent} acts while delayed",
            start + 1
        )),
        "{err}"
    );
    // Settings refused by name, nothing written.
    let none = dir.join("none.json");
    let n = none.to_str().unwrap();
    for (args, says) in [
        (
            vec!["--ticks", "50", "--delays", "bernoulli:p=2,min=1,max=3"],
            "p=2 is outside [0, 1]",
        ),
        (
            vec!["--ticks", "50", "--executor", "adg"],
            "--executor adg: expected tpg",
        ),
        (
            vec!["--ticks", "50", "--agent-size", "1.5"],
            "--agent-size 1.5",
        ),
        (
            vec!["--steps", "50", "--delays", "none"],
            "--delays applies to lifelong runs in ticks",
        ),
        (
            vec!["--steps", "50", "--k-robust", "1"],
            "--k-robust applies to lifelong runs in ticks",
        ),
        (
            vec!["--ticks", "50", "--k-robust", "-2"],
            "--k-robust -2: expected 0 to 1000",
        ),
    ] {
        let mut all = vec!["solve", "--lorr", MAZE, "-P", "lifelong-pibt", "-o", n];
        all.extend(args);
        let (code, stdout, err) = mrpp(&all);
        assert_eq!(code, Some(1), "{all:?}: {stdout}{err}");
        assert!(err.contains(says), "{all:?}: {err}");
        assert!(!none.exists());
    }
    // A problem whose delayConfig the kit would refuse.
    let src = root().join("data/robot-runners/lorr2026-maze");
    let copy = dir.join("maze");
    for sub in ["maps", "agents", "tasks"] {
        std::fs::create_dir_all(copy.join(sub)).unwrap();
        for f in std::fs::read_dir(src.join(sub)).unwrap() {
            let f = f.unwrap().path();
            std::fs::copy(&f, copy.join(sub).join(f.file_name().unwrap())).unwrap();
        }
    }
    let text = std::fs::read_to_string(src.join("maze-example_40.json"))
        .unwrap()
        .replace("\"minDelay\": 5", "\"minDelay\": 0");
    let problem = copy.join("maze-example_40.json");
    std::fs::write(&problem, text).unwrap();
    let (code, stdout, err) = mrpp(&[
        "solve",
        "--lorr",
        problem.to_str().unwrap(),
        "-P",
        "lifelong-pibt",
        "--ticks",
        "50",
        "-o",
        n,
    ]);
    assert_eq!(code, Some(1), "{stdout}{err}");
    assert!(
        err.contains("maze-example_40.json") && err.contains("delayConfig"),
        "{err}"
    );
    assert!(!none.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn info_gives_the_congestion_free_reference_over_a_horizon() {
    let (code, stdout, err) = mrpp(&["info", "--lorr", MAZE, "--lifelong", "--steps", "150"]);
    assert_eq!(code, Some(0), "{stdout}{err}");
    for scheduler in [
        "greedy scheduler",
        "hungarian scheduler",
        "hungarian scheduler with -p chain_weight=0",
    ] {
        assert!(reference_tasks(&stdout, scheduler) > 0, "{stdout}");
    }
}

/// The tasks of `info`'s congestion-free reference line for `name`.
fn reference_tasks(stdout: &str, name: &str) -> usize {
    let line = stdout
        .lines()
        .find(|l| l.contains(&format!("congestion-free reference ({name},")))
        .unwrap_or_else(|| panic!("{stdout}"));
    line.split(": ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{line}"))
}

/// `--reference-scheduler` adds the reference under a scheduler given as the planners' options
/// (with the kit's scheduler it equals the `greedy` line); a malformed or unknown option is an
/// error naming the flag, exit 1.
#[test]
fn info_takes_the_reference_under_a_given_scheduler() {
    let info = |spec: &str| {
        mrpp(&[
            "info",
            "--lorr",
            MAZE,
            "--lifelong",
            "--steps",
            "150",
            "--reference-scheduler",
            spec,
        ])
    };
    let (code, stdout, err) = info("scheduler=greedy");
    assert_eq!(code, Some(0), "{stdout}{err}");
    assert_eq!(
        reference_tasks(&stdout, "scheduler scheduler=greedy"),
        reference_tasks(&stdout, "greedy scheduler")
    );
    let (code, stdout, err) = info("scheduler=hungarian,lookahead=10");
    assert_eq!(code, Some(0), "{stdout}{err}");
    assert!(reference_tasks(&stdout, "scheduler scheduler=hungarian,lookahead=10") > 0);
    for bad in ["lookahead", "window=3", "lookahead=5000"] {
        let (code, stdout, err) = info(bad);
        assert_eq!(code, Some(1), "{bad}: {stdout}{err}");
        assert!(err.contains("--reference-scheduler"), "{bad}: {err}");
    }
}
