//! Seeded continuous worlds.
//!
//! - [`random_world`]: the HBMO paper's setting — a 500 × 400 workspace, `obstacles` polygons of
//!   different shapes (triangles, squares, pentagons, hexagons, rectangles and non-convex L shapes,
//!   cycling through them, each randomly sized and rotated), placed apart by at least three robot
//!   diameters, and `robots` discs of radius 6 and speed 16 (the paper's 6-pixel robots, "velocity
//!   = 16 unit") with starts and goals in free space (clearance ≥ one radius from obstacles,
//!   ≥ three radii between robots, start to goal at least a third of the diagonal) such that every
//!   goal has an ideal path. Every random choice comes from `seed`.
//! - [`circle_world`]: RVO2's "circle" scenario — `robots` discs evenly on a circle, each going to
//!   the antipodal point, no obstacles.

use std::f64::consts::PI;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::geometry::{Point, dist, point_polygon};
use crate::ideal::{corner_nodes, ideal_length};
use crate::world::{Robot, World};

/// The paper's robot radius (pixels).
pub const PAPER_RADIUS: f64 = 6.0;
/// The paper's usual speed (units per step).
pub const PAPER_SPEED: f64 = 16.0;

/// Shapes in the order [`random_world`] cycles through them.
const SHAPES: [&str; 6] = [
    "triangle",
    "square",
    "pentagon",
    "l-shape",
    "hexagon",
    "rectangle",
];

/// The outline of shape `k` (see [`SHAPES`]) of size `s` around `c`, rotated by `rot`.
fn shape(k: usize, c: Point, s: f64, rot: f64, rng: &mut ChaCha8Rng) -> Vec<Point> {
    let local: Vec<Point> = match SHAPES[k % SHAPES.len()] {
        "triangle" => regular(3, s),
        "square" => regular(4, s),
        "pentagon" => regular(5, s),
        "hexagon" => regular(6, s),
        "rectangle" => {
            let (w, h) = (
                s * rng.random_range(0.4..0.8),
                s * rng.random_range(1.0..1.6),
            );
            vec![[-w, -h], [w, -h], [w, h], [-w, h]]
        }
        _ => vec![
            [-s, -s],
            [s, -s],
            [s, -s / 3.0],
            [-s / 3.0, -s / 3.0],
            [-s / 3.0, s],
            [-s, s],
        ],
    };
    let (sin, cos) = rot.sin_cos();
    local
        .iter()
        .map(|p| {
            [
                c[0] + p[0] * cos - p[1] * sin,
                c[1] + p[0] * sin + p[1] * cos,
            ]
        })
        .collect()
}

fn regular(n: usize, s: f64) -> Vec<Point> {
    (0..n)
        .map(|k| {
            let a = 2.0 * PI * k as f64 / n as f64;
            [s * a.cos(), s * a.sin()]
        })
        .collect()
}

/// A random world (see the module doc); `None` when 1000 attempts found no placement.
pub fn random_world(robots: usize, obstacles: usize, seed: u64) -> Option<World> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (w, h) = (500.0, 400.0);
    let r = PAPER_RADIUS;
    for _ in 0..1000 {
        let mut world = World {
            workspace: [0.0, 0.0, w, h],
            obstacles: Vec::new(),
            robots: Vec::new(),
            epsilon: 1.0,
            step_limit: 500,
            source: None,
        };
        for k in 0..obstacles {
            for _ in 0..200 {
                let s = rng.random_range(20.0..45.0);
                let c = [
                    rng.random_range(s + 20.0..w - s - 20.0),
                    rng.random_range(s + 20.0..h - s - 20.0),
                ];
                let poly = shape(k, c, s, rng.random_range(0.0..2.0 * PI), &mut rng);
                let apart = world.obstacles.iter().all(|q| {
                    poly.iter().all(|&p| point_polygon(p, q) >= 6.0 * r)
                        && q.iter().all(|&p| point_polygon(p, &poly) >= 6.0 * r)
                });
                if apart {
                    world.obstacles.push(poly);
                    break;
                }
            }
        }
        if world.obstacles.len() < obstacles {
            continue;
        }
        if let Some(rs) = place_robots(&world, robots, &mut rng) {
            world.robots = rs;
            if world.check().is_ok() {
                return Some(world);
            }
        }
    }
    None
}

/// Starts and goals for `n` robots in `world` (see the module doc).
fn place_robots(world: &World, n: usize, rng: &mut ChaCha8Rng) -> Option<Vec<Robot>> {
    let r = PAPER_RADIUS;
    let [x0, y0, x1, y1] = world.workspace;
    let diag = dist([x0, y0], [x1, y1]);
    let mut out: Vec<Robot> = Vec::new();
    let free = |p: Point, out: &[Robot], goal: bool| {
        world.disc_in_workspace(p, 2.0 * r)
            && world.obstacle_within(p, 2.0 * r).is_none()
            && out
                .iter()
                .all(|q| dist(if goal { q.goal } else { q.start }, p) >= 3.0 * r)
    };
    // The visibility-graph nodes depend only on the obstacles and the radius.
    let nodes = corner_nodes(world, r);
    let draw = |rng: &mut ChaCha8Rng| [rng.random_range(x0..x1), rng.random_range(y0..y1)];
    for _ in 0..n {
        let mut placed = false;
        for _ in 0..2000 {
            let (s, g) = (draw(rng), draw(rng));
            if dist(s, g) < diag / 3.0 || !free(s, &out, false) || !free(g, &out, true) {
                continue;
            }
            if ideal_length(world, &nodes, s, g, r).is_none() {
                continue;
            }
            out.push(Robot {
                start: s,
                goal: g,
                radius: r,
                speed: PAPER_SPEED,
            });
            placed = true;
            break;
        }
        if !placed {
            return None;
        }
    }
    Some(out)
}

/// RVO2's circle scenario: `n` robots of `radius` and `speed` evenly on a circle of radius
/// `ring` (centred in a square workspace with one ring radius of margin), each to its antipode.
pub fn circle_world(n: usize, ring: f64, radius: f64, speed: f64) -> World {
    let c = 2.0 * ring;
    let robots = (0..n)
        .map(|k| {
            let a = 2.0 * PI * k as f64 / n as f64;
            let p = [c + ring * a.cos(), c + ring * a.sin()];
            Robot {
                start: p,
                goal: [2.0 * c - p[0], 2.0 * c - p[1]],
                radius,
                speed,
            }
        })
        .collect();
    World {
        workspace: [0.0, 0.0, 2.0 * c, 2.0 * c],
        obstacles: Vec::new(),
        robots,
        epsilon: 1.0,
        step_limit: 2000,
        source: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn random_worlds_are_valid_and_seeded() {
        for seed in 0..5 {
            let w = random_world(6, 4, seed).unwrap();
            assert!(w.check().is_ok());
            assert_eq!((w.robots.len(), w.obstacles.len()), (6, 4));
            assert_eq!(Some(w.clone()), random_world(6, 4, seed));
        }
        assert_ne!(random_world(6, 4, 1), random_world(6, 4, 2));
        let big = random_world(10, 10, 3).unwrap();
        assert!(big.check().is_ok());
    }

    #[test]
    fn circle_goals_are_antipodes() {
        let w = circle_world(8, 100.0, 6.0, 10.0);
        assert!(w.check().is_ok());
        for r in &w.robots {
            assert!((dist(r.start, r.goal) - 200.0).abs() < 1e-9);
        }
    }
}
