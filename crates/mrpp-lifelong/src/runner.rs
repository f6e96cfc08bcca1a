//! A lifelong run: the League of Robot Runners' loop of scheduler, planner and simulator
//! (start kit v2.1.2, `src/CompetitionSystem.cpp`; `docs/lorr-semantics.md` §2, "One simulation
//! step"), and the lifelong planners of the registry.
//!
//! Each call gets the current state and the step's planning time (`--step-time-limit`): the
//! scheduler proposes an assignment within half of it, then the planner proposes one action per
//! robot. As in the kit, a call that runs over the budget is not interrupted: every full budget
//! it used costs one step in which nobody moves and no task is updated (`T` in the paths, a
//! *late step*), then its answer is executed. The answer is checked by the kit's rules
//! ([`Simulation::check_actions`]): the kit would make every robot wait, but mrpp's planners
//! never propose an invalid step, so one is reported as a bug (the run fails, nothing is
//! repaired). The proposed schedule is checked too; a refused one keeps the old assignment and is
//! recorded, as the kit does.
//!
//! The whole run stops at the horizon (`--steps`) or, with what it has done so far, when the
//! run's time limit passes (`--time-limit`; the trace is then shorter than the horizon). Within
//! the budget a run is reproducible from its seed; a late step depends on the machine.

use std::time::{Duration, Instant};

use mrpp_core::mapf::graph::VertexId;
use mrpp_core::{Ctx, Deadline, Param, Planner, PlannerEntry, Progress, Unsolved};

use crate::distances::{DEFAULT_BUDGET, Distances};
use crate::model::Action;
use crate::problem::{Assign, LifelongProblem, ScheduleErrorRecord, Trace};
use crate::rotation_pibt::RotationPibt;
use crate::scheduler::{SchedulerKind, schedule};
use crate::sim::Simulation;

/// The parameters every lifelong planner takes (the scheduler).
const SCHEDULER_PARAMS: [Param; 2] = [
    Param {
        name: "scheduler",
        default: "greedy",
        doc: "greedy = the start kit's (nearest free task per free robot, never re-assigned); hungarian = minimum-cost assignment of every robot not yet at its first errand, each step",
    },
    Param {
        name: "hungarian_max",
        default: "400",
        doc: "above this many robots or tasks in the batch, hungarian falls back to greedy for the step",
    },
];

/// Rolling PIBT with rotations in the planner registry.
pub const PIBT_ENTRY: PlannerEntry<LifelongProblem> = PlannerEntry {
    name: "lifelong-pibt",
    about: "lifelong PIBT, one step per call, rotation-aware (the LoRR start kit's PIBT without guide paths; Okumura et al., AIJ 2022)",
    params: &SCHEDULER_PARAMS,
    build: |p| {
        let scheduler = match p.choice("scheduler", &["greedy", "hungarian"])? {
            0 => SchedulerKind::Greedy,
            _ => SchedulerKind::Hungarian,
        };
        Ok(Box::new(LifelongPibt {
            scheduler,
            hungarian_max: p.get_in("hungarian_max", 1..=5000)?,
        }))
    },
};

/// Rolling PIBT with rotations ([`crate::rotation_pibt`]) and a scheduler.
#[derive(Debug, Clone, Copy)]
pub struct LifelongPibt {
    pub scheduler: SchedulerKind,
    pub hungarian_max: usize,
}

impl Planner<LifelongProblem> for LifelongPibt {
    fn name(&self) -> &str {
        PIBT_ENTRY.name
    }

    fn plan(&self, problem: &LifelongProblem, ctx: &Ctx) -> Result<Trace, Unsolved> {
        let vertices = problem.map().graph().num_vertices();
        let mut pibt = RotationPibt::new(problem.starts().len(), vertices, ctx.seed);
        run(problem, ctx, |sim, dist, budget| {
            let proposal = schedule(
                self.scheduler,
                self.hungarian_max,
                sim,
                dist,
                Deadline::after(budget / 2),
            );
            let goals: Vec<VertexId> = proposal
                .iter()
                .zip(&sim.states)
                .map(|(task, s)| {
                    task.map_or(s.vertex, |k| {
                        let t = &sim.tasks[k];
                        t.errands[t.done]
                    })
                })
                .collect();
            let actions = pibt.step(sim, &goals, dist);
            (actions, proposal)
        })
    }
}

/// What one planner call returns: one action per robot and the proposed assignment.
pub type Answer = (Vec<Action>, Vec<Option<usize>>);

/// Runs the kit's loop (module doc) with `call` as scheduler and planner: given the state, the
/// distance tables and the step's budget, it answers.
///
/// # Errors
/// [`Unsolved::Invalid`] when an answer breaks the rules (a bug in the planner).
pub fn run(
    problem: &LifelongProblem,
    ctx: &Ctx,
    mut call: impl FnMut(&Simulation<'_>, &mut Distances, Duration) -> Answer,
) -> Result<Trace, Unsolved> {
    let n = problem.starts().len();
    let steps = problem.steps();
    let budget = problem.step_time().max(Duration::from_micros(1));
    let mut sim = Simulation::new(problem);
    let graph = problem.map().graph();
    let mut dist = Distances::new(graph.num_vertices(), DEFAULT_BUDGET);
    // Preprocessing (the kit's `initialize`): distance tables of the errands of the tasks
    // revealed first (the pool, then as many again as there are robots), in the order they will
    // be revealed, within the preprocessing time and the tables' budget.
    let started = Instant::now();
    let mut seen = rustc_hash::FxHashSet::default();
    let file = problem.task_file();
    let errands: Vec<VertexId> = (0..problem.reveal_pool() + n)
        .flat_map(|k| &file[k % file.len()])
        .copied()
        .filter(|&v| seen.insert(v))
        .collect();
    let prep = Deadline::after(problem.preprocess_time());
    for (k, chunk) in errands.chunks(256).enumerate() {
        let live = dist.warm(graph, chunk, &[prep, ctx.deadline]);
        ctx.report(Progress {
            stage: "preprocessing",
            done: ((k * 256) + chunk.len()) as u64,
            total: errands.len() as u64,
            note: format!("{live} distance tables"),
        });
        if prep.expired() || ctx.deadline.expired() || live < (k * 256) + chunk.len() {
            // Out of time, or the tables' budget is full.
            break;
        }
    }
    let mut trace = Trace {
        actions: vec![Vec::with_capacity((steps as usize).min(4096)); n],
        planned: vec![Vec::with_capacity((steps as usize).min(4096)); n],
        ..Trace::default()
    };
    trace.preprocess_time = started.elapsed().as_secs_f64();
    let mut last_proposal: Vec<Option<usize>> = vec![None; n];
    while sim.t < steps && !ctx.deadline.expired() {
        let started = Instant::now();
        let (actions, proposal) = call(&sim, &mut dist, budget);
        let elapsed = started.elapsed();
        let late = (elapsed.as_nanos() / budget.as_nanos()).min(u128::from(steps)) as u32;
        for _ in 0..late {
            if sim.t >= steps {
                break;
            }
            trace.late_steps.push(sim.t);
            for i in 0..n {
                trace.actions[i].push(Action::NoAction);
                trace.planned[i].push(Action::NoAction);
            }
            sim.idle_step();
        }
        trace.planner_times.push(elapsed.as_secs_f64());
        if sim.t >= steps {
            break;
        }
        let next = sim.check_actions(&actions).map_err(|e| {
            let (a, b) = e.agents();
            Unsolved::Invalid(format!(
                "step {}: the planner proposed a joint action with a {} (robots {a} and {b})",
                sim.t + 1,
                e.message()
            ))
        })?;
        for (i, &a) in actions.iter().enumerate() {
            trace.actions[i].push(a);
            trace.planned[i].push(a);
        }
        sim.step(next);
        for (agent, (&now, &before)) in proposal.iter().zip(&last_proposal).enumerate() {
            if now != before {
                trace.proposed_schedule.push(Assign {
                    t: sim.t,
                    agent,
                    task: now,
                });
            }
        }
        last_proposal.clone_from(&proposal);
        let applied = match sim.check_schedule(&proposal) {
            Ok(()) => Some(proposal.as_slice()),
            Err(e) => {
                let (task, agent1, agent2) = e.ids();
                trace.schedule_errors.push(ScheduleErrorRecord {
                    task,
                    agent1,
                    agent2,
                    t: sim.t,
                    message: e.message().to_string(),
                });
                None
            }
        };
        let t = sim.t;
        for (agent, task) in sim.update_tasks(applied) {
            trace.schedule.push(Assign { t, agent, task });
        }
        if sim.t.is_multiple_of(10) || sim.t == steps {
            ctx.report(Progress {
                stage: "step",
                done: u64::from(sim.t),
                total: u64::from(steps),
                note: format!("{} tasks finished", sim.finished),
            });
        }
    }
    Ok(trace)
}
