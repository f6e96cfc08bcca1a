//! What the metaheuristics share. Every algorithm here is generic over the problem it optimises
//! and takes its random generator from the caller (a seeded `ChaCha8Rng`), so one seed gives one
//! result on every machine; none of them prints.
//!
//! - [`nsga3`]: NSGA-III (Deb & Jain 2014), a many-objective evolutionary driver with
//!   non-dominated sorting and reference-point niching.
//! - [`real`]: the real-coded variation operators of that paper (SBX, polynomial mutation).

pub mod nsga3;
pub mod real;
