//! mrpp: multi-robot path planning.
//!
//! One graph/instance/plan model, one validator ([`plan::Plan::validate`]) that judges every plan,
//! and the planners of the grid MAPF family (`grid_mapf`). The library never prints and never
//! exits; the `mrpp` binary turns its results and typed errors into files, messages and exit codes.

pub mod error;
pub mod graph;
pub mod grid;
pub mod instance;
pub mod plan;

pub use error::{Error, Result};
pub use graph::{Graph, VertexId};
pub use grid::GridMap;
pub use instance::Instance;
pub use plan::{GoalSemantics, Metrics, Plan, ValidateOptions, Violation};
pub mod evo;
pub mod experiments;
pub mod grid_mapf;
pub mod io;
pub mod search;
pub mod seeds;
pub mod solve;
pub mod trees;
