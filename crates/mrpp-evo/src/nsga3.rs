//! NSGA-III (K. Deb, H. Jain, "An Evolutionary Many-Objective Optimization Algorithm Using
//! Reference-Point-Based Nondominated Sorting Approach, Part I", IEEE TEC 18(4), 2014), generic
//! over the problem.
//!
//! NSGA-II's crowding distance stops discriminating once most of the population is non-dominated,
//! which happens quickly with three or more objectives; NSGA-III replaces it with a fixed set of
//! well-spread reference directions and keeps, from the last front that fits only partly, the
//! members that fill the least crowded directions. The steps of one generation, each a function
//! named after the paper's step:
//!
//! 1. Offspring: parents picked at random (the paper uses no tournament), then the problem's
//!    [`Problem::crossover`] and [`Problem::mutate`].
//! 2. `R = P ∪ Q`, [`non_dominated_sort`] into `F1, F2, ...`; `S` = the fronts up to the first `F_l`
//!    with `|S| >= N`. If `|S| = N` the next population is `S`.
//! 3. [`normalize`]: ideal point, extreme points by the achievement scalarising function (ASF),
//!    intercepts of the hyperplane through them (falling back to the per-axis maximum when the
//!    hyperplane is degenerate).
//! 4. [`associate`] each member of `S` with the reference line of least perpendicular distance;
//!    the reference points come from [`das_dennis`].
//! 5. [`niching`]: members of `F_l` fill the reference points with the fewest associated members.
//!
//! Objectives are minimised. Every random choice draws from the caller's generator, and nothing
//! iterates a hash map, so a run is determined by its seed. The deadline is polled before every
//! evaluation; when it expires the run ends with the last complete population (a half-made
//! generation is dropped).

use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use mrpp_core::contract::Deadline;

/// A problem NSGA-III can optimise: how to make, judge and vary genomes.
pub trait Problem {
    type Genome: Clone;
    /// Number of objectives `M`.
    fn num_objectives(&self) -> usize;
    /// The `M` objective values of a genome (all minimised).
    fn evaluate(&self, genome: &Self::Genome) -> Vec<f64>;
    /// A random genome of the initial population.
    fn random_genome(&self, rng: &mut ChaCha8Rng) -> Self::Genome;
    /// Two children of two parents (the operator decides its own crossover probability).
    fn crossover(
        &self,
        a: &Self::Genome,
        b: &Self::Genome,
        rng: &mut ChaCha8Rng,
    ) -> (Self::Genome, Self::Genome);
    /// Mutates a child in place.
    fn mutate(&self, genome: &mut Self::Genome, rng: &mut ChaCha8Rng);
}

/// A genome with its objective values.
#[derive(Debug, Clone, PartialEq)]
pub struct Individual<G> {
    pub genome: G,
    pub objectives: Vec<f64>,
}

/// What the per-generation callback sees.
#[derive(Debug)]
pub struct Generation<'a, G> {
    /// 0 for the initial population, then 1, 2, ...
    pub index: usize,
    pub population: &'a [Individual<G>],
}

/// The per-generation callback of [`Nsga3::run`].
pub type OnGeneration<'a, G> = &'a mut dyn FnMut(&Generation<G>);

/// The result of a run.
#[derive(Debug, Clone)]
pub struct Outcome<G> {
    /// The last complete population (empty only if the deadline expired before it was evaluated).
    pub population: Vec<Individual<G>>,
    /// Generations completed after the initial population.
    pub generations: usize,
    /// The deadline ended the run early.
    pub interrupted: bool,
}

impl<G> Outcome<G> {
    /// The non-dominated members of the final population.
    pub fn first_front(&self) -> Vec<&Individual<G>> {
        let objs: Vec<&[f64]> = self
            .population
            .iter()
            .map(|i| i.objectives.as_slice())
            .collect();
        match non_dominated_sort(&objs).first() {
            Some(front) => front.iter().map(|&i| &self.population[i]).collect(),
            None => Vec::new(),
        }
    }
}

/// The NSGA-III driver's parameters.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Nsga3 {
    /// Generations after the initial population.
    pub generations: usize,
    /// Das–Dennis divisions `p` per objective axis (`H = C(M + p - 1, p)` reference points).
    pub divisions: usize,
    /// Population size `N`; `None` = the smallest multiple of 4 that is at least `H` (Deb & Jain).
    pub population: Option<usize>,
}

impl Default for Nsga3 {
    /// Deb & Jain's three-objective setting: `p = 12` (91 points, N = 92), 250 generations.
    fn default() -> Self {
        Nsga3 {
            generations: 250,
            divisions: 12,
            population: None,
        }
    }
}

/// The smallest multiple of 4 that is at least `h` (and at least 4).
pub fn population_for(h: usize) -> usize {
    h.max(1).div_ceil(4) * 4
}

impl Nsga3 {
    /// The population size used for `m` objectives.
    pub fn population_size(&self, m: usize) -> usize {
        self.population
            .unwrap_or_else(|| population_for(das_dennis(m, self.divisions).len()))
            .max(2)
    }

    /// Runs NSGA-III on `problem`. `on_generation` (if any) sees the initial population and the
    /// population after every generation.
    pub fn run<P: Problem>(
        &self,
        problem: &P,
        rng: &mut ChaCha8Rng,
        deadline: Deadline,
        mut on_generation: Option<OnGeneration<'_, P::Genome>>,
    ) -> Outcome<P::Genome> {
        let m = problem.num_objectives();
        let refs = das_dennis(m, self.divisions);
        let n = self.population_size(m);
        let stop = |population, generations| Outcome {
            population,
            generations,
            interrupted: true,
        };

        let mut pop = Vec::with_capacity(n);
        for _ in 0..n {
            if deadline.expired() {
                return stop(Vec::new(), 0);
            }
            let genome = problem.random_genome(rng);
            let objectives = problem.evaluate(&genome);
            pop.push(Individual { genome, objectives });
        }
        if let Some(f) = on_generation.as_mut() {
            f(&Generation {
                index: 0,
                population: &pop,
            });
        }

        for gen_index in 1..=self.generations {
            let Some(offspring) = make_offspring(problem, &pop, n, rng, deadline) else {
                return stop(pop, gen_index - 1);
            };
            let mut combined = pop;
            combined.extend(offspring);
            let objs: Vec<&[f64]> = combined.iter().map(|i| i.objectives.as_slice()).collect();
            let mut keep = select_survivors(&objs, n, &refs, rng);
            keep.sort_unstable();
            let mut next = Vec::with_capacity(n);
            let mut k = 0;
            for (i, ind) in combined.into_iter().enumerate() {
                if k < keep.len() && keep[k] == i {
                    next.push(ind);
                    k += 1;
                }
            }
            pop = next;
            if let Some(f) = on_generation.as_mut() {
                f(&Generation {
                    index: gen_index,
                    population: &pop,
                });
            }
        }
        Outcome {
            population: pop,
            generations: self.generations,
            interrupted: false,
        }
    }
}

/// Step 1: `n` offspring from random parent pairs; `None` when the deadline expires.
fn make_offspring<P: Problem>(
    problem: &P,
    pop: &[Individual<P::Genome>],
    n: usize,
    rng: &mut ChaCha8Rng,
    deadline: Deadline,
) -> Option<Vec<Individual<P::Genome>>> {
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        let a = rng.random_range(0..pop.len());
        let mut b = a;
        if pop.len() > 1 {
            b = rng.random_range(0..pop.len() - 1);
            if b >= a {
                b += 1;
            }
        }
        let (mut c1, mut c2) = problem.crossover(&pop[a].genome, &pop[b].genome, rng);
        problem.mutate(&mut c1, rng);
        problem.mutate(&mut c2, rng);
        for genome in [c1, c2] {
            if out.len() == n {
                break;
            }
            if deadline.expired() {
                return None;
            }
            let objectives = problem.evaluate(&genome);
            out.push(Individual { genome, objectives });
        }
    }
    Some(out)
}

/// Das–Dennis reference points: every point of the unit simplex in `m` dimensions whose
/// coordinates are multiples of `1/p`, `C(m + p - 1, p)` of them, first coordinate ascending
/// (`m = 2, p = 4`: (0,1), (¼,¾), (½,½), (¾,¼), (1,0)).
pub fn das_dennis(m: usize, p: usize) -> Vec<Vec<f64>> {
    assert!(m >= 1 && p >= 1, "das_dennis needs m >= 1 and p >= 1");
    fn rec(m: usize, left: usize, p: usize, cur: &mut Vec<usize>, out: &mut Vec<Vec<f64>>) {
        if cur.len() == m - 1 {
            cur.push(left);
            out.push(cur.iter().map(|&k| k as f64 / p as f64).collect());
            cur.pop();
            return;
        }
        for k in 0..=left {
            cur.push(k);
            rec(m, left - k, p, cur, out);
            cur.pop();
        }
    }
    let mut out = Vec::new();
    rec(m, p, p, &mut Vec::with_capacity(m), &mut out);
    out
}

/// Pareto dominance for minimisation: `a` is nowhere worse and somewhere better.
pub fn dominates(a: &[f64], b: &[f64]) -> bool {
    let mut better = false;
    for (x, y) in a.iter().zip(b) {
        if x > y {
            return false;
        }
        if x < y {
            better = true;
        }
    }
    better
}

/// Step 2, non-dominated sorting: the fronts `F1, F2, ...` (Pareto ranks) as indices into
/// `objs`, each in ascending index order. The same fronts as Deb et al.'s fast non-dominated sort
/// (2002), found by Zhang et al.'s efficient non-dominated sort with sequential search (ENS-SS,
/// IEEE TEVC 2015): points in lexicographic order of their objectives can only be dominated by
/// earlier ones, and each goes to the first front none of whose members dominates it. O(M N²) in
/// the worst case, far fewer comparisons in practice. Objectives must not be NaN.
pub fn non_dominated_sort(objs: &[&[f64]]) -> Vec<Vec<usize>> {
    let mut order: Vec<usize> = (0..objs.len()).collect();
    order.sort_by(|&a, &b| {
        objs[a]
            .iter()
            .zip(objs[b])
            .map(|(x, y)| x.partial_cmp(y).unwrap_or(std::cmp::Ordering::Equal))
            .find(|o| o.is_ne())
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    let mut fronts: Vec<Vec<usize>> = Vec::new();
    for i in order {
        // Later members of a front are the likelier dominators: check them first.
        let k = fronts
            .iter()
            .position(|f| !f.iter().rev().any(|&j| dominates(objs[j], objs[i])))
            .unwrap_or(fronts.len());
        if k == fronts.len() {
            fronts.push(Vec::new());
        }
        fronts[k].push(i);
    }
    for f in &mut fronts {
        f.sort_unstable();
    }
    fronts
}

/// Step 3: the normalised objectives of `objs` (the members of `S`). Translates by the ideal point
/// `z*`, finds each axis' extreme point by minimising the ASF `max_i f'_i / w_i` with `w = e_j`
/// (1e-6 elsewhere), and divides by the intercepts of the hyperplane through the extreme points.
/// When that hyperplane is degenerate (singular system, or an intercept that is not positive and
/// finite) each intercept falls back to the largest translated value on its axis.
pub fn normalize(objs: &[&[f64]]) -> Vec<Vec<f64>> {
    let Some(first) = objs.first() else {
        return Vec::new();
    };
    let m = first.len();
    let mut ideal = vec![f64::INFINITY; m];
    for f in objs {
        for (z, &v) in ideal.iter_mut().zip(f.iter()) {
            *z = z.min(v);
        }
    }
    let translated: Vec<Vec<f64>> = objs
        .iter()
        .map(|f| f.iter().zip(&ideal).map(|(v, z)| v - z).collect())
        .collect();
    let extremes: Vec<&[f64]> = (0..m)
        .map(|j| {
            let asf = |f: &[f64]| {
                f.iter()
                    .enumerate()
                    .map(|(i, &v)| if i == j { v } else { v / 1e-6 })
                    .fold(f64::NEG_INFINITY, f64::max)
            };
            let mut best = 0;
            let mut best_val = f64::INFINITY;
            for (k, f) in translated.iter().enumerate() {
                let v = asf(f);
                if v < best_val {
                    best_val = v;
                    best = k;
                }
            }
            translated[best].as_slice()
        })
        .collect();
    let hyperplane = solve_linear(&extremes, &vec![1.0; m]).and_then(|x| {
        let a: Vec<f64> = x.iter().map(|&xi| 1.0 / xi).collect();
        a.iter().all(|&ai| ai.is_finite() && ai > 1e-6).then_some(a)
    });
    let intercepts = hyperplane.unwrap_or_else(|| {
        (0..m)
            .map(|j| {
                let max = translated.iter().map(|f| f[j]).fold(0.0, f64::max);
                if max > 1e-12 { max } else { 1.0 }
            })
            .collect()
    });
    translated
        .into_iter()
        .map(|f| f.iter().zip(&intercepts).map(|(v, a)| v / a).collect())
        .collect()
}

/// Solves `A x = b` by Gaussian elimination with partial pivoting; `None` when `A` is singular.
fn solve_linear(a: &[&[f64]], b: &[f64]) -> Option<Vec<f64>> {
    let m = b.len();
    let mut aug: Vec<Vec<f64>> = a
        .iter()
        .zip(b)
        .map(|(row, &bi)| {
            let mut r = row.to_vec();
            r.push(bi);
            r
        })
        .collect();
    for col in 0..m {
        let pivot = (col..m).max_by(|&i, &j| aug[i][col].abs().total_cmp(&aug[j][col].abs()))?;
        if aug[pivot][col].abs() < 1e-12 {
            return None;
        }
        aug.swap(col, pivot);
        for row in 0..m {
            if row != col {
                let factor = aug[row][col] / aug[col][col];
                if factor != 0.0 {
                    let pivot_row = aug[col].clone();
                    for (x, p) in aug[row][col..].iter_mut().zip(&pivot_row[col..]) {
                        *x -= factor * p;
                    }
                }
            }
        }
    }
    Some((0..m).map(|i| aug[i][m] / aug[i][i]).collect())
}

/// Step 4: for each normalised member, the reference point whose line (through the origin) is
/// nearest, and the perpendicular distance `d⊥` to it (ties: the lower reference index).
pub fn associate(normalized: &[Vec<f64>], refs: &[Vec<f64>]) -> Vec<(usize, f64)> {
    let norms: Vec<f64> = refs.iter().map(|w| w.iter().map(|x| x * x).sum()).collect();
    normalized
        .iter()
        .map(|f| {
            let f_sq: f64 = f.iter().map(|x| x * x).sum();
            let mut best = (0, f64::INFINITY);
            for (j, w) in refs.iter().enumerate() {
                let dot: f64 = f.iter().zip(w).map(|(a, b)| a * b).sum();
                // |f - (w·f / |w|²) w|² = |f|² - (w·f)² / |w|².
                let d = (f_sq - dot * dot / norms[j]).max(0.0).sqrt();
                if d < best.1 {
                    best = (j, d);
                }
            }
            best
        })
        .collect()
}

/// Step 5, niching: picks `k` members of the last front `last` (indices into `assoc`) given the
/// niche counts `rho` of the members already chosen. Repeatedly takes a reference point of least
/// count (random tie); if no remaining member of `last` is associated with it, the point is
/// excluded; otherwise it adds the closest such member when the count is 0, else a random one.
pub fn niching(
    k: usize,
    rho: &mut [usize],
    assoc: &[(usize, f64)],
    last: &[usize],
    rng: &mut ChaCha8Rng,
) -> Vec<usize> {
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); rho.len()];
    for &s in last {
        members[assoc[s].0].push(s);
    }
    let mut excluded = vec![false; rho.len()];
    let mut chosen = Vec::with_capacity(k);
    let mut least = Vec::new();
    while chosen.len() < k {
        let Some(min) = (0..rho.len())
            .filter(|&j| !excluded[j])
            .map(|j| rho[j])
            .min()
        else {
            break;
        };
        least.clear();
        least.extend((0..rho.len()).filter(|&j| !excluded[j] && rho[j] == min));
        let j = least[rng.random_range(0..least.len())];
        if members[j].is_empty() {
            excluded[j] = true;
            continue;
        }
        let pos = if rho[j] == 0 {
            let mut best = 0;
            for (p, &s) in members[j].iter().enumerate() {
                if assoc[s].1 < assoc[members[j][best]].1 {
                    best = p;
                }
            }
            best
        } else {
            rng.random_range(0..members[j].len())
        };
        chosen.push(members[j].swap_remove(pos));
        rho[j] += 1;
    }
    chosen
}

/// Steps 2–5: the indices of the `n` members of `objs` (= `R`) that survive.
pub fn select_survivors(
    objs: &[&[f64]],
    n: usize,
    refs: &[Vec<f64>],
    rng: &mut ChaCha8Rng,
) -> Vec<usize> {
    let fronts = non_dominated_sort(objs);
    let mut next: Vec<usize> = Vec::with_capacity(n);
    let mut last: &[usize] = &[];
    for front in &fronts {
        if next.len() + front.len() <= n {
            next.extend_from_slice(front);
            if next.len() == n {
                return next;
            }
        } else {
            last = front;
            break;
        }
    }
    if last.is_empty() {
        return next;
    }
    // S = next ∪ last; positions 0..next.len() are the accepted members.
    let s: Vec<usize> = next.iter().chain(last).copied().collect();
    let s_objs: Vec<&[f64]> = s.iter().map(|&i| objs[i]).collect();
    let assoc = associate(&normalize(&s_objs), refs);
    let mut rho = vec![0usize; refs.len()];
    for a in &assoc[..next.len()] {
        rho[a.0] += 1;
    }
    let last_pos: Vec<usize> = (next.len()..s.len()).collect();
    let picked = niching(n - next.len(), &mut rho, &assoc, &last_pos, rng);
    next.extend(picked.into_iter().map(|p| s[p]));
    next
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::real::{polynomial_mutation, sbx};
    use rand::SeedableRng;

    #[test]
    fn das_dennis_counts_and_points() {
        assert_eq!(das_dennis(3, 12).len(), 91);
        assert_eq!(population_for(91), 92);
        assert_eq!(das_dennis(3, 12).iter().filter(|w| w[0] == 0.0).count(), 13);
        for w in das_dennis(3, 12) {
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        }
        assert_eq!(
            das_dennis(2, 4),
            vec![
                vec![0.0, 1.0],
                vec![0.25, 0.75],
                vec![0.5, 0.5],
                vec![0.75, 0.25],
                vec![1.0, 0.0]
            ]
        );
        assert_eq!(das_dennis(5, 6).len(), 210); // C(10, 6)
        assert_eq!(das_dennis(1, 3), vec![vec![1.0]]);
    }

    /// The fronts equal Pareto ranks found by peeling (the definition), on random points with
    /// many ties and duplicates, in 2 and 3 objectives.
    #[test]
    fn non_dominated_sort_matches_peeling() {
        let peel = |objs: &[&[f64]]| {
            let mut left: Vec<usize> = (0..objs.len()).collect();
            let mut fronts = Vec::new();
            while !left.is_empty() {
                let front: Vec<usize> = left
                    .iter()
                    .copied()
                    .filter(|&i| !left.iter().any(|&j| dominates(objs[j], objs[i])))
                    .collect();
                left.retain(|i| !front.contains(i));
                fronts.push(front);
            }
            fronts
        };
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for round in 0..300 {
            let m = 2 + round % 2;
            let n = rng.random_range(0..60);
            let points: Vec<Vec<f64>> = (0..n)
                .map(|_| (0..m).map(|_| rng.random_range(0..6) as f64).collect())
                .collect();
            let objs: Vec<&[f64]> = points.iter().map(|p| p.as_slice()).collect();
            assert_eq!(non_dominated_sort(&objs), peel(&objs), "round {round}");
        }
    }

    #[test]
    fn non_dominated_sort_hand_example() {
        let pts: Vec<Vec<f64>> = vec![
            vec![1.0, 5.0], // 0: F1
            vec![2.0, 3.0], // 1: F1
            vec![4.0, 1.0], // 2: F1
            vec![3.0, 4.0], // 3: dominated by 1 -> F2
            vec![5.0, 2.0], // 4: dominated by 2 -> F2
            vec![2.0, 3.0], // 5: equal to 1 (not dominated) -> F1
            vec![6.0, 4.5], // 6: dominated by 3 and 4, not by 7 -> F3
            vec![4.0, 5.0], // 7: dominated by 3 -> F3
        ];
        let objs: Vec<&[f64]> = pts.iter().map(Vec::as_slice).collect();
        assert_eq!(
            non_dominated_sort(&objs),
            vec![vec![0, 1, 2, 5], vec![3, 4], vec![6, 7]]
        );
        assert!(dominates(&[1.0, 2.0], &[1.0, 3.0]));
        assert!(!dominates(&[1.0, 2.0], &[1.0, 2.0]));
        assert!(!dominates(&[0.0, 3.0], &[1.0, 2.0]));
    }

    #[test]
    fn normalisation_maps_a_scaled_plane_to_the_simplex() {
        // Points on the plane f1/2 + f2/4 = 1, shifted by (1, 1): intercepts (2, 4).
        let pts: Vec<Vec<f64>> = vec![
            vec![3.0, 1.0],
            vec![1.0, 5.0],
            vec![2.0, 3.0],
            vec![1.5, 4.0],
        ];
        let objs: Vec<&[f64]> = pts.iter().map(Vec::as_slice).collect();
        let n = normalize(&objs);
        for f in &n {
            assert!((f[0] + f[1] - 1.0).abs() < 1e-9, "{f:?}");
        }
        let a = associate(&n, &das_dennis(2, 4));
        assert_eq!(a[0].0, 4);
        assert_eq!(a[1].0, 0);
        assert_eq!(a[2].0, 2);
        // Degenerate: all points equal -> fallback, no NaN.
        let same = [vec![1.0, 1.0], vec![1.0, 1.0]];
        let objs: Vec<&[f64]> = same.iter().map(Vec::as_slice).collect();
        assert!(normalize(&objs).iter().flatten().all(|v| v.is_finite()));
    }

    /// DTLZ2 with `m` objectives and `m - 1 + 10` variables in [0, 1].
    struct Dtlz2 {
        m: usize,
        bounds: Vec<(f64, f64)>,
    }

    impl Dtlz2 {
        fn new(m: usize) -> Self {
            Dtlz2 {
                m,
                bounds: vec![(0.0, 1.0); m - 1 + 10],
            }
        }
    }

    impl Problem for Dtlz2 {
        type Genome = Vec<f64>;
        fn num_objectives(&self) -> usize {
            self.m
        }
        fn evaluate(&self, x: &Vec<f64>) -> Vec<f64> {
            let m = self.m;
            let g: f64 = x[m - 1..].iter().map(|v| (v - 0.5) * (v - 0.5)).sum();
            let half_pi = std::f64::consts::FRAC_PI_2;
            (0..m)
                .map(|i| {
                    let mut f = 1.0 + g;
                    for &xj in &x[..m - 1 - i] {
                        f *= (xj * half_pi).cos();
                    }
                    if i > 0 {
                        f *= (x[m - 1 - i] * half_pi).sin();
                    }
                    f
                })
                .collect()
        }
        fn random_genome(&self, rng: &mut ChaCha8Rng) -> Vec<f64> {
            self.bounds.iter().map(|_| rng.random::<f64>()).collect()
        }
        fn crossover(
            &self,
            a: &Vec<f64>,
            b: &Vec<f64>,
            rng: &mut ChaCha8Rng,
        ) -> (Vec<f64>, Vec<f64>) {
            sbx(a, b, &self.bounds, 30.0, rng)
        }
        fn mutate(&self, x: &mut Vec<f64>, rng: &mut ChaCha8Rng) {
            let rate = 1.0 / self.bounds.len() as f64;
            polynomial_mutation(x, &self.bounds, 20.0, rate, rng);
        }
    }

    #[test]
    fn dtlz2_three_objectives_converges_and_covers_the_front() {
        let problem = Dtlz2::new(3);
        let algo = Nsga3 {
            generations: 250,
            divisions: 12,
            population: None,
        };
        let mut seen = 0;
        let mut progress = |g: &Generation<Vec<f64>>| {
            assert_eq!(g.index, seen);
            assert_eq!(g.population.len(), 92);
            seen += 1;
        };
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let out = algo.run(&problem, &mut rng, Deadline::none(), Some(&mut progress));
        assert_eq!(seen, 251);
        assert!(!out.interrupted);
        assert_eq!(out.generations, 250);
        assert_eq!(out.population.len(), 92);

        let radii: Vec<f64> = out
            .population
            .iter()
            .map(|i| i.objectives.iter().map(|v| v * v).sum::<f64>().sqrt())
            .collect();
        let mean = radii.iter().sum::<f64>() / radii.len() as f64;
        assert!((mean - 1.0).abs() < 0.05, "mean radius {mean}");
        assert!(radii.iter().all(|&r| r < 1.25), "{radii:?}");
        assert!(
            out.population
                .iter()
                .all(|i| i.objectives.iter().all(|&v| v >= 0.0))
        );

        // Coverage: the true front point of a reference direction w is w/|w| on the sphere.
        let refs = das_dennis(3, 12);
        let covered = refs
            .iter()
            .filter(|w| {
                let norm = w.iter().map(|v| v * v).sum::<f64>().sqrt();
                out.population.iter().any(|ind| {
                    let r = ind.objectives.iter().map(|v| v * v).sum::<f64>().sqrt();
                    let d: f64 = ind
                        .objectives
                        .iter()
                        .zip(w.iter())
                        .map(|(f, wi)| (f / r - wi / norm).powi(2))
                        .sum::<f64>()
                        .sqrt();
                    d < 0.05
                })
            })
            .count();
        assert!(covered >= 85, "only {covered} of 91 directions covered");

        // Same seed, same run.
        let mut rng2 = ChaCha8Rng::seed_from_u64(7);
        let again = algo.run(&problem, &mut rng2, Deadline::none(), None);
        assert_eq!(again.population, out.population);
    }

    #[test]
    fn expired_deadline_returns_what_exists() {
        let problem = Dtlz2::new(3);
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let out = Nsga3::default().run(
            &problem,
            &mut rng,
            Deadline::after(std::time::Duration::ZERO),
            None,
        );
        assert!(out.interrupted);
        assert!(out.population.is_empty());
        assert_eq!(out.generations, 0);
    }
}
