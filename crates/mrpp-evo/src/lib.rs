//! What the metaheuristics share. Every algorithm here is generic over the problem it optimises
//! and takes its random generator from the caller (a seeded `ChaCha8Rng`), so one seed gives one
//! result on every machine; none of them prints.
//!
//! - [`nsga3`]: NSGA-III (Deb & Jain 2014), a many-objective evolutionary driver with
//!   non-dominated sorting and reference-point niching.
//! - [`real`]: the real-coded variation operators of that paper (SBX, polynomial mutation).
//! - [`space`]: the box-bounded (clamped or wrapping, e.g. heading angles) search [`Space`], the
//!   [`Minimum`] a minimiser returns and the object-safe [`Minimizer`] trait shared by the three
//!   single-objective continuous minimisers below, built for the per-step heading optimisation of
//!   Sahoo et al. (HBMO multi-robot navigation):
//!   - [`de`]: differential evolution, DE/rand/1/bin (Storn & Price 1997);
//!   - [`pso`]: global-best particle swarm optimisation with linearly falling inertia (Kennedy &
//!     Eberhart 1995; Shi & Eberhart 1998);
//!   - [`hbmo`]: Honey Bee Mating Optimization (Abbass 2001; Haddad, Afshar & Mariño 2006) as the
//!     paper describes it.

pub mod de;
pub mod hbmo;
pub mod nsga3;
pub mod pso;
pub mod real;
pub mod space;

pub use space::{Minimizer, Minimum, Space};
