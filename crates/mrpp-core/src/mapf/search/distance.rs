//! Breadth-first distance tables on unit-cost graphs.

use std::collections::VecDeque;

use crate::contract::Deadline;
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
/// stopped, so an agent that never looks far never pays for the whole map. The BFS queue holds
/// only the frontier and is freed when the search is done. [`GoalDistances::warm_up`] grows every
/// table up to a given vertex in parallel (rayon); the values never depend on the order or the
/// thread count of queries.
///
/// Storage, allocated whole at a table's first query (on open maps the search grows over most of
/// the map before it reaches an agent far from its goal, so lazier storage would save little):
/// - 2 bytes per vertex (4 once a distance reaches 65 535), while agents × vertices is at most
///   [`PACK_ENTRIES`] (e.g. 10 000 agents on the 38 756 free cells of MovingAI's
///   warehouse-20-40-10-2-2: 775 MB);
/// - beyond, **2 bits per vertex** (10 000 agents on a 500 x 500 map: 625 MB instead of 5 GB):
///   each vertex keeps its distance modulo 3 (0 = not reached yet). Adjacent vertices' distances
///   differ by at most 1, so the code of a neighbour tells its distance from a known one; a table
///   remembers its last answer (its *anchor*) and finds a new vertex's distance through a short
///   walk to the anchor (within 3 steps), or else by walking down the codes to the goal, one
///   step per unit of distance. PIBT and LaCAM query the neighbourhood of an agent's last
///   position, so most answers are a few steps from the anchor; a search that jumps around (the
///   SIPP of LaCAM*'s refinement) pays the walk to the goal on most queries, so anytime
///   refinement on instances this large is slow.
pub struct GoalDistances<'g> {
    graph: &'g Graph,
    goals: Vec<VertexId>,
    tables: Vec<std::sync::Mutex<LazyBfs>>,
    /// Every table, when [`GoalDistances::warm_up`] found them small enough to finish, or
    /// [`GoalDistances::warm_up_near`] grew them around the starts (read without locking).
    complete: Option<Vec<Store>>,
    /// Per table of `complete`: whether it holds its goal's whole component (else a vertex it has
    /// not reached is looked up in `tables`, which resumes the search).
    whole: Vec<bool>,
    packed: bool,
}

/// [`GoalDistances::warm_up`] completes every table when agents × vertices is at most this.
/// [`GoalDistances::warm_up_near`] keeps its tables for lock-free reads up to [`PACK_ENTRIES`]
/// instead: it grows each only near its start, and a lookup through the table's lock costs more
/// than the rest of PIBT together once the tables outgrow the caches. 10,000 agents on MovingAI's
/// warehouse-20-40-10-2-1 (22,599 free cells, 2.3 × 10^8 entries; the scenario from `mrpp gen
/// scen --map warehouse-20-40-10-2-1.map --agents 10000 --seed 0 --out w.scen`), `mrpp solve -m
/// warehouse-20-40-10-2-1.map -i w.scen -N 10000 -P lacam -s S -t 60` side by side, same plans:
/// first plan 19.8 → 12.2 s (seed 6) and 47.1 → 27.7 s (seed 1), peak memory (max RSS) 0.97 →
/// 1.11 GB and 1.44 → 1.53 GB (tables copied on far queries).
const COMPLETE_ENTRIES: usize = 1 << 26;

/// [`GoalDistances::warm_up`] runs on the calling thread when agents × vertices is at most this
/// (about 0.6 ms of breadth-first search here): below, starting rayon's thread pool in a fresh
/// process costs more than the searches it would share. Measured on the H* paper's Scenario 2,
/// 4 robots per room (16 agents, ~1,000 cells): 0.15 ms on one thread, 0.4 ms with the pool.
const SEQUENTIAL_WARM_UP: usize = 1 << 16;

/// Tables store 2 bits per vertex instead of 2 bytes when agents × vertices exceeds this (2 bytes
/// each would then take more than 1 GiB).
pub const PACK_ENTRIES: usize = 1 << 29;

/// A table's storage: 2 or 4 bytes per vertex, or 2 bits (the distance modulo 3, plus 1; 0 = not
/// reached).
enum Store {
    Unallocated,
    Narrow(Vec<u16>),
    Wide(Vec<u32>),
    Packed(Vec<u8>),
}

impl Store {
    /// The distance of `v` (not for `Packed`, which knows distances only modulo 3).
    #[inline]
    fn get(&self, v: usize) -> u32 {
        match self {
            Store::Unallocated | Store::Packed(_) => UNREACHABLE,
            Store::Narrow(d) => match d[v] {
                u16::MAX => UNREACHABLE,
                x => u32::from(x),
            },
            Store::Wide(d) => d[v],
        }
    }
    /// `Packed`: 1 + the distance of `v` modulo 3, or 0 when `v` is not reached yet.
    #[inline]
    fn code(bits: &[u8], v: usize) -> u8 {
        (bits[v >> 2] >> ((v & 3) * 2)) & 3
    }
    fn seen(&self, v: usize) -> bool {
        match self {
            Store::Packed(b) => Store::code(b, v) != 0,
            _ => self.get(v) != UNREACHABLE,
        }
    }
    fn set(&mut self, v: usize, x: u32) {
        match self {
            Store::Unallocated => unreachable!("set after allocation"),
            Store::Packed(b) => {
                let shift = (v & 3) * 2;
                b[v >> 2] = (b[v >> 2] & !(3 << shift)) | (((x % 3) as u8 + 1) << shift);
            }
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
    /// The frontier: first the rest of the layer at distance `front_d` (`front_left` vertices),
    /// then the next layer.
    queue: VecDeque<VertexId>,
    front_d: u32,
    front_left: usize,
    /// Packed tables: the last vertex answered and its distance.
    anchor: (VertexId, u32),
}

impl LazyBfs {
    /// Expands the next vertex of the queue; false when the search is done.
    fn step(&mut self, g: &Graph) -> bool {
        let Some(u) = self.queue.pop_front() else {
            self.queue = VecDeque::new();
            return false;
        };
        let du = self.front_d;
        match &mut self.dist {
            // The hot loop of huge instances, without a storage match per neighbour.
            Store::Packed(bits) => {
                let code = (du + 1) % 3 + 1;
                for &w in g.neighbors(u) {
                    let (byte, shift) = (w as usize >> 2, (w as usize & 3) * 2);
                    if (bits[byte] >> shift) & 3 == 0 {
                        bits[byte] |= (code as u8) << shift;
                        self.queue.push_back(w);
                    }
                }
            }
            Store::Narrow(d) if du + 1 < u32::from(u16::MAX) => {
                for &w in g.neighbors(u) {
                    if d[w as usize] == u16::MAX {
                        d[w as usize] = (du + 1) as u16;
                        self.queue.push_back(w);
                    }
                }
            }
            dist => {
                for &w in g.neighbors(u) {
                    if !dist.seen(w as usize) {
                        dist.set(w as usize, du + 1);
                        self.queue.push_back(w);
                    }
                }
            }
        }
        self.front_left -= 1;
        if self.front_left == 0 {
            self.front_d += 1;
            self.front_left = self.queue.len();
            // A frontier that shrank gives back its memory (10 000 queues add up).
            if self.queue.capacity() > 256 && self.queue.len() < self.queue.capacity() / 4 {
                self.queue.shrink_to(self.queue.capacity() / 2);
            }
        }
        true
    }

    /// Allocates the table and starts the search from `goal`, unless it is started already.
    fn start(&mut self, g: &Graph, goal: VertexId, packed: bool) {
        if matches!(self.dist, Store::Unallocated) {
            let n = g.num_vertices();
            self.dist = if packed {
                Store::Packed(vec![0; n.div_ceil(4)])
            } else {
                Store::Narrow(vec![u16::MAX; n])
            };
            self.dist.set(goal as usize, 0);
            self.queue.push_back(goal);
            (self.front_d, self.front_left) = (0, 1);
            self.anchor = (goal, 0);
        }
    }

    /// Runs the (started) search to the end of the goal's component, or with `near = Some((v,
    /// margin))` until every vertex within `margin` steps beyond `v`'s distance has its distance
    /// (the search stops before expanding a vertex farther than `d(v) + margin`; the rest of the
    /// frontier stays queued, so [`LazyBfs::step`] resumes from there). The component is
    /// exhausted when the queue is left empty.
    ///
    /// A 2-byte table runs a plain array-queue BFS instead of [`LazyBfs::step`]'s layer
    /// bookkeeping: each vertex's distance is its parent's plus one, read from the table. This is
    /// what every warm-up runs (most of LaCAM's first-plan time on the MovingAI maps of
    /// 256 x 256 cells). Should a distance reach 65 535 (graphs that large and that long), the
    /// rest goes back to [`LazyBfs::step`], which widens the table.
    fn expand(&mut self, g: &Graph, near: Option<(VertexId, u32)>) {
        if let Store::Narrow(d) = &mut self.dist {
            let mut queue: Vec<VertexId> = Vec::with_capacity(g.num_vertices());
            queue.extend(self.queue.drain(..));
            let mut head = 0;
            let mut limit = u32::MAX;
            while let Some(&u) = queue.get(head) {
                if limit == u32::MAX
                    && let Some((v, margin)) = near
                    && d[v as usize] != u16::MAX
                {
                    limit = u32::from(d[v as usize]).saturating_add(margin);
                }
                let du = d[u as usize] + 1;
                if du == u16::MAX || u32::from(d[u as usize]) > limit {
                    // Back to the layered search from `u` on; the queue is in distance order.
                    let rest = &queue[head..];
                    self.front_d = u32::from(d[u as usize]);
                    self.front_left = rest
                        .iter()
                        .filter(|&&v| d[v as usize] == d[u as usize])
                        .count();
                    self.queue = rest.iter().copied().collect();
                    break;
                }
                head += 1;
                for &w in g.neighbors(u) {
                    let dw = &mut d[w as usize];
                    if *dw == u16::MAX {
                        *dw = du;
                        queue.push(w);
                    }
                }
            }
            if head == queue.len() {
                self.queue = VecDeque::new();
                self.front_left = 0;
                return;
            }
            if near.is_some() && limit != u32::MAX {
                return;
            }
        }
        while self.step(g) {}
    }

    /// Distance from `v` to the table's goal, growing the search until `v` is reached or the
    /// component is exhausted.
    fn get(&mut self, g: &Graph, goal: VertexId, v: VertexId, packed: bool) -> u32 {
        self.start(g, goal, packed);
        // The common case: a 2-byte table that has reached `v`.
        if let Store::Narrow(d) = &self.dist
            && d[v as usize] != u16::MAX
        {
            return u32::from(d[v as usize]);
        }
        while !self.dist.seen(v as usize) {
            if !self.step(g) {
                return UNREACHABLE;
            }
        }
        match &self.dist {
            Store::Packed(bits) => {
                let d = resolve(g, bits, goal, self.anchor, v);
                self.anchor = (v, d);
                d
            }
            other => other.get(v as usize),
        }
    }
}

/// The distance of the reached vertex `v` in a packed table, from the anchor `(a, da)` when a
/// walk of at most 3 steps over reached vertices joins them, else by walking down to `goal`.
fn resolve(g: &Graph, bits: &[u8], goal: VertexId, (a, da): (VertexId, u32), v: VertexId) -> u32 {
    let code = |x: VertexId| Store::code(bits, x as usize);
    // d(y) - d(x) for adjacent reached x, y: their codes differ by 0, +1 or -1 modulo 3.
    let delta = |x: VertexId, y: VertexId| match (code(y) + 3 - code(x)) % 3 {
        0 => 0i64,
        1 => 1,
        _ => -1,
    };
    if v == a {
        return da;
    }
    // Breadth-first over reached vertices around `v`, carrying d(x) - d(v).
    let mut layer: Vec<(VertexId, i64)> = vec![(v, 0)];
    let mut visited: Vec<VertexId> = vec![v];
    for _ in 0..3 {
        let mut next = Vec::new();
        for &(x, off) in &layer {
            for &y in g.neighbors(x) {
                if code(y) == 0 || visited.contains(&y) {
                    continue;
                }
                let oy = off + delta(x, y);
                if y == a {
                    return (i64::from(da) - oy) as u32;
                }
                visited.push(y);
                next.push((y, oy));
            }
        }
        layer = next;
    }
    // Down the codes to the goal: some neighbour is one closer (a BFS predecessor).
    let (mut x, mut d) = (v, 0u32);
    while x != goal {
        x = *g
            .neighbors(x)
            .iter()
            .find(|&&y| code(y) != 0 && delta(x, y) == -1)
            .expect("a reached vertex has a reached predecessor");
        d += 1;
    }
    d
}

impl<'g> GoalDistances<'g> {
    /// Empty tables for `goals` on `graph` (nothing is searched yet); packed (2 bits per vertex)
    /// when agents × vertices exceeds [`PACK_ENTRIES`].
    pub fn new(graph: &'g Graph, goals: &[VertexId]) -> Self {
        let packed = goals.len().saturating_mul(graph.num_vertices()) > PACK_ENTRIES;
        Self::with_packing(graph, goals, packed)
    }

    /// Empty tables for `goals` on `graph`, packed or not as asked (the distances are the same;
    /// packed tables take 2 bits per vertex instead of 2 bytes, and answer far jumps slower).
    pub fn with_packing(graph: &'g Graph, goals: &[VertexId], packed: bool) -> Self {
        GoalDistances {
            graph,
            goals: goals.to_vec(),
            tables: goals
                .iter()
                .map(|_| {
                    std::sync::Mutex::new(LazyBfs {
                        dist: Store::Unallocated,
                        queue: VecDeque::new(),
                        front_d: 0,
                        front_left: 0,
                        anchor: (0, 0),
                    })
                })
                .collect(),
            complete: None,
            whole: Vec::new(),
            packed,
        }
    }

    /// Whether the tables store 2 bits per vertex.
    pub fn is_packed(&self) -> bool {
        self.packed
    }

    /// Agent `i`'s whole table as 2 bytes per vertex (`u16::MAX` = no route), when
    /// [`GoalDistances::warm_up`] completed it in that form (`None` otherwise: use
    /// [`GoalDistances::get`]). Searches that ask for many distances read it directly.
    pub fn narrow(&self, i: usize) -> Option<&[u16]> {
        match self.complete.as_ref().map(|done| &done[i]) {
            Some(Store::Narrow(d)) if self.whole[i] => Some(d),
            _ => None,
        }
    }

    /// Hop distance from `v` to agent `i`'s goal ([`UNREACHABLE`] when there is no route).
    #[inline]
    pub fn get(&self, i: usize, v: VertexId) -> u32 {
        if let Some(done) = &self.complete {
            let d = done[i].get(v as usize);
            if d != UNREACHABLE || self.whole[i] {
                return d;
            }
            return self.get_beyond(i, v);
        }
        self.get_lazy(i, v)
    }

    /// [`GoalDistances::get`] of a vertex that a table grown by [`GoalDistances::warm_up_near`]
    /// has not reached: the search resumes from its frontier on a copy of the table (made at the
    /// first such query), locked.
    #[inline(never)]
    fn get_beyond(&self, i: usize, v: VertexId) -> u32 {
        let mut t = self.tables[i]
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if matches!(t.dist, Store::Unallocated) {
            if t.queue.is_empty() {
                return UNREACHABLE;
            }
            t.dist = match &self.complete.as_ref().expect("called with tables")[i] {
                Store::Narrow(d) => Store::Narrow(d.clone()),
                Store::Wide(d) => Store::Wide(d.clone()),
                Store::Packed(_) | Store::Unallocated => {
                    unreachable!("warm_up_near keeps 2 or 4 bytes")
                }
            };
        }
        t.get(self.graph, self.goals[i], v, self.packed)
    }

    /// [`GoalDistances::get`] on a table that may still grow (locked).
    #[inline(never)]
    fn get_lazy(&self, i: usize, v: VertexId) -> u32 {
        self.tables[i]
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .get(self.graph, self.goals[i], v, self.packed)
    }

    /// Grows every agent's table until it reaches `at[i]` (typically the starts), in parallel
    /// when agents × vertices is above [`SEQUENTIAL_WARM_UP`].
    /// When the tables are not packed and agents × vertices is at most 2^26, every table is
    /// completed instead, and later
    /// queries read them without locking.
    ///
    /// Returns `false` when `deadline` passed first: the deadline is checked before each table
    /// (one table costs at most one breadth-first search of the graph), so thousands of agents
    /// on a large map stop within one search of the limit; the tables stay usable (lazy).
    pub fn warm_up(&mut self, at: &[VertexId], deadline: Deadline) -> bool {
        self.warm_up_within(at, None, deadline)
    }

    /// [`GoalDistances::warm_up`] that, unless the tables are packed (at any size below
    /// [`PACK_ENTRIES`], not only below `warm_up`'s limit), grows each only until it knows every
    /// vertex within `margin` steps beyond `at[i]`'s distance: about half the breadth-first
    /// search for a start and goal drawn at random (a vertex is nearer the goal than the start
    /// for half of the pairs), for searches that mostly look near their agents' shortest paths
    /// (LaCAM's first plan). Those distances are then read without locking. Queries beyond resume
    /// the search on a copy of the table, locked (each table is copied once, at its first such
    /// query, so the tables take up to twice their size). The distances are the same.
    pub fn warm_up_near(&mut self, at: &[VertexId], margin: u32, deadline: Deadline) -> bool {
        self.warm_up_within(at, Some(margin), deadline)
    }

    fn warm_up_within(&mut self, at: &[VertexId], margin: Option<u32>, deadline: Deadline) -> bool {
        use rayon::prelude::*;
        let (g, goals, packed) = (self.graph, &self.goals, self.packed);
        // Packed tables are never finished (their reads walk the codes anyway); tables grown
        // near the starts are kept for lock-free reads at any size below that.
        let finish = !packed
            && at.len() == goals.len()
            && (margin.is_some()
                || goals.len().saturating_mul(g.num_vertices()) <= COMPLETE_ENTRIES);
        let work = |(i, (t, &v)): (usize, (&mut std::sync::Mutex<LazyBfs>, &VertexId))| {
            if deadline.expired() {
                return;
            }
            let t = t
                .get_mut()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            if finish {
                t.start(g, goals[i], packed);
                t.expand(g, margin.map(|m| (v, m)));
            } else {
                t.get(g, goals[i], v, packed);
            }
        };
        if goals.len().saturating_mul(g.num_vertices()) <= SEQUENTIAL_WARM_UP {
            self.tables.iter_mut().zip(at).enumerate().for_each(work);
        } else {
            self.tables
                .par_iter_mut()
                .zip(at.par_iter())
                .enumerate()
                .for_each(work);
        }
        if deadline.expired() {
            return false;
        }
        if finish {
            // A table whose search left nothing queued holds its whole component.
            self.whole = self
                .tables
                .iter_mut()
                .map(|t| {
                    t.get_mut()
                        .unwrap_or_else(std::sync::PoisonError::into_inner)
                        .queue
                        .is_empty()
                })
                .collect();
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
        true
    }

    /// A shortest route from `from` to agent `i`'s goal (empty when unreachable): [`descend`] on
    /// this agent's table.
    pub fn descend(&self, i: usize, from: VertexId) -> Vec<VertexId> {
        let mut d = self.get(i, from);
        if d == UNREACHABLE {
            return Vec::new();
        }
        let mut route = vec![from];
        let mut v = from;
        while d > 0 {
            v = *self
                .graph
                .neighbors(v)
                .iter()
                .find(|&&w| self.get(i, w).wrapping_add(1) == d)
                .expect("a BFS table always has a predecessor");
            d -= 1;
            route.push(v);
        }
        route
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
    dijkstra_distances_until(g, source, enter, Deadline::none())
        .expect("no deadline, so the search ends")
}

/// [`dijkstra_distances`] that gives up (`None`) once `deadline` has passed (polled every 4096
/// settled vertices), so planners that run one per agent on large maps keep their time limit.
pub fn dijkstra_distances_until(
    g: &Graph,
    source: VertexId,
    enter: &dyn Fn(VertexId) -> u64,
    deadline: Deadline,
) -> Option<Vec<u64>> {
    use std::cmp::Reverse;
    let mut dist = vec![UNREACHED; g.num_vertices()];
    let mut heap = std::collections::BinaryHeap::new();
    dist[source as usize] = 0;
    heap.push(Reverse((0u64, source)));
    let mut settled = 0u32;
    while let Some(Reverse((d, u))) = heap.pop() {
        if d > dist[u as usize] {
            continue;
        }
        settled = settled.wrapping_add(1);
        if settled.is_multiple_of(4096) && deadline.expired() {
            return None;
        }
        for &v in g.neighbors(u) {
            let nd = d + enter(v);
            if nd < dist[v as usize] {
                dist[v as usize] = nd;
                heap.push(Reverse((nd, v)));
            }
        }
    }
    Some(dist)
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

/// The hop distance from `from` to `to`, or `None` when `to` cannot be reached: an A* search
/// (the `pathfinding` crate's) with the Manhattan distance of the vertices' cells as its
/// heuristic, admissible on 4-connected grid graphs (0 on graphs without coordinates, where it
/// is a breadth-first search). On a 1000 x 1000 map a query explores a narrow band around a
/// shortest path instead of the whole map.
pub fn shortest_distance(g: &Graph, from: VertexId, to: VertexId) -> Option<u32> {
    pathfinding::directed::astar::astar(
        &from,
        |&v| g.neighbors(v).iter().map(|&w| (w, 1u32)),
        |&v| g.manhattan(v, to),
        |&v| v == to,
    )
    .map(|(_, d)| d)
}

/// Lower bounds that any valid plan meets: the sum and the maximum over agents of the start–goal
/// distance (each agent alone on the map; [`shortest_distance`]). `Err(i)` when agent `i` cannot
/// reach its goal.
pub fn lower_bounds(
    g: &Graph,
    starts: &[VertexId],
    goals: &[VertexId],
) -> Result<(u64, u64), usize> {
    let mut sum = 0u64;
    let mut max = 0u64;
    for (i, (&s, &goal)) in starts.iter().zip(goals).enumerate() {
        let Some(d) = shortest_distance(g, s, goal) else {
            return Err(i);
        };
        sum += u64::from(d);
        max = max.max(u64::from(d));
    }
    Ok((sum, max))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shortest_distance_is_the_breadth_first_one() {
        // 12 x 9 grids with pseudo-random walls (some vertices cut off), every vertex pair.
        for seed in 0..4u32 {
            let (w, h) = (12u32, 9u32);
            let free = |x: u32, y: u32| !(x * 7 + y * 13 + seed * 5).is_multiple_of(9);
            let mut id = vec![None; (w * h) as usize];
            let mut coords = Vec::new();
            for y in 0..h {
                for x in 0..w {
                    if free(x, y) {
                        id[(y * w + x) as usize] = Some(coords.len() as VertexId);
                        coords.push((x, y));
                    }
                }
            }
            let adj: Vec<Vec<VertexId>> = coords
                .iter()
                .map(|&(x, y)| {
                    [(1i64, 0i64), (-1, 0), (0, 1), (0, -1)]
                        .iter()
                        .filter_map(|&(dx, dy)| {
                            let (nx, ny) = (i64::from(x) + dx, i64::from(y) + dy);
                            (nx >= 0 && ny >= 0 && nx < i64::from(w) && ny < i64::from(h))
                                .then(|| id[(ny as u32 * w + nx as u32) as usize])
                                .flatten()
                        })
                        .collect()
                })
                .collect();
            let g = Graph::from_adjacency(&adj, Some(coords));
            for t in 0..g.num_vertices() as VertexId {
                let table = bfs_distances(&g, t);
                for s in 0..g.num_vertices() as VertexId {
                    let want = Some(table[s as usize]).filter(|&d| d != UNREACHABLE);
                    assert_eq!(shortest_distance(&g, s, t), want, "seed {seed}: {s} -> {t}");
                }
            }
        }
    }

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
        assert!(warmed.warm_up(&[19, 0, 20], Deadline::none()));
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
    fn packed_tables_equal_full_bfs_near_and_far_in_any_order() {
        // A 12x9 grid with walls, so distances are not Manhattan; queries jump around (far from
        // the anchor) and step to neighbours (near it).
        let (w, h) = (12u32, 9u32);
        let id = |x: u32, y: u32| y * w + x;
        let wall = |x: u32, y: u32| (x == 4 && y < 7) || (x == 8 && y > 1);
        let mut edges = Vec::new();
        for y in 0..h {
            for x in 0..w {
                if wall(x, y) {
                    continue;
                }
                if x + 1 < w && !wall(x + 1, y) {
                    edges.push((id(x, y), id(x + 1, y)));
                }
                if y + 1 < h && !wall(x, y + 1) {
                    edges.push((id(x, y), id(x, y + 1)));
                }
            }
        }
        let n = (w * h) as usize;
        let g = Graph::from_edges(n, &edges);
        let goals = [id(0, 0), id(11, 8), id(5, 4), id(4, 0)]; // the last is a wall: isolated
        let full = goal_distance_tables(&g, &goals);
        let packed = GoalDistances::with_packing(&g, &goals, true);
        assert!(packed.is_packed() && !GoalDistances::new(&g, &goals).is_packed());
        let mut x = 12345u64;
        for _ in 0..4000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let i = (x % goals.len() as u64) as usize;
            let v = ((x >> 8) % n as u64) as VertexId;
            assert_eq!(
                packed.get(i, v),
                full[i][v as usize],
                "agent {i} vertex {v}"
            );
            for &u in g.neighbors(v) {
                assert_eq!(
                    packed.get(i, u),
                    full[i][u as usize],
                    "agent {i} vertex {u}"
                );
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
    fn tables_grown_near_the_starts_answer_everywhere() {
        // The grid of lazy_tables_equal_full_bfs_in_any_query_order, bigger (9 x 7, a wall with a
        // gap), goals and starts spread out, an isolated vertex; queries near and far, in order
        // and in reverse, and from two threads.
        let (w, h) = (9u32, 7u32);
        let id = |x: u32, y: u32| y * w + x;
        let mut edges = Vec::new();
        for y in 0..h {
            for x in 0..w {
                if x + 1 < w && !(x == 4 && y > 0) {
                    edges.push((id(x, y), id(x + 1, y)));
                }
                if y + 1 < h {
                    edges.push((id(x, y), id(x, y + 1)));
                }
            }
        }
        let n = (w * h) as usize + 1; // the last vertex is isolated
        let g = Graph::from_edges(n, &edges);
        let goals = [0, id(8, 6), id(3, 3), n as VertexId - 1];
        let starts = [1, id(0, 6), id(3, 3), n as VertexId - 1];
        let full = goal_distance_tables(&g, &goals);
        for margin in [0, 2, 100] {
            let mut t = GoalDistances::new(&g, &goals);
            assert!(t.warm_up_near(&starts, margin, Deadline::none()));
            // Only tables that reached their whole component are lent out whole.
            assert_eq!(t.narrow(0).is_some(), margin == 100, "margin {margin}");
            assert!(t.narrow(3).is_some());
            std::thread::scope(|sc| {
                for rev in [false, true] {
                    let (t, full) = (&t, &full);
                    sc.spawn(move || {
                        for (i, table) in full.iter().enumerate() {
                            let order: Vec<VertexId> = if rev {
                                (0..n as VertexId).rev().collect()
                            } else {
                                (0..n as VertexId).collect()
                            };
                            for v in order {
                                assert_eq!(t.get(i, v), table[v as usize], "agent {i} vertex {v}");
                            }
                        }
                    });
                }
            });
        }
    }

    #[test]
    fn tables_grown_near_the_starts_are_lock_free_above_the_complete_limit() {
        // Just over COMPLETE_ENTRIES agents x vertices: 65,536 vertices (a 4 x 4 grid, the rest
        // isolated) and 1,025 agents. warm_up keeps such tables lazy; warm_up_near keeps them
        // for reading without locks (each is whole here: the margin covers the grid).
        let n = 1usize << 16;
        let mut edges = Vec::new();
        for v in 0..16u32 {
            if v % 4 < 3 {
                edges.push((v, v + 1));
            }
            if v < 12 {
                edges.push((v, v + 4));
            }
        }
        let g = Graph::from_edges(n, &edges);
        let agents = COMPLETE_ENTRIES / n + 1;
        let goals: Vec<VertexId> = (0..agents).map(|i| (i % 16) as VertexId).collect();
        let starts: Vec<VertexId> = (0..agents).map(|i| 15 - (i % 16) as VertexId).collect();
        let full = goal_distance_tables(&g, &goals[..16]);
        let mut near = GoalDistances::new(&g, &goals);
        let mut lazy = GoalDistances::new(&g, &goals);
        assert!(!near.is_packed());
        assert!(near.warm_up_near(&starts, 100, Deadline::none()));
        assert!(lazy.warm_up(&starts, Deadline::none()));
        assert!((0..agents).all(|i| near.narrow(i).is_some()));
        assert!(lazy.narrow(0).is_none());
        for i in (0..agents).step_by(61) {
            for v in (0..20).chain([n as VertexId - 1]) {
                let want = full[i % 16][v as usize];
                assert_eq!(near.get(i, v), want, "agent {i} vertex {v}");
                assert_eq!(lazy.get(i, v), want, "agent {i} vertex {v}");
            }
        }
    }

    #[test]
    fn a_completed_warm_up_widens_past_65535_too() {
        // The warm-up's array-queue BFS hands over to the layered one when distances reach
        // 65 535: a path with a branch, goals at an end and in the middle.
        let n = 70_000usize;
        let mut edges: Vec<(VertexId, VertexId)> =
            (0..n as VertexId - 2).map(|v| (v, v + 1)).collect();
        edges.push((65_530, n as VertexId - 1));
        let g = Graph::from_edges(n, &edges);
        let goals = [0, 35_000];
        let full = goal_distance_tables(&g, &goals);
        let mut t = GoalDistances::new(&g, &goals);
        assert!(t.warm_up(&[10, 20], Deadline::none()));
        for (i, table) in full.iter().enumerate() {
            for v in (0..n as VertexId)
                .step_by(97)
                .chain([65_534, 65_535, 69_998, 69_999])
            {
                assert_eq!(t.get(i, v), table[v as usize], "agent {i} vertex {v}");
            }
        }
        assert_eq!(t.get(0, 69_999), 65_531);
        assert_eq!(t.get(0, 69_998), 69_998);
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
