//! What every planner shares: options (seed, time limit), the outcome type, and the final check
//! that no plan leaves a planner without passing the validator.

use std::time::{Duration, Instant};

use crate::graph::Graph;
use crate::instance::Instance;
use crate::plan::{Plan, ValidateOptions};

/// A wall-clock limit that planners poll.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Deadline(Option<Instant>);

impl Deadline {
    pub fn none() -> Self {
        Deadline(None)
    }
    pub fn after(limit: Duration) -> Self {
        Deadline(Instant::now().checked_add(limit))
    }
    pub fn expired(&self) -> bool {
        self.0.is_some_and(|d| Instant::now() >= d)
    }
}

/// Options every planner takes.
#[derive(Debug, Clone, Copy)]
pub struct SolveOptions {
    /// Seed of every random choice the planner makes.
    pub seed: u64,
    pub deadline: Deadline,
}

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions {
            seed: 0,
            deadline: Deadline::none(),
        }
    }
}

/// Why a planner returned no plan.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Unsolved {
    /// The time limit was reached.
    TimeLimit,
    /// The planner finished without a valid plan (it explains why).
    GaveUp(String),
}

impl std::fmt::Display for Unsolved {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Unsolved::TimeLimit => write!(f, "time limit reached"),
            Unsolved::GaveUp(why) => write!(f, "{why}"),
        }
    }
}

/// A multi-agent planner on a graph.
pub trait Planner: Send + Sync {
    /// Name used on the command line and in outputs.
    fn name(&self) -> String;
    /// Plans for `inst`; must honour `opts.deadline`.
    fn plan(&self, graph: &Graph, inst: &Instance, opts: &SolveOptions) -> Result<Plan, Unsolved>;
}

/// Runs `planner` and passes its plan through the validator: a plan that fails is turned into
/// [`Unsolved::GaveUp`], so no caller ever receives an invalid plan.
pub fn solve(
    planner: &dyn Planner,
    graph: &Graph,
    inst: &Instance,
    opts: &SolveOptions,
) -> Result<Plan, Unsolved> {
    let mut plan = planner.plan(graph, inst, opts)?;
    plan.trim();
    match plan.validate(graph, inst, ValidateOptions::default()) {
        Ok(_) => Ok(plan),
        Err(v) => Err(Unsolved::GaveUp(format!(
            "internal error, plan rejected by the validator: {}",
            v.describe(graph)
        ))),
    }
}
