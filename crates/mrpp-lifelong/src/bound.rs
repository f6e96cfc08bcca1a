//! A congestion-free reference for a lifelong problem: the tasks its robots would finish in the
//! horizon if they never got in each other's way.
//!
//! The League's rules are kept except collisions: tasks revealed and errands completed as in
//! [`Simulation`], the same scheduler every step ([`crate::scheduler`]), and every robot takes,
//! alone on the map, an action that brings it closest to its next errand (under `MAPF_T` by
//! the rotation-aware tables, [`TurnDistances`]: forward when that shortens the remaining
//! actions, else the turn that does; a robot without a task waits). Robots may share cells and
//! swap. No planner with this scheduler can expect to finish many more tasks than this (a planner
//! could only beat it by scheduling differently), so it says how much of a gap to the best
//! possible is left — e.g. whether a target of 1.5 times another planner's tasks is reachable on
//! a problem. `mrpp info --lorr P.json --lifelong --steps N` prints it.

use mrpp_core::Deadline;
use mrpp_core::mapf::graph::VertexId;

use crate::distances::{DEFAULT_BUDGET, Distances, TurnDistances};
use crate::model::{Action, ActionModel, State, apply};
use crate::problem::LifelongProblem;
use crate::scheduler::Scheduler;
use crate::sim::Simulation;

/// Tasks finished in `problem`'s horizon without collisions (module doc), with `scheduler`,
/// or `None` when `ctx.deadline` passed first.
/// Reports the step and the tasks finished through `ctx` (a 5,000-robot problem takes a
/// minute).
pub fn congestion_free(
    problem: &LifelongProblem,
    scheduler: &Scheduler,
    ctx: &mrpp_core::Ctx,
) -> Option<usize> {
    let deadline = ctx.deadline;
    let mut throttle = mrpp_core::Throttle::new();
    let map = problem.map();
    let graph = map.graph();
    let mut dist = Distances::new(graph.num_vertices(), DEFAULT_BUDGET);
    let mut turns = (problem.model() == ActionModel::MapfT)
        .then(|| TurnDistances::new(map, DEFAULT_BUDGET / 2));
    let mut sim = Simulation::new(problem);
    let far = Deadline::after(std::time::Duration::from_secs(3600));
    while sim.t < problem.steps() {
        if deadline.expired() {
            return None;
        }
        throttle.report(ctx, || mrpp_core::Progress {
            stage: "congestion-free step",
            done: u64::from(sim.t),
            total: u64::from(problem.steps()),
            note: format!("{} tasks finished", sim.finished),
        });
        let proposal = scheduler.propose(&sim, &mut dist, far);
        let next: Vec<State> = sim
            .states
            .iter()
            .zip(&proposal)
            .map(|(&s, task)| {
                let Some(k) = *task else { return s };
                let t = &sim.tasks[k];
                let goal = t.errands[t.done];
                best_move(problem, s, goal, &mut dist, turns.as_mut())
            })
            .collect();
        sim.step(next);
        let applied = sim.check_schedule(&proposal).is_ok();
        sim.update_tasks(applied.then_some(proposal.as_slice()));
    }
    Some(sim.finished)
}

/// The state after the action of a lone robot at `s` that brings it closest to `goal`.
fn best_move(
    problem: &LifelongProblem,
    s: State,
    goal: VertexId,
    dist: &mut Distances,
    turns: Option<&mut TurnDistances>,
) -> State {
    let map = problem.map();
    if s.vertex == goal {
        return s;
    }
    let candidates: &[Action] = match problem.model() {
        ActionModel::MapfT => &[Action::Forward, Action::Clockwise, Action::CounterClockwise],
        ActionModel::Mapf => &[
            Action::Move(0),
            Action::Move(1),
            Action::Move(2),
            Action::Move(3),
        ],
    };
    let mut best = (u32::MAX, s);
    match turns {
        Some(t) => {
            for &a in candidates {
                if let Some(n) = apply(map, s, a) {
                    let d = t.get(n.vertex, n.orientation, goal);
                    if d < best.0 {
                        best = (d, n);
                    }
                }
            }
        }
        None => {
            for &a in candidates {
                if let Some(n) = apply(map, s, a) {
                    let d = dist.get(map.graph(), n.vertex, goal);
                    if d < best.0 {
                        best = (d, n);
                    }
                }
            }
        }
    }
    best.1
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::PLANNERS;
    use mrpp_core::{Ctx, solve};
    use std::path::Path;
    use std::time::Duration;

    #[test]
    fn no_planner_run_beats_the_congestion_free_reference() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../data/robot-runners/lorr2026-maze/maze-example_40.json");
        for model in [ActionModel::MapfT, ActionModel::Mapf] {
            let problem = LifelongProblem::load(&path, model, 150, Duration::from_secs(1)).unwrap();
            let bound = congestion_free(
                &problem,
                &Scheduler::new(crate::scheduler::SchedulerKind::Hungarian),
                &Ctx::default(),
            )
            .unwrap();
            let planner = PLANNERS[1]
                .instantiate(&[("lns_iterations".into(), "100".into())])
                .unwrap();
            let run = solve(planner.as_ref(), &problem, &Ctx::default()).unwrap();
            assert!(
                run.metrics.tasks_finished <= bound,
                "{}: {} tasks, the congestion-free reference {bound}",
                model.name(),
                run.metrics.tasks_finished
            );
            assert!(bound > 0);
        }
    }
}
