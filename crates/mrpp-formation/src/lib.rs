//! mrpp-formation: a formation of robots on a Voronoi roadmap of a polygon map (M. E. Pereyra,
//! G. Perez Paina, M. Pucheta, R. G. Araguás, "Planificación de caminos para múltiples robots
//! basado en algoritmo genético" — "Genetic algorithm based multirobot path planning"; "the GA
//! paper" below).
//!
//! R robots start together at `Q_ini` and must all reach `Q_goal`; they may split onto different
//! corridors and merge again, the first robot at a shared vertex waiting for the others; a
//! corridor's cost depends on how many robots cross it together, and a plan costs its worst
//! robot's arrival, `c_max`.
//!
//! - [`polymap`]: CTU/CIIRC polygon maps (parser with file:line errors); [`generator`]: seeded
//!   stand-ins for the maps that are not public;
//! - [`roadmap`]: the generalized Voronoi roadmap (spade), corridors with length and clearance;
//! - [`cost`]: cost vectors `c_e(r)` (named models); [`capacity`]: whether the formation fits
//!   the corridors at all (a maximum flow; the corridors that hold it back when it does not);
//! - [`problem`]: [`FormationProblem`], plans, the validator and its timing;
//! - [`paths`]: Dijkstra, loop elimination, k-shortest and all simple paths;
//! - [`planners`] (`sequential`), [`ga`] (`ga`) and [`exact`] (`exact`), registered in [`PLANNERS`];
//! - [`render`]: an SVG picture of the map, roadmap and plan;
//! - [`world`]: the formation file (map, robots, Q_ini, Q_goal, cost model) and plan files.

pub mod capacity;
pub mod cost;
pub mod exact;
pub mod ga;
pub mod generator;
pub mod paths;
pub mod planners;
pub mod polymap;
pub mod problem;
pub mod render;
pub mod roadmap;
pub mod world;

pub use cost::CostModel;
pub use problem::{FormationMetrics, FormationPlan, FormationProblem, FormationViolation};

use mrpp_core::PlannerEntry;

/// The formation family's name in plan files and `mrpp planners --family`.
pub const FAMILY: &str = "formation";

/// Every formation planner, in the order `mrpp planners` lists them.
pub static PLANNERS: &[PlannerEntry<FormationProblem>] =
    &[planners::SEQUENTIAL_ENTRY, ga::ENTRY, exact::ENTRY];
