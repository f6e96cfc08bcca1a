//! The search space and result shared by the box-bounded continuous minimisers ([`crate::de`],
//! [`crate::pso`], [`crate::hbmo`]).
//!
//! A [`Space`] is a box `[lo_i, hi_i]` per coordinate. It is either *clamped* (a point outside the
//! box is moved to the nearest bound) or *wrapping*: every coordinate is periodic with period
//! `hi_i - lo_i` and lives in the half-open interval `[lo_i, hi_i)`. Wrapping is what headings
//! need: in the per-step heading optimisation of Sahoo et al. ("Navigational path planning of
//! multi-robot using Honey Bee Mating Optimization") each robot's heading θ_i is an angle in
//! `[-π, π)`, and θ = π - 0.01 is 0.02 rad from θ = -π + 0.01, not 2π - 0.02. In a wrapping space
//! the optimisers therefore take differences between points with [`Space::delta`] (the shortest
//! signed difference round the circle) and bring every new point back with [`Space::fix`].
//!
//! [`Minimizer`] is the object-safe form of the optimisers' common entry point
//! `minimize(&self, space, f, init, rng) -> Minimum`, for callers that pick the algorithm at run
//! time.
//!
//! NaN objective values are ordered as `+inf` by every optimiser (see [`Minimizer`]), so a NaN is
//! never chosen as the best point while any point has a number.

use rand::{Rng, RngExt};
use rand_chacha::ChaCha8Rng;

/// A box-bounded search space of dimension `lo.len()`.
///
/// Build it with [`Space::new`] (checked) or [`Space::angles`]; the fields are public for reading,
/// and a `Space` assembled by hand must keep `lo.len() == hi.len()` and `lo_i < hi_i` (both
/// finite) for the methods to make sense.
#[derive(Debug, Clone, PartialEq)]
pub struct Space {
    /// Lower bound of each coordinate.
    pub lo: Vec<f64>,
    /// Upper bound of each coordinate (exclusive when `wrap`, inclusive otherwise).
    pub hi: Vec<f64>,
    /// `true`: every coordinate is periodic with period `hi_i - lo_i` (angles) and is kept in
    /// `[lo_i, hi_i)`; `false`: coordinates are clamped into `[lo_i, hi_i]`.
    pub wrap: bool,
}

impl Space {
    /// A checked space. Errors (as a message) when `lo` and `hi` differ in length, are empty, or
    /// some bound is not finite or has `lo_i >= hi_i`.
    pub fn new(lo: Vec<f64>, hi: Vec<f64>, wrap: bool) -> Result<Space, String> {
        if lo.len() != hi.len() {
            return Err(format!(
                "space bounds differ in length: {} lower, {} upper",
                lo.len(),
                hi.len()
            ));
        }
        if lo.is_empty() {
            return Err("space has no coordinates".to_string());
        }
        for (i, (&l, &h)) in lo.iter().zip(&hi).enumerate() {
            if !l.is_finite() || !h.is_finite() {
                return Err(format!("coordinate {i}: bounds [{l}, {h}] are not finite"));
            }
            if l >= h {
                return Err(format!(
                    "coordinate {i}: lower bound {l} >= upper bound {h}"
                ));
            }
        }
        Ok(Space { lo, hi, wrap })
    }

    /// `n` headings: `[-π, π)` in every coordinate, wrapping (radians).
    ///
    /// # Panics
    /// If `n == 0` (a space needs a coordinate).
    pub fn angles(n: usize) -> Space {
        assert!(n > 0, "Space::angles needs at least one coordinate");
        Space {
            lo: vec![-std::f64::consts::PI; n],
            hi: vec![std::f64::consts::PI; n],
            wrap: true,
        }
    }

    /// Number of coordinates.
    pub fn dim(&self) -> usize {
        self.lo.len()
    }

    /// Width `hi_i - lo_i` of coordinate `i` (the period when wrapping).
    pub fn span(&self, i: usize) -> f64 {
        self.hi[i] - self.lo[i]
    }

    /// Brings `x` (length [`Space::dim`]) into the space: wrapped into `[lo_i, hi_i)` (any
    /// distance outside, e.g. 10π for an angle) or clamped into `[lo_i, hi_i]`. A non-finite
    /// coordinate (NaN, or ±inf when wrapping, which has no position on the circle) is put at the
    /// centre of its range; ±inf is clamped to the bound when not wrapping.
    pub fn fix(&self, x: &mut [f64]) {
        debug_assert_eq!(x.len(), self.dim(), "point and space differ in dimension");
        for ((xi, &lo), &hi) in x.iter_mut().zip(&self.lo).zip(&self.hi) {
            if xi.is_nan() || (self.wrap && xi.is_infinite()) {
                *xi = 0.5 * (lo + hi);
            } else if self.wrap && (lo..hi).contains(xi) {
                // Already inside: nothing to do (the common case, without a division).
            } else if self.wrap {
                let y = lo + (*xi - lo).rem_euclid(hi - lo);
                // Rounding can land exactly on `hi` (e.g. for a tiny negative offset).
                *xi = if y >= hi || y < lo { lo } else { y };
            } else {
                *xi = xi.clamp(lo, hi);
            }
        }
    }

    /// A uniformly random point of the space (each coordinate in `[lo_i, hi_i)`).
    pub fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> Vec<f64> {
        let mut x: Vec<f64> = self
            .lo
            .iter()
            .zip(&self.hi)
            .map(|(&lo, &hi)| lo + rng.random::<f64>() * (hi - lo))
            .collect();
        self.fix(&mut x);
        x
    }

    /// The signed difference `b_i - a_i` of coordinate `i`; when wrapping, the shortest one round
    /// the circle, in `(-span/2, span/2]` (so `a_i + delta` is `b_i` modulo the period).
    pub fn delta(&self, a: &[f64], b: &[f64], i: usize) -> f64 {
        let d = b[i] - a[i];
        if !self.wrap {
            return d;
        }
        let p = self.span(i);
        let r = d.rem_euclid(p);
        if r > 0.5 * p { r - p } else { r }
    }
}

/// The result of one minimisation.
#[derive(Debug, Clone, PartialEq)]
pub struct Minimum {
    /// The best point found (inside the space: already passed through [`Space::fix`]).
    pub x: Vec<f64>,
    /// The objective at `x`, exactly as the objective returned it when `x` was evaluated (NaN only
    /// if every evaluation was NaN).
    pub value: f64,
    /// How many times the objective was called.
    pub evaluations: usize,
}

/// A box-bounded continuous minimiser chosen at run time: the object-safe form of the generic
/// `minimize` each optimiser has ([`crate::de::De::minimize`], [`crate::pso::Pso::minimize`],
/// [`crate::hbmo::Hbmo::minimize`]), which does the work.
///
/// Contract shared by all implementations: `init` points (each of length `space.dim()`) are fixed
/// into the space and placed first in the initial population (the ones beyond its size are
/// ignored); every random choice comes from `rng`, so one seed gives one result; the returned
/// value is the objective of the returned point; NaN values count as `+inf`; `evaluations` counts
/// every call of `f`.
pub trait Minimizer: Send + Sync {
    /// Minimises `f` over `space`; see the trait documentation.
    fn minimize_dyn(
        &self,
        space: &Space,
        f: &mut dyn FnMut(&[f64]) -> f64,
        init: &[Vec<f64>],
        rng: &mut ChaCha8Rng,
    ) -> Minimum;
    /// Short name of the algorithm ("DE", "PSO", "HBMO").
    fn name(&self) -> &'static str;
}

/// The order the optimisers compare objective values by: NaN as `+inf`.
pub(crate) fn key(v: f64) -> f64 {
    if v.is_nan() { f64::INFINITY } else { v }
}

/// The objective with its evaluation counter.
pub(crate) struct Counted<F> {
    f: F,
    pub(crate) evaluations: usize,
}

impl<F: FnMut(&[f64]) -> f64> Counted<F> {
    pub(crate) fn new(f: F) -> Self {
        Counted { f, evaluations: 0 }
    }

    pub(crate) fn eval(&mut self, x: &[f64]) -> f64 {
        self.evaluations += 1;
        (self.f)(x)
    }
}

/// The `n` starting points: the caller's `init` points (fixed into the space, at most `n`) first,
/// then uniform samples.
///
/// # Panics
/// If an `init` point's length differs from the space's dimension.
pub(crate) fn initial_points<R: Rng + ?Sized>(
    space: &Space,
    init: &[Vec<f64>],
    n: usize,
    rng: &mut R,
) -> Vec<Vec<f64>> {
    let mut points = Vec::with_capacity(n);
    for p in init.iter().take(n) {
        assert_eq!(
            p.len(),
            space.dim(),
            "init point has {} coordinates, the space {}",
            p.len(),
            space.dim()
        );
        let mut x = p.clone();
        space.fix(&mut x);
        points.push(x);
    }
    while points.len() < n {
        points.push(space.sample(rng));
    }
    points
}

/// Index of the least value by [`key`] (the first on ties); `None` for an empty slice.
pub(crate) fn argmin(values: &[f64]) -> Option<usize> {
    let mut best: Option<usize> = None;
    for (i, &v) in values.iter().enumerate() {
        if best.is_none_or(|b| key(v) < key(values[b])) {
            best = Some(i);
        }
    }
    best
}

/// Shared test problems and checks.
#[cfg(test)]
pub(crate) mod testing {
    use super::*;
    use rand::SeedableRng;

    pub(crate) fn sphere(x: &[f64]) -> f64 {
        x.iter().map(|v| v * v).sum()
    }

    pub(crate) fn rastrigin(x: &[f64]) -> f64 {
        10.0 * x.len() as f64
            + x.iter()
                .map(|v| v * v - 10.0 * (2.0 * std::f64::consts::PI * v).cos())
                .sum::<f64>()
    }

    pub(crate) fn cube(n: usize, r: f64) -> Space {
        Space::new(vec![-r; n], vec![r; n], false).unwrap()
    }

    /// Runs `m` on the 1-D heading problem `1 - cos(θ - target)` and returns the angular error.
    pub(crate) fn heading_error(m: &dyn Minimizer, target: f64, init: &[Vec<f64>]) -> f64 {
        let space = Space::angles(1);
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mut f = |x: &[f64]| 1.0 - (x[0] - target).cos();
        let r = m.minimize_dyn(&space, &mut f, init, &mut rng);
        assert!((-std::f64::consts::PI..std::f64::consts::PI).contains(&r.x[0]));
        space.delta(&[target], &r.x, 0).abs()
    }

    /// Same seed, same result; the value is the objective of the point; two seeds evaluate
    /// different points.
    pub(crate) fn check_contract(m: &dyn Minimizer, expected_evaluations: usize) {
        let space = cube(3, 5.0);
        let run = |seed: u64| {
            let mut seen = Vec::new();
            let mut f = |x: &[f64]| {
                seen.push(x.to_vec());
                rastrigin(x)
            };
            let r = m.minimize_dyn(&space, &mut f, &[], &mut ChaCha8Rng::seed_from_u64(seed));
            (r, seen)
        };
        let (a, seen_a) = run(5);
        let (b, seen_b) = run(5);
        let (_, seen_c) = run(6);
        assert_eq!(a, b);
        assert_eq!(seen_a, seen_b);
        assert_ne!(seen_a, seen_c);
        assert_eq!(a.evaluations, seen_a.len());
        assert_eq!(a.evaluations, expected_evaluations);
        assert_eq!(a.value.to_bits(), rastrigin(&a.x).to_bits());
        assert!(seen_a.contains(&a.x));
    }

    /// A seed point at the optimum survives a tiny budget.
    pub(crate) fn check_init_used(m: &dyn Minimizer) {
        let space = cube(4, 5.0);
        let opt = vec![0.0; 4];
        let mut f = |x: &[f64]| sphere(x);
        let r = m.minimize_dyn(
            &space,
            &mut f,
            std::slice::from_ref(&opt),
            &mut ChaCha8Rng::seed_from_u64(3),
        );
        assert_eq!(r.x, opt);
        assert_eq!(r.value, 0.0);
    }

    /// NaN in half the space is never the answer, and the value is still f(x).
    pub(crate) fn check_nan(m: &dyn Minimizer) {
        let space = cube(2, 5.0);
        let g = |x: &[f64]| {
            if x[0] < 1.0 { f64::NAN } else { sphere(x) }
        };
        let mut f = g;
        // Start from a NaN point to make sure it is not kept as the best.
        let r = m.minimize_dyn(
            &space,
            &mut f,
            &[vec![0.0, 0.0]],
            &mut ChaCha8Rng::seed_from_u64(9),
        );
        assert!(!r.value.is_nan(), "{r:?}");
        assert!(r.x[0] >= 1.0);
        assert_eq!(r.value.to_bits(), g(&r.x).to_bits());
        // All-NaN objective: the result is NaN but still f(x), and nothing panics.
        let mut h = |_: &[f64]| f64::NAN;
        let r = m.minimize_dyn(&space, &mut h, &[], &mut ChaCha8Rng::seed_from_u64(9));
        assert!(r.value.is_nan());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use std::f64::consts::PI;

    #[test]
    fn new_checks_bounds() {
        assert!(Space::new(vec![0.0], vec![1.0, 2.0], false).is_err());
        assert!(Space::new(vec![], vec![], false).is_err());
        assert!(Space::new(vec![1.0], vec![1.0], false).is_err());
        assert!(Space::new(vec![2.0], vec![1.0], true).is_err());
        assert!(Space::new(vec![f64::NAN], vec![1.0], true).is_err());
        assert!(Space::new(vec![0.0], vec![f64::INFINITY], false).is_err());
        let s = Space::new(vec![0.0, -1.0], vec![1.0, 3.0], false).unwrap();
        assert_eq!(s.dim(), 2);
        assert_eq!(s.span(1), 4.0);
        let a = Space::angles(3);
        assert_eq!(a.dim(), 3);
        assert!(a.wrap);
        assert_eq!(a.span(2), 2.0 * PI);
    }

    #[test]
    fn fix_wraps_far_outside_values() {
        let s = Space::angles(1);
        let cases = [
            (0.5, 0.5),
            (PI, -PI),
            (-PI, -PI),
            (10.0 * PI, 0.0),
            (11.0 * PI + 0.5, -PI + 0.5),
            (-10.0 * PI + 0.25, 0.25),
            (3.0 * PI / 2.0, -PI / 2.0),
            (-3.0 * PI / 2.0, PI / 2.0),
            (1e6, (1e6f64 + PI).rem_euclid(2.0 * PI) - PI),
        ];
        for (input, want) in cases {
            let mut x = [input];
            s.fix(&mut x);
            assert!((x[0] - want).abs() < 1e-9, "{input} -> {} not {want}", x[0]);
            assert!((-PI..PI).contains(&x[0]));
        }
        // Tiny offsets below `lo` never land on `hi`.
        let mut x = [-PI - 1e-18, -PI - 1e-300];
        Space::angles(2).fix(&mut x);
        assert!(x.iter().all(|v| (-PI..PI).contains(v)), "{x:?}");
        // Non-finite values go to the centre.
        let mut x = [f64::NAN, f64::INFINITY];
        Space::angles(2).fix(&mut x);
        assert_eq!(x, [0.0, 0.0]);
    }

    #[test]
    fn fix_clamps_without_wrap() {
        let s = Space::new(vec![-1.0, 0.0, 2.0], vec![1.0, 5.0, 3.0], false).unwrap();
        let mut x = [10.0 * PI, -10.0 * PI, 2.5];
        s.fix(&mut x);
        assert_eq!(x, [1.0, 0.0, 2.5]);
        let mut x = [f64::INFINITY, f64::NEG_INFINITY, f64::NAN];
        s.fix(&mut x);
        assert_eq!(x, [1.0, 0.0, 2.5]);
    }

    #[test]
    fn delta_is_the_shortest_signed_difference() {
        let s = Space::angles(1);
        let d = |a: f64, b: f64| s.delta(&[a], &[b], 0);
        assert!((d(0.0, 1.0) - 1.0).abs() < 1e-12);
        assert!((d(1.0, 0.0) + 1.0).abs() < 1e-12);
        // Across the wrap point: from 3.1 to -3.1 is +0.083..., not -6.2.
        assert!((d(3.1, -3.1) - (2.0 * PI - 6.2)).abs() < 1e-12);
        assert!((d(-3.1, 3.1) + (2.0 * PI - 6.2)).abs() < 1e-12);
        // Far outside the range.
        assert!((d(0.0, 10.0 * PI + 0.3) - 0.3).abs() < 1e-9);
        assert!((d(-10.0 * PI, 0.3) - 0.3).abs() < 1e-9);
        // Exactly half a turn is +π (the interval is (-π, π]).
        assert!((d(0.0, PI) - PI).abs() < 1e-12);
        assert!((d(PI, 0.0) - PI).abs() < 1e-12);
        let mut rng = ChaCha8Rng::seed_from_u64(2);
        for _ in 0..1000 {
            let a = rng.random_range(-50.0..50.0);
            let b = rng.random_range(-50.0..50.0);
            let v = d(a, b);
            assert!(v > -PI && v <= PI);
            // a + delta is b modulo the period.
            let mut x = [a + v];
            let mut y = [b];
            s.fix(&mut x);
            s.fix(&mut y);
            assert!(s.delta(&x, &y, 0).abs() < 1e-9);
        }
        let c = Space::new(vec![-1.0], vec![1.0], false).unwrap();
        assert_eq!(c.delta(&[-0.9], &[0.9], 0), 1.8);
    }

    #[test]
    fn samples_are_inside_and_seeded() {
        let s = Space::new(vec![-1.0, 10.0], vec![1.0, 11.0], false).unwrap();
        let mut r1 = ChaCha8Rng::seed_from_u64(4);
        let mut r2 = ChaCha8Rng::seed_from_u64(4);
        for _ in 0..1000 {
            let x = s.sample(&mut r1);
            assert_eq!(x, s.sample(&mut r2));
            assert!((-1.0..1.0).contains(&x[0]) && (10.0..11.0).contains(&x[1]));
        }
    }

    #[test]
    fn nan_is_never_the_least() {
        assert_eq!(argmin(&[f64::NAN, 3.0, 1.0, 1.0]), Some(2));
        assert_eq!(argmin(&[f64::NAN, f64::NAN]), Some(0));
        assert_eq!(argmin(&[]), None);
        assert_eq!(key(f64::NAN), f64::INFINITY);
    }
}
