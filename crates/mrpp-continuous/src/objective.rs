//! The HBMO paper's per-step objective (§2, eq. 7), to be minimised over the robots' headings:
//!
//! `f = Σ_i (v_i + ‖p_i' − g_i‖) + f_dp Σ_{i<j} min(0, d_ij − (r_i + r_j))² + Σ_i f_st / d_i`
//!
//! with `p_i' = p_i + v_i (cos θ_i, sin θ_i)` (eq. 3–4, Δt = 1), `d_ij = ‖p_i' − p_j'‖` and `d_i` the
//! distance from `p_i'` to the nearest obstacle (0 inside one). The paper writes the robots' pair
//! term with `2r` (all robots alike) and the obstacle term as `f_st / d_{i-obs}` without saying
//! whether it sums over robots; here it does, with `d_i` floored at [`MIN_OBSTACLE_DISTANCE`] so
//! a point inside an obstacle costs a finite but huge amount. The paper's scale factors are the
//! defaults: `f_dp = 100`, `f_st = 5000`.
//!
//! **The obstacle term** ([`ObstacleTerm`]). Read literally (`Inverse`: `f_st / d_i` everywhere), it
//! pushes every robot away from every obstacle at any distance, with a gradient `f_st / d²` that
//! beats the distance term's 1 per unit within `√f_st ≈ 71` units: a robot whose goal lies within
//! about 70 units of an obstacle stops short of it and the run deadlocks (seen on generated worlds:
//! a robot halted 32 units below its goal, 31 units from an L-shaped obstacle). The default,
//! `Near`, keeps the paper's `f_st / d` shape where it matters and lets it vanish smoothly at one
//! robot diameter: `f_st · max(0, 1/d_i − 1/(2 r_i))`.
//!
//! **The target.** The distance term measures to a *target* per robot: its goal (the paper), or,
//! with the waypoint guide of [`crate::navigate`], the farthest visible point of its ideal path.
use crate::geometry::{Point, box_distance, dist, point_polygon};
use crate::problem::NavProblem;

/// The floor of `d_i` in the obstacle term.
pub const MIN_OBSTACLE_DISTANCE: f64 = 1e-3;

/// How closeness to obstacles is charged (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ObstacleTerm {
    /// `f_st / d_i` at any distance (the paper read literally).
    Inverse,
    /// `f_st · max(0, 1/d_i − 1/(2 r_i))`: the same near obstacles, nothing beyond a diameter.
    Near,
}

/// The objective's scale factors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Objective {
    /// `f_dp`, the weight of overlapping robots (paper: 100).
    pub f_dp: f64,
    /// `f_st`, the weight of closeness to obstacles (paper: 5000).
    pub f_st: f64,
    pub obstacle: ObstacleTerm,
}

impl Default for Objective {
    fn default() -> Self {
        Objective {
            f_dp: 100.0,
            f_st: 5000.0,
            obstacle: ObstacleTerm::Near,
        }
    }
}

/// The next position for heading `theta` at speed `v`.
pub fn next_position(p: Point, v: f64, theta: f64) -> Point {
    let (sin, cos) = theta.sin_cos();
    [p[0] + v * cos, p[1] + v * sin]
}

impl Objective {
    /// One robot's own terms: `v + ‖p' − target‖` plus its obstacle term.
    pub fn own(&self, p: &NavProblem, v: f64, radius: f64, next: Point, target: Point) -> f64 {
        let world = p.world();
        if world.obstacles.is_empty() {
            return v + dist(next, target);
        }
        let reach = 2.0 * radius;
        let d = world
            .obstacles
            .iter()
            .zip(p.obstacle_boxes())
            .map(|(poly, b)| {
                // Near: obstacles beyond a diameter (by their bounding box) cost nothing.
                if self.obstacle == ObstacleTerm::Near && box_distance(next, b) >= reach {
                    f64::INFINITY
                } else {
                    point_polygon(next, poly)
                }
            })
            .fold(f64::INFINITY, f64::min)
            .max(MIN_OBSTACLE_DISTANCE);
        let obstacle = match self.obstacle {
            ObstacleTerm::Inverse => self.f_st / d,
            ObstacleTerm::Near => self.f_st * (1.0 / d - 1.0 / reach).max(0.0),
        };
        v + dist(next, target) + obstacle
    }

    /// The pair term of two robots at `a` and `b` needing `reach` (the sum of their radii).
    pub fn pair(&self, a: Point, b: Point, reach: f64) -> f64 {
        let (dx, dy) = (a[0] - b[0], a[1] - b[1]);
        let d2 = dx * dx + dy * dy;
        if d2 >= reach * reach {
            return 0.0;
        }
        let short = d2.sqrt() - reach;
        self.f_dp * short * short
    }

    /// The whole objective for next positions `next` and distance targets `targets` (one per
    /// robot; robots that do not move this step appear at their current positions).
    pub fn total(&self, problem: &NavProblem, next: &[Point], targets: &[Point]) -> f64 {
        let world = problem.world();
        let mut f = 0.0;
        for (i, (r, &p)) in world.robots.iter().zip(next).enumerate() {
            f += self.own(problem, r.speed, r.radius, p, targets[i]);
            for (j, q) in world.robots.iter().enumerate().skip(i + 1) {
                f += self.pair(p, next[j], r.radius + q.radius);
            }
        }
        f
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::Robot;

    #[test]
    fn heading_to_the_goal_is_best_for_one_robot() {
        // baselines §6: one robot from (0,0) to (10,0), v = 1: θ = 0 gives F = 10.
        let w = crate::world::World {
            workspace: [-20.0, -20.0, 20.0, 20.0],
            obstacles: vec![],
            robots: vec![Robot {
                start: [0.0, 0.0],
                goal: [10.0, 0.0],
                radius: 0.5,
                speed: 1.0,
            }],
            epsilon: 0.1,
            step_limit: 10,
            source: None,
        };
        let w = NavProblem::new(w);
        let o = Objective::default();
        let f = |t: f64| o.total(&w, &[next_position([0.0, 0.0], 1.0, t)], &[[10.0, 0.0]]);
        assert!((f(0.0) - 10.0).abs() < 1e-12);
        assert!(f(0.1) > f(0.0) && f(-0.1) > f(0.0));
    }
}
