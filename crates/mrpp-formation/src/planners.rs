//! The formation planners, each registered in [`crate::PLANNERS`]:
//!
//! - [`Sequential`] — the sequential planner of Pereyra, Araguás and Kulich ("Sequential path
//!   planning for a formation of mobile robots with split and merge", LA-CCI 2017 / MESAS 2017),
//!   reconstructed from its abstracts: robots one at a time, each by Dijkstra on the **marginal**
//!   edge costs `c_e(n_e + 1) − c_e(n_e)` given the robots already placed (`n_e` of them on edge
//!   `e`); an edge already crossed the other way is forbidden. Splits and merges emerge where paths
//!   part and meet. Ties go to the lower vertex id. Should a path make the robots wait in a circle,
//!   the robot takes the first robot's path instead, so the planner always returns a valid plan.
//! - [`Exact`] — the optimum `c_max`, proven by branch and bound. Every path of an optimal plan
//!   costs at least its length (costs never fall below `c_e(1) = ℓ_e`), so the candidate paths are
//!   the simple paths no longer than the best known `c_max` (Yen's algorithm, shortest
//!   first). Robots are identical, so a plan is a multiset of candidates, searched depth-first
//!   with non-decreasing candidate index; adding a path never lowers `c_max` (costs are
//!   non-decreasing in the robot count and waits only grow), so a partial plan's `c_max` bounds its
//!   completions — all the more when edges that every candidate uses are counted with all R
//!   robots from the start — and a candidate no shorter than the best `c_max` ends the loop. The first bound
//!   is the better of the sequential plan and a short GA run (30 generations, seed 0), which keeps
//!   the candidate set small when that plan is already optimal; then a greedy placement with
//!   single-robot moves over the 200 shortest candidates may lower it further (large R, where
//!   robots spread over many corridors). The paper's
//!   exhaustive search (every simple path, every multiset) is [`brute_force`], used to check it.
//! - [`crate::ga::Ga`] — the paper's genetic algorithm (§2.2).

use mrpp_core::{Ctx, Param, Planner, PlannerEntry, Unsolved};

use crate::paths::{Cut, all_simple_paths, dijkstra, paths_up_to};
use crate::problem::{FormationPlan, FormationProblem};

/// Registry name of the sequential planner.
pub const SEQUENTIAL: &str = "sequential";
/// Registry name of the exact planner.
pub const EXACT: &str = "exact";

/// The sequential planner in the registry.
pub const SEQUENTIAL_ENTRY: PlannerEntry<FormationProblem> = PlannerEntry {
    name: SEQUENTIAL,
    about: "sequential Dijkstra on marginal edge costs, robot by robot, split and merge (Pereyra, Araguas, Kulich 2017)",
    params: &[],
    build: |_| Ok(Box::new(Sequential)),
};

/// The exact planner in the registry.
pub const EXACT_ENTRY: PlannerEntry<FormationProblem> = PlannerEntry {
    name: EXACT,
    about: "proven optimum c_max: branch and bound over k-shortest paths (the GA paper's exhaustive baseline, any R)",
    params: &[Param {
        name: "candidate_limit",
        default: "200000",
        doc: "most candidate paths considered; more within the bound = gave up",
    }],
    build: |p| {
        Ok(Box::new(Exact {
            candidate_limit: p.get_in("candidate_limit", 1..=10_000_000)?,
        }))
    },
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

impl Planner<FormationProblem> for Sequential {
    fn name(&self) -> &str {
        SEQUENTIAL
    }
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
        Ok(FormationPlan { paths })
    }
}

/// The exact planner.
#[derive(Debug, Clone, Copy)]
pub struct Exact {
    pub candidate_limit: usize,
}

impl Planner<FormationProblem> for Exact {
    fn name(&self) -> &str {
        EXACT
    }
    fn plan(&self, p: &FormationProblem, ctx: &Ctx) -> Result<FormationPlan, Unsolved> {
        // The first bound: the better of the sequential plan and a short GA run (both valid).
        let seq = sequential_paths(p, &|_| 1.0);
        if seq.len() < p.robots() {
            return Err(Unsolved::GaveUp(
                "Q_goal cannot be reached from Q_ini on the roadmap".into(),
            ));
        }
        let seq_cost = p.evaluate(&seq).map(|e| e.c_max).unwrap_or(f64::INFINITY);
        let ga = crate::ga::Ga {
            generations: 30,
            ..crate::ga::Ga::default()
        };
        let (seed, ub) = match ga.run(p, &Ctx::new(0, ctx.deadline)) {
            Some(run) if run.c_max < seq_cost => (run.plan.paths, run.c_max),
            _ => (seq, seq_cost),
        };
        let bound = if ub.is_finite() { ub } else { f64::MAX };
        let (lim, dl) = (self.candidate_limit, &ctx.deadline);
        let cands = paths_up_to(p.roadmap(), p.start(), p.goal(), bound, lim, dl).map_err(
            |cut| match cut {
                Cut::Deadline => Unsolved::TimeLimit,
                Cut::Limit => Unsolved::GaveUp(format!(
                    "more than {lim} candidate paths within the bound {ub}"
                )),
            },
        )?;
        // A tighter first bound when robots can spread: greedy c_max plus local moves over the
        // shortest candidates (only lowers the bound; the search still proves the optimum).
        let (seed, ub) = match greedy_incumbent(p, &cands[..cands.len().min(200)]) {
            Some((plan, c)) if c < ub => (plan, c),
            _ => (seed, ub),
        };
        // Edges on every candidate path carry all R robots in any plan made of candidates: the
        // search bounds partial plans with them counted at R.
        let mut floor = vec![0usize; p.roadmap().edges.len()];
        if let Some((first, _)) = cands.first() {
            for w in first.windows(2) {
                let e = p
                    .roadmap()
                    .edge_between(w[0], w[1])
                    .expect("a roadmap path");
                let on_all = cands
                    .iter()
                    .all(|(q, _)| q.windows(2).any(|x| (x[0], x[1]) == (w[0], w[1])));
                if on_all {
                    floor[e as usize] = p.robots();
                }
            }
        }
        let mut search = Search {
            p,
            cands: &cands,
            best: ub,
            best_plan: seed,
            ctx,
            steps: 0,
            floor,
        };
        search.dfs(&mut Vec::new(), 0)?;
        Ok(FormationPlan {
            paths: search.best_plan,
        })
    }
}

/// Robots placed one by one, each on the candidate that gives the lowest `c_max` so far (ties:
/// the shorter candidate), then single-robot moves to other candidates while one lowers `c_max`.
fn greedy_incumbent(
    p: &FormationProblem,
    cands: &[(Vec<u32>, f64)],
) -> Option<(Vec<Vec<u32>>, f64)> {
    let cost = |paths: &[Vec<u32>]| p.evaluate(paths).map_or(f64::INFINITY, |e| e.c_max);
    let mut chosen: Vec<Vec<u32>> = Vec::with_capacity(p.robots());
    for _ in 0..p.robots() {
        let mut best: Option<(f64, &Vec<u32>)> = None;
        for (q, _) in cands {
            chosen.push(q.clone());
            let c = cost(&chosen);
            chosen.pop();
            if best.is_none_or(|b| c < b.0) {
                best = Some((c, q));
            }
        }
        chosen.push(best?.1.clone());
    }
    let mut current = cost(&chosen);
    let mut improved = true;
    while improved {
        improved = false;
        for i in 0..chosen.len() {
            for (q, _) in cands {
                let old = std::mem::replace(&mut chosen[i], q.clone());
                let c = cost(&chosen);
                if c < current - 1e-12 {
                    current = c;
                    improved = true;
                } else {
                    chosen[i] = old;
                }
            }
        }
    }
    current.is_finite().then_some((chosen, current))
}

/// The branch-and-bound state.
struct Search<'a> {
    p: &'a FormationProblem,
    cands: &'a [(Vec<u32>, f64)],
    best: f64,
    best_plan: Vec<Vec<u32>>,
    ctx: &'a Ctx,
    steps: u64,
    /// Robots counted at least on each edge while bounding (R on edges every candidate uses).
    floor: Vec<usize>,
}

impl Search<'_> {
    fn dfs(&mut self, chosen: &mut Vec<Vec<u32>>, from: usize) -> Result<(), Unsolved> {
        let eps = 1e-9 * self.best.abs().max(1.0);
        for i in from..self.cands.len() {
            if self.cands[i].1 >= self.best - eps {
                break;
            }
            self.steps += 1;
            if self.steps.is_multiple_of(1024) && self.ctx.deadline.expired() {
                return Err(Unsolved::TimeLimit);
            }
            chosen.push(self.cands[i].0.clone());
            let bound = if chosen.len() == self.p.robots() {
                self.p.evaluate(chosen)
            } else {
                self.p.evaluate_with_floor(chosen, &self.floor)
            };
            if let Ok(ev) = bound
                && ev.c_max < self.best - eps
            {
                if chosen.len() == self.p.robots() {
                    self.best = ev.c_max;
                    self.best_plan = chosen.clone();
                } else {
                    self.dfs(chosen, i)?;
                }
            }
            chosen.pop();
        }
        Ok(())
    }
}

/// The paper's exhaustive search: every multiset of `robots` simple paths (at most `limit` paths);
/// the optimal plan and its `c_max`, or `None` when there are more paths.
pub fn brute_force(p: &FormationProblem, limit: usize) -> Option<(Vec<Vec<u32>>, f64)> {
    let all = all_simple_paths(p.roadmap(), p.start(), p.goal(), limit)?;
    fn go(
        p: &FormationProblem,
        all: &[Vec<u32>],
        chosen: &mut Vec<Vec<u32>>,
        from: usize,
        best: &mut Option<(Vec<Vec<u32>>, f64)>,
    ) {
        if chosen.len() == p.robots() {
            if let Ok(ev) = p.evaluate(chosen)
                && best.as_ref().is_none_or(|b| ev.c_max < b.1)
            {
                *best = Some((chosen.clone(), ev.c_max));
            }
            return;
        }
        for i in from..all.len() {
            chosen.push(all[i].clone());
            go(p, all, chosen, i, best);
            chosen.pop();
        }
    }
    let mut best = None;
    go(p, &all, &mut Vec::new(), 0, &mut best);
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cost::CostModel;
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
    use crate::roadmap::Roadmap;
    use mrpp_core::solve;
    use proptest::prelude::*;
    use std::sync::Arc;

    /// A random connected graph: a spanning path 0..n plus extra chords, random lengths and
    /// clearances (some corridors narrower than a pair of robots).
    fn graph() -> impl Strategy<Value = (Roadmap, usize, u32)> {
        (
            4usize..=7,
            prop::collection::vec((0usize..7, 0usize..7, 1u32..=6, 1u32..=4), 1..=6),
            1usize..=3,
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

    proptest! {
        #![proptest_config(ProptestConfig {
            cases: 128,
            rng_seed: proptest::test_runner::RngSeed::Fixed(20_261_130),
            ..ProptestConfig::default()
        })]

        /// `exact` equals the paper's exhaustive search; sequential and GA are valid and never
        /// below it.
        #[test]
        fn exact_equals_brute_force((r, robots, goal) in graph(), kappa in 0.0f64..=1.0) {
            let p = FormationProblem::new(Arc::new(r), robots, 0, goal, CostModel::Lanes { kappa }, 0.2).unwrap();
            let ctx = Ctx::default();
            let exact = solve(&Exact { candidate_limit: 100_000 }, &p, &ctx).unwrap();
            let (_, brute) = brute_force(&p, 100_000).unwrap();
            prop_assert!((exact.metrics.c_max - brute).abs() < 1e-9, "exact {} brute {brute}", exact.metrics.c_max);
            let seq = solve(&Sequential, &p, &ctx).unwrap();
            let ga = solve(&crate::ga::Ga { generations: 20, ..crate::ga::Ga::default() }, &p, &ctx).unwrap();
            prop_assert!(seq.metrics.c_max >= brute - 1e-9 && ga.metrics.c_max >= brute - 1e-9);
            prop_assert!(ga.metrics.c_max <= seq.metrics.c_max + 1e-9);
        }
    }
}
