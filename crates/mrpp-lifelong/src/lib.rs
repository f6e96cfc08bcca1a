//! mrpp-lifelong: the lifelong family. A League of Robot Runners (LoRR) problem (a map, robots, a
//! task file of errand sequences; GitHub `MAPF-Competition/Start-Kit`, MIT licence) is run step by
//! step for a horizon, under an action model (`MAPF`, or `MAPF_T` with orientation), with a fixed
//! planning time per step; robots get a new task when they finish one. The problem is a
//! [`LifelongProblem`]; its plan is the executed [`Trace`]; its metrics ([`LifelongMetrics`]) are
//! tasks finished, errands, throughput and planner time. The validator replays the trace under
//! the start kit's rules ([`sim`]); `tools/check/lifelong.py` checks LoRR's output JSON
//! independently.
//!
//! Parts, as in the kit, so each can be swapped: the simulator ([`sim`]), the scheduler
//! ([`scheduler`]) and the planner ([`rotation_pibt`], optionally on [`guide_paths`]), joined by
//! the loop in [`runner`]. Output in LoRR's own JSON (which the kit's viewer PlanViz reads) is
//! [`lorr_output`].
//! `docs/lorr-semantics.md` has the kit's semantics with file and line references.

pub mod bound;
pub mod distances;
pub mod execution;
pub mod executor;
pub mod guide_paths;
pub mod k_robust;
pub mod lorr_output;
pub mod model;
pub mod problem;
pub mod rotation_pibt;
pub mod runner;
pub mod scheduler;
pub mod sim;
pub mod ticks;
pub mod window_lns;

pub use model::{Action, ActionModel, State};
pub use problem::{LifelongMetrics, LifelongProblem, LifelongViolation, Trace};

use mrpp_core::PlannerEntry;

/// The lifelong family's name in plan files and `mrpp planners --family`.
pub const FAMILY: &str = "lifelong";

/// Every lifelong planner, in the order `mrpp planners` lists them.
pub static PLANNERS: &[PlannerEntry<LifelongProblem>] = &[runner::PIBT_ENTRY, runner::LNS_ENTRY];
