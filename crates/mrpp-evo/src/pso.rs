//! Particle swarm optimisation, the standard global-best form with linearly decreasing inertia
//! (J. Kennedy, R. Eberhart, "Particle Swarm Optimization", ICNN 1995; Y. Shi, R. Eberhart, "A
//! Modified Particle Swarm Optimizer", ICEC 1998), a box-bounded minimiser over a [`Space`]; one
//! of the baselines of the per-step heading optimisation of Sahoo et al. (HBMO multi-robot
//! navigation).
//!
//! Every particle has a position `x`, a velocity `v` and its best position `pbest`; `gbest` is the
//! best position of the swarm. Each iteration `t = 0..T`, for every particle in turn, per
//! coordinate `j` with fresh `r1, r2 ~ U(0, 1)`:
//!
//! ```text
//! v_j ← w(t)·v_j + c1·r1·(pbest_j − x_j) + c2·r2·(gbest_j − x_j)
//! v_j ← clamp(v_j, −v_max·span_j, v_max·span_j)
//! x_j ← x_j + v_j,  then Space::fix(x)
//! ```
//!
//! then `x` is evaluated and `pbest` and `gbest` are updated at once when it is strictly better
//! (asynchronous update; NaN counts as `+inf`). In a wrapping space the differences
//! `pbest − x` and `gbest − x` are the shortest ones round the circle ([`Space::delta`]) and the
//! position is wrapped back, so a particle at 3.1 rad attracted by −3.1 rad moves by +0.08 across
//! ±π; otherwise the position is clamped (the velocity is left as it is).
//!
//! The inertia falls linearly from `w_start` at the first iteration to `w_end` at the last:
//! `w(t) = w_start + (w_end − w_start)·t/(T − 1)`. Initial velocities are uniform in
//! `[−v_max·span_j, v_max·span_j]`. Defaults ([`Pso::default`]): 20 particles, 40 iterations,
//! inertia 0.9 → 0.4 (Shi & Eberhart), `c1 = c2 = 2.0` (Kennedy & Eberhart), `v_max` = 0.2 of the
//! span — sized, like the DE defaults, to keep one per-step optimisation for 10 robots under about
//! a millisecond. The answer is `gbest`, the best point evaluated.
//!
//! Evaluations per call: `particles·(1 + iterations)` (with `particles` at least 1); 820 at the
//! defaults.

use rand::{Rng, RngExt};
use rand_chacha::ChaCha8Rng;

use crate::space::{Counted, Minimizer, Minimum, Space, argmin, initial_points, key};

/// Global-best PSO settings. See the module documentation for the algorithm and the defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct Pso {
    /// Swarm size (default 20; 0 is treated as 1).
    pub particles: usize,
    /// Number of iterations after the initial evaluation (default 40).
    pub iterations: usize,
    /// Inertia weight at the first iteration (default 0.9).
    pub w_start: f64,
    /// Inertia weight at the last iteration (default 0.4).
    pub w_end: f64,
    /// Cognitive coefficient: pull towards the particle's own best (default 2.0).
    pub c1: f64,
    /// Social coefficient: pull towards the swarm's best (default 2.0).
    pub c2: f64,
    /// Largest speed per coordinate and iteration, as a fraction of the coordinate's span
    /// `hi − lo` (default 0.2).
    pub v_max: f64,
}

impl Default for Pso {
    /// `particles: 20, iterations: 40, w_start: 0.9, w_end: 0.4, c1: 2.0, c2: 2.0, v_max: 0.2`
    /// (820 evaluations per call).
    fn default() -> Self {
        Pso {
            particles: 20,
            iterations: 40,
            w_start: 0.9,
            w_end: 0.4,
            c1: 2.0,
            c2: 2.0,
            v_max: 0.2,
        }
    }
}

impl Pso {
    /// Minimises `f` over `space`, starting from the `init` points (fixed into the space, placed
    /// first in the swarm; those beyond the swarm size are ignored) and uniform samples. Every
    /// random choice comes from `rng`. Returns the swarm's best point, its objective value and the
    /// number of evaluations (`max(particles, 1)·(1 + iterations)`).
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
        let n = self.particles.max(1);
        let dim = space.dim();
        let vmax: Vec<f64> = (0..dim).map(|j| self.v_max * space.span(j)).collect();
        let mut f = Counted::new(f);
        let mut x = initial_points(space, init, n, rng);
        let mut v: Vec<Vec<f64>> = (0..n)
            .map(|_| {
                vmax.iter()
                    .map(|&m| (2.0 * rng.random::<f64>() - 1.0) * m)
                    .collect()
            })
            .collect();
        let mut pbest_value: Vec<f64> = x.iter().map(|p| f.eval(p)).collect();
        let mut pbest = x.clone();
        let g = argmin(&pbest_value).expect("swarm is never empty");
        let mut gbest = pbest[g].clone();
        let mut gbest_value = pbest_value[g];
        for t in 0..self.iterations {
            let w = if self.iterations > 1 {
                self.w_start + (self.w_end - self.w_start) * t as f64 / (self.iterations - 1) as f64
            } else {
                self.w_start
            };
            for i in 0..n {
                for j in 0..dim {
                    let r1 = rng.random::<f64>();
                    let r2 = rng.random::<f64>();
                    let vj = w * v[i][j]
                        + self.c1 * r1 * space.delta(&x[i], &pbest[i], j)
                        + self.c2 * r2 * space.delta(&x[i], &gbest, j);
                    // `max` then `min` rather than `clamp`: no panic for a negative `v_max`.
                    v[i][j] = vj.max(-vmax[j]).min(vmax[j]);
                    x[i][j] += v[i][j];
                }
                space.fix(&mut x[i]);
                let fx = f.eval(&x[i]);
                if key(fx) < key(pbest_value[i]) {
                    pbest[i].clone_from(&x[i]);
                    pbest_value[i] = fx;
                    if key(fx) < key(gbest_value) {
                        gbest.clone_from(&x[i]);
                        gbest_value = fx;
                    }
                }
            }
        }
        Minimum {
            x: gbest,
            value: gbest_value,
            evaluations: f.evaluations,
        }
    }
}

impl Minimizer for Pso {
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
        "PSO"
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::space::testing::*;
    use rand::SeedableRng;

    #[test]
    fn sphere_5d() {
        let pso = Pso {
            iterations: 150,
            ..Pso::default()
        };
        let r = pso.minimize(
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
        let pso = Pso {
            particles: 40,
            iterations: 400,
            ..Pso::default()
        };
        let r = pso.minimize(
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
        let pso = Pso::default();
        assert!(heading_error(&pso, 3.0, &[]) < 0.01);
        assert!(heading_error(&pso, -3.1, &[vec![3.1]]) < 0.01);
        assert!(heading_error(&pso, -3.1, &[]) < 0.01);
    }

    #[test]
    fn contract() {
        check_contract(&Pso::default(), 820);
        check_init_used(&Pso {
            particles: 2,
            iterations: 1,
            ..Pso::default()
        });
        check_nan(&Pso::default());
        assert_eq!(Pso::default().name(), "PSO");
    }
}
