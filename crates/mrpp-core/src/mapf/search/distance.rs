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
    fn path_graph_distances() {
        let g = Graph::from_edges(4, &[(0, 1), (1, 2)]);
        assert_eq!(bfs_distances(&g, 0), vec![0, 1, 2, UNREACHABLE]);
        assert_eq!(
            bfs_distances_avoiding(&g, 0, |v| v == 1),
            vec![0, UNREACHABLE, UNREACHABLE, UNREACHABLE]
        );
    }
}
