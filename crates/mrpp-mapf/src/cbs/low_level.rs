//! CBS's low level: one agent's space-time search under its constraints, with a focal list
//! (Pearl and Kim's A*_ε, as ECBS uses it) that prefers paths with fewer conflicts with the other
//! agents' current paths. With weight `w = 1` the focal list holds exactly the nodes of minimal
//! `f`, which makes it A* with conflict-avoidance tie-breaking, the low level of CBS.
//!
//! Rules are the validator's (stay semantics, following allowed): a state is `(vertex, t)`; moves
//! and waits cost 1; an agent's cost is the step at which it reaches its goal for good, so the goal
//! counts only after the last vertex constraint on it.

use std::collections::BTreeSet;

use rustc_hash::{FxHashMap, FxHashSet};

use mrpp_core::mapf::search::distance::{UNREACHABLE, bfs_distances_avoiding};
use mrpp_core::{Deadline, Graph, VertexId};

/// A CBS constraint on one agent.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Constraint {
    /// The agent is not at `v` at time `t`.
    Vertex { v: VertexId, t: u32 },
    /// The agent does not move from `u` (at `t - 1`) to `v` (at `t`).
    Edge { u: VertexId, v: VertexId, t: u32 },
    /// Disjoint splitting: the agent is at `v` at time `t` (and every other agent is not).
    AtVertex { v: VertexId, t: u32 },
    /// Disjoint splitting: the agent moves from `u` to `v` at time `t` (and no other agent is at
    /// `u` at `t - 1`, at `v` at `t`, or moves `v -> u` at `t`).
    Traverses { u: VertexId, v: VertexId, t: u32 },
    /// Target reasoning: the agent's path ends on its goal `goal` by time `t` (its cost is at most
    /// `t`), so from `t` on it stands there and no other agent may be at `goal` (CBSH2-RTC's
    /// length constraint `l <= t`; Li et al., ICAPS 2020).
    FinishBy { goal: VertexId, t: u32 },
    /// Target reasoning: the agent's cost is more than `t` (it is not on its goal for good by
    /// `t`; it may pass it earlier). Checked on the path's length, so a path that reaches the
    /// goal by `t` and waits there past `t` obeys it too: the two branches of a target split may
    /// share solutions (sound, not disjoint; CBSH2-RTC's low level refuses arrivals by a wait on
    /// the goal, which needs the wait in the search state; not done here).
    FinishAfter { t: u32 },
    /// Implied by another agent's [`Constraint::FinishBy`]: the agent is not at `v` at any time
    /// from `t` on.
    VertexFrom { v: VertexId, t: u32 },
    /// Rectangle reasoning's barrier (Li, Harabor, Stuckey, Ma, Koenig, AAAI 2019): the agent is
    /// not at the `k`-th cell of a straight run of grid cells at time `t + k`, for `k` in
    /// `0..len`. The run starts at grid cell `(x, y)` and goes one cell per step along `dir`
    /// (0: +x, 1: -x, 2: +y, 3: -y); blocked cells are skipped. It needs the grid to be read, so
    /// CBS turns it into [`Constraint::Vertex`] constraints before any search sees it
    /// ([`Constraint::barrier_cells`]); [`Constraint::holds_on`] and [`Constraints::new`] never
    /// see one.
    Barrier {
        x: u32,
        y: u32,
        t: u32,
        len: u16,
        dir: u8,
    },
}

impl Constraint {
    /// The negative constraints a positive constraint of another agent implies (none for a
    /// negative one).
    pub fn implied_for_others(&self) -> Vec<Constraint> {
        match *self {
            Constraint::AtVertex { v, t } => vec![Constraint::Vertex { v, t }],
            Constraint::Traverses { u, v, t } => vec![
                Constraint::Vertex { v: u, t: t - 1 },
                Constraint::Vertex { v, t },
                Constraint::Edge { u: v, v: u, t },
            ],
            Constraint::FinishBy { goal, t } => vec![Constraint::VertexFrom { v: goal, t }],
            _ => Vec::new(),
        }
    }

    /// The `(x, y, t)` grid cells and times of a [`Constraint::Barrier`] (empty for any other
    /// constraint); cells off the grid's non-negative quadrant end the run.
    pub fn barrier_cells(&self) -> Vec<(u32, u32, u32)> {
        let Constraint::Barrier { x, y, t, len, dir } = *self else {
            return Vec::new();
        };
        let (dx, dy): (i64, i64) = [(1, 0), (-1, 0), (0, 1), (0, -1)][dir as usize & 3];
        (0..i64::from(len))
            .map_while(|k| {
                let (cx, cy) = (i64::from(x) + dx * k, i64::from(y) + dy * k);
                (cx >= 0 && cy >= 0).then(|| (cx as u32, cy as u32, t + k as u32))
            })
            .collect()
    }

    /// Whether `path` (stay semantics: the agent rests on its last vertex) obeys this constraint.
    /// A [`Constraint::Barrier`] is taken as obeyed (it is checked as its vertex constraints).
    pub fn holds_on(&self, path: &[VertexId]) -> bool {
        let at = |t: u32| path[(t as usize).min(path.len() - 1)];
        match *self {
            Constraint::Vertex { v, t } => at(t) != v,
            Constraint::Edge { u, v, t } => t == 0 || !(at(t - 1) == u && at(t) == v),
            Constraint::AtVertex { v, t } => at(t) == v,
            Constraint::Traverses { u, v, t } => t > 0 && at(t - 1) == u && at(t) == v,
            Constraint::FinishBy { t, .. } => path.len() - 1 <= t as usize,
            Constraint::FinishAfter { t } => path.len() - 1 > t as usize,
            Constraint::VertexFrom { v, t } => {
                path.iter().skip(t as usize).all(|&x| x != v) && at(t) != v
            }
            Constraint::Barrier { .. } => true,
        }
    }
}

/// The constraints of one agent, indexed for the search.
#[derive(Debug, Default)]
pub struct Constraints {
    vertices: FxHashSet<(VertexId, u32)>,
    edges: FxHashSet<(VertexId, VertexId, u32)>,
    /// Where the agent must be when (its positive constraints), by time.
    landmarks: Vec<(u32, VertexId)>,
    /// Latest constrained time step (0 when none).
    pub last_t: u32,
    /// Latest vertex constraint on the goal, if any (or `t` of a [`Constraint::FinishAfter`]).
    goal_last: Option<u32>,
    /// The time by which the agent must be on its goal for good ([`Constraint::FinishBy`]).
    finish_by: Option<u32>,
    /// Vertices the agent may not be at from a time on ([`Constraint::VertexFrom`]).
    forbidden_from: Vec<(VertexId, u32)>,
    /// Whether a [`Constraint::VertexFrom`] is on the agent's own goal (then it never finishes).
    goal_blocked: bool,
}

impl Constraints {
    /// Indexes `list` for an agent going to `goal`.
    pub fn new<'a>(goal: VertexId, list: impl IntoIterator<Item = &'a Constraint>) -> Self {
        let mut c = Constraints::default();
        for &k in list {
            match k {
                Constraint::Vertex { v, t } => {
                    c.vertices.insert((v, t));
                    if v == goal {
                        c.goal_last = Some(c.goal_last.map_or(t, |g| g.max(t)));
                    }
                    c.last_t = c.last_t.max(t);
                }
                Constraint::Edge { u, v, t } => {
                    c.edges.insert((u, v, t));
                    c.last_t = c.last_t.max(t);
                }
                Constraint::AtVertex { v, t } => {
                    c.landmarks.push((t, v));
                    c.last_t = c.last_t.max(t);
                }
                Constraint::Traverses { u, v, t } => {
                    c.landmarks.push((t - 1, u));
                    c.landmarks.push((t, v));
                    c.last_t = c.last_t.max(t);
                }
                Constraint::FinishBy { t, .. } => {
                    c.finish_by = Some(c.finish_by.map_or(t, |f| f.min(t)));
                    c.last_t = c.last_t.max(t);
                }
                Constraint::FinishAfter { t } => {
                    c.goal_last = Some(c.goal_last.map_or(t, |g| g.max(t)));
                    c.last_t = c.last_t.max(t);
                }
                Constraint::VertexFrom { v, t } => {
                    c.forbidden_from.push((v, t));
                    c.goal_blocked |= v == goal;
                    c.last_t = c.last_t.max(t);
                }
                // Turned into vertex constraints by CBS before a search (variant doc).
                Constraint::Barrier { .. } => {}
            }
        }
        c.landmarks.sort_unstable();
        c.landmarks.dedup();
        c
    }

    /// Whether moving (or waiting) from `u` at `t - 1` to `v` at `t` is allowed.
    pub fn allows(&self, u: VertexId, v: VertexId, t: u32) -> bool {
        !self.vertices.contains(&(v, t))
            && !self.edges.contains(&(u, v, t))
            && self.landmark_at(t).is_none_or(|l| l == v)
            && self
                .forbidden_from
                .iter()
                .all(|&(x, from)| x != v || t < from)
    }

    /// Where the agent must be at `t`, if a positive constraint says.
    fn landmark_at(&self, t: u32) -> Option<VertexId> {
        self.landmarks
            .binary_search_by_key(&t, |&(tl, _)| tl)
            .ok()
            .map(|k| self.landmarks[k].1)
    }

    /// The first landmark at or after `t`.
    fn next_landmark(&self, t: u32) -> Option<(u32, VertexId)> {
        let k = self.landmarks.partition_point(|&(tl, _)| tl < t);
        self.landmarks.get(k).copied()
    }

    /// The last landmark's time (0 when none).
    fn last_landmark(&self) -> Option<(u32, VertexId)> {
        self.landmarks.last().copied()
    }

    /// Whether an agent standing on its goal at `t` may stay there for good.
    pub fn goal_free_from(&self, t: u32) -> bool {
        !self.goal_blocked
            && self.goal_last.is_none_or(|g| g < t)
            && self.finish_by.is_none_or(|f| t <= f)
    }
}

/// Where the other agents are: the conflict-avoidance table a search consults to count the
/// conflicts of a move.
#[derive(Debug, Default)]
pub struct AvoidanceTable {
    at: FxHashMap<(VertexId, u32), u32>,
    moves: FxHashMap<(VertexId, VertexId, u32), u32>,
    /// Vertex → earliest time from which some agent rests there for good (and how many).
    parked: FxHashMap<VertexId, Vec<u32>>,
}

impl AvoidanceTable {
    /// The table of `paths` except agent `skip`'s.
    pub fn new(paths: &[std::sync::Arc<Vec<VertexId>>], skip: usize) -> Self {
        // Sized for every entry at once: growing the maps one rehash at a time took a quarter
        // of CBS's time on den520d with 100 agents.
        let entries: usize = paths.iter().map(|p| p.len()).sum();
        let mut t = AvoidanceTable {
            at: FxHashMap::with_capacity_and_hasher(entries, Default::default()),
            moves: FxHashMap::with_capacity_and_hasher(entries, Default::default()),
            parked: FxHashMap::with_capacity_and_hasher(paths.len(), Default::default()),
        };
        for (j, p) in paths.iter().enumerate() {
            if j == skip || p.is_empty() {
                continue;
            }
            for (k, &v) in p.iter().enumerate() {
                *t.at.entry((v, k as u32)).or_default() += 1;
                if k > 0 && p[k - 1] != v {
                    *t.moves.entry((p[k - 1], v, k as u32)).or_default() += 1;
                }
            }
            let end = p.len() as u32 - 1;
            t.parked.entry(p[p.len() - 1]).or_default().push(end);
        }
        t
    }

    /// Conflicts of moving from `u` at `t - 1` to `v` at `t`.
    fn conflicts(&self, u: VertexId, v: VertexId, t: u32) -> u32 {
        let mut c = self.at.get(&(v, t)).copied().unwrap_or(0);
        if let Some(ends) = self.parked.get(&v) {
            c += ends.iter().filter(|&&e| e < t).count() as u32;
        }
        if u != v {
            c += self.moves.get(&(v, u, t)).copied().unwrap_or(0);
        }
        c
    }
}

/// One agent's query.
pub struct Query<'a> {
    pub graph: &'a Graph,
    pub start: VertexId,
    pub goal: VertexId,
    /// Distance to the goal of every vertex (the heuristic; `u32::MAX` = unreachable).
    pub h: &'a dyn Fn(VertexId) -> u32,
    pub constraints: &'a Constraints,
    pub avoid: &'a AvoidanceTable,
    /// Focal weight (>= 1; 1 = A*).
    pub w: f64,
    pub deadline: Deadline,
    /// Distances around the agent's [`Constraint::VertexFrom`] walls, shared between calls
    /// ([`BlockedCache`]; `None`: computed for this call alone).
    pub blocked: Option<&'a std::cell::RefCell<BlockedCache>>,
}

/// Goal distances around walls, by the goal and the sorted wall vertices: the same walls recur
/// in most calls under one constraint-tree branch, and each table is a breadth-first search of
/// the whole graph (15% of CBS's time on den520d with 100 agents before it was kept). Emptied
/// when it holds [`BlockedCache::BYTES`] of tables.
#[derive(Debug, Default)]
pub struct BlockedCache {
    tables: FxHashMap<(VertexId, Vec<VertexId>), std::rc::Rc<Vec<u32>>>,
    bytes: usize,
}

impl BlockedCache {
    /// Most bytes of tables kept at once.
    pub const BYTES: usize = 64 << 20;
}

/// A found path and the lower bound on the agent's cost the search proved (`f_min`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Found {
    pub path: Vec<VertexId>,
    pub lower_bound: u64,
}

/// Why no path came back.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoPath {
    /// No path satisfies the constraints.
    None,
    TimedOut,
}

struct Node {
    v: VertexId,
    t: u32,
    g: u32,
    f: u32,
    conflicts: u32,
    parent: u32,
    closed: bool,
}

/// The search's heuristic at `(v, t)`: the distance to the goal, or more when the last landmark
/// must still be reached in time and the goal after it (`u32::MAX`: unreachable).
fn landmark_h(q: &Query, blocked: &Blocked, v: VertexId, t: u32) -> u32 {
    let mut hv = (q.h)(v);
    if let Some((from, d)) = blocked
        && t >= *from
        && hv != u32::MAX
    {
        hv = hv.max(d[v as usize]);
    }
    // The agent cannot stay on its goal before its last constraint there is past (EECBS's
    // holding time, Li et al. AAAI 2021's code): without this bound a goal constraint far in
    // the future made A* expand every state whose distance-only `f` was below the arrival.
    if let Some(g) = q.constraints.goal_last
        && hv != u32::MAX
        && g >= t
    {
        hv = hv.max(g + 1 - t);
    }
    // A state that cannot be on the goal by the finish time is dead (`g = t` here: every
    // action costs 1).
    if let Some(f) = q.constraints.finish_by
        && hv != u32::MAX
        && t.saturating_add(hv) > f
    {
        return u32::MAX;
    }
    match q.constraints.last_landmark() {
        Some((tl, vl)) if tl >= t && hv != u32::MAX => {
            let hl = (q.h)(vl);
            if hl == u32::MAX {
                u32::MAX
            } else {
                hv.max(tl - t + hl)
            }
        }
        _ => hv,
    }
}

/// Distances to the goal avoiding every vertex of the agent's [`Constraint::VertexFrom`]
/// constraints, and the time from which all of them hold (`None` without such constraints).
/// From then on they are walls: a state that cannot reach the goal around them is dead, which
/// spares the search every later time step when another agent's finished goal cuts it off (it
/// used to expand every (vertex, time) up to its horizon to prove that).
type Blocked = Option<(u32, std::rc::Rc<Vec<u32>>)>;

fn blocked_distances(q: &Query) -> Blocked {
    let c = q.constraints;
    let from = c.forbidden_from.iter().map(|&(_, t)| t).max()?;
    let mut walls: Vec<VertexId> = c.forbidden_from.iter().map(|&(v, _)| v).collect();
    walls.sort_unstable();
    walls.dedup();
    let Some(cache) = q.blocked else {
        return Some((from, std::rc::Rc::new(distances_around(q, &walls))));
    };
    let key = (q.goal, walls);
    if let Some(d) = cache.borrow().tables.get(&key) {
        return Some((from, d.clone()));
    }
    let d = std::rc::Rc::new(distances_around(q, &key.1));
    let mut cache = cache.borrow_mut();
    let size = d.len() * 4 + key.1.len() * 4;
    if cache.bytes + size > BlockedCache::BYTES {
        cache.tables.clear();
        cache.bytes = 0;
    }
    cache.bytes += size;
    cache.tables.insert(key, d.clone());
    Some((from, d))
}

/// Breadth-first distances to `q.goal` that never enter a vertex of `walls` (sorted; all
/// unreachable when the goal is one).
fn distances_around(q: &Query, walls: &[VertexId]) -> Vec<u32> {
    if walls.binary_search(&q.goal).is_ok() {
        return vec![UNREACHABLE; q.graph.num_vertices()];
    }
    bfs_distances_avoiding(q.graph, q.goal, |v| walls.binary_search(&v).is_ok())
}

/// Whether a state can still reach the next landmark in time (Manhattan distance: a lower bound
/// on grids, 0 elsewhere); a state that cannot is dead.
fn on_time(q: &Query, v: VertexId, t: u32) -> bool {
    q.constraints
        .next_landmark(t)
        .is_none_or(|(tl, vl)| q.graph.manhattan(v, vl) <= tl - t)
}

/// Focal search for one agent (module doc). The returned path costs at most `w` times the
/// returned lower bound, which is at most the agent's optimal cost under its constraints.
/// With `w = 1` it runs [`optimal_search`], which returns the same path.
pub fn focal_search(q: &Query) -> Result<Found, NoPath> {
    if q.w <= 1.0 {
        return optimal_search(q);
    }
    let c = q.constraints;
    if c.goal_blocked {
        return Err(NoPath::None);
    }
    let blocked = blocked_distances(q);
    let h = |v: VertexId, t: u32| landmark_h(q, &blocked, v, t);
    let on_time = |v: VertexId, t: u32| on_time(q, v, t);
    let h0 = h(q.start, 0);
    if h0 == u32::MAX || !c.allows(q.start, q.start, 0) || !on_time(q.start, 0) {
        return Err(NoPath::None);
    }
    let done_after = c.last_landmark().map_or(0, |(tl, _)| tl);
    // After the last constraint, any vertex reaches the goal within |V| steps.
    let max_t = q.constraints.last_t + q.graph.num_vertices() as u32 + 1;
    let mut nodes = vec![Node {
        v: q.start,
        t: 0,
        g: 0,
        f: h0,
        conflicts: 0,
        parent: u32::MAX,
        closed: false,
    }];
    let mut index: FxHashMap<(VertexId, u32), u32> = FxHashMap::default();
    index.insert((q.start, 0), 0);
    let mut open: BTreeSet<(u32, u32)> = BTreeSet::from([(h0, 0)]);
    // (conflicts, f, higher g first, id)
    let focal_key = |n: &Node, id: u32| (n.conflicts, n.f, u32::MAX - n.g, id);
    let mut focal: BTreeSet<(u32, u32, u32, u32)> = BTreeSet::from([focal_key(&nodes[0], 0)]);
    let bound_of = |f_min: u32| (f64::from(f_min) * q.w + 1e-9).floor() as u32;
    let mut f_min = h0;
    let mut expansions = 0u64;
    while let Some(&(_, _, _, id)) = focal.first() {
        expansions += 1;
        if expansions.is_multiple_of(1024) && q.deadline.expired() {
            return Err(NoPath::TimedOut);
        }
        focal.pop_first();
        let (v, t, g, f) = {
            let n = &nodes[id as usize];
            (n.v, n.t, n.g, n.f)
        };
        open.remove(&(f, id));
        nodes[id as usize].closed = true;
        if v == q.goal && q.constraints.goal_free_from(t) && t >= done_after {
            let mut path = Vec::with_capacity(t as usize + 1);
            let mut k = id;
            while k != u32::MAX {
                path.push(nodes[k as usize].v);
                k = nodes[k as usize].parent;
            }
            path.reverse();
            return Ok(Found {
                path,
                lower_bound: u64::from(f_min),
            });
        }
        if t < max_t {
            let nt = t + 1;
            for &w in std::iter::once(&v).chain(q.graph.neighbors(v)) {
                if !q.constraints.allows(v, w, nt) || !on_time(w, nt) {
                    continue;
                }
                let hw = h(w, nt);
                if hw == u32::MAX {
                    continue;
                }
                let (ng, nf) = (g + 1, g + 1 + hw);
                let nc = nodes[id as usize].conflicts + q.avoid.conflicts(v, w, nt);
                let bound = bound_of(f_min);
                match index.get(&(w, nt)) {
                    Some(&k) => {
                        let old = &nodes[k as usize];
                        if old.closed || (ng, nc) >= (old.g, old.conflicts) {
                            continue;
                        }
                        open.remove(&(old.f, k));
                        focal.remove(&focal_key(old, k));
                        let n = &mut nodes[k as usize];
                        (n.g, n.f, n.conflicts, n.parent) = (ng, nf, nc, id);
                        open.insert((nf, k));
                        if nf <= bound {
                            focal.insert(focal_key(&nodes[k as usize], k));
                        }
                    }
                    None => {
                        let k = nodes.len() as u32;
                        nodes.push(Node {
                            v: w,
                            t: nt,
                            g: ng,
                            f: nf,
                            conflicts: nc,
                            parent: id,
                            closed: false,
                        });
                        index.insert((w, nt), k);
                        open.insert((nf, k));
                        if nf <= bound {
                            focal.insert(focal_key(&nodes[k as usize], k));
                        }
                    }
                }
            }
        }
        // The lower bound rose: nodes now within w * f_min join the focal list.
        if let Some(&(new_min, _)) = open.first()
            && new_min > f_min
        {
            let (old_bound, new_bound) = (bound_of(f_min), bound_of(new_min));
            for &(f, k) in open.range((old_bound + 1, 0)..) {
                if f > new_bound {
                    break;
                }
                focal.insert(focal_key(&nodes[k as usize], k));
            }
            f_min = new_min;
        }
    }
    Err(NoPath::None)
}

/// [`focal_search`] with `w = 1`: A* over `(vertex, t)` whose open list is one binary heap on
/// `(f, conflicts, higher g first, id)`, which pops the node the focal list would (at `w = 1`
/// it holds exactly the nodes of least `f`, ordered by conflicts, then `f`, `g` and id). A node
/// reached again more cheaply, or as cheaply with fewer conflicts, is pushed again and its older
/// entry skipped when popped. CBS's low level, and the one its heuristics' two-agent searches
/// call thousands of times; the two ordered sets of the focal version cost about twice the time.
pub fn optimal_search(q: &Query) -> Result<Found, NoPath> {
    use std::cmp::Reverse;
    let c = q.constraints;
    if c.goal_blocked {
        return Err(NoPath::None);
    }
    let blocked = blocked_distances(q);
    let h0 = landmark_h(q, &blocked, q.start, 0);
    if h0 == u32::MAX || !c.allows(q.start, q.start, 0) || !on_time(q, q.start, 0) {
        return Err(NoPath::None);
    }
    let done_after = c.last_landmark().map_or(0, |(tl, _)| tl);
    let max_t = c.last_t + q.graph.num_vertices() as u32 + 1;
    let mut nodes = vec![Node {
        v: q.start,
        t: 0,
        g: 0,
        f: h0,
        conflicts: 0,
        parent: u32::MAX,
        closed: false,
    }];
    let mut index: FxHashMap<(VertexId, u32), u32> = FxHashMap::default();
    index.insert((q.start, 0), 0);
    let key = |n: &Node, id: u32| Reverse((n.f, n.conflicts, u32::MAX - n.g, id));
    let mut open = std::collections::BinaryHeap::from([key(&nodes[0], 0)]);
    let mut expansions = 0u64;
    while let Some(Reverse((f, conflicts, g_rev, id))) = open.pop() {
        {
            let n = &nodes[id as usize];
            if n.closed || (n.f, n.conflicts, u32::MAX - n.g) != (f, conflicts, g_rev) {
                continue;
            }
        }
        expansions += 1;
        if expansions.is_multiple_of(1024) && q.deadline.expired() {
            return Err(NoPath::TimedOut);
        }
        nodes[id as usize].closed = true;
        let (v, t, g) = {
            let n = &nodes[id as usize];
            (n.v, n.t, n.g)
        };
        if v == q.goal && c.goal_free_from(t) && t >= done_after {
            let mut path = Vec::with_capacity(t as usize + 1);
            let mut k = id;
            while k != u32::MAX {
                path.push(nodes[k as usize].v);
                k = nodes[k as usize].parent;
            }
            path.reverse();
            return Ok(Found {
                path,
                lower_bound: u64::from(f),
            });
        }
        if t >= max_t {
            continue;
        }
        let nt = t + 1;
        for &w in std::iter::once(&v).chain(q.graph.neighbors(v)) {
            if !c.allows(v, w, nt) || !on_time(q, w, nt) {
                continue;
            }
            let hw = landmark_h(q, &blocked, w, nt);
            if hw == u32::MAX {
                continue;
            }
            let (ng, nf) = (g + 1, g + 1 + hw);
            let nc = conflicts + q.avoid.conflicts(v, w, nt);
            let k = match index.get(&(w, nt)) {
                Some(&k) => {
                    let old = &nodes[k as usize];
                    if old.closed || (ng, nc) >= (old.g, old.conflicts) {
                        continue;
                    }
                    let n = &mut nodes[k as usize];
                    (n.g, n.f, n.conflicts, n.parent) = (ng, nf, nc, id);
                    k
                }
                None => {
                    let k = nodes.len() as u32;
                    nodes.push(Node {
                        v: w,
                        t: nt,
                        g: ng,
                        f: nf,
                        conflicts: nc,
                        parent: id,
                        closed: false,
                    });
                    index.insert((w, nt), k);
                    k
                }
            };
            open.push(key(&nodes[k as usize], k));
        }
    }
    Err(NoPath::None)
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrpp_core::mapf::search::distance::bfs_distances;

    #[test]
    fn a_goal_constraint_delays_arrival_and_an_edge_constraint_forces_a_wait() {
        // Path 0-1-2.
        let g = Graph::from_edges(3, &[(0, 1), (1, 2)]);
        let d = bfs_distances(&g, 2);
        let h = |v: VertexId| d[v as usize];
        let empty = AvoidanceTable::default();
        let run = |list: &[Constraint]| {
            let c = Constraints::new(2, list);
            focal_search(&Query {
                graph: &g,
                start: 0,
                goal: 2,
                h: &h,
                constraints: &c,
                avoid: &empty,
                w: 1.0,
                deadline: Deadline::none(),
                blocked: None,
            })
        };
        assert_eq!(run(&[]).unwrap().path, vec![0, 1, 2]);
        // Not on the goal at t = 4: the agent may pass earlier but must arrive after.
        assert_eq!(
            run(&[Constraint::Vertex { v: 2, t: 4 }])
                .unwrap()
                .path
                .len(),
            6
        );
        let p = run(&[Constraint::Edge { u: 0, v: 1, t: 1 }]).unwrap();
        assert_eq!(p.path, vec![0, 0, 1, 2]);
        assert_eq!(p.lower_bound, 3);
        assert_eq!(run(&[Constraint::Vertex { v: 0, t: 0 }]), Err(NoPath::None));
    }
}
