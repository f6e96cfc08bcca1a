//! Safe-interval path planning (M. Phillips, M. Likhachev, "SIPP: Safe interval path planning for
//! dynamic environments", ICRA 2011) over the [`Reservations`] table, with the validator's rules:
//! no two agents on a vertex at once, no swaps, following allowed, and the goal free for ever
//! from the arrival on.
//!
//! A state is a vertex and one of its *safe intervals* (a maximal run of time steps at which no
//! reserved path is on it); the search keeps the earliest arrival per state, and waiting inside an
//! interval is implicit. Where space-time A* expands every `(vertex, time)` an agent might wait
//! in, SIPP expands each interval once, which is what makes re-planning in a dense plan cheap
//! (large-neighbourhood search re-plans thousands of agents against hundreds of fixed paths).
//! lacam3's refiner uses SIPP for the same reason (Okumura, "Engineering LaCAM*", AAMAS 2024).
//!
//! Swaps are edge constraints, which intervals do not capture: a move `v -> w` arriving at `a` is
//! refused when a reserved path moves `w -> v` at `a`. That path then holds `v` at `a`, so `a - 1`
//! is the last step of the agent's interval on `v` and no later departure exists: the move is
//! lost from this interval. The first arrival in each interval of `w` is kept, so the result has the least arrival time, the same cost as [`space_time_astar`]'s full
//! mode (a property test checks both on random tables).
//!
//! [`space_time_astar`]: crate::mapf::search::spacetime::space_time_astar

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use rustc_hash::FxHashMap;

use crate::mapf::graph::VertexId;
use crate::mapf::search::buckets::BucketQueue;
use crate::mapf::search::spacetime::{Query, Reservations, Search};

/// Earliest-arrival path from `q.start` at `q.start_time` to `q.goal`, arriving at a time from
/// which the goal is free for ever, and no later than `q.max_time` (states that cannot make it,
/// by `q.h`, are pruned). The path lists one vertex per time step from `q.start_time` on (waits
/// repeat the vertex). `q.window` must be `None` (SIPP has no windowed mode). Ties: lower `f`, then
/// higher `g`, then insertion order, so the result is deterministic.
///
/// # Panics
/// When `q.window` is `Some`.
pub fn sipp<H: Fn(VertexId) -> u32 + ?Sized>(q: &Query<H>, res: &Reservations) -> Search {
    assert!(q.window.is_none(), "SIPP has no windowed mode");
    if !res.vertex_free(q.start, q.start_time) {
        return Search::NotFound;
    }
    if (q.h)(q.start) == u32::MAX {
        return Search::NotFound;
    }
    let mut nodes = vec![Node {
        v: q.start,
        t: q.start_time,
        parent: u32::MAX,
    }];
    // (f, g, insertion order, node): max-heap on lower f, then higher g, then earlier insertion.
    let mut open: BinaryHeap<(Reverse<u32>, u32, Reverse<u32>, u32)> = BinaryHeap::new();
    open.push((Reverse((q.h)(q.start)), 0, Reverse(0), 0));
    // (vertex, interval start) -> (earliest arrival, expanded).
    let mut best: FxHashMap<(VertexId, u32), (u32, bool)> = FxHashMap::default();
    best.insert(
        (q.start, res.interval_start(q.start, q.start_time)),
        (q.start_time, false),
    );
    let mut counter = 0u32;
    let mut expansions = 0u64;
    while let Some((_, _, _, idx)) = open.pop() {
        let (v, t) = (nodes[idx as usize].v, nodes[idx as usize].t);
        if v == q.goal && res.free_from(v, t) {
            return Search::Found(unwind(&nodes, idx));
        }
        let entry = best
            .get_mut(&(v, res.interval_start(v, t)))
            .expect("every queued state is recorded");
        if entry.1 || entry.0 < t {
            continue;
        }
        entry.1 = true;
        expansions += 1;
        if expansions.is_multiple_of(1024) && q.deadline.expired() {
            return Search::TimedOut;
        }
        if t >= q.max_time {
            continue;
        }
        successors(q, res, v, t, |w, a, hw| {
            let key = (w, res.interval_start(w, a));
            let e = best.entry(key).or_insert((u32::MAX, false));
            if !e.1 && a < e.0 {
                *e = (a, false);
                nodes.push(Node {
                    v: w,
                    t: a,
                    parent: idx,
                });
                counter += 1;
                let g = a - q.start_time;
                open.push((Reverse(g + hw), g, Reverse(counter), nodes.len() as u32 - 1));
            }
        });
    }
    Search::NotFound
}

/// A least-*loss* path from `q.start` at `q.start_time` to `q.goal` (loss: the steps the agent
/// does not spend waiting on its goal, [`path_loss`]; lacam3's refiner objective, Okumura,
/// "Engineering LaCAM*", AAMAS 2024), ending at a time from which the goal is free for ever,
/// no later than `q.max_time`, with loss at most `max_loss` (states that cannot make either, by
/// `q.h`, are pruned). Unlike [`sipp`]'s earliest arrival, the path may reach the goal early,
/// wait there for free and step aside for a passing agent. The path lists one vertex per time
/// step from `q.start_time` on. `q.window` must be `None`.
///
/// A state is a vertex, one of its safe intervals and an arrival time with its loss `g`; a
/// state is dropped when another of the same interval arrived no later and, after waiting until
/// its arrival (free on the goal, one per step elsewhere), has no more loss. Moves off a
/// non-goal vertex leave as early as they can (as [`sipp`]); moves off the goal are drawn both
/// as early and as late as the goal's interval allows (lacam3's SIPP takes only the latest), so
/// the search keeps earliest arrivals where waits cost and the cheapest ones where they do not.
/// Waits in between are not drawn, so the loss found is not proven least: callers keep a path
/// only when it improves (large-neighbourhood search does).
///
/// Ties: lower `f`, then higher `g`, then the newest state (depth first among equals; lacam3's
/// SIPP also pops its newest node among equals). Among paths of equal loss this is the one
/// that matters for large-neighbourhood search: with the oldest state first instead (as
/// [`sipp`]), LaCAM\*'s refinement on den520d with 1,000 agents ended 0.1-0.2% higher in sum of
/// loss (docs/benchmark.md, "Newest-first ties").
///
/// [`path_loss`]: crate::mapf::plan::path_loss
///
/// # Panics
/// When `q.window` is `Some`.
pub fn sipp_loss<H: Fn(VertexId) -> u32 + ?Sized>(
    q: &Query<H>,
    res: &Reservations,
    max_loss: u32,
) -> Search {
    assert!(q.window.is_none(), "SIPP has no windowed mode");
    if !res.vertex_free(q.start, q.start_time) {
        return Search::NotFound;
    }
    let h0 = (q.h)(q.start);
    if h0 == u32::MAX || h0 > max_loss {
        return Search::NotFound;
    }
    LOSS.with_borrow_mut(|s| s.search(q, res, h0, max_loss))
}

/// The per-thread tables of [`sipp_loss`], cleared per query.
#[derive(Default)]
struct LossScratch {
    nodes: Vec<Node>,
    /// Per node: its loss, whether a later state dominated it, and the next node of its state
    /// key (`u32::MAX`: none).
    meta: Vec<(u32, bool, u32)>,
    /// (f, g, node): max-heap on lower f, then higher g, then the newer node.
    open: BinaryHeap<(Reverse<u32>, u32, u32)>,
    /// (vertex, interval start) -> the newest node of that key; older ones follow `meta.2`.
    front: FxHashMap<(VertexId, u32), u32>,
}

thread_local! {
    static LOSS: std::cell::RefCell<LossScratch> = std::cell::RefCell::default();
}

impl LossScratch {
    fn search<H: Fn(VertexId) -> u32 + ?Sized>(
        &mut self,
        q: &Query<H>,
        res: &Reservations,
        h0: u32,
        max_loss: u32,
    ) -> Search {
        let LossScratch {
            nodes,
            meta,
            open,
            front,
        } = self;
        nodes.clear();
        meta.clear();
        open.clear();
        front.clear();
        nodes.push(Node {
            v: q.start,
            t: q.start_time,
            parent: u32::MAX,
        });
        meta.push((0, false, u32::MAX));
        open.push((Reverse(h0), 0, 0));
        front.insert((q.start, res.interval_start(q.start, q.start_time)), 0);
        let mut expansions = 0u64;
        while let Some((_, _, idx)) = open.pop() {
            let (v, t) = (nodes[idx as usize].v, nodes[idx as usize].t);
            let (g, dead, _) = meta[idx as usize];
            if dead {
                continue;
            }
            if v == q.goal && res.free_from(v, t) {
                return Search::Found(unwind(nodes, idx));
            }
            expansions += 1;
            if expansions.is_multiple_of(1024) && q.deadline.expired() {
                return Search::TimedOut;
            }
            if t >= q.max_time {
                continue;
            }
            let on_goal = v == q.goal;
            // Only departures from the goal need the end of the stay (drawn late as well).
            let stay = if on_goal { stay_end(q, res, v, t) } else { 0 };
            // The earliest arrival in each safe interval of each neighbour, as [`sipp`]'s.
            successors(q, res, v, t, |w, a, hw| {
                // Waiting on `w` from one arrival to a later one: free on the goal.
                let wait = |from: u32, to: u32| if w == q.goal { 0 } else { to - from };
                let mut arrivals = [(a, g + if on_goal { 1 } else { a - t }), (a, u32::MAX)];
                if on_goal {
                    // Leave the goal as late as both intervals allow.
                    let mut late = (stay + 1)
                        .min(res.next_reserved(w, a).saturating_sub(1))
                        .min(q.max_time.saturating_sub(hw));
                    if late > a && res.arrives(v, late, w) {
                        late -= 1;
                    }
                    if late > a {
                        arrivals[1] = (late, g + 1);
                    }
                }
                let key = (w, res.interval_start(w, a));
                for (arr, ga) in arrivals {
                    if ga == u32::MAX || ga.saturating_add(hw) > max_loss {
                        continue;
                    }
                    let head = front.get(&key).copied().unwrap_or(u32::MAX);
                    // Dominated by a state of the key, or dominating some.
                    let mut j = head;
                    let mut dominated = false;
                    while j != u32::MAX {
                        let (gj, dj, next) = meta[j as usize];
                        let tj = nodes[j as usize].t;
                        if !dj {
                            if tj <= arr && gj + wait(tj, arr) <= ga {
                                dominated = true;
                                break;
                            }
                            if arr <= tj && ga + wait(arr, tj) <= gj {
                                meta[j as usize].1 = true;
                            }
                        }
                        j = next;
                    }
                    if dominated {
                        continue;
                    }
                    let id = nodes.len() as u32;
                    nodes.push(Node {
                        v: w,
                        t: arr,
                        parent: idx,
                    });
                    meta.push((ga, false, head));
                    front.insert(key, id);
                    open.push((Reverse(ga + hw), ga, id));
                }
            });
        }
        Search::NotFound
    }
}

/// The last time step the agent, on `v` from `t` (`t < q.max_time`), may stay there: the end of
/// its safe interval, and before `q.max_time`.
#[inline]
fn stay_end<H: Fn(VertexId) -> u32 + ?Sized>(
    q: &Query<H>,
    res: &Reservations,
    v: VertexId,
    t: u32,
) -> u32 {
    res.next_reserved(v, t + 1)
        .saturating_sub(1)
        .min(q.max_time - 1)
}

/// The successor states of `v` reached at `t` (the start of its stay in a safe interval): for each
/// neighbour `w` and each safe interval of `w` the agent can enter before its interval on `v`
/// ends, `visit(w, a, h(w))` with the earliest arrival `a` in it. Arrivals that cannot reach the
/// goal by `q.max_time` (by `q.h`) are left out; the caller checks `t < q.max_time`.
#[inline]
fn successors<H: Fn(VertexId) -> u32 + ?Sized>(
    q: &Query<H>,
    res: &Reservations,
    v: VertexId,
    t: u32,
    mut visit: impl FnMut(VertexId, u32, u32),
) {
    // The agent may stay on `v` up to `stay` (the end of its safe interval), so it can
    // arrive on a neighbour at any time in `t + 1 ..= stay + 1`.
    let stay = stay_end(q, res, v, t);
    for &w in q.graph.neighbors(v) {
        let hw = (q.h)(w);
        if hw == u32::MAX {
            continue;
        }
        let mut a = t + 1;
        loop {
            a = res.first_free(w, a);
            if a == u32::MAX || a > stay + 1 || a.saturating_add(hw) > q.max_time {
                break;
            }
            if res.arrives(v, a, w) {
                // A reserved path moves w -> v at `a`, so `v` is taken at `a` and this is
                // the last arrival the interval of `v` allows: no move to `w` from it.
                break;
            }
            visit(w, a, hw);
            // On to the next safe interval of `w`.
            a = res.next_reserved(w, a);
            if a == u32::MAX {
                break;
            }
        }
    }
}

/// [`sipp`]'s arrival time alone: the earliest time, at most `q.max_time`, at which the agent can
/// stand on `q.goal` for ever, or `Err` ([`Search::NotFound`], [`Search::TimedOut`]); a start on
/// the goal that is free for ever answers `q.start_time` whatever `q.max_time`, as in [`sipp`].
/// The same number [`sipp`] finds (a property test checks), with less bookkeeping since no path
/// is drawn:
///
/// - the open list is a bucket queue on `f = g + h`, as many buckets as the largest `f` queued,
///   ties in any order;
/// - with a consistent `q.h`, a vertex's states leave the queue in order of time, so a state is
///   dominated exactly when the vertex's latest expanded state lies in the same safe interval,
///   and one mark per vertex (its interval's end) replaces the table of states.
///
/// Tables are kept per thread and stamped per query. `q.h` must be consistent (a distance
/// table is); `q.window` must be `None`.
pub fn earliest_arrival<H: Fn(VertexId) -> u32 + ?Sized>(
    q: &Query<H>,
    res: &Reservations,
) -> Result<u32, Search> {
    debug_assert!(q.window.is_none(), "SIPP has no windowed mode");
    if !res.vertex_free(q.start, q.start_time) {
        return Err(Search::NotFound);
    }
    let h0 = (q.h)(q.start);
    if h0 == u32::MAX {
        return Err(Search::NotFound);
    }
    if q.start == q.goal && res.free_from(q.start, q.start_time) {
        return Ok(q.start_time);
    }
    if q.start_time.saturating_add(h0) > q.max_time {
        return Err(Search::NotFound);
    }
    ARRIVAL.with_borrow_mut(|s| s.search(q, res, h0))
}

/// The per-thread tables of [`earliest_arrival`].
#[derive(Default)]
struct ArrivalScratch {
    /// States `(v, t)` keyed by `f - f0`.
    open: BucketQueue<(VertexId, u32)>,
    /// Per vertex: `stamp << 32 | end`, where `end` is the first reserved time after the
    /// vertex's latest expanded state (its safe interval is `.. end`).
    done: Vec<u64>,
    stamp: u32,
}

thread_local! {
    static ARRIVAL: std::cell::RefCell<ArrivalScratch> = std::cell::RefCell::default();
}

impl ArrivalScratch {
    fn search<H: Fn(VertexId) -> u32 + ?Sized>(
        &mut self,
        q: &Query<H>,
        res: &Reservations,
        h0: u32,
    ) -> Result<u32, Search> {
        let nv = q.graph.num_vertices();
        if self.done.len() < nv || self.stamp == u32::MAX {
            self.done = vec![0; nv.max(self.done.len())];
            self.stamp = 0;
        }
        self.stamp += 1;
        let stamp = u64::from(self.stamp);
        let f0 = q.start_time + h0;
        // Whether a state at `(v, t)` lies in the interval of `v`'s latest expanded state.
        let dominated = |done: &[u64], v: VertexId, t: u32| {
            let d = done[v as usize];
            d >> 32 == stamp && t < d as u32
        };
        let open = &mut self.open;
        open.clear();
        open.push(0, (q.start, q.start_time));
        let mut expansions = 0u64;
        while let Some((_, (v, t))) = open.pop() {
            if dominated(&self.done, v, t) {
                continue;
            }
            if v == q.goal && res.free_from(v, t) {
                return Ok(t);
            }
            self.done[v as usize] = stamp << 32 | u64::from(res.next_reserved(v, t));
            expansions += 1;
            if expansions.is_multiple_of(1024) && q.deadline.expired() {
                return Err(Search::TimedOut);
            }
            if t >= q.max_time {
                continue;
            }
            let done = &self.done;
            successors(q, res, v, t, |w, a, hw| {
                if !dominated(done, w, a) {
                    open.push((a + hw).saturating_sub(f0) as usize, (w, a));
                }
            });
        }
        Err(Search::NotFound)
    }
}

/// A search node: `v` first reached at time `t` from node `parent`.
struct Node {
    v: VertexId,
    t: u32,
    parent: u32,
}

/// The path of node `idx`, one vertex per time step: each node's vertex from its arrival, held
/// until its child's arrival.
fn unwind(nodes: &[Node], idx: u32) -> Vec<VertexId> {
    let mut n = &nodes[idx as usize];
    let mut rev = vec![n.v];
    while n.parent != u32::MAX {
        let p = &nodes[n.parent as usize];
        rev.extend(std::iter::repeat_n(p.v, (n.t - p.t) as usize));
        n = p;
    }
    rev.reverse();
    rev
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mapf::graph::Graph;
    use crate::mapf::search::distance::bfs_distances;
    use crate::mapf::search::spacetime::{query, space_time_astar, space_time_astar_plain};
    use proptest::prelude::*;

    /// A random connected graph, a few reserved paths (random walks, some parked) that do not
    /// collide with each other, and a query: start (free at the start time when one of 20 draws
    /// is), goal, start time in 0..4 and time limit in 0..30.
    #[allow(clippy::type_complexity)]
    fn case() -> impl Strategy<
        Value = (
            Graph,
            Vec<(Vec<VertexId>, bool)>,
            VertexId,
            VertexId,
            u32,
            u32,
        ),
    > {
        (4usize..12, any::<u64>()).prop_map(|(n, seed)| {
            let mut x = seed | 1;
            let mut next = move |m: usize| {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                (x % m as u64) as usize
            };
            let mut edges: Vec<(VertexId, VertexId)> = (1..n)
                .map(|v| (next(v) as VertexId, v as VertexId))
                .collect();
            for _ in 0..n {
                let (a, b) = (next(n), next(n));
                if a != b {
                    edges.push((a as VertexId, b as VertexId));
                }
            }
            let g = Graph::from_edges(n, &edges);
            let mut res = Reservations::new(n);
            let mut paths = Vec::new();
            for _ in 0..next(7) + 1 {
                let mut p = vec![next(n) as VertexId];
                for t in 1..next(16) + 1 {
                    let v = *p.last().unwrap();
                    let nb = g.neighbors(v);
                    let w = if next(3) == 0 { v } else { nb[next(nb.len())] };
                    if !res.move_free(v, w, t as u32) {
                        break;
                    }
                    p.push(w);
                }
                let park = next(2) == 0 && res.free_from(*p.last().unwrap(), p.len() as u32 - 1);
                if res.vertex_free(p[0], 0)
                    && p.iter()
                        .enumerate()
                        .all(|(t, &v)| res.vertex_free(v, t as u32))
                {
                    res.reserve_path(&p, 0, park);
                    paths.push((p, park));
                }
            }
            let start_time = next(4) as u32;
            let max_time = next(30) as u32;
            let mut s = next(n) as VertexId;
            for _ in 0..20 {
                if res.vertex_free(s, start_time) {
                    break;
                }
                s = next(n) as VertexId;
            }
            let goal = next(n) as VertexId;
            (g, paths, s, goal, start_time, max_time)
        })
    }

    proptest! {
        /// SIPP finds a path exactly when space-time A* does, with the same arrival time, and
        /// its path obeys every reservation; [`earliest_arrival`] gives that arrival.
        #[test]
        fn sipp_matches_space_time_astar((g, paths, s, goal, t0, max_time) in case()) {
            let mut res = Reservations::new(g.num_vertices());
            for (p, park) in &paths {
                res.reserve_path(p, 0, *park);
            }
            let d = bfs_distances(&g, goal);
            let h = |v: VertexId| d[v as usize];
            let mut q = query(&g, s, goal, &h, max_time);
            q.start_time = t0;
            let a = space_time_astar(&q, &res);
            // The dense tables and the bucket queue draw the same path as the plain search.
            prop_assert_eq!(&a, &space_time_astar_plain(&q, &res));
            let b = sipp(&q, &res);
            let arrival = earliest_arrival(&q, &res);
            match &b {
                Search::Found(pb) => prop_assert_eq!(arrival, Ok(t0 + pb.len() as u32 - 1)),
                other => prop_assert_eq!(arrival, Err(other.clone())),
            }
            match (&a, &b) {
                (Search::Found(pa), Search::Found(pb)) => {
                    prop_assert_eq!(pa.len(), pb.len());
                    prop_assert_eq!(pb[0], s);
                    prop_assert_eq!(*pb.last().unwrap(), goal);
                    for (t, w) in pb.windows(2).enumerate() {
                        prop_assert!(w[0] == w[1] || g.neighbors(w[0]).contains(&w[1]));
                        let t = t0 + t as u32 + 1;
                        prop_assert!(res.move_free(w[0], w[1], t), "{pb:?} at {t}");
                    }
                    let arrival = t0 + pb.len() as u32 - 1;
                    prop_assert!(res.free_from(goal, arrival) && arrival <= max_time.max(t0));
                }
                (Search::NotFound, Search::NotFound) => {}
                _ => prop_assert!(false, "A* {a:?}, SIPP {b:?}"),
            }
        }

        /// [`sipp_loss`] finds a path whenever [`sipp`] does (within a loss bound of that
        /// path's loss), the path obeys every reservation and ends on the goal free for ever by
        /// `max_time`, and its loss is at most the bound.
        #[test]
        fn sipp_loss_finds_valid_paths((g, paths, s, goal, t0, max_time) in case()) {
            let mut res = Reservations::new(g.num_vertices());
            for (p, park) in &paths {
                res.reserve_path(p, 0, *park);
            }
            let d = bfs_distances(&g, goal);
            let h = |v: VertexId| d[v as usize];
            let mut q = query(&g, s, goal, &h, max_time);
            q.start_time = t0;
            let Search::Found(pe) = sipp(&q, &res) else {
                return Ok(());
            };
            let bound = crate::mapf::plan::path_loss(&pe, goal) as u32;
            let Search::Found(pl) = sipp_loss(&q, &res, bound) else {
                prop_assert!(false, "earliest-arrival path {pe:?} of loss {bound}, none by loss");
                unreachable!()
            };
            prop_assert_eq!(pl[0], s);
            prop_assert_eq!(*pl.last().unwrap(), goal);
            for (t, w) in pl.windows(2).enumerate() {
                prop_assert!(w[0] == w[1] || g.neighbors(w[0]).contains(&w[1]));
                let t = t0 + t as u32 + 1;
                prop_assert!(res.move_free(w[0], w[1], t), "{pl:?} at {t}");
            }
            let arrival = t0 + pl.len() as u32 - 1;
            prop_assert!(res.free_from(goal, arrival) && arrival <= max_time.max(t0));
            prop_assert!(crate::mapf::plan::path_loss(&pl, goal) <= u64::from(bound));
        }
    }
}
