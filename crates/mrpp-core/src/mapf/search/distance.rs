//! Breadth-first distance tables on unit-cost graphs.

use std::collections::VecDeque;

use crate::mapf::graph::{Graph, VertexId};

/// Distance of an unreachable vertex.
pub const UNREACHABLE: u32 = u32::MAX;

/// Hop distance from `source` to every vertex, skipping vertices for which `blocked` is true
/// (the source itself is never skipped).
pub fn bfs_distances_avoiding(
    g: &Graph,
    source: VertexId,
    blocked: impl Fn(VertexId) -> bool,
) -> Vec<u32> {
    let mut dist = vec![UNREACHABLE; g.num_vertices()];
    let mut queue = VecDeque::new();
    dist[source as usize] = 0;
    queue.push_back(source);
    while let Some(u) = queue.pop_front() {
        let d = dist[u as usize] + 1;
        for &v in g.neighbors(u) {
            if dist[v as usize] == UNREACHABLE && !blocked(v) {
                dist[v as usize] = d;
                queue.push_back(v);
            }
        }
    }
    dist
}

/// Hop distance from `source` to every vertex.
pub fn bfs_distances(g: &Graph, source: VertexId) -> Vec<u32> {
    bfs_distances_avoiding(g, source, |_| false)
}

/// One distance table per agent goal: `tables[i][v]` = distance from `v` to goal `i`.
pub fn goal_distance_tables(g: &Graph, goals: &[VertexId]) -> Vec<Vec<u32>> {
    goals.iter().map(|&goal| bfs_distances(g, goal)).collect()
}

/// One BFS distance table per agent goal, grown lazily (as in Okumura's LaCAM code): agent `i`'s
/// breadth-first search from its goal runs only as far as the queries need and resumes where it
/// stopped, so an agent that never looks far never pays for the whole map. A table stores 2 bytes
/// per vertex (4 once a distance reaches 65 535, which needs a path that long), allocated at its
/// first query; the BFS queue holds only the frontier and is freed when the search is done.
/// [`GoalDistances::warm_up`] grows every table up to a given vertex in parallel (rayon); the
/// values never depend on the order or the thread count of queries.
///
/// Memory: agents × vertices × 2 bytes once a table is touched (e.g. 10 000 agents on the 38 756
/// free cells of MovingAI's warehouse-20-40-10-2-2: 775 MB). A table is allocated whole at its
/// first query; on open maps the search grows over most of the map before it reaches an agent
/// far from its goal, so lazier storage would save little.
pub struct GoalDistances<'g> {
    graph: &'g Graph,
    goals: Vec<VertexId>,
    tables: Vec<std::sync::Mutex<LazyBfs>>,
    /// Every table, complete, when [`GoalDistances::warm_up`] found them small enough to finish
    /// (read without locking).
    complete: Option<Vec<Store>>,
}

/// [`GoalDistances::warm_up`] completes every table when agents × vertices is at most this.
const COMPLETE_ENTRIES: usize = 1 << 26;

/// A table's storage: 2 or 4 bytes per vertex.
enum Store {
    Unallocated,
    Narrow(Vec<u16>),
    Wide(Vec<u32>),
}

impl Store {
    fn get(&self, v: usize) -> u32 {
        match self {
            Store::Unallocated => UNREACHABLE,
            Store::Narrow(d) => match d[v] {
                u16::MAX => UNREACHABLE,
                x => u32::from(x),
            },
            Store::Wide(d) => d[v],
        }
    }
    fn set(&mut self, v: usize, x: u32) {
        match self {
            Store::Unallocated => unreachable!("set after allocation"),
            Store::Narrow(d) if x < u32::from(u16::MAX) => d[v] = x as u16,
            Store::Narrow(d) => {
                // A distance of 65 535 or more: this table needs 4 bytes per vertex after all.
                let mut wide: Vec<u32> = d
                    .iter()
                    .map(|&y| {
                        if y == u16::MAX {
                            UNREACHABLE
                        } else {
                            u32::from(y)
                        }
                    })
                    .collect();
                wide[v] = x;
                *self = Store::Wide(wide);
            }
            Store::Wide(d) => d[v] = x,
        }
    }
}

/// One agent's resumable BFS.
struct LazyBfs {
    dist: Store,
    queue: VecDeque<VertexId>,
}

impl LazyBfs {
    /// Expands the next vertex of the queue; false when the search is done.
    fn step(&mut self, g: &Graph) -> bool {
        let Some(u) = self.queue.pop_front() else {
            self.queue = VecDeque::new();
            return false;
        };
        let d = self.dist.get(u as usize) + 1;
        for &w in g.neighbors(u) {
            if self.dist.get(w as usize) == UNREACHABLE {
                self.dist.set(w as usize, d);
                self.queue.push_back(w);
            }
        }
        true
    }

    /// Runs the (started) search to the end of the goal's component.
    fn finish(&mut self, g: &Graph) {
        while self.step(g) {}
    }

    /// Distance from `v` to the table's goal, growing the search until `v` is reached or the
    /// component is exhausted.
    fn get(&mut self, g: &Graph, goal: VertexId, v: VertexId) -> u32 {
        if matches!(self.dist, Store::Unallocated) {
            self.dist = Store::Narrow(vec![u16::MAX; g.num_vertices()]);
            self.dist.set(goal as usize, 0);
            self.queue.push_back(goal);
        }
        let known = self.dist.get(v as usize);
        if known != UNREACHABLE {
            return known;
        }
        while self.step(g) {
            if self.dist.get(v as usize) != UNREACHABLE {
                return self.dist.get(v as usize);
            }
        }
        UNREACHABLE
    }
}

impl<'g> GoalDistances<'g> {
    /// Empty tables for `goals` on `graph` (nothing is searched yet).
    pub fn new(graph: &'g Graph, goals: &[VertexId]) -> Self {
        GoalDistances {
            graph,
            goals: goals.to_vec(),
            tables: goals
                .iter()
                .map(|_| {
                    std::sync::Mutex::new(LazyBfs {
                        dist: Store::Unallocated,
                        queue: VecDeque::new(),
                    })
                })
                .collect(),
            complete: None,
        }
    }

    /// Hop distance from `v` to agent `i`'s goal ([`UNREACHABLE`] when there is no route).
    #[inline]
    pub fn get(&self, i: usize, v: VertexId) -> u32 {
        if let Some(done) = &self.complete {
            return done[i].get(v as usize);
        }
        self.tables[i]
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .get(self.graph, self.goals[i], v)
    }

    /// Grows every agent's table until it reaches `at[i]` (typically the starts), in parallel.
    /// When agents × vertices is at most 2^26, every table is completed instead, and later
    /// queries read them without locking.
    pub fn warm_up(&mut self, at: &[VertexId]) {
        use rayon::prelude::*;
        let (g, goals) = (self.graph, &self.goals);
        let finish = at.len() == goals.len()
            && goals.len().saturating_mul(g.num_vertices()) <= COMPLETE_ENTRIES;
        self.tables
            .par_iter_mut()
            .zip(at.par_iter())
            .enumerate()
            .for_each(|(i, (t, &v))| {
                let t = t
                    .get_mut()
                    .unwrap_or_else(std::sync::PoisonError::into_inner);
                t.get(g, goals[i], v);
                if finish {
                    t.finish(g);
                }
            });
        if finish {
            self.complete = Some(
                self.tables
                    .iter_mut()
                    .map(|t| {
                        let t = t
                            .get_mut()
                            .unwrap_or_else(std::sync::PoisonError::into_inner);
                        std::mem::replace(&mut t.dist, Store::Unallocated)
                    })
                    .collect(),
            );
        }
    }

    /// Number of agents (tables).
    pub fn len(&self) -> usize {
        self.tables.len()
    }

    /// Whether there are no tables.
    pub fn is_empty(&self) -> bool {
        self.tables.is_empty()
    }
}

/// A shortest route from `from` down a distance table to its source (ties: neighbour order).
/// Empty when `from` cannot reach it.
pub fn descend(g: &Graph, dist: &[u32], from: VertexId) -> Vec<VertexId> {
    if dist[from as usize] == UNREACHABLE {
        return Vec::new();
    }
    let mut route = vec![from];
    let mut v = from;
    while dist[v as usize] > 0 {
        v = *g
            .neighbors(v)
            .iter()
            .find(|&&w| dist[w as usize] + 1 == dist[v as usize])
            .expect("a BFS table always has a predecessor");
        route.push(v);
    }
    route
}

/// Distance of an unreachable vertex in [`dijkstra_distances`].
pub const UNREACHED: u64 = u64::MAX;

/// Dijkstra from `source` where stepping onto `v` costs `enter(v)` (> 0). Used where some cells
/// should be avoided without being forbidden (e.g. other robots' goals).
pub fn dijkstra_distances(
    g: &Graph,
    source: VertexId,
    enter: &dyn Fn(VertexId) -> u64,
) -> Vec<u64> {
    use std::cmp::Reverse;
    let mut dist = vec![UNREACHED; g.num_vertices()];
    let mut heap = std::collections::BinaryHeap::new();
    dist[source as usize] = 0;
    heap.push(Reverse((0u64, source)));
    while let Some(Reverse((d, u))) = heap.pop() {
        if d > dist[u as usize] {
            continue;
        }
        for &v in g.neighbors(u) {
            let nd = d + enter(v);
            if nd < dist[v as usize] {
                dist[v as usize] = nd;
                heap.push(Reverse((nd, v)));
            }
        }
    }
    dist
}

/// A least-cost route from `from` down a [`dijkstra_distances`] table (built with the same
/// `enter`) to its source; ties: neighbour order. Empty when `from` cannot reach it. Because the
/// table holds costs of routes *from* the source, a step from `v` to `w` is on a least-cost route
/// when `table[w] + enter(v) == table[v]`.
pub fn descend_weighted(
    g: &Graph,
    table: &[u64],
    from: VertexId,
    enter: &dyn Fn(VertexId) -> u64,
) -> Vec<VertexId> {
    if table[from as usize] == UNREACHED {
        return Vec::new();
    }
    let mut route = vec![from];
    let mut v = from;
    while table[v as usize] > 0 {
        let step = enter(v);
        v = *g
            .neighbors(v)
            .iter()
            .find(|&&w| {
                table[w as usize] != UNREACHED && table[w as usize] + step == table[v as usize]
            })
            .expect("a Dijkstra table always has a predecessor");
        route.push(v);
    }
    route
}

/// Lower bounds that any valid plan meets: the sum and the maximum over agents of the start–goal
/// distance (each agent alone on the map). `Err(i)` when agent `i` cannot reach its goal.
pub fn lower_bounds(
    g: &Graph,
    starts: &[VertexId],
    goals: &[VertexId],
) -> Result<(u64, u64), usize> {
    let mut sum = 0u64;
    let mut max = 0u64;
    for (i, (&s, &goal)) in starts.iter().zip(goals).enumerate() {
        let d = bfs_distances(g, goal)[s as usize];
        if d == UNREACHABLE {
            return Err(i);
        }
        sum += u64::from(d);
        max = max.max(u64::from(d));
    }
    Ok((sum, max))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lazy_tables_equal_full_bfs_in_any_query_order() {
        // A 5x4 grid with a wall segment, goals spread out; queries in two different orders.
        let id = |x: u32, y: u32| y * 5 + x;
        let mut edges = Vec::new();
        for y in 0..4 {
            for x in 0..5 {
                if x + 1 < 5 && !(x == 2 && y < 3) {
                    edges.push((id(x, y), id(x + 1, y)));
                }
                if y + 1 < 4 {
                    edges.push((id(x, y), id(x, y + 1)));
                }
            }
        }
        let g = Graph::from_edges(21, &edges); // vertex 20 is isolated
        let goals = [0, 19, 7];
        let full = goal_distance_tables(&g, &goals);
        let lazy = GoalDistances::new(&g, &goals);
        let mut warmed = GoalDistances::new(&g, &goals);
        warmed.warm_up(&[19, 0, 20]);
        for (i, table) in full.iter().enumerate() {
            for v in (0..21).rev() {
                assert_eq!(lazy.get(i, v), table[v as usize], "agent {i} vertex {v}");
            }
            for v in 0..21 {
                assert_eq!(warmed.get(i, v), table[v as usize], "agent {i} vertex {v}");
            }
        }
    }

    #[test]
    fn a_table_widens_when_a_distance_reaches_65535() {
        let n = 70_000usize;
        let edges: Vec<(VertexId, VertexId)> = (0..n as VertexId - 1).map(|v| (v, v + 1)).collect();
        let g = Graph::from_edges(n, &edges);
        let t = GoalDistances::new(&g, &[0]);
        assert_eq!(t.get(0, 10), 10);
        assert_eq!(t.get(0, 69_999), 69_999);
        assert_eq!(t.get(0, 65_535), 65_535);
        assert_eq!(t.get(0, 3), 3);
    }

    #[test]
    fn path_graph_distances() {
        let g = Graph::from_edges(4, &[(0, 1), (1, 2)]);
        assert_eq!(bfs_distances(&g, 0), vec![0, 1, 2, UNREACHABLE]);
        assert_eq!(
            bfs_distances_avoiding(&g, 0, |v| v == 1),
            vec![0, UNREACHABLE, UNREACHABLE, UNREACHABLE]
        );
    }
}
