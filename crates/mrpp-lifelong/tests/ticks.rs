//! Lifelong runs under the League of Robot Runners' 2026 execution model (ticks, delays, an
//! executor): every planner on the bundled examples, validated by `solve` (footprints, delays,
//! tasks recounted), written as LoRR's 2026 output JSON and read back; and the validator
//! refusing what it must refuse.

use std::path::{Path, PathBuf};
use std::time::Duration;

use mrpp_core::{Ctx, Problem, solve};
use mrpp_exec::DelayConfig;
use mrpp_lifelong::execution::ExecutionModel;
use mrpp_lifelong::executor::ExecutorKind;
use mrpp_lifelong::lorr_output::{from_json, to_json};
use mrpp_lifelong::{Action, ActionModel, LifelongProblem, LifelongViolation, PLANNERS};

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/robot-runners")
        .join(rel)
}

fn in_ticks(
    example: &str,
    model: ActionModel,
    ticks: u32,
    change: impl FnOnce(&mut ExecutionModel),
) -> LifelongProblem {
    let problem =
        LifelongProblem::load(&data(example), model, ticks, Duration::from_secs(1)).unwrap();
    let mut m = ExecutionModel::of_problem(problem.files()).unwrap();
    change(&mut m);
    problem.with_execution(m)
}

#[test]
fn every_planner_runs_in_ticks_under_delays_and_its_2026_output_reads_back() {
    for example in [
        "lorr2023-warehouse_small/warehouse_small_10.json",
        "lorr2026-maze/maze-example_40.json",
    ] {
        for model in [ActionModel::MapfT, ActionModel::Mapf] {
            for (executor, size, counter) in [
                (ExecutorKind::Tpg, 1.0, 3),
                (ExecutorKind::Tpg, 0.5, 2),
                (ExecutorKind::Naive, 1.0, 3),
            ] {
                let problem = in_ticks(example, model, 300, |m| {
                    m.executor = executor;
                    m.agent_size = size;
                    m.agent_counter = counter;
                    m.delays = DelayConfig::parse("bernoulli:p=0.01,min=1,max=6").unwrap();
                    m.delay_seed = 3;
                });
                for entry in PLANNERS {
                    let what = format!(
                        "{example}, {}, {}, {}, size {size}, counter {counter}",
                        model.name(),
                        entry.name,
                        executor.name()
                    );
                    let planner = entry
                        .instantiate(&[("lns_iterations".into(), "50".into())])
                        .unwrap();
                    let ctx = Ctx {
                        seed: 5,
                        ..Ctx::default()
                    };
                    let solved = solve(planner.as_ref(), &problem, &ctx)
                        .unwrap_or_else(|e| panic!("{what}: {e}"));
                    let m = solved.metrics;
                    assert_eq!(m.steps, 300, "{what}");
                    let record = solved.plan.ticks.as_ref().expect("a run in ticks");
                    let delayed: usize = record.delays.iter().map(Vec::len).sum();
                    assert!(
                        delayed > 0,
                        "{what}: p = 0.01 over 300 ticks delays someone"
                    );
                    if executor == ExecutorKind::Tpg {
                        assert!(m.tasks_finished > 0, "{what}: no task finished");
                    }
                    let json = to_json(&problem, &solved.plan).unwrap();
                    assert_eq!(json["version"], "2026 LoRR");
                    assert_eq!(json["makespan"], 300);
                    assert_eq!(json["numTaskFinished"], m.tasks_finished, "{what}");
                    let (back, _) =
                        from_json(&problem, &json.to_string(), Path::new("out.json")).unwrap();
                    assert_eq!(back.actions, solved.plan.actions, "{what}");
                    assert_eq!(back.planned, solved.plan.planned, "{what}");
                    assert_eq!(back.schedule, solved.plan.schedule, "{what}");
                    assert_eq!(back.ticks.as_ref().unwrap().delays, record.delays, "{what}");
                    let again = problem.validate(&back).unwrap();
                    assert_eq!(again.tasks_finished, m.tasks_finished, "{what}");
                    // The kit v3.1.0 stamps each robot's first schedule entry with an
                    // uninitialised clock (e.g. 741946930): read as tick 0.
                    let mut kit_like = json.clone();
                    for (k, entry) in kit_like["actualSchedule"]
                        .as_array_mut()
                        .unwrap()
                        .iter_mut()
                        .enumerate()
                    {
                        let s = entry.as_str().unwrap().to_string();
                        let clock = if k % 2 == 0 {
                            "741946930"
                        } else {
                            "-1350986528"
                        };
                        if let Some(rest) = s.strip_prefix("0:") {
                            *entry = serde_json::Value::String(format!("{clock}:{rest}"));
                        }
                    }
                    let (back, _) =
                        from_json(&problem, &kit_like.to_string(), Path::new("out.json")).unwrap();
                    assert_eq!(back.schedule, solved.plan.schedule, "{what}");
                    eprintln!(
                        "{what}: {} tasks, {} delays, {} waits imposed",
                        m.tasks_finished, delayed, m.planner_errors
                    );
                }
            }
        }
    }
}

#[test]
fn the_validator_refuses_a_delayed_robot_that_moves_and_overlapping_footprints() {
    let problem = in_ticks(
        "lorr2026-maze/maze-example_40.json",
        ActionModel::MapfT,
        200,
        |m| m.delays = DelayConfig::parse("bernoulli:p=0.02,min=2,max=4").unwrap(),
    );
    let planner = PLANNERS[0].instantiate(&[]).unwrap();
    let solved = solve(planner.as_ref(), &problem, &Ctx::default()).unwrap();
    let record = solved.plan.ticks.clone().unwrap();
    // A robot held by a delay that turns anyway.
    let (agent, tick) = record
        .delays
        .iter()
        .enumerate()
        .find_map(|(i, d)| d.first().map(|iv| (i, iv[0] as usize)))
        .expect("some delay");
    let mut bad = solved.plan.clone();
    bad.actions[agent][tick] = Action::Clockwise;
    assert_eq!(
        problem.validate(&bad),
        Err(LifelongViolation::MovesWhenDelayed {
            tick: tick as u32 + 1,
            agent
        })
    );
    // Two robots in one corridor: the one behind drives into the one in front, which waits.
    let mut bad = solved.plan.clone();
    let (first, second) = find_robot_behind(&problem, &bad).expect("a robot facing another");
    for t in 0..bad.steps() as usize {
        bad.actions[second][t] = Action::Wait;
        bad.actions[first][t] = if t < 3 { Action::Forward } else { Action::Wait };
    }
    bad.ticks.as_mut().unwrap().delays = vec![Vec::new(); problem.num_agents()];
    bad.schedule.clear();
    match problem.validate(&bad) {
        Err(LifelongViolation::Footprints {
            tick: 1,
            agent1,
            agent2,
        }) => assert_eq!(
            (agent1.min(agent2), agent1.max(agent2)),
            (first.min(second), first.max(second))
        ),
        other => panic!("expected overlapping footprints at tick 1, got {other:?}"),
    }
}

/// A robot facing (east, as every robot starts) the cell of another robot.
fn find_robot_behind(
    problem: &LifelongProblem,
    _: &mrpp_lifelong::Trace,
) -> Option<(usize, usize)> {
    let map = problem.map();
    let starts = problem.starts();
    starts.iter().enumerate().find_map(|(i, &v)| {
        let (x, y) = map.cell(v);
        let ahead = map.vertex_at(i64::from(x) + 1, i64::from(y))?;
        starts.iter().position(|&w| w == ahead).map(|j| (i, j))
    })
}

/// Executed moves (one tick an action, so cells change at every tick) that enter a cell another
/// robot left fewer than `k` ticks earlier, same tick included (following).
fn slack_breaches(problem: &LifelongProblem, trace: &mrpp_lifelong::Trace, k: u64) -> usize {
    let record = trace.ticks.as_ref().expect("a run in ticks");
    let mut cells: Vec<Vec<u32>> = Vec::new();
    mrpp_lifelong::execution::replay_tick_states(problem, trace, record, |sim, _| {
        cells.push(sim.states.iter().map(|s| s.vertex).collect());
    })
    .unwrap();
    let starts: Vec<u32> = problem.starts().to_vec();
    let mut before = &starts;
    let mut left: std::collections::HashMap<u32, (usize, u64)> = Default::default();
    let mut breaches = 0;
    for (t, now) in cells.iter().enumerate() {
        let t = t as u64;
        for (i, (&a, &b)) in before.iter().zip(now).enumerate() {
            if a != b {
                left.insert(a, (i, t));
            }
        }
        for (i, (&a, &b)) in before.iter().zip(now).enumerate() {
            if a != b
                && let Some(&(j, when)) = left.get(&b)
                && j != i
                && t < when + k
            {
                breaches += 1;
            }
        }
        before = now;
    }
    breaches
}

/// What `--k-robust` does to executed runs without delays (3 ticks an action, a plan every 10
/// ticks, the League's executor): the executor alone already keeps one action between a robot
/// leaving a cell and the next entering it (so k = 1 adds nothing there); k = 2 plans make
/// passages closer than two actions rarer, though not impossible (a robot the executor stops
/// falls behind its plan's timing, and the next plan starts from where it stands).
#[test]
fn k_robust_plans_space_out_the_executed_passages() {
    for model in [ActionModel::Mapf, ActionModel::MapfT] {
        for entry in PLANNERS {
            let mut close = Vec::new();
            for k in [0u32, 2] {
                let problem = in_ticks("lorr2026-maze/maze-example_40.json", model, 600, |m| {
                    m.agent_counter = 3;
                    m.plan_every = 10;
                    m.delays = DelayConfig::none();
                    m.k_robust = k;
                });
                let planner = entry
                    .instantiate(&[("lns_iterations".into(), "50".into())])
                    .unwrap();
                let solved = solve(planner.as_ref(), &problem, &Ctx::default()).unwrap();
                let what = format!("{} {} k = {k}", model.name(), entry.name);
                assert!(solved.metrics.tasks_finished > 0, "{what}");
                assert_eq!(
                    slack_breaches(&problem, &solved.plan, 3),
                    0,
                    "{what}: the executor let a robot into a cell less than an action after another left it"
                );
                close.push(slack_breaches(&problem, &solved.plan, 6));
            }
            assert!(
                close[1] * 4 < close[0] * 3,
                "{} {}: passages closer than two actions, k = 0 / k = 2: {close:?}",
                model.name(),
                entry.name
            );
        }
    }
}
