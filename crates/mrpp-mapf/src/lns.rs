//! Large-neighbourhood search that lowers a valid plan's sum of costs (J. Li, Z. Chen, D. Harabor,
//! P. J. Stuckey, S. Koenig, "Anytime multi-agent path finding via large neighborhood search",
//! IJCAI 2021): each step takes up to `k` agents' paths out, re-plans those agents one at a time
//! in a random order with safe-interval path planning ([`sipp`]) against everyone else's paths,
//! and keeps the new paths when their summed cost is not larger (else restores the old ones).
//! LaCAM*'s anytime phase runs it between its own search rounds (the role of the refiners of
//! lacam3, Okumura, AAMAS 2024).
//!
//! **What it lowers** ([`Lns::new`]'s `loss`): the sum of costs, or the sum of loss (lacam3's
//! objective: each agent's steps except those it stays on its goal, so an agent that waits on its
//! goal and steps aside later is not charged for the waits). With sum of loss a step keeps the
//! new paths when their summed loss is lower, or equal with a sum of costs not larger; the
//! searches still find earliest-arrival paths, whose loss is at least their goal distance (the
//! same lower bound prunes both).
//!
//! Neighbourhoods alternate between *random* (uniform agents) and *agent-based* (the most delayed
//! agent, cost minus distance, among a random sample, with the agents whose paths visit the cells
//! of its shortest route), as MAPF-LNS does. The plan stays valid after every step: the
//! re-planned paths obey the reservation table that holds every other path, with the rules of
//! the validator (stay at the goal, following allowed).

use rand::SeedableRng;
use rand::seq::{IndexedRandom, SliceRandom};
use rand_chacha::ChaCha8Rng;
use rustc_hash::FxHashSet;

use mrpp_core::mapf::search::distance::GoalDistances;
use mrpp_core::mapf::search::sipp::sipp;
use mrpp_core::mapf::search::spacetime::{Query, Reservations, Search};
use mrpp_core::{Deadline, Graph, VertexId};

/// Steps a re-planned path may end after the current makespan (a second bound, besides the
/// group's budget).
const SLACK: u32 = 8;

/// A plan being improved.
pub(crate) struct Lns<'a> {
    graph: &'a Graph,
    goals: &'a [VertexId],
    dist: &'a GoalDistances<'a>,
    paths: Vec<Vec<VertexId>>,
    res: Reservations,
    rng: ChaCha8Rng,
    steps: u64,
    improved: u64,
    /// Neighbourhood size.
    k: usize,
    /// Lower the sum of loss (module doc) instead of the sum of costs.
    loss: bool,
    /// Copies of `res` for the other workers of [`Lns::steps`] (`threads - 1` of them), kept
    /// equal to it between rounds.
    replicas: Vec<Reservations>,
}

/// What a worker of a step needs to read: the graph, the goals and their distance tables, the
/// current plan, and whether the sum of loss is lowered.
struct View<'v> {
    graph: &'v Graph,
    goals: &'v [VertexId],
    dist: &'v GoalDistances<'v>,
    paths: &'v [Vec<VertexId>],
    loss: bool,
}

pub(crate) use mrpp_core::mapf::plan::path_loss;

/// A path's cost: the step of its last arrival at `goal` (its length - 1 once trailing waits on
/// the goal are cut).
fn trimmed(mut p: Vec<VertexId>) -> Vec<VertexId> {
    while p.len() > 1 && p[p.len() - 1] == p[p.len() - 2] {
        p.pop();
    }
    p
}

impl<'a> Lns<'a> {
    /// Starts from the valid plan `paths` (one path per agent, from its start to its goal).
    pub(crate) fn new(
        graph: &'a Graph,
        goals: &'a [VertexId],
        dist: &'a GoalDistances<'a>,
        paths: Vec<Vec<VertexId>>,
        seed: u64,
        loss: bool,
    ) -> Self {
        let paths: Vec<Vec<VertexId>> = paths.into_iter().map(trimmed).collect();
        let mut res = Reservations::new(graph.num_vertices());
        for p in &paths {
            res.reserve_path(p, 0, true);
        }
        Lns {
            graph,
            goals,
            dist,
            k: paths.len().min(8),
            paths,
            res,
            rng: ChaCha8Rng::seed_from_u64(seed),
            steps: 0,
            improved: 0,
            loss,
            replicas: Vec::new(),
        }
    }

    /// Re-plans `threads` neighbourhoods at once in [`Lns::steps`] (default 1).
    pub(crate) fn with_threads(mut self, threads: usize) -> Self {
        self.replicas = (1..threads.max(1)).map(|_| self.res.clone()).collect();
        self
    }

    /// The current plan's cost on what it lowers: (sum of loss, sum of costs) with `loss`, else
    /// (sum of costs, 0); lower is better.
    pub(crate) fn key(&self) -> (u64, u64) {
        self.key_of(&self.paths, 0..self.paths.len())
    }

    /// [`Self::key`] of another plan of the same agents (e.g. the search's; trailing waits on
    /// the goals are not counted).
    pub(crate) fn key_of_plan(&self, paths: &[Vec<VertexId>]) -> (u64, u64) {
        let trimmed: Vec<Vec<VertexId>> = paths.iter().cloned().map(trimmed).collect();
        self.key_of(&trimmed, 0..trimmed.len())
    }

    /// [`Self::key`] of `paths`, the paths of `agents` in order.
    fn key_of(
        &self,
        paths: &[Vec<VertexId>],
        agents: impl IntoIterator<Item = usize>,
    ) -> (u64, u64) {
        key_of(self.goals, self.loss, paths, agents)
    }

    /// Whether it lowers the sum of loss (else the sum of costs).
    pub(crate) fn lowers_loss(&self) -> bool {
        self.loss
    }

    /// Steps taken and steps that lowered the plan's cost.
    pub(crate) fn counts(&self) -> (u64, u64) {
        (self.steps, self.improved)
    }

    /// The current plan.
    pub(crate) fn paths(&self) -> &[Vec<VertexId>] {
        &self.paths
    }

    /// Replaces the plan by `paths` (e.g. a better one found elsewhere).
    pub(crate) fn reset(&mut self, paths: Vec<Vec<VertexId>>) {
        for p in &self.paths {
            self.res.release_path(p, 0, true);
        }
        self.paths = paths.into_iter().map(trimmed).collect();
        for p in &self.paths {
            self.res.reserve_path(p, 0, true);
        }
        for r in &mut self.replicas {
            r.clone_from(&self.res);
        }
    }

    /// The agents of the next neighbourhood.
    fn neighbourhood(&mut self) -> Vec<usize> {
        let n = self.paths.len();
        let mut chosen: Vec<usize> = Vec::new();
        if self.steps.is_multiple_of(2) {
            // Agent-based: the most delayed agent of a sample, and the agents on its route.
            let sample: Vec<usize> = (0..n)
                .collect::<Vec<_>>()
                .sample(&mut self.rng, n.min(32))
                .copied()
                .collect();
            let delay = |i: usize| {
                let p = &self.paths[i];
                let cost = if self.loss {
                    path_loss(p, self.goals[i])
                } else {
                    p.len() as u64 - 1
                };
                cost.saturating_sub(u64::from(self.dist.get(i, p[0])))
            };
            if let Some(&a) = sample
                .iter()
                .max_by_key(|&&i| (delay(i), std::cmp::Reverse(i)))
                && delay(a) > 0
            {
                chosen.push(a);
                // A shortest route of `a`, down its distance table.
                let mut route: FxHashSet<VertexId> = FxHashSet::default();
                let mut v = self.paths[a][0];
                route.insert(v);
                while self.dist.get(a, v) > 0 {
                    let d = self.dist.get(a, v);
                    v = *self
                        .graph
                        .neighbors(v)
                        .iter()
                        .find(|&&w| self.dist.get(a, w) + 1 == d)
                        .expect("a BFS table always has a predecessor");
                    route.insert(v);
                }
                let mut others: Vec<usize> = (0..n)
                    .filter(|&j| j != a && self.paths[j].iter().any(|v| route.contains(v)))
                    .collect();
                others.shuffle(&mut self.rng);
                chosen.extend(others.into_iter().take(self.k - 1));
            }
        }
        if chosen.len() < 2 {
            chosen = (0..n)
                .collect::<Vec<_>>()
                .sample(&mut self.rng, self.k)
                .copied()
                .collect();
        }
        chosen
    }

    /// One destroy-and-repair step; true when the plan's cost ([`Self::key`]) dropped.
    pub(crate) fn step(&mut self, deadline: Deadline) -> bool {
        self.steps += 1;
        let mut group = self.neighbourhood();
        group.shuffle(&mut self.rng);
        let view = View {
            graph: self.graph,
            goals: self.goals,
            dist: self.dist,
            paths: &self.paths,
            loss: self.loss,
        };
        let Some((new, improved)) = view.repair(&mut self.res, &group, deadline) else {
            return false;
        };
        self.improved += u64::from(improved);
        for (&i, p) in group.iter().zip(new) {
            self.res.release_path(&self.paths[i], 0, true);
            self.paths[i] = p;
        }
        for &i in &group {
            self.res.reserve_path(&self.paths[i], 0, true);
        }
        improved
    }

    /// `rounds` rounds of steps; the number that lowered the plan's cost. With one thread
    /// ([`Lns::with_threads`]) each round is one [`Lns::step`]. With `t` threads a round draws
    /// `t` neighbourhoods (in order, from the one seeded generator), repairs them at once on `t`
    /// threads (this one and `t - 1` scoped ones), each
    /// against its own copy of the reservation table and the plan as it was at the round's
    /// start, and then keeps the repairs in draw order: one whose agents another kept repair of
    /// the round already moved is dropped, and one whose new paths now collide with those is
    /// dropped too. So for a seed and a thread count the result depends on the rounds run, not
    /// on how the threads are scheduled.
    pub(crate) fn steps(&mut self, rounds: usize, deadline: Deadline) -> u64 {
        let threads = self.replicas.len() + 1;
        let mut lowered = 0;
        for _ in 0..rounds {
            if threads == 1 {
                lowered += u64::from(self.step(deadline));
                continue;
            }
            let groups: Vec<Vec<usize>> = (0..threads)
                .map(|_| {
                    self.steps += 1;
                    let mut g = self.neighbourhood();
                    g.shuffle(&mut self.rng);
                    g
                })
                .collect();
            let view = View {
                graph: self.graph,
                goals: self.goals,
                dist: self.dist,
                paths: &self.paths,
                loss: self.loss,
            };
            let mut tables: Vec<&mut Reservations> = std::iter::once(&mut self.res)
                .chain(self.replicas.iter_mut())
                .collect();
            // Plain scoped threads, not a rayon pool: a rayon worker that waits for another
            // pool runs its own pool's queued jobs meanwhile, which in `mrpp bench` are other
            // runs, started inside this one.
            let view = &view;
            let repairs: Vec<Option<(Vec<Vec<VertexId>>, bool)>> = std::thread::scope(|sc| {
                let mut work = tables.iter_mut().zip(&groups);
                let (own_res, own_group) = work.next().expect("at least one worker");
                let others: Vec<_> = work
                    .map(|(res, group)| sc.spawn(move || view.repair(res, group, deadline)))
                    .collect();
                let own = view.repair(own_res, own_group, deadline);
                std::iter::once(own)
                    .chain(
                        others
                            .into_iter()
                            .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e))),
                    )
                    .collect()
            });
            // Keep them in draw order.
            let mut moved: FxHashSet<usize> = FxHashSet::default();
            let mut kept: Vec<(usize, Vec<VertexId>, Vec<VertexId>)> = Vec::new();
            for (group, repair) in groups.iter().zip(repairs) {
                let Some((new, improved)) = repair else {
                    continue;
                };
                if group.iter().any(|i| moved.contains(i)) {
                    continue;
                }
                for &i in group {
                    self.res.release_path(&self.paths[i], 0, true);
                }
                if !kept.is_empty() && !fits(&mut self.res, &new) {
                    for &i in group {
                        self.res.reserve_path(&self.paths[i], 0, true);
                    }
                    continue;
                }
                for (&i, p) in group.iter().zip(new) {
                    self.res.reserve_path(&p, 0, true);
                    let old = std::mem::replace(&mut self.paths[i], p);
                    kept.push((i, old, self.paths[i].clone()));
                    moved.insert(i);
                }
                self.improved += u64::from(improved);
                lowered += u64::from(improved);
            }
            // The other tables take the same changes.
            for r in &mut self.replicas {
                for (_, old, _) in &kept {
                    r.release_path(old, 0, true);
                }
                for (_, _, new) in &kept {
                    r.reserve_path(new, 0, true);
                }
            }
        }
        lowered
    }
}

/// Whether `paths` (each from time 0, parked at its end) obey `res` and each other, by the rules
/// [`sipp`] plans with; reserves them when they do, leaves `res` as it was when not.
fn fits(res: &mut Reservations, paths: &[Vec<VertexId>]) -> bool {
    for (n, p) in paths.iter().enumerate() {
        let ok = (1..p.len()).all(|t| res.move_free(p[t - 1], p[t], t as u32))
            && res.free_from(p[p.len() - 1], p.len() as u32 - 1)
            && res.vertex_free(p[p.len() - 1], p.len() as u32 - 1);
        if !ok {
            for q in &paths[..n] {
                res.release_path(q, 0, true);
            }
            return false;
        }
        res.reserve_path(p, 0, true);
    }
    for q in paths {
        res.release_path(q, 0, true);
    }
    true
}

/// The (objective, sum of costs) key of `paths`, the paths of `agents` in order ([`Lns::key`]).
fn key_of(
    goals: &[VertexId],
    loss: bool,
    paths: &[Vec<VertexId>],
    agents: impl IntoIterator<Item = usize>,
) -> (u64, u64) {
    let soc: u64 = paths.iter().map(|p| p.len() as u64 - 1).sum();
    if loss {
        let sol = paths
            .iter()
            .zip(agents)
            .map(|(p, i)| path_loss(p, goals[i]))
            .sum();
        (sol, soc)
    } else {
        (soc, 0)
    }
}

impl View<'_> {
    /// Re-plans the agents of `group`, in its order, against `res` without their paths: their
    /// new paths and whether they lower the key, when they are found and do not raise it, else
    /// `None`. `res` is left as it was.
    fn repair(
        &self,
        res: &mut Reservations,
        group: &[usize],
        deadline: Deadline,
    ) -> Option<(Vec<Vec<VertexId>>, bool)> {
        let old: Vec<&Vec<VertexId>> = group.iter().map(|&i| &self.paths[i]).collect();
        for p in &old {
            res.release_path(p, 0, true);
        }
        // The group's new paths may not cost more than its old ones, nor end more than SLACK
        // steps after the makespan: each search is bounded by what is left of that budget after
        // the paths already found and the distances of the agents still to go, so a hopeless
        // search fails fast instead of exploring every (cell, time) up to a far horizon.
        let old_key = key_of(
            self.goals,
            self.loss,
            &old.iter().map(|p| p.to_vec()).collect::<Vec<_>>(),
            group.iter().copied(),
        );
        // Each new path's loss is at most its cost, and its cost at most the group's old
        // objective value left after the others' lower bounds.
        let old_cost = old_key.0;
        let lower: Vec<u64> = group
            .iter()
            .map(|&i| u64::from(self.dist.get(i, self.paths[i][0])))
            .collect();
        let mut spent = 0u64;
        let makespan = self.paths.iter().map(Vec::len).max().unwrap_or(1) as u32;
        let mut new: Vec<Vec<VertexId>> = Vec::with_capacity(group.len());
        for (k, &i) in group.iter().enumerate() {
            let rest: u64 = lower[k + 1..].iter().sum();
            let Some(budget) = old_cost.checked_sub(spent + rest) else {
                break;
            };
            let dist = self.dist;
            let h = move |v: VertexId| dist.get(i, v);
            let q = Query {
                graph: self.graph,
                start: self.paths[i][0],
                goal: self.goals[i],
                start_time: 0,
                h: &h,
                max_time: u32::try_from(budget)
                    .unwrap_or(u32::MAX)
                    .min(makespan + SLACK),
                window: None,
                deadline,
            };
            match sipp(&q, res) {
                Search::Found(p) => {
                    let p = trimmed(p);
                    spent += p.len() as u64 - 1;
                    res.reserve_path(&p, 0, true);
                    new.push(p);
                }
                _ => break,
            }
        }
        for p in &new {
            res.release_path(p, 0, true);
        }
        for p in &old {
            res.reserve_path(p, 0, true);
        }
        let new_key = key_of(self.goals, self.loss, &new, group.iter().copied());
        (new.len() == group.len() && new_key <= old_key).then_some((new, new_key < old_key))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lacam::Lacam;
    use mrpp_core::{Ctx, MapfProblem, Plan, Planner, Problem, Rules};

    /// On both objectives, with one and with several threads: every round leaves a valid plan
    /// whose (objective, sum of costs) key never rises, the key is the validator's count, and
    /// 200 steps lower it.
    #[test]
    fn steps_keep_the_plan_valid_and_never_raise_its_cost() {
        let map = crate::GridMap::load(std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../data/movingai/random-32-32-20.map"
        )))
        .unwrap();
        let inst = crate::map::random_instance(&map, 120, 3).unwrap();
        let g = map.graph();
        let p = MapfProblem::on(g, &inst, Rules::default());
        let plan = Lacam::default().plan(&p, &Ctx::default()).unwrap();
        let mut dist = GoalDistances::new(g, &inst.goals);
        assert!(dist.warm_up(&inst.starts, Deadline::none()));
        // The validator's sum of costs, and the sum of loss recounted from the padded paths.
        let counts = |paths: &[Vec<VertexId>]| {
            let soc = p.validate(&Plan::new(paths.to_vec())).unwrap().sum_of_costs;
            let horizon = paths.iter().map(Vec::len).max().unwrap();
            let sol: u64 = paths
                .iter()
                .zip(&inst.goals)
                .map(|(q, &goal)| {
                    (0..horizon - 1)
                        .filter(|&t| {
                            let at = |t: usize| q[t.min(q.len() - 1)];
                            !(at(t) == goal && at(t + 1) == goal)
                        })
                        .count() as u64
                })
                .sum();
            (sol, soc)
        };
        for (loss, threads) in [(false, 1), (true, 1), (false, 3), (true, 2)] {
            let mut lns =
                Lns::new(g, &inst.goals, &dist, plan.paths.clone(), 7, loss).with_threads(threads);
            let key = |paths: &[Vec<VertexId>]| {
                let (sol, soc) = counts(paths);
                if loss { (sol, soc) } else { (soc, 0) }
            };
            let before = key(&plan.paths);
            let mut last = lns.key();
            assert_eq!(last, before, "loss {loss}");
            for _ in 0..200 / threads {
                lns.steps(1, Deadline::none());
                assert!(lns.key() <= last, "loss {loss}");
                // Valid after every round (the validator judges the padded plan).
                p.validate(&Plan::new(lns.paths().to_vec())).unwrap();
                last = lns.key();
            }
            // The other threads' tables are the main one's.
            for r in &lns.replicas {
                for v in 0..g.num_vertices() as VertexId {
                    for t in 0..40 {
                        assert_eq!(r.vertex_free(v, t), lns.res.vertex_free(v, t));
                    }
                }
            }
            assert_eq!(key(lns.paths()), last, "loss {loss}");
            // Rounds do not depend on how the threads were scheduled.
            let mut again =
                Lns::new(g, &inst.goals, &dist, plan.paths.clone(), 7, loss).with_threads(threads);
            for _ in 0..200 / threads {
                again.steps(1, Deadline::none());
            }
            assert_eq!(again.paths(), lns.paths(), "loss {loss}, {threads} threads");
            assert!(last < before, "loss {loss}: {last:?} !< {before:?}");
        }
    }
}
