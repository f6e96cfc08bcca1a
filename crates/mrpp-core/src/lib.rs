//! mrpp-core: the one contract every planner family of mrpp implements, and the discrete graph
//! MAPF model that the grid and tree families share.
//!
//! - [`contract`]: [`Problem`] (plan, metrics, violation, `validate`), [`Planner`], the run
//!   context [`Ctx`] (seed, deadline, progress), [`Solved`], [`Unsolved`], and [`solve`], which
//!   validates every plan exactly once.
//! - [`registry`]: [`PlannerEntry`] (name, one-line description, parameters, build function) and
//!   [`Params`] (`-p key=value`).
//! - [`envelope`]: the one versioned JSON plan file of every family.
//! - [`mapf`]: graph (CSR), instance, [`Rules`] (goal semantics, following), plan, validator,
//!   metrics and the shared searches (BFS tables, space-time A*).
//! - [`seeds`]: per-job seed derivation; [`picture`]: the agents' colours and waits of every picture;
//!   [`error`]: typed errors; [`files_read`]: the files a process read (outputs refuse them);
//!   [`memory`]: the process-wide memory limit every planner honours through its deadline.
//!
//! No family, no file format of another tool and no geometry dependency lives here. The library
//! never prints and never exits.

pub mod contract;
pub mod envelope;
pub mod error;
pub mod files_read;
pub mod mapf;
pub mod memory;
pub mod picture;
pub mod registry;
pub mod seeds;

pub use contract::{
    Ctx, Deadline, Planner, Problem, Progress, ProgressFn, Solved, Throttle, Unsolved, accept,
    request_stop, solve, stop_requested,
};
pub use error::{Error, Result};
pub use mapf::graph::{Graph, VertexId};
pub use mapf::instance::Instance;
pub use mapf::plan::{GoalSemantics, Metrics, Plan, Rules, Violation};
pub use mapf::{MapfProblem, MapfViolation};
pub use registry::{Param, Params, PlannerEntry};
