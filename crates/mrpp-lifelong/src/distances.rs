//! Breadth-first distance tables to errand cells, built the first time a cell is asked for and
//! kept while they fit a memory budget (the start kit's default planner keeps one per target
//! too, `get_h` in `default_planner/heuristics.cpp`). Distances ignore orientation; the planners
//! add turns.
//!
//! A table takes 2 bytes per vertex (4 on graphs of 65,535 vertices or more). When the tables
//! would exceed the budget (default [`DEFAULT_BUDGET`]), the one used longest ago is dropped and
//! rebuilt when asked for again. [`Distances::warm`] builds tables ahead of a run (the kit's
//! preprocessing), within a deadline.

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

/// Distance tables by target vertex, least recently used dropped beyond the budget.
#[derive(Debug)]
pub struct Distances {
    tables: Vec<Option<(Table, u64)>>,
    live: Vec<VertexId>,
    max_tables: usize,
    clock: u64,
    built: usize,
}

impl Distances {
    /// No table yet, for a graph of `vertices` vertices, at most `budget` bytes of tables (at
    /// least one table).
    pub fn new(vertices: usize, budget: usize) -> Self {
        let per_table = vertices.max(1) * if vertices < u16::MAX as usize { 2 } else { 4 };
        Distances {
            tables: (0..vertices).map(|_| None).collect(),
            live: Vec::new(),
            max_tables: (budget / per_table).max(1),
            clock: 0,
            built: 0,
        }
    }

    /// Hop distance from `from` to `to` ([`UNREACHABLE`] in another component).
    pub fn get(&mut self, graph: &Graph, from: VertexId, to: VertexId) -> u32 {
        self.ensure(graph, to);
        self.tables[to as usize]
            .as_ref()
            .expect("built")
            .0
            .get(from)
    }

    /// Hop distances to `to` from each of `from`, in order (one table look-up).
    pub fn to(&mut self, graph: &Graph, to: VertexId, from: &[VertexId], out: &mut Vec<u32>) {
        self.ensure(graph, to);
        let table = &self.tables[to as usize].as_ref().expect("built").0;
        out.clear();
        out.extend(from.iter().map(|&v| table.get(v)));
    }

    /// Builds the tables of `targets` not built yet, in order, until one of `deadlines` passes or
    /// the budget is full (the kit's preprocessing); returns how many tables are live.
    pub fn warm(&mut self, graph: &Graph, targets: &[VertexId], deadlines: &[Deadline]) -> usize {
        for &t in targets {
            if self.live.len() >= self.max_tables || deadlines.iter().any(Deadline::expired) {
                break;
            }
            self.ensure(graph, t);
        }
        self.live.len()
    }

    /// Tables built so far (rebuilt ones counted again).
    pub fn built(&self) -> usize {
        self.built
    }

    fn ensure(&mut self, graph: &Graph, to: VertexId) {
        self.clock += 1;
        if let Some((_, used)) = &mut self.tables[to as usize] {
            *used = self.clock;
            return;
        }
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
        let table = Self::bfs(graph, to);
        self.tables[to as usize] = Some((table, self.clock));
        self.live.push(to);
        self.built += 1;
    }

    fn bfs(graph: &Graph, source: VertexId) -> Table {
        let dist = bfs_distances(graph, source);
        if graph.num_vertices() < u16::MAX as usize {
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
    use mrpp_mapf::GridMap;

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
        assert!(d.live.len() <= 2);
        assert!(d.built() > n);
    }
}
