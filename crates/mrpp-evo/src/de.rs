//! Differential evolution, DE/rand/1/bin (R. Storn, K. Price, "Differential Evolution – A Simple
//! and Efficient Heuristic for Global Optimization over Continuous Spaces", J. Global Optimization
//! 11, 1997), a box-bounded minimiser over a [`Space`]; one of the baselines of the per-step
//! heading optimisation of Sahoo et al. (HBMO multi-robot navigation).
//!
//! One generation, for every member `x_i` of the population of `NP` points:
//!
//! 1. Mutation: `v = x_r1 + F·(x_r2 - x_r3)` with `r1, r2, r3` distinct, different from `i`, drawn
//!    uniformly. In a wrapping space `x_r2 - x_r3` is the shortest difference round the circle
//!    ([`Space::delta`]), so two headings either side of ±π differ by a little, not by ~2π.
//! 2. Binomial crossover: `u_j = v_j` with probability `CR`, and always for one coordinate
//!    `j_rand` drawn uniformly, otherwise `u_j = x_i,j`; then [`Space::fix`] (wrap or clamp).
//! 3. Greedy selection: `u` replaces `x_i` in the next generation when `f(u) <= f(x_i)` (NaN counts
//!    as `+inf`).
//!
//! The generation is synchronous: all trial vectors are built from the current population and the
//! replacements take effect together. The answer is the best member of the last population, which
//! (selection being greedy) is the best point evaluated.
//!
//! Parameters: the baselines of the paper's comparison use `NP = 30` (or `10·D`), `F` in 0.5–0.8,
//! `CR = 0.9` and 50 generations. The defaults here ([`De::default`]: `NP = 20`, 40 generations,
//! `F = 0.6`, `CR = 0.9`) are smaller, meant to keep one per-step optimisation for 10 robots
//! (820 objective evaluations) under about a millisecond. DE/rand/1 needs four distinct members; a population below 4 is raised to 4
//! (rather than failing, so that `minimize` always returns a point).
//!
//! Evaluations per call: `NP·(1 + generations)` with `NP = max(population, 4)`; 820 at the
//! defaults.

use rand::{Rng, RngExt};
use rand_chacha::ChaCha8Rng;

use crate::space::{Counted, Minimizer, Minimum, Space, argmin, initial_points, key};

/// DE/rand/1/bin settings. See the module documentation for the algorithm and the defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct De {
    /// Population size `NP` (default 20; values below 4 are treated as 4).
    pub population: usize,
    /// Number of generations after the initial population (default 40).
    pub generations: usize,
    /// Differential weight `F` (default 0.6; the usual range is 0.5–0.8).
    pub f: f64,
    /// Crossover rate `CR` in `[0, 1]` (default 0.9).
    pub cr: f64,
}

impl Default for De {
    /// `population: 20, generations: 40, f: 0.6, cr: 0.9` (820 evaluations per call).
    fn default() -> Self {
        De {
            population: 20,
            generations: 40,
            f: 0.6,
            cr: 0.9,
        }
    }
}

impl De {
    /// Minimises `f` over `space`, starting from the `init` points (fixed into the space, placed
    /// first in the population; those beyond the population size are ignored) and uniform samples.
    /// Every random choice comes from `rng`. Returns the best point, its objective value and the
    /// number of evaluations (`max(population, 4)·(1 + generations)`).
    ///
    /// # Panics
    /// If an `init` point's length differs from `space.dim()`.
    pub fn minimize<F: FnMut(&[f64]) -> f64, R: Rng + ?Sized>(
        &self,
        space: &Space,
        f: F,
        init: &[Vec<f64>],
        rng: &mut R,
    ) -> Minimum {
        let np = self.population.max(4);
        let dim = space.dim();
        let mut f = Counted::new(f);
        let mut pop = initial_points(space, init, np, rng);
        let mut values: Vec<f64> = pop.iter().map(|x| f.eval(x)).collect();
        for _ in 0..self.generations {
            let mut next = pop.clone();
            let mut next_values = values.clone();
            for i in 0..np {
                let [r1, r2, r3] = distinct_others(i, np, rng);
                let j_rand = rng.random_range(0..dim.max(1));
                let mut u = pop[i].clone();
                for (j, uj) in u.iter_mut().enumerate() {
                    if j == j_rand || rng.random::<f64>() < self.cr {
                        *uj = pop[r1][j] + self.f * space.delta(&pop[r3], &pop[r2], j);
                    }
                }
                space.fix(&mut u);
                let fu = f.eval(&u);
                if key(fu) <= key(values[i]) {
                    next[i] = u;
                    next_values[i] = fu;
                }
            }
            pop = next;
            values = next_values;
        }
        let best = argmin(&values).expect("population is never empty");
        Minimum {
            x: pop.swap_remove(best),
            value: values[best],
            evaluations: f.evaluations,
        }
    }
}

/// Three distinct indices in `0..n`, all different from `i` (`n >= 4`).
fn distinct_others<R: Rng + ?Sized>(i: usize, n: usize, rng: &mut R) -> [usize; 3] {
    let mut out = [usize::MAX; 3];
    for k in 0..3 {
        out[k] = loop {
            let r = rng.random_range(0..n);
            if r != i && !out[..k].contains(&r) {
                break r;
            }
        };
    }
    out
}

impl Minimizer for De {
    fn minimize_dyn(
        &self,
        space: &Space,
        f: &mut dyn FnMut(&[f64]) -> f64,
        init: &[Vec<f64>],
        rng: &mut ChaCha8Rng,
    ) -> Minimum {
        self.minimize(space, f, init, rng)
    }

    fn name(&self) -> &'static str {
        "DE"
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::space::testing::*;
    use rand::SeedableRng;

    #[test]
    fn sphere_5d() {
        let de = De {
            generations: 150,
            ..De::default()
        };
        let r = de.minimize(
            &cube(5, 5.0),
            sphere,
            &[],
            &mut ChaCha8Rng::seed_from_u64(1),
        );
        assert!(r.value < 1e-3, "{r:?}");
        assert_eq!(r.value, sphere(&r.x));
        assert_eq!(r.evaluations, 20 * 151);
    }

    #[test]
    fn rastrigin_5d() {
        let de = De {
            population: 50,
            generations: 400,
            f: 0.5,
            cr: 0.9,
        };
        let r = de.minimize(
            &cube(5, 5.12),
            rastrigin,
            &[],
            &mut ChaCha8Rng::seed_from_u64(1),
        );
        assert!(r.value < 5.0, "{r:?}");
        assert_eq!(r.value, rastrigin(&r.x));
    }

    #[test]
    fn headings_wrap() {
        let de = De::default();
        assert!(heading_error(&de, 3.0, &[]) < 0.01);
        assert!(heading_error(&de, -3.1, &[vec![3.1]]) < 0.01);
        assert!(heading_error(&de, -3.1, &[]) < 0.01);
    }

    #[test]
    fn contract() {
        check_contract(&De::default(), 820);
        check_init_used(&De {
            population: 4,
            generations: 1,
            ..De::default()
        });
        check_nan(&De::default());
        // A population below 4 is raised to 4.
        let small = De {
            population: 1,
            generations: 2,
            ..De::default()
        };
        let r = small.minimize(
            &cube(2, 1.0),
            sphere,
            &[],
            &mut ChaCha8Rng::seed_from_u64(0),
        );
        assert_eq!(r.evaluations, 12);
        assert_eq!(De::default().name(), "DE");
    }
}
