//! The shared single-agent searches. Planners call these; they do not carry private copies.
//!
//! - [`buckets`]: the bucket queue of the searches keyed by `f` (SIPP's arrival, H*'s corridor
//!   routes).
//! - [`distance`]: BFS distance tables (the exact heuristic of HCA*/WHCA*, PIBT, ...).
//! - [`spacetime`]: a reservation table and space-time A* over `(vertex, time)`, with an optional
//!   window (CA*, HCA*, WHCA*, and H*'s repair step).
//! - [`sipp`]: safe-interval path planning over the same table (the re-planning step of LaCAM*'s
//!   large-neighbourhood refinement), and its earliest arrival alone (H*'s local re-planning).

pub mod buckets;
pub mod distance;
pub mod sipp;
pub mod spacetime;
