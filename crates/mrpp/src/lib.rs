//! mrpp: multi-robot path planning in Rust. A facade over the workspace's crates, so a user needs
//! one dependency:
//!
//! - [`core`] (`mrpp-core`): the contract (`Problem`, `Planner`, `solve`, registry, plan
//!   envelope) and discrete graph MAPF (graph, instance, rules, validator, searches);
//! - [`grid`] (`mrpp-grid`): grid MAPF (MovingAI and H*-paper files; H*, CA*/HCA*/WHCA*,
//!   Enol2023, NSGA-III);
//! - [`mapf`] (`mrpp-mapf`): graph-MAPF planners shared by the graph families (PIBT,
//!   LaCAM/LaCAM*, LNS, CBS/EECBS), grid maps, League of Robot Runners files;
//! - [`lifelong`] (`mrpp-lifelong`): lifelong League of Robot Runners runs (simulator,
//!   schedulers, rotation-aware PIBT, LoRR output JSON);
//! - [`trees`] (`mrpp-trees`): single-lane trees (generator, Push-Swap-Wait, GP);
//! - [`formation`] (`mrpp-formation`): formations on Voronoi roadmaps of polygon maps
//!   (sequential, GA, exact);
//! - [`continuous`] (`mrpp-continuous`): circular robots among polygons, one heading per step
//!   (HBMO, DE, PSO);
//! - [`evo`] (`mrpp-evo`): generic, seeded metaheuristics.

pub use mrpp_continuous as continuous;
pub use mrpp_core as core;
pub use mrpp_evo as evo;
pub use mrpp_formation as formation;
pub use mrpp_grid as grid;
pub use mrpp_lifelong as lifelong;
pub use mrpp_mapf as mapf;
pub use mrpp_trees as trees;

pub use mrpp_core::{Ctx, Deadline, MapfProblem, Planner, Problem, Solved, Unsolved, solve};
