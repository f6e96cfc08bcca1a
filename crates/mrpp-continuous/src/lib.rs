//! mrpp-continuous: circular robots among polygon obstacles in a continuous 2D world, each
//! choosing its heading step by step (R. R. Sahoo, S. Swarnalipi, P. Rakshit, B. K. Balabantaray,
//! M. T. Haidar, S. Mohapatra, "Navigational path planning of multi-robot using Honey Bee Mating
//! Optimization Algorithm (HBMO)", International Journal of Computer Applications 2012; "the HBMO
//! paper" below).
//!
//! - [`world`]: the JSON world (workspace, polygon obstacles, robots) with item-naming errors;
//! - [`geometry`]: distances, swept discs;
//! - [`problem`]: [`NavProblem`], trajectories, the validator and the paper's metrics;
//! - [`ideal`]: the ideal (shortest clear) path of each robot, for ATPD;
//! - [`objective`]: the paper's per-step objective (eq. 7); [`navigate`]: the per-step loop and
//!   its collision repair; [`orca`]: ORCA (RVO2's method); [`planners`]: `hbmo`, `de`, `pso`,
//!   `orca`, registered in [`PLANNERS`];
//! - [`generator`]: seeded worlds and RVO2's circle; [`plan_file`]: plans in the envelope;
//!   [`render`]: an SVG picture.

pub mod generator;
pub mod geometry;
pub mod ideal;
pub mod navigate;
pub mod objective;
pub mod orca;
pub mod plan_file;
pub mod planners;
pub mod problem;
pub mod render;
pub mod world;

pub use problem::{NavMetrics, NavProblem, NavViolation, Trajectories};
pub use world::{Robot, World};

/// The continuous family's name in plan files and `mrpp planners --family`.
pub const FAMILY: &str = "continuous";

/// Every continuous planner, in the order `mrpp planners` lists them.
pub static PLANNERS: &[mrpp_core::PlannerEntry<NavProblem>] = &[
    planners::HBMO_ENTRY,
    planners::DE_ENTRY,
    planners::PSO_ENTRY,
    planners::ORCA_ENTRY,
];
