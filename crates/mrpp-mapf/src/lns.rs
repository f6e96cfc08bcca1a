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
        }
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
        let soc: u64 = paths.iter().map(|p| p.len() as u64 - 1).sum();
        if self.loss {
            let sol = paths
                .iter()
                .zip(agents)
                .map(|(p, i)| path_loss(p, self.goals[i]))
                .sum();
            (sol, soc)
        } else {
            (soc, 0)
        }
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
        let old: Vec<Vec<VertexId>> = group.iter().map(|&i| self.paths[i].clone()).collect();
        for p in &old {
            self.res.release_path(p, 0, true);
        }
        // The group's new paths may not cost more than its old ones, nor end more than SLACK steps
        // after the makespan: each search is bounded by
        // what is left of that budget after the paths already found and the distances of the
        // agents still to go, so a hopeless search fails fast instead of exploring every
        // (cell, time) up to a far horizon.
        let old_key = self.key_of(&old, group.iter().copied());
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
            match sipp(&q, &self.res) {
                Search::Found(p) => {
                    let p = trimmed(p);
                    spent += p.len() as u64 - 1;
                    self.res.reserve_path(&p, 0, true);
                    new.push(p);
                }
                _ => break,
            }
        }
        let new_key = self.key_of(&new, group.iter().copied());
        let keep = new.len() == group.len() && new_key <= old_key;
        let improved = keep && new_key < old_key;
        self.improved += u64::from(improved);
        if keep {
            for (&i, p) in group.iter().zip(new) {
                self.paths[i] = p;
            }
        } else {
            for p in &new {
                self.res.release_path(p, 0, true);
            }
            for p in &old {
                self.res.reserve_path(p, 0, true);
            }
        }
        improved
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lacam::Lacam;
    use mrpp_core::{Ctx, MapfProblem, Plan, Planner, Problem, Rules};

    /// On both objectives: every step leaves a valid plan whose (objective, sum of costs) key
    /// never rises, the key is the validator's count, and 200 steps lower it.
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
        for loss in [false, true] {
            let mut lns = Lns::new(g, &inst.goals, &dist, plan.paths.clone(), 7, loss);
            let key = |paths: &[Vec<VertexId>]| {
                let (sol, soc) = counts(paths);
                if loss { (sol, soc) } else { (soc, 0) }
            };
            let before = key(&plan.paths);
            let mut last = lns.key();
            assert_eq!(last, before, "loss {loss}");
            for _ in 0..200 {
                lns.step(Deadline::none());
                assert!(lns.key() <= last, "loss {loss}");
                last = lns.key();
            }
            assert_eq!(key(lns.paths()), last, "loss {loss}");
            assert!(last < before, "loss {loss}: {last:?} !< {before:?}");
        }
    }
}
