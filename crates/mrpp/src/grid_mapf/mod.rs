//! Planners for MAPF on 4-connected grids (they work on any [`crate::Graph`] with coordinates):
//! H* (the paper's hybrid greedy planner) and the cooperative A* family (CA*, HCA*, WHCA*).

pub mod corridors;
pub mod hstar;

use crate::error::{Error, Result};
use crate::solve::Planner;

/// What the command line (or an experiment) asks for; unknown names give a clear error.
#[derive(Debug, Clone, Default)]
pub struct PlannerSpec {
    /// `hstar`, `ca`, `hca`, `whca`.
    pub name: String,
    /// WHCA* window (default 8).
    pub window: Option<u32>,
    /// H* variant: `repaired` (default) or `paper`.
    pub variant: Option<String>,
}

/// Names accepted by [`build_planner`].
pub const PLANNER_NAMES: &[&str] = &[];

/// Builds the planner a spec names.
pub fn build_planner(spec: &PlannerSpec) -> Result<Box<dyn Planner>> {
    Err(Error::Param(format!(
        "unknown planner `{}` (known: {})",
        spec.name,
        PLANNER_NAMES.join(", ")
    )))
}
