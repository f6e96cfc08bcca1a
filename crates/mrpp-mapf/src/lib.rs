//! Graph-MAPF planners shared by the families that plan on graphs, and the grid maps they run on.
//!
//! PIBT ([`pibt`]), LaCAM/LaCAM* ([`lacam`]), MAPF-LNS ([`lns`]) and CBS/EECBS ([`cbs`]) plan on
//! any [`mrpp_core::Graph`]; each module cites its paper and registers its planner next to it
//! (`ENTRY`). [`map`] reads grid maps (MovingAI, the H* paper's ASCII maps, the League of Robot
//! Runners' maps) into such graphs, and [`instance_rules`] checks starts and goals read from files
//! against one, naming file and line; [`lorr_files`] reads the League of Robot Runners' problem files
//! for both the one-shot and the lifelong family.
//!
//! The families that plan on graphs (`mrpp-grid` for one-shot grid MAPF, `mrpp-lifelong` for the
//! League of Robot Runners' lifelong problems) build on this crate, never on each other
//! (architecture: core <- evo, mapf planners <- families <- bench <- cli/py).

pub mod cbs;
pub(crate) mod guidance;
pub mod instance_rules;
pub mod lacam;
pub mod lns;
pub mod lorr_files;
pub mod map;
pub mod pibt;
pub(crate) mod scatter;

pub use map::GridMap;
