//! Lifelong runs on the bundled League of Robot Runners examples: every planner and scheduler,
//! both action models, validated by `solve`, written as LoRR's output JSON and read back.

use std::path::{Path, PathBuf};
use std::time::Duration;

use mrpp_core::{Ctx, Problem, solve};
use mrpp_lifelong::lorr_output::{from_json, to_json};
use mrpp_lifelong::{ActionModel, LifelongProblem, PLANNERS};

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/robot-runners")
        .join(rel)
}

const EXAMPLES: [&str; 2] = [
    "lorr2023-warehouse_small/warehouse_small_10.json",
    "lorr2026-maze/maze-example_40.json",
];

#[test]
fn every_planner_finishes_tasks_and_its_output_reads_back() {
    for example in EXAMPLES {
        for model in [ActionModel::MapfT, ActionModel::Mapf] {
            let problem =
                LifelongProblem::load(&data(example), model, 200, Duration::from_secs(1)).unwrap();
            for entry in PLANNERS {
                for (scheduler, guidance, distances, window) in [
                    ("greedy", "none", "hops", "0"),
                    ("hungarian", "none", "hops", "0"),
                    ("greedy", "traffic-flow", "hops", "0"),
                    ("hungarian", "traffic-flow", "hops", "0"),
                    ("greedy", "none", "turns", "0"),
                    ("hungarian", "none", "turns", "0"),
                    ("hungarian", "traffic-flow", "hops", "8"),
                    ("greedy", "none", "turns", "5"),
                    ("matching", "traffic-flow", "hops", "0"),
                    ("matching", "none", "turns", "6"),
                ] {
                    let what = format!(
                        "{example}, {}, {}, {scheduler}, {guidance}, {distances}, window {window}",
                        model.name(),
                        entry.name
                    );
                    let planner = entry
                        .instantiate(&[
                            ("scheduler".into(), scheduler.into()),
                            ("guidance".into(), guidance.into()),
                            ("distances".into(), distances.into()),
                            ("window".into(), window.into()),
                            ("lns_iterations".into(), "200".into()),
                        ])
                        .unwrap();
                    let ctx = Ctx {
                        seed: 7,
                        ..Ctx::default()
                    };
                    let solved = solve(planner.as_ref(), &problem, &ctx)
                        .unwrap_or_else(|e| panic!("{what}: {e}"));
                    let m = solved.metrics;
                    assert_eq!(m.steps, 200, "{what}");
                    assert!(m.tasks_finished > 0, "{what}: no task finished");
                    assert_eq!(m.planner_errors, 0, "{what}");
                    assert_eq!(m.schedule_errors, 0, "{what}");
                    let json = to_json(&problem, &solved.plan).unwrap();
                    assert_eq!(json["numTaskFinished"], m.tasks_finished, "{what}");
                    let (back, claims) =
                        from_json(&problem, &json.to_string(), Path::new("out.json")).unwrap();
                    assert_eq!(claims.model, model);
                    assert_eq!(back.actions, solved.plan.actions, "{what}");
                    assert_eq!(back.schedule, solved.plan.schedule, "{what}");
                    let again = problem.validate(&back).unwrap();
                    assert_eq!(again.tasks_finished, m.tasks_finished, "{what}");
                    eprintln!("{what}: {} tasks, {} errands", m.tasks_finished, m.errands);
                }
            }
        }
    }
}

/// Windowed LNS (`-p window=W`) against one PIBT step per call, same seed and scheduler, on
/// the bundled maze (40 robots) under both action models: LNS never finishes fewer tasks.
#[test]
fn windowed_lns_finishes_at_least_as_many_tasks_as_pibt() {
    for model in [ActionModel::MapfT, ActionModel::Mapf] {
        let problem =
            LifelongProblem::load(&data(EXAMPLES[1]), model, 300, Duration::from_secs(1)).unwrap();
        let tasks = |window: &str| {
            let planner = PLANNERS[0]
                .instantiate(&[
                    ("scheduler".into(), "hungarian".into()),
                    ("window".into(), window.into()),
                    ("lns_iterations".into(), "500".into()),
                ])
                .unwrap();
            let ctx = Ctx {
                seed: 1,
                ..Ctx::default()
            };
            solve(planner.as_ref(), &problem, &ctx)
                .unwrap()
                .metrics
                .tasks_finished
        };
        let (pibt, lns) = (tasks("0"), tasks("10"));
        eprintln!("{}: PIBT {pibt}, windowed LNS {lns}", model.name());
        assert!(lns >= pibt, "{}: LNS {lns} < PIBT {pibt}", model.name());
    }
}

#[test]
fn a_run_is_reproducible_from_its_seed() {
    let problem = LifelongProblem::load(
        &data(EXAMPLES[1]),
        ActionModel::MapfT,
        100,
        Duration::from_secs(1),
    )
    .unwrap();
    for window in ["0", "6"] {
        let planner = PLANNERS[0]
            .instantiate(&[
                ("guidance".into(), "traffic-flow".into()),
                ("window".into(), window.into()),
                ("lns_iterations".into(), "100".into()),
            ])
            .unwrap();
        let run = |seed| {
            let ctx = Ctx {
                seed,
                ..Ctx::default()
            };
            solve(planner.as_ref(), &problem, &ctx)
                .unwrap()
                .plan
                .actions
        };
        assert_eq!(run(3), run(3));
    }
}

/// `lifelong-lns` above `lns_max_density` is `lifelong-pibt` (one PIBT step per call), step for
/// step; below it, it plans its window (so the test can fail).
#[test]
fn windowed_lns_steps_aside_above_its_density_limit() {
    let problem = LifelongProblem::load(
        &data(EXAMPLES[1]),
        ActionModel::MapfT,
        100,
        Duration::from_secs(1),
    )
    .unwrap();
    let run = |entry: usize, density: Option<&str>| {
        let mut params = vec![
            ("scheduler".to_string(), "hungarian".to_string()),
            ("lns_iterations".to_string(), "100".to_string()),
        ];
        if let Some(d) = density {
            params.push(("lns_max_density".into(), d.into()));
        } else {
            params.pop();
        }
        let planner = PLANNERS[entry].instantiate(&params).unwrap();
        let ctx = Ctx {
            seed: 4,
            ..Ctx::default()
        };
        solve(planner.as_ref(), &problem, &ctx)
            .unwrap()
            .plan
            .actions
    };
    assert_eq!(PLANNERS[1].name, "lifelong-lns");
    let pibt = run(0, None);
    assert_eq!(run(1, Some("0")), pibt);
    assert_ne!(run(1, Some("1")), pibt);
}

/// `distance_tables=manhattan` (no tables, walls ignored; the start kit's choice on large maps)
/// gives valid runs that finish tasks with both planners on the walled maze; `auto` keeps exact
/// tables there (40 robots on a small map), step for step, and Manhattan distances change the
/// plan (so the test can fail).
#[test]
fn manhattan_distances_give_valid_runs_and_auto_keeps_exact_tables_where_they_fit() {
    let problem = LifelongProblem::load(
        &data(EXAMPLES[1]),
        ActionModel::MapfT,
        150,
        Duration::from_secs(1),
    )
    .unwrap();
    for entry in PLANNERS {
        let run = |tables: &str| {
            let planner = entry
                .instantiate(&[
                    ("distance_tables".into(), tables.into()),
                    ("lns_iterations".into(), "100".into()),
                ])
                .unwrap();
            let ctx = Ctx {
                seed: 2,
                ..Ctx::default()
            };
            solve(planner.as_ref(), &problem, &ctx).unwrap_or_else(|e| panic!("{tables}: {e}"))
        };
        let manhattan = run("manhattan");
        assert!(manhattan.metrics.tasks_finished > 0, "{}", entry.name);
        assert_eq!(manhattan.metrics.planner_errors, 0, "{}", entry.name);
        let exact = run("exact");
        assert_eq!(
            run("auto").plan.actions,
            exact.plan.actions,
            "{}",
            entry.name
        );
        assert_ne!(manhattan.plan.actions, exact.plan.actions, "{}", entry.name);
        eprintln!(
            "{}: manhattan {} tasks, exact {}",
            entry.name, manhattan.metrics.tasks_finished, exact.metrics.tasks_finished
        );
    }
}

/// `commitment=hold` (the kit's `decided`: a robot keeps the cell it turned towards) and
/// `prefer` both give valid runs on the maze under `MAPF_T` and differ (so the option acts);
/// under `MAPF` (no turns) they are the same run.
#[test]
fn both_commitments_give_valid_runs_and_differ_only_with_rotations() {
    for model in [ActionModel::MapfT, ActionModel::Mapf] {
        let problem =
            LifelongProblem::load(&data(EXAMPLES[1]), model, 150, Duration::from_secs(1)).unwrap();
        let run = |commitment: &str| {
            let planner = PLANNERS[0]
                .instantiate(&[("commitment".into(), commitment.into())])
                .unwrap();
            let ctx = Ctx {
                seed: 5,
                ..Ctx::default()
            };
            solve(planner.as_ref(), &problem, &ctx).unwrap_or_else(|e| panic!("{commitment}: {e}"))
        };
        let (hold, prefer) = (run("hold"), run("prefer"));
        assert!(hold.metrics.tasks_finished > 0 && prefer.metrics.tasks_finished > 0);
        eprintln!(
            "{}: hold {} tasks, prefer {}",
            model.name(),
            hold.metrics.tasks_finished,
            prefer.metrics.tasks_finished
        );
        if model == ActionModel::MapfT {
            assert_ne!(hold.plan.actions, prefer.plan.actions);
        } else {
            assert_eq!(hold.plan.actions, prefer.plan.actions);
        }
    }
}
