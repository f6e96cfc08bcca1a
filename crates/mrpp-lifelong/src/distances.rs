//! Breadth-first distance tables to errand cells, built the first time a cell is asked for and
//! kept for the run (the start kit's default planner keeps one per target too, `get_h` in
//! `default_planner/heuristics.cpp`). Distances ignore orientation; the planners add turns.

use mrpp_core::mapf::graph::{Graph, VertexId};
use mrpp_core::mapf::search::distance::{UNREACHABLE, bfs_distances};

/// Distance tables by target vertex.
#[derive(Debug, Default)]
pub struct Distances {
    tables: Vec<Option<Box<[u32]>>>,
    built: usize,
}

impl Distances {
    /// No table yet, for a graph of `vertices` vertices.
    pub fn new(vertices: usize) -> Self {
        Distances {
            tables: vec![None; vertices],
            built: 0,
        }
    }

    /// Hop distance from `from` to `to` ([`UNREACHABLE`] in another component).
    pub fn get(&mut self, graph: &Graph, from: VertexId, to: VertexId) -> u32 {
        self.table(graph, to)[from as usize]
    }

    /// The table of distances to `to`, indexed by vertex.
    pub fn table(&mut self, graph: &Graph, to: VertexId) -> &[u32] {
        let slot = &mut self.tables[to as usize];
        if slot.is_none() {
            *slot = Some(bfs_distances(graph, to).into_boxed_slice());
            self.built += 1;
        }
        slot.as_deref().expect("just built")
    }

    /// Tables built so far.
    pub fn built(&self) -> usize {
        self.built
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
