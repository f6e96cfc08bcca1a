//! Single-lane tree workspaces (Trudeau & Clark, `shared/papers/gp-single-lane-trees.md`): the
//! random tree generator (Algorithm 2, [`generator`]), tree instances and their JSON files
//! ([`instance`]), rooted-tree queries ([`rooted`]) and the Push-Swap-Wait baseline ([`psw`],
//! `shared/docs/baselines.md` §1).
//!
//! The problem (§3 of the paper): a tree T(N, E) rooted at node 0, robots with unique starts and
//! unique goals; in one time step a robot moves along one edge or stays. The rules, enforced by the
//! crate's one validator ([`crate::plan::Plan::validate`]):
//! - one robot per node at the end of every step (no vertex conflict);
//! - one robot per edge per step (no swap conflict);
//! - **following is allowed**: a robot may enter a node that another robot leaves in the same
//!   step. The paper only forbids two robots on a node at the end of a step and two robots on an
//!   edge in one step; a robot that follows another traverses a different edge, and `design.md`
//!   allows it too. [`tree_validate_options`] takes the choice as a flag (PSW has the matching
//!   [`psw::Psw::allow_following`]) so that runs without following stay possible. (On the T-tree
//!   reference instance the optimum makespan is 5 with following, 7 without.)
//! - **`visit` goal semantics**: a problem is solved at the first step by which every robot has
//!   stood on its goal at least once; robots need not stay there. A robot's cost is the step of
//!   its first arrival;
//! - the step cap is the paper's M = |N|²·|R|² ([`psw::step_cap`]).
//!
//! Leaves are non-root nodes of degree 1; branch nodes have degree ≥ 3. PSW is complete when
//! #robots < #leaves, which is why the paper's problems have #leaves − 1 robots; our PSW solved
//! every one of 40 000 such generated problems (depth budgets 3–10).
//!
//! [`solve::solve`](crate::solve::solve) validates with `stay` semantics, so tree plans go through
//! [`validate_tree_plan`] / [`solve_tree`] instead.

pub mod generator;
pub mod gp;
pub mod instance;
pub mod psw;
pub mod rooted;

pub use generator::{ChildCount, ProblemSpec, RobotCount, generate_problem, mst_generator};
pub use instance::TreeInstance;
pub use psw::{Psw, PswRun, step_cap};
pub use rooted::RootedTree;

use crate::graph::Graph;
use crate::instance::Instance;
use crate::plan::{GoalSemantics, Metrics, Plan, ValidateOptions, Violation};
use crate::solve::{Planner, SolveOptions, Unsolved};

/// Validator options for tree plans: `visit` semantics, following as given.
pub fn tree_validate_options(allow_following: bool) -> ValidateOptions {
    ValidateOptions {
        semantics: GoalSemantics::Visit,
        allow_following,
    }
}

/// Judges a tree plan (`visit` semantics); on success returns its metrics (cost of a robot = the
/// step of its first arrival on its goal).
pub fn validate_tree_plan(
    graph: &Graph,
    inst: &Instance,
    plan: &Plan,
    allow_following: bool,
) -> Result<Metrics, Violation> {
    plan.validate(graph, inst, tree_validate_options(allow_following))
}

/// [`crate::solve::solve`] for trees: runs `planner` and passes its plan through the validator with
/// `visit` semantics, so no caller ever receives an invalid plan.
pub fn solve_tree(
    planner: &dyn Planner,
    graph: &Graph,
    inst: &Instance,
    opts: &SolveOptions,
    allow_following: bool,
) -> Result<Plan, Unsolved> {
    let mut plan = planner.plan(graph, inst, opts)?;
    plan.trim();
    match validate_tree_plan(graph, inst, &plan, allow_following) {
        Ok(_) => Ok(plan),
        Err(v) => Err(Unsolved::GaveUp(format!(
            "internal error, plan rejected by the validator: {}",
            v.describe(graph)
        ))),
    }
}
