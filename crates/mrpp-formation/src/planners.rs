//! The sequential formation planner; every formation planner is registered in [`crate::PLANNERS`]:
//!
//! - [`Sequential`] — the sequential planner of Pereyra, Araguás and Kulich ("Sequential path
//!   planning for a formation of mobile robots with split and merge", LA-CCI 2017 / MESAS 2017),
//!   reconstructed from its abstracts: robots one at a time, each by Dijkstra on the **marginal**
//!   edge costs `c_e(n_e + 1) − c_e(n_e)` given the robots already placed (`n_e` of them on edge
//!   `e`); an edge already crossed the other way is forbidden. Splits and merges emerge where paths
//!   part and meet. Ties go to the lower vertex id. Should a path make the robots wait in a circle,
//!   or should no path be left within the corridors' capacity (the `hard` model), the robot takes
//!   the first robot's path instead; a plan that is then over a corridor's capacity (an infinite
//!   cost) is not returned: the planner gives up naming that corridor.
//! - [`crate::exact::Exact`] — the proven optimum (branch and bound, any R).
//! - [`crate::ga::Ga`] — the paper's genetic algorithm (§2.2).

use mrpp_core::{Ctx, Planner, PlannerEntry, Unsolved};

use crate::paths::dijkstra;
use crate::problem::{FormationPlan, FormationProblem};

/// Registry name of the sequential planner.
pub const SEQUENTIAL: &str = "sequential";
/// The sequential planner in the registry.
pub const SEQUENTIAL_ENTRY: PlannerEntry<FormationProblem> = PlannerEntry {
    name: SEQUENTIAL,
    about: "sequential Dijkstra on marginal edge costs, robot by robot, split and merge (Pereyra, Araguas, Kulich 2017)",
    params: &[],
    build: |_| Ok(Box::new(Sequential)),
};

/// The sequential planner.
#[derive(Debug, Clone, Copy, Default)]
pub struct Sequential;

/// One path per robot by Dijkstra on marginal costs; `scale(e)` multiplies each edge's weight (the
/// GA's diverse variants use noise; the planner itself uses 1).
pub fn sequential_paths(p: &FormationProblem, scale: &dyn Fn(u32) -> f64) -> Vec<Vec<u32>> {
    let r = p.roadmap();
    let m = r.edges.len();
    let (mut count, mut dir) = (vec![0usize; m], vec![0i8; m]);
    let mut paths: Vec<Vec<u32>> = Vec::with_capacity(p.robots());
    let banned = vec![false; r.num_vertices()];
    for _ in 0..p.robots() {
        let weight = |e: u32, a: u32, _: u32| {
            let forward = r.edges[e as usize].u == a;
            let d = if forward { 1 } else { -1 };
            if dir[e as usize] == -d {
                return f64::INFINITY;
            }
            let n = count[e as usize];
            let (next, now) = (p.edge_cost(e, n + 1), p.edge_cost(e, n));
            if next.is_infinite() {
                f64::INFINITY
            } else {
                (next - now).max(0.0) * scale(e)
            }
        };
        let mut path = dijkstra(r, p.start(), p.goal(), &banned, &weight).map(|(q, _)| q);
        if let Some(q) = &path {
            let mut trial = paths.clone();
            trial.push(q.clone());
            if p.evaluate(&trial).is_err() {
                path = None;
            }
        }
        let path = match (path, paths.first()) {
            (Some(q), _) => q,
            (None, Some(first)) => first.clone(),
            (None, None) => break,
        };
        for w in path.windows(2) {
            let e = r.edge_between(w[0], w[1]).expect("a roadmap path") as usize;
            count[e] += 1;
            dir[e] = if r.edges[e].u == w[0] { 1 } else { -1 };
        }
        paths.push(path);
    }
    paths
}

/// Why `planner`, whose best plan `paths` has no finite cost (or breaks a rule), returns no
/// plan: the bottleneck that proves no plan has a finite cost ([`crate::capacity`]), or, when
/// one exists, the first violation of `paths` (the corridor over capacity, typically).
pub(crate) fn no_finite_plan(p: &FormationProblem, planner: &str, paths: &[Vec<u32>]) -> Unsolved {
    Unsolved::GaveUp(match crate::capacity::within_capacity(p) {
        Err(bottleneck) => bottleneck.to_string(),
        Ok(_) => format!(
            "{planner} found no plan with a finite cost (one exists: the exact planner finds it); \
             its best: {}",
            p.why_not(paths)
        ),
    })
}

impl Planner<FormationProblem> for Sequential {
    fn name(&self) -> &str {
        SEQUENTIAL
    }
    /// # Errors
    /// [`Unsolved::TimeLimit`] at an expired deadline; [`Unsolved::GaveUp`] when `Q_goal`
    /// cannot be reached, or when the plan has no finite cost (naming the corridors over
    /// capacity: a minimum cut when no plan fits, else the plan's first such corridor).
    fn plan(&self, p: &FormationProblem, ctx: &Ctx) -> Result<FormationPlan, Unsolved> {
        if ctx.deadline.expired() {
            return Err(Unsolved::TimeLimit);
        }
        let paths = sequential_paths(p, &|_| 1.0);
        if paths.len() < p.robots() {
            return Err(Unsolved::GaveUp(
                "Q_goal cannot be reached from Q_ini on the roadmap".into(),
            ));
        }
        let plan = FormationPlan { paths };
        if p.metrics(&plan).is_err() {
            return Err(no_finite_plan(p, SEQUENTIAL, &plan.paths));
        }
        Ok(plan)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cost::CostModel;
    use crate::exact::{Exact, brute_force};
    use crate::problem::tests::diamond;
    use mrpp_core::{Problem, solve};

    #[test]
    fn sequential_splits_and_merges_on_the_diamond() {
        let p = diamond(CostModel::Hard);
        let s = solve(&Sequential, &p, &Ctx::default()).unwrap();
        assert_eq!(
            s.plan.paths,
            vec![vec![0, 1, 3], vec![0, 2, 3], vec![0, 2, 3]]
        );
        assert_eq!(s.metrics.c_max, 3.0);
        let e = solve(
            &Exact {
                candidate_limit: 100,
            },
            &p,
            &Ctx::default(),
        )
        .unwrap();
        assert_eq!(e.metrics.c_max, 3.0);
        assert_eq!(brute_force(&p, 100).unwrap().1, 3.0);
        assert_eq!(p.validate(&e.plan).unwrap().c_max, 3.0);
    }
}

#[cfg(test)]
mod property_tests {
    use super::*;
    use crate::cost::CostModel;
    use crate::exact::{Exact, brute_force};
    use crate::roadmap::Roadmap;
    use mrpp_core::solve;
    use proptest::prelude::*;
    use std::sync::Arc;

    /// A random connected graph: a spanning path 0..n plus extra chords, random lengths and
    /// clearances (some corridors narrower than a pair of robots).
    fn graph() -> impl Strategy<Value = (Roadmap, usize, u32)> {
        (
            4usize..=8,
            prop::collection::vec((0usize..8, 0usize..8, 1u32..=6, 1u32..=4), 1..=8),
            1usize..=5,
            any::<u64>(),
        )
            .prop_map(|(n, chords, robots, seed)| {
                let pts: Vec<[f64; 2]> =
                    (0..n).map(|i| [i as f64, (seed >> i & 3) as f64]).collect();
                let mut segs: Vec<(u32, u32, f64)> =
                    (0..n as u32 - 1).map(|i| (i, i + 1, 0.5)).collect();
                for (a, b, _, c) in &chords {
                    let (a, b) = ((*a % n) as u32, (*b % n) as u32);
                    if a != b && !segs.iter().any(|s| (s.0, s.1) == (a.min(b), a.max(b))) {
                        segs.push((a.min(b), a.max(b), f64::from(*c) * 0.3));
                    }
                }
                let mut r = Roadmap::from_segments(pts, &segs);
                for (k, e) in r.edges.iter_mut().enumerate() {
                    e.length = 1.0 + ((seed >> (k % 60)) & 7) as f64;
                }
                (r, robots, (n - 1) as u32)
            })
    }

    fn cost_model() -> impl Strategy<Value = CostModel> {
        prop_oneof![
            (0.0f64..=1.0).prop_map(|kappa| CostModel::Lanes { kappa }),
            Just(CostModel::Waves),
            Just(CostModel::Hard),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig {
            cases: 512,
            rng_seed: proptest::test_runner::RngSeed::Fixed(20_261_130),
            ..ProptestConfig::default()
        })]

        /// `exact` equals the paper's exhaustive search; sequential and GA are valid and never
        /// below it. A solved plan's metrics are finite; when no plan has a finite cost (only
        /// the hard model, every plan over some corridor's capacity), every planner gives up.
        #[test]
        fn exact_equals_brute_force((r, robots, goal) in graph(), cost in cost_model()) {
            let p = FormationProblem::new(Arc::new(r), robots, 0, goal, cost, 0.2).unwrap();
            let ctx = Ctx::default();
            let exact = solve(&Exact { candidate_limit: 100_000 }, &p, &ctx);
            let seq = solve(&Sequential, &p, &ctx);
            let ga = solve(&crate::ga::Ga { generations: 20, ..crate::ga::Ga::default() }, &p, &ctx);
            // The random start (`-p initial=random`): valid, never below the optimum.
            let random = crate::ga::Ga { generations: 20, random_start: true, ..crate::ga::Ga::default() };
            let ga_random = solve(&random, &p, &ctx);
            for s in [&exact, &seq, &ga, &ga_random].into_iter().flatten() {
                prop_assert!(s.metrics.c_max.is_finite() && s.metrics.sum_of_costs.is_finite());
            }
            for s in [&exact, &seq, &ga, &ga_random] {
                if let Err(e) = s {
                    prop_assert!(matches!(e, Unsolved::GaveUp(_)), "{e:?}");
                }
            }
            let (_, brute) = brute_force(&p, 100_000).unwrap();
            if !brute.is_finite() {
                prop_assert!(matches!(cost, CostModel::Hard));
                prop_assert!(exact.is_err() && seq.is_err() && ga.is_err() && ga_random.is_err());
                return Ok(());
            }
            if let Ok(g) = &ga_random {
                prop_assert!(g.metrics.c_max >= brute - 1e-9);
            }
            if !matches!(cost, CostModel::Hard) {
                prop_assert!(ga_random.is_ok());
            }
            let exact = exact.unwrap();
            prop_assert!((exact.metrics.c_max - brute).abs() < 1e-9, "exact {} brute {brute}", exact.metrics.c_max);
            // The heuristics may miss every plan within capacity under the hard model.
            if !matches!(cost, CostModel::Hard) {
                prop_assert!(seq.is_ok() && ga.is_ok());
            }
            if let Ok(seq) = &seq {
                let ga = ga.as_ref().expect("the GA starts from the sequential plan and keeps its best");
                prop_assert!(seq.metrics.c_max >= brute - 1e-9 && ga.metrics.c_max >= brute - 1e-9);
                prop_assert!(ga.metrics.c_max <= seq.metrics.c_max + 1e-9);
            }
            if let Ok(ga) = &ga {
                prop_assert!(ga.metrics.c_max >= brute - 1e-9);
            }
        }
    }
}
