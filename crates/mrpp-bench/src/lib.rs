//! mrpp-bench: the run harness (jobs -> validated run records, shard and merge) and the paper
//! tables built on it ([`papers`]).

pub mod papers;
