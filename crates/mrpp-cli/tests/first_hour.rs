//! A newcomer's first hour (issue 30): the README renders as written (item 6: a blank line after
//! the GP row turned the eleven rows after it into raw `|` text), and shell completion offers
//! planner, family and world-kind names rather than file names (item 4).

mod common;

use std::path::{Path, PathBuf};

/// What one run of `mrpp` gave: exit code, stdout, stderr.
struct Ran {
    code: Option<i32>,
    out: String,
    err: String,
}

/// Runs `mrpp args` in `dir`.
fn mrpp_in(dir: &Path, args: &[&str]) -> Ran {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_mrpp"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run mrpp");
    Ran {
        code: o.status.code(),
        out: String::from_utf8_lossy(&o.stdout).into_owned(),
        err: String::from_utf8_lossy(&o.stderr).into_owned(),
    }
}

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
        let r = mrpp_in(&std::env::temp_dir(), args);
        (r.code, r.err)
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

/// Item 2: the README's commands leave no trace and its picture is what its command draws. Every
/// file a README command block writes (`--out X`, `> X`, a venv) is ignored by git, none is a
/// tracked file; and `docs/warehouse-hstar.png` is byte for byte what the README's `solve` and
/// `render` lines draw.
#[test]
fn readme_commands_leave_no_trace_and_its_picture_is_what_they_draw() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let blocks: Vec<&str> = readme
        .split("```sh\n")
        .skip(1)
        .filter_map(|b| b.split("```").next())
        .collect();
    let mut written = Vec::new();
    for line in blocks.iter().flat_map(|b| b.lines()) {
        let words: Vec<&str> = line.split_whitespace().collect();
        for w in words.windows(2) {
            if ["--out", "-o", ">"].contains(&w[0]) && !w[1].starts_with('~') {
                written.push(w[1].to_string());
            }
        }
        if line.contains("python3 -m venv ") {
            written.push(".venv/".into());
        }
    }
    assert!(written.len() >= 3, "{written:?}");
    let git = |args: &[&str]| {
        std::process::Command::new("git")
            .args(args)
            .current_dir(&root)
            .output()
    };
    if git(&["rev-parse", "--git-dir"]).is_ok_and(|o| o.status.success()) {
        for path in &written {
            let ignored = git(&["check-ignore", "-q", "--no-index", path]).unwrap();
            assert!(
                ignored.status.success(),
                "the README writes {path}, which git does not ignore"
            );
        }
    }
    // The picture: the README's solve, then its render.
    let dir = std::env::temp_dir().join(format!("mrpp-readme-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let data = root.join("data/hstar-paper/scenario3");
    let (map, robots) = (data.join("scenery_warehouse.txt"), data.join("30warehouse"));
    let run = |args: &[&str]| {
        let r = mrpp_in(&dir, args);
        assert_eq!(r.code, Some(0), "{}", r.err);
    };
    let m = map.to_str().unwrap();
    run(&[
        "solve",
        "--map",
        m,
        "--scen",
        robots.to_str().unwrap(),
        "--planner",
        "hstar",
        "--out",
        "plan.json",
    ]);
    run(&[
        "render",
        "--map",
        m,
        "--plan",
        "plan.json",
        "--out",
        "plan.png",
    ]);
    assert!(
        std::fs::read(dir.join("plan.png")).unwrap()
            == std::fs::read(root.join("docs/warehouse-hstar.png")).unwrap(),
        "docs/warehouse-hstar.png is not what the README's commands draw: copy {} there",
        dir.join("plan.png").display()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 12: the 2026 LoRR header said "LoRR 2026 LoRR"; `render --help` said "an SVG picture".
#[test]
fn headers_and_help_say_what_is_done() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let problem = root.join("data/robot-runners/lorr2026-maze/maze-example_40.json");
    let out = std::env::temp_dir().join(format!("mrpp-header-{}.json", std::process::id()));
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_mrpp"))
        .args([
            "solve",
            "--lorr",
            problem.to_str().unwrap(),
            "-P",
            "pibt",
            "-o",
        ])
        .arg(&out)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("| 2026 LoRR one-shot"), "{stdout}");
    assert!(!stdout.contains("LoRR 2026 LoRR"), "{stdout}");
    let _ = std::fs::remove_file(&out);
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_mrpp"))
        .args(["render", "--help"])
        .output()
        .unwrap();
    let help = String::from_utf8_lossy(&o.stdout);
    assert!(
        help.contains("an SVG picture, a PNG, or an animated GIF"),
        "{help}"
    );
}

/// Item 8 (part): a bad `-p` value says what the value must be, not Rust's type name ("not a
/// valid u32/usize").
#[test]
fn bad_parameter_values_say_what_they_must_be() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/movingai");
    let (m, i) = (
        root.join("random-32-32-20.map"),
        root.join("random-32-32-20-random-1.scen"),
    );
    for (planner, param, says) in [
        (
            "pibt",
            "max_steps=-3",
            "max_steps=-3 is not a whole number from 0",
        ),
        (
            "lacam",
            "restart_rate=abc",
            "restart_rate=abc is not a number",
        ),
    ] {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_mrpp"))
            .args([
                "solve",
                "-m",
                m.to_str().unwrap(),
                "-i",
                i.to_str().unwrap(),
            ])
            .args(["-N", "5", "-P", planner, "-p", param, "-o", "-"])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{err}");
        assert!(err.contains(says), "{err}");
        assert!(
            !err.contains("u32") && !err.contains("usize") && !err.contains("f64"),
            "{err}"
        );
    }
}

/// Item 10: summaries give a yardstick (the lower bounds `mrpp info` knows, with the excess over
/// them), numbers a person reads (no 16 digits), and `-v` prints the planner's notes once.
#[test]
fn summaries_state_lower_bounds_and_round_numbers() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data");
    let run = |args: &[&str]| mrpp_in(&std::env::temp_dir(), args).out;
    let lorr = root.join("robot-runners/lorr2026-maze/maze-example_40.json");
    let out = std::env::temp_dir().join(format!("mrpp-summary-{}.json", std::process::id()));
    let o = out.to_str().unwrap();
    let grid = run(&[
        "solve",
        "--lorr",
        lorr.to_str().unwrap(),
        "-P",
        "pibt",
        "-o",
        o,
    ]);
    assert!(
        grid.contains("sum_of_costs 2892 (lower bound 2185, +32.4%)")
            && grid.contains("makespan 121 (lower bound 117, +3.4%)"),
        "{grid}"
    );
    let world = root.join("continuous/six-robots-four-obstacles.json");
    let cont = run(&[
        "solve",
        "--world",
        world.to_str().unwrap(),
        "-P",
        "orca",
        "-o",
        o,
    ]);
    let solved = cont.lines().find(|l| l.starts_with("solved:")).unwrap();
    for number in solved.split(' ').filter_map(|w| w.parse::<f64>().ok()) {
        let decimals = number.to_string().split('.').nth(1).map_or(0, str::len);
        assert!(decimals <= 3, "{solved}");
    }
    let verbose = run(&[
        "solve",
        "-v",
        "--lorr",
        lorr.to_str().unwrap(),
        "-P",
        "lacam",
        "-o",
        o,
    ]);
    assert_eq!(
        verbose.lines().filter(|l| l.starts_with("lacam")).count(),
        1,
        "{verbose}"
    );
    // Planner notes say what they measure: LaCAM's costs are sums of loss (was `first_cost
    // 2431 | final_cost 2431`), H*'s way to its plan is said in words (was `finished_by repair`).
    let lacam = run(&[
        "solve",
        "--lorr",
        lorr.to_str().unwrap(),
        "-P",
        "lacam",
        "-o",
        o,
    ]);
    assert!(
        lacam.contains("first_sum_of_loss ") && !lacam.contains("first_cost"),
        "{lacam}"
    );
    let hstar = run(&[
        "solve",
        "--map",
        root.join("hstar-paper/scenario2/scenery_4rooms_B.txt")
            .to_str()
            .unwrap(),
        "--scen",
        root.join("hstar-paper/scenario2/6robots-per-room.txt")
            .to_str()
            .unwrap(),
        "-P",
        "hstar",
        "-o",
        o,
    ]);
    assert!(
        hstar.contains("hstar: solved_by the paper's steps + mrpp's repair")
            && !hstar.contains("finished_by"),
        "{hstar}"
    );
    let _ = std::fs::remove_file(&out);
}

/// Sends SIGINT (Ctrl-C) to `child` after `secs` seconds and waits for it: `(exit code, stderr)`.
fn interrupt_after(mut child: std::process::Child, secs: f64) -> (Option<i32>, String) {
    std::thread::sleep(std::time::Duration::from_secs_f64(secs));
    std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    let started = std::time::Instant::now();
    let status = child.wait().unwrap();
    assert!(
        started.elapsed().as_secs_f64() < 20.0,
        "Ctrl-C did not stop it"
    );
    let mut err = String::new();
    use std::io::Read as _;
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    (status.code(), err)
}

/// Item 12: Ctrl-C in LaCAM* writes its best plan so far (valid, `status: interrupted`), and an
/// interrupted experiment says how to resume and keeps only jobs that finished before it.
#[test]
fn ctrl_c_keeps_the_best_plan_and_says_how_to_resume() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/movingai");
    let (m, i) = (
        root.join("random-32-32-20.map"),
        root.join("random-32-32-20-random-1.scen"),
    );
    let dir = std::env::temp_dir().join(format!("mrpp-ctrl-c-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let plan = dir.join("plan.json");
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_mrpp"))
        .args([
            "solve",
            "-m",
            m.to_str().unwrap(),
            "-i",
            i.to_str().unwrap(),
            "-N",
            "200",
        ])
        .args(["-P", "lacam", "-p", "anytime=true", "-t", "60", "-o"])
        .arg(&plan)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let (code, err) = interrupt_after(child, 3.0);
    assert_eq!(code, Some(130), "{err}");
    let text = std::fs::read_to_string(&plan).unwrap();
    assert!(text.contains("\"status\": \"interrupted\""), "{text}");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_mrpp"))
        .args(["validate", "-m", m.to_str().unwrap(), "--plan"])
        .arg(&plan)
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    // An experiment: stopped, it names its progress file and how to resume.
    let out = dir.join("exp");
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_mrpp"))
        .args(["experiment", "hstar-table2", "--runs", "3", "-o"])
        .arg(&out)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let (code, err) = interrupt_after(child, 3.0);
    assert_eq!(code, Some(130), "{err}");
    assert!(
        err.contains("run the same command again to resume") && err.contains("progress-1-of-1-"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 11 (part): `render` and `view` of a plan with a teleport still draw it (a broken plan is
/// worth seeing) but say on stderr which rule it breaks; a valid plan draws without a word.
#[test]
fn drawing_an_invalid_plan_says_so() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/movingai");
    let (m, i) = (
        root.join("random-32-32-20.map"),
        root.join("random-32-32-20-random-1.scen"),
    );
    let dir = std::env::temp_dir().join(format!("mrpp-teleport-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let run = |args: &[&str]| {
        let r = mrpp_in(&dir, args);
        (r.code, r.err)
    };
    let map = m.to_str().unwrap();
    let (code, _) = run(&[
        "solve",
        "-m",
        map,
        "-i",
        i.to_str().unwrap(),
        "-N",
        "5",
        "-P",
        "pibt",
        "-o",
        "ok.json",
    ]);
    assert_eq!(code, Some(0));
    let mut plan: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("ok.json")).unwrap()).unwrap();
    let step = &mut plan["agents"][0]["path"][2];
    step[0] = serde_json::json!(step[0].as_i64().unwrap() + 5);
    plan["metrics"] = serde_json::json!({});
    std::fs::write(dir.join("teleport.json"), plan.to_string()).unwrap();
    for (verb, out) in [("render", "t.svg"), ("view", "t.html")] {
        let (code, err) = run(&[verb, "-m", map, "--plan", "teleport.json", "-o", out]);
        assert_eq!(code, Some(0), "{err}");
        assert!(
            err.contains("warning: this plan is not valid") && err.contains("agent 0 jumps"),
            "{verb}: {err}"
        );
        assert!(dir.join(out).exists());
        let (_, err) = run(&[verb, "-m", map, "--plan", "ok.json", "-o", out]);
        assert!(err.is_empty(), "{verb}: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 3: no planner is silent. With `--progress plain` (what a terminal shows as a spinner or
/// bar) every planner of every family prints a progress line every half second: a run that
/// lasts longer than 1.2 s has printed one by then, and the planner itself has reported what it
/// is doing (`ctx.report`: stage, iteration, best cost).
#[test]
fn every_planner_shows_progress_within_a_second() {
    let data = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data");
    let d = |rel: &str| data.join(rel).to_string_lossy().into_owned();
    let (map, scen) = (
        d("movingai/random-32-32-20.map"),
        d("movingai/random-32-32-20-random-1.scen"),
    );
    let grid = ["-m", map.as_str(), "-i", scen.as_str(), "-N", "300"];
    let (trees, formation, world) = (
        d("trees/example.json"),
        d("formation/var_density2-8.json"),
        d("continuous/circle-16.json"),
    );
    let mut silent = Vec::new();
    let mut checked = 0;
    for (planners, inputs) in [
        (
            &[
                "hstar",
                "ca",
                "hca",
                "whca",
                "coevolution",
                "nsga3",
                "pibt",
                "lacam",
                "cbs",
                "eecbs",
            ][..],
            &grid[..],
        ),
        (&["psw", "gp"][..], &["--instance", trees.as_str()][..]),
        (
            &["sequential", "ga", "exact"][..],
            &["--formation", formation.as_str()][..],
        ),
        (
            &["hbmo", "de", "pso", "orca"][..],
            &["--world", world.as_str()][..],
        ),
    ] {
        for planner in planners {
            let started = std::time::Instant::now();
            let o = std::process::Command::new(env!("CARGO_BIN_EXE_mrpp"))
                .args([
                    "--progress",
                    "plain",
                    "solve",
                    "-P",
                    planner,
                    "-t",
                    "1.5",
                    "-o",
                    "/dev/null",
                ])
                .args(inputs)
                .output()
                .unwrap();
            let secs = started.elapsed().as_secs_f64();
            let err = String::from_utf8_lossy(&o.stderr);
            if secs > 1.2 {
                checked += 1;
                // The CLI's own half-second line, and at least one line with what the planner
                // itself reported (its stage, iteration or best cost after the colon).
                if !err.contains(&format!("[0.5 s] {planner}"))
                    || !err.contains(&format!("] {planner}: "))
                {
                    silent.push(format!("{planner} ({secs:.1} s): {err}"));
                }
            }
        }
    }
    assert!(silent.is_empty(), "silent: {silent:?}");
    assert!(
        checked >= 3,
        "too few planners ran long enough to check ({checked})"
    );
}

/// Item 8 (part): a file of the wrong kind is named as such: a grid map given to `gen formation`
/// ("`type` is not a number" before), a JSON file given to `bench run --config` ("invalid
/// key-value pair" before).
#[test]
fn a_file_of_the_wrong_kind_is_named_as_such() {
    let data = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data");
    let dir = std::env::temp_dir().join(format!("mrpp-wrong-kind-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let json = dir.join("sweep.json");
    std::fs::write(&json, "{\"name\": \"x\"}\n").unwrap();
    let map = data.join("movingai/random-32-32-20.map");
    for (args, says) in [
        (
            vec![
                "gen",
                "formation",
                "--map",
                map.to_str().unwrap(),
                "--robots",
                "2",
                "-s",
                "0",
                "-o",
                "f.json",
            ],
            "this is a MovingAI grid map; formations need a polygon map",
        ),
        (
            vec![
                "bench",
                "run",
                "--config",
                json.to_str().unwrap(),
                "-o",
                "out",
            ],
            "this is JSON; a bench config is TOML",
        ),
    ] {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_mrpp"))
            .args(&args)
            .current_dir(&dir)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{err}");
        assert!(err.contains(says), "{args:?}: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 12 (part): `mrpp info` answers for a map alone (was "grid problems need --scen") and for
/// a tree instance (was "`mrpp info` is not available for trees problems yet").
#[test]
fn info_describes_a_map_alone_and_a_tree_instance() {
    let data = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data");
    let d = |rel: &str| data.join(rel).to_string_lossy().into_owned();
    let map = mrpp_in(
        &std::env::temp_dir(),
        &["info", "--map", &d("movingai/random-32-32-20.map")],
    );
    assert_eq!(map.code, Some(0), "{}", map.err);
    assert!(
        map.out
            .contains("32x32 | free cells 819 | largest connected area 819 cells (100%)"),
        "{}",
        map.out
    );
    let tree = mrpp_in(
        &std::env::temp_dir(),
        &["info", "--instance", &d("trees/example.json")],
    );
    assert_eq!(tree.code, Some(0), "{}", tree.err);
    assert!(
        tree.out.contains("nodes 37 | leaves 19") && tree.out.contains("robots 18"),
        "{}",
        tree.out
    );
    // The lower bounds are those of each robot alone: the plan's own costs meet them.
    let plan = std::env::temp_dir().join(format!("mrpp-info-tree-{}.json", std::process::id()));
    let solved = mrpp_in(
        &std::env::temp_dir(),
        &[
            "solve",
            "--instance",
            &d("trees/example.json"),
            "-P",
            "psw",
            "-o",
            plan.to_str().unwrap(),
        ],
    );
    let bound = |text: &str, key: &str| -> u64 {
        let at = text.find(key).unwrap_or_else(|| panic!("{key} in {text}")) + key.len();
        text[at..]
            .trim_start_matches([' ', '>', '='])
            .split(|c: char| !c.is_ascii_digit())
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    assert!(
        bound(&solved.out, "sum_of_costs") >= bound(&tree.out, "sum_of_costs")
            && bound(&solved.out, "makespan") >= bound(&tree.out, "makespan"),
        "{}\n{}",
        solved.out,
        tree.out
    );
    let _ = std::fs::remove_file(&plan);
}

/// Item 11 (part): a grid plan file that says `solved: false` can be looked at: `render` and
/// `view` draw its starts and goals and say that it holds no plan (was: exit 1 "it holds no plan
/// (nothing to check or draw)"); `validate` still refuses it.
#[test]
fn an_unsolved_grid_plan_file_shows_its_starts_and_goals() {
    let data = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data");
    let d = |rel: &str| data.join(rel).to_string_lossy().into_owned();
    let dir = std::env::temp_dir().join(format!("mrpp-unsolved-{}", std::process::id()));
    let (map, scen) = (
        d("movingai/random-32-32-20.map"),
        d("movingai/random-32-32-20-random-1.scen"),
    );
    common::unsolved_plan_file_is_drawn(
        &dir,
        &["--map", map.as_str(), "--scen", scen.as_str(), "-N", "10"],
        "pibt",
        |verb, err, _| assert!(err.contains("only the starts and goals"), "{verb}: {err}"),
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 11 for trees: a tree plan file that says solved=false shows its starts and goals too
/// (before: `mrpp render --instance data/trees/example.json --plan unsolved.json` exited 1, "the
/// file says solved=false: it holds no plan").
#[test]
fn an_unsolved_tree_plan_file_shows_its_starts_and_goals() {
    let data = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data");
    let dir = std::env::temp_dir().join(format!("mrpp-unsolved-tree-{}", std::process::id()));
    let instance = data.join("trees/example.json");
    common::unsolved_plan_file_is_drawn(
        &dir,
        &["--instance", instance.to_str().unwrap()],
        "psw",
        |_, _, _| {},
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 8 (part): a plan file with a value of the wrong type names the key path of that value,
/// not serde's "at line 1 column 496".
#[test]
fn a_malformed_plan_file_names_the_key_path() {
    let data = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data");
    let dir = std::env::temp_dir().join(format!("mrpp-key-path-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let map = data.join("movingai/random-32-32-20.map");
    let scen = data.join("movingai/random-32-32-20-random-1.scen");
    let (map, scen) = (map.to_str().unwrap(), scen.to_str().unwrap());
    let r = mrpp_in(
        &dir,
        &[
            "solve", "-m", map, "-i", scen, "-N", "5", "-P", "lacam", "-o", "p.json",
        ],
    );
    assert_eq!(r.code, Some(0), "{}", r.err);
    let mut plan: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("p.json")).unwrap()).unwrap();
    plan["agents"][3]["path"][2][0] = serde_json::json!("a");
    std::fs::write(dir.join("bad.json"), plan.to_string()).unwrap();
    let r = mrpp_in(&dir, &["validate", "-m", map, "--plan", "bad.json"]);
    assert_eq!(r.code, Some(1));
    assert!(
        r.err
            .contains("`agents[3].path[2][0]`: invalid type: string \"a\", expected i64"),
        "{}",
        r.err
    );
    assert!(!r.err.contains("column"), "{}", r.err);
    let _ = std::fs::remove_dir_all(&dir);
}
