//! Real-coded variation operators as Deb's reference implementation (and Deb & Jain 2014) use them:
//! simulated binary crossover (SBX) and polynomial mutation, both bounded.
//!
//! They are the standard operators for the real-valued test problems (DTLZ, ZDT) on which the
//! NSGA-III driver is checked, and for later real-coded planners. Bounds are `(lower, upper)` per
//! variable; children are always clamped into them.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;

/// Bounded SBX with distribution index `eta` (Deb & Jain use 30). Each variable is crossed with
/// probability 0.5 (when the parents differ in it) and the two children's values are swapped with
/// probability 0.5, as in Deb's code.
pub fn sbx(
    a: &[f64],
    b: &[f64],
    bounds: &[(f64, f64)],
    eta: f64,
    rng: &mut ChaCha8Rng,
) -> (Vec<f64>, Vec<f64>) {
    let mut c1 = a.to_vec();
    let mut c2 = b.to_vec();
    for (i, &(lo, hi)) in bounds.iter().enumerate() {
        if rng.random::<f64>() > 0.5 || (a[i] - b[i]).abs() <= 1e-14 || hi <= lo {
            continue;
        }
        let (y1, y2) = if a[i] < b[i] {
            (a[i], b[i])
        } else {
            (b[i], a[i])
        };
        let u = rng.random::<f64>();
        let spread = |beta: f64| {
            let alpha = 2.0 - beta.powf(-(eta + 1.0));
            if u <= 1.0 / alpha {
                (u * alpha).powf(1.0 / (eta + 1.0))
            } else {
                (1.0 / (2.0 - u * alpha)).powf(1.0 / (eta + 1.0))
            }
        };
        let bq1 = spread(1.0 + 2.0 * (y1 - lo) / (y2 - y1));
        let v1 = (0.5 * ((y1 + y2) - bq1 * (y2 - y1))).clamp(lo, hi);
        let bq2 = spread(1.0 + 2.0 * (hi - y2) / (y2 - y1));
        let v2 = (0.5 * ((y1 + y2) + bq2 * (y2 - y1))).clamp(lo, hi);
        if rng.random::<f64>() <= 0.5 {
            c1[i] = v2;
            c2[i] = v1;
        } else {
            c1[i] = v1;
            c2[i] = v2;
        }
    }
    (c1, c2)
}

/// Bounded polynomial mutation with distribution index `eta` (Deb & Jain use 20); each variable
/// mutates with probability `rate` (usually 1/D).
pub fn polynomial_mutation(
    x: &mut [f64],
    bounds: &[(f64, f64)],
    eta: f64,
    rate: f64,
    rng: &mut ChaCha8Rng,
) {
    for (xi, &(lo, hi)) in x.iter_mut().zip(bounds) {
        if rng.random::<f64>() >= rate || hi <= lo {
            continue;
        }
        let y = *xi;
        let d1 = (y - lo) / (hi - lo);
        let d2 = (hi - y) / (hi - lo);
        let r = rng.random::<f64>();
        let pow = 1.0 / (eta + 1.0);
        let dq = if r < 0.5 {
            let v = 2.0 * r + (1.0 - 2.0 * r) * (1.0 - d1).powf(eta + 1.0);
            v.powf(pow) - 1.0
        } else {
            let v = 2.0 * (1.0 - r) + 2.0 * (r - 0.5) * (1.0 - d2).powf(eta + 1.0);
            1.0 - v.powf(pow)
        };
        *xi = (y + dq * (hi - lo)).clamp(lo, hi);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn children_stay_in_bounds_and_near_parents() {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let bounds = vec![(0.0, 1.0); 5];
        let a = [0.1, 0.2, 0.3, 0.4, 0.5];
        let b = [0.9, 0.8, 0.7, 0.6, 0.5];
        for _ in 0..1000 {
            let (mut c1, c2) = sbx(&a, &b, &bounds, 30.0, &mut rng);
            polynomial_mutation(&mut c1, &bounds, 20.0, 1.0, &mut rng);
            for v in c1.iter().chain(&c2) {
                assert!((0.0..=1.0).contains(v));
            }
            // Identical parent values are never changed by SBX.
            assert_eq!(c2[4], 0.5);
        }
    }
}
