//! The ideal path of one robot, against which the HBMO paper measures path deviation (ATPD, §5.1):
//! the shortest path of a disc of radius `r` from its start to its goal that stays in the workspace
//! and clear of obstacles, passing corners at `r + δ` (the paper's threshold δ is one pixel).
//!
//! Computed on a visibility graph: besides start and goal, every convex obstacle corner carries
//! [`CORNER_SAMPLES`] points on a circle around it, of radius `(r + δ) / cos(π / k)`, so that the
//! chords between neighbouring points keep `r + δ` from the corner (the polygon circumscribes the
//! clearance arc); two nodes are joined when the segment between them keeps `r` from every obstacle
//! (straight stretches may pass at `r`, like the robots) and the disc stays in the workspace. The
//! result overestimates the shortest path keeping `r` only around corners: by at most
//! `tan(π/k)/(π/k) − 1` of the arcs (about 2.6% for k = 8) plus the δ detour; and since a robot
//! stops within ε of its goal, a plan can come out slightly shorter than its ideal path (a small
//! negative deviation).

use crate::geometry::{Point, cross, dist, segment_polygon, sub};
use crate::world::World;

/// Points per convex corner (k).
pub const CORNER_SAMPLES: usize = 8;

/// The paper's threshold spacing δ: one unit (pixel).
pub const THRESHOLD: f64 = 1.0;

/// The visibility-graph nodes for discs of `radius`: points around each convex corner that are
/// clear of every obstacle and inside the workspace.
pub fn corner_nodes(world: &World, radius: f64) -> Vec<Point> {
    let k = CORNER_SAMPLES as f64;
    let ring = (radius + THRESHOLD) / (std::f64::consts::PI / k).cos();
    let mut out = Vec::new();
    for poly in &world.obstacles {
        let n = poly.len();
        let orient = crate::geometry::signed_area2(poly).signum();
        for i in 0..n {
            let (a, v, b) = (poly[(i + n - 1) % n], poly[i], poly[(i + 1) % n]);
            // Convex corner: the turn a→v→b goes the polygon's way.
            if cross(sub(v, a), sub(b, v)) * orient <= 0.0 {
                continue;
            }
            for s in 0..CORNER_SAMPLES {
                let ang = 2.0 * std::f64::consts::PI * s as f64 / k;
                let p = [v[0] + ring * ang.cos(), v[1] + ring * ang.sin()];
                if world.disc_in_workspace(p, radius) && world.obstacle_within(p, radius).is_none()
                {
                    out.push(p);
                }
            }
        }
    }
    out
}

/// Whether a disc of `radius` can slide straight from `a` to `b`.
pub fn clear_segment(world: &World, a: Point, b: Point, radius: f64) -> bool {
    world.disc_in_workspace(a, radius)
        && world.disc_in_workspace(b, radius)
        && world
            .obstacles
            .iter()
            .all(|poly| segment_polygon(a, b, poly) >= radius)
}

/// The ideal path from `start` to `goal` for a disc of `radius` over `nodes` ([`corner_nodes`]):
/// its points (start and goal included) and its length; `None` when the goal cannot be reached.
pub fn ideal_path(
    world: &World,
    nodes: &[Point],
    start: Point,
    goal: Point,
    radius: f64,
) -> Option<(Vec<Point>, f64)> {
    if clear_segment(world, start, goal, radius) {
        return Some((vec![start, goal], dist(start, goal)));
    }
    // Dijkstra on the dense visibility graph: node 0 = start, 1 = goal, then the corners.
    let pts: Vec<Point> = [start, goal]
        .into_iter()
        .chain(nodes.iter().copied())
        .collect();
    let n = pts.len();
    let mut d = vec![f64::INFINITY; n];
    let mut prev = vec![usize::MAX; n];
    let mut done = vec![false; n];
    d[0] = 0.0;
    for _ in 0..n {
        let u = (0..n)
            .filter(|&i| !done[i])
            .min_by(|&a, &b| d[a].total_cmp(&d[b]))?;
        if !d[u].is_finite() {
            return None;
        }
        if u == 1 {
            let mut path = vec![goal];
            let mut v = 1;
            while prev[v] != usize::MAX {
                v = prev[v];
                path.push(pts[v]);
            }
            path.reverse();
            return Some((path, d[1]));
        }
        done[u] = true;
        for v in 0..n {
            if !done[v] {
                let nd = d[u] + dist(pts[u], pts[v]);
                if nd < d[v] && clear_segment(world, pts[u], pts[v], radius) {
                    d[v] = nd;
                    prev[v] = u;
                }
            }
        }
    }
    None
}

/// The length of [`ideal_path`].
pub fn ideal_length(
    world: &World,
    nodes: &[Point],
    start: Point,
    goal: Point,
    radius: f64,
) -> Option<f64> {
    ideal_path(world, nodes, start, goal, radius).map(|(_, l)| l)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::Robot;

    #[test]
    fn straight_when_clear_and_around_a_square_otherwise() {
        let w = World {
            workspace: [0.0, 0.0, 100.0, 100.0],
            obstacles: vec![vec![[40.0, 40.0], [60.0, 40.0], [60.0, 60.0], [40.0, 60.0]]],
            robots: vec![Robot {
                start: [10.0, 50.0],
                goal: [90.0, 50.0],
                radius: 5.0,
                speed: 4.0,
            }],
            epsilon: 1.0,
            step_limit: 100,
            source: None,
        };
        let nodes = corner_nodes(&w, 5.0);
        assert_eq!(
            ideal_length(&w, &nodes, [10.0, 10.0], [90.0, 10.0], 5.0),
            Some(80.0)
        );
        let l = ideal_length(&w, &nodes, [10.0, 50.0], [90.0, 50.0], 5.0).unwrap();
        // Around the square at clearance 6: two tangents to the corners' arcs plus the side.
        let exact = 2.0 * (30.0f64.powi(2) + 16.0f64.powi(2) - 36.0).sqrt() + 20.0;
        assert!(
            l > 80.0 && l >= exact - 1.0 && l < exact * 1.05,
            "{l} vs {exact}"
        );
    }
}
