//! The planner contract every family implements: a [`Problem`] (its plan, metrics and violation
//! types, and the one validator that judges plans), a [`Planner`] for it, the run context [`Ctx`]
//! (seed, deadline, progress), and [`solve`], which runs a planner and validates its plan exactly
//! once, returning the metrics with the plan ([`Solved`]) or why there is none ([`Unsolved`]).

use std::sync::Arc;
use std::time::{Duration, Instant};

/// A wall-clock limit that planners poll.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Deadline(Option<Instant>);

impl Deadline {
    /// No limit.
    pub fn none() -> Self {
        Deadline(None)
    }
    /// `limit` from now (no limit when `now + limit` overflows).
    pub fn after(limit: Duration) -> Self {
        Deadline(Instant::now().checked_add(limit))
    }
    /// The part `share` (in `0..=1`) of the time left (no limit stays no limit): e.g. a
    /// preparation step that may take half of what remains.
    pub fn share(&self, share: f64) -> Self {
        match self.0 {
            None => Deadline(None),
            Some(d) => {
                let left = d.saturating_duration_since(Instant::now());
                Deadline::after(left.mul_f64(share.clamp(0.0, 1.0)))
            }
        }
    }
    /// Whether the limit has passed, the process's memory limit is exceeded
    /// ([`crate::memory`]) or a stop was requested ([`request_stop`], e.g. Ctrl-C): every
    /// planner stops at any of them the same way (anytime planners with their best plan).
    pub fn expired(&self) -> bool {
        self.0.is_some_and(|d| Instant::now() >= d)
            || crate::memory::over_limit()
            || STOP.load(std::sync::atomic::Ordering::Relaxed)
    }
}

/// Set by [`request_stop`].
static STOP: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Asks every running planner to stop as at its deadline, for good (the binary calls it on
/// Ctrl-C): [`Deadline::expired`] answers `true` from now on, and [`solve`] reports
/// [`Unsolved::Interrupted`] for a planner that stopped without a plan.
pub fn request_stop() {
    STOP.store(true, std::sync::atomic::Ordering::Relaxed);
}

/// Whether [`request_stop`] has been called.
pub fn stop_requested() -> bool {
    STOP.load(std::sync::atomic::Ordering::Relaxed)
}

/// What a long-running planner reports: `done` of `total` units of `stage` (e.g. generations).
#[derive(Debug, Clone, PartialEq)]
pub struct Progress {
    /// The planner's name for the current stage ("generation", "run", ...).
    pub stage: &'static str,
    pub done: u64,
    /// `0` when unknown.
    pub total: u64,
    /// A short note for a person (e.g. the best fitness so far); may be empty.
    pub note: String,
}

/// Reports from a loop at most every [`Throttle::PERIOD`], for planners whose iterations are
/// much faster than a person reads (`ctx.report` on every PIBT step would cost more than the
/// step). Costs nothing without a progress callback.
#[derive(Debug, Clone, Default)]
pub struct Throttle {
    last: Option<std::time::Instant>,
}

impl Throttle {
    /// Time between two reports.
    pub const PERIOD: std::time::Duration = std::time::Duration::from_millis(250);

    /// A throttle that reports at its first call.
    pub fn new() -> Self {
        Throttle::default()
    }

    /// Calls `ctx.report(make())` when a callback is set and [`Self::PERIOD`] has passed since
    /// the last report (or there was none).
    pub fn report(&mut self, ctx: &Ctx, make: impl FnOnce() -> Progress) {
        if !ctx.reporting() {
            return;
        }
        let now = std::time::Instant::now();
        if self
            .last
            .is_none_or(|t| now.duration_since(t) >= Self::PERIOD)
        {
            self.last = Some(now);
            ctx.report(make());
        }
    }
}

/// A progress callback (called from the planner's calling thread).
pub type ProgressFn = Arc<dyn Fn(&Progress) + Send + Sync>;

/// The run context every planner takes: the seed of every random choice, the wall-clock deadline,
/// and an optional progress callback. The library never prints: the binary turns progress into a
/// bar or plain lines.
#[derive(Clone, Default)]
pub struct Ctx {
    /// Seed of every random choice the planner makes.
    pub seed: u64,
    pub deadline: Deadline,
    pub progress: Option<ProgressFn>,
}

impl Default for Deadline {
    fn default() -> Self {
        Deadline::none()
    }
}

impl std::fmt::Debug for Ctx {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Ctx")
            .field("seed", &self.seed)
            .field("deadline", &self.deadline)
            .field("progress", &self.progress.is_some())
            .finish()
    }
}

impl Ctx {
    /// A context with `seed` and `deadline` and no progress callback.
    pub fn new(seed: u64, deadline: Deadline) -> Self {
        Ctx {
            seed,
            deadline,
            progress: None,
        }
    }
    /// Whether anyone listens to [`Self::report`] (so a planner can skip building notes).
    pub fn reporting(&self) -> bool {
        self.progress.is_some()
    }

    /// Reports progress when a callback is set.
    pub fn report(&self, p: Progress) {
        if let Some(f) = &self.progress {
            f(&p);
        }
    }
}

/// A planning problem of one family: what a plan is, how it is judged, and what it measures.
pub trait Problem: Send + Sync {
    /// A candidate solution (e.g. one vertex sequence per agent).
    type Plan: Clone + Send;
    /// What the validator measures on a valid plan (e.g. sum of costs, makespan).
    type Metrics: Copy + Send + serde::Serialize;
    /// The first rule a plan breaks, described in the problem's own terms (cells, nodes, points).
    type Violation: std::fmt::Display;
    /// Number of agents (robots).
    fn num_agents(&self) -> usize;
    /// The one judge of plans: the metrics of a valid plan, or the first rule it breaks.
    fn validate(&self, plan: &Self::Plan) -> Result<Self::Metrics, Self::Violation>;
    /// The rules every instance of this problem obeys before any planner sees it (e.g. distinct
    /// starts and goals on the graph): an instance that breaks one is one the validator would
    /// refuse at t = 0. Readers enforce them and name the file and line; debug builds assert them
    /// at [`solve`]'s entry. Default: no rules beyond the type.
    ///
    /// # Errors
    /// The first rule broken, in the problem's own terms.
    fn instance_rules(&self) -> Result<(), String> {
        Ok(())
    }
    /// Lower bounds that every valid plan's metrics meet, as `(metric name, bound)` in the
    /// units of [`Problem::Metrics`] (e.g. the sum and the largest of the agents' start-goal
    /// distances for MAPF's sum of costs and makespan): the yardstick a summary states beside a
    /// plan's metrics. Default: none known.
    fn lower_bounds(&self) -> Vec<(&'static str, f64)> {
        Vec::new()
    }
    /// Puts a plan in canonical form before it is validated and returned (default: as is), e.g.
    /// drops trailing waits that carry no information.
    fn canonical(&self, plan: Self::Plan) -> Self::Plan {
        plan
    }
}

/// A planner for problems of type `P`. It must honour `ctx.deadline` and draw every random
/// choice from `ctx.seed`.
pub trait Planner<P: Problem>: Send + Sync {
    /// The name used on the command line and in outputs (its registry name).
    fn name(&self) -> &str;
    /// Plans for `problem`. An `Err` is an honest "no plan"; a returned plan is judged by
    /// [`solve`], never trusted.
    fn plan(&self, problem: &P, ctx: &Ctx) -> Result<P::Plan, Unsolved>;
    /// What the planner wants recorded beside its last plan (e.g. the GP program that made it,
    /// generations run); empty by default. Plan files keep it, summaries print the short values.
    fn notes(&self) -> serde_json::Map<String, serde_json::Value> {
        serde_json::Map::new()
    }
}

/// A validated plan with its metrics.
pub struct Solved<P: Problem> {
    pub plan: P::Plan,
    pub metrics: P::Metrics,
    /// Wall-clock time of the planner's `plan` call (validation excluded).
    pub runtime: Duration,
}

impl<P: Problem> Clone for Solved<P> {
    fn clone(&self) -> Self {
        Solved {
            plan: self.plan.clone(),
            metrics: self.metrics,
            runtime: self.runtime,
        }
    }
}

impl<P: Problem> std::fmt::Debug for Solved<P>
where
    P::Plan: std::fmt::Debug,
    P::Metrics: std::fmt::Debug,
{
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Solved")
            .field("plan", &self.plan)
            .field("metrics", &self.metrics)
            .field("runtime", &self.runtime)
            .finish()
    }
}

/// Why a run produced no plan.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Unsolved {
    /// The time limit was reached.
    TimeLimit,
    /// The memory limit ([`crate::memory`]) was reached: the planner stopped as at a deadline.
    MemoryLimit,
    /// A stop was requested ([`request_stop`], Ctrl-C) before the planner had a plan.
    Interrupted,
    /// The planner finished without a plan (it explains why): an honest "not solved".
    GaveUp(String),
    /// The planner returned a plan the validator rejects: a bug in mrpp, never the user's fault.
    /// The binary exits 1 on it, never 3.
    Invalid(String),
}

impl Unsolved {
    /// `true` for [`Unsolved::Invalid`] (a bug), `false` for an honest "not solved".
    pub fn is_bug(&self) -> bool {
        matches!(self, Unsolved::Invalid(_))
    }
    /// A short status word for records: `time_limit`, `memory_limit`, `interrupted`, `gave_up`
    /// or `invalid`.
    pub fn status(&self) -> &'static str {
        match self {
            Unsolved::TimeLimit => "time_limit",
            Unsolved::MemoryLimit => "memory_limit",
            Unsolved::Interrupted => "interrupted",
            Unsolved::GaveUp(_) => "gave_up",
            Unsolved::Invalid(_) => "invalid",
        }
    }
}

impl std::fmt::Display for Unsolved {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Unsolved::TimeLimit => write!(f, "time limit reached"),
            Unsolved::Interrupted => write!(f, "interrupted"),
            Unsolved::MemoryLimit => write!(
                f,
                "memory limit reached ({} MB of heap; --memory-limit)",
                crate::memory::limit().unwrap_or(0) >> 20
            ),
            Unsolved::GaveUp(why) => write!(f, "{why}"),
            Unsolved::Invalid(why) => write!(f, "invalid plan: {why}"),
        }
    }
}

/// Runs `planner` on `problem` and passes its plan through the problem's validator, exactly once
/// ([`accept`]): a plan that breaks a rule becomes [`Unsolved::Invalid`], so no caller ever
/// receives an invalid plan, and a valid one comes back with its metrics.
pub fn solve<P: Problem>(
    planner: &dyn Planner<P>,
    problem: &P,
    ctx: &Ctx,
) -> Result<Solved<P>, Unsolved> {
    debug_assert_eq!(
        problem.instance_rules(),
        Ok(()),
        "a reader let through an instance that breaks the rules"
    );
    let started = Instant::now();
    crate::memory::reset_tripped();
    let plan = planner.plan(problem, ctx).map_err(|why| match why {
        // A planner stopped by the memory limit or a stop request saw an expired deadline.
        Unsolved::TimeLimit | Unsolved::GaveUp(_) if crate::memory::tripped() => {
            Unsolved::MemoryLimit
        }
        Unsolved::TimeLimit | Unsolved::GaveUp(_) if stop_requested() => Unsolved::Interrupted,
        other => other,
    })?;
    accept(problem, plan, planner.name(), started.elapsed())
}

/// The one gate every plan passes: puts `plan` in canonical form and validates it once. [`solve`]
/// calls it; so does code that runs a planner's internals directly because it needs more than
/// the plan (e.g. an experiment that also counts PSW's swaps). `made_by` names the planner in
/// the message of an [`Unsolved::Invalid`].
pub fn accept<P: Problem>(
    problem: &P,
    plan: P::Plan,
    made_by: &str,
    runtime: Duration,
) -> Result<Solved<P>, Unsolved> {
    let plan = problem.canonical(plan);
    match problem.validate(&plan) {
        Ok(metrics) => Ok(Solved {
            plan,
            metrics,
            runtime,
        }),
        Err(v) => Err(Unsolved::Invalid(format!(
            "planner `{made_by}` returned a plan the validator rejects: {v}"
        ))),
    }
}
