//! The lifelong problem (a League of Robot Runners problem run for a horizon under an action
//! model and a planning time per step), its plan (the executed [`Trace`]), its validator and its
//! metrics.

use std::path::Path;
use std::sync::Arc;
use std::time::Duration;

use serde::Serialize;

use mrpp_core::error::Result;
use mrpp_core::mapf::graph::VertexId;
use mrpp_mapf::GridMap;
use mrpp_mapf::lorr_files::{self, LorrFiles};

use crate::execution::{ExecutionModel, TickRecord};
use crate::model::{Action, ActionModel};
use crate::sim::Simulation;

/// Default horizon in steps when neither the user nor the problem sets one.
pub const DEFAULT_STEPS: u32 = 1000;

/// Default planning time per step (the kit's `--planTimeLimit` default, 1000 ms).
pub const DEFAULT_STEP_TIME: Duration = Duration::from_secs(1);

/// Default preprocessing time before the first step (the kit's `--preprocessTimeLimit`
/// default, 30 000 ms).
pub const DEFAULT_PREPROCESS_TIME: Duration = Duration::from_secs(30);

/// A lifelong problem: a LoRR problem's map, robots and task file, run for `steps` steps under
/// `model`, with `step_time` for each planner call.
#[derive(Debug, Clone)]
pub struct LifelongProblem {
    files: Arc<LorrFiles>,
    model: ActionModel,
    steps: u32,
    step_time: Duration,
    preprocess_time: Duration,
    execution: Option<ExecutionModel>,
}

impl LifelongProblem {
    /// The problem of `files` under `model` for `steps` steps (at least 1) with `step_time` per
    /// planner call.
    pub fn new(files: LorrFiles, model: ActionModel, steps: u32, step_time: Duration) -> Self {
        LifelongProblem {
            files: Arc::new(files),
            model,
            steps: steps.max(1),
            step_time,
            preprocess_time: DEFAULT_PREPROCESS_TIME,
            execution: None,
        }
    }

    /// The same problem run under the 2026 execution model ([`crate::execution`]): its
    /// horizon (`steps`) then counts ticks, and `step_time` is the planning period's time.
    pub fn with_execution(mut self, model: ExecutionModel) -> Self {
        self.execution = Some(model);
        self
    }

    /// The execution model, when the run is in ticks.
    pub fn execution(&self) -> Option<&ExecutionModel> {
        self.execution.as_ref()
    }

    /// The same problem with `limit` for preprocessing (before step 0; not counted in any step).
    pub fn with_preprocess_time(mut self, limit: Duration) -> Self {
        self.preprocess_time = limit;
        self
    }

    /// Preprocessing time before the first step.
    pub fn preprocess_time(&self) -> Duration {
        self.preprocess_time
    }

    /// Reads a LoRR problem JSON (`mrpp_mapf::lorr_files::load`) as a lifelong problem.
    ///
    /// # Errors
    /// The file, line and rule of the first problem in the files.
    pub fn load(path: &Path, model: ActionModel, steps: u32, step_time: Duration) -> Result<Self> {
        Ok(Self::new(lorr_files::load(path)?, model, steps, step_time))
    }

    /// The files the problem was read from.
    pub fn files(&self) -> &LorrFiles {
        &self.files
    }
    /// The map.
    pub fn map(&self) -> &GridMap {
        &self.files.map
    }
    /// Each robot's start vertex.
    pub fn starts(&self) -> &[VertexId] {
        &self.files.starts
    }
    /// The task file's tasks, cycled by the reveal.
    pub fn task_file(&self) -> &[Vec<VertexId>] {
        &self.files.tasks
    }
    /// Tasks kept open at once.
    pub fn reveal_pool(&self) -> usize {
        self.files.reveal_pool()
    }
    /// The action model.
    pub fn model(&self) -> ActionModel {
        self.model
    }
    /// The horizon in steps.
    pub fn steps(&self) -> u32 {
        self.steps
    }
    /// Planning time per planner call.
    pub fn step_time(&self) -> Duration {
        self.step_time
    }
}

/// A schedule change: from step `t`'s task update on, robot `agent` holds `task` (`None`: none).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Assign {
    pub t: u32,
    pub agent: usize,
    pub task: Option<usize>,
}

/// A refused joint action: LoRR's `errors` tuple `[agent1, agent2, t, message]`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct StepError {
    pub agent1: i64,
    pub agent2: i64,
    pub t: u32,
    pub message: String,
}

/// A refused schedule: LoRR's `scheduleErrors` tuple `[task, agent1, agent2, t, message]`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ScheduleErrorRecord {
    pub task: i64,
    pub agent1: i64,
    pub agent2: i64,
    pub t: u32,
    pub message: String,
}

/// A lifelong run as executed: the plan of the lifelong family. The validator replays
/// [`Trace::actions`] and [`Trace::schedule`] from the start; the rest is the record LoRR's output
/// keeps (what the planner proposed, its time per call, what was refused).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Trace {
    /// `actions[i][k]`: robot `i`'s executed action at step `k` (LoRR's `actualPaths`).
    pub actions: Vec<Vec<Action>>,
    /// `planned[i][k]`: the action the planner proposed (`plannerPaths`; `T` on a late step).
    pub planned: Vec<Vec<Action>>,
    /// Applied schedule changes in order (`actualSchedule`).
    pub schedule: Vec<Assign>,
    /// Proposed schedule changes in order, refused ones included (`plannerSchedule`).
    pub proposed_schedule: Vec<Assign>,
    /// Steps (0-based) on which the planner was late: nobody moved, no task update.
    pub late_steps: Vec<u32>,
    /// Wall time of each planner call in seconds, late steps included (`plannerTimes`).
    pub planner_times: Vec<f64>,
    /// Refused joint actions (`errors`).
    pub errors: Vec<StepError>,
    /// Refused schedules (`scheduleErrors`).
    pub schedule_errors: Vec<ScheduleErrorRecord>,
    /// Wall time of the preprocessing before step 0, seconds.
    pub preprocess_time: f64,
    /// Under the 2026 execution model ([`crate::execution`]): the steps are ticks, and this
    /// holds what else was executed (delays, ticks per action, footprints).
    pub ticks: Option<TickRecord>,
}

impl Trace {
    /// Steps executed.
    pub fn steps(&self) -> u32 {
        self.actions.first().map_or(0, |a| a.len() as u32)
    }
}

/// What a valid trace measures.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LifelongMetrics {
    /// Tasks whose last errand was done within the run (LoRR's `numTaskFinished`).
    pub tasks_finished: usize,
    /// Errands done.
    pub errands: usize,
    /// Steps executed.
    pub steps: u32,
    /// Tasks finished per step.
    pub throughput: f64,
    /// Refused joint actions (`numPlannerErrors`).
    pub planner_errors: usize,
    /// Refused schedules (`numScheduleErrors`).
    pub schedule_errors: usize,
    /// Steps lost to a late planner (`numEntryTimeouts`).
    pub late_steps: usize,
    /// Mean planner time per call, milliseconds (as recorded, not validated).
    pub mean_planner_ms: f64,
    /// Largest planner time of a call, milliseconds (as recorded).
    pub max_planner_ms: f64,
}

/// The first rule a trace breaks.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum LifelongViolation {
    #[error("the trace has {got} robots, the problem {want}")]
    Robots { got: usize, want: usize },
    #[error("robot {agent} has {got} steps, robot 0 has {want}")]
    Ragged {
        agent: usize,
        got: usize,
        want: usize,
    },
    #[error("the trace runs {got} steps, past the horizon of {horizon}")]
    PastHorizon { got: u32, horizon: u32 },
    #[error("step {step}: robot {agent} acts on a late step (only `T` is allowed there)")]
    ActsWhenLate { step: u32, agent: usize },
    #[error("step {step}: {message} (robots {agent1} and {agent2})")]
    Action {
        step: u32,
        message: &'static str,
        agent1: i64,
        agent2: i64,
    },
    #[error(
        "step {step}: schedule change of robot {agent}: {message} (task {task}, robots {agent1} and {agent2})"
    )]
    Schedule {
        step: u32,
        agent: usize,
        message: &'static str,
        task: i64,
        agent1: i64,
        agent2: i64,
    },
    #[error("tick {tick}: robot {agent} acts while delayed (only `W` is allowed then)")]
    MovesWhenDelayed { tick: u32, agent: usize },
    #[error("tick {tick}: the footprints of robots {agent1} and {agent2} overlap")]
    Footprints {
        tick: u32,
        agent1: usize,
        agent2: usize,
    },
    #[error("schedule change {index} is out of order or past the run (step {step})")]
    ScheduleOrder { index: usize, step: u32 },
}

impl mrpp_core::Problem for LifelongProblem {
    type Plan = Trace;
    type Metrics = LifelongMetrics;
    type Violation = LifelongViolation;

    fn num_agents(&self) -> usize {
        self.starts().len()
    }

    fn validate(&self, trace: &Trace) -> std::result::Result<LifelongMetrics, LifelongViolation> {
        let sim = replay(self, trace, |_| {})?;
        let times = &trace.planner_times;
        Ok(LifelongMetrics {
            tasks_finished: sim.finished,
            errands: sim.events.len(),
            steps: sim.t,
            throughput: if sim.t == 0 {
                0.0
            } else {
                sim.finished as f64 / f64::from(sim.t)
            },
            planner_errors: trace.errors.len(),
            schedule_errors: trace.schedule_errors.len(),
            late_steps: trace
                .ticks
                .as_ref()
                .map_or(trace.late_steps.len(), |r| r.entry_timeouts as usize),
            mean_planner_ms: if times.is_empty() {
                0.0
            } else {
                1e3 * times.iter().sum::<f64>() / times.len() as f64
            },
            max_planner_ms: 1e3 * times.iter().copied().fold(0.0, f64::max),
        })
    }
}

/// The trace's length, after checking it has one action list per robot, all of one length, no
/// longer than the horizon (steps or ticks).
///
/// # Errors
/// [`LifelongViolation::Robots`], [`LifelongViolation::Ragged`], [`LifelongViolation::PastHorizon`].
pub(crate) fn check_shape(
    problem: &LifelongProblem,
    trace: &Trace,
) -> std::result::Result<u32, LifelongViolation> {
    let n = problem.starts().len();
    if trace.actions.len() != n {
        return Err(LifelongViolation::Robots {
            got: trace.actions.len(),
            want: n,
        });
    }
    let steps = trace.steps();
    for (agent, a) in trace.actions.iter().enumerate() {
        if a.len() != steps as usize {
            return Err(LifelongViolation::Ragged {
                agent,
                got: a.len(),
                want: steps as usize,
            });
        }
    }
    if steps > problem.steps() {
        return Err(LifelongViolation::PastHorizon {
            got: steps,
            horizon: problem.steps(),
        });
    }
    Ok(steps)
}

/// The recorded schedule changes stamped `t` (taken from `changes`, in order), applied to the
/// current assignment and checked by the kit's rules; `None` when there are none.
///
/// # Errors
/// [`LifelongViolation::ScheduleOrder`] for a change out of order or of no robot,
/// [`LifelongViolation::Schedule`] for a schedule the rules refuse.
pub(crate) fn scheduled_at<'a>(
    sim: &Simulation<'_>,
    changes: &mut std::iter::Peekable<std::iter::Enumerate<std::slice::Iter<'a, Assign>>>,
    t: u32,
) -> std::result::Result<Option<Vec<Option<usize>>>, LifelongViolation> {
    let n = sim.states.len();
    let mut proposal = sim.assignment.clone();
    let mut any = false;
    while let Some(&(index, c)) = changes.peek() {
        if c.t != t {
            if c.t < t || c.agent >= n {
                return Err(LifelongViolation::ScheduleOrder { index, step: c.t });
            }
            break;
        }
        if c.agent >= n {
            return Err(LifelongViolation::ScheduleOrder { index, step: c.t });
        }
        proposal[c.agent] = c.task;
        any = true;
        changes.next();
    }
    if !any {
        return Ok(None);
    }
    sim.check_schedule(&proposal).map_err(|e| {
        let (task, agent1, agent2) = e.ids();
        LifelongViolation::Schedule {
            step: t,
            agent: agent1.max(0) as usize,
            message: e.message(),
            task,
            agent1,
            agent2,
        }
    })?;
    Ok(Some(proposal))
}

/// Replays `trace` from the start under the kit's rules (the validator), calling `after_step`
/// with the state after each step's task update; returns the final state. A trace in ticks
/// is replayed tick by tick ([`crate::execution::replay_ticks`]).
///
/// # Errors
/// The first rule the trace breaks.
pub fn replay<'p>(
    problem: &'p LifelongProblem,
    trace: &Trace,
    mut after_step: impl FnMut(&Simulation<'p>),
) -> std::result::Result<Simulation<'p>, LifelongViolation> {
    if let Some(record) = &trace.ticks {
        return crate::execution::replay_ticks(problem, trace, record, after_step);
    }
    let n = problem.starts().len();
    let steps = check_shape(problem, trace)?;
    let late: rustc_hash::FxHashSet<u32> = trace.late_steps.iter().copied().collect();
    let mut sim = Simulation::new(problem);
    let mut changes = trace.schedule.iter().enumerate().peekable();
    let mut joint = vec![Action::Wait; n];
    for k in 0..steps {
        for (i, a) in trace.actions.iter().enumerate() {
            joint[i] = a[k as usize];
        }
        if late.contains(&k) {
            if let Some(agent) = joint.iter().position(|&a| a != Action::NoAction) {
                return Err(LifelongViolation::ActsWhenLate { step: k + 1, agent });
            }
            sim.idle_step();
            after_step(&sim);
            continue;
        }
        let next = sim.check_actions(&joint).map_err(|e| {
            let (agent1, agent2) = e.agents();
            LifelongViolation::Action {
                step: k + 1,
                message: e.message(),
                agent1,
                agent2,
            }
        })?;
        sim.step(next);
        // The schedule applied at this update: the assignment with this step's changes.
        let proposal = scheduled_at(&sim, &mut changes, sim.t)?;
        sim.update_tasks(proposal.as_deref());
        after_step(&sim);
    }
    if let Some((index, c)) = changes.next() {
        return Err(LifelongViolation::ScheduleOrder { index, step: c.t });
    }
    Ok(sim)
}

/// A problem for unit tests: `map` with robots on `starts` and `tasks`, `reveal` tasks per robot
/// open, 10 steps of 1 s under `model` (file names made up).
#[cfg(test)]
pub(crate) fn test_problem(
    map: mrpp_mapf::GridMap,
    starts: Vec<VertexId>,
    tasks: Vec<Vec<VertexId>>,
    reveal: f64,
    model: crate::model::ActionModel,
) -> LifelongProblem {
    use std::path::PathBuf;
    let files = mrpp_mapf::lorr_files::LorrFiles {
        path: PathBuf::from("p.json"),
        map_path: PathBuf::from("m.map"),
        agent_path: PathBuf::from("a.agents"),
        task_path: PathBuf::from("t.tasks"),
        map,
        start_lines: (0..starts.len()).collect(),
        starts,
        task_lines: (0..tasks.len()).collect(),
        tasks,
        num_tasks_reveal: reveal,
        version: "2024 LoRR".into(),
        json: serde_json::Value::Null,
    };
    LifelongProblem::new(files, model, 10, std::time::Duration::from_secs(1))
}
