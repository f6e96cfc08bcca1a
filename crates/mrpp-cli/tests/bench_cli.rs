//! The harness from the command line: sharded runs merged with `mrpp bench merge` equal the
//! unsharded run (apart from wall-clock columns), for a paper table and for a TOML sweep; bad
//! configs are one-line errors naming the file and line.

mod common;

use common::{mrpp_exits, root};
use std::path::{Path, PathBuf};

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("mrpp-bench-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A CSV file without its wall-clock and memory columns (they depend on the machine and on what
/// ran before in the process).
fn without_timing(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let keep: Vec<usize> = (0..header.len())
        .filter(|&i| {
            ![
                "runtime_ms",
                "gp_seconds",
                "seconds",
                "first_solution_ms",
                "peak_memory_mb",
            ]
            .contains(&header[i])
        })
        .collect();
    text.lines()
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            keep.iter()
                .map(|&i| f.get(i).copied().unwrap_or(""))
                .collect::<Vec<_>>()
                .join(",")
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The value of column `name` (by `records.csv`'s header, the first line of `records`) in `row`.
fn field<'a>(records: &str, row: &'a str, name: &str) -> &'a str {
    let header = records.lines().next().unwrap_or_default();
    let at = header
        .split(',')
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name} in {header}"));
    row.split(',')
        .nth(at)
        .unwrap_or_else(|| panic!("no {name} in {row}"))
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn sharded_paper_table_merges_to_the_whole() {
    let dir = tmp("gp3");
    let (parts, whole, merged) = (dir.join("parts"), dir.join("whole"), dir.join("merged"));
    let base = [
        "experiment",
        "gp-table3",
        "--problems",
        "5",
        "--seed",
        "4",
        "--population",
        "40",
        "--generations",
        "3",
        "--runs",
        "1",
    ];
    for shard in ["1/3", "2/3", "3/3"] {
        let mut a = base.to_vec();
        a.extend(["--shard", shard, "--out", s(&parts)]);
        mrpp_exits(&a, 0);
    }
    let mut a = base.to_vec();
    a.extend(["--out", s(&whole)]);
    mrpp_exits(&a, 0);
    let (out, _) = mrpp_exits(&["bench", "merge", "--out", s(&merged), s(&parts)], 0);
    assert!(out.contains("merged 5 jobs"), "{out}");
    for f in ["results.csv", "records.csv"] {
        assert_eq!(
            without_timing(&whole.join(f)),
            without_timing(&merged.join(f)),
            "{f}"
        );
    }
    let manifest = std::fs::read_to_string(merged.join("manifest.json")).unwrap();
    assert!(
        manifest.contains("merged from 3 parts") && manifest.contains("gp-table3"),
        "{manifest}"
    );
    // A folder without parts beside the good one is refused, naming it (issue 30, item 12),
    // and so is merging into one of the parts' folders (issue 27: they are inputs).
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let again = dir.join("again");
    let (_, err) = mrpp_exits(
        &["bench", "merge", "--out", s(&again), s(&parts), s(&empty)],
        1,
    );
    assert!(
        err.contains("empty: no part-i-of-N.jsonl files in this folder"),
        "{err}"
    );
    let (_, err) = mrpp_exits(&["bench", "merge", "--out", s(&parts), s(&parts)], 1);
    assert!(err.contains("input folder"), "{err}");
    // A missing shard is named, and nothing is written.
    std::fs::remove_file(parts.join("part-2-of-3.jsonl")).unwrap();
    let again = dir.join("again");
    let (_, err) = mrpp_exits(&["bench", "merge", "--out", s(&again), s(&parts)], 1);
    assert!(err.contains("jobs are in no part"), "{err}");
    assert!(!again.join("results.csv").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn toml_sweep_shards_merge_and_bad_configs_are_named() {
    let dir = tmp("toml");
    let config = "bench/configs/example.toml";
    let (parts, whole, merged) = (dir.join("parts"), dir.join("whole"), dir.join("merged"));
    mrpp_exits(&["bench", "run", "--config", config, "--out", s(&whole)], 0);
    for shard in ["1/2", "2/2"] {
        mrpp_exits(
            &[
                "bench",
                "run",
                "--config",
                config,
                "--shard",
                shard,
                "--out",
                s(&parts),
            ],
            0,
        );
    }
    mrpp_exits(&["bench", "merge", "--out", s(&merged), s(&parts)], 0);
    let records = without_timing(&merged.join("records.csv"));
    assert_eq!(without_timing(&whole.join("records.csv")), records);
    assert_eq!(records.lines().count(), 1 + 3 * 3 * 2, "{records}");
    assert!(
        records.lines().skip(1).all(|l| l.contains(",solved,")),
        "{records}"
    );
    let bad = dir.join("bad.toml");
    std::fs::write(
        &bad,
        "name = \"x\"\n\n[[planners]]\nname = \"hstar\"\nwidow = 3\n",
    )
    .unwrap();
    let (_, err) = mrpp_exits(
        &[
            "bench",
            "run",
            "--config",
            s(&bad),
            "--out",
            s(&dir.join("o")),
        ],
        1,
    );
    assert!(err.contains("bad.toml:") && err.contains("widow"), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_peer_command_joins_the_sweep_and_an_interrupted_run_resumes() {
    let dir = tmp("peer");
    let out = dir.join("out");
    // The peer is mrpp itself behind its LaCAM text output, run as an external command.
    let peer = format!(
        "mrpp-pibt={} solve --map {{map}} --scen {{scen}} --agents {{agents}} --planner pibt -p swap=true --seed {{seed}} --time-limit {{time_limit}} --format lacam --out {{out}}",
        env!("CARGO_BIN_EXE_mrpp")
    );
    let args = [
        "bench",
        "run",
        "--map",
        "data/movingai/random-32-32-20.map",
        "--scen",
        "data/movingai/random-32-32-20-random-1.scen",
        "--agents",
        "20,40",
        "--planners",
        "lacam",
        "--runs",
        "2",
        "--time-limit",
        "5",
        "--jobs",
        "1",
        "--peer",
        &peer,
        "--out",
        s(&out),
    ];
    mrpp_exits(&args, 0);
    let records = std::fs::read_to_string(out.join("records.csv")).unwrap();
    assert_eq!(records.lines().count(), 1 + 2 * 2 * 2, "{records}");
    let peer_rows: Vec<&str> = records
        .lines()
        .filter(|l| l.contains(",mrpp-pibt,peer,"))
        .collect();
    assert_eq!(peer_rows.len(), 4, "{records}");
    assert!(
        peer_rows.iter().all(|l| l.contains(",solved,")),
        "{records}"
    );
    // Issue 31's quality columns, on every solved run of both solvers: the sum of loss between
    // the lower bound and the sum of costs, the ratios, the first plan within the run, memory.
    let col = |row: &str, name: &str| -> f64 {
        field(&records, row, name)
            .parse()
            .unwrap_or_else(|_| panic!("{name} in {row}"))
    };
    for row in records.lines().skip(1) {
        let (soc, loss, lb) = (
            col(row, "sum_of_costs"),
            col(row, "sum_of_loss"),
            col(row, "lower_bound"),
        );
        assert!(0.0 < lb && lb <= loss && loss <= soc, "{row}");
        assert!(
            col(row, "makespan_lower_bound") <= col(row, "makespan"),
            "{row}"
        );
        assert!(
            (col(row, "sum_of_costs_ratio") - soc / lb).abs() < 1e-9,
            "{row}"
        );
        assert!(
            (col(row, "sum_of_loss_ratio") - loss / lb).abs() < 1e-9,
            "{row}"
        );
        assert!(
            col(row, "first_solution_ms") <= col(row, "runtime_ms") + 1e-6,
            "{row}"
        );
        assert!(col(row, "peak_memory_mb") > 0.0, "{row}");
    }
    let summary = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(
        summary.contains("| random-32-32-20 | 40 | mrpp-pibt | 100 |"),
        "{summary}"
    );
    // Both solvers solve all four runs: each solved 4/4, and the speed comparison is over the
    // two instances both solved.
    for solver in ["lacam", "mrpp-pibt"] {
        assert!(
            summary.contains(&format!("| {solver} | 4/4 | 100.0 |")),
            "{summary}"
        );
    }
    assert!(
        summary.contains("the 2 instances every solver solved"),
        "{summary}"
    );
    for f in ["success.svg", "runtime.svg", "solved_over_time.svg"] {
        assert!(
            std::fs::read_to_string(out.join(f))
                .unwrap()
                .starts_with("<svg"),
            "{f}"
        );
    }
    assert_eq!(common::every_svg_rasterises(&out), 3);
    // Interrupted after three jobs, in the middle of the fourth line: the rerun runs only the
    // other five, and a second rerun finds all eight.
    let progress = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| {
            p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with("progress-1-of-1-")
        })
        .expect("a progress file");
    let lines: Vec<String> = std::fs::read_to_string(&progress)
        .unwrap()
        .lines()
        .map(String::from)
        .collect();
    let mut kept: String = lines[..3].iter().map(|l| format!("{l}\n")).collect();
    kept.push_str(&lines[3][..10]);
    std::fs::write(&progress, kept).unwrap();
    std::fs::remove_file(out.join("records.csv")).unwrap();
    let (stdout, _) = mrpp_exits(&args, 0);
    assert!(
        stdout.contains("resuming: 3 of 8 jobs already done"),
        "{stdout}"
    );
    let (stdout, _) = mrpp_exits(&args, 0);
    assert!(
        stdout.contains("resuming: 8 of 8 jobs already done"),
        "{stdout}"
    );
    assert_eq!(
        without_timing(&out.join("records.csv")).lines().count(),
        records.lines().count()
    );
    // A bad template is named before anything runs.
    let (_, err) = mrpp_exits(
        &[
            "bench",
            "run",
            "--map",
            "data/movingai/empty-8-8.map",
            "--scen",
            "data/movingai/empty-8-8-random-1.scen",
            "--planners",
            "lacam",
            "--peer",
            "x=echo {mapp} {out}",
            "--out",
            s(&dir.join("o")),
        ],
        1,
    );
    assert!(err.contains("unknown placeholder `{mapp}`"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 30, item 1: a peer command that cannot run is not a peer that solved nothing. Each
/// failed run warns on the terminal and is recorded as `peer_failed` with its exit status and
/// stderr; after three in a row the sweep stops with exit 1 naming the command. A peer that
/// exits non-zero after writing a result is a failure too.
#[test]
fn a_broken_peer_command_warns_is_recorded_and_stops_the_sweep() {
    let dir = tmp("broken-peer");
    let out = dir.join("out");
    let run = |peer: &str, code: i32| {
        mrpp_exits(
            &[
                "bench",
                "run",
                "--map",
                "data/movingai/random-32-32-20.map",
                "--scen",
                "data/movingai/random-32-32-20-random-1.scen",
                "--agents",
                "5",
                "--planners",
                "pibt",
                "--runs",
                "3",
                "--time-limit",
                "2",
                "--jobs",
                "1",
                "--peer",
                peer,
                "--out",
                s(&out),
            ],
            code,
        )
    };
    let (_, err) = run("typo=/nonexistent/lacam0 -m {map} -o {out}", 1);
    assert_eq!(
        err.matches("warning: peer `typo` failed").count(),
        2,
        "{err}"
    );
    assert!(
        err.contains("exit 127") && err.contains("not found"),
        "{err}"
    );
    assert!(
        err.contains("peer `typo` failed 3 runs in a row")
            && err.contains("check its command: /nonexistent/lacam0"),
        "{err}"
    );
    // A command that runs but fails says why (its exit status and stderr), and the failed runs
    // are in the progress file as `peer_failed` with that reason.
    let _ = std::fs::remove_dir_all(&out);
    let (_, err) = run("flaky=sh -c 'echo broken pipe >&2; exit 3' {out}", 1);
    assert!(err.contains("exit 3: broken pipe"), "{err}");
    let progress = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| std::fs::read_to_string(e.unwrap().path()).unwrap_or_default())
        .find(|t| t.contains("peer_failed"))
        .expect("the failed runs are recorded");
    assert!(progress.contains("exit 3: broken pipe"), "{progress}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The 13,900-instance MovingAI protocol (bench/configs/movingai-full.toml) counts its jobs
/// without the data (`--dry-run`), and its shards cover every job exactly once; with a map
/// missing, a real run is a one-line error naming the file, not a panic.
#[test]
fn movingai_full_counts_13900_jobs_without_the_data() {
    let config = "bench/configs/movingai-full.toml";
    let (out, _) = mrpp_exits(&["bench", "run", "--config", config, "--dry-run"], 0);
    assert!(out.contains("13900 jobs (825 instance specs"), "{out}");
    let mut total = 0;
    for i in 1..=7 {
        let shard = format!("{i}/7");
        let (out, _) = mrpp_exits(
            &[
                "bench",
                "run",
                "--config",
                config,
                "--dry-run",
                "--shard",
                &shard,
            ],
            0,
        );
        let owned: usize = out
            .split(&format!("shard {shard}: "))
            .nth(1)
            .and_then(|r| r.split_whitespace().next())
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("{out}"));
        assert!((1985..=1986).contains(&owned), "{out}");
        total += owned;
    }
    assert_eq!(total, 13900);
    // The slice is the full protocol's random-1 scenario: 556 of the 13,900 (one in 25).
    let (out, _) = mrpp_exits(
        &[
            "bench",
            "run",
            "--config",
            "bench/configs/movingai-slice.toml",
            "--dry-run",
        ],
        0,
    );
    assert!(out.contains("556 jobs (33 instance specs"), "{out}");
    // The LaCAM* quality comparison: 14 instances, one planner (its peers come as flags).
    let (out, _) = mrpp_exits(
        &[
            "bench",
            "run",
            "--config",
            "bench/configs/lacam-star-quality.toml",
            "--dry-run",
        ],
        0,
    );
    assert!(out.contains("14 jobs (8 instance specs"), "{out}");

    // A config naming files that are not there: --dry-run says so, a run fails naming one.
    let dir = tmp("full-missing");
    let cfg = dir.join("missing.toml");
    std::fs::write(
        &cfg,
        "[[instances]]\nmap = \"nowhere.map\"\nscen = \"nowhere-random-{k}.scen\"\nscens = \"1..=2\"\nagents = \"10..=20 step 10\"\n[[planners]]\nname = \"lacam\"\n",
    )
    .unwrap();
    let (out, _) = mrpp_exits(&["bench", "run", "--config", s(&cfg), "--dry-run"], 0);
    assert!(
        out.contains("4 jobs") && out.contains("3 of the 3"),
        "{out}"
    );
    let (_, err) = mrpp_exits(
        &[
            "bench",
            "run",
            "--config",
            s(&cfg),
            "--out",
            s(&dir.join("o")),
        ],
        1,
    );
    assert!(
        err.contains("nowhere.map") && !err.contains("panicked"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A config with scenario numbers (`scens`) and an agent range runs and its shards merge to the
/// whole, on the bundled files.
#[test]
fn scens_and_agent_ranges_shard_and_merge() {
    let dir = tmp("scens");
    let cfg = dir.join("c.toml");
    let data = root().join("data/movingai");
    std::fs::write(
        &cfg,
        format!(
            "time_limit = 5.0\n[[instances]]\nmap = \"{0}/empty-8-8.map\"\nscen = \"{0}/empty-8-8-random-{{k}}.scen\"\nscens = \"1..=2\"\nagents = \"4..=8 step 4\"\n[[planners]]\nname = \"lacam\"\n",
            data.display()
        ),
    )
    .unwrap();
    let (parts, whole, merged) = (dir.join("parts"), dir.join("whole"), dir.join("merged"));
    mrpp_exits(
        &["bench", "run", "--config", s(&cfg), "--out", s(&whole)],
        0,
    );
    for shard in ["1/3", "2/3", "3/3"] {
        mrpp_exits(
            &[
                "bench",
                "run",
                "--config",
                s(&cfg),
                "--shard",
                shard,
                "--out",
                s(&parts),
            ],
            0,
        );
    }
    mrpp_exits(&["bench", "merge", "--out", s(&merged), s(&parts)], 0);
    let records = without_timing(&merged.join("records.csv"));
    assert_eq!(without_timing(&whole.join("records.csv")), records);
    assert_eq!(records.lines().count(), 1 + 2 * 2, "{records}");
    assert!(records.contains("empty-8-8-random-2"), "{records}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `tools/check/bench_plans.py` solves a config's instances again with plans saved and has the
/// independent checker accept each (with mrpp's sum of costs, sum of loss and lower bounds, the
/// bounds `mrpp bench` records): two scenarios x two agent counts of the bundled
/// random-32-32-20.
#[test]
fn every_plan_of_a_config_passes_the_independent_checker() {
    let dir = tmp("bench-plans");
    let cfg = dir.join("mini.toml");
    let data = root().join("data/movingai");
    std::fs::write(
        &cfg,
        format!(
            "time_limit = 5.0\n[[planners]]\nname = \"lacam\"\n[[instances]]\nmap = \"{0}/random-32-32-20.map\"\nscen = \"{0}/random-32-32-20-random-{{k}}.scen\"\nscens = \"1..=2\"\nagents = \"20..=40 step 20\"\n",
            data.display()
        ),
    )
    .unwrap();
    let o = std::process::Command::new("python3")
        .arg(root().join("tools/check/bench_plans.py"))
        .args([
            s(&cfg),
            "--out",
            s(&dir.join("plans")),
            "--jobs",
            "2",
            "--bounds",
        ])
        .args(["--mrpp", env!("CARGO_BIN_EXE_mrpp")])
        .output()
        .expect("python3 is required for the independent checker");
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{out}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(
        out.contains("4 instances: 4 plans accepted by grid.py, 0 rejected, 0 unsolved"),
        "{out}"
    );
    assert!(
        out.contains("sum of loss compared with mrpp's on 4 "),
        "{out}"
    );
    // Each accepted line ends with the checker's JSON, bounds and sum of loss included.
    assert_eq!(
        out.matches("\"makespan_lower_bound\": ").count(),
        4,
        "{out}"
    );
    assert_eq!(out.matches("\"sum_of_loss\": ").count(), 4, "{out}");
    assert_eq!(
        std::fs::read_dir(dir.join("plans")).unwrap().count(),
        4,
        "{out}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// LaCAM* with `threads=2` runs its LNS workers on threads of its own: inside `mrpp bench
/// --jobs 1` (every job on one rayon worker) a run neither starts the next job inside itself
/// nor outlives its time limit by more than a moment. (A rayon pool of its own did both: the
/// waiting worker ran the next job meanwhile, and a 30 s run took up to 266 s.)
#[test]
fn lacam_star_with_two_threads_keeps_to_its_time_limit_in_a_sweep() {
    let dir = tmp("bench-threads");
    let cfg = dir.join("t.toml");
    let data = root().join("data/movingai");
    std::fs::write(
        &cfg,
        format!(
            "time_limit = 1.0\n[[planners]]\nname = \"lacam\"\nparams = {{ anytime = \"true\", threads = \"2\" }}\n[[instances]]\nmap = \"{0}/random-32-32-20.map\"\nscen = \"{0}/random-32-32-20-random-{{k}}.scen\"\nscens = \"1..=3\"\nagents = [200]\n",
            data.display()
        ),
    )
    .unwrap();
    let out = dir.join("out");
    mrpp_exits(
        &[
            "bench",
            "run",
            "--config",
            s(&cfg),
            "--jobs",
            "1",
            "--progress",
            "none",
            "--out",
            s(&out),
        ],
        0,
    );
    let records = std::fs::read_to_string(out.join("records.csv")).unwrap();
    let rows: Vec<&str> = records.lines().skip(1).collect();
    assert_eq!(rows.len(), 3, "{records}");
    for row in rows {
        assert!(row.contains(",solved,"), "{row}");
        let ms: f64 = field(&records, row, "runtime_ms").parse().unwrap();
        // One second of search, and a generous allowance for a loaded machine; a nested run
        // would add at least another second.
        assert!(ms < 1_900.0, "{ms} ms: {row}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `peer_timeout` kills a peer that outlives it (recorded as `time_limit`, after about that many
/// seconds rather than the default of twice the time limit plus 10 s), and one below the time
/// limit is a one-line error naming the key.
#[test]
fn a_peer_is_killed_after_peer_timeout() {
    let dir = tmp("peer-timeout");
    let root = root();
    let config = |timeout: f64| {
        format!(
            "time_limit = 0.5\npeer_timeout = {timeout}\n[[instances]]\nmap = \"{0}/data/movingai/random-32-32-20.map\"\nscen = \"{0}/data/movingai/random-32-32-20-random-1.scen\"\nagents = [5]\n[[peers]]\nname = \"slow\"\ncommand = \"sleep 60; echo solved=1 > {{out}}\"\n",
            root.display()
        )
    };
    let path = dir.join("c.toml");
    std::fs::write(&path, config(1.0)).unwrap();
    let out = dir.join("out");
    mrpp_exits(
        &[
            "bench",
            "run",
            "--config",
            s(&path),
            "--jobs",
            "1",
            "--out",
            s(&out),
        ],
        0,
    );
    let records = std::fs::read_to_string(out.join("records.csv")).unwrap();
    let row = records.lines().nth(1).expect("one record");
    assert_eq!(field(&records, row, "status"), "time_limit", "{records}");
    let ms: f64 = field(&records, row, "runtime_ms").parse().unwrap();
    assert!((1000.0..11_000.0).contains(&ms), "killed after {ms} ms");
    std::fs::write(&path, config(0.25)).unwrap();
    let (_, err) = mrpp_exits(
        &[
            "bench",
            "run",
            "--config",
            s(&path),
            "--out",
            s(&dir.join("o")),
        ],
        1,
    );
    assert!(
        err.contains("peer_timeout") && err.contains("0.25"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
