//! Lifelong runs under the League of Robot Runners' 2026 execution model (start kit v3.1.0,
//! `src/CompetitionSystem.cpp` `simulate`, `src/Simulator.cpp`, `src/TaskManager.cpp`;
//! `docs/lorr-semantics.md` §2–§6 "K3"): two rates, delays, multi-tick actions.
//!
//! - **Ticks.** Time advances in ticks; each action takes `agentCounter` ticks
//!   ([`crate::ticks`]). Every tick: the executor says go or stop per robot
//!   ([`crate::executor`]); the delays of the tick are drawn (`delayConfig`, mrpp-exec's
//!   [`DelayGenerator`]: a held robot makes no progress); each robot asks for its next staged
//!   action when told to go and not held, else waits; the per-tick resolution makes robots wait
//!   rather than collide and records why; a staged action leaves the stage when the robot's
//!   cell or orientation changed; then the task update (errands completed by standing on them,
//!   tasks finished, new tasks revealed).
//! - **Planning.** The planner is called every `plan_every` ticks (the kit's
//!   `planCommTimeLimit / actionMoveTimeLimit`, 10 by default) with the planning period's time
//!   (`--step-time-limit`, the kit's `planCommTimeLimit`, 1 s). As in the kit it plans from the
//!   states the executor *predicts* at the end of what is staged, in parallel with execution:
//!   a plan asked for at tick `t` is staged at tick `t + plan_every`, and its schedule applied
//!   then. Where the kit runs the planner in a thread against the wall clock, mrpp calls it at
//!   tick `t` and stages its answer `plan_every` ticks later, so a run is reproducible from its
//!   seeds; a call that takes longer than its time is staged one period later per full period
//!   it used, and counted in `numEntryTimeouts` (the kit keeps that count at 0).
//! - **Multi-step plans.** mrpp's lifelong planners answer one step at a time; a plan is
//!   `actions per period + 1` of their steps rolled out from the predicted states (as the kit's
//!   default planner rolls out PIBT), each with an equal share of the period's time. The
//!   schedule is the first step's. With `k_robust` > 0 each rolled-out step is filtered to keep
//!   that many actions of slack between robots passing through a cell ([`crate::k_robust`]).
//! - **Schedules** are repaired as the kit repairs them (`TaskManager::validate_task_assignment`):
//!   a finished or twice-proposed task is dropped from the later robot, a robot that has opened
//!   a task keeps it, a task opened by another robot is dropped; each repair is a schedule error.
//!   A robot that finishes its task between the call and the staging loses its entry in the
//!   pending schedule (as in the kit).
//!
//! The executed trace holds, per tick and robot, the executed action (`W` when held, stopped or
//! delayed) and the asked one; the delays; the planner's schedule changes; and why robots were
//! made to wait (`errors`: mrpp records every tick's, the kit only the last tick's).
//! [`replay_ticks`] is its validator: it replays the ticks from the start, checks that a
//! delayed robot does not progress, that no move leaves the map or enters an obstacle and that
//! no two footprints overlap at any instant, and recounts the tasks.

use std::collections::VecDeque;
use std::path::Path;
use std::time::{Duration, Instant};

use serde_json::Value;

use mrpp_core::error::{Error, Result};
use mrpp_core::{Ctx, Progress, Unsolved};
use mrpp_exec::delays::{DelayConfig, DelayGenerator, DurationModel, EventModel};
use mrpp_mapf::lorr_files::LorrFiles;

use crate::distances::Distances;
use crate::executor::{Executor, ExecutorKind};
use crate::k_robust::KRobust;
use crate::model::{Action, State};
use crate::problem::{
    Assign, LifelongProblem, LifelongViolation, ScheduleErrorRecord, StepError, Trace, check_shape,
    scheduled_at,
};
use crate::runner::Answer;
use crate::sim::Simulation;
use crate::ticks::{Bins, Resolver, TickState, after_tick, first_overlap, is_wait};

/// Ticks between planner calls by default (the kit's `planCommTimeLimit` 1000 ms over its
/// `actionMoveTimeLimit` 100 ms).
pub const DEFAULT_PLAN_EVERY: u32 = 10;

/// The 2026 execution model's settings (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct ExecutionModel {
    /// Ticks per action (`agentCounter`, default 10 as in the kit), at least 1.
    pub agent_counter: u32,
    /// Side of a robot's square in cells (`agentSize`), in (0, 1].
    pub agent_size: f64,
    /// The delays (`delayConfig`).
    pub delays: DelayConfig,
    /// The delays' seed (`delayConfig.seed`; mrpp's random stream, not the kit's).
    pub delay_seed: u64,
    /// Ticks between planner calls.
    pub plan_every: u32,
    /// The executor.
    pub executor: ExecutorKind,
    /// Actions of slack the multi-step plans keep ([`crate::k_robust`]; 0: plans as the planner
    /// made them).
    pub k_robust: u32,
}

impl ExecutionModel {
    /// Actions a plan covers and the executor stages: the actions of one planning period, plus
    /// one (the kit's `window`).
    pub fn window(&self) -> usize {
        (self.plan_every / self.agent_counter.max(1)) as usize + 1
    }

    /// The model a LoRR problem file sets: `agentCounter` (default 10), `agentSize` (default 1)
    /// and `delayConfig` (default: no delays; the kit requires it), with the kit's executor,
    /// planning every [`DEFAULT_PLAN_EVERY`] ticks.
    ///
    /// # Errors
    /// The problem file and the key: a counter that is not a whole number of at least 1, a
    /// size outside (0, 1], a `delayConfig` with a missing or mistyped field or one the kit
    /// refuses (`p` outside [0, 1], `minDelay` of 0, `minDelay` above `maxDelay`, ratios out of
    /// range).
    pub fn of_problem(files: &LorrFiles) -> Result<Self> {
        let path = &files.path;
        let json = &files.json;
        let agent_counter = match json.get("agentCounter") {
            None => 10,
            Some(v) => v
                .as_u64()
                .filter(|&c| (1..=1000).contains(&c))
                .ok_or_else(|| {
                    Error::invalid(
                        path,
                        format!(
                            "`agentCounter` is {v}: expected a whole number of ticks, 1 to 1000"
                        ),
                    )
                })? as u32,
        };
        let agent_size = match json.get("agentSize") {
            None => 1.0,
            Some(v) => v.as_f64().filter(|&s| s > 0.0 && s <= 1.0).ok_or_else(|| {
                Error::invalid(
                    path,
                    format!("`agentSize` is {v}: expected a number in (0, 1] (cells)"),
                )
            })?,
        };
        let (delays, delay_seed) = match json.get("delayConfig") {
            None => (DelayConfig::none(), 0),
            Some(v) => delay_config(v, path)?,
        };
        Ok(ExecutionModel {
            agent_counter,
            agent_size,
            delays,
            delay_seed,
            plan_every: DEFAULT_PLAN_EVERY,
            executor: ExecutorKind::Tpg,
            k_robust: 0,
        })
    }
}

/// The `delayConfig` object the kit reads for `delays` and `seed` (its eight fields; the
/// inverse of what [`ExecutionModel::of_problem`] reads).
pub fn delay_config_json(delays: &DelayConfig, seed: u64) -> Value {
    let (duration, mean, std) = match delays.duration_model {
        DurationModel::Uniform => ("uniform", 0.5, 0.22),
        DurationModel::Gaussian {
            mean_ratio,
            std_ratio,
        } => ("gaussian", mean_ratio, std_ratio),
    };
    serde_json::json!({
        "seed": seed,
        "minDelay": delays.min_delay,
        "maxDelay": delays.max_delay,
        "eventModel": match delays.event_model {
            EventModel::Bernoulli => "bernoulli",
            EventModel::Poisson => "poisson",
        },
        "pDelay": delays.p_delay,
        "durationModel": duration,
        "gaussMeanRatio": mean,
        "gaussStdRatio": std,
    })
}

/// A `delayConfig` object and its seed (the kit's eight fields, all required).
fn delay_config(v: &Value, path: &Path) -> Result<(DelayConfig, u64)> {
    let field = |k: &str| {
        v.get(k).ok_or_else(|| {
            Error::invalid(
                path,
                format!("`delayConfig` has no `{k}` (the kit requires seed, minDelay, maxDelay, eventModel, pDelay, durationModel, gaussMeanRatio, gaussStdRatio)"),
            )
        })
    };
    let whole = |k: &str| -> Result<u64> {
        field(k)?
            .as_u64()
            .ok_or_else(|| Error::invalid(path, format!("`delayConfig.{k}` is not a whole number")))
    };
    let number = |k: &str| -> Result<f64> {
        field(k)?
            .as_f64()
            .ok_or_else(|| Error::invalid(path, format!("`delayConfig.{k}` is not a number")))
    };
    let text = |k: &str| -> Result<String> {
        field(k)?
            .as_str()
            .map(str::to_string)
            .ok_or_else(|| Error::invalid(path, format!("`delayConfig.{k}` is not a string")))
    };
    let seed = whole("seed")?;
    let event_model = match text("eventModel")?.as_str() {
        "bernoulli" => EventModel::Bernoulli,
        "poisson" => EventModel::Poisson,
        other => {
            return Err(Error::invalid(
                path,
                format!("`delayConfig.eventModel` is `{other}`: expected bernoulli or poisson"),
            ));
        }
    };
    let duration_model = match text("durationModel")?.as_str() {
        "uniform" => DurationModel::Uniform,
        "gaussian" => DurationModel::Gaussian {
            mean_ratio: number("gaussMeanRatio")?,
            std_ratio: number("gaussStdRatio")?,
        },
        other => {
            return Err(Error::invalid(
                path,
                format!("`delayConfig.durationModel` is `{other}`: expected uniform or gaussian"),
            ));
        }
    };
    let ticks = |k: &str| -> Result<u32> {
        u32::try_from(whole(k)?)
            .map_err(|_| Error::invalid(path, format!("`delayConfig.{k}` is too large")))
    };
    let cfg = DelayConfig {
        event_model,
        p_delay: number("pDelay")?,
        min_delay: ticks("minDelay")?,
        max_delay: ticks("maxDelay")?,
        duration_model,
    };
    cfg.check()
        .map_err(|e| Error::invalid(path, format!("`delayConfig`: {e}")))?;
    Ok((cfg, seed))
}

/// What an executed trace records beyond the step model's [`Trace`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TickRecord {
    /// Ticks per action.
    pub agent_counter: u32,
    /// Side of a robot's square, cells.
    pub agent_size: f64,
    /// Each robot's delays as `[first tick, first tick after]`.
    pub delays: Vec<Vec<[u64; 2]>>,
    /// Planner calls that took longer than their time (`numEntryTimeouts`).
    pub entry_timeouts: u32,
    /// The executor's name.
    pub executor: String,
    /// Ticks between planner calls.
    pub plan_every: u32,
}

/// The kit's schedule repair (module doc): the schedule to apply and the repairs made, at tick `t`.
fn repair(
    sim: &Simulation<'_>,
    proposal: &[Option<usize>],
    t: u32,
) -> (Vec<Option<usize>>, Vec<ScheduleErrorRecord>) {
    let mut out = proposal.to_vec();
    let mut errors = Vec::new();
    let mut holder = rustc_hash::FxHashMap::default();
    let error =
        |task: Option<usize>, a1: usize, a2: Option<usize>, message: &str| ScheduleErrorRecord {
            task: task.map_or(-1, |k| k as i64),
            agent1: a1 as i64,
            agent2: a2.map_or(-1, |a| a as i64),
            t,
            message: message.to_string(),
        };
    for (i, slot) in out.iter_mut().enumerate() {
        if let Some(k) = *slot
            && !sim.open.contains(&k)
        {
            errors.push(error(Some(k), i, None, "task already finished"));
            *slot = None;
        }
        if let Some(k) = *slot
            && let Some(&other) = holder.get(&k)
        {
            errors.push(error(
                Some(k),
                i,
                Some(other),
                "task is already assigned by the second agent at the same time",
            ));
            *slot = None;
        }
        if let Some(held) = sim.assignment[i]
            && sim.tasks[held].done > 0
            && *slot != Some(held)
        {
            errors.push(error(
                *slot,
                i,
                None,
                "schedule agent to another task who is already opened a task",
            ));
            *slot = Some(held);
        }
        if let Some(k) = *slot
            && sim.tasks[k].done > 0
            && sim.tasks[k].agent != Some(i)
        {
            errors.push(error(
                Some(k),
                i,
                sim.tasks[k].agent,
                "task is already opened by other agent",
            ));
            *slot = None;
        }
        if let Some(k) = *slot {
            holder.insert(k, i);
        }
    }
    (out, errors)
}

/// A multi-step plan (per robot its actions) and the schedule that comes with it.
type Planned = (Vec<Vec<Action>>, Vec<Option<usize>>);

/// A plan of `steps` steps rolled out by `call` from `predicted` (module doc, "Multi-step
/// plans"): per robot its actions, and the first step's schedule.
/// With `robust` (and `ticks`: the tick the plan is staged at, ticks per action), each step is
/// filtered to keep its slack ([`crate::k_robust`]) before it is checked.
#[allow(clippy::too_many_arguments)]
fn rollout(
    sim: &Simulation<'_>,
    predicted: &[State],
    steps: usize,
    budget: Duration,
    dist: &mut Distances,
    call: &mut impl FnMut(&Simulation<'_>, &mut Distances, Duration) -> Answer,
    mut robust: Option<&mut KRobust>,
    ticks: (u64, u32),
) -> std::result::Result<Planned, Unsolved> {
    let n = predicted.len();
    if let Some(r) = robust.as_deref_mut() {
        r.begin_rollout(&sim.states, predicted, ticks.0);
    }
    let mut v = sim.clone();
    v.step(predicted.to_vec());
    let mut plan = vec![Vec::with_capacity(steps); n];
    let mut first = None;
    let share = budget / steps.max(1) as u32;
    for k in 0..steps {
        let (mut actions, proposal) = call(&v, dist, share);
        if actions.len() != n || proposal.len() != n {
            return Err(Unsolved::Invalid(format!(
                "tick {}: the planner answered {} actions and {} tasks for {n} robots",
                sim.t,
                actions.len(),
                proposal.len()
            )));
        }
        if let Some(r) = robust.as_deref_mut() {
            let tick = ticks.0 + k as u64 * u64::from(ticks.1);
            r.filter_step(sim.problem().map(), &v.states, &mut actions, tick);
        }
        let next = v.check_actions(&actions).map_err(|e| {
            Unsolved::Invalid(format!(
                "tick {}, planned step {}: the plan breaks a rule: {} (robots {:?})",
                sim.t,
                k + 1,
                e.message(),
                e.agents()
            ))
        })?;
        for (p, &a) in plan.iter_mut().zip(&actions) {
            p.push(a);
        }
        v.step(next);
        let applied = v.check_schedule(&proposal).is_ok();
        v.update_tasks(applied.then_some(proposal.as_slice()));
        if first.is_none() {
            first = Some(proposal);
        }
    }
    Ok((plan, first.unwrap_or_else(|| sim.assignment.clone())))
}

/// Runs `problem` under `model` for its horizon in ticks (module doc), with `call` as
/// scheduler and planner (one step per call, as in [`crate::runner::run`]).
///
/// # Errors
/// [`Unsolved::Invalid`] when a planned step breaks a rule (a planner bug).
pub fn run_ticks(
    problem: &LifelongProblem,
    model: &ExecutionModel,
    ctx: &Ctx,
    dist: &mut Distances,
    mut call: impl FnMut(&Simulation<'_>, &mut Distances, Duration) -> Answer,
) -> std::result::Result<Trace, Unsolved> {
    let map = problem.map();
    let n = problem.starts().len();
    let ticks = problem.steps();
    let budget = problem.step_time().max(Duration::from_micros(1));
    let window = model.window();
    let plan_every = model.plan_every.max(1);
    let mut sim = Simulation::new(problem);
    let mut now: Vec<TickState> = sim.states.iter().map(|&s| TickState::idle(s)).collect();
    let mut staged: Vec<VecDeque<Action>> = vec![VecDeque::new(); n];
    let mut executor = Executor::new(model.executor, map, &sim.states, window);
    let mut delays = DelayGenerator::new(model.delays.clone(), n, model.delay_seed);
    let mut resolver = Resolver::new(map);
    let mut robust = KRobust::new(
        model.k_robust,
        model.agent_counter,
        map.graph().num_vertices(),
    );
    let mut trace = Trace {
        actions: vec![Vec::with_capacity((ticks as usize).min(1 << 16)); n],
        planned: vec![Vec::with_capacity((ticks as usize).min(1 << 16)); n],
        ..Trace::default()
    };
    let mut record = TickRecord {
        agent_counter: model.agent_counter,
        agent_size: model.agent_size,
        executor: model.executor.name().to_string(),
        plan_every,
        ..TickRecord::default()
    };
    let mut last_proposal: Vec<Option<usize>> = vec![None; n];
    // The plan asked for at tick 0 from the starts (the kit's initial plan), staged at once.
    let started = Instant::now();
    let mut pending = Some(rollout(
        &sim,
        &sim.states.clone(),
        window,
        budget,
        dist,
        &mut call,
        robust.as_mut(),
        (0, model.agent_counter),
    )?);
    trace.planner_times.push(started.elapsed().as_secs_f64());
    let mut due = 0u32;
    while sim.t < ticks && !ctx.deadline.expired() {
        let t = sim.t;
        if t == due
            && let Some((plan, proposal)) = pending.take()
        {
            for (agent, (&p, before)) in proposal.iter().zip(&mut last_proposal).enumerate() {
                if p != *before {
                    trace.proposed_schedule.push(Assign { t, agent, task: p });
                    *before = p;
                }
            }
            let (schedule, errors) = repair(&sim, &proposal, t);
            trace.schedule_errors.extend(errors);
            for (agent, task) in sim.apply_schedule(&schedule) {
                trace.schedule.push(Assign { t, agent, task });
            }
            let predicted = executor.process_new_plan(map, &plan, &mut staged, &now);
            let started = Instant::now();
            let next = rollout(
                &sim,
                &predicted,
                window,
                budget,
                dist,
                &mut call,
                robust.as_mut(),
                (u64::from(t + plan_every), model.agent_counter),
            )?;
            let elapsed = started.elapsed();
            trace.planner_times.push(elapsed.as_secs_f64());
            let late = (elapsed.as_nanos() / budget.as_nanos()).min(u128::from(ticks)) as u32;
            record.entry_timeouts += late;
            due = t.saturating_add(plan_every.saturating_mul(1 + late));
            pending = Some(next);
        }
        let go = executor.next_command(map, &staged, &now);
        delays.next_tick();
        let asked: Vec<Action> = (0..n)
            .map(|i| match staged[i].front() {
                Some(&a) if go[i] && !delays.delayed(i) => a,
                _ => Action::Wait,
            })
            .collect();
        let (done, held) =
            resolver.resolve(map, &now, &asked, model.agent_counter, model.agent_size);
        for h in held {
            trace.errors.push(StepError {
                agent1: h.agent as i64,
                agent2: h.other.map_or(-1, |o| o as i64),
                t: t + 1,
                message: h.message,
            });
        }
        for i in 0..n {
            let next = after_tick(map, now[i], done[i], model.agent_counter).unwrap_or(now[i]);
            if next.state != now[i].state {
                staged[i].pop_front();
            }
            if next.state.vertex != now[i].state.vertex
                && let Some(r) = robust.as_mut()
            {
                r.executed_move(i, now[i].state.vertex, u64::from(t) + 1);
            }
            now[i] = next;
            trace.actions[i].push(done[i]);
            trace.planned[i].push(asked[i]);
        }
        sim.step(now.iter().map(|s| s.state).collect());
        for agent in sim.complete_and_reveal() {
            if let Some((_, proposal)) = pending.as_mut() {
                proposal[agent] = None;
            }
        }
        let t = sim.t;
        if t.is_multiple_of(100) || t == ticks {
            ctx.report(Progress {
                stage: "tick",
                done: u64::from(t),
                total: u64::from(ticks),
                note: format!("{} tasks finished", sim.finished),
            });
        }
    }
    record.delays = delays.intervals.clone();
    // Delays drawn past the last tick executed are cut there.
    let end = u64::from(sim.t);
    for d in &mut record.delays {
        d.retain(|iv| iv[0] < end);
    }
    trace.ticks = Some(record);
    Ok(trace)
}

/// Replays an executed trace (module doc, last paragraph), calling `after_tick` with the state
/// after each tick's task update; returns the final state.
///
/// # Errors
/// The first rule the trace breaks.
pub fn replay_ticks<'p>(
    problem: &'p LifelongProblem,
    trace: &Trace,
    record: &TickRecord,
    mut after: impl FnMut(&Simulation<'p>),
) -> std::result::Result<Simulation<'p>, LifelongViolation> {
    replay_tick_states(problem, trace, record, |sim, _| after(sim))
}

/// [`replay_ticks`], also handing `after` every robot's state within its action at the end of
/// each tick (the cell it stands on until a move completes, the action in progress and its ticks
/// done): what a picture needs to draw robots between cells.
///
/// # Errors
/// As [`replay_ticks`].
pub fn replay_tick_states<'p>(
    problem: &'p LifelongProblem,
    trace: &Trace,
    record: &TickRecord,
    mut after: impl FnMut(&Simulation<'p>, &[TickState]),
) -> std::result::Result<Simulation<'p>, LifelongViolation> {
    let map = problem.map();
    let n = problem.starts().len();
    let ticks = check_shape(problem, trace)?;
    let counter = record.agent_counter.max(1);
    let mut sim = Simulation::new(problem);
    let mut now: Vec<TickState> = sim.states.iter().map(|&s| TickState::idle(s)).collect();
    let mut bins = Bins::new(map);
    let mut changes = trace.schedule.iter().enumerate().peekable();
    let held = |i: usize, t: u64| {
        record
            .delays
            .get(i)
            .is_some_and(|d| d.iter().any(|iv| iv[0] <= t && t < iv[1]))
    };
    let mut next = now.clone();
    for k in 0..ticks {
        // Schedule changes take effect before the tick's moves (when a plan is staged).
        if let Some(proposal) = scheduled_at(&sim, &mut changes, k)? {
            sim.apply_schedule(&proposal);
        }
        for i in 0..n {
            let a = trace.actions[i][k as usize];
            if held(i, u64::from(k)) && !is_wait(a) {
                return Err(LifelongViolation::MovesWhenDelayed {
                    tick: k + 1,
                    agent: i,
                });
            }
            if !a.belongs_to(problem.model()) {
                return Err(LifelongViolation::Action {
                    step: k + 1,
                    message: "unallowed move",
                    agent1: i as i64,
                    agent2: -1,
                });
            }
            next[i] = after_tick(map, now[i], a, counter).ok_or(LifelongViolation::Action {
                step: k + 1,
                message: "unallowed move",
                agent1: i as i64,
                agent2: -1,
            })?;
        }
        if let Some((a, b)) = first_overlap(map, &now, &next, counter, record.agent_size, &mut bins)
        {
            return Err(LifelongViolation::Footprints {
                tick: k + 1,
                agent1: a,
                agent2: b,
            });
        }
        std::mem::swap(&mut now, &mut next);
        sim.step(now.iter().map(|s| s.state).collect());
        sim.complete_and_reveal();
        after(&sim, &now);
    }
    if let Some((index, c)) = changes.next() {
        return Err(LifelongViolation::ScheduleOrder { index, step: c.t });
    }
    Ok(sim)
}
