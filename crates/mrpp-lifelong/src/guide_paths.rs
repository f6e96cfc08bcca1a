//! Traffic-flow-optimised guide paths: each robot follows a path to its goal chosen to avoid
//! the traffic of the other robots' paths, and PIBT ranks its candidate cells by their distance
//! *to that path* instead of to the goal (H. Chen, D. Harabor, J. Li, P. J. Stuckey, "Traffic
//! flow optimisation for lifelong multi-agent path finding", AAAI 2024; the League of Robot
//! Runners start kit's default planner, v2.1.2, `default_planner/flow.cpp` and `search.cpp`).
//!
//! **Flow.** Every guide path adds one unit of flow to each of its moves: `flow[v][d]` counts
//! the paths that leave cell `v` in direction `d` (0 east, 1 south, 2 west, 3 north).
//!
//! **A guide path** is an A\* search from the robot's cell to its goal in which a move
//! `u -> v` in direction `d` costs `1 + (flow[u][d] + 1) * flow[v][d + 2]` (the paper's
//! contraflow: paths that would meet head on) `+ (flow[v][0] + ... + flow[v][3]) / 2` (vertex
//! congestion, integer division), with the robot's own path removed from the flow first. The
//! breadth-first distance to the goal is the heuristic (consistent: every move costs at least
//! 1). The kit orders the same sum; mrpp breaks ties towards the larger cost already paid and
//! then by vertex index, so a run is reproducible.
//!
//! **Distance to the path** of cell `c`: a breadth-first search started from every cell of the
//! path at once (the goal first), each carrying how many moves of the path remain from it
//! (`togo`); `c`'s value is its hop distance to the path plus the `togo` of the path cell that
//! reached it first. The search is expanded lazily, only as far as the cells asked for (a robot
//! on its path asks for its cell and its neighbours: a few dozen cells).
//!
//! **When paths are planned.** Every step, each robot whose goal changed gets a new path (the
//! kit's `require_guide_path`); a robot without a task has none. Then, as the kit's
//! `frank_wolfe` re-plans paths until its time runs out, mrpp re-plans a fixed number of them
//! per step ([`GuidePaths::replans`], the named option `guide_replans`), so that a run does not
//! depend on machine speed: those whose robot is farthest from its path first, then those
//! planned longest ago, then by robot index. Both stop at the step's deadline; a robot left
//! without a path that step ranks its candidates by distance to its goal.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, VecDeque};

use mrpp_core::Deadline;
use mrpp_core::mapf::graph::VertexId;
use mrpp_core::mapf::search::distance::UNREACHABLE;
use mrpp_mapf::GridMap;
use rustc_hash::FxHashMap;

use crate::distances::Distances;
use crate::model::neighbour;

const NONE: VertexId = VertexId::MAX;

/// One robot's guide path and its lazily expanded distance-to-path search.
#[derive(Debug, Clone, Default)]
struct Guide {
    /// Cells from the robot's cell when planned to its goal; empty: no path.
    path: Vec<VertexId>,
    /// Cells reached by the search: (hops to the path, moves of the path left from there).
    reached: FxHashMap<VertexId, (u32, u32)>,
    open: VecDeque<VertexId>,
    /// Step at which the path was planned.
    planned_at: u32,
}

/// The guide paths of every robot and the flow they make (module doc).
#[derive(Debug, Clone)]
pub struct GuidePaths {
    /// Neighbour of each cell in each direction (`NONE`: wall or edge of the map).
    next: Vec<[VertexId; 4]>,
    flow: Vec<[u32; 4]>,
    guides: Vec<Guide>,
    /// Paths re-planned per step beyond those of robots with a new goal.
    pub replans: usize,
    // A* buffers, reused: cost paid, parent, and the search that last touched each cell.
    g: Vec<u64>,
    parent: Vec<VertexId>,
    touched: Vec<u32>,
    closed: Vec<u32>,
    search: u32,
    heap: BinaryHeap<(Reverse<u64>, u64, Reverse<VertexId>)>,
    /// Guide paths planned so far.
    pub planned: usize,
}

impl GuidePaths {
    /// No path yet, for `robots` robots on `map`; `replans` paths re-planned per step.
    pub fn new(map: &GridMap, robots: usize, replans: usize) -> Self {
        let n = map.graph().num_vertices();
        let next = (0..n as VertexId)
            .map(|v| std::array::from_fn(|d| neighbour(map, v, d as u8).unwrap_or(NONE)))
            .collect();
        GuidePaths {
            next,
            flow: vec![[0; 4]; n],
            guides: vec![Guide::default(); robots],
            replans,
            g: vec![0; n],
            parent: vec![NONE; n],
            touched: vec![0; n],
            closed: vec![0; n],
            search: 0,
            heap: BinaryHeap::new(),
            planned: 0,
        }
    }

    /// Plans the paths of this step (module doc): robot `i` is on `cells[i]` and heads for
    /// `goals[i]` (its own cell when it has no task); `t` is the step.
    pub fn update(
        &mut self,
        cells: &[VertexId],
        goals: &[VertexId],
        t: u32,
        dist: &mut Distances,
        graph: &mrpp_core::mapf::graph::Graph,
        deadline: Deadline,
    ) {
        for (i, (&cell, &goal)) in cells.iter().zip(goals).enumerate() {
            if goal == cell {
                self.drop_path(i);
            } else if self.guides[i].path.last() != Some(&goal) && !deadline.expired() {
                self.replan(i, cell, goal, t, dist, graph);
            }
        }
        if self.replans == 0 || deadline.expired() {
            return;
        }
        let mut order: Vec<(Reverse<u32>, u32, usize)> = Vec::new();
        for (i, &cell) in cells.iter().enumerate() {
            if self.guides[i].path.len() > 1 && self.guides[i].planned_at < t {
                let off = self.path_distance(i, cell).0;
                order.push((Reverse(off), self.guides[i].planned_at, i));
            }
        }
        let k = self.replans.min(order.len());
        if k == 0 {
            return;
        }
        order.select_nth_unstable(k - 1);
        order.truncate(k);
        order.sort_unstable();
        for (_, _, i) in order {
            if deadline.expired() {
                break;
            }
            let goal = *self.guides[i].path.last().expect("a path");
            self.replan(i, cells[i], goal, t, dist, graph);
        }
    }

    /// Whether robot `i` has a guide path to `goal`.
    pub fn follows(&self, i: usize, goal: VertexId) -> bool {
        self.guides[i].path.last() == Some(&goal)
    }

    /// Distance to robot `i`'s goal along its guide path from each of `cells`, in order
    /// (module doc; [`UNREACHABLE`] for a cell in another component).
    pub fn distances(&mut self, i: usize, cells: &[VertexId], out: &mut Vec<u32>) {
        out.clear();
        for &c in cells {
            let (off, togo) = self.path_distance(i, c);
            out.push(if off == UNREACHABLE {
                UNREACHABLE
            } else {
                off + togo
            });
        }
    }

    /// Robot `i`'s hops from `cell` to its path and the moves left from where it meets it
    /// ([`UNREACHABLE`] hops for a cell in another component or a robot without a path).
    pub fn path_distance(&mut self, i: usize, cell: VertexId) -> (u32, u32) {
        let Guide { reached, open, .. } = &mut self.guides[i];
        while !reached.contains_key(&cell) {
            let Some(c) = open.pop_front() else {
                return (UNREACHABLE, 0);
            };
            let (off, togo) = reached[&c];
            for &w in &self.next[c as usize] {
                if w != NONE && !reached.contains_key(&w) {
                    reached.insert(w, (off + 1, togo));
                    open.push_back(w);
                }
            }
        }
        reached[&cell]
    }

    fn drop_path(&mut self, i: usize) {
        let path = std::mem::take(&mut self.guides[i].path);
        for w in path.windows(2) {
            let d = self.dir(w[0], w[1]);
            self.flow[w[0] as usize][d] -= 1;
        }
        self.guides[i].reached.clear();
        self.guides[i].open.clear();
    }

    fn dir(&self, u: VertexId, v: VertexId) -> usize {
        self.next[u as usize]
            .iter()
            .position(|&w| w == v)
            .expect("a path moves between neighbours")
    }

    /// A new guide path for robot `i` from `start` to `goal` (module doc).
    fn replan(
        &mut self,
        i: usize,
        start: VertexId,
        goal: VertexId,
        t: u32,
        dist: &mut Distances,
        graph: &mrpp_core::mapf::graph::Graph,
    ) {
        self.drop_path(i);
        self.planned += 1;
        if dist.get(graph, start, goal) == UNREACHABLE {
            return;
        }
        self.search = self.search.wrapping_add(1);
        if self.search == 0 {
            self.touched.fill(0);
            self.closed.fill(0);
            self.search = 1;
        }
        let s = self.search;
        self.heap.clear();
        self.g[start as usize] = 0;
        self.parent[start as usize] = NONE;
        self.touched[start as usize] = s;
        self.heap.push((
            Reverse(u64::from(dist.get(graph, start, goal))),
            0,
            Reverse(start),
        ));
        while let Some((_, g, Reverse(u))) = self.heap.pop() {
            if self.closed[u as usize] == s || g != self.g[u as usize] {
                continue;
            }
            self.closed[u as usize] = s;
            if u == goal {
                break;
            }
            for d in 0..4 {
                let v = self.next[u as usize][d];
                if v == NONE || self.closed[v as usize] == s {
                    continue;
                }
                let fv = self.flow[v as usize];
                let contra = u64::from(self.flow[u as usize][d] + 1) * u64::from(fv[(d + 2) % 4]);
                let congestion = u64::from(fv.iter().sum::<u32>() / 2);
                let gv = g + 1 + contra + congestion;
                if self.touched[v as usize] != s || gv < self.g[v as usize] {
                    self.touched[v as usize] = s;
                    self.g[v as usize] = gv;
                    self.parent[v as usize] = u;
                    let h = u64::from(dist.get(graph, v, goal));
                    self.heap.push((Reverse(gv + h), gv, Reverse(v)));
                }
            }
        }
        let mut path = vec![goal];
        while let Some(&v) = path.last()
            && v != start
        {
            path.push(self.parent[v as usize]);
        }
        path.reverse();
        for w in path.windows(2) {
            let d = self.dir(w[0], w[1]);
            self.flow[w[0] as usize][d] += 1;
        }
        let guide = &mut self.guides[i];
        for (k, &v) in path.iter().enumerate().rev() {
            guide.reached.insert(v, (0, (path.len() - 1 - k) as u32));
            guide.open.push_back(v);
        }
        guide.path = path;
        guide.planned_at = t;
    }

    /// Total flow on the map's moves (the sum of the guide paths' lengths).
    pub fn total_flow(&self) -> u64 {
        self.flow
            .iter()
            .map(|f| f.iter().map(|&x| u64::from(x)).sum::<u64>())
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::distances::Distances;

    fn open_map(w: usize, h: usize) -> GridMap {
        GridMap::from_free_rows(&vec![vec![true; w]; h])
    }

    #[test]
    fn a_path_is_shortest_without_traffic_and_its_flow_is_its_length() {
        let map = open_map(6, 4);
        let g = map.graph();
        let mut dist = Distances::new(g.num_vertices(), 1 << 20);
        let mut gp = GuidePaths::new(&map, 1, 0);
        let (s, t) = (map.vertex_at(0, 0).unwrap(), map.vertex_at(5, 3).unwrap());
        gp.update(&[s], &[t], 0, &mut dist, g, Deadline::none());
        assert!(gp.follows(0, t));
        assert_eq!(gp.guides[0].path.len(), 9);
        assert_eq!(gp.total_flow(), 8);
        let mut out = Vec::new();
        gp.distances(0, &[s, t], &mut out);
        assert_eq!(out, vec![8, 0]);
        // The distance to the path is at least the distance to the goal, for every cell.
        let all: Vec<VertexId> = (0..g.num_vertices() as VertexId).collect();
        gp.distances(0, &all, &mut out);
        for (&v, &d) in all.iter().zip(&out) {
            assert!(d >= dist.get(g, v, t));
        }
        // Goal reached: the path and its flow are gone.
        gp.update(&[t], &[t], 1, &mut dist, g, Deadline::none());
        assert!(!gp.follows(0, t));
        assert_eq!(gp.total_flow(), 0);
    }

    #[test]
    fn a_path_avoids_oncoming_traffic_when_a_parallel_lane_is_free() {
        // Three rows; robot 0 goes east along the middle row; robot 1 goes west from the same
        // row: its path should leave the middle row rather than meet robot 0's head on.
        let map = open_map(8, 3);
        let g = map.graph();
        let mut dist = Distances::new(g.num_vertices(), 1 << 20);
        let mut gp = GuidePaths::new(&map, 2, 0);
        let v = |x, y| map.vertex_at(x, y).unwrap();
        gp.update(&[v(0, 1)], &[v(7, 1)], 0, &mut dist, g, Deadline::none());
        let cells = [v(0, 1), v(7, 1)];
        let goals = [v(7, 1), v(0, 1)];
        gp.update(&cells, &goals, 0, &mut dist, g, Deadline::none());
        let second = &gp.guides[1].path;
        assert_eq!(second.first(), Some(&v(7, 1)));
        assert_eq!(second.last(), Some(&v(0, 1)));
        let on_middle = second.iter().filter(|&&c| map.cell(c).1 == 1).count();
        assert!(on_middle <= 2, "path {second:?} stays on the busy row");
        assert_eq!(gp.total_flow(), 7 + (second.len() as u64 - 1));
    }

    #[test]
    fn replanning_is_bounded_and_keeps_flow_consistent() {
        let map = open_map(10, 10);
        let g = map.graph();
        let mut dist = Distances::new(g.num_vertices(), 1 << 22);
        let n = 20;
        let mut gp = GuidePaths::new(&map, n, 5);
        let cells: Vec<VertexId> = (0..n as VertexId).collect();
        let goals: Vec<VertexId> = (0..n as VertexId).map(|i| 99 - i).collect();
        gp.update(&cells, &goals, 0, &mut dist, g, Deadline::none());
        assert_eq!(gp.planned, n);
        gp.update(&cells, &goals, 1, &mut dist, g, Deadline::none());
        assert_eq!(gp.planned, n + 5);
        let lengths: u64 = gp.guides.iter().map(|q| q.path.len() as u64 - 1).sum();
        assert_eq!(gp.total_flow(), lengths);
    }
}
