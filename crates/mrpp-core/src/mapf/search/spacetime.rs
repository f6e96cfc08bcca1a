//! Reservation table and space-time A* (Silver 2005), shared by CA*, HCA*, WHCA* and H*'s repair.
//!
//! A search state is `(vertex, t)`. Moves and waits cost 1, except waiting on the goal in windowed
//! mode, which is free (Silver's convention, so an agent that has arrived prefers to stay). A
//! successor is legal when its vertex is not reserved at `t + 1` and the reverse edge is not
//! reserved at the same step (no swaps). Following a reserved agent is allowed, as in the validator.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use rustc_hash::FxHashMap;

use crate::contract::Deadline;
use crate::mapf::graph::{Graph, VertexId};

const NEVER: u32 = u32::MAX;

/// Vertex and edge reservations over time, plus vertices held forever by parked agents.
///
/// Stored per vertex as a short list of `(t, from)` sorted by `t`: an agent is on the vertex at
/// `t`, having come from `from` at `t - 1` (itself for a wait or a start). A vertex is reserved at
/// few time steps, so a binary search of its list is cheaper than hashing `(vertex, t)` pairs, and
/// the sorted list gives the vertex's safe intervals to [`crate::mapf::search::sipp`].
#[derive(Debug, Clone)]
pub struct Reservations {
    at: Vec<Vec<(u32, VertexId)>>,
    /// `parked[v] = t`: some agent sits on `v` for every step `>= t`.
    parked: Vec<u32>,
    /// Latest time at which `v` is reserved (`NEVER` when never).
    last: Vec<u32>,
    horizon: u32,
}

impl Reservations {
    pub fn new(num_vertices: usize) -> Self {
        Reservations {
            at: vec![Vec::new(); num_vertices],
            parked: vec![NEVER; num_vertices],
            last: vec![NEVER; num_vertices],
            horizon: 0,
        }
    }

    /// Reserves `path` starting at time `t0`. With `park`, its last vertex stays reserved forever.
    pub fn reserve_path(&mut self, path: &[VertexId], t0: u32, park: bool) {
        for (k, &v) in path.iter().enumerate() {
            let t = t0 + k as u32;
            let from = if k > 0 { path[k - 1] } else { v };
            let list = &mut self.at[v as usize];
            let pos = list.partition_point(|&e| e <= (t, from));
            list.insert(pos, (t, from));
            let last = &mut self.last[v as usize];
            *last = if *last == NEVER { t } else { (*last).max(t) };
            self.horizon = self.horizon.max(t);
        }
        if park && let Some(&v) = path.last() {
            let t = t0 + path.len() as u32 - 1;
            self.parked[v as usize] = self.parked[v as usize].min(t);
        }
    }

    /// Undoes [`Reservations::reserve_path`] with the same arguments (large-neighbourhood search
    /// takes paths out and puts new ones in). The horizon is kept (an upper bound).
    pub fn release_path(&mut self, path: &[VertexId], t0: u32, park: bool) {
        for (k, &v) in path.iter().enumerate() {
            let t = t0 + k as u32;
            let from = if k > 0 { path[k - 1] } else { v };
            let list = &mut self.at[v as usize];
            if let Ok(pos) = list.binary_search(&(t, from)) {
                list.remove(pos);
            }
            self.last[v as usize] = list.last().map_or(NEVER, |&(tt, _)| tt);
        }
        if park && let Some(&v) = path.last() {
            let t = t0 + path.len() as u32 - 1;
            if self.parked[v as usize] == t {
                self.parked[v as usize] = NEVER;
            }
        }
    }

    /// Whether `v` is free at time `t`.
    #[inline]
    pub fn vertex_free(&self, v: VertexId, t: u32) -> bool {
        self.parked[v as usize] > t && !self.reserved_at(v, t)
    }

    /// Whether some path is on `v` at `t` (parked agents aside).
    #[inline]
    fn reserved_at(&self, v: VertexId, t: u32) -> bool {
        let list = &self.at[v as usize];
        let i = list.partition_point(|&(tt, _)| tt < t);
        list.get(i).is_some_and(|&(tt, _)| tt == t)
    }

    /// Whether some path moves from `from` onto `v` at step `t` (a wait when `from == v`).
    #[inline]
    pub fn arrives(&self, v: VertexId, t: u32, from: VertexId) -> bool {
        self.at[v as usize].binary_search(&(t, from)).is_ok()
    }

    /// The first time `>= t` at which `v` is reserved (by a path or a parked agent), or
    /// `u32::MAX` when it is free from `t` on: a safe interval that contains `t` ends just before.
    #[inline]
    pub fn next_reserved(&self, v: VertexId, t: u32) -> u32 {
        let list = &self.at[v as usize];
        // The usual case: no path on `v` from `t` on.
        if list.last().is_none_or(|&(tt, _)| tt < t) {
            return self.parked[v as usize].max(t);
        }
        let i = list.partition_point(|&(tt, _)| tt < t);
        let by_path = list.get(i).map_or(NEVER, |&(tt, _)| tt);
        by_path.min(self.parked[v as usize].max(t))
    }

    /// The first time `>= t` at which `v` is free, or `u32::MAX` when a parked agent holds it
    /// from then on.
    #[inline]
    pub fn first_free(&self, v: VertexId, t: u32) -> u32 {
        let mut u = t;
        let list = &self.at[v as usize];
        // The usual case: no path on `v` from `t` on.
        if list.last().is_none_or(|&(tt, _)| tt < t) {
            return if t >= self.parked[v as usize] {
                NEVER
            } else {
                t
            };
        }
        let mut i = list.partition_point(|&(tt, _)| tt < u);
        while let Some(&(tt, _)) = list.get(i) {
            if tt > u {
                break;
            }
            if tt == u {
                u += 1;
            }
            i += 1;
        }
        if u >= self.parked[v as usize] {
            NEVER
        } else {
            u
        }
    }

    /// The start of the safe interval of `v` that contains the free time `t`: one after the
    /// latest reserved time before `t`, or 0.
    #[inline]
    pub fn interval_start(&self, v: VertexId, t: u32) -> u32 {
        let list = &self.at[v as usize];
        let i = list.partition_point(|&(tt, _)| tt < t);
        if i == 0 { 0 } else { list[i - 1].0 + 1 }
    }

    /// Whether an agent may move (or wait, when `u == v`) from `u` at `t - 1` to `v` at `t`:
    /// `v` is free at `t` and no agent moves `v -> u` at the same step (a swap).
    #[inline]
    pub fn move_free(&self, u: VertexId, v: VertexId, t: u32) -> bool {
        self.vertex_free(v, t) && (u == v || !self.arrives(u, t, v))
    }

    /// Whether `v` is free at every step `>= t`.
    pub fn free_from(&self, v: VertexId, t: u32) -> bool {
        self.parked[v as usize] == NEVER
            && (self.last[v as usize] == NEVER || self.last[v as usize] < t)
    }

    /// The first time from which `v` stays free for good (one after its latest reservation, 0
    /// when never reserved), or `None` when a parked agent holds it forever.
    pub fn free_for_good_from(&self, v: VertexId) -> Option<u32> {
        if self.parked[v as usize] != NEVER {
            return None;
        }
        Some(match self.last[v as usize] {
            NEVER => 0,
            t => t + 1,
        })
    }

    /// Latest reserved time step.
    pub fn horizon(&self) -> u32 {
        self.horizon
    }
}

/// The best `g` of each `(vertex, time)` state and whether it was expanded: a dense table over
/// the query's time span when it is small enough (the usual case; [`DenseStates`], in one of
/// two layouts), else a hash map. [`space_time_astar`]'s search is compiled
/// once per table, so the lookups inline.
trait Seen {
    fn get(&self, v: VertexId, t: u32) -> Option<(u32, bool)>;
    fn set(&mut self, v: VertexId, t: u32, g: u32, closed: bool);
}

/// A dense table over a query's span: `(v, t)` at `(t - t0) * nv + v`, in the calling thread's
/// [`DenseScratch`]; an entry holding another stamp (an earlier query's) counts as unseen, so
/// nothing is cleared between queries. Two layouts:
/// - windowed mode, `u64` entries: `stamp << 32 | x` where `x` is `g + 1` with [`CLOSED`] set
///   once expanded;
/// - full mode, `u16` entries: every way to `(v, t)` costs `t - t0` (moves and waits cost 1), so
///   a state needs only whether it was seen and expanded: the stamp, with [`FLAG_CLOSED`] set
///   once expanded. A quarter of the bytes: a query touches (and a fresh process faults in) a
///   quarter of the pages.
struct DenseStates<'s, T> {
    cells: &'s mut [T],
    stamp: u32,
    nv: usize,
    t0: u32,
}

/// Queries whose span is too large for a dense table.
type HashStates = FxHashMap<(VertexId, u32), (u32, bool)>;

const CLOSED: u32 = 1 << 31;

/// The expanded mark of a full-mode [`DenseStates`] entry; the other 15 bits hold the stamp.
const FLAG_CLOSED: u16 = 1 << 15;

/// Dense tables up to this many states (8 bytes each in windowed mode, 32 MiB; 2 bytes in full
/// mode): they are kept per thread and never cleared (entries carry the query's stamp), so a
/// query touches only the states it visits; beyond, a hash map.
const DENSE_STATES: usize = 1 << 22;

/// The least size of a thread's dense table (2 MiB in windowed mode, 512 KiB in full mode): its
/// pages are zeroed lazily, so only the states a query visits cost memory, and small queries
/// whose spans grow need no new table.
const DENSE_FIRST: usize = 1 << 18;

/// One thread's dense table, reused by every query on that thread (`u64` entries in windowed
/// mode, `u16` in full mode: [`DenseStates`]).
#[derive(Default)]
struct DenseScratch<T> {
    cells: Vec<T>,
    stamp: u32,
}

thread_local! {
    static DENSE: std::cell::RefCell<DenseScratch<u64>> = std::cell::RefCell::default();
    static FLAGS: std::cell::RefCell<DenseScratch<u16>> = std::cell::RefCell::default();
}

/// An entry type of [`DenseStates`], and the largest stamp it holds.
trait Entry: Copy + Default {
    const LAST_STAMP: u32;
}

impl Entry for u64 {
    const LAST_STAMP: u32 = u32::MAX;
}

/// The top bit is the expanded mark.
impl Entry for u16 {
    const LAST_STAMP: u32 = FLAG_CLOSED as u32 - 1;
}

impl<T: Entry> DenseScratch<T> {
    /// A fresh stamp for a query over `n` states (a new, lazily zeroed table when it must grow
    /// or the stamps run out). A table starts at [`DENSE_FIRST`] states and
    /// grows to a power of two, so that queries whose spans creep up do not each get a new table
    /// and fault its pages in again.
    fn begin(&mut self, n: usize) -> u32 {
        debug_assert!(n <= DENSE_STATES);
        if self.cells.len() < n || self.stamp == T::LAST_STAMP {
            let size = n.max(self.cells.len()).max(DENSE_FIRST).next_power_of_two();
            self.cells = vec![T::default(); size.min(DENSE_STATES)];
            self.stamp = 0;
        }
        self.stamp += 1;
        self.stamp
    }

    /// The table of a query over `n` states of `nv` vertices from time `t0`, with a fresh stamp.
    fn states(&mut self, n: usize, nv: usize, t0: u32) -> DenseStates<'_, T> {
        let stamp = self.begin(n);
        DenseStates {
            cells: &mut self.cells[..n],
            stamp,
            nv,
            t0,
        }
    }
}

/// The index of `(v, t)` in a dense table over `nv` vertices from time `t0`.
#[inline]
fn slot(nv: usize, t0: u32, v: VertexId, t: u32) -> usize {
    (t - t0) as usize * nv + v as usize
}

impl Seen for DenseStates<'_, u64> {
    #[inline]
    fn get(&self, v: VertexId, t: u32) -> Option<(u32, bool)> {
        let c = *self.cells.get(slot(self.nv, self.t0, v, t))?;
        let x = c as u32;
        (c >> 32 == u64::from(self.stamp)).then(|| ((x & !CLOSED) - 1, x & CLOSED != 0))
    }

    #[inline]
    fn set(&mut self, v: VertexId, t: u32, g: u32, closed: bool) {
        if let Some(c) = self.cells.get_mut(slot(self.nv, self.t0, v, t)) {
            let x = (g + 1) | if closed { CLOSED } else { 0 };
            *c = (u64::from(self.stamp) << 32) | u64::from(x);
        }
    }
}

impl Seen for DenseStates<'_, u16> {
    #[inline]
    fn get(&self, v: VertexId, t: u32) -> Option<(u32, bool)> {
        let c = *self.cells.get(slot(self.nv, self.t0, v, t))?;
        (u32::from(c & !FLAG_CLOSED) == self.stamp).then_some((t - self.t0, c & FLAG_CLOSED != 0))
    }

    #[inline]
    fn set(&mut self, v: VertexId, t: u32, g: u32, closed: bool) {
        debug_assert_eq!(g, t - self.t0, "full mode: the cost of (v, t) is t - t0");
        if let Some(c) = self.cells.get_mut(slot(self.nv, self.t0, v, t)) {
            *c = self.stamp as u16 | if closed { FLAG_CLOSED } else { 0 };
        }
    }
}

impl Seen for HashStates {
    #[inline]
    fn get(&self, v: VertexId, t: u32) -> Option<(u32, bool)> {
        FxHashMap::get(self, &(v, t)).copied()
    }

    #[inline]
    fn set(&mut self, v: VertexId, t: u32, g: u32, closed: bool) {
        self.insert((v, t), (g, closed));
    }
}

/// One space-time query. `H` is the heuristic's type: a closure's own type where the caller
/// names it (the search is then compiled for it and the heuristic inlines), else `dyn Fn`.
pub struct Query<'a, H: Fn(VertexId) -> u32 + ?Sized = dyn Fn(VertexId) -> u32 + 'a> {
    pub graph: &'a Graph,
    pub start: VertexId,
    pub goal: VertexId,
    pub start_time: u32,
    /// Admissible estimate of the remaining cost to the goal.
    pub h: &'a H,
    /// Full search: only paths arriving by this time (states that cannot are pruned with `h`).
    /// Windowed search: ignored.
    pub max_time: u32,
    /// `Some(w)`: depth-limited search; states at `start_time + w` are terminal with cost `g + h`.
    pub window: Option<u32>,
    pub deadline: Deadline,
}

/// Outcome of a space-time search.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Search {
    /// The path from `start` at `start_time` (index 0) onward.
    Found(Vec<VertexId>),
    NotFound,
    TimedOut,
}

/// Space-time A*. Full mode: reach the goal at a time from which it is free forever (minimising the
/// arrival time). Windowed mode: a best path of `w` steps whose end is ranked by `g + h`.
/// Ties: lower f, then higher g, then insertion order (deterministic).
///
/// Full mode uses the goal-reservation bound: no plan arrives for good before the goal's last
/// reservation has passed, so the heuristic of `(v, t)` is `max(h(v), T_goal - t)` with `T_goal`
/// from [`Reservations::free_for_good_from`] (admissible and consistent). With ties going to the
/// higher `g`, a goal reserved late no longer makes the search expand every `(cell, time)` state
/// before `T_goal`; a goal parked on forever is answered at once (`NotFound`).
pub fn space_time_astar<H: Fn(VertexId) -> u32 + ?Sized>(
    q: &Query<H>,
    res: &Reservations,
) -> Search {
    let end_time = q.window.map(|w| q.start_time + w);
    let last_time = end_time.unwrap_or(q.max_time);
    let nv = q.graph.num_vertices();
    let span = last_time.saturating_sub(q.start_time) as usize + 1;
    match nv.checked_mul(span) {
        Some(n) if n <= DENSE_STATES && q.window.is_none() => FLAGS.with_borrow_mut(|scratch| {
            search(q, res, &mut scratch.states(n, nv, q.start_time), true)
        }),
        Some(n) if n <= DENSE_STATES => DENSE.with_borrow_mut(|scratch| {
            search(q, res, &mut scratch.states(n, nv, q.start_time), true)
        }),
        _ => search(q, res, &mut HashStates::default(), true),
    }
}

/// [`space_time_astar`] with its table of seen states; `buckets`: a bucket queue when the
/// `(f, g)` grid is small (else, and always without, a binary heap: same order).
fn search<H: Fn(VertexId) -> u32 + ?Sized>(
    q: &Query<H>,
    res: &Reservations,
    seen: &mut impl Seen,
    buckets: bool,
) -> Search {
    if !res.vertex_free(q.start, q.start_time) {
        return Search::NotFound;
    }
    let goal_free = match q.window {
        Some(_) => 0,
        None => match res.free_for_good_from(q.goal) {
            Some(t) => t,
            None => return Search::NotFound,
        },
    };
    let h = |v, t: u32| match (q.h)(v) {
        u32::MAX => u32::MAX,
        hv => hv.max(goal_free.saturating_sub(t)),
    };
    if h(q.start, q.start_time) == u32::MAX {
        return Search::NotFound;
    }
    let mut nodes = NODES.take();
    nodes.clear();
    let end_time = q.window.map(|w| q.start_time + w);
    let f0 = h(q.start, q.start_time);
    // Full mode: `f` and `g` lie in `0 ..= max_time - start_time` (the pruning by `max_time`
    // keeps `f` there, whatever the heuristic), so a bucket queue over that grid replaces the
    // heap when it is small.
    let span = u64::from(q.max_time.saturating_sub(q.start_time)) + 1;
    let mut open = match end_time {
        None if buckets
            && u64::from(f0) < span
            && span
                .checked_mul(span)
                .is_some_and(|n| n <= BUCKET_CELLS as u64) =>
        {
            let mut b = BUCKETS.take();
            b.begin(span as usize);
            Open::Buckets(b)
        }
        _ => Open::Heap(BinaryHeap::new(), 0),
    };
    nodes.push(Node {
        v: q.start,
        t: q.start_time,
        parent: u32::MAX,
    });
    open.push(f0, 0, 0, false);
    seen.set(q.start, q.start_time, 0, false);
    let mut expansions = 0u64;
    let found = loop {
        let Some((g, idx, terminal)) = open.pop() else {
            break Search::NotFound;
        };
        let (v, t) = (nodes[idx as usize].v, nodes[idx as usize].t);
        if terminal || (end_time.is_none() && v == q.goal && res.free_from(v, t)) {
            let mut path = Vec::with_capacity((t - q.start_time + 1) as usize);
            let mut i = idx;
            while i != u32::MAX {
                path.push(nodes[i as usize].v);
                i = nodes[i as usize].parent;
            }
            path.reverse();
            break Search::Found(path);
        }
        match seen.get(v, t) {
            Some((g, false)) => seen.set(v, t, g, true),
            _ => continue,
        }
        expansions += 1;
        if expansions.is_multiple_of(1024) && q.deadline.expired() {
            break Search::TimedOut;
        }
        if let Some(end) = end_time {
            if t == end {
                // Terminal: rank by g + h; re-queued so that cheaper terminals win.
                let hv = h(v, t);
                open.push(g.saturating_add(hv), g, idx, true);
                continue;
            }
        } else if t >= q.max_time {
            continue;
        }
        let nt = t + 1;
        let waits_free = end_time.is_some() && v == q.goal;
        for &w in std::iter::once(&v).chain(q.graph.neighbors(v)) {
            let hw = h(w, nt);
            // Unreachable, or (full mode) cannot arrive by `max_time` even unobstructed.
            if hw == u32::MAX || (end_time.is_none() && nt.saturating_add(hw) > q.max_time) {
                continue;
            }
            if !res.move_free(v, w, nt) {
                continue;
            }
            let ng = g + if w == v && waits_free { 0 } else { 1 };
            let e = seen.get(w, nt).unwrap_or((u32::MAX, false));
            if e.1 || ng >= e.0 {
                continue;
            }
            seen.set(w, nt, ng, false);
            nodes.push(Node {
                v: w,
                t: nt,
                parent: idx,
            });
            open.push(ng + hw, ng, nodes.len() as u32 - 1, false);
        }
    };
    if let Open::Buckets(b) = open {
        BUCKETS.set(b);
    }
    NODES.set(nodes);
    found
}

/// A state [`space_time_astar`] reached: its vertex and time, and the node it came from
/// (`u32::MAX` for the start).
struct Node {
    v: VertexId,
    t: u32,
    parent: u32,
}

thread_local! {
    /// The calling thread's node arena, lent to one search at a time.
    static NODES: std::cell::Cell<Vec<Node>> = const { std::cell::Cell::new(Vec::new()) };
}

/// Bucket queues up to this many `(f, g)` cells; beyond, a binary heap.
const BUCKET_CELLS: usize = 1 << 16;

thread_local! {
    /// The calling thread's bucket queue, lent to one search at a time.
    static BUCKETS: std::cell::Cell<Buckets> = std::cell::Cell::default();
}

/// The open list of [`space_time_astar`]: entries leave in order of lower `f`, then higher `g`,
/// then insertion (each entry is a node index; a terminal flag for windowed mode).
enum Open {
    /// A max-heap of `(f, g, insertion order, node index, terminal)` on lower `f`, then higher
    /// `g`, and the number of entries pushed so far.
    #[allow(clippy::type_complexity)]
    Heap(
        BinaryHeap<(Reverse<u32>, u32, Reverse<u32>, u32, bool)>,
        u32,
    ),
    /// Full mode, when the `(f, g)` grid is small: one FIFO per cell, in the same order.
    Buckets(Buckets),
}

impl Open {
    #[inline]
    fn push(&mut self, f: u32, g: u32, idx: u32, terminal: bool) {
        match self {
            Open::Heap(heap, counter) => {
                *counter += 1;
                heap.push((Reverse(f), g, Reverse(*counter), idx, terminal));
            }
            Open::Buckets(b) => b.push(f, g, idx),
        }
    }

    #[inline]
    fn pop(&mut self) -> Option<(u32, u32, bool)> {
        match self {
            Open::Heap(heap, _) => heap
                .pop()
                .map(|(_, g, _, idx, terminal)| (g, idx, terminal)),
            Open::Buckets(b) => b.pop().map(|(g, idx)| (g, idx, false)),
        }
    }
}

/// A bucket queue over `f` and `g`, both in `0 .. size`: per cell a FIFO of node indices, a
/// linked list through one arena of entries (`first[c]` and `last[c]` hold an entry's index + 1;
/// `first[c]` is 0 when the cell is empty, `last[c]` when the search has not used it). Within a level of `f` the highest `g` with entries leaves first;
/// `top[f]` bounds it from above. `level` is the least `f` that may hold entries (a heuristic
/// that is not consistent may queue below the level being emptied).
///
/// The cell tables are allocated zeroed (lazily, by the system) and only the cells a search
/// used are reset, by the next search's `begin`, so a search touches only the pages of the cells
/// it uses: the grid has `size²` cells, of which a search uses a thin band.
#[derive(Default)]
struct Buckets {
    first: Vec<u32>,
    last: Vec<u32>,
    /// Per entry: the node index and the next entry of its cell (index + 1, 0 at the end).
    entries: Vec<(u32, u32)>,
    top: Vec<i64>,
    touched: Vec<u32>,
    size: usize,
    level: usize,
}

impl Buckets {
    fn begin(&mut self, size: usize) {
        for &c in &self.touched {
            self.first[c as usize] = 0;
            self.last[c as usize] = 0;
        }
        self.touched.clear();
        self.entries.clear();
        let n = size * size;
        if self.first.len() < n {
            let n = n.next_power_of_two();
            self.first = vec![0; n];
            self.last = vec![0; n];
        }
        self.top.clear();
        self.top.resize(size, -1);
        (self.size, self.level) = (size, 0);
    }

    #[inline]
    fn push(&mut self, f: u32, g: u32, idx: u32) {
        debug_assert!((f as usize) < self.size && (g as usize) < self.size);
        let l = f as usize;
        let c = l * self.size + g as usize;
        self.entries.push((idx, 0));
        let e = self.entries.len() as u32;
        if self.first[c] == 0 {
            if self.last[c] == 0 {
                self.touched.push(c as u32);
            }
            self.first[c] = e;
        } else {
            self.entries[self.last[c] as usize - 1].1 = e;
        }
        self.last[c] = e;
        self.top[l] = self.top[l].max(i64::from(g));
        self.level = self.level.min(l);
    }

    #[inline]
    fn pop(&mut self) -> Option<(u32, u32)> {
        while self.level < self.top.len() {
            let l = self.level;
            while self.top[l] >= 0 {
                let c = l * self.size + self.top[l] as usize;
                match self.first[c] {
                    0 => self.top[l] -= 1,
                    e => {
                        let (idx, next) = self.entries[e as usize - 1];
                        self.first[c] = next;
                        return Some((self.top[l] as u32, idx));
                    }
                }
            }
            self.level += 1;
        }
        None
    }
}

/// A full-mode query from `start` at time 0 (the tests of this module and of SIPP).
#[cfg(test)]
pub(crate) fn query<'a>(
    g: &'a Graph,
    start: VertexId,
    goal: VertexId,
    h: &'a dyn Fn(VertexId) -> u32,
    max_time: u32,
) -> Query<'a> {
    Query {
        graph: g,
        start,
        goal,
        start_time: 0,
        h,
        max_time,
        window: None,
        deadline: Deadline::none(),
    }
}

/// [`space_time_astar`] with a hash map of states and a binary heap, the plainest form of the
/// search: the tests check that the tables used for speed do not change its answer.
#[cfg(test)]
pub(crate) fn space_time_astar_plain(q: &Query, res: &Reservations) -> Search {
    search(q, res, &mut HashStates::default(), false)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mapf::search::distance::bfs_distances;
    use crate::mapf::search::sipp::sipp;

    /// A goal that a parked agent holds forever is answered at once, and a goal reserved late
    /// gives an arrival right after its last reservation.
    #[test]
    fn goal_reservations_bound_the_arrival() {
        let g = Graph::from_edges(4, &[(0, 1), (1, 2), (2, 3)]);
        let h = |v: VertexId| 3u32.abs_diff(v);
        let mut res = Reservations::new(4);
        res.reserve_path(&[3, 3, 3, 3, 3, 3, 3, 2], 0, false);
        assert_eq!(res.free_for_good_from(3), Some(7));
        match space_time_astar(&query(&g, 0, 3, &h, 50), &res) {
            // The holder leaves 3 for 2 at t = 7: arriving then would be a swap, and 2 is taken at 7.
            Search::Found(p) => assert_eq!(p.len() - 1, 9, "{p:?}"),
            other => panic!("{other:?}"),
        }
        res.reserve_path(&[1, 2, 3], 0, true);
        assert_eq!(res.free_for_good_from(3), None);
        assert_eq!(
            space_time_astar(&query(&g, 0, 3, &h, 1_000_000), &res),
            Search::NotFound
        );
    }

    #[test]
    fn waits_for_a_reserved_centre_in_both_searches() {
        // Plus: centre 0, W=1 E=2 N=3 S=4. Agent a W->E reserved; b S->N must wait one step.
        let g = Graph::from_edges(5, &[(0, 1), (0, 2), (0, 3), (0, 4)]);
        let mut res = Reservations::new(5);
        res.reserve_path(&[1, 0, 2], 0, true);
        let d = bfs_distances(&g, 3);
        let h = |v: VertexId| d[v as usize];
        let q = query(&g, 4, 3, &h, 50);
        assert_eq!(space_time_astar(&q, &res), Search::Found(vec![4, 4, 0, 3]));
        assert_eq!(sipp(&q, &res), Search::Found(vec![4, 4, 0, 3]));
    }

    #[test]
    fn swap_is_refused_and_parked_goal_blocks_in_both_searches() {
        // Path 0-1-2. a moves 2->1->0 and parks; b at 0 wants 2: it can never get past.
        let g = Graph::from_edges(3, &[(0, 1), (1, 2)]);
        let mut res = Reservations::new(3);
        res.reserve_path(&[2, 1, 0], 0, true);
        let d = bfs_distances(&g, 2);
        let h = |v: VertexId| d[v as usize];
        let q = query(&g, 0, 2, &h, 50);
        assert_eq!(space_time_astar(&q, &res), Search::NotFound);
        assert_eq!(sipp(&q, &res), Search::NotFound);
    }

    /// A bound of `u32::MAX` (CA*/HCA* with an unbounded slack) takes the heap, and SIPP's
    /// arrival search allocates buckets only for the `f` it queues.
    #[test]
    fn the_largest_time_bound_is_answered() {
        let g = Graph::from_edges(3, &[(0, 1), (1, 2)]);
        let res = Reservations::new(3);
        let d = |v: VertexId| 2 - v;
        let q = query(&g, 2, 2, &d, u32::MAX);
        assert_eq!(space_time_astar(&q, &res), Search::Found(vec![2]));
        assert_eq!(crate::mapf::search::sipp::earliest_arrival(&q, &res), Ok(0));
        let q = query(&g, 0, 2, &d, u32::MAX);
        assert_eq!(space_time_astar(&q, &res), Search::Found(vec![0, 1, 2]));
        assert_eq!(crate::mapf::search::sipp::earliest_arrival(&q, &res), Ok(2));
    }

    #[test]
    fn goal_must_stay_free() {
        // Path 0-1-2; reserved agent passes 1 at t=3; b from 0 to goal 1 must arrive after t=3.
        let g = Graph::from_edges(3, &[(0, 1), (1, 2)]);
        let mut res = Reservations::new(3);
        res.reserve_path(&[2, 2, 2, 1, 2], 0, false);
        let d = bfs_distances(&g, 1);
        let h = |v: VertexId| d[v as usize];
        match space_time_astar(&query(&g, 0, 1, &h, 50), &res) {
            Search::Found(p) => assert_eq!(p.len(), 5),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn releasing_a_path_frees_its_cells_and_goal() {
        let g = Graph::from_edges(3, &[(0, 1), (1, 2)]);
        let mut res = Reservations::new(3);
        res.reserve_path(&[2, 1, 0], 0, true);
        res.reserve_path(&[1, 2], 5, false);
        res.release_path(&[2, 1, 0], 0, true);
        assert!(res.vertex_free(1, 1) && res.vertex_free(0, 9) && res.move_free(0, 1, 1));
        assert!(!res.vertex_free(1, 5) && !res.free_from(2, 6) && res.free_from(0, 0));
        let d = bfs_distances(&g, 2);
        let h = |v: VertexId| d[v as usize];
        // The goal is free from t = 7 on.
        match space_time_astar(&query(&g, 0, 2, &h, 50), &res) {
            Search::Found(p) => assert_eq!(p.len(), 8),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn windowed_search_stops_at_window() {
        let g = Graph::from_edges(6, &[(0, 1), (1, 2), (2, 3), (3, 4), (4, 5)]);
        let res = Reservations::new(6);
        let d = bfs_distances(&g, 5);
        let h = |v: VertexId| d[v as usize];
        let mut q = query(&g, 0, 5, &h, 50);
        q.window = Some(2);
        assert_eq!(space_time_astar(&q, &res), Search::Found(vec![0, 1, 2]));
    }

    /// The full-mode state table's 15-bit stamps run out after 32,767 queries: the table must
    /// then be replaced, or an entry left by an early query would read as seen by a late one.
    #[test]
    fn the_state_table_never_hands_out_a_stamp_its_cells_hold() {
        let mut scratch = DenseScratch::<u16>::default();
        let first = scratch.begin(100) as u16;
        scratch.cells[7] = first | FLAG_CLOSED; // written once, by the first query only
        for k in 0..70_000 {
            let stamp = scratch.begin(100);
            assert!(
                stamp < u32::from(FLAG_CLOSED),
                "query {k}: stamp {stamp} hits the mark"
            );
            assert_ne!(
                u32::from(scratch.cells[7] & !FLAG_CLOSED),
                stamp,
                "query {k}"
            );
            scratch.cells[3] = stamp as u16; // every query writes here
        }
    }
}
