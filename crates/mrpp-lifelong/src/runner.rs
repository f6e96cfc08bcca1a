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

use crate::distances::{DEFAULT_BUDGET, Distances, TableKind, TurnDistances};
use crate::guide_paths::GuidePaths;
use crate::model::{Action, ActionModel};
use crate::problem::{Assign, LifelongProblem, ScheduleErrorRecord, Trace};
use crate::rotation_pibt::RotationPibt;
use crate::scheduler::{Scheduler, SchedulerKind};
use crate::sim::Simulation;
use crate::window_lns::{LnsOptions, WindowLns};

/// lifelong-pibt's parameters: the scheduler, the guide paths and windowed LNS.
const PIBT_PARAMS: [Param; 13] = [
    Param {
        name: "scheduler",
        default: "greedy",
        doc: "greedy = the start kit's (nearest free task per free robot, never re-assigned); hungarian = minimum-cost assignment of every robot not yet at its first errand, each step; matching = greedy matching of the same pairs by increasing cost (scales to thousands of robots)",
    },
    Param {
        name: "hungarian_max",
        default: "400",
        doc: "above this many robots or tasks in the batch, hungarian falls back to matching for the step",
    },
    Param {
        name: "guidance",
        default: "auto",
        doc: "traffic-flow = follow guide paths that avoid the other robots' flow (the start kit's default planner; Chen et al., AAAI 2024); none = head straight for the goal; auto = traffic-flow when the robots cover at least 2% of the free cells, else none",
    },
    Param {
        name: "guide_replans",
        default: "100",
        doc: "guide paths re-planned per step beyond those of robots with a new goal, farthest from their path first (the kit re-plans until its time runs out; a count keeps runs reproducible)",
    },
    Param {
        name: "distances",
        default: "hops",
        doc: "how a robot without a guide path ranks its cells under MAPF_T: hops = moves to the goal, then fewer turns; turns = actions to the goal counting quarter turns, from tables over (cell, orientation)",
    },
    Param {
        name: "window",
        default: "0",
        doc: "0 = one PIBT step per call; W > 0 = plan W steps ahead (PIBT rollout or the last plan shifted) and refine them by large neighbourhood search within the step's time (WPPL; Jiang et al., SoCS 2024)",
    },
    Param {
        name: "lns_iterations",
        default: "2000",
        doc: "with window > 0: neighbourhoods re-planned per step at most (fewer when the step's time runs out first)",
    },
    Param {
        name: "lns_group",
        default: "8",
        doc: "with window > 0: robots re-planned together in one neighbourhood at most",
    },
    Param {
        name: "chain_weight",
        default: "1",
        doc: "the scheduler's cost of a task is d(robot, next errand) + W x (the distances between its later errands), W in [0, 10]: 1 = the start kit's; 0 = pickup distance only, which finished more tasks on the kit's random_32_32_20_100 over 1,000 steps and fewer on its larger maps (docs/performance.md)",
    },
    Param {
        name: "commitment",
        default: "hold",
        doc: "under MAPF_T, a robot that turned towards a cell (or was held back from it): hold = keeps that cell reserved at the next steps until it gets there or is stuck (the start kit's `decided`); prefer = the cell only goes first among equally good candidates",
    },
    Param {
        name: "distance_tables",
        default: "auto",
        doc: "exact = breadth-first distance tables to errand cells (4 GiB at most, least recently used rebuilt); manhattan = |dx| + |dy|, no tables (the start kit's choice on maps over 90,000 cells); auto = exact unless the 4 GiB hold tables for fewer than twice the robots (e.g. 10,000 robots on 2.2 million cells)",
    },
    Param {
        name: "reassign_margin",
        default: "0",
        doc: "steps in 0..=1000 a re-assignment by hungarian or matching must save: a robot's own task costs this much less for it, so robots on their way turn back less often; 0 = the plain minimum-cost assignment",
    },
    Param {
        name: "lookahead",
        default: "0",
        doc: "steps in 0..=1000: with hungarian or matching, robots that will finish their task within this many steps bid for the open tasks from their last errand (arrival time added), and a task one of them wins is left for it rather than given to a robot that is free now; 0 = off",
    },
];

/// Rolling PIBT with rotations in the planner registry.
pub const PIBT_ENTRY: PlannerEntry<LifelongProblem> = PlannerEntry {
    name: "lifelong-pibt",
    about: "lifelong PIBT, one step per call, rotation-aware, on traffic-flow guide paths (the LoRR start kit's default planner; Okumura et al., AIJ 2022; Chen et al., AAAI 2024)",
    params: &PIBT_PARAMS,
    build: |p| Ok(Box::new(build(PIBT_ENTRY.name, p)?)),
};

/// lifelong-lns's parameters: lifelong-pibt's, with a window of 10 steps and the `hungarian`
/// scheduler (`matching` above `hungarian_max`).
const LNS_PARAMS: [Param; 15] = [
    Param {
        name: "scheduler",
        default: "hungarian",
        doc: PIBT_PARAMS[0].doc,
    },
    PIBT_PARAMS[1],
    PIBT_PARAMS[2],
    PIBT_PARAMS[3],
    PIBT_PARAMS[4],
    Param {
        name: "window",
        default: "10",
        doc: PIBT_PARAMS[5].doc,
    },
    PIBT_PARAMS[6],
    PIBT_PARAMS[7],
    Param {
        name: "lns_max_density",
        default: "0.2",
        doc: "above this share of the free cells covered by robots, plan one PIBT step per call (no window, no LNS): on the kit's warehouse map windowed LNS finished more tasks at 13% (5,000 robots) and far fewer at 26% (10,000 robots), where its rollouts leave the guide paths too little time",
    },
    Param {
        name: "lns_guide_weight",
        default: "0",
        doc: "k in 0..=64: LNS minimises a path's steps plus the actions still needed to the goal, and with k > 0 also the detour of the robot's traffic-flow guide path from where the path ends (k x hops to the guide path + the guide path's moves left - the hop distance), so re-planned paths keep the guide paths' lanes; 0 = plain distances (WPPL without a guidance graph)",
    },
    PIBT_PARAMS[8],
    PIBT_PARAMS[9],
    PIBT_PARAMS[10],
    PIBT_PARAMS[11],
    PIBT_PARAMS[12],
];

/// Windowed PIBT refined by LNS in the planner registry ([`crate::window_lns`]).
pub const LNS_ENTRY: PlannerEntry<LifelongProblem> = PlannerEntry {
    name: "lifelong-lns",
    about: "lifelong windowed planning: PIBT rolled out W steps (or the last plan shifted), refined by large neighbourhood search within the step's time (WPPL, the LoRR 2023 winner; Jiang et al., SoCS 2024; Li et al., AAAI 2022)",
    params: &LNS_PARAMS,
    build: |p| Ok(Box::new(build(LNS_ENTRY.name, p)?)),
};

/// The `-p` options of the lifelong planners that make their scheduler.
pub const SCHEDULER_PARAMS: [&str; 5] = [
    "scheduler",
    "hungarian_max",
    "chain_weight",
    "reassign_margin",
    "lookahead",
];

/// The scheduler the lifelong planners build from `given` `-p` options, only those of
/// [`SCHEDULER_PARAMS`] (others are refused), with `lifelong-pibt`'s defaults (`greedy`); what
/// `mrpp info --lorr P.json --lifelong --steps N --reference-scheduler ...` takes its congestion-free
/// reference with.
///
/// # Errors
/// An unknown option or a value out of its range.
pub fn scheduler_from(given: &[(String, String)]) -> mrpp_core::Result<Scheduler> {
    let declared: Vec<Param> = PIBT_PARAMS
        .iter()
        .filter(|p| SCHEDULER_PARAMS.contains(&p.name))
        .copied()
        .collect();
    scheduler_of(&mrpp_core::Params::resolve("scheduler", &declared, given)?)
}

fn scheduler_of(p: &mrpp_core::Params) -> mrpp_core::Result<Scheduler> {
    Ok(Scheduler {
        kind: match p.choice("scheduler", &["greedy", "hungarian", "matching"])? {
            0 => SchedulerKind::Greedy,
            1 => SchedulerKind::Hungarian,
            _ => SchedulerKind::Matching,
        },
        hungarian_max: p.get_in("hungarian_max", 1..=5000)?,
        chain_weight: p.get_in("chain_weight", 0.0..=10.0)?,
        reassign_margin: p.get_in("reassign_margin", 0..=1000)?,
        lookahead: p.get_in("lookahead", 0..=1000)?,
    })
}

/// The planner of either entry from its checked parameters.
fn build(name: &'static str, p: &mrpp_core::Params) -> mrpp_core::Result<LifelongPibt> {
    Ok(LifelongPibt {
        name,
        scheduler: scheduler_of(p)?,
        guidance: match p.choice("guidance", &["auto", "none", "traffic-flow"])? {
            0 => Guidance::Auto,
            1 => Guidance::None,
            _ => Guidance::TrafficFlow,
        },
        guide_replans: p.get_in("guide_replans", 0..=1_000_000)?,
        turn_distances: p.choice("distances", &["hops", "turns"])? == 1,
        hold: p.choice("commitment", &["hold", "prefer"])? == 0,
        tables: match p.choice("distance_tables", &["auto", "exact", "manhattan"])? {
            0 => TableKind::Auto,
            1 => TableKind::Exact,
            _ => TableKind::Manhattan,
        },
        lns: match p.get_in("window", 0..=64)? {
            0 => None,
            window => Some(LnsOptions {
                window,
                iterations: p.get_in("lns_iterations", 0..=10_000_000)?,
                group: p.get_in("lns_group", 1..=1000)?,
                max_density: if name == LNS_ENTRY.name {
                    p.get_in("lns_max_density", 0.0..=1.0)?
                } else {
                    1.0
                },
                guide_weight: if name == LNS_ENTRY.name {
                    p.get_in("lns_guide_weight", 0..=64)?
                } else {
                    0
                },
            }),
        },
    })
}

/// Whether lifelong-pibt follows guide paths ([`crate::guide_paths`]).
///
/// On the start kit's five example problems at 300 steps (docs/performance.md), guide paths
/// finished 5-53% more tasks on the three where the robots cover 3.7-13% of the free cells
/// (random, sortation, warehouse) and 6-9% fewer on the two sparse ones (0.5-1.2%: paris,
/// brc202d), where congestion costs turn paths aside for little traffic; `Auto` draws the line
/// at [`AUTO_DENSITY`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Guidance {
    /// `TrafficFlow` when robots / free cells >= [`AUTO_DENSITY`], else `None`.
    Auto,
    /// Candidates ranked by distance to the goal.
    None,
    /// Candidates ranked by distance along a traffic-flow guide path.
    TrafficFlow,
}

/// The share of free cells covered by robots from which `Guidance::Auto` uses guide paths.
pub const AUTO_DENSITY: f64 = 0.02;

/// Rolling PIBT with rotations ([`crate::rotation_pibt`]), a scheduler, and optionally guide
/// paths ([`crate::guide_paths`]).
#[derive(Debug, Clone, Copy)]
pub struct LifelongPibt {
    /// The registry name it was built under.
    pub name: &'static str,
    pub scheduler: Scheduler,
    /// Whether robots follow traffic-flow guide paths.
    pub guidance: Guidance,
    /// Guide paths re-planned per step ([`GuidePaths::replans`]).
    pub guide_replans: usize,
    /// Under `MAPF_T`, rank cells by rotation-aware distances ([`TurnDistances`]).
    pub turn_distances: bool,
    /// Under `MAPF_T`, keep the cell a robot turned towards reserved
    /// ([`RotationPibt::hold`]).
    pub hold: bool,
    /// Exact distance tables or Manhattan distances ([`crate::distances`], "Large maps").
    /// Rotation-aware tables are built only with exact ones.
    pub tables: TableKind,
    /// Plan a window ahead and refine it by LNS ([`crate::window_lns`]); `None`: one PIBT step.
    pub lns: Option<LnsOptions>,
}

impl Planner<LifelongProblem> for LifelongPibt {
    fn name(&self) -> &str {
        self.name
    }

    fn plan(&self, problem: &LifelongProblem, ctx: &Ctx) -> Result<Trace, Unsolved> {
        let vertices = problem.map().graph().num_vertices();
        let n = problem.starts().len();
        let mut pibt = RotationPibt::new(n, vertices, ctx.seed);
        pibt.hold = self.hold;
        let density = n as f64 / vertices.max(1) as f64;
        let mut windowed = self
            .lns
            .filter(|o| density <= o.max_density)
            .map(|o| WindowLns::new(problem, o, ctx.seed));
        let guided = match self.guidance {
            Guidance::None => false,
            Guidance::TrafficFlow => true,
            Guidance::Auto => n as f64 >= AUTO_DENSITY * vertices as f64,
        };
        let mut guide = guided.then(|| GuidePaths::new(problem.map(), n, self.guide_replans));
        let dist = Distances::of_kind(self.tables, vertices, n, DEFAULT_BUDGET);
        // Built during preprocessing and used by every step: shared by the two closures.
        let turn_tables = std::cell::RefCell::new(
            ((self.turn_distances || windowed.is_some())
                && problem.model() == ActionModel::MapfT
                && dist.is_exact())
            .then(|| TurnDistances::new(problem.map(), DEFAULT_BUDGET / 2)),
        );
        let mut cells = Vec::with_capacity(n);
        let prepare = |targets: &[VertexId], deadlines: &[Deadline]| {
            if let Some(t) = turn_tables.borrow_mut().as_mut() {
                t.warm(targets, deadlines);
            }
        };
        run(problem, ctx, dist, prepare, |sim, dist, budget| {
            let started = Instant::now();
            let proposal = self
                .scheduler
                .propose(sim, dist, Deadline::after(budget / 2));
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
            if let Some(g) = guide.as_mut() {
                cells.clear();
                cells.extend(sim.states.iter().map(|s| s.vertex));
                // Leave a tenth of the budget for PIBT, or with a window 40% for the rollout
                // and LNS.
                let share = if windowed.is_some() { 6 } else { 9 };
                let left = (budget * share / 10).saturating_sub(started.elapsed());
                let graph = problem.map().graph();
                g.update(&cells, &goals, sim.t, dist, graph, Deadline::after(left));
            }
            let mut turns = turn_tables.borrow_mut();
            let actions = match windowed.as_mut() {
                None => pibt.step(
                    problem,
                    &sim.states,
                    &goals,
                    dist,
                    guide.as_mut(),
                    turns.as_mut().filter(|_| self.turn_distances),
                ),
                Some(w) => {
                    // LNS until 85% of the budget has passed.
                    let left = (budget * 85 / 100).saturating_sub(started.elapsed());
                    // The errand after each robot's next one, in the same task.
                    let seconds: Vec<VertexId> = proposal
                        .iter()
                        .map(|task| {
                            task.and_then(|k| {
                                let t = &sim.tasks[k];
                                t.errands.get(t.done + 1).copied()
                            })
                            .unwrap_or(VertexId::MAX)
                        })
                        .collect();
                    w.step(
                        problem,
                        &sim.states,
                        &goals,
                        &seconds,
                        &mut pibt,
                        dist,
                        guide.as_mut(),
                        turns.as_mut(),
                        self.turn_distances,
                        Deadline::after(left),
                    )
                }
            };
            (actions, proposal)
        })
    }
}

/// What one planner call returns: one action per robot and the proposed assignment.
pub type Answer = (Vec<Action>, Vec<Option<usize>>);

/// Runs the kit's loop (module doc) with `call` as scheduler and planner: given the state, the
/// distance tables (`dist`, warmed here during preprocessing) and the step's budget, it answers.
/// `prepare` is called during preprocessing
/// with each batch of errand cells whose hop tables were built, and the deadlines that bound it
/// (a planner's own tables, e.g. [`TurnDistances`]).
///
/// # Errors
/// [`Unsolved::Invalid`] when an answer breaks the rules (a bug in the planner).
pub fn run(
    problem: &LifelongProblem,
    ctx: &Ctx,
    mut dist: Distances,
    mut prepare: impl FnMut(&[VertexId], &[Deadline]),
    mut call: impl FnMut(&Simulation<'_>, &mut Distances, Duration) -> Answer,
) -> Result<Trace, Unsolved> {
    let n = problem.starts().len();
    let steps = problem.steps();
    let budget = problem.step_time().max(Duration::from_micros(1));
    let graph = problem.map().graph();
    // Preprocessing (the kit's `initialize`): distance tables of the errands of the tasks
    // revealed first (the pool, then as many again as there are robots), in the order they will
    // be revealed, within the preprocessing time and the tables' budget.
    // With Manhattan distances there is nothing to build.
    let started = Instant::now();
    if dist.is_exact() {
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
            prepare(chunk, &[prep, ctx.deadline]);
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
    } else {
        ctx.report(Progress {
            stage: "preprocessing",
            done: 0,
            total: 0,
            note: "Manhattan distances: no tables (distance_tables)".into(),
        });
    }
    if let Some(model) = problem.execution() {
        let preprocess_time = started.elapsed().as_secs_f64();
        let mut trace = crate::execution::run_ticks(problem, model, ctx, &mut dist, call)?;
        trace.preprocess_time = preprocess_time;
        return Ok(trace);
    }
    let mut run = Run::new(problem);
    run.trace.preprocess_time = started.elapsed().as_secs_f64();
    while run.sim.t < steps && !ctx.deadline.expired() {
        let started = Instant::now();
        let (actions, proposal) = call(&run.sim, &mut dist, budget);
        let elapsed = started.elapsed();
        let late = (elapsed.as_nanos() / budget.as_nanos()).min(u128::from(steps)) as u32;
        run.late(late);
        run.trace.planner_times.push(elapsed.as_secs_f64());
        if run.sim.t >= steps {
            break;
        }
        run.advance(&actions, &proposal)?;
        let t = run.sim.t;
        if t.is_multiple_of(10) || t == steps {
            ctx.report(Progress {
                stage: "step",
                done: u64::from(t),
                total: u64::from(steps),
                note: format!("{} tasks finished", run.sim.finished),
            });
        }
    }
    Ok(run.trace)
}

/// A run in progress: the simulation and its trace so far. [`run`] drives one with mrpp's
/// planners; bindings drive one with a planner of their own (one [`Run::advance`] per step).
#[derive(Debug, Clone)]
pub struct Run<'p> {
    /// The system state.
    pub sim: Simulation<'p>,
    /// What was executed so far (a valid trace for the steps done).
    pub trace: Trace,
    last_proposal: Vec<Option<usize>>,
}

impl<'p> Run<'p> {
    /// Step 0 of `problem`: nothing executed yet.
    pub fn new(problem: &'p LifelongProblem) -> Self {
        let n = problem.starts().len();
        let steps = problem.steps();
        Run {
            sim: Simulation::new(problem),
            trace: Trace {
                actions: vec![Vec::with_capacity((steps as usize).min(4096)); n],
                planned: vec![Vec::with_capacity((steps as usize).min(4096)); n],
                ..Trace::default()
            },
            last_proposal: vec![None; n],
        }
    }

    /// `steps` late steps (the planner ran over its budget; module doc): nobody moves, no task
    /// update; none beyond the horizon.
    pub fn late(&mut self, steps: u32) {
        let n = self.sim.states.len();
        for _ in 0..steps {
            if self.sim.t >= self.sim.problem().steps() {
                break;
            }
            self.trace.late_steps.push(self.sim.t);
            for i in 0..n {
                self.trace.actions[i].push(Action::NoAction);
                self.trace.planned[i].push(Action::NoAction);
            }
            self.sim.idle_step();
        }
    }

    /// Executes one step: `actions` (one per robot, checked by the kit's rules), then the task
    /// update with `proposal` (each robot's task, or `None`; a refused proposal keeps the old
    /// assignment and is recorded, as in the kit).
    ///
    /// # Errors
    /// [`Unsolved::Invalid`] naming the step, the rule and the two robots when the joint
    /// action breaks a rule (nothing is executed), or when `actions` or `proposal` do not have
    /// one entry per robot.
    pub fn advance(
        &mut self,
        actions: &[Action],
        proposal: &[Option<usize>],
    ) -> Result<(), Unsolved> {
        let n = self.sim.states.len();
        if actions.len() != n || proposal.len() != n {
            return Err(Unsolved::Invalid(format!(
                "step {}: {} actions and {} tasks for {n} robots (one each)",
                self.sim.t + 1,
                actions.len(),
                proposal.len()
            )));
        }
        let next = self.sim.check_actions(actions).map_err(|e| {
            let who = match e.agents() {
                (a, -1) => format!("robot {a}"),
                (a, b) => format!("robots {a} and {b}"),
            };
            Unsolved::Invalid(format!(
                "step {}: the joint action breaks a rule: {} ({who})",
                self.sim.t + 1,
                e.message()
            ))
        })?;
        for (i, &a) in actions.iter().enumerate() {
            self.trace.actions[i].push(a);
            self.trace.planned[i].push(a);
        }
        self.sim.step(next);
        let t = self.sim.t;
        for (agent, (&now, &before)) in proposal.iter().zip(&self.last_proposal).enumerate() {
            if now != before {
                self.trace.proposed_schedule.push(Assign {
                    t,
                    agent,
                    task: now,
                });
            }
        }
        self.last_proposal.clear();
        self.last_proposal.extend_from_slice(proposal);
        let applied = match self.sim.check_schedule(proposal) {
            Ok(()) => Some(proposal),
            Err(e) => {
                let (task, agent1, agent2) = e.ids();
                self.trace.schedule_errors.push(ScheduleErrorRecord {
                    task,
                    agent1,
                    agent2,
                    t,
                    message: e.message().to_string(),
                });
                None
            }
        };
        for (agent, task) in self.sim.update_tasks(applied) {
            self.trace.schedule.push(Assign { t, agent, task });
        }
        Ok(())
    }
}
