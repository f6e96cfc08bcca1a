//! The roadmap: the generalized Voronoi diagram of the free space (the GA paper's §2.1, Fig. 1a),
//! as a graph whose edges are corridors with a length and a clearance.
//!
//! Construction (each step a function):
//! 1. [`sample_boundaries`]: every border and obstacle edge is sampled every `spacing` units
//!    (default: the robot radius, at most 0.5), each sample tagged with its polygon.
//! 2. [`voronoi_edges`]: the Voronoi diagram of the samples, from `spade`'s Delaunay
//!    triangulation (its dual). A Voronoi edge is kept only when its two generating samples belong to
//!    **different polygons** (edges between samples of one polygon are the spurs into its corners),
//!    both its ends are in free space, it crosses no boundary, and its exact clearance (distance to
//!    the nearest boundary, computed on the polygons, not the samples) is at least the robot radius
//!    plus `margin`.
//! 3. [`RoadmapBuilder`]: coincident Voronoi vertices are merged; leaves are pruned repeatedly in
//!    every component that has a cycle (dead ends left by the clearance filter; a component that is
//!    a tree is kept whole); chains of degree-2 vertices are merged into one edge (lengths summed,
//!    the minimum clearance kept, the polyline kept for pictures).
//! 4. [`Roadmap::link`]: a start or goal point becomes a vertex joined by straight edges to up to
//!    three nearest roadmap vertices it sees with enough clearance.
//!
//! An edge's **width** is twice its clearance (the corridor's narrowest point); the cost model
//! turns it into a capacity ([`crate::cost`]).

use rustc_hash::FxHashMap;
use spade::handles::VoronoiVertex;
use spade::{DelaunayTriangulation, HasPosition, Point2, Triangulation};

use crate::polymap::{Point, PolygonMap, point_segment_distance};

/// Roadmap construction options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoadmapOptions {
    /// Robot radius (working units): corridors narrower than `2 (radius + margin)` are dropped.
    pub radius: f64,
    /// Extra clearance beyond the radius.
    pub margin: f64,
    /// Boundary sampling step; `None` = min(radius, 0.5).
    pub spacing: Option<f64>,
}

impl Default for RoadmapOptions {
    fn default() -> Self {
        RoadmapOptions {
            radius: 0.25,
            margin: 0.0,
            spacing: None,
        }
    }
}

/// A corridor between two roadmap vertices.
#[derive(Debug, Clone, PartialEq)]
pub struct RoadEdge {
    pub u: u32,
    pub v: u32,
    /// Length of the polyline.
    pub length: f64,
    /// Minimum distance from the polyline to any boundary.
    pub clearance: f64,
    /// The corridor's centre line from `u` to `v`.
    pub polyline: Vec<Point>,
}

impl RoadEdge {
    /// Twice the clearance: the corridor's narrowest width.
    pub fn width(&self) -> f64 {
        2.0 * self.clearance
    }
    /// The other end of the edge.
    pub fn other(&self, x: u32) -> u32 {
        if x == self.u { self.v } else { self.u }
    }
}

/// A roadmap: vertices (points) and corridors.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Roadmap {
    pub points: Vec<Point>,
    pub edges: Vec<RoadEdge>,
    /// Per vertex: `(neighbour, edge id)`, in edge-id order.
    adj: Vec<Vec<(u32, u32)>>,
}

impl Roadmap {
    /// A roadmap from points and edges (used by tests and by the builder).
    pub fn new(points: Vec<Point>, edges: Vec<RoadEdge>) -> Self {
        let mut adj = vec![Vec::new(); points.len()];
        for (i, e) in edges.iter().enumerate() {
            adj[e.u as usize].push((e.v, i as u32));
            adj[e.v as usize].push((e.u, i as u32));
        }
        Roadmap { points, edges, adj }
    }

    /// A roadmap of straight edges between `points` with the given clearances (tests, examples).
    pub fn from_segments(points: Vec<Point>, segments: &[(u32, u32, f64)]) -> Self {
        let edges = segments
            .iter()
            .map(|&(u, v, clearance)| {
                let (a, b) = (points[u as usize], points[v as usize]);
                RoadEdge {
                    u,
                    v,
                    length: dist(a, b),
                    clearance,
                    polyline: vec![a, b],
                }
            })
            .collect();
        Roadmap::new(points, edges)
    }

    pub fn num_vertices(&self) -> usize {
        self.points.len()
    }

    /// `(neighbour, edge id)` of `v`.
    pub fn neighbors(&self, v: u32) -> &[(u32, u32)] {
        &self.adj[v as usize]
    }

    /// The edge joining `u` and `v`, if any.
    pub fn edge_between(&self, u: u32, v: u32) -> Option<u32> {
        self.adj
            .get(u as usize)?
            .iter()
            .find(|&&(w, _)| w == v)
            .map(|&(_, e)| e)
    }

    /// Number of connected components and independent cycles (E − V + C).
    pub fn components_and_cycles(&self) -> (usize, usize) {
        let n = self.points.len();
        let mut seen = vec![false; n];
        let mut comps = 0;
        for s in 0..n {
            if seen[s] {
                continue;
            }
            comps += 1;
            let mut stack = vec![s];
            seen[s] = true;
            while let Some(x) = stack.pop() {
                for &(y, _) in &self.adj[x] {
                    if !seen[y as usize] {
                        seen[y as usize] = true;
                        stack.push(y as usize);
                    }
                }
            }
        }
        (comps, self.edges.len() + comps - n)
    }

    /// Adds `p` as a vertex joined by a straight edge to the nearest point of the roadmap (a vertex
    /// or a point of a corridor's centre line, where the corridor is then split) that it sees with
    /// clearance at least `min_clearance`. Returns the new vertex, or `None` when it sees none.
    pub fn link(&mut self, map: &PolygonMap, p: Point, min_clearance: f64) -> Option<u32> {
        // Candidates: (distance, edge, index in its polyline).
        let mut cands: Vec<(f64, usize, usize)> = Vec::new();
        for (e, edge) in self.edges.iter().enumerate() {
            for (k, &q) in edge.polyline.iter().enumerate() {
                cands.push((dist(p, q), e, k));
            }
        }
        cands.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        let &(_, e, k) = cands.iter().find(|&&(_, e, k)| {
            let q = self.edges[e].polyline[k];
            !map.segment_hits_boundary(p, q) && segment_clearance(map, p, q) >= min_clearance
        })?;
        let at = self.vertex_at(map, e, k);
        let q = self.points[at as usize];
        let id = self.points.len() as u32;
        let mut edges = std::mem::take(&mut self.edges);
        edges.push(RoadEdge {
            u: id,
            v: at,
            length: dist(p, q),
            clearance: segment_clearance(map, p, q),
            polyline: vec![p, q],
        });
        let mut points = std::mem::take(&mut self.points);
        points.push(p);
        *self = Roadmap::new(points, edges);
        Some(id)
    }

    /// The vertex at point `k` of edge `e`'s polyline, splitting the edge there when it is an
    /// interior point (both parts get their exact length and clearance).
    fn vertex_at(&mut self, map: &PolygonMap, e: usize, k: usize) -> u32 {
        let edge = self.edges[e].clone();
        if k == 0 {
            return edge.u;
        }
        if k == edge.polyline.len() - 1 {
            return edge.v;
        }
        let w = self.points.len() as u32;
        let part = |line: &[Point], u: u32, v: u32| RoadEdge {
            u,
            v,
            length: line.windows(2).map(|s| dist(s[0], s[1])).sum(),
            clearance: line
                .windows(2)
                .map(|s| segment_clearance(map, s[0], s[1]))
                .fold(f64::INFINITY, f64::min),
            polyline: line.to_vec(),
        };
        let mut edges = std::mem::take(&mut self.edges);
        edges[e] = part(&edge.polyline[..=k], edge.u, w);
        edges.push(part(&edge.polyline[k..], w, edge.v));
        let mut points = std::mem::take(&mut self.points);
        points.push(edge.polyline[k]);
        *self = Roadmap::new(points, edges);
        w
    }
}

/// Euclidean distance.
pub fn dist(a: Point, b: Point) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

/// The exact clearance of the segment `a`–`b`: its distance to the nearest boundary edge (the
/// segment crosses none).
pub fn segment_clearance(map: &PolygonMap, a: Point, b: Point) -> f64 {
    map.polygons()
        .flat_map(|poly| poly.edges())
        .map(|(c, d)| {
            point_segment_distance(a, c, d)
                .min(point_segment_distance(b, c, d))
                .min(point_segment_distance(c, a, b))
                .min(point_segment_distance(d, a, b))
        })
        .fold(f64::INFINITY, f64::min)
}

/// A boundary sample and the polygon it lies on (0 = border, i = obstacle i − 1).
#[derive(Debug, Clone, Copy)]
pub struct Sample {
    pub p: Point2<f64>,
    pub polygon: u32,
}

impl HasPosition for Sample {
    type Scalar = f64;
    fn position(&self) -> Point2<f64> {
        self.p
    }
}

/// Step 1: samples every `spacing` along every polygon edge.
pub fn sample_boundaries(map: &PolygonMap, spacing: f64) -> Vec<Sample> {
    let mut out = Vec::new();
    for (id, poly) in map.polygons().enumerate() {
        for (a, b) in poly.edges() {
            let n = (dist(a, b) / spacing).ceil().max(1.0) as usize;
            for k in 0..n {
                let t = k as f64 / n as f64;
                out.push(Sample {
                    p: Point2::new(a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])),
                    polygon: id as u32,
                });
            }
        }
    }
    out
}

/// A kept Voronoi edge: its two end points and its exact clearance.
pub type VoronoiSegment = (Point, Point, f64);

/// Step 2: the Voronoi edges between different polygons, in free space, with enough clearance.
pub fn voronoi_edges(
    map: &PolygonMap,
    samples: Vec<Sample>,
    min_clearance: f64,
) -> Vec<VoronoiSegment> {
    let Ok(dt) = DelaunayTriangulation::<Sample>::bulk_load(samples) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for e in dt.undirected_voronoi_edges() {
        let [VoronoiVertex::Inner(f0), VoronoiVertex::Inner(f1)] = e.vertices() else {
            continue;
        };
        let [a, b] = e.as_delaunay_edge().vertices();
        if a.data().polygon == b.data().polygon {
            continue;
        }
        let (c0, c1) = (f0.circumcenter(), f1.circumcenter());
        let (p, q) = ([c0.x, c0.y], [c1.x, c1.y]);
        if !map.is_free(p) || !map.is_free(q) || map.segment_hits_boundary(p, q) {
            continue;
        }
        let c = segment_clearance(map, p, q);
        if c >= min_clearance {
            out.push((p, q, c));
        }
    }
    out
}

/// Step 3: merges, prunes and simplifies Voronoi segments into a [`Roadmap`].
pub struct RoadmapBuilder {
    points: Vec<Point>,
    /// Undirected edges; removed ones are `None` (ids stay stable while chains merge).
    edges: Vec<Option<RoadEdge>>,
    adj: Vec<Vec<u32>>,
}

impl RoadmapBuilder {
    /// Merges coincident end points (closer than `eps`) and drops zero-length segments.
    pub fn new(segments: &[VoronoiSegment], eps: f64) -> Self {
        let mut ids: FxHashMap<(i64, i64), u32> = FxHashMap::default();
        let mut b = RoadmapBuilder {
            points: Vec::new(),
            edges: Vec::new(),
            adj: Vec::new(),
        };
        let mut key_of = |b: &mut RoadmapBuilder, p: Point| -> u32 {
            let key = ((p[0] / eps).round() as i64, (p[1] / eps).round() as i64);
            *ids.entry(key).or_insert_with(|| {
                b.points.push(p);
                b.adj.push(Vec::new());
                (b.points.len() - 1) as u32
            })
        };
        let mut seen: FxHashMap<(u32, u32), ()> = FxHashMap::default();
        for &(p, q, c) in segments {
            let (u, v) = (key_of(&mut b, p), key_of(&mut b, q));
            if u == v || seen.insert((u.min(v), u.max(v)), ()).is_some() {
                continue;
            }
            let id = b.edges.len() as u32;
            b.edges.push(Some(RoadEdge {
                u,
                v,
                length: dist(p, q),
                clearance: c,
                polyline: vec![p, q],
            }));
            b.adj[u as usize].push(id);
            b.adj[v as usize].push(id);
        }
        b
    }

    fn degree(&self, v: usize) -> usize {
        self.adj[v].len()
    }

    fn remove_edge(&mut self, id: u32) {
        if let Some(e) = self.edges[id as usize].take() {
            self.adj[e.u as usize].retain(|&x| x != id);
            self.adj[e.v as usize].retain(|&x| x != id);
        }
    }

    /// Components (vertex lists) of the current graph, ignoring isolated vertices.
    fn components(&self) -> Vec<Vec<usize>> {
        let n = self.points.len();
        let mut comp = vec![usize::MAX; n];
        let mut out = Vec::new();
        for s in 0..n {
            if comp[s] != usize::MAX || self.adj[s].is_empty() {
                continue;
            }
            let mut members = vec![s];
            comp[s] = out.len();
            let mut i = 0;
            while i < members.len() {
                let x = members[i];
                i += 1;
                for &e in &self.adj[x] {
                    let edge = self.edges[e as usize].as_ref().expect("live edge");
                    let y = edge.other(x as u32) as usize;
                    if comp[y] == usize::MAX {
                        comp[y] = out.len();
                        members.push(y);
                    }
                }
            }
            out.push(members);
        }
        out
    }

    /// Removes leaves repeatedly in every component that has a cycle.
    pub fn prune_spurs(&mut self) {
        for members in self.components() {
            let edges: usize = members.iter().map(|&v| self.degree(v)).sum::<usize>() / 2;
            if edges < members.len() {
                continue; // a tree: keep it whole
            }
            let mut stack: Vec<usize> = members
                .iter()
                .copied()
                .filter(|&v| self.degree(v) == 1)
                .collect();
            while let Some(v) = stack.pop() {
                if self.degree(v) != 1 {
                    continue;
                }
                let e = self.adj[v][0];
                let w = self.edges[e as usize]
                    .as_ref()
                    .expect("live edge")
                    .other(v as u32) as usize;
                self.remove_edge(e);
                if self.degree(w) == 1 {
                    stack.push(w);
                }
            }
        }
    }

    /// Merges chains through degree-2 vertices and renumbers into a [`Roadmap`].
    pub fn finish(mut self) -> Roadmap {
        for v in 0..self.points.len() {
            if self.degree(v) != 2 {
                continue;
            }
            let (e1, e2) = (self.adj[v][0], self.adj[v][1]);
            let a = self.edges[e1 as usize].clone().expect("live edge");
            let b = self.edges[e2 as usize].clone().expect("live edge");
            let (x, y) = (a.other(v as u32), b.other(v as u32));
            if x == y {
                continue; // a loop of two edges: keep the vertex
            }
            let mut line_a = a.polyline.clone();
            if a.u == v as u32 {
                line_a.reverse(); // now x .. v
            }
            let mut line_b = b.polyline.clone();
            if b.v == v as u32 {
                line_b.reverse(); // now v .. y
            }
            line_a.extend_from_slice(&line_b[1..]);
            self.remove_edge(e1);
            self.remove_edge(e2);
            let id = self.edges.len() as u32;
            self.edges.push(Some(RoadEdge {
                u: x,
                v: y,
                length: a.length + b.length,
                clearance: a.clearance.min(b.clearance),
                polyline: line_a,
            }));
            self.adj[x as usize].push(id);
            self.adj[y as usize].push(id);
        }
        let mut new_id = vec![u32::MAX; self.points.len()];
        let mut points = Vec::new();
        for (v, id) in new_id.iter_mut().enumerate() {
            if !self.adj[v].is_empty() {
                *id = points.len() as u32;
                points.push(self.points[v]);
            }
        }
        let edges = self
            .edges
            .into_iter()
            .flatten()
            .map(|mut e| {
                e.u = new_id[e.u as usize];
                e.v = new_id[e.v as usize];
                e
            })
            .collect();
        Roadmap::new(points, edges)
    }
}

/// The roadmap of `map` for robots of radius `opts.radius` (steps 1–3).
pub fn build_roadmap(map: &PolygonMap, opts: &RoadmapOptions) -> Roadmap {
    let spacing = opts.spacing.unwrap_or(opts.radius.min(0.5)).max(1e-3);
    let samples = sample_boundaries(map, spacing);
    let segments = voronoi_edges(map, samples, opts.radius + opts.margin);
    let (lo, hi) = map.bounds();
    let eps = 1e-9 * (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1.0);
    let mut b = RoadmapBuilder::new(&segments, eps);
    b.prune_spurs();
    b.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn data(name: &str) -> PolygonMap {
        let p = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../data/polygon-maps")
            .join(name);
        PolygonMap::load(&p).unwrap()
    }

    /// Every edge in free space with at least its stated clearance; one component.
    fn check(map: &PolygonMap, r: &Roadmap, radius: f64) {
        assert!(!r.edges.is_empty());
        for e in &r.edges {
            assert!(e.clearance >= radius - 1e-9);
            for w in e.polyline.windows(2) {
                assert!(!map.segment_hits_boundary(w[0], w[1]));
                assert!(segment_clearance(map, w[0], w[1]) >= e.clearance - 1e-9);
                assert!(map.is_free(w[0]) && map.is_free(w[1]));
            }
            let len: f64 = e.polyline.windows(2).map(|w| dist(w[0], w[1])).sum();
            assert!((len - e.length).abs() < 1e-9);
        }
        assert_eq!(r.components_and_cycles().0, 1, "one connected roadmap");
    }

    #[test]
    fn bundled_maps_give_valid_connected_roadmaps() {
        for name in ["gaps.txt", "potholes.txt", "var_density2.txt"] {
            let map = data(name);
            let opts = RoadmapOptions {
                radius: 0.3,
                ..RoadmapOptions::default()
            };
            let r = build_roadmap(&map, &opts);
            check(&map, &r, 0.3);
        }
    }

    #[test]
    fn obstacles_inside_the_border_each_make_one_cycle() {
        let text = "[BORDER]\n0 0\n20 0\n20 20\n0 20\n[OBSTACLE]\n3 3\n6 3\n6 6\n3 6\n[OBSTACLE]\n12 4\n16 4\n14 8\n[OBSTACLE]\n5 12\n9 12\n9 16\n5 16\n";
        let map = PolygonMap::parse(text, Path::new("t.txt")).unwrap();
        let r = build_roadmap(&map, &RoadmapOptions::default());
        check(&map, &r, 0.25);
        assert_eq!(r.components_and_cycles(), (1, 3));
    }
}
