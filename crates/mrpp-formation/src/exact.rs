//! The `exact` planner: the optimum `c_max`, proven by branch and bound for any R (the GA paper's
//! exhaustive baseline goes to R = 3; [`brute_force`] is that search, kept to check this one).
//!
//! **Candidates.** Every path of an optimal plan costs at least its length (costs never fall
//! below `c_e(1) = ℓ_e`), so the candidate paths are the simple paths shorter than the best known
//! `c_max` (Yen's algorithm, shortest first). The first bound is the better of the sequential plan
//! and a short GA run (30 generations, seed 0); a greedy placement with single-robot moves over
//! the 200 shortest candidates may lower it further (large R, where robots spread over many
//! corridors).
//!
//! **Search.** Robots are identical, so a plan is a multiset of candidates, searched depth first
//! with non-decreasing candidate index. Every bound rests on facts of the timing
//! ([`crate::problem`]): the placed robots' times `T(v)` are the longest paths of the union of
//! their paths (the validator's rule); a robot reaches each vertex no sooner than its previous
//! one plus `c_e(n_e)`, nor before the robots already there leave; and `c_e` never falls as the
//! count `n_e` grows, so adding robots never lowers anything. With the counts `n_e` and times of
//! the robots placed so far, a candidate is **feasible** for the next robot when
//! 1. it crosses no edge the other way from a placed robot (the opposite-directions rule),
//! 2. at every vertex of it, its earliest arrival (with `n_e + 1` on its edges, waiting for the
//!    placed robots there) plus the placed robots' longest path on to `Q_goal` is below the best
//!    `c_max`, and
//! 3. every placed robot's sum, and the placed robots' longest path through each shared edge,
//!    with one more robot on the edges it shares, stay below the best `c_max`.
//!
//! Counts only grow deeper in the tree, so a candidate infeasible at a node is infeasible below
//! it: each node passes its children the feasible list, filtered again. A node with robots left
//! to place and no feasible candidate is pruned, and so is one whose **completion bound**
//! reaches the best `c_max`:
//! - *forced edges*: edges that every feasible candidate uses carry all `m` remaining robots;
//!   with those counts, the placed robots' sums and the cheapest feasible candidate's sum;
//! - *the mean robot*: `c_max` is at least the mean of the robots' sums, `Σ_e n_e c_e(n_e) / R`;
//!   with `n c_e(n)` replaced by its lower convex hull, the cheapest way to add the remaining
//!   robots over the feasible candidates' edges is a convex-cost flow, solved exactly by
//!   successive shortest paths (var_density2, R = 8: 108.3 at the root for an optimum of 110.3).
//!
//! Before the search, and again after the first robot is placed, each feasible candidate is
//! tried alone: if the completion bound with one more robot on it reaches the best `c_max`, no
//! plan below it uses the candidate, and it leaves every branch at once. States (the signed counts per edge) already searched from the same or
//! an earlier candidate index are skipped (a 128-bit Zobrist hash per state, at most 2^24 of
//! them). A node is also pruned when the placed robots' timing reaches the best `c_max` or makes
//! them wait in a circle; a full plan is scored by the validator's timing
//! ([`FormationProblem::evaluate`]).
//!
//! **Capacity.** First of all, [`crate::capacity::within_capacity`] (a maximum flow) decides
//! whether any plan has a finite cost: when none does (the `hard` model with corridors too
//! narrow for the formation), `exact` gives up naming the corridors of a minimum cut; when one
//! does but neither the sequential plan nor the GA run found one, the flow's plan is the first
//! bound, so the search always starts from a finite bound.
//!
//! Counts of robots per edge are bit sets of placed robots, so `exact` takes at most 64 robots.
//! Measured with R = 4..8 on 10 random start/goal pairs of each bundled map
//! (`docs/reproduction/ga-formation.md`): every optimum proven, the slowest in about 6 s.

use mrpp_core::seeds::mix64;
use mrpp_core::{Ctx, Param, Planner, PlannerEntry, Unsolved};
use rustc_hash::FxHashMap;

use crate::paths::{Cut, all_simple_paths, paths_up_to};
use crate::planners::sequential_paths;
use crate::problem::{FormationPlan, FormationProblem};

/// Registry name of the exact planner.
pub const EXACT: &str = "exact";

/// Most states the search remembers (about 40 bytes each).
const MEMO_LIMIT: usize = 1 << 24;

/// Most robots `exact` takes (one bit per placed robot on each edge).
pub const MAX_ROBOTS: usize = 64;

/// The exact planner in the registry.
pub const ENTRY: PlannerEntry<FormationProblem> = PlannerEntry {
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

/// The exact planner.
#[derive(Debug, Clone, Copy)]
pub struct Exact {
    /// Most candidate paths considered; more within the first bound = [`Unsolved::GaveUp`].
    pub candidate_limit: usize,
}

impl Planner<FormationProblem> for Exact {
    fn name(&self) -> &str {
        EXACT
    }
    fn plan(&self, p: &FormationProblem, ctx: &Ctx) -> Result<FormationPlan, Unsolved> {
        if p.robots() > MAX_ROBOTS {
            return Err(Unsolved::GaveUp(format!(
                "exact takes at most {MAX_ROBOTS} robots, not {}",
                p.robots()
            )));
        }
        let fits =
            crate::capacity::within_capacity(p).map_err(|b| Unsolved::GaveUp(b.to_string()))?;
        let stage = |k: u64, note: String| {
            ctx.report(mrpp_core::Progress {
                stage: "exact stage",
                done: k,
                total: 3,
                note,
            });
        };
        stage(1, "first bound (sequential, a short GA)".into());
        let (seed, ub) = match first_bound(p, ctx)? {
            (_, ub) if !ub.is_finite() => {
                let c = p.evaluate(&fits).map_or(f64::INFINITY, |e| e.c_max);
                (fits, c)
            }
            found => found,
        };
        let bound = if ub.is_finite() { ub } else { f64::MAX };
        stage(2, format!("candidate paths within c_max {ub:.2}"));
        let (lim, dl) = (self.candidate_limit, &ctx.deadline);
        let cands = paths_up_to(p.roadmap(), p.start(), p.goal(), bound, lim, dl).map_err(
            |cut| match cut {
                Cut::Deadline => Unsolved::TimeLimit,
                Cut::Limit => Unsolved::GaveUp(format!(
                    "more than {lim} candidate paths within the bound {ub}"
                )),
            },
        )?;
        // A tighter first bound when robots can spread (only lowers it; the search proves it).
        let (seed, ub) = match greedy_incumbent(p, &cands[..cands.len().min(200)]) {
            Some((plan, c)) if c < ub => (plan, c),
            _ => (seed, ub),
        };
        stage(
            3,
            format!("branch and bound over {} candidate paths", cands.len()),
        );
        let mut search = Search::new(p, ctx, &cands, ub);
        let all: Vec<usize> = (0..search.cands.len()).collect();
        let root = search.feasible(&all);
        let root = search.usable(&root)?;
        search.dfs(&root)?;
        let paths = match search.best_plan {
            Some(ids) => ids.iter().map(|&i| cands[i].0.clone()).collect(),
            None if ub.is_finite() => seed,
            // Not reached: the flow's plan is valid with a finite cost.
            None => return Err(crate::planners::no_finite_plan(p, EXACT, &seed)),
        };
        Ok(FormationPlan { paths })
    }
}

/// The better of the sequential plan and a short GA run (both valid), with its `c_max`.
fn first_bound(p: &FormationProblem, ctx: &Ctx) -> Result<(Vec<Vec<u32>>, f64), Unsolved> {
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
    Ok(match ga.run(p, &Ctx::new(0, ctx.deadline)) {
        Some(run) if run.c_max < seq_cost => (run.plan.paths, run.c_max),
        _ => (seq, seq_cost),
    })
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

/// A candidate path: its vertices, its edges `(edge id, forward)` and its length.
struct Cand {
    path: Vec<u32>,
    edges: Vec<(u32, bool)>,
    length: f64,
}

/// The branch-and-bound state: the placed robots and the counts they put on the edges.
struct Search<'a> {
    p: &'a FormationProblem,
    ctx: &'a Ctx,
    cands: Vec<Cand>,
    robots: usize,
    best: f64,
    best_plan: Option<Vec<usize>>,
    steps: u64,
    throttle: mrpp_core::Throttle,
    /// Candidate index of each placed robot.
    chosen: Vec<usize>,
    /// Per edge: the placed robots on it (bit i = robot i).
    on: Vec<u64>,
    /// Per edge: whether its robots cross it from `u` to `v` (meaningful when `on` is not 0).
    forward: Vec<bool>,
    /// Per edge: how many feasible candidates use it (scratch of [`Search::completion_bound`]).
    uses: Vec<usize>,
    /// Explored states: a 128-bit Zobrist hash of the per-edge signed robot counts → the least
    /// candidate index its completions were searched from.
    seen: FxHashMap<u128, usize>,
    /// The current state's hash (see [`Search::zobrist`]) and its random numbers.
    hash: u128,
    keys: Vec<u128>,
    /// Per vertex: when the placed robots leave it (`T(v)`, the longest path from `Q_ini` over
    /// their edges), and the longest path from it to `Q_goal`; −∞ off their paths.
    t_from: Vec<f64>,
    t_to: Vec<f64>,
    /// Per edge: the lower convex hull of `n ↦ n c_e(n)` at `n = 0..=R` ([`Search::flow_bound`]).
    hull: Vec<Vec<f64>>,
    /// Per edge: `c_e(n_e)` and `c_e(n_e + 1)` for the placed robots' counts `n_e`.
    cost_now: Vec<f64>,
    cost_next: Vec<f64>,
    /// Scratch of [`Search::dag_times`]: in-degrees and a topological order.
    indeg: Vec<usize>,
    order: Vec<u32>,
}

impl<'a> Search<'a> {
    fn new(p: &'a FormationProblem, ctx: &'a Ctx, cands: &[(Vec<u32>, f64)], best: f64) -> Self {
        let r = p.roadmap();
        let cands: Vec<Cand> = cands
            .iter()
            .map(|(path, length)| Cand {
                edges: path
                    .windows(2)
                    .map(|w| {
                        let e = r.edge_between(w[0], w[1]).expect("a roadmap path");
                        (e, r.edges[e as usize].u == w[0])
                    })
                    .collect(),
                path: path.clone(),
                length: *length,
            })
            .collect();
        let ne = r.edges.len();
        Search {
            p,
            ctx,
            cands,
            robots: p.robots(),
            best,
            best_plan: None,
            steps: 0,
            throttle: mrpp_core::Throttle::new(),
            chosen: Vec::with_capacity(p.robots()),
            on: vec![0; ne],
            forward: vec![true; ne],
            uses: vec![0; ne],
            seen: FxHashMap::default(),
            hash: 0,
            keys: (0..(ne * 2 * p.robots()) as u64)
                .map(|k| u128::from(mix64(k)) << 64 | u128::from(mix64(!k)))
                .collect(),
            t_from: vec![f64::NEG_INFINITY; r.num_vertices()],
            t_to: vec![f64::NEG_INFINITY; r.num_vertices()],
            hull: (0..ne as u32)
                .map(|e| convex_hull_of_totals(p, e))
                .collect(),
            cost_now: vec![0.0; ne],
            cost_next: (0..ne as u32).map(|e| p.edge_cost(e, 1)).collect(),
            indeg: vec![0; r.num_vertices()],
            order: Vec::with_capacity(r.num_vertices()),
        }
    }

    /// Pruning margin: bounds must stay below `best − eps`.
    fn limit(&self) -> f64 {
        if self.best.is_finite() {
            self.best - 1e-9 * self.best.abs().max(1.0)
        } else {
            f64::INFINITY
        }
    }

    fn count(&self, e: u32) -> usize {
        self.on[e as usize].count_ones() as usize
    }

    /// Robot `q`'s sum of `c_e` along its path with `extra(e)` more robots on edge `e`.
    fn placed_sum(&self, q: usize, extra: &dyn Fn(u32) -> usize) -> f64 {
        self.cands[self.chosen[q]]
            .edges
            .iter()
            .map(|&(e, _)| self.p.edge_cost(e, self.count(e) + extra(e)))
            .sum()
    }

    /// The candidates of `from` (ascending) that are feasible for the next robot.
    fn feasible(&self, from: &[usize]) -> Vec<usize> {
        let limit = self.limit();
        let slack: Vec<f64> = (0..self.chosen.len())
            .map(|q| limit - self.placed_sum(q, &|_| 0))
            .collect();
        let mut inc = vec![0.0; self.chosen.len()];
        let mut out = Vec::new();
        for &j in from {
            if self.cands[j].length >= limit {
                break;
            }
            if self.test(j, limit, &slack, &mut inc) {
                out.push(j);
            }
        }
        out
    }

    /// The candidates of `list` (a node's feasible list) that some completion below the bound
    /// can use: with one more robot on the candidate, the completion bound of the others over
    /// `list` stays below it. Run at the root and after the first robot, this removes a
    /// candidate from every branch below at once (var_density2, R = 8: 1242 feasible
    /// candidates at the root, 101 usable).
    fn usable(&mut self, list: &[usize]) -> Result<Vec<usize>, Unsolved> {
        let mut out = Vec::new();
        for &j in list {
            if self.ctx.deadline.expired() {
                return Err(Unsolved::TimeLimit);
            }
            self.place(j);
            let limit = self.limit();
            let ok = self.dag_times() < limit && self.completion_bound(list, limit) < limit;
            self.unplace();
            if ok {
                out.push(j);
            }
        }
        self.dag_times();
        Ok(out)
    }

    /// Whether candidate `j` is feasible for the next robot (the module doc's three rules):
    /// `slack[q]` is how far placed robot `q`'s sum is below `limit`; `inc` is scratch.
    fn test(&self, j: usize, limit: f64, slack: &[f64], inc: &mut [f64]) -> bool {
        let c = &self.cands[j];
        inc.iter_mut().for_each(|x| *x = 0.0);
        // `own`: the earliest this robot can reach each vertex of its path (it waits for the
        // placed robots where it meets them); from there the placed robots' longest path to
        // Q_goal still has to be run.
        let mut own: f64 = 0.0;
        for (&(e, fwd), &v) in c.edges.iter().zip(&c.path[1..]) {
            let (e, v) = (e as usize, v as usize);
            let bits = self.on[e];
            let cost = self.cost_next[e];
            own = (own + cost).max(self.t_from[v]);
            if (bits != 0 && self.forward[e] != fwd) || own + self.t_to[v] >= limit {
                return false;
            }
            let delta = cost - self.cost_now[e];
            if bits != 0 && delta > 0.0 {
                // The placed robots' longest path through this edge, now one robot slower.
                if self.t_from[self.tail(e) as usize] + cost + self.t_to[v] >= limit {
                    return false;
                }
                let mut b = bits;
                while b != 0 {
                    inc[b.trailing_zeros() as usize] += delta;
                    b &= b - 1;
                }
            }
        }
        own < limit && inc.iter().zip(slack).all(|(x, s)| x < s)
    }

    /// A lower bound on every completion when the next robots come from `feasible` (not
    /// empty): the better of [`Search::forced_bound`] and [`Search::flow_bound`] (the latter
    /// only when the former is below `limit`).
    fn completion_bound(&mut self, feasible: &[usize], limit: f64) -> f64 {
        for &j in feasible {
            for &(e, _) in &self.cands[j].edges {
                self.uses[e as usize] += 1;
            }
        }
        let mut bound = self.forced_bound(feasible);
        if bound < limit {
            // Directions the feasible candidates cross each edge in (1: u→v, 2: v→u).
            let mut allowed = vec![0u8; self.uses.len()];
            for &j in feasible {
                for &(e, fwd) in &self.cands[j].edges {
                    allowed[e as usize] |= if fwd { 1 } else { 2 };
                }
            }
            bound = bound.max(self.flow_bound(&allowed));
        }
        for &j in feasible {
            for &(e, _) in &self.cands[j].edges {
                self.uses[e as usize] = 0;
            }
        }
        bound
    }

    /// Edges every feasible candidate uses carry all `m` remaining robots: the placed robots'
    /// sums and the cheapest feasible candidate's sum with those counts (`uses` filled).
    fn forced_bound(&self, feasible: &[usize]) -> f64 {
        let m = self.robots - self.chosen.len();
        let all = feasible.len();
        let uses = &self.uses;
        let forced = |e: u32| if uses[e as usize] == all { m } else { 0 };
        let placed = (0..self.chosen.len())
            .map(|q| self.placed_sum(q, &forced))
            .fold(0.0, f64::max);
        let next = feasible
            .iter()
            .map(|&j| {
                self.cands[j]
                    .edges
                    .iter()
                    .map(|&(e, _)| self.p.edge_cost(e, self.count(e) + forced(e).max(1)))
                    .sum::<f64>()
            })
            .fold(f64::INFINITY, f64::min);
        placed.max(next)
    }

    /// A lower bound from the average robot: `c_max` is at least the mean of the robots'
    /// sums, which is `Σ_e n_e c_e(n_e) / R`. With `G_e` the lower convex hull of
    /// `n ↦ n c_e(n)`, the cheapest way to add the remaining robots to the placed counts is a
    /// convex-cost flow, found exactly by successive shortest paths (Bellman–Ford on the
    /// residual roadmap; an edge the placed robots cross one way takes no flow the other way).
    fn flow_bound(&self, allowed: &[u8]) -> f64 {
        let r = self.p.roadmap();
        let ne = r.edges.len();
        let n: Vec<usize> = (0..ne as u32).map(|e| self.count(e)).collect();
        // Signed extra flow per edge (+ from u to v).
        let mut x = vec![0i64; ne];
        let mut total: f64 = (0..ne).map(|e| self.hull[e][n[e]]).sum();
        let nv = r.num_vertices();
        let (s, g) = (self.p.start() as usize, self.p.goal() as usize);
        let mut dist = vec![f64::INFINITY; nv];
        let mut via: Vec<(u32, bool)> = vec![(u32::MAX, true); nv];
        let mut queue = std::collections::VecDeque::with_capacity(nv);
        let mut queued = vec![false; nv];
        for _ in self.chosen.len()..self.robots {
            // Shortest augmenting path by a queue-based Bellman–Ford (costs may be negative on
            // residual arcs; convex costs leave no negative cycle).
            dist.iter_mut().for_each(|d| *d = f64::INFINITY);
            dist[s] = 0.0;
            queue.push_back(s as u32);
            queued[s] = true;
            while let Some(a) = queue.pop_front() {
                queued[a as usize] = false;
                let da = dist[a as usize];
                for &(b, e) in r.neighbors(a) {
                    let (e, edge) = (e as usize, &r.edges[e as usize]);
                    let sign = if edge.u == a { 1 } else { -1 };
                    let load = n[e] + x[e].unsigned_abs() as usize;
                    // Direction the edge's robots take (+1 u→v, −1 v→u, 0 none yet).
                    let dir = if n[e] > 0 {
                        if self.forward[e] { 1 } else { -1 }
                    } else {
                        x[e].signum()
                    };
                    let cost = if dir == 0 || dir == sign {
                        if load >= self.robots || allowed[e] & if sign == 1 { 1 } else { 2 } == 0 {
                            continue;
                        }
                        self.hull[e][load + 1] - self.hull[e][load]
                    } else if x[e] != 0 {
                        self.hull[e][load - 1] - self.hull[e][load]
                    } else {
                        continue;
                    };
                    if da + cost < dist[b as usize] - 1e-12 {
                        dist[b as usize] = da + cost;
                        via[b as usize] = (e as u32, sign == 1);
                        if !queued[b as usize] {
                            queued[b as usize] = true;
                            queue.push_back(b);
                        }
                    }
                }
            }
            if !dist[g].is_finite() {
                return f64::INFINITY;
            }
            total += dist[g];
            let mut v = g;
            while v != s {
                let (e, fwd) = via[v];
                let edge = &r.edges[e as usize];
                x[e as usize] += if fwd { 1 } else { -1 };
                v = if fwd { edge.u } else { edge.v } as usize;
            }
        }
        total / self.robots as f64
    }

    fn place(&mut self, j: usize) {
        let q = self.chosen.len();
        self.chosen.push(j);
        for i in 0..self.cands[j].edges.len() {
            let (e, fwd) = self.cands[j].edges[i];
            self.hash ^= self.zobrist(e);
            self.on[e as usize] |= 1 << q;
            self.forward[e as usize] = fwd;
            self.hash ^= self.zobrist(e);
            self.recost(e);
        }
    }

    /// Refreshes `cost_now` and `cost_next` of edge `e` after its count changed.
    fn recost(&mut self, e: u32) {
        let n = self.count(e);
        self.cost_now[e as usize] = self.p.edge_cost(e, n);
        self.cost_next[e as usize] = self.p.edge_cost(e, n + 1);
    }

    fn unplace(&mut self) {
        let q = self.chosen.len() - 1;
        let j = self.chosen.pop().expect("a placed robot");
        for i in 0..self.cands[j].edges.len() {
            let e = self.cands[j].edges[i].0;
            self.hash ^= self.zobrist(e);
            self.on[e as usize] &= !(1 << q);
            self.hash ^= self.zobrist(e);
            self.recost(e);
        }
    }

    /// The placed robots' exact `c_max` (waits included, by the validator's timing), infinite
    /// when they break a rule.
    fn timing(&self) -> f64 {
        let paths: Vec<Vec<u32>> = self
            .chosen
            .iter()
            .map(|&j| self.cands[j].path.clone())
            .collect();
        self.p.evaluate(&paths).map_or(f64::INFINITY, |e| e.c_max)
    }

    /// The vertex robots leave placed edge `e` from (meaningful when `on[e]` is not 0).
    fn tail(&self, e: usize) -> u32 {
        let edge = &self.p.roadmap().edges[e];
        if self.forward[e] { edge.u } else { edge.v }
    }

    /// Fills `t_from` and `t_to` for the placed robots (the same timing as the validator's:
    /// the longest paths of the union of their paths); `T(Q_goal)`, or infinite when they would
    /// wait for each other in a circle.
    fn dag_times(&mut self) -> f64 {
        let r = self.p.roadmap();
        self.indeg.iter_mut().for_each(|d| *d = 0);
        let mut placed = 0;
        for e in 0..self.on.len() {
            if self.on[e] != 0 {
                let edge = &r.edges[e];
                let head = if self.forward[e] { edge.v } else { edge.u };
                self.indeg[head as usize] += 1;
                placed += 1;
            }
        }
        self.t_from.iter_mut().for_each(|t| *t = f64::NEG_INFINITY);
        self.t_to.iter_mut().for_each(|t| *t = f64::NEG_INFINITY);
        let start = self.p.start();
        self.t_from[start as usize] = 0.0;
        self.order.clear();
        self.order.push(start);
        let mut k = 0;
        while k < self.order.len() {
            let a = self.order[k];
            k += 1;
            for &(b, e) in r.neighbors(a) {
                if self.on[e as usize] == 0 || self.tail(e as usize) != a {
                    continue;
                }
                placed -= 1;
                let t = self.t_from[a as usize] + self.cost_now[e as usize];
                self.t_from[b as usize] = self.t_from[b as usize].max(t);
                self.indeg[b as usize] -= 1;
                if self.indeg[b as usize] == 0 {
                    self.order.push(b);
                }
            }
        }
        if placed > 0 {
            return f64::INFINITY;
        }
        for k in (0..self.order.len()).rev() {
            let a = self.order[k];
            let mut t: f64 = if a == self.p.goal() {
                0.0
            } else {
                f64::NEG_INFINITY
            };
            for &(b, e) in r.neighbors(a) {
                if self.on[e as usize] != 0 && self.tail(e as usize) == a {
                    t = t.max(self.cost_now[e as usize] + self.t_to[b as usize]);
                }
            }
            self.t_to[a as usize] = t;
        }
        self.t_from[self.p.goal() as usize]
    }

    /// Edge `e`'s share of the state's hash: a fixed random number per (edge, signed count).
    fn zobrist(&self, e: u32) -> u128 {
        let n = self.count(e);
        if n == 0 {
            return 0;
        }
        let signed = if self.forward[e as usize] {
            n - 1
        } else {
            self.robots + n - 1
        };
        self.keys[e as usize * 2 * self.robots + signed]
    }

    /// Places the next robot on each candidate of `feasible` in turn (non-decreasing index).
    fn dfs(&mut self, feasible: &[usize]) -> Result<(), Unsolved> {
        for (k, &j) in feasible.iter().enumerate() {
            if self.cands[j].length >= self.limit() {
                break;
            }
            self.steps += 1;
            if self.steps.is_multiple_of(256) {
                if self.ctx.deadline.expired() {
                    return Err(Unsolved::TimeLimit);
                }
                let (steps, best) = (self.steps, self.best);
                self.throttle.report(self.ctx, || mrpp_core::Progress {
                    stage: "branch and bound",
                    done: steps,
                    total: 0,
                    note: format!("best c_max {best:.2}"),
                });
            }
            self.place(j);
            if self.chosen.len() < self.robots {
                // The completions depend only on the counts: skip a state already searched
                // from this candidate index or an earlier one.
                match self.seen.get(&self.hash) {
                    Some(&from) if from <= j => {
                        self.unplace();
                        continue;
                    }
                    _ if self.seen.len() < MEMO_LIMIT => {
                        self.seen.insert(self.hash, j);
                    }
                    _ => {}
                }
            }
            let c = if self.chosen.len() == self.robots {
                self.timing()
            } else {
                self.dag_times()
            };
            if c < self.limit() {
                if self.chosen.len() == self.robots {
                    self.best = c;
                    self.best_plan = Some(self.chosen.clone());
                } else {
                    let next = self.feasible(&feasible[k..]);
                    let limit = self.limit();
                    if !next.is_empty() && self.completion_bound(&next, limit) < limit {
                        // After the first robot, the candidates are tried alone again.
                        let next = if self.chosen.len() == 1 {
                            self.usable(&next)?
                        } else {
                            next
                        };
                        self.dfs(&next)?;
                    }
                }
            }
            self.unplace();
        }
        Ok(())
    }
}

/// The lower convex hull of `n ↦ n c_e(n)` for `n = 0..=R`, evaluated at each `n`.
fn convex_hull_of_totals(p: &FormationProblem, e: u32) -> Vec<f64> {
    // Counts with an infinite cost (the hard model above capacity) stay infinite.
    let all: Vec<f64> = (0..=p.robots())
        .map(|n| n as f64 * p.edge_cost(e, n))
        .collect();
    let finite = all.iter().take_while(|c| c.is_finite()).count();
    let pts = &all[..finite];
    let mut hull: Vec<usize> = Vec::new();
    for i in 0..pts.len() {
        while hull.len() >= 2 {
            let (a, b) = (hull[hull.len() - 2], hull[hull.len() - 1]);
            // b lies on or above the segment a–i: drop it.
            let (da, db) = ((b - a) as f64, (i - a) as f64);
            if (pts[b] - pts[a]) * db >= (pts[i] - pts[a]) * da {
                hull.pop();
            } else {
                break;
            }
        }
        hull.push(i);
    }
    let mut out = vec![f64::INFINITY; all.len()];
    out[0] = 0.0;
    for w in hull.windows(2) {
        let (a, b) = (w[0], w[1]);
        for (k, o) in out.iter_mut().enumerate().take(b + 1).skip(a) {
            *o = pts[a] + (pts[b] - pts[a]) * (k - a) as f64 / (b - a) as f64;
        }
    }
    out
}

/// The paper's exhaustive search: every multiset of `robots` simple paths (at most `limit` paths);
/// the optimal plan and its `c_max` (an empty plan and an infinite `c_max` when no multiset is a
/// valid plan, e.g. every one over a corridor's capacity), or `None` when there are more paths.
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
    Some(best.unwrap_or((Vec::new(), f64::INFINITY)))
}
