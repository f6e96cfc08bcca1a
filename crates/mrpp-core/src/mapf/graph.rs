//! A compact undirected graph in CSR form, shared by every planner family.
//!
//! Vertices are dense ids `0..n`. A graph built from a grid also carries each vertex's cell
//! `(x, y)` (x = column, y = row) so that messages and outputs can speak in cells.

/// Dense vertex id.
pub type VertexId = u32;

/// Undirected graph with sorted-by-insertion adjacency lists stored contiguously.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Graph {
    offsets: Vec<u32>,
    targets: Vec<VertexId>,
    coords: Option<Vec<(u32, u32)>>,
}

impl Graph {
    /// Builds a graph from per-vertex neighbour lists. Each undirected edge must appear in both
    /// lists; the order of each list is kept (planners use it as their tie-break order).
    pub fn from_adjacency(adj: &[Vec<VertexId>], coords: Option<Vec<(u32, u32)>>) -> Self {
        let mut offsets = Vec::with_capacity(adj.len() + 1);
        let mut targets = Vec::with_capacity(adj.iter().map(Vec::len).sum());
        offsets.push(0);
        for list in adj {
            targets.extend_from_slice(list);
            offsets.push(targets.len() as u32);
        }
        if let Some(c) = &coords {
            assert_eq!(c.len(), adj.len(), "one coordinate per vertex");
        }
        Graph {
            offsets,
            targets,
            coords,
        }
    }

    /// Builds a graph from compressed rows: vertex `v`'s neighbours are
    /// `targets[offsets[v]..offsets[v + 1]]` (so `offsets` has one entry more than vertices and
    /// starts at 0); `coords`, when given, has one cell per vertex. What large grid maps use: no
    /// list per vertex is allocated.
    pub fn from_csr(
        offsets: Vec<u32>,
        targets: Vec<VertexId>,
        coords: Option<Vec<(u32, u32)>>,
    ) -> Self {
        assert_eq!(offsets.first(), Some(&0), "offsets start at 0");
        assert_eq!(
            offsets.last().map(|&o| o as usize),
            Some(targets.len()),
            "offsets end at the target count"
        );
        if let Some(c) = &coords {
            assert_eq!(c.len() + 1, offsets.len(), "one coordinate per vertex");
        }
        Graph {
            offsets,
            targets,
            coords,
        }
    }

    /// Builds an undirected graph from an edge list over `n` vertices.
    pub fn from_edges(n: usize, edges: &[(VertexId, VertexId)]) -> Self {
        let mut adj = vec![Vec::new(); n];
        for &(u, v) in edges {
            adj[u as usize].push(v);
            adj[v as usize].push(u);
        }
        Graph::from_adjacency(&adj, None)
    }

    pub fn num_vertices(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Number of undirected edges.
    pub fn num_edges(&self) -> usize {
        self.targets.len() / 2
    }

    #[inline]
    pub fn neighbors(&self, v: VertexId) -> &[VertexId] {
        let v = v as usize;
        &self.targets[self.offsets[v] as usize..self.offsets[v + 1] as usize]
    }

    #[inline]
    pub fn degree(&self, v: VertexId) -> usize {
        self.neighbors(v).len()
    }

    pub fn has_edge(&self, u: VertexId, v: VertexId) -> bool {
        self.neighbors(u).contains(&v)
    }

    /// The cell of a vertex, when the graph came from a grid.
    pub fn coord(&self, v: VertexId) -> Option<(u32, u32)> {
        self.coords.as_ref().map(|c| c[v as usize])
    }

    /// Human-readable name of a vertex: `(x,y)` on grids, `#id` otherwise.
    pub fn label(&self, v: VertexId) -> String {
        match self.coord(v) {
            Some((x, y)) => format!("({x},{y})"),
            None => format!("#{v}"),
        }
    }

    /// Manhattan distance between two grid vertices (0 on graphs without coordinates).
    #[inline]
    pub fn manhattan(&self, a: VertexId, b: VertexId) -> u32 {
        match &self.coords {
            Some(c) => {
                let (ax, ay) = c[a as usize];
                let (bx, by) = c[b as usize];
                ax.abs_diff(bx) + ay.abs_diff(by)
            }
            None => 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edges_are_symmetric() {
        let g = Graph::from_edges(4, &[(0, 1), (1, 2), (1, 3)]);
        assert_eq!(g.num_vertices(), 4);
        assert_eq!(g.num_edges(), 3);
        assert_eq!(g.neighbors(1), &[0, 2, 3]);
        assert!(g.has_edge(3, 1));
        assert!(!g.has_edge(0, 2));
        assert_eq!(g.label(2), "#2");
    }
}
