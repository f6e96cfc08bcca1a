//! Single-path searches on the roadmap that the formation planners share: Dijkstra with any edge
//! weight, loop elimination, every simple path (brute force), and simple paths in order of
//! length (Yen's k-shortest paths) up to a bound.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use rustc_hash::{FxHashMap, FxHashSet};

use crate::roadmap::Roadmap;

/// A totally ordered f64 for heaps (weights are finite or +inf, never NaN).
#[derive(Debug, Clone, Copy, PartialEq)]
struct W(f64);
impl Eq for W {}
impl PartialOrd for W {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for W {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&o.0)
    }
}

/// The cheapest path from `from` to `to` under `weight(edge id, from vertex, to vertex)` (an
/// infinite weight forbids the edge), avoiding `banned` vertices; ties broken by vertex id.
/// Returns the vertex sequence and its weight.
pub fn dijkstra(
    r: &Roadmap,
    from: u32,
    to: u32,
    banned: &[bool],
    weight: &dyn Fn(u32, u32, u32) -> f64,
) -> Option<(Vec<u32>, f64)> {
    let (dist, prev) = search(r, from, to, banned, weight);
    if !dist[to as usize].is_finite() {
        return None;
    }
    let mut path = vec![to];
    while *path.last().expect("non-empty") != from {
        path.push(prev[*path.last().expect("non-empty") as usize]);
    }
    path.reverse();
    Some((path, dist[to as usize]))
}

/// Dijkstra from `from` until `to` is settled: distances and predecessors.
fn search(
    r: &Roadmap,
    from: u32,
    to: u32,
    banned: &[bool],
    weight: &dyn Fn(u32, u32, u32) -> f64,
) -> (Vec<f64>, Vec<u32>) {
    let n = r.num_vertices();
    let mut dist = vec![f64::INFINITY; n];
    let mut prev = vec![u32::MAX; n];
    let mut heap = BinaryHeap::new();
    dist[from as usize] = 0.0;
    heap.push(Reverse((W(0.0), from)));
    while let Some(Reverse((W(d), u))) = heap.pop() {
        if d > dist[u as usize] {
            continue;
        }
        if u == to {
            break;
        }
        for &(v, e) in r.neighbors(u) {
            if banned.get(v as usize).copied().unwrap_or(false) {
                continue;
            }
            let nd = d + weight(e, u, v);
            if nd < dist[v as usize] {
                dist[v as usize] = nd;
                prev[v as usize] = u;
                heap.push(Reverse((W(nd), v)));
            }
        }
    }
    (dist, prev)
}

/// Cuts every loop out of a vertex sequence (a repeated vertex keeps its first visit and continues
/// from its last).
pub fn eliminate_loops(path: &[u32]) -> Vec<u32> {
    let mut out: Vec<u32> = Vec::with_capacity(path.len());
    for &v in path {
        if let Some(i) = out.iter().position(|&w| w == v) {
            out.truncate(i + 1);
        } else {
            out.push(v);
        }
    }
    out
}

/// Length of a path: the sum of its edges' lengths (`c_e(1)`).
pub fn path_length(r: &Roadmap, path: &[u32]) -> f64 {
    path.windows(2)
        .map(|w| {
            r.edge_between(w[0], w[1])
                .map_or(f64::INFINITY, |e| r.edges[e as usize].length)
        })
        .sum()
}

/// Every simple path from `from` to `to` (depth-first, in neighbour order), at most `limit` of
/// them; `None` when there are more.
pub fn all_simple_paths(r: &Roadmap, from: u32, to: u32, limit: usize) -> Option<Vec<Vec<u32>>> {
    fn go(
        r: &Roadmap,
        path: &mut Vec<u32>,
        on: &mut [bool],
        to: u32,
        out: &mut Vec<Vec<u32>>,
        limit: usize,
    ) -> bool {
        let u = *path.last().expect("non-empty");
        if u == to {
            out.push(path.clone());
            return out.len() <= limit;
        }
        for &(v, _) in r.neighbors(u) {
            if !on[v as usize] {
                on[v as usize] = true;
                path.push(v);
                let ok = go(r, path, on, to, out, limit);
                path.pop();
                on[v as usize] = false;
                if !ok {
                    return false;
                }
            }
        }
        true
    }
    let mut on = vec![false; r.num_vertices()];
    on[from as usize] = true;
    let mut out = Vec::new();
    go(r, &mut vec![from], &mut on, to, &mut out, limit).then_some(out)
}

/// Why [`paths_up_to`] stopped before listing every path within its bound.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cut {
    /// More than `limit` paths are within the bound.
    Limit,
    /// The deadline passed.
    Deadline,
}

/// Simple paths from `from` to `to` in non-decreasing length (Yen's algorithm), every path of
/// length at most `bound`, at most `limit` of them; the deadline is checked once per path.
///
/// # Errors
/// [`Cut::Limit`] when more than `limit` paths are within the bound, [`Cut::Deadline`] when the
/// deadline passes first.
pub fn paths_up_to(
    r: &Roadmap,
    from: u32,
    to: u32,
    bound: f64,
    limit: usize,
    deadline: &mrpp_core::Deadline,
) -> Result<Vec<(Vec<u32>, f64)>, Cut> {
    let (found, cut) = yen(r, from, to, bound, limit, deadline);
    match cut {
        Some(c) => Err(c),
        None => Ok(found),
    }
}

/// The `k` shortest simple paths from `from` to `to` (fewer when there are fewer), with their
/// lengths, in non-decreasing length (Yen's algorithm).
pub fn k_shortest_paths(r: &Roadmap, from: u32, to: u32, k: usize) -> Vec<(Vec<u32>, f64)> {
    yen(r, from, to, f64::MAX, k, &mrpp_core::Deadline::none()).0
}

/// Yen's algorithm: the paths found, and why it stopped early (`None`: every path within
/// `bound` is listed).
fn yen(
    r: &Roadmap,
    from: u32,
    to: u32,
    bound: f64,
    limit: usize,
    deadline: &mrpp_core::Deadline,
) -> (Vec<(Vec<u32>, f64)>, Option<Cut>) {
    let len = |e: u32, _: u32, _: u32| r.edges[e as usize].length;
    let n = r.num_vertices();
    let Some(first) = dijkstra(r, from, to, &vec![false; n], &len) else {
        return (Vec::new(), None);
    };
    let mut found: Vec<(Vec<u32>, f64)> = Vec::new();
    // Candidates in a min-heap by (length, path); every path ever queued, to queue it once; per
    // root prefix, the next vertices the found paths with that prefix took.
    let mut heap: BinaryHeap<Reverse<(W, Vec<u32>)>> = BinaryHeap::new();
    let mut seen: FxHashSet<Vec<u32>> = FxHashSet::default();
    let mut next_of: FxHashMap<Vec<u32>, Vec<u32>> = FxHashMap::default();
    seen.insert(first.0.clone());
    heap.push(Reverse((W(first.1), first.0)));
    let eps = 1e-9 * bound.abs().max(1.0);
    while let Some(Reverse((W(cost), path))) = heap.pop() {
        if cost > bound + eps {
            break;
        }
        if found.len() == limit {
            return (found, Some(Cut::Limit));
        }
        if deadline.expired() {
            return (found, Some(Cut::Deadline));
        }
        for i in 0..path.len() - 1 {
            next_of
                .entry(path[..=i].to_vec())
                .or_default()
                .push(path[i + 1]);
        }
        for i in 0..path.len() - 1 {
            let root = &path[..=i];
            let spur = path[i];
            // Edges leaving the spur that found paths with this root took are removed.
            let removed = next_of.get(root).map(Vec::as_slice).unwrap_or(&[]);
            let mut banned = vec![false; n];
            for &v in &root[..i] {
                banned[v as usize] = true;
            }
            let w = |e: u32, a: u32, b: u32| {
                if a == spur && removed.contains(&b) {
                    f64::INFINITY
                } else {
                    len(e, a, b)
                }
            };
            if let Some((tail, c)) = dijkstra(r, spur, to, &banned, &w) {
                let mut p = root[..i].to_vec();
                p.extend(tail);
                if seen.insert(p.clone()) {
                    let total = path_length(r, &root[..=i]) + c;
                    heap.push(Reverse((W(total), p)));
                }
            }
        }
        found.push((path, cost));
    }
    (found, None)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3x3 grid of unit edges, vertex = 3 row + column.
    fn grid() -> Roadmap {
        let pts: Vec<[f64; 2]> = (0..9).map(|i| [(i % 3) as f64, (i / 3) as f64]).collect();
        let mut segs = Vec::new();
        for i in 0..9u32 {
            if i % 3 < 2 {
                segs.push((i, i + 1, 1.0));
            }
            if i < 6 {
                segs.push((i, i + 3, 1.0));
            }
        }
        Roadmap::from_segments(pts, &segs)
    }

    fn none() -> mrpp_core::Deadline {
        mrpp_core::Deadline::none()
    }

    #[test]
    fn yen_agrees_with_brute_force() {
        let r = grid();
        let mut all = all_simple_paths(&r, 0, 8, 10_000).unwrap();
        all.sort_by(|a, b| path_length(&r, a).total_cmp(&path_length(&r, b)));
        for bound in [4.0, 6.0, 8.0] {
            let yen = paths_up_to(&r, 0, 8, bound, 10_000, &none()).unwrap();
            let brute: Vec<&Vec<u32>> = all
                .iter()
                .filter(|p| path_length(&r, p) <= bound + 1e-9)
                .collect();
            assert_eq!(yen.len(), brute.len(), "bound {bound}");
            assert!(yen.windows(2).all(|w| w[0].1 <= w[1].1 + 1e-12));
        }
        assert_eq!(paths_up_to(&r, 0, 8, 4.0, 6, &none()).unwrap().len(), 6);
        assert_eq!(paths_up_to(&r, 0, 8, 4.0, 5, &none()), Err(Cut::Limit));
        // The first k of them whatever their length (the GA's initial variants).
        let all = paths_up_to(&r, 0, 8, f64::MAX, 10_000, &none()).unwrap();
        assert!(all.len() > 5);
        assert_eq!(k_shortest_paths(&r, 0, 8, 5), all[..5]);
        assert_eq!(k_shortest_paths(&r, 0, 8, 10_000), all);
        assert_eq!(eliminate_loops(&[0, 1, 2, 1, 4, 0, 3]), vec![0, 3]);
    }
}
