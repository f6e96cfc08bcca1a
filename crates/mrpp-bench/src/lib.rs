//! mrpp-bench: the run harness ([`harness`]: jobs -> validated run records in one schema, shards
//! and their merge, output manifests), the report helpers ([`report`]: CSV, SVG figures), the
//! paper tables built on the harness ([`papers`]), sweeps described as data ([`sweep`]:
//! MovingAI maps x scenarios x agent counts x planners x runs, from TOML or flags) and League of
//! Robot Runners problems run lifelong ([`lorr`]).
//!
//! Nothing here prints or writes files: the binary shows progress and writes what these return.

pub mod execution;
pub mod harness;
pub mod lorr;
pub mod papers;
pub mod report;
pub mod stats;
pub mod sweep;

pub use harness::{Manifest, RunRecord, Shard, Sweep};
