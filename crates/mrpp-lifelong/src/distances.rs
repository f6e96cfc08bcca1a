//! Breadth-first distance tables to errand cells, built the first time a cell is asked for and
//! kept while they fit a memory budget (the start kit's default planner keeps one per target
//! too, `get_h` in `default_planner/heuristics.cpp`). [`Distances`] count moves and ignore
//! orientation; [`TurnDistances`] count `MAPF_T` actions (moves and quarter turns) from each
//! (cell, orientation) state.
//!
//! A table takes 2 bytes per vertex (4 on graphs of 65,535 vertices or more). When the tables
//! would exceed the budget (default [`DEFAULT_BUDGET`]), the one used longest ago is dropped and
//! rebuilt when asked for again. [`Distances::warm`] builds tables ahead of a run (the kit's
//! preprocessing), within a deadline.
//!
//! **Large maps.** A table costs a breadth-first search over the whole map. When the budget
//! cannot hold a table for each robot's next two errands, the tables are rebuilt over and over
//! (on the kit v3's `iron-example_10000`, 2.2 million free cells and 10,000 robots, calls took
//! 18-32 s instead of 1 s). [`TableKind`] (the lifelong planners' option `distance_tables`)
//! chooses: `exact` tables always, `manhattan` distances (|dx| + |dy|, a lower bound that needs
//! no search and ignores walls), or `auto`, exact unless the budget holds fewer tables than
//! twice the robots. The kit's default planner switches to Manhattan distances on every map of
//! more than 90,000 cells (`is_large_map`, `default_planner/utils.cpp`, v3.1.0); mrpp keeps exact
//! tables wherever they fit (e.g. brc202d, 254,930 cells), where they found more tasks.

use mrpp_core::Deadline;
use mrpp_core::mapf::graph::{Graph, VertexId};
use mrpp_core::mapf::search::distance::{UNREACHABLE, bfs_distances};

/// Default memory budget of the tables: 4 GiB.
pub const DEFAULT_BUDGET: usize = 4 << 30;

#[derive(Debug)]
enum Table {
    Narrow(Box<[u16]>),
    Wide(Box<[u32]>),
}

impl Table {
    fn get(&self, v: VertexId) -> u32 {
        match self {
            Table::Narrow(t) => match t[v as usize] {
                u16::MAX => UNREACHABLE,
                d => u32::from(d),
            },
            Table::Wide(t) => t[v as usize],
        }
    }
}

impl Table {
    /// A table of `dist` (entries [`UNREACHABLE`] or below `u16::MAX` when `narrow`).
    fn of(dist: Vec<u32>, narrow: bool) -> Table {
        if narrow {
            Table::Narrow(
                dist.into_iter()
                    .map(|d| if d == UNREACHABLE { u16::MAX } else { d as u16 })
                    .collect(),
            )
        } else {
            Table::Wide(dist.into_boxed_slice())
        }
    }
}

/// Tables by target vertex, the least recently used dropped beyond the budget.
#[derive(Debug)]
struct Cache {
    tables: Vec<Option<(Table, u64)>>,
    live: Vec<VertexId>,
    max_tables: usize,
    clock: u64,
    built: usize,
}

impl Cache {
    /// Room for `vertices` targets' tables of `entries` entries each within `budget` bytes (at
    /// least one table); `narrow` says whether entries take 2 bytes (else 4).
    fn new(vertices: usize, entries: usize, narrow: bool, budget: usize) -> Self {
        Cache {
            tables: (0..vertices).map(|_| None).collect(),
            live: Vec::new(),
            max_tables: Cache::capacity(entries, narrow, budget),
            clock: 0,
            built: 0,
        }
    }

    /// How many tables of `entries` entries (2 bytes each when `narrow`, else 4) fit in
    /// `budget` bytes, at least one.
    fn capacity(entries: usize, narrow: bool, budget: usize) -> usize {
        (budget / (entries.max(1) * if narrow { 2 } else { 4 })).max(1)
    }

    /// The table of `to`, built by `build` if it is not live.
    fn ensure(&mut self, to: VertexId, build: impl FnOnce() -> Table) -> &Table {
        self.clock += 1;
        if self.tables[to as usize].is_none() {
            if self.live.len() >= self.max_tables {
                let (pos, _) = self
                    .live
                    .iter()
                    .enumerate()
                    .min_by_key(|(_, v)| self.tables[**v as usize].as_ref().map_or(0, |t| t.1))
                    .expect("at least one table is live");
                let old = self.live.swap_remove(pos);
                self.tables[old as usize] = None;
            }
            self.tables[to as usize] = Some((build(), 0));
            self.live.push(to);
            self.built += 1;
        }
        let (table, used) = self.tables[to as usize].as_mut().expect("built");
        *used = self.clock;
        table
    }
}

/// How [`Distances`] measures (module doc, "Large maps"); the lifelong planners' option
/// `distance_tables`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TableKind {
    /// `Exact` when the budget holds tables for twice the robots, else `Manhattan`.
    Auto,
    /// Breadth-first tables, rebuilt least recently used first beyond the budget.
    Exact,
    /// |dx| + |dy| on the grid: no table, walls ignored.
    Manhattan,
}

impl TableKind {
    /// Whether a run of `robots` robots on a graph of `vertices` vertices uses exact tables
    /// within `budget` bytes.
    pub fn exact_for(self, vertices: usize, robots: usize, budget: usize) -> bool {
        match self {
            TableKind::Exact => true,
            TableKind::Manhattan => false,
            TableKind::Auto => Cache::capacity(vertices, narrow(vertices), budget) >= 2 * robots,
        }
    }
}

/// Whether hop tables of a graph of `vertices` vertices take 2-byte entries.
fn narrow(vertices: usize) -> bool {
    vertices < u16::MAX as usize
}

/// Hop-distance tables by target vertex, or Manhattan distances (module doc).
#[derive(Debug)]
pub struct Distances {
    /// The tables; `None`: Manhattan distances, no table.
    cache: Option<Cache>,
    narrow: bool,
}

impl Distances {
    /// No table yet, for a graph of `vertices` vertices, at most `budget` bytes of tables (at
    /// least one table).
    pub fn new(vertices: usize, budget: usize) -> Self {
        let narrow = narrow(vertices);
        Distances {
            cache: Some(Cache::new(vertices, vertices, narrow, budget)),
            narrow,
        }
    }

    /// Manhattan distances on a grid graph (|dx| + |dy|; 0 on a graph without coordinates): no
    /// table is ever built.
    pub fn manhattan() -> Self {
        Distances {
            cache: None,
            narrow: true,
        }
    }

    /// Exact tables within `budget` bytes or Manhattan distances, as `kind` says for `robots`
    /// robots on a graph of `vertices` vertices ([`TableKind::exact_for`]).
    pub fn of_kind(kind: TableKind, vertices: usize, robots: usize, budget: usize) -> Self {
        if kind.exact_for(vertices, robots, budget) {
            Distances::new(vertices, budget)
        } else {
            Distances::manhattan()
        }
    }

    /// Whether distances are exact hop counts (else Manhattan lower bounds).
    pub fn is_exact(&self) -> bool {
        self.cache.is_some()
    }

    /// Hop distance from `from` to `to` ([`UNREACHABLE`] in another component); the Manhattan
    /// distance in Manhattan mode.
    pub fn get(&mut self, graph: &Graph, from: VertexId, to: VertexId) -> u32 {
        match self.table(graph, to) {
            Some(t) => t.get(from),
            None => graph.manhattan(from, to),
        }
    }

    /// Hop distances to `to` from each of `from`, in order (one table look-up).
    pub fn to(&mut self, graph: &Graph, to: VertexId, from: &[VertexId], out: &mut Vec<u32>) {
        out.clear();
        match self.table(graph, to) {
            Some(t) => out.extend(from.iter().map(|&v| t.get(v))),
            None => out.extend(from.iter().map(|&v| graph.manhattan(v, to))),
        }
    }

    /// Builds the tables of `targets` not built yet, in order, until one of `deadlines` passes or
    /// the budget is full (the kit's preprocessing); returns how many tables are live (0 in
    /// Manhattan mode).
    pub fn warm(&mut self, graph: &Graph, targets: &[VertexId], deadlines: &[Deadline]) -> usize {
        let Some(cache) = self.cache.as_mut() else {
            return 0;
        };
        let narrow = self.narrow;
        for &t in targets {
            if cache.live.len() >= cache.max_tables || deadlines.iter().any(Deadline::expired) {
                break;
            }
            cache.ensure(t, || Table::of(bfs_distances(graph, t), narrow));
        }
        cache.live.len()
    }

    /// Tables built so far (rebuilt ones counted again; 0 in Manhattan mode).
    pub fn built(&self) -> usize {
        self.cache.as_ref().map_or(0, |c| c.built)
    }

    /// The table of `to` (built if needed), or `None` in Manhattan mode.
    fn table(&mut self, graph: &Graph, to: VertexId) -> Option<&Table> {
        let narrow = self.narrow;
        let cache = self.cache.as_mut()?;
        Some(cache.ensure(to, || Table::of(bfs_distances(graph, to), narrow)))
    }
}

/// Rotation-aware distance tables by target vertex: the fewest `MAPF_T` actions (forward one
/// cell, or a quarter turn) from each (cell, orientation) state until the robot stands on the
/// target, facing any way. Built by a breadth-first search backwards from the target's four
/// states, kept like [`Distances`]' tables (4 entries per vertex).
#[derive(Debug)]
pub struct TurnDistances {
    cache: Cache,
    narrow: bool,
    /// Neighbour of each vertex in each direction (0 east, 1 south, 2 west, 3 north).
    next: Vec<[VertexId; 4]>,
}

impl TurnDistances {
    /// No table yet for `map`, at most `budget` bytes of tables.
    pub fn new(map: &mrpp_mapf::GridMap, budget: usize) -> Self {
        let n = map.graph().num_vertices();
        let narrow = 4 * n < u16::MAX as usize;
        TurnDistances {
            cache: Cache::new(n, 4 * n, narrow, budget),
            narrow,
            next: (0..n as VertexId)
                .map(|v| {
                    std::array::from_fn(|d| {
                        crate::model::neighbour(map, v, d as u8).unwrap_or(VertexId::MAX)
                    })
                })
                .collect(),
        }
    }

    /// Builds the tables of `targets` not built yet, in order, until one of `deadlines` passes or
    /// the budget is full; returns how many tables are live.
    pub fn warm(&mut self, targets: &[VertexId], deadlines: &[Deadline]) -> usize {
        for &t in targets {
            if self.cache.live.len() >= self.cache.max_tables
                || deadlines.iter().any(Deadline::expired)
            {
                break;
            }
            let (narrow, next) = (self.narrow, &self.next);
            self.cache
                .ensure(t, || Table::of(turn_bfs(next, t), narrow));
        }
        self.cache.live.len()
    }

    /// Whether the table of `to` is built (so [`Self::get`] for `to` is a look-up).
    pub fn has(&self, to: VertexId) -> bool {
        self.cache.tables[to as usize].is_some()
    }

    /// Actions from `v` facing `o` until standing on `to` ([`UNREACHABLE`] in another component).
    pub fn get(&mut self, v: VertexId, o: u8, to: VertexId) -> u32 {
        let (narrow, next) = (self.narrow, &self.next);
        self.cache
            .ensure(to, || Table::of(turn_bfs(next, to), narrow))
            .get(4 * v + u32::from(o))
    }
}

/// Backward breadth-first search over (vertex, orientation) states from `to`'s four states:
/// entry `4 v + o` is the fewest actions from (v, o) to `to`.
fn turn_bfs(next: &[[VertexId; 4]], to: VertexId) -> Vec<u32> {
    let mut dist = vec![UNREACHABLE; 4 * next.len()];
    let mut queue = std::collections::VecDeque::new();
    for o in 0..4 {
        dist[4 * to as usize + o] = 0;
        queue.push_back((to, o));
    }
    while let Some((v, o)) = queue.pop_front() {
        let d = dist[4 * v as usize + o] + 1;
        // Predecessors: the cell behind (forward into v facing o), and the two turns into o.
        let behind = next[v as usize][(o + 2) % 4];
        let mut visit = |u: VertexId, p: usize| {
            let slot = &mut dist[4 * u as usize + p];
            if *slot == UNREACHABLE {
                *slot = d;
                queue.push_back((u, p));
            }
        };
        if behind != VertexId::MAX {
            visit(behind, o);
        }
        visit(v, (o + 3) % 4);
        visit(v, (o + 1) % 4);
    }
    dist
}

/// A distance that may be [`UNREACHABLE`], plus `extra`, without overflow.
pub fn plus(d: u32, extra: u32) -> u32 {
    if d == UNREACHABLE {
        UNREACHABLE
    } else {
        d.saturating_add(extra)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Action, State, apply};
    use mrpp_mapf::GridMap;

    #[test]
    fn turn_tables_agree_with_a_forward_search_over_actions() {
        let map = GridMap::from_free_rows(&[
            vec![true, true, true, false, true],
            vec![true, false, true, true, true],
            vec![true, true, true, false, true],
        ]);
        let n = map.graph().num_vertices() as VertexId;
        // Room for two tables: eviction is exercised too.
        let mut d = TurnDistances::new(&map, 2 * 4 * n as usize * 2);
        for to in 0..n {
            for v in 0..n {
                for o in 0..4u8 {
                    // Forward breadth-first search from (v, o) with the model's own actions.
                    let start = State {
                        vertex: v,
                        orientation: o,
                    };
                    let mut seen = std::collections::HashMap::from([(start, 0u32)]);
                    let mut queue = std::collections::VecDeque::from([start]);
                    let mut truth = UNREACHABLE;
                    while let Some(s) = queue.pop_front() {
                        if s.vertex == to {
                            truth = seen[&s];
                            break;
                        }
                        for a in [Action::Forward, Action::Clockwise, Action::CounterClockwise] {
                            if let Some(t) = apply(&map, s, a)
                                && !seen.contains_key(&t)
                            {
                                seen.insert(t, seen[&s] + 1);
                                queue.push_back(t);
                            }
                        }
                    }
                    assert_eq!(d.get(v, o, to), truth, "from ({v}, {o}) to {to}");
                }
            }
        }
        assert!(d.cache.live.len() <= 2 && d.cache.built == n as usize);
    }

    #[test]
    fn tables_agree_with_bfs_under_eviction() {
        let map = GridMap::from_free_rows(&[
            vec![true, true, true, false],
            vec![true, false, true, true],
            vec![true, true, true, false],
        ]);
        let g = map.graph();
        let n = g.num_vertices();
        // Room for two tables only.
        let mut d = Distances::new(n, 2 * 2 * n);
        for round in 0..3 {
            for to in 0..n as VertexId {
                let truth = bfs_distances(g, to);
                for from in 0..n as VertexId {
                    assert_eq!(d.get(g, from, to), truth[from as usize], "round {round}");
                }
            }
        }
        assert!(d.cache.as_ref().unwrap().live.len() <= 2);
        assert!(d.built() > n);
    }

    #[test]
    fn auto_keeps_exact_tables_while_twice_the_robots_fit_and_manhattan_needs_no_table() {
        // 1,000 vertices: 2-byte entries, 2,000 bytes a table.
        assert!(TableKind::Auto.exact_for(1000, 50, 200_000));
        assert!(!TableKind::Auto.exact_for(1000, 51, 200_000));
        assert!(TableKind::Exact.exact_for(1000, 51, 200_000));
        assert!(!TableKind::Manhattan.exact_for(1000, 1, usize::MAX));
        // The kit v3's iron_harvest: 2.2 million vertices, 10,000 robots, 4 GiB.
        assert!(!TableKind::Auto.exact_for(2_217_759, 10_000, DEFAULT_BUDGET));
        let map = GridMap::from_free_rows(&[
            vec![true, true, true, true],
            vec![true, false, false, true],
            vec![true, true, true, true],
        ]);
        let g = map.graph();
        let mut d = Distances::of_kind(TableKind::Manhattan, g.num_vertices(), 1, 1 << 20);
        assert!(!d.is_exact());
        let (a, b) = (map.vertex_at(1, 0).unwrap(), map.vertex_at(1, 2).unwrap());
        // The wall between them is ignored: 2, where the hop distance is 4.
        assert_eq!(d.get(g, a, b), 2);
        assert_eq!(bfs_distances(g, b)[a as usize], 4);
        let mut out = Vec::new();
        d.to(g, b, &[a, b], &mut out);
        assert_eq!(out, [2, 0]);
        assert_eq!(d.warm(g, &[a, b], &[]), 0);
        assert_eq!(d.built(), 0);
    }
}
