//! mrpp-trees: single-lane tree workspaces (A. Trudeau and C. M. Clark, "Multi-Robot Path
//! Planning Via Genetic Programming", Harvey Mudd College; "the GP paper" below): the
//! random tree generator (Algorithm 2, [`generator`]), tree instances and their JSON files
//! ([`instance`]), rooted-tree queries ([`rooted`]) and the Push-Swap-Wait baseline ([`psw`],
//! Wiktor et al., IROS 2014).
//!
//! The problem (§3 of the paper): a tree T(N, E) rooted at node 0, robots with unique starts and
//! unique goals; in one time step a robot moves along one edge or stays. The rules, enforced by the
//! one MAPF validator of `mrpp-core` ([`mrpp_core::MapfProblem`] with [`Rules::visit`]):
//! - one robot per node at the end of every step (no vertex conflict);
//! - one robot per edge per step (no swap conflict);
//! - **following is allowed**: a robot may enter a node that another robot leaves in the same
//!   step. The paper only forbids two robots on a node at the end of a step and two robots on an
//!   edge in one step; a robot that follows another traverses a different edge, and the MAPF convention
//!   allows it too. [`tree_problem`] takes the choice as a flag (PSW has the matching
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
//!
//! [`PLANNERS`] is the family's registry (`psw`, `gp`); every plan goes through
//! [`mrpp_core::solve`] with the problem of [`tree_problem`].

pub mod generator;
pub mod gp;
pub mod instance;
pub mod plan_json;
pub mod psw;
pub mod rooted;

use std::sync::Arc;

pub use generator::{ChildCount, ProblemSpec, RobotCount, generate_problem, mst_generator};
pub use instance::TreeInstance;
pub use psw::{Psw, PswRun, step_cap};
pub use rooted::RootedTree;

use mrpp_core::{MapfProblem, PlannerEntry, Rules};

/// The tree family's name in plan files and `mrpp planners --family`.
pub const FAMILY: &str = "trees";

/// Every tree planner, in the order `mrpp planners` lists them.
pub static PLANNERS: &[PlannerEntry<MapfProblem>] = &[psw::ENTRY, gp::ENTRY];

/// The [`MapfProblem`] of a tree instance: `visit` goal semantics, following as given.
pub fn tree_problem(tree: &TreeInstance, allow_following: bool) -> MapfProblem {
    MapfProblem::new(
        Arc::new(tree.graph.clone()),
        tree.instance.clone(),
        Rules::visit(allow_following),
    )
    .expect("a TreeInstance names only its own nodes")
}

/// Unit-test shorthands: judge or solve a tree plan on a graph and instance.
#[cfg(test)]
pub(crate) mod test_support {
    use mrpp_core::mapf::graph::Graph;
    use mrpp_core::mapf::instance::Instance;
    use mrpp_core::mapf::plan::{Metrics, Plan};
    use mrpp_core::{Ctx, MapfProblem, MapfViolation, Planner, Problem, Rules, Unsolved, solve};

    /// The validator's verdict on a tree plan (`visit` rules).
    pub(crate) fn validate_tree_plan(
        graph: &Graph,
        inst: &Instance,
        plan: &Plan,
        allow_following: bool,
    ) -> Result<Metrics, MapfViolation> {
        MapfProblem::on(graph, inst, Rules::visit(allow_following)).validate(plan)
    }

    /// [`solve`] on a tree problem, keeping the plan.
    pub(crate) fn solve_tree(
        planner: &dyn Planner<MapfProblem>,
        graph: &Graph,
        inst: &Instance,
        ctx: &Ctx,
        allow_following: bool,
    ) -> Result<Plan, Unsolved> {
        solve(
            planner,
            &MapfProblem::on(graph, inst, Rules::visit(allow_following)),
            ctx,
        )
        .map(|s| s.plan)
    }
}
