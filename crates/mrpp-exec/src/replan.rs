//! Re-planning when the executed state drifts from the plan (issue 29, item 5).
//!
//! An executor keeps a plan's order of passage however late a robot is ([`crate::adg`]), so one
//! late robot can hold up every robot whose path crosses its own. Re-planning starts over from
//! where the robots are: when some robot should have started its next move more than `drift`
//! ticks ago by its current plan's timing (the plan's step `s` is due at tick `t0 + s x
//! ticks_per_move`, `t0` the tick the plan took over), the planner is asked for a plan from the
//! configuration the robots will stand in once their moves in progress are done (a robot in the
//! middle of a move is committed to its end cell) to the same goals, and its plan takes over at
//! once, its step 0 at that tick. Robots in the middle of a move finish it as the new plan's
//! first step (the others wait that step out), so the new plan's action dependency graph orders
//! every move into a cell being left after the move that leaves it; no robot stops for the
//! switch.
//!
//! Where the issue is silent, mrpp chooses:
//! - **Planning takes no ticks.** The planner's wall time is not charged to the execution (a real
//!   fleet plans while its robots finish their moves; mrpp's executions stay reproducible).
//! - **A failed re-plan** (no plan found, or one that starts elsewhere) leaves the current plan in
//!   force; the next attempt is `drift` ticks later. Both counts are in [`crate::execute::ExecMetrics`].
//! - **Lag** counts any reason a robot is behind: its own delays, waiting for dependencies, or a
//!   ring that could not start.
//!
//! The record's plan is the *executed plan*: each plan's executed prefix (padded with waits to one
//! length, so later plans' steps stay aligned across robots), then the next, the last one whole.
//! Under the ADG its prefix is a valid plan: the moves done form a set closed under the ADG's
//! dependencies, so no robot's done move enters a cell before the robot the plan sent first left
//! it (a property test validates every executed plan).

use std::time::Duration;

use mrpp_core::mapf::graph::VertexId;
use mrpp_core::mapf::instance::Instance;
use mrpp_core::mapf::plan::Plan;
use mrpp_core::seeds::derive_seed;
use mrpp_core::{Ctx, Deadline, MapfProblem, Planner, Progress, ProgressFn, Unsolved, solve};

use crate::adg::Adg;

/// A re-planner built on a MAPF planner: call `k` (from 1) plans from the configuration it is
/// given to the problem's goals with seed `derive_seed(seed, "replan/k")` within `budget` of
/// wall time, through [`mrpp_core::solve`] (so its plan is validated). What `mrpp execute` and
/// `mrpp experiment execution` re-plan with.
pub struct Replanner<'a> {
    problem: &'a MapfProblem,
    planner: &'a dyn Planner<MapfProblem>,
    seed: u64,
    budget: Duration,
    progress: Option<ProgressFn>,
    /// Calls so far.
    pub calls: u64,
    /// The first call whose planner returned a plan the validator rejects (a planner bug; the
    /// execution went on without that plan): the caller should fail with it.
    pub invalid: Option<String>,
}

impl<'a> Replanner<'a> {
    /// Re-plans `problem`'s goals with `planner`, `budget` per call, seeds derived from `seed`.
    pub fn new(
        problem: &'a MapfProblem,
        planner: &'a dyn Planner<MapfProblem>,
        seed: u64,
        budget: Duration,
    ) -> Self {
        Replanner {
            problem,
            planner,
            seed,
            budget,
            progress: None,
            calls: 0,
            invalid: None,
        }
    }

    /// Reports each call (stage `re-plan`, the count of calls, the outcome) to `progress`.
    pub fn with_progress(mut self, progress: Option<ProgressFn>) -> Self {
        self.progress = progress;
        self
    }

    /// A plan from `at` (one vertex per robot) to the goals, or `None`: no plan within the
    /// budget, a configuration that is not one (two robots on a vertex), or an invalid plan
    /// (kept in [`Self::invalid`]).
    pub fn plan(&mut self, at: &[VertexId]) -> Option<Plan> {
        self.calls += 1;
        let ctx = Ctx::new(
            derive_seed(self.seed, &format!("replan/{}", self.calls)),
            Deadline::after(self.budget),
        );
        let result = Instance::new(at.to_vec(), self.problem.instance().goals.clone())
            .ok()
            .and_then(|i| {
                MapfProblem::new(self.problem.graph_arc().clone(), i, self.problem.rules()).ok()
            })
            .map(|from| solve(self.planner, &from, &ctx));
        let (plan, note) = match result {
            Some(Ok(s)) => (Some(s.plan), "plan found".to_string()),
            Some(Err(Unsolved::Invalid(why))) => {
                self.invalid.get_or_insert(why);
                (None, "invalid plan (a planner bug)".to_string())
            }
            Some(Err(e)) => (None, format!("no plan: {}", e.status())),
            None => (None, "not a configuration".to_string()),
        };
        if let Some(f) = &self.progress {
            f(&Progress {
                stage: "re-plan",
                done: self.calls,
                total: 0,
                note,
            });
        }
        plan
    }
}

/// How to re-plan on drift (module doc).
pub struct Replanning<'a> {
    /// Ticks a robot may lag behind its plan's timing before a re-plan, at least 1.
    pub drift: u64,
    /// A plan from the given configuration (one vertex per robot) to the robots' goals, or
    /// `None` when there is none in the planner's budget.
    pub planner: &'a mut dyn FnMut(&[VertexId]) -> Option<Plan>,
}

/// Cuts `executed` (whose paths from index `offset` on are those of the plan `adg` was built
/// from) after each robot's first `done[i]` moves of that plan, pads every path with waits to
/// one length, and returns that length minus one: the index at which the next plan starts.
pub(crate) fn cut(executed: &mut Plan, offset: usize, adg: &Adg, done: &[usize]) -> usize {
    // A move at step s ends at path index s + 1.
    let ends: Vec<usize> = adg
        .moves
        .iter()
        .zip(done)
        .map(|(m, &d)| d.checked_sub(1).map_or(0, |k| m[k].step as usize + 1))
        .collect();
    let last = offset + ends.iter().copied().max().unwrap_or(0);
    for (path, &e) in executed.paths.iter_mut().zip(&ends) {
        path.truncate(offset + e + 1);
        let v = *path.last().expect("a path has a start");
        path.resize(last + 1, v);
    }
    last
}

/// Appends `next` (which starts where `executed` ends) to `executed`.
pub(crate) fn append(executed: &mut Plan, next: &Plan) {
    for (path, more) in executed.paths.iter_mut().zip(&next.paths) {
        path.extend_from_slice(&more[1..]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cut_keeps_each_robots_done_moves_and_aligns_the_next_plan() {
        // Robot 0 did 1 of its 2 moves, robot 1 both of its moves (after a wait).
        let mut executed = Plan {
            paths: vec![vec![9, 0, 1, 2], vec![9, 5, 5, 6, 7]],
        };
        let cur = Plan {
            paths: vec![vec![0, 1, 2], vec![5, 5, 6, 7]],
        };
        let at = cut(&mut executed, 1, &Adg::new(&cur), &[1, 2]);
        assert_eq!(at, 4);
        assert_eq!(
            executed.paths,
            vec![vec![9, 0, 1, 1, 1], vec![9, 5, 5, 6, 7]]
        );
        append(
            &mut executed,
            &Plan {
                paths: vec![vec![1, 3], vec![7, 7]],
            },
        );
        assert_eq!(
            executed.paths,
            vec![vec![9, 0, 1, 1, 1, 3], vec![9, 5, 5, 6, 7, 7]]
        );
    }
}
