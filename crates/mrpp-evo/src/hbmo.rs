//! Honey Bee Mating Optimization (HBMO), the minimiser of the per-step heading optimisation of
//! Sahoo et al., "Navigational path planning of multi-robot using Honey Bee Mating Optimization"
//! (§3, eq. 8–10, and the pseudo-code of §4), after H. A. Abbass, "MBO: Marriage in Honey Bees
//! Optimization — a Haplometrosis Polygynous Swarming Approach" (CEC 2001) and O. Bozorg Haddad,
//! A. Afshar, M. A. Mariño, "Honey-Bees Mating Optimization (HBMO) Algorithm: A New Heuristic
//! Approach for Water Resources Optimization" (Water Resources Management 20, 2006). It is a
//! box-bounded minimiser over a [`Space`]; in the paper a point is the vector of the robots'
//! headings θ_i ∈ [−π, π) ([`Space::angles`]), and the objective is minimised (lower is fitter).
//!
//! # Steps
//!
//! 1. **Initial population.** `population` points — the caller's `init` points first (fixed into
//!    the space), then uniform samples — are evaluated; the best is the *queen*.
//! 2. **Mating flight** (repeated `flights` times). The queen starts with speed
//!    `S = speed_max` and energy `E = energy_max`; `drones` uniformly random drones are generated
//!    and evaluated and, with `brood_drones` (the default), the broods of the previous flight
//!    that did not replace the queen join them as drones (§3: "If the brood fails to replace the
//!    queen, then in the next mating flight of the queen this brood will be one of the drones";
//!    their values are known, so they cost no evaluation). The spermatheca (capacity
//!    `spermatheca`) starts empty. While
//!    `S > speed_min` **and** the spermatheca is not full **and** `E > 0`: a drone is drawn
//!    uniformly (with replacement) and mates — its genotype is stored in the spermatheca — with
//!    probability `exp(−D/S)` (eq. 8), where `D` is the fitness difference between queen and drone;
//!    then `S ← α·S` (eq. 9) and `E ← γ·E` (eq. 10).
//! 3. **Broods.** For each of `broods` broods a sperm is taken at random from the spermatheca (a
//!    random drone if the spermatheca stayed empty) and
//!    `brood = drone + u·(queen − drone)` with one `u ~ U(0, 1)` per brood (the pseudo-code's
//!    `Brood_i = Drone_i + rand(0,1)(Queen − Drone_i)`); the difference is the shortest one round
//!    the circle in a wrapping space ([`Space::delta`]), and the brood is then fixed into the space
//!    and evaluated.
//! 4. **Workers.** The workers are `workers` local-search heuristics (Abbass; Haddad et al.):
//!    worker `k = 0, 1, ...` is a Gaussian hill climber with per-coordinate step
//!    `σ_k = 0.3·0.4^k·span_j`, which makes `local_steps` trial moves (every coordinate perturbed,
//!    fixed, evaluated) and keeps each one that strictly improves. Every brood is improved by one
//!    worker chosen by roulette over the workers' fitness, which starts at 1.0 for each worker and
//!    grows by the worker's relative improvement `(f_before − f_after)/max(|f_before|, 1e-12)`,
//!    clipped to `[0, 1]`, after each use ("choose the worker by roulette on its past gains and
//!    update its fitness"). The workers' fitness is kept across the flights of one call.
//! 5. **Replacement.** The best brood replaces the queen if it is strictly better; the other
//!    broods (all of them when none replaces the queen) are the next flight's extra drones when
//!    `brood_drones` is on.
//!
//! The answer is the final queen. NaN objective values count as `+inf` throughout (a NaN drone
//! never mates, a NaN brood never replaces the queen).
//!
//! # Where the paper is silent or was changed
//!
//! - **Parameters** are those of the paper's Table 1 (population 10, 9 drones, 9 broods, 5
//!   workers, spermatheca 9, speed 1.0 → 0.2, energy 1.0, α = γ = 0.93). The number of mating
//!   flights (the paper's `Maxiter`) is not given; the default is 18 flights, which gives the same
//!   budget as DE's and PSO's defaults (820 evaluations per call). `local_steps` (3)
//!   and the workers' steps are not given either.
//! - **Loop condition.** The pseudo-code reads "While Speed > S_min OR Spermatheca is NOT full",
//!   which never ends when no drone is accepted (the spermatheca then never fills, and the queen's
//!   speed only matters through the OR); the loop here uses AND, as in Abbass and Haddad et al.
//!   With `E ← γ·E` the energy never reaches 0, so at the defaults a flight ends when the
//!   spermatheca is full or after at most 23 transitions (0.93^23 < 0.2). For safety against
//!   α ≥ 1 a flight also ends after [`MAX_TRANSITIONS`] transitions.
//! - **The difference `D`** of eq. 8 is, with [`FitnessScale::Relative`] (the default),
//!   `|f(queen) − f(drone)| / max(|f(queen)|, 1e-12)`; with [`FitnessScale::Absolute`],
//!   `|f(queen) − f(drone)|` as written ("D(f) is the absolute difference between the fitness of
//!   D and the fitness of the queen"). The paper's *fitness* is maximised ("the bee with highest
//!   fitness") and never defined in terms of the minimised objective f (eq. 7), so its scale is
//!   not known; on f itself, a distance sum in hundreds of length units, an absolute difference
//!   divided by a speed ≤ 1 gives `exp(−D/S) ≈ 0` and almost no fresh drone mates (the broods
//!   then come from uniformly drawn drones, step 3; carried broods, near the queen, still mate).
//!   The relative difference makes the acceptance independent of the objective's unit.
//! - **Brood drones** (`brood_drones`, on by default: the paper states the step): the failed
//!   broods are *added* to the `drones` fresh ones, so a flight's drone pool holds up to
//!   `drones + broods` bees and the evaluation count does not change. The other reading (failed
//!   broods *replace* fresh drones) would lower the evaluations per flight. Off, every flight's
//!   drones are fresh uniform samples (mrpp before issue 32).
//! - **Drones** never replace the queen directly (only through broods: `u` near 0 gives a brood
//!   near the drone); the spermatheca is emptied between flights. The other members of the
//!   initial population only compete for the first queen. The caller's `init` points (the
//!   navigation loop's straight-to-target headings, which `Navigation::straight_init` in
//!   `mrpp-continuous` switches off) are the only non-random members; the paper's pseudo-code only
//!   says "Initialize all the bees (initial population)".
//! - **Parameter edge cases**: `population` and `drones` below 1 are treated as 1; `workers: 0`
//!   disables the local search.
//!
//! Evaluations per call: `population + flights·(drones + broods·(1 + local_steps))` (without the
//! `local_steps` term when `workers` is 0); 820 at the defaults.

use rand::{Rng, RngExt};
use rand_chacha::ChaCha8Rng;

use crate::space::{Counted, Minimizer, Minimum, Space, argmin, initial_points, key};

/// Upper bound on the drone draws of one mating flight, so that a flight ends even when the
/// speed does not fall (`alpha >= 1`).
pub const MAX_TRANSITIONS: usize = 10_000;

/// How the fitness difference `D` between queen and drone in the mating probability
/// `exp(−D/S)` (eq. 8) is measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FitnessScale {
    /// `D = |f(queen) − f(drone)| / max(|f(queen)|, 1e-12)`: independent of the objective's unit
    /// (the default, see the module documentation).
    #[default]
    Relative,
    /// `D = |f(queen) − f(drone)|`, as the paper writes it.
    Absolute,
}

/// HBMO settings; names and defaults as the paper's Table 1 where it gives them. See the module
/// documentation for the algorithm.
#[derive(Debug, Clone, PartialEq)]
pub struct Hbmo {
    /// Size of the initial population the first queen is chosen from (default 10; 0 is treated
    /// as 1).
    pub population: usize,
    /// Drones generated for each mating flight (default 9; 0 is treated as 1).
    pub drones: usize,
    /// Broods bred after each mating flight (default 9).
    pub broods: usize,
    /// Number of workers, i.e. local-search step sizes `0.3·0.4^k` of the span (default 5).
    pub workers: usize,
    /// Capacity of the queen's spermatheca (default 9).
    pub spermatheca: usize,
    /// Queen's speed at the start of a flight (default 1.0).
    pub speed_max: f64,
    /// A flight ends when the speed falls to this (default 0.2).
    pub speed_min: f64,
    /// Queen's energy at the start of a flight (default 1.0).
    pub energy_max: f64,
    /// Speed reduction factor per transition, `S ← α·S` (eq. 9; default 0.93).
    pub alpha: f64,
    /// Energy reduction factor per transition, `E ← γ·E` (eq. 10; default 0.93).
    pub gamma: f64,
    /// Number of mating flights (the paper's `Maxiter`, which it does not give; default 18, the
    /// evaluation budget of DE's and PSO's defaults).
    pub flights: usize,
    /// Trial moves of a worker on one brood (not in the paper; default 3).
    pub local_steps: usize,
    /// How `D` in the mating probability is measured (default [`FitnessScale::Relative`]).
    pub fitness_scale: FitnessScale,
    /// Broods that fail to replace the queen join the next flight's drones (§3, last sentence;
    /// default `true`). `false` gives every flight only fresh random drones.
    pub brood_drones: bool,
}

/// What one mating flight did (for tests and diagnostics): sizes, not contents.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FlightLog {
    /// Drones in the flight's pool: `drones` fresh ones plus the carried broods.
    pub drones: usize,
    /// Of those, broods of the previous flight (0 without `brood_drones`).
    pub carried: usize,
    /// Drones that mated (sperm stored in the spermatheca).
    pub matings: usize,
    /// Whether the best brood replaced the queen.
    pub replaced: bool,
}

impl Default for Hbmo {
    /// Table 1 of the paper: `population: 10, drones: 9, broods: 9, workers: 5, spermatheca: 9,
    /// speed_max: 1.0, speed_min: 0.2, energy_max: 1.0, alpha: 0.93, gamma: 0.93`; plus
    /// `flights: 18, local_steps: 3, fitness_scale: Relative, brood_drones: true` (820
    /// evaluations per call).
    fn default() -> Self {
        Hbmo {
            population: 10,
            drones: 9,
            broods: 9,
            workers: 5,
            spermatheca: 9,
            speed_max: 1.0,
            speed_min: 0.2,
            energy_max: 1.0,
            alpha: 0.93,
            gamma: 0.93,
            flights: 18,
            local_steps: 3,
            fitness_scale: FitnessScale::Relative,
            brood_drones: true,
        }
    }
}

impl Hbmo {
    /// Minimises `f` over `space`, starting from the `init` points (fixed into the space, placed
    /// first in the initial population; those beyond its size are ignored) and uniform samples.
    /// Every random choice comes from `rng`. Returns the final queen, its objective value and the
    /// number of evaluations (see the module documentation).
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
        self.minimize_logged(space, f, init, rng, &mut Vec::new())
    }

    /// [`Hbmo::minimize`], also appending one [`FlightLog`] per mating flight to `log` (the same
    /// random choices and result).
    pub fn minimize_logged<F: FnMut(&[f64]) -> f64, R: Rng + ?Sized>(
        &self,
        space: &Space,
        f: F,
        init: &[Vec<f64>],
        rng: &mut R,
        log: &mut Vec<FlightLog>,
    ) -> Minimum {
        let dim = space.dim();
        let mut f = Counted::new(f);

        // 1. Initial population; the best is the queen.
        let mut pop = initial_points(space, init, self.population.max(1), rng);
        let values: Vec<f64> = pop.iter().map(|x| f.eval(x)).collect();
        let q = argmin(&values).expect("population is never empty");
        let mut queen = pop.swap_remove(q);
        let mut queen_value = values[q];

        let sigmas: Vec<f64> = (0..self.workers)
            .map(|k| 0.3 * 0.4f64.powi(k as i32))
            .collect();
        let mut worker_fitness = vec![1.0; self.workers];
        // The previous flight's broods that did not replace the queen, with their values.
        let mut carried: Vec<(Vec<f64>, f64)> = Vec::new();

        for _ in 0..self.flights {
            // 2. Mating flight.
            let mut drones: Vec<Vec<f64>> =
                (0..self.drones.max(1)).map(|_| space.sample(rng)).collect();
            let mut drone_values: Vec<f64> = drones.iter().map(|d| f.eval(d)).collect();
            let n_carried = carried.len();
            for (b, v) in carried.drain(..) {
                drones.push(b);
                drone_values.push(v);
            }
            let mut sperm: Vec<usize> = Vec::with_capacity(self.spermatheca);
            let mut speed = self.speed_max;
            let mut energy = self.energy_max;
            let mut transitions = 0;
            while speed > self.speed_min
                && sperm.len() < self.spermatheca
                && energy > 0.0
                && transitions < MAX_TRANSITIONS
            {
                let d = rng.random_range(0..drones.len());
                let diff = (key(queen_value) - key(drone_values[d])).abs();
                let diff = match self.fitness_scale {
                    FitnessScale::Absolute => diff,
                    FitnessScale::Relative => diff / key(queen_value).abs().max(1e-12),
                };
                let p = (-diff / speed).exp();
                // A NaN probability (e.g. inf − inf) compares false: no mating.
                if rng.random::<f64>() < p {
                    sperm.push(d);
                }
                speed *= self.alpha;
                energy *= self.gamma;
                transitions += 1;
            }

            // 3. Broods, each improved by a worker (4.); the best is kept.
            let mut broods: Vec<(Vec<f64>, f64)> = Vec::with_capacity(self.broods);
            for _ in 0..self.broods {
                let d = if sperm.is_empty() {
                    rng.random_range(0..drones.len())
                } else {
                    sperm[rng.random_range(0..sperm.len())]
                };
                let drone = &drones[d];
                let u = rng.random::<f64>();
                let mut brood: Vec<f64> = (0..dim)
                    .map(|j| drone[j] + u * space.delta(drone, &queen, j))
                    .collect();
                space.fix(&mut brood);
                let mut brood_value = f.eval(&brood);

                if !sigmas.is_empty() {
                    let k = roulette(&worker_fitness, rng);
                    let before = key(brood_value);
                    for _ in 0..self.local_steps {
                        let mut trial: Vec<f64> = brood
                            .iter()
                            .enumerate()
                            .map(|(j, &b)| b + sigmas[k] * space.span(j) * gaussian(rng))
                            .collect();
                        space.fix(&mut trial);
                        let v = f.eval(&trial);
                        if key(v) < key(brood_value) {
                            brood = trial;
                            brood_value = v;
                        }
                    }
                    worker_fitness[k] += relative_gain(before, key(brood_value));
                }

                broods.push((brood, brood_value));
            }

            // 5. The best brood (the first on ties) replaces the queen if it is strictly better;
            // the others become drones of the next flight.
            let best = argmin(&broods.iter().map(|(_, v)| *v).collect::<Vec<_>>());
            let mut replaced = false;
            if let Some(b) = best
                && key(broods[b].1) < key(queen_value)
            {
                let (brood, value) = broods.remove(b);
                queen = brood;
                queen_value = value;
                replaced = true;
            }
            if self.brood_drones {
                carried = broods;
            }
            log.push(FlightLog {
                drones: drones.len(),
                carried: n_carried,
                matings: sperm.len(),
                replaced,
            });
        }

        Minimum {
            x: queen,
            value: queen_value,
            evaluations: f.evaluations,
        }
    }
}

/// Relative improvement from `before` to `after` (both already NaN-free, `after <= before`),
/// clipped to `[0, 1]`: a step from `+inf` to a number counts 1.
fn relative_gain(before: f64, after: f64) -> f64 {
    if before.is_finite() {
        let g = (before - after) / before.abs().max(1e-12);
        if g.is_nan() { 0.0 } else { g.clamp(0.0, 1.0) }
    } else if after < before {
        1.0
    } else {
        0.0
    }
}

/// Index drawn with probability proportional to `weights` (all positive and finite).
fn roulette<R: Rng + ?Sized>(weights: &[f64], rng: &mut R) -> usize {
    let total: f64 = weights.iter().sum();
    let mut r = rng.random::<f64>() * total;
    for (k, &w) in weights.iter().enumerate() {
        if r < w {
            return k;
        }
        r -= w;
    }
    weights.len() - 1
}

/// A standard normal sample (Marsaglia's polar method, no trigonometry; `rand` 0.10 has no
/// normal distribution without `rand_distr`).
fn gaussian<R: Rng + ?Sized>(rng: &mut R) -> f64 {
    loop {
        let u = 2.0 * rng.random::<f64>() - 1.0;
        let v = 2.0 * rng.random::<f64>() - 1.0;
        let s = u * u + v * v;
        if s > 0.0 && s < 1.0 {
            return u * (-2.0 * s.ln() / s).sqrt();
        }
    }
}

impl Minimizer for Hbmo {
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
        "HBMO"
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::space::testing::*;
    use rand::SeedableRng;

    #[test]
    fn sphere_5d() {
        // HBMO refines slowly: broods lie on segments from random drones to the queen and the
        // finest worker step is 0.3·0.4^4 of the span, so 1e-3 takes ~45 000 evaluations here
        // (DE and PSO need ~3 000).
        let hbmo = Hbmo {
            flights: 1000,
            ..Hbmo::default()
        };
        let r = hbmo.minimize(
            &cube(5, 5.0),
            sphere,
            &[],
            &mut ChaCha8Rng::seed_from_u64(1),
        );
        assert!(r.value < 1e-3, "{r:?}");
        assert_eq!(r.value, sphere(&r.x));
        assert_eq!(r.evaluations, 10 + 1000 * (9 + 9 * 4));
    }

    #[test]
    fn rastrigin_5d() {
        let hbmo = Hbmo {
            flights: 1000,
            ..Hbmo::default()
        };
        let r = hbmo.minimize(
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
        let hbmo = Hbmo::default();
        assert!(heading_error(&hbmo, 3.0, &[]) < 0.01);
        assert!(heading_error(&hbmo, -3.1, &[vec![3.1]]) < 0.01);
        assert!(heading_error(&hbmo, -3.1, &[]) < 0.01);
    }

    #[test]
    fn contract() {
        check_contract(&Hbmo::default(), 820);
        check_init_used(&Hbmo {
            flights: 1,
            ..Hbmo::default()
        });
        check_nan(&Hbmo::default());
        assert_eq!(Hbmo::default().name(), "HBMO");
        let no_workers = Hbmo {
            workers: 0,
            ..Hbmo::default()
        };
        let r = no_workers.minimize(
            &cube(2, 1.0),
            sphere,
            &[],
            &mut ChaCha8Rng::seed_from_u64(0),
        );
        assert_eq!(r.evaluations, 10 + 18 * 18);
    }

    #[test]
    fn drones_mate_on_large_objectives() {
        // With values in the hundreds, the relative difference lets drones mate; the absolute one
        // does not. Observe it through the broods: with an empty spermatheca the broods come
        // from all drones, with matings only from the mated ones, so the runs differ.
        let space = cube(3, 5.0);
        let f = |x: &[f64]| 300.0 + sphere(x);
        let run = |scale| {
            Hbmo {
                fitness_scale: scale,
                ..Hbmo::default()
            }
            .minimize(&space, f, &[], &mut ChaCha8Rng::seed_from_u64(2))
        };
        let rel = run(FitnessScale::Relative);
        let abs = run(FitnessScale::Absolute);
        assert_ne!(rel, abs);
        assert!(rel.value < 300.5, "{rel:?}");
    }

    #[test]
    fn failed_broods_become_drones_of_the_next_flight() {
        // §3: "If the brood fails to replace the queen, then in the next mating flight of the
        // queen this brood will be one of the drones". On: flight k > 0 has the 9 fresh drones
        // plus the 9 broods of flight k − 1 (8 when one of them replaced the queen); off: 9.
        let space = cube(3, 5.0);
        let run = |brood_drones| {
            let mut log = Vec::new();
            let r = Hbmo {
                brood_drones,
                ..Hbmo::default()
            }
            .minimize_logged(
                &space,
                sphere,
                &[],
                &mut ChaCha8Rng::seed_from_u64(3),
                &mut log,
            );
            (r, log)
        };
        let (on, log_on) = run(true);
        let (off, log_off) = run(false);
        assert_eq!(log_on.len(), 18);
        assert_eq!((log_on[0].drones, log_on[0].carried), (9, 0));
        for k in 1..18 {
            let expect = if log_on[k - 1].replaced { 8 } else { 9 };
            assert_eq!(log_on[k].carried, expect, "flight {k}: {log_on:?}");
            assert_eq!(log_on[k].drones, 9 + expect);
        }
        assert!(log_off.iter().all(|l| l.drones == 9 && l.carried == 0));
        // Carried drones cost no evaluation: the budget is the same.
        assert_eq!(on.evaluations, 820);
        assert_eq!(off.evaluations, 820);
        assert_ne!(on.x, off.x);
    }

    #[test]
    fn absolute_difference_stops_mating_on_large_objectives() {
        // Eq. 8 with D = |f(queen) − f(drone)| on values in the hundreds: exp(−D/S) ≈ 0 for
        // every fresh drone that differs from the queen by more than a few units, so the
        // spermatheca stays (nearly) empty; with the relative difference drones mate in every
        // flight. (Carried broods lie near the queen and do mate under the absolute rule, so
        // this compares fresh drones only.)
        let space = cube(3, 5.0);
        let f = |x: &[f64]| 300.0 + sphere(x);
        let matings = |scale| {
            let mut log = Vec::new();
            Hbmo {
                fitness_scale: scale,
                brood_drones: false,
                ..Hbmo::default()
            }
            .minimize_logged(
                &space,
                f,
                &[],
                &mut ChaCha8Rng::seed_from_u64(2),
                &mut log,
            );
            log.iter().map(|l| l.matings).sum::<usize>()
        };
        let rel = matings(FitnessScale::Relative);
        let abs = matings(FitnessScale::Absolute);
        // Relative: the spermatheca (9) fills in every one of the 18 flights.
        assert_eq!(rel, 18 * 9, "relative");
        assert!(abs * 10 < rel, "absolute: {abs}, relative: {rel}");
    }

    #[test]
    fn helpers() {
        assert_eq!(relative_gain(10.0, 5.0), 0.5);
        assert_eq!(relative_gain(-10.0, -50.0), 1.0);
        assert_eq!(relative_gain(f64::INFINITY, 1.0), 1.0);
        assert_eq!(relative_gain(f64::INFINITY, f64::INFINITY), 0.0);
        assert_eq!(relative_gain(0.0, 0.0), 0.0);
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let mut counts = [0usize; 3];
        for _ in 0..30_000 {
            counts[roulette(&[1.0, 2.0, 3.0], &mut rng)] += 1;
        }
        assert!(
            (counts[2] as f64 / 30_000.0 - 0.5).abs() < 0.02,
            "{counts:?}"
        );
        let (mut m, mut s) = (0.0, 0.0);
        for _ in 0..20_000 {
            let g = gaussian(&mut rng);
            m += g;
            s += g * g;
        }
        assert!((m / 20_000.0f64).abs() < 0.03 && (s / 20_000.0 - 1.0f64).abs() < 0.05);
    }
}
