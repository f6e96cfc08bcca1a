//! Re-planning on drift (issue 29, item 5; `mrpp_exec::replan`): under every delay model, ADG
//! execution with LaCAM re-planning never collides, always finishes, its record replays against
//! the executed plan, and that executed plan (the prefixes of every plan, then the last) is a
//! valid plan of the original problem. A re-planner that finds nothing leaves the execution
//! exactly as without re-planning.

mod common;

use std::time::Duration;

use mrpp_core::mapf::graph::VertexId;
use mrpp_core::mapf::plan::Plan;
use mrpp_core::{Ctx, Deadline, MapfProblem, Problem, solve};
use mrpp_exec::execute::Ending;
use mrpp_exec::{
    DelayConfig, ExecConfig, ExecutorKind, Replanner, Replanning, check::check, execute,
    execute_replanning,
};
use mrpp_grid::PLANNERS;

const SIZE: f64 = 0.5;

/// ADG execution, `ticks_per_move` ticks a move, delays `spec` drawn from `seed`.
fn adg(ticks_per_move: u32, spec: &str, seed: u64) -> ExecConfig {
    ExecConfig {
        executor: ExecutorKind::Adg,
        ticks_per_move,
        delays: DelayConfig::parse(spec).unwrap(),
        seed,
        agent_size: SIZE,
        max_ticks: 1_000_000,
    }
}

fn lacam_plan(problem: &MapfProblem, seed: u64) -> Option<Plan> {
    let planner = lacam_planner();
    let ctx = Ctx::new(seed, Deadline::after(Duration::from_secs(5)));
    solve(planner.as_ref(), problem, &ctx).ok().map(|s| s.plan)
}

fn lacam_planner() -> Box<dyn mrpp_core::Planner<MapfProblem>> {
    let entry = mrpp_core::registry::find(PLANNERS, "lacam").unwrap();
    entry.instantiate(&[]).unwrap()
}

#[test]
fn adg_with_replanning_stays_collision_free_and_its_executed_plan_is_valid() {
    let (grid, problem) =
        common::bundled("random-32-32-20.map", "random-32-32-20-random-1.scen", 60);
    let plan = lacam_plan(&problem, 0).unwrap();
    let lacam = lacam_planner();
    let models = [
        "bernoulli:p=0.02,min=1,max=4",
        "poisson:p=0.01,min=2,max=8,duration=gaussian,mean=0.5,std=0.22",
        "bernoulli:p=0.05,min=5,max=20",
    ];
    let (mut runs, mut replans) = (0, 0);
    let (mut plain_sum, mut replanned_sum) = (0u64, 0u64);
    for spec in models {
        for counter in [1, 3] {
            for drift in [4, 16] {
                for seed in 0..8u64 {
                    let cfg = adg(counter, spec, seed);
                    let mut replanner =
                        Replanner::new(&problem, lacam.as_ref(), seed, Duration::from_secs(5));
                    let mut planner = |at: &[VertexId]| replanner.plan(at);
                    let (run, executed) = execute_replanning(
                        &grid,
                        &plan,
                        &cfg,
                        Some(Replanning {
                            drift,
                            planner: &mut planner,
                        }),
                    );
                    let what = format!("{spec} x{counter} drift {drift} seed {seed}");
                    assert_eq!(replanner.invalid, None, "{what}");
                    assert_eq!(run.ending, Ending::Finished, "{what}");
                    assert!(run.collisions.is_empty(), "{what}: {:?}", run.collisions[0]);
                    problem
                        .validate(&executed)
                        .unwrap_or_else(|v| panic!("{what}: executed plan invalid: {v}"));
                    let replayed = check(&grid, &executed, &run, counter, SIZE)
                        .unwrap_or_else(|e| panic!("{what}: {e}"));
                    assert!(replayed.is_empty(), "{what}");
                    assert_eq!(run.metrics.replans, run.replans.len());
                    runs += 1;
                    replans += run.metrics.replans;
                    plain_sum += execute(&grid, &plan, &cfg).metrics.makespan;
                    replanned_sum += run.metrics.makespan;
                }
            }
        }
    }
    eprintln!(
        "{runs} runs, {replans} re-plans; executed makespan summed: ADG {plain_sum}, ADG + re-planning {replanned_sum}"
    );
    assert!(
        replans > runs,
        "re-planning hardly ever triggered ({replans} in {runs} runs): the test checks little"
    );
}

#[test]
fn a_replanner_that_finds_nothing_leaves_the_execution_unchanged() {
    let (grid, problem) =
        common::bundled("random-32-32-20.map", "random-32-32-20-random-1.scen", 40);
    let plan = lacam_plan(&problem, 0).unwrap();
    let cfg = adg(2, "bernoulli:p=0.05,min=2,max=6", 3);
    let plain = execute(&grid, &plan, &cfg);
    let mut nothing = |_: &[VertexId]| None;
    let (run, executed) = execute_replanning(
        &grid,
        &plan,
        &cfg,
        Some(Replanning {
            drift: 3,
            planner: &mut nothing,
        }),
    );
    assert_eq!(executed.paths, plan.paths);
    assert_eq!(run.moves, plain.moves);
    assert_eq!(run.delays, plain.delays);
    assert_eq!(run.metrics.replans, 0);
    assert!(run.metrics.failed_replans > 0);
}

/// A planner whose plan teleports every robot to its goal in one step.
struct Teleport;

impl mrpp_core::Planner<MapfProblem> for Teleport {
    fn name(&self) -> &str {
        "teleport"
    }

    fn plan(&self, problem: &MapfProblem, _: &Ctx) -> Result<Plan, mrpp_core::Unsolved> {
        let i = problem.instance();
        Ok(Plan {
            paths: i
                .starts
                .iter()
                .zip(&i.goals)
                .map(|(&s, &g)| vec![s, g])
                .collect(),
        })
    }
}

/// `Replanner` keeps a re-plan the validator rejects (a planner bug) for its caller to fail
/// with, instead of passing it off as "no plan found"; the execution goes on with the old plan.
#[test]
fn a_replanner_keeps_an_invalid_plan_as_an_error() {
    let (grid, problem) =
        common::bundled("random-32-32-20.map", "random-32-32-20-random-1.scen", 30);
    let plan = lacam_plan(&problem, 0).unwrap();
    let cfg = adg(2, "bernoulli:p=0.05,min=2,max=6", 1);
    let mut replanner = Replanner::new(&problem, &Teleport, 0, Duration::from_secs(1));
    let mut planner = |at: &[VertexId]| replanner.plan(at);
    let (run, executed) = execute_replanning(
        &grid,
        &plan,
        &cfg,
        Some(Replanning {
            drift: 3,
            planner: &mut planner,
        }),
    );
    assert_eq!(executed.paths, plan.paths);
    assert!(run.metrics.failed_replans > 0);
    assert_eq!(replanner.calls, run.metrics.failed_replans as u64);
    let why = replanner.invalid.expect("the teleport is refused");
    assert!(why.contains("teleport"), "{why}");
}
