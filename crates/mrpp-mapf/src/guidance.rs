//! Local guidance for LaCAM's configuration generator (T. Arita, K. Okumura, "Local guidance for
//! configuration-based multi-agent pathfinding", AAAI 2026, arXiv 2510.19072): whenever LaCAM
//! generates successors of a configuration, every agent first gets a short space-time path (the
//! *guidance path*, `window` steps) that avoids the guidance paths already planned for the agents
//! before it in the configuration's order, and PIBT tries that path's first step first
//! ([`crate::pibt`]'s preference; with `-p scatter` too, guidance wins). PIBT's greedy choice
//! sees one step ahead and one agent at a time; the guidance paths see `window` steps ahead and
//! the agents of higher priority, so queues form less often and agents step aside earlier.
//!
//! **The guidance path** ([`Guidance::plan`]): for the agents in the configuration's order, an A*
//! over (vertex, step) from the agent's vertex at step 0 up to step `window`, minimising
//!
//! * the steps spent off the goal (a step resting on the goal costs nothing: sum of loss, LaCAM's
//!   objective),
//! * plus the goal distance of the vertex reached at step `window` (where the window ends),
//! * plus `collision_cost` for each collision with a guidance path planned before it in this
//!   configuration: the same vertex at the same step, or the two moving through one edge in
//!   opposite directions at the same step (the table keeps the last agent per vertex and step, so
//!   a swap with an earlier agent hidden under a later one on the same cell goes uncounted).
//!
//! The goal distance is the heuristic (admissible: a step lowers it by one at most and costs one
//! unless on the goal). Ties in `f` go to the state with fewer collisions, then to the later step,
//! then to the one generated first. The path is stored in a space-time table that the next agents'
//! searches consult, and its first step is the agent's guidance.
//!
//! Where the paper's text (as read here: its abstract and summaries; the full method section was
//! not available) is silent, mrpp's choices, each a named option or a constant here: the window
//! (`-p local_guidance=W`, 0 = off, the default), a collision costs as much as four steps off the
//! goal (`-p guidance_collision_cost`, default 4; soft: an agent may keep a colliding path when
//! every other is dearer; of 1, 4, 10 and 100, 4 was the only one within 4% of the lowest sum of
//! costs on four dense instances, docs/performance.md), the
//! agents not planned yet are not obstacles (the configuration's order is a priority order, as in
//! prioritised planning), each configuration's guidance is computed once, when it first generates a
//! successor, and kept in its node (`n` vertices per configuration), and the A* of one agent stops
//! after `MAX_EXPANSIONS` states with the best state reached so far (bounded work at any density).
//!
//! Memory: `(W + 1) x vertices x 28` bytes of buffers (a 10-step window on a 256 x 256 map: 20 MB;
//! the largest window, 64, on a 500 x 500 map: 450 MB), plus 4 bytes per agent per configuration
//! that generated a successor.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use mrpp_core::mapf::search::distance::GoalDistances;
use mrpp_core::{Ctx, Graph, Progress, Throttle, VertexId};

/// States one agent's A* may expand before it settles for the best state reached.
const MAX_EXPANSIONS: u32 = 4096;

/// No agent / no state.
const NOBODY: u32 = u32::MAX;

/// An A* entry, smallest first: `(f, collisions, Reverse(step), sequence, state)`.
type Entry = Reverse<(u32, u32, Reverse<u32>, u32, u32)>;

/// The reusable buffers of the guidance searches: a space-time table of the guidance paths of one
/// configuration, and the A*'s per-state marks, both indexed by `step * vertices + vertex` and
/// stamped so that nothing is cleared between configurations or agents.
pub(crate) struct Guidance {
    window: u32,
    /// Cost of one collision with an earlier agent's guidance path, in steps.
    collision_cost: u32,
    vertices: usize,
    /// Per (step, vertex): `(stamp, agent count, last agent)` of the guidance paths of the
    /// configuration being planned (stamp = its number).
    table: Vec<(u32, u16, u32)>,
    table_stamp: u32,
    /// Per (step, vertex): `(stamp, best g, collisions, parent state)` of the current agent's A*.
    marks: Vec<(u32, u32, u32, u32)>,
    mark_stamp: u32,
    heap: BinaryHeap<Entry>,
    /// The current agent's guidance path, as state indices from step 0 to the window's end.
    path: Vec<u32>,
}

impl Guidance {
    /// Buffers for guidance paths of `window` steps (1 or more) on `graph`.
    pub(crate) fn new(graph: &Graph, window: u32, collision_cost: u32) -> Guidance {
        let states = (window as usize + 1) * graph.num_vertices();
        Guidance {
            window,
            collision_cost,
            vertices: graph.num_vertices(),
            table: vec![(0, 0, NOBODY); states],
            table_stamp: 0,
            marks: vec![(0, 0, 0, NOBODY); states],
            mark_stamp: 0,
            heap: BinaryHeap::new(),
            path: Vec::new(),
        }
    }

    /// Each agent's guidance for `config`: the first step of its guidance path (its own vertex
    /// when the path waits), planned in `order` (the configuration's agent order, highest priority
    /// first). `dist` answers goal distances for every agent; `goals[i]` is agent `i`'s goal.
    /// Agents not planned when the run's deadline passes (checked every 64 agents, when progress
    /// is reported too) get no guidance (`VertexId::MAX`), so a run keeps its time limit at any
    /// number of agents.
    pub(crate) fn plan(
        &mut self,
        graph: &Graph,
        dist: &GoalDistances,
        goals: &[VertexId],
        config: &[VertexId],
        order: &[u32],
        ctx: &Ctx,
    ) -> Box<[VertexId]> {
        self.table_stamp = self.table_stamp.wrapping_add(1);
        if self.table_stamp == 0 {
            self.table.fill((0, 0, NOBODY));
            self.table_stamp = 1;
        }
        let mut first = vec![VertexId::MAX; config.len()].into_boxed_slice();
        let mut throttle = Throttle::new();
        for (k, &i) in order.iter().enumerate() {
            if k % 64 == 63 {
                if ctx.deadline.expired() {
                    break;
                }
                throttle.report(ctx, || Progress {
                    stage: "LaCAM local guidance",
                    done: k as u64,
                    total: order.len() as u64,
                    note: "agents' guidance paths of one configuration".into(),
                });
            }
            let i = i as usize;
            self.search(graph, dist, i, config[i], goals[i]);
            first[i] = (self.path[1] as usize % self.vertices) as VertexId;
            for &s in &self.path {
                let e = &mut self.table[s as usize];
                if e.0 != self.table_stamp {
                    *e = (self.table_stamp, 0, NOBODY);
                }
                e.1 = e.1.saturating_add(1);
                e.2 = i as u32;
            }
        }
        first
    }

    /// Collisions of agent `i` moving `v -> u` from step `t` with the table.
    fn collisions(&self, i: u32, v: VertexId, u: VertexId, t: u32) -> u32 {
        let nv = self.vertices;
        let at = |t: u32, w: VertexId| {
            let e = self.table[t as usize * nv + w as usize];
            if e.0 == self.table_stamp {
                (e.1, e.2)
            } else {
                (0, NOBODY)
            }
        };
        let (on_u, _) = at(t + 1, u);
        let mut c = u32::from(on_u);
        if v != u {
            // Someone moving u -> v at the same step (the last agent recorded on each).
            let (_, a) = at(t, u);
            let (_, b) = at(t + 1, v);
            if a != NOBODY && a == b && a != i {
                c += 1;
            }
        }
        c
    }

    /// Agent `i`'s guidance path from `start` into `self.path` (state indices from step 0).
    fn search(
        &mut self,
        graph: &Graph,
        dist: &GoalDistances,
        i: usize,
        start: VertexId,
        goal: VertexId,
    ) {
        let nv = self.vertices;
        let w = self.window;
        self.mark_stamp = self.mark_stamp.wrapping_add(1);
        if self.mark_stamp == 0 {
            self.marks.fill((0, 0, 0, NOBODY));
            self.mark_stamp = 1;
        }
        let stamp = self.mark_stamp;
        let h = |v: VertexId| dist.get(i, v);
        self.heap.clear();
        self.marks[start as usize] = (stamp, 0, 0, NOBODY);
        self.heap.push(Reverse((h(start), 0, Reverse(0), 0, start)));
        let mut seq = 1u32;
        // (f, collisions, state) of the best state popped, the end of the path.
        let mut best: (u32, u32, u32) = (u32::MAX, u32::MAX, start);
        let mut expansions = 0u32;
        while let Some(Reverse((f, col, Reverse(t), _, s))) = self.heap.pop() {
            let m = self.marks[s as usize];
            let v = (s as usize % nv) as VertexId;
            let g = f.saturating_sub(h(v));
            if (m.1, m.2) < (g, col) {
                continue; // a stale entry
            }
            if t == w || (v == goal && self.rests_free(goal, t)) {
                // The window's end (or the goal with nothing passing through it later): the
                // remaining cost is exactly h (0 on the goal).
                best = (f, col, s);
                break;
            }
            if (f, col) < (best.0, best.1) {
                best = (f, col, s);
            }
            expansions += 1;
            if expansions > MAX_EXPANSIONS {
                break;
            }
            for u in std::iter::once(v).chain(graph.neighbors(v).iter().copied()) {
                let step = u32::from(!(v == goal && u == goal));
                let c = self.collisions(i as u32, v, u, t);
                // Saturating: only a preference, never a plan's validity, rests on these sums.
                let ng = g
                    .saturating_add(step)
                    .saturating_add(c.saturating_mul(self.collision_cost));
                let nc = col + c;
                let ns = (t + 1) as usize * nv + u as usize;
                let e = self.marks[ns];
                if e.0 == stamp && (e.1, e.2) <= (ng, nc) {
                    continue;
                }
                self.marks[ns] = (stamp, ng, nc, s);
                self.heap.push(Reverse((
                    ng.saturating_add(h(u)),
                    nc,
                    Reverse(t + 1),
                    seq,
                    ns as u32,
                )));
                seq += 1;
            }
        }
        self.path.clear();
        let mut s = best.2;
        while s != NOBODY {
            self.path.push(s);
            s = self.marks[s as usize].3;
        }
        self.path.reverse();
        // A path that ends on the goal before the window's end rests there to its end.
        let last = *self.path.last().expect("the start at least");
        let (t_end, v_end) = (last as usize / nv, last as usize % nv);
        for t in t_end + 1..=w as usize {
            self.path.push((t * nv + v_end) as u32);
        }
    }

    /// Whether no guidance path planned so far is on `goal` after step `t` (so resting there to
    /// the window's end costs nothing more).
    fn rests_free(&self, goal: VertexId, t: u32) -> bool {
        (t + 1..=self.window).all(|s| {
            let e = self.table[s as usize * self.vertices + goal as usize];
            e.0 != self.table_stamp || e.1 == 0
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::GridMap;
    use mrpp_core::Deadline;

    /// An open `side` x `side` grid (the ASCII map format), vertex `y * side + x`.
    fn open_grid(side: usize) -> Graph {
        let text = format!("{}\n", ".".repeat(side)).repeat(side);
        let (map, _) = GridMap::parse(&text, std::path::Path::new("open.txt")).expect("parses");
        map.graph().clone()
    }

    fn ctx(deadline: Deadline) -> Ctx {
        Ctx::new(0, deadline)
    }

    #[test]
    fn a_later_agent_is_guided_around_an_earlier_agents_path() {
        let g = open_grid(3);
        // Agent 0 crosses the middle row left to right, agent 1 the middle column top to bottom:
        // both shortest paths enter the centre (4) at step 1.
        let goals = [5, 7];
        let config = [3, 1];
        let dist = GoalDistances::new(&g, &goals);
        for cost in [1, 4, 100] {
            let mut gd = Guidance::new(&g, 4, cost);
            let first = gd.plan(&g, &dist, &goals, &config, &[0, 1], &ctx(Deadline::none()));
            assert_eq!(first[0], 4, "the first agent goes straight (cost {cost})");
            assert_ne!(
                first[1], 4,
                "the second agent keeps out of the centre (cost {cost})"
            );
            // In the other order the roles swap.
            let first = gd.plan(&g, &dist, &goals, &config, &[1, 0], &ctx(Deadline::none()));
            assert_eq!(first[1], 4, "cost {cost}");
            assert_ne!(first[0], 4, "cost {cost}");
        }
        // Alone, each agent heads for the centre.
        let mut gd = Guidance::new(&g, 4, 4);
        let alone = gd.plan(
            &g,
            &dist,
            &goals[..1],
            &config[..1],
            &[0],
            &ctx(Deadline::none()),
        );
        assert_eq!(&*alone, &[4]);
    }

    #[test]
    fn agents_left_when_the_deadline_passes_get_no_guidance() {
        // 100 agents on a 10 x 10 grid, each heading one cell right (wrapping): with a deadline
        // already passed, the first 63 in the order are guided and the rest are not.
        let g = open_grid(10);
        let config: Vec<VertexId> = (0..100).collect();
        let goals: Vec<VertexId> = (0..100)
            .map(|v| (v / 10) * 10 + (v % 10 + 1) % 10)
            .collect();
        let dist = GoalDistances::new(&g, &goals);
        let order: Vec<u32> = (0..100).rev().collect();
        let mut gd = Guidance::new(&g, 3, 4);
        let past = Deadline::after(std::time::Duration::ZERO);
        std::thread::sleep(std::time::Duration::from_millis(2));
        let first = gd.plan(&g, &dist, &goals, &config, &order, &ctx(past));
        for (k, &i) in order.iter().enumerate() {
            assert_eq!(
                first[i as usize] == VertexId::MAX,
                k >= 63,
                "agent {i}, {k}th in the order"
            );
        }
        let all = gd.plan(&g, &dist, &goals, &config, &order, &ctx(Deadline::none()));
        assert!(all.iter().all(|&v| v != VertexId::MAX));
    }

    #[test]
    fn an_agent_on_its_goal_stays_unless_someone_must_pass() {
        let g = open_grid(3);
        // Agent 0 rests on the centre; agent 1 (planned first) must cross it to reach 7 from 1.
        let goals = [4, 7];
        let config = [4, 1];
        let dist = GoalDistances::new(&g, &goals);
        let mut gd = Guidance::new(&g, 4, 4);
        let first = gd.plan(&g, &dist, &goals, &config, &[0, 1], &ctx(Deadline::none()));
        assert_eq!(first[0], 4, "first in the order, it rests on its goal");
        let first = gd.plan(&g, &dist, &goals, &config, &[1, 0], &ctx(Deadline::none()));
        assert_eq!(first[1], 4, "the crossing agent goes straight");
        assert_ne!(first[0], 4, "the resting agent steps aside");
    }
}
