//! The corridor-compressed graph of the H* paper (§IV-A).
//!
//! Every maximal chain of cells with exactly two free neighbours becomes one node that keeps its
//! cells in order; every other cell (dead end, junction) is a node of its own. H* marks whole nodes
//! as occupied when a robot stands on any of their cells, so a robot never plans into a corridor
//! another robot is in. [`Corridors::route_length`] is A* on this graph: it moves from a node's end
//! straight to its other end (or to the goal inside it) in one weighted step.

use mrpp_core::mapf::graph::{Graph, VertexId};
use mrpp_core::mapf::search::buckets::BucketQueue;

/// Node id in the compressed graph.
pub type NodeId = u32;

/// Nodes of the compressed graph and where each cell sits in them.
#[derive(Debug, Clone)]
pub struct Corridors {
    node_of: Vec<NodeId>,
    /// A cell's place in its node's chain ([`ONE_CELL`] when the node is that cell alone).
    index_in_node: Vec<u32>,
    cells: Vec<Vec<VertexId>>,
}

/// [`Corridors`]' `index_in_node` of a cell that is a node by itself.
const ONE_CELL: u32 = u32::MAX;

/// The tables of [`Corridors::route_length`], kept between calls: best cost per cell stamped
/// with the call that set it, and the open list as buckets of equal `f` (a consistent bound
/// makes `f` never decrease along the search, so the least bucket is found by a cursor).
#[derive(Debug, Default)]
pub struct RouteScratch {
    /// Per cell: `call << 32 | best cost`, where `call` is the call that set it.
    best: Vec<u64>,
    call: u32,
    /// The `(g, cell)` entries keyed by `f - f0`.
    open: BucketQueue<(u32, VertexId)>,
    /// The blocked nodes the searches met (entered from a free neighbour, or the goal's node),
    /// appended by every call and cleared only by the caller: with the robot's own cell, they
    /// are the walls that kept a failed search from the goal.
    pub walls: Vec<NodeId>,
}

impl RouteScratch {
    fn begin(&mut self, num_vertices: usize) {
        if self.best.len() != num_vertices || self.call == u32::MAX {
            self.best = vec![0; num_vertices];
            self.call = 0;
        }
        self.call += 1;
        self.open.clear();
    }

    /// The id of the latest call (each call of [`Corridors::route_length`] that searches takes a
    /// new one).
    pub fn last_call(&self) -> u32 {
        self.call
    }

    /// Whether call `call` reached cell `v` at the end of a move (as long as no later call
    /// reached it too). A call that found no route without a limit reached every cell of the
    /// free region around its start that does not lie inside a corridor.
    pub fn reached_in(&self, v: VertexId, call: u32) -> bool {
        self.best
            .get(v as usize)
            .is_some_and(|&b| b >> 32 == u64::from(call))
    }

    #[inline]
    fn best(&self, v: VertexId) -> u32 {
        let b = self.best[v as usize];
        if b >> 32 == u64::from(self.call) {
            b as u32
        } else {
            u32::MAX
        }
    }

    #[inline]
    fn improve(&mut self, v: VertexId, cost: u32) {
        self.best[v as usize] = u64::from(self.call) << 32 | u64::from(cost);
    }
}

/// The tables of [`Corridors::cut_off`], kept between calls.
#[derive(Debug, Default)]
pub struct RegionScratch {
    /// Per cell: `call << 1 | side` of the last call that reached it.
    mark: Vec<u64>,
    call: u64,
    /// Per side (0: the sources', 1: the goal's): cells reached in order, and the blocked nodes met.
    reached: [Vec<VertexId>; 2],
    walls: [Vec<NodeId>; 2],
}

impl Corridors {
    /// Whether the goal is cut off from every cell of `sources`: the cells that are not `avoid`
    /// and lie in no node for which `blocked(node)` holds, connect none of `sources` to `goal`.
    /// Returns the blocked nodes around the side that ran out of cells (that side is walled in
    /// by them and `avoid`), or `None` when a source reaches the goal.
    ///
    /// This is the question a search of [`Corridors::route_length`] without a limit answers with
    /// `None` from each source (its routes enter no blocked node and never step on `avoid`), asked
    /// once for all sources with one breadth-first search from the sources and one from the goal,
    /// expanded in turn: a cut-off side is found after at most twice its size in cells, however
    /// large the other side.
    pub fn cut_off(
        &self,
        g: &Graph,
        sources: &[VertexId],
        goal: VertexId,
        avoid: VertexId,
        blocked: impl Fn(NodeId) -> bool,
        scratch: &mut RegionScratch,
    ) -> Option<Vec<NodeId>> {
        if sources.contains(&goal) {
            return None;
        }
        if scratch.mark.len() != g.num_vertices() {
            scratch.mark = vec![0; g.num_vertices()];
            scratch.call = 0;
        }
        scratch.call += 1;
        for side in 0..2 {
            scratch.reached[side].clear();
            scratch.walls[side].clear();
        }
        let starts: [&[VertexId]; 2] = [sources, std::slice::from_ref(&goal)];
        for (side, cells) in starts.into_iter().enumerate() {
            for &v in cells {
                if v != avoid {
                    // A start the other side holds is impossible: no source is the goal.
                    self.reach(scratch, side, v, &blocked);
                }
            }
        }
        let mut next = [0usize; 2];
        loop {
            for (side, at) in next.iter_mut().enumerate() {
                let Some(&u) = scratch.reached[side].get(*at) else {
                    return Some(std::mem::take(&mut scratch.walls[side]));
                };
                *at += 1;
                for &w in g.neighbors(u) {
                    if w != avoid && self.reach(scratch, side, w, &blocked) {
                        return None; // the two sides meet
                    }
                }
            }
        }
    }

    /// One step of [`Corridors::cut_off`]'s search on `side` into cell `w`: `true` when the other
    /// side has reached `w` (the sides meet); else `w` is queued, or its node, when blocked, is
    /// recorded as one of the side's walls (nothing when this side has reached `w` already).
    #[inline(always)]
    fn reach(
        &self,
        scratch: &mut RegionScratch,
        side: usize,
        w: VertexId,
        blocked: &impl Fn(NodeId) -> bool,
    ) -> bool {
        let mark = scratch.mark[w as usize];
        if mark >> 1 == scratch.call {
            return mark & 1 != side as u64;
        }
        let nw = self.node_of(w);
        if blocked(nw) {
            scratch.walls[side].push(nw);
        } else {
            scratch.mark[w as usize] = scratch.call << 1 | side as u64;
            scratch.reached[side].push(w);
        }
        false
    }

    /// Compresses `g`: chains of degree-2 vertices are merged in order. A closed ring of degree-2
    /// vertices (no junction at all) is cut at its lowest vertex id.
    pub fn build(g: &Graph) -> Self {
        Self::build_until(g, mrpp_core::Deadline::none()).expect("no deadline")
    }

    /// [`Corridors::build`], giving up (`None`) once `deadline` passes (polled every 65 536
    /// cells: a million-cell map takes tens of milliseconds).
    pub fn build_until(g: &Graph, deadline: mrpp_core::Deadline) -> Option<Self> {
        let n = g.num_vertices();
        let mut node_of = vec![u32::MAX; n];
        let mut index_in_node = vec![0u32; n];
        let mut cells: Vec<Vec<VertexId>> = Vec::new();
        let is_corridor = |v: VertexId| g.degree(v) == 2;
        for v in 0..n as VertexId {
            if v % 65_536 == 0 && deadline.expired() {
                return None;
            }
            if node_of[v as usize] != u32::MAX {
                continue;
            }
            let id = cells.len() as NodeId;
            if !is_corridor(v) {
                node_of[v as usize] = id;
                cells.push(vec![v]);
                continue;
            }
            // Walk both ways from v while the cells are corridor cells not yet taken.
            node_of[v as usize] = id;
            let mut halves: [Vec<VertexId>; 2] = [Vec::new(), Vec::new()];
            for (side, half) in halves.iter_mut().enumerate() {
                let mut prev = v;
                let mut cur = g.neighbors(v)[side];
                while is_corridor(cur) && node_of[cur as usize] == u32::MAX {
                    node_of[cur as usize] = id;
                    half.push(cur);
                    let next = g
                        .neighbors(cur)
                        .iter()
                        .copied()
                        .find(|&w| w != prev)
                        .unwrap_or(prev);
                    prev = cur;
                    cur = next;
                }
            }
            let [left, right] = halves;
            let mut chain: Vec<VertexId> = left.into_iter().rev().collect();
            chain.push(v);
            chain.extend(right);
            cells.push(chain);
        }
        for chain in &cells {
            for (i, &c) in chain.iter().enumerate() {
                index_in_node[c as usize] = if chain.len() == 1 { ONE_CELL } else { i as u32 };
            }
        }
        Some(Corridors {
            node_of,
            index_in_node,
            cells,
        })
    }

    pub fn num_nodes(&self) -> usize {
        self.cells.len()
    }
    #[inline]
    pub fn node_of(&self, v: VertexId) -> NodeId {
        self.node_of[v as usize]
    }
    /// The cells of a node, in corridor order.
    pub fn cells(&self, node: NodeId) -> &[VertexId] {
        &self.cells[node as usize]
    }

    /// Length of a shortest route from `from` to `goal` that enters no node for which
    /// `blocked(node)` holds and never steps on `avoid` (the robot's own cell, so routes cannot
    /// circle back through it), if one of at most `limit` steps exists (`None` otherwise, and
    /// when there is no route at all; `u32::MAX` = no limit).
    ///
    /// A* over node ends guided by `h`, a lower bound on the hop distance to `goal` that is
    /// consistent on the grid (`u32::MAX` = unreachable): the goal's breadth-first distances make
    /// a route with nothing in the way cost one expansion per node on it; the Manhattan distance
    /// also works (any consistent bound gives the same length, since only the length is
    /// returned). Edge costs are cell counts, at least the grid distance they cover, so the
    /// bound stays consistent on the compressed graph. A walk that keeps stepping one closer by
    /// `h` (`dive`) answers first when it reaches the goal: no route is shorter. `scratch` holds
    /// the search's tables between calls (no allocation per call once it has grown to the map).
    /// With the exact bound and a `limit`, a neighbour that cannot beat the best route so far
    /// costs no search at all.
    #[allow(clippy::too_many_arguments)]
    pub fn route_length(
        &self,
        g: &Graph,
        from: VertexId,
        goal: VertexId,
        avoid: VertexId,
        blocked: impl Fn(NodeId) -> bool,
        h: impl Fn(VertexId) -> u32,
        limit: u32,
        scratch: &mut RouteScratch,
    ) -> Option<u32> {
        if from == goal {
            return Some(0);
        }
        if from == avoid || blocked(self.node_of(from)) {
            return None;
        }
        if blocked(self.node_of(goal)) {
            scratch.walls.push(self.node_of(goal));
            return None;
        }
        let h0 = h(from);
        if h0 == u32::MAX || h0 > limit {
            return None;
        }
        if let Some(len) = self.dive(g, from, goal, avoid, &blocked, &h, h0) {
            return Some(len);
        }
        scratch.begin(g.num_vertices());
        scratch.improve(from, 0);
        scratch.open.push(0, (0, from));
        while let Some((_, (gu, u))) = scratch.open.pop() {
            if u == goal {
                return Some(gu);
            }
            if gu > scratch.best(u) {
                continue; // a stale entry: u was reached cheaper since
            }
            let nu = self.node_of(u);
            for &w in g.neighbors(u) {
                if w == avoid {
                    continue;
                }
                let nw = self.node_of(w);
                // Along our own corridor (only when starting inside it), or into an open node.
                if nw != nu && blocked(nw) {
                    scratch.walls.push(nw);
                    continue;
                }
                let Some((x, steps)) = self.walk(u, w, goal, avoid) else {
                    continue;
                };
                let gx = gu + steps;
                if gx >= scratch.best(x) {
                    continue;
                }
                let hx = h(x);
                if hx == u32::MAX || gx.saturating_add(hx) > limit {
                    continue;
                }
                scratch.improve(x, gx);
                scratch
                    .open
                    .push((gx + hx).saturating_sub(h0) as usize, (gx, x));
            }
        }
        None
    }

    /// A route of `h0` steps (the least possible) found without a search, if stepping each time
    /// to the first neighbour one step closer by `h` that the search could enter (not `avoid`,
    /// and in the current cell's node or in a node that is not blocked) reaches `goal`; `None`
    /// at a dead end. Most routes of the greedy stage have nothing in the way: one such walk
    /// replaces the search's expansions and queue. Within a corridor it visits the cells
    /// [`Corridors::walk`] steps over, so the route is one the search could take.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    fn dive(
        &self,
        g: &Graph,
        from: VertexId,
        goal: VertexId,
        avoid: VertexId,
        blocked: &impl Fn(NodeId) -> bool,
        h: &impl Fn(VertexId) -> u32,
        h0: u32,
    ) -> Option<u32> {
        let (mut x, mut hx) = (from, h0);
        'step: while x != goal {
            let nx = self.node_of(x);
            let closer = hx.checked_sub(1)?;
            for &w in g.neighbors(x) {
                if w == avoid || h(w) != closer {
                    continue;
                }
                let nw = self.node_of(w);
                if nw != nx && blocked(nw) {
                    continue;
                }
                (x, hx) = (w, closer);
                continue 'step;
            }
            return None;
        }
        // `h` is a lower bound, so no route is shorter than the `h0 - h(goal)` steps taken.
        Some(h0 - hx)
    }

    /// Steps from `u` into `w` and on along `w`'s corridor to its far end, stopping early at the
    /// goal. Returns the cell reached and the number of steps, or `None` if `avoid` is in the way.
    #[inline(always)]
    fn walk(
        &self,
        u: VertexId,
        w: VertexId,
        goal: VertexId,
        avoid: VertexId,
    ) -> Option<(VertexId, u32)> {
        let i = self.index_in_node[w as usize];
        if i == ONE_CELL || w == goal {
            return Some((w, 1));
        }
        let i = i as usize;
        let node = self.node_of(w);
        let chain = &self.cells[node as usize];
        // Direction: away from u (u is either outside the node or the previous cell of the chain).
        let forward = if self.node_of(u) == node {
            (self.index_in_node[u as usize] as usize) < i
        } else {
            i == 0
        };
        let mut steps = 1;
        let mut k = i;
        loop {
            let next = if forward {
                if k + 1 >= chain.len() {
                    break;
                }
                k + 1
            } else {
                if k == 0 {
                    break;
                }
                k - 1
            };
            let c = chain[next];
            if c == avoid {
                // The corridor is cut by the robot's own cell: only its part up to here is usable.
                return (chain[k] != u).then_some((chain[k], steps));
            }
            k = next;
            steps += 1;
            if c == goal {
                return Some((c, steps));
            }
        }
        Some((chain[k], steps))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::GridMap;
    use std::path::Path;

    fn map(text: &str) -> GridMap {
        GridMap::parse(text, Path::new("t.txt")).unwrap().0
    }

    #[test]
    fn corridor_is_one_node_in_order() {
        // A 1-wide corridor between two 2x2 rooms.
        let m = map("########\n#  ##  #\n#      #\n#  ##  #\n########");
        let c = Corridors::build(m.graph());
        let a = m.vertex_at(3, 2).unwrap();
        let b = m.vertex_at(4, 2).unwrap();
        assert_eq!(c.node_of(a), c.node_of(b));
        assert_eq!(c.cells(c.node_of(a)).len(), 2);
        let j = m.vertex_at(2, 2).unwrap();
        assert_ne!(c.node_of(j), c.node_of(a));
        // Nodes partition the cells, and consecutive cells of a node are adjacent.
        let total: usize = (0..c.num_nodes() as NodeId).map(|n| c.cells(n).len()).sum();
        assert_eq!(total, m.graph().num_vertices());
        for n in 0..c.num_nodes() as NodeId {
            for w in c.cells(n).windows(2) {
                assert!(m.graph().has_edge(w[0], w[1]));
            }
            assert!(c.cells(n).iter().all(|&v| c.node_of(v) == n));
        }
    }

    /// `route_length` with the Manhattan bound and with the goal's exact distances, which must
    /// agree (the bound only steers the search).
    fn route(
        c: &Corridors,
        g: &Graph,
        from: VertexId,
        goal: VertexId,
        avoid: VertexId,
        blocked: &dyn Fn(NodeId) -> bool,
    ) -> Option<u32> {
        let d = mrpp_core::mapf::search::distance::bfs_distances(g, goal);
        let mut scratch = RouteScratch::default();
        let by_manhattan = c.route_length(
            g,
            from,
            goal,
            avoid,
            blocked,
            |v| g.manhattan(v, goal),
            u32::MAX,
            &mut scratch,
        );
        let exact = |v: VertexId| d[v as usize];
        let by_distance =
            c.route_length(g, from, goal, avoid, blocked, exact, u32::MAX, &mut scratch);
        assert_eq!(
            by_manhattan, by_distance,
            "{from} -> {goal} avoiding {avoid}"
        );
        // A limit keeps exactly the routes that fit in it.
        if let Some(len) = by_manhattan {
            for limit in len.saturating_sub(2)..=len + 1 {
                let limited =
                    c.route_length(g, from, goal, avoid, blocked, exact, limit, &mut scratch);
                assert_eq!(limited, (len <= limit).then_some(len), "limit {limit}");
            }
        }
        by_manhattan
    }

    #[test]
    fn route_length_matches_bfs_and_respects_blocks() {
        let m = map("########\n#  ##  #\n#      #\n#  ##  #\n########");
        let g = m.graph();
        let c = Corridors::build(g);
        let from = m.vertex_at(1, 1).unwrap();
        let goal = m.vertex_at(6, 3).unwrap();
        let d = mrpp_core::mapf::search::distance::bfs_distances(g, goal);
        let none = |_: NodeId| false;
        assert_eq!(
            route(&c, g, from, goal, u32::MAX, &none),
            Some(d[from as usize])
        );
        // Every cell to every goal equals BFS when nothing is blocked.
        for s in 0..g.num_vertices() as VertexId {
            assert_eq!(
                route(&c, g, s, goal, u32::MAX, &none),
                Some(d[s as usize]),
                "from {s}"
            );
        }
        let corridor = c.node_of(m.vertex_at(3, 2).unwrap());
        let blocked = |n: NodeId| n == corridor;
        assert_eq!(route(&c, g, from, goal, u32::MAX, &blocked), None);
        // Starting inside the corridor with the cell behind us avoided.
        let inside = m.vertex_at(4, 2).unwrap();
        let behind = m.vertex_at(3, 2).unwrap();
        assert_eq!(
            route(&c, g, inside, goal, behind, &none),
            Some(d[inside as usize])
        );
        let left_goal = m.vertex_at(1, 1).unwrap();
        assert_eq!(route(&c, g, inside, left_goal, behind, &none), None);
    }

    /// Rooms, corridors, a dead end and a loop.
    fn rooms() -> GridMap {
        map("##########\n#   #    #\n# # # ## #\n#   #  # #\n## ### # #\n#        #\n##########")
    }

    #[test]
    fn cut_off_answers_as_the_unlimited_searches_and_its_walls_suffice() {
        // Corridors and dead ends (`rooms`), then open rooms with many junctions.
        let open_rooms = map(
            "##########\n#    #   #\n#    #   #\n#        #\n#### # ###\n#        #\n#  ##    #\n##########",
        );
        let mut x = 0x2545_f491_4f6c_dd1du64;
        let mut next = move |m: u64| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x % m
        };
        let (mut region, mut routes) = (RegionScratch::default(), RouteScratch::default());
        for m in [rooms(), open_rooms] {
            let g = m.graph();
            let c = Corridors::build(g);
            let nv = g.num_vertices() as VertexId;
            let mut no_route =
                |blocked: &dyn Fn(NodeId) -> bool, sources: &[VertexId], goal, avoid| {
                    sources.iter().all(|&s| {
                        c.route_length(
                            g,
                            s,
                            goal,
                            avoid,
                            blocked,
                            |v| g.manhattan(v, goal),
                            u32::MAX,
                            &mut routes,
                        )
                        .is_none()
                    })
                };
            let (mut cut, mut open) = (0, 0);
            for _ in 0..3000 {
                let taken: Vec<NodeId> = (0..c.num_nodes() as NodeId)
                    .filter(|_| next(100) < 25)
                    .collect();
                let blocked = |n: NodeId| taken.contains(&n);
                let avoid = next(u64::from(nv)) as VertexId;
                let goal = next(u64::from(nv)) as VertexId;
                if goal == avoid {
                    continue;
                }
                let sources: Vec<VertexId> = g
                    .neighbors(avoid)
                    .iter()
                    .copied()
                    .filter(|&v| !blocked(c.node_of(v)) && next(3) > 0)
                    .collect();
                let searched = no_route(&blocked, &sources, goal, avoid);
                let walls = c.cut_off(g, &sources, goal, avoid, blocked, &mut region);
                assert_eq!(
                    walls.is_some(),
                    searched,
                    "{sources:?} -> {goal} avoiding {avoid}, {taken:?}"
                );
                let Some(walls) = walls else {
                    open += 1;
                    continue;
                };
                // What a seal relies on: with the walls blocked, whatever else is, no source has
                // a route.
                assert!(walls.iter().all(|&w| blocked(w)));
                let extra: Vec<NodeId> = (0..c.num_nodes() as NodeId)
                    .filter(|&n| !c.cells(n).contains(&goal) && next(100) < 20)
                    .collect();
                let walls_and_more = |n: NodeId| walls.contains(&n) || extra.contains(&n);
                let sources: Vec<VertexId> = sources
                    .into_iter()
                    .filter(|&v| !walls_and_more(c.node_of(v)))
                    .collect();
                assert!(
                    no_route(&walls_and_more, &sources, goal, avoid),
                    "the walls {walls:?} with {extra:?} let {sources:?} reach {goal}"
                );
                cut += 1;
            }
            assert!(cut > 300 && open > 300, "{cut} cut off, {open} not");
        }
    }

    #[test]
    fn both_bounds_agree_under_every_single_blocked_node_and_avoided_cell() {
        let m = rooms();
        let g = m.graph();
        let c = Corridors::build(g);
        let nv = g.num_vertices() as VertexId;
        for blocked_node in (0..c.num_nodes() as NodeId).step_by(3) {
            let blocked = |n: NodeId| n == blocked_node;
            for from in (0..nv).step_by(2) {
                for goal in (0..nv).step_by(5) {
                    let avoid = g.neighbors(from).first().copied().unwrap_or(u32::MAX);
                    route(&c, g, from, goal, avoid, &blocked);
                    route(&c, g, from, goal, u32::MAX, &blocked);
                }
            }
        }
    }
}
