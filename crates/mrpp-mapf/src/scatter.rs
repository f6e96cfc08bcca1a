//! Space-utilisation optimisation ("scatter"; S. D. Han, J. Yu, "Optimizing space utilization
//! for more effective multi-robot path planning", ICRA 2022), as LaCAM*'s PIBT uses it
//! (K. Okumura, "Engineering LaCAM*: Towards real-time, large-scale, and near-optimal
//! multi-agent pathfinding", AAMAS 2024, §4 "SUO"): before the search, every agent gets a path to
//! its goal at most `margin` steps longer than its shortest, chosen to cross the other agents'
//! paths as seldom as possible; PIBT then tries that path's next vertex first whenever the agent
//! stands on it ([`Scatter::next`]). The agents spread over the map's parallel routes instead of
//! all taking the same shortest corridor, so the configuration search meets fewer jams and its
//! first plan is cheaper.
//!
//! **The paths** ([`Scatter::build`]): rounds over the agents in a seeded random order; each agent
//! in turn is taken out of a collision table and re-planned by a best-first search over vertices
//! (not time: a path never waits, so an agent is on its path's `t`-th vertex at step `t`) that
//! orders states by the collisions met so far, then by `f = g + h` with `h` the goal distance,
//! then by insertion; a vertex is expanded once, the start is never re-entered, and a state whose
//! `g + 1 + h` exceeds the agent's distance + `margin` is not generated. A collision of a move
//! `v -> u` from step `t` is another path on `u` at `t + 1`, another path moving `u -> v` at the
//! same step, or an agent that reached its goal `u` (where it stays) before `t + 1`. Rounds
//! repeat while the total count falls (at least two), until the deadline; the round with the
//! fewest collisions is kept.
//!
//! Where the papers are silent: ties after collisions and `f` go to the state generated first;
//! the default margin is 10 steps (lacam3's `--scatter-margin`).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use rand::SeedableRng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;
use rustc_hash::FxHashMap;

use mrpp_core::mapf::search::distance::GoalDistances;
use mrpp_core::{Deadline, Graph, VertexId};

/// Each agent's preferred path, as the next vertex after each vertex of it.
#[derive(Debug, Default)]
pub(crate) struct Scatter {
    next: Vec<FxHashMap<VertexId, VertexId>>,
    /// Collisions among the kept paths, and rounds run.
    collisions: u64,
    rounds: u32,
}

/// Who is where when: per vertex, `(step, agent)` sorted; per vertex, the agent whose path ends
/// there and the step it arrives (goals are distinct, so at most one).
struct Table {
    at: Vec<Vec<(u32, u32)>>,
    ends: Vec<Option<(u32, u32)>>,
}

impl Table {
    /// Agents other than `me` on `v` at step `t`.
    fn on(&self, v: VertexId, t: u32) -> impl Iterator<Item = u32> + '_ {
        let list = &self.at[v as usize];
        let from = list.partition_point(|&(s, _)| s < t);
        list[from..]
            .iter()
            .take_while(move |&&(s, _)| s == t)
            .map(|&(_, a)| a)
    }

    /// Collisions of the move `v -> u` from step `t` with the paths in the table.
    fn cost(&self, v: VertexId, u: VertexId, t: u32) -> u32 {
        let mut c = self.on(u, t + 1).count() as u32;
        if v != u {
            for j in self.on(v, t + 1) {
                if self.on(u, t).any(|k| k == j) {
                    c += 1;
                }
            }
        }
        if let Some((_, end)) = self.ends[u as usize]
            && end < t + 1
        {
            c += 1;
        }
        c
    }

    /// Collisions of agent `i`'s `path` with the table (which does not hold it): its moves,
    /// and the paths on its goal after it arrives there.
    fn path_cost(&self, path: &[VertexId]) -> u64 {
        let moves: u64 = path
            .windows(2)
            .enumerate()
            .map(|(t, w)| u64::from(self.cost(w[0], w[1], t as u32)))
            .sum();
        let arrive = path.len() as u32 - 1;
        let goal = path[path.len() - 1];
        let parked = self.at[goal as usize]
            .iter()
            .filter(|&&(s, _)| s > arrive)
            .count() as u64;
        moves + parked
    }

    fn insert(&mut self, i: u32, path: &[VertexId]) {
        for (t, &v) in path.iter().enumerate() {
            let list = &mut self.at[v as usize];
            let pos = list.partition_point(|&e| e < (t as u32, i));
            list.insert(pos, (t as u32, i));
        }
        self.ends[path[path.len() - 1] as usize] = Some((i, path.len() as u32 - 1));
    }

    fn remove(&mut self, i: u32, path: &[VertexId]) {
        for (t, &v) in path.iter().enumerate() {
            let list = &mut self.at[v as usize];
            if let Ok(pos) = list.binary_search(&(t as u32, i)) {
                list.remove(pos);
            }
        }
        let end = &mut self.ends[path[path.len() - 1] as usize];
        if end.is_some_and(|(a, _)| a == i) {
            *end = None;
        }
    }
}

/// The search's per-vertex marks, stamped per agent so nothing is cleared between searches.
struct Marks {
    /// `(stamp, parent)`: expanded in the search of `stamp`, reached from `parent`.
    closed: Vec<(u32, VertexId)>,
    stamp: u32,
}

impl Scatter {
    /// The paths of `starts` to `goals` (each goal distance from `dist`, which must answer for
    /// every agent) at most `margin` steps longer than the shortest, rounds as in the module
    /// doc until `deadline` (the rounds finished by then are used; none: no preference).
    pub(crate) fn build(
        graph: &Graph,
        starts: &[VertexId],
        goals: &[VertexId],
        dist: &GoalDistances,
        margin: u32,
        seed: u64,
        deadline: Deadline,
    ) -> Scatter {
        let n = starts.len();
        let nv = graph.num_vertices();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut table = Table {
            at: vec![Vec::new(); nv],
            ends: vec![None; nv],
        };
        let mut marks = Marks {
            closed: vec![(0, 0); nv],
            stamp: 0,
        };
        let mut paths: Vec<Vec<VertexId>> = vec![Vec::new(); n];
        let mut total = 0u64;
        let mut best: Option<(u64, Vec<Vec<VertexId>>)> = None;
        let mut rounds = 0u32;
        let mut order: Vec<usize> = (0..n).collect();
        'rounds: loop {
            let before = best.as_ref().map(|b| b.0);
            order.shuffle(&mut rng);
            for &i in &order {
                if deadline.expired() {
                    break 'rounds;
                }
                if !paths[i].is_empty() {
                    table.remove(i as u32, &paths[i]);
                    total -= table.path_cost(&paths[i]);
                }
                let found = shortest_with_fewest_collisions(
                    graph, &table, &mut marks, dist, i, starts[i], goals[i], margin,
                );
                if let Some(p) = found {
                    paths[i] = p;
                }
                if !paths[i].is_empty() {
                    total += table.path_cost(&paths[i]);
                    table.insert(i as u32, &paths[i]);
                }
            }
            rounds += 1;
            if best.as_ref().is_none_or(|b| total < b.0) {
                best = Some((total, paths.clone()));
            }
            let improved = before.is_none_or(|b| total < b);
            if total == 0 || (rounds >= 2 && !improved) {
                break;
            }
        }
        let Some((collisions, kept)) = best else {
            return Scatter::default();
        };
        let next = kept
            .iter()
            .map(|p| p.windows(2).map(|w| (w[0], w[1])).collect())
            .collect();
        Scatter {
            next,
            collisions,
            rounds,
        }
    }

    /// Agent `i`'s preferred next vertex when it stands on `v` (on its path), else `None`.
    #[inline]
    pub(crate) fn next(&self, i: usize, v: VertexId) -> Option<VertexId> {
        self.next.get(i)?.get(&v).copied()
    }

    /// Collisions among the paths kept, and rounds run.
    pub(crate) fn counts(&self) -> (u64, u32) {
        (self.collisions, self.rounds)
    }
}

/// Agent `i`'s path from `start` to `goal` with the fewest collisions against `table`, then the
/// least length, at most its distance + `margin` long (module doc), or `None` (no such path
/// within the margin, which cannot happen with an exact distance table).
/// An open state: (collisions, f, insertion order, g, vertex, parent); popped lowest first.
type Entry = (u32, u32, u32, u32, VertexId, VertexId);

#[allow(clippy::too_many_arguments)]
fn shortest_with_fewest_collisions(
    graph: &Graph,
    table: &Table,
    marks: &mut Marks,
    dist: &GoalDistances,
    i: usize,
    start: VertexId,
    goal: VertexId,
    margin: u32,
) -> Option<Vec<VertexId>> {
    let bound = dist.get(i, start).saturating_add(margin);
    marks.stamp = marks.stamp.wrapping_add(1);
    if marks.stamp == 0 {
        marks.closed.fill((0, 0));
        marks.stamp = 1;
    }
    let stamp = marks.stamp;
    let mut open: BinaryHeap<Reverse<Entry>> = BinaryHeap::new();
    let mut counter = 0u32;
    open.push(Reverse((0, dist.get(i, start), 0, 0, start, start)));
    while let Some(Reverse((c, _, _, g, v, parent))) = open.pop() {
        if marks.closed[v as usize].0 == stamp {
            continue;
        }
        marks.closed[v as usize] = (stamp, parent);
        if v == goal {
            let mut path = vec![v];
            let mut w = v;
            while w != start {
                w = marks.closed[w as usize].1;
                path.push(w);
            }
            path.reverse();
            return Some(path);
        }
        for &u in graph.neighbors(v) {
            if u == start || marks.closed[u as usize].0 == stamp {
                continue;
            }
            let h = dist.get(i, u);
            if g.saturating_add(1).saturating_add(h) > bound {
                continue;
            }
            counter += 1;
            open.push(Reverse((
                c + table.cost(v, u, g),
                g + 1 + h,
                counter,
                g + 1,
                u,
                v,
            )));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrpp_core::Deadline;

    /// Two agents crossing a 3 x 3 grid along the middle row, one each way: with a margin of 2
    /// one of them takes the top or bottom row instead of meeting the other head on, and each
    /// kept path runs from its start to its goal over edges of the graph within the margin.
    #[test]
    fn agents_take_parallel_routes_instead_of_meeting_head_on() {
        // 3 x 3 open grid, vertex = y * 3 + x.
        let mut edges = Vec::new();
        for y in 0..3u32 {
            for x in 0..3u32 {
                let v = y * 3 + x;
                if x + 1 < 3 {
                    edges.push((v, v + 1));
                }
                if y + 1 < 3 {
                    edges.push((v, v + 3));
                }
            }
        }
        let g = Graph::from_edges(9, &edges);
        let (starts, goals) = (vec![3, 5], vec![5, 3]);
        let mut dist = GoalDistances::new(&g, &goals);
        assert!(dist.warm_up(&starts, Deadline::none()));
        let s = Scatter::build(&g, &starts, &goals, &dist, 2, 1, Deadline::none());
        assert_eq!(s.counts().0, 0, "{s:?}");
        for i in 0..2 {
            let mut v = starts[i];
            let mut steps = 0;
            while v != goals[i] {
                let w = s.next(i, v).expect("a path to the goal");
                assert!(g.neighbors(v).contains(&w));
                v = w;
                steps += 1;
            }
            assert!(steps <= 2 + 2, "agent {i}: {steps} steps");
        }
        // Not both on the middle row.
        assert!(s.next(0, 3) != Some(4) || s.next(1, 5) != Some(4), "{s:?}");
    }
}
