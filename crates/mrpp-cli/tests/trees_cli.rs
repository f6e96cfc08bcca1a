//! End-to-end tests of `mrpp trees …`: generated instances solved by PSW and GP and accepted by
//! `trees validate`, saved and bundled GP programs, reproducible GP runs, and one-line errors
//! (exit 1, the file named, nothing written) for bad parameters, instances, programs and plans.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn data(rel: &str) -> String {
    root()
        .join("data/trees")
        .join(rel)
        .to_string_lossy()
        .into_owned()
}

fn mrpp(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mrpp"))
        .args(args)
        .output()
        .expect("run mrpp")
}

fn text(o: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// A fresh file path in this test's own directory (tests run in parallel).
fn tmp(test: &str, name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("mrpp-trees-test-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    let _ = std::fs::remove_file(&p);
    p
}

/// Removes a test's directory (left in place when the test fails, for inspection).
fn cleanup(test: &str) {
    let dir = std::env::temp_dir().join(format!("mrpp-trees-test-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(dir);
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Runs mrpp and asserts the exit code, showing the output when it differs.
fn run(args: &[&str], code: i32) -> (String, String) {
    let o = mrpp(args);
    let (out, err) = text(&o);
    assert_eq!(
        o.status.code(),
        Some(code),
        "mrpp {}\nstdout: {out}\nstderr: {err}",
        args.join(" ")
    );
    (out, err)
}

/// Asserts the one-line error contract: exit 1, one stderr line containing `needle`, no panic,
/// and `out` not written.
fn fails(args: &[&str], needle: &str, out: &Path) {
    let (_, err) = run(args, 1);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.starts_with("mrpp: error: ") && err.contains(needle),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    assert!(!out.exists(), "{} was written", out.display());
}

fn generate(test: &str, seed: &str, depth: &str, robots: &[&str]) -> PathBuf {
    let inst = tmp(test, "instance.json");
    let mut args = vec![
        "trees",
        "gen",
        "--seed",
        seed,
        "--depth",
        depth,
        "--out",
        s(&inst),
    ];
    args.extend_from_slice(robots);
    let (out, _) = run(&args, 0);
    assert!(
        out.contains(&format!("seed {seed}")) && out.contains("mrpp "),
        "{out}"
    );
    inst
}

fn json(p: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// `trees validate` must accept the plan; returns its stdout.
/// `mrpp trees validate` on a plan it must accept; the independent checker
/// (`tools/check/trees.py`) must accept it too, with the same metrics.
fn valid(inst: &Path, plan: &Path) -> String {
    let out = run(
        &[
            "trees",
            "validate",
            "--instance",
            s(inst),
            "--plan",
            s(plan),
        ],
        0,
    )
    .0;
    let checker = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tools/check/trees.py");
    let o = std::process::Command::new("python3")
        .arg(checker)
        .arg(inst)
        .arg(plan)
        .output()
        .expect("python3 runs the independent checker");
    let line = String::from_utf8_lossy(&o.stdout).trim().to_string();
    let verdict: serde_json::Value =
        serde_json::from_str(&line).unwrap_or_else(|e| panic!("{line}: {e}"));
    assert!(
        o.status.success() && verdict["valid"] == true,
        "checker: {line}"
    );
    for key in ["sum_of_costs", "makespan", "sum_of_moves"] {
        let ours = format!("{key} {}", verdict[key]);
        assert!(
            out.contains(&ours),
            "mrpp says `{out}`, the checker {key} = {}",
            verdict[key]
        );
    }
    out
}

const SMALL_GP: [&str; 6] = ["--population", "40", "--generations", "6", "--runs", "1"];

#[test]
fn gen_solve_psw_validate_round_trip() {
    let inst = generate("psw", "7", "6", &["--leaf-multiplier", "1.0"]);
    let t = json(&inst);
    let plan = tmp("psw", "plan.json");
    let (out, _) = run(
        &[
            "trees",
            "solve",
            "--instance",
            s(&inst),
            "--planner",
            "psw",
            "--out",
            s(&plan),
        ],
        0,
    );
    assert!(
        out.contains("planner psw | seed 0") && out.contains("solved:"),
        "{out}"
    );
    let p = json(&plan);
    assert_eq!(p["solved"], true);
    assert_eq!(p["format"], "mrpp-plan/1");
    assert_eq!(p["family"], "trees");
    assert_eq!(p["rules"]["goal"], "visit");
    assert_eq!(p["planner"], "psw");
    assert_eq!(p["world"]["file"], "instance.json");
    assert!(p["metrics"]["makespan"].as_u64().unwrap() > 0);
    assert_eq!(p["agents"][0]["start"], t["robots"][0]["start"]);
    assert!(valid(&inst, &plan).contains("valid:"));

    // Without following: recorded in the file and honoured by the validator.
    let strict = tmp("psw", "strict.json");
    run(
        &[
            "trees",
            "solve",
            "--instance",
            s(&inst),
            "--planner",
            "psw",
            "--no-following",
            "--out",
            s(&strict),
        ],
        0,
    );
    assert_eq!(json(&strict)["rules"]["following"], false);
    assert!(valid(&inst, &strict).contains("following forbidden"));
    cleanup("psw");
}

#[test]
fn gen_solve_gp_validate_and_saved_program_runs() {
    let inst = generate("gp", "2", "5", &["--leaf-multiplier", "1.0"]);
    let plan = tmp("gp", "plan.json");
    let prog = tmp("gp", "evolved.gp");
    let mut args = vec![
        "trees",
        "solve",
        "--instance",
        s(&inst),
        "--planner",
        "gp",
        "--seed",
        "5",
        "--save-program",
        s(&prog),
        "--out",
        s(&plan),
    ];
    args.extend_from_slice(&SMALL_GP);
    let (out, _) = run(&args, 0);
    assert!(
        out.contains("planner gp | seed 5") && out.contains("program written"),
        "{out}"
    );
    let p = json(&plan);
    assert_eq!(p["solved"], true);
    assert_eq!(p["seed"], 5);
    assert!(p["program"].as_str().unwrap().starts_with('('));
    assert!(valid(&inst, &plan).contains("planner gp | seed 5"));

    // The saved program, run again, gives the same plan and names itself in the file.
    let rerun = tmp("gp", "rerun.json");
    run(
        &[
            "trees",
            "run",
            "--program",
            s(&prog),
            "--instance",
            s(&inst),
            "--out",
            s(&rerun),
        ],
        0,
    );
    valid(&inst, &rerun);
    let r = json(&rerun);
    assert_eq!(r["agents"], p["agents"]);
    assert_eq!(r["program"], p["program"]);
    // `trees solve --program` is the same run.
    let via_solve = tmp("gp", "via_solve.json");
    run(
        &[
            "trees",
            "solve",
            "--instance",
            s(&inst),
            "--planner",
            "gp",
            "--program",
            s(&prog),
            "--out",
            s(&via_solve),
        ],
        0,
    );
    assert_eq!(json(&via_solve)["agents"], p["agents"]);
    cleanup("gp");
}

#[test]
fn bundled_program_solves_bundled_example() {
    let plan = tmp("bundled", "plan.json");
    let (out, _) = run(
        &[
            "trees",
            "run",
            "--program",
            &data("example-program.gp"),
            "--instance",
            &data("example.json"),
            "--out",
            s(&plan),
        ],
        0,
    );
    assert!(out.contains("makespan 70"), "{out}");
    let v = valid(Path::new(&data("example.json")), &plan);
    assert!(
        v.contains("18 agents | sum_of_costs") && v.contains("makespan 70"),
        "{v}"
    );
    // The program evolved at the paper's settings: 44 steps, a valid plan.
    let (out, _) = run(
        &[
            "trees",
            "run",
            "--program",
            &data("example-paper-settings.gp"),
            "--instance",
            &data("example.json"),
            "--out",
            s(&plan),
        ],
        0,
    );
    assert!(out.contains("makespan 44"), "{out}");
    let v = valid(Path::new(&data("example.json")), &plan);
    assert!(
        v.contains("18 agents | sum_of_costs") && v.contains("makespan 44"),
        "{v}"
    );
    // The bundled instance is what its README command makes.
    let again = generate("bundled", "1", "5", &["--robots", "18"]);
    assert_eq!(
        std::fs::read_to_string(&again).unwrap(),
        std::fs::read_to_string(data("example.json")).unwrap()
    );
    cleanup("bundled");
}

/// The same seed gives the same evolved program and plan with 1 and with 2 threads.
#[test]
fn gp_is_deterministic_for_a_seed() {
    let ex = data("example.json");
    let plans: Vec<serde_json::Value> = (0..2)
        .map(|k| {
            let plan = tmp("det", &format!("plan{k}.json"));
            let mut args = vec![
                "trees",
                "solve",
                "--instance",
                &ex,
                "--planner",
                "gp",
                "--seed",
                "3",
                "--out",
                s(&plan),
            ];
            args.extend_from_slice(&SMALL_GP);
            // One run on 1 rayon thread, the other on 2: the same program and plan.
            let o = Command::new(env!("CARGO_BIN_EXE_mrpp"))
                .args(&args)
                .env("RAYON_NUM_THREADS", (k + 1).to_string())
                .output()
                .expect("run mrpp");
            assert_eq!(o.status.code(), Some(0), "{:?}", text(&o));
            let mut v = json(&plan);
            // The only field allowed to differ: wall time.
            v["runtime_ms"] = serde_json::Value::Null;
            v
        })
        .collect();
    assert_eq!(plans[0], plans[1]);
    assert!(plans[0]["program"].is_string());
    cleanup("det");
}

#[test]
fn unsolved_runs_exit_3_and_still_write_the_file() {
    let prog = tmp("unsolved", "stay.gp");
    std::fs::write(&prog, "stay\n").unwrap();
    let plan = tmp("unsolved", "plan.json");
    let (out, _) = run(
        &[
            "trees",
            "run",
            "--program",
            s(&prog),
            "--instance",
            &data("example.json"),
            "--out",
            s(&plan),
        ],
        3,
    );
    assert!(out.contains("not solved"), "{out}");
    let p = json(&plan);
    assert_eq!(p["solved"], false);
    assert_eq!(p["metrics"]["makespan"], serde_json::Value::Null);
    assert!(
        p["agents"]
            .as_array()
            .unwrap()
            .iter()
            .all(|a| a["path"] == serde_json::json!([]))
    );
    // A file that holds no plan does not validate.
    fails(
        &[
            "trees",
            "validate",
            "--instance",
            &data("example.json"),
            "--plan",
            s(&plan),
        ],
        "no plan",
        &tmp("unsolved", "none"),
    );
    cleanup("unsolved");
}

#[test]
fn bad_instance_files_are_one_line_errors_naming_the_file() {
    let cases: [(&str, Option<&str>, &str); 6] = [
        (
            "cycle.json",
            Some(
                r#"{"nodes": 4, "edges": [[0, 1], [1, 2], [2, 0], [2, 3]], "robots": [{"start": 3, "goal": 0}]}"#,
            ),
            "cycle",
        ),
        (
            "disconnected.json",
            Some(
                r#"{"nodes": 5, "edges": [[0, 1], [1, 2], [3, 4]], "robots": [{"start": 2, "goal": 0}]}"#,
            ),
            "disconnected",
        ),
        (
            "shared_start.json",
            Some(
                "{\"nodes\": 4, \"edges\": [[0, 1], [1, 2], [1, 3]],\n\"robots\": [\n{\"start\": 2, \"goal\": 3},\n{\"start\": 2, \"goal\": 0}\n]}",
            ),
            "starts on node 2, the start of robot 0",
        ),
        (
            "goal_off.json",
            Some(
                r#"{"nodes": 4, "edges": [[0, 1], [1, 2], [1, 3]], "robots": [{"start": 2, "goal": 4}]}"#,
            ),
            "goal 4 is not a node",
        ),
        (
            "malformed.json",
            Some("{\"nodes\": 4, \"edges\": [[0, 1],"),
            "malformed.json:1:",
        ),
        ("missing.json", None, "missing.json"),
    ];
    let prog = data("example-program.gp");
    for (name, content, needle) in cases {
        let inst = tmp("badinst", name);
        if let Some(c) = content {
            std::fs::write(&inst, c).unwrap();
        }
        let out = tmp("badinst", "plan.json");
        let commands: [Vec<&str>; 4] = [
            vec!["trees", "solve", "--instance", s(&inst), "--planner", "psw"],
            vec!["trees", "solve", "--instance", s(&inst), "--planner", "gp"],
            vec!["trees", "run", "--program", &prog, "--instance", s(&inst)],
            vec![
                "trees",
                "validate",
                "--instance",
                s(&inst),
                "--plan",
                s(&out),
            ],
        ];
        for mut args in commands {
            if args[1] != "validate" {
                args.extend_from_slice(&["--out", s(&out)]);
            }
            fails(&args, needle, &out);
            fails(&args, name, &out);
        }
    }
    cleanup("badinst");
}

#[test]
fn bad_program_file_names_file_and_line() {
    let prog = tmp("badprog", "unclosed.gp");
    std::fs::write(
        &prog,
        "; a comment\n(if-robot-is-solved\n  stay\n  (if-neighbor-on-path-is-free move-toward-objective stay)\n",
    )
    .unwrap();
    let out = tmp("badprog", "plan.json");
    let needle = format!("{}:2:", prog.display());
    fails(
        &[
            "trees",
            "run",
            "--program",
            s(&prog),
            "--instance",
            &data("example.json"),
            "--out",
            s(&out),
        ],
        &needle,
        &out,
    );
    fails(
        &[
            "trees",
            "solve",
            "--planner",
            "gp",
            "--program",
            s(&prog),
            "--instance",
            &data("example.json"),
            "--out",
            s(&out),
        ],
        &needle,
        &out,
    );
    cleanup("badprog");
}

#[test]
fn absurd_gen_and_solve_parameters_are_refused() {
    let out = tmp("params", "out.json");
    let o = s(&out);
    let gen_cases: [(&[&str], &str); 9] = [
        (&["--depth", "0", "--robots", "2"], "--depth"),
        (&["--depth", "31", "--robots", "2"], "--depth"),
        (
            &["--depth", "5", "--branching", "0", "--robots", "2"],
            "--branching",
        ),
        (
            &["--depth", "5", "--branching", "17", "--robots", "2"],
            "--branching",
        ),
        (&["--depth", "5", "--robots", "36"], "at most 35"),
        (
            &["--depth", "5", "--leaf-multiplier", "-0.5"],
            "--leaf-multiplier",
        ),
        (
            &["--depth", "5", "--leaf-multiplier", "NaN"],
            "--leaf-multiplier",
        ),
        (
            &["--depth", "5", "--robots", "3", "--leaf-multiplier", "1"],
            "not both",
        ),
        (&["--depth", "5"], "--robots N or --leaf-multiplier M"),
    ];
    for (extra, needle) in gen_cases {
        let mut args = vec!["trees", "gen", "--seed", "1", "--out", o];
        args.extend_from_slice(extra);
        fails(&args, needle, &out);
    }
    // Huge trees are refused quickly instead of exhausting memory.
    let started = std::time::Instant::now();
    fails(
        &[
            "trees",
            "gen",
            "--seed",
            "1",
            "--depth",
            "30",
            "--leaf-multiplier",
            "1",
            "--out",
            o,
        ],
        "--max-nodes",
        &out,
    );
    fails(
        &[
            "trees",
            "gen",
            "--seed",
            "1",
            "--depth",
            "30",
            "--branching",
            "16",
            "--robots",
            "3",
            "--out",
            o,
        ],
        "nodes",
        &out,
    );
    assert!(started.elapsed().as_secs() < 30);

    let ex = data("example.json");
    let solve_cases: [(&[&str], &str); 5] = [
        (&["--planner", "gp", "--population", "1"], "population"),
        (&["--planner", "gp", "--generations", "0"], "generation"),
        (&["--planner", "psw", "--population", "10"], "--planner gp"),
        (&["--planner", "psw", "--program", "x.gp"], "--planner gp"),
        (&["--planner", "psw", "--time-limit", "-1"], "--time-limit"),
    ];
    for (extra, needle) in solve_cases {
        let mut args = vec!["trees", "solve", "--instance", &ex, "--out", o];
        args.extend_from_slice(extra);
        fails(&args, needle, &out);
    }
    cleanup("params");
}

#[test]
fn validate_rejects_tampered_plans() {
    let ex = data("example.json");
    let plan = tmp("tamper", "plan.json");
    run(
        &[
            "trees",
            "solve",
            "--instance",
            &ex,
            "--planner",
            "psw",
            "--out",
            s(&plan),
        ],
        0,
    );
    let good = json(&plan);
    let bad = tmp("tamper", "bad.json");
    let check = |edit: &dyn Fn(&mut serde_json::Value), needle: &str| {
        let mut v = good.clone();
        edit(&mut v);
        std::fs::write(&bad, serde_json::to_string_pretty(&v).unwrap()).unwrap();
        let (_, err) = run(
            &["trees", "validate", "--instance", &ex, "--plan", s(&bad)],
            1,
        );
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains("bad.json") && err.contains(needle), "{err}");
    };
    check(
        &|v| v["metrics"]["sum_of_costs"] = serde_json::json!(1),
        "claims sum_of_costs 1",
    );
    check(
        &|v| v["metrics"]["makespan"] = serde_json::json!(2),
        "claims makespan 2",
    );
    check(
        &|v| v["agents"][0]["path"][1] = serde_json::json!(99),
        "node 99",
    );
    check(
        &|v| v["agents"][0]["goal"] = serde_json::json!(0),
        "robot 0 has goal 0",
    );
    // Robot 1 jumps onto robot 0's start at t = 1.
    check(
        &|v| {
            let to = v["agents"][0]["path"][0].clone();
            v["agents"][1]["path"][1] = to;
        },
        "invalid plan",
    );
    check(
        &|v| v["agents"].as_array_mut().unwrap().truncate(3),
        "3 robots but the instance has 18",
    );
    // Malformed JSON names the file and line.
    std::fs::write(
        &bad,
        "{\n\"solved\": true,\n\"agents\": [\n{\"start\": -1}]}",
    )
    .unwrap();
    let (_, err) = run(
        &["trees", "validate", "--instance", &ex, "--plan", s(&bad)],
        1,
    );
    assert!(err.contains("bad.json:4:"), "{err}");
    cleanup("tamper");
}

/// The three GP experiments at toy size: every output file is written, the Markdown tables carry
/// the paper's numbers beside ours, and the CSV rows are those of the problems asked for.
#[test]
fn gp_experiments_write_tables_csv_and_figures() {
    let dir = tmp("experiments", "x");
    let base = dir.parent().unwrap().to_path_buf();
    let small = [
        "--population",
        "12",
        "--generations",
        "2",
        "--runs",
        "1",
        "--depths",
        "3-4",
        "--seed",
        "3",
    ];
    let out3 = base.join("t3");
    let mut args = vec![
        "experiment",
        "gp-table3",
        "--problems",
        "4",
        "--out",
        s(&out3),
    ];
    args.extend(small);
    let (stdout, _) = run(&args, 0);
    assert!(stdout.contains("seed 3") && stdout.contains("| paper (1000 problems) | 73.3%"));
    let csv = std::fs::read_to_string(out3.join("results.csv")).unwrap();
    assert_eq!(csv.lines().count(), 5, "{csv}");
    for f in ["table3.md", "fig4.svg", "fig5.svg"] {
        assert!(out3.join(f).exists(), "{f}");
    }
    assert_eq!(common::every_svg_rasterises(&out3), 2);
    assert!(
        std::fs::read_to_string(out3.join("fig4.svg"))
            .unwrap()
            .contains("<svg")
    );

    let out4 = base.join("t4");
    let mut args = vec![
        "experiment",
        "gp-table4",
        "--problems",
        "3",
        "--train-sizes",
        "1,2",
        "--trials",
        "1",
        "--out",
        s(&out4),
    ];
    args.extend(small);
    let (stdout, _) = run(&args, 0);
    // One row per |X|, each over its 3 test problems.
    assert!(
        stdout.contains("| 1 | ") && stdout.contains("| 2 | ") && stdout.contains(" / 3 |"),
        "{stdout}"
    );
    let csv = std::fs::read_to_string(out4.join("results.csv")).unwrap();
    assert_eq!(csv.lines().count(), 7, "{csv}");
    for f in ["programs.csv", "table4.md", "fig6.svg", "fig7.svg"] {
        assert!(out4.join(f).exists(), "{f}");
    }
    assert_eq!(common::every_svg_rasterises(&out4), 2);

    let out5 = base.join("t5");
    let mut args = vec![
        "experiment",
        "gp-table5",
        "--problems",
        "2",
        "--multipliers",
        "0.5,1.5",
        "--out",
        s(&out5),
    ];
    args.extend(small);
    let (stdout, _) = run(&args, 0);
    assert!(
        stdout.contains("| 1.5 |") && stdout.contains("| 58 | 34 |"),
        "{stdout}"
    );
    let csv = std::fs::read_to_string(out5.join("results.csv")).unwrap();
    assert_eq!(csv.lines().count(), 5, "{csv}");
    assert!(out5.join("table5.svg").exists());
    assert_eq!(common::every_svg_rasterises(&out5), 1);

    // Absurd parameters: one line, exit 1.
    for bad in [
        vec!["experiment", "gp-table3", "--problems", "0"],
        vec!["experiment", "gp-table3", "--depths", "9-3"],
        vec!["experiment", "gp-table5", "--multipliers", "-1"],
        vec!["experiment", "gp-table4", "--train-sizes", "0"],
        vec!["experiment", "gp-table3", "--population", "1"],
    ] {
        let o = mrpp(&bad);
        let (_, err) = text(&o);
        assert_eq!(o.status.code(), Some(1), "{bad:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    cleanup("experiments");
}
