//! The continuous navigation problem, its plans (trajectories) and the validator with the HBMO
//! paper's metrics.
//!
//! A plan gives every robot its position at steps `0..=T` (the same `T` for all; Δt = 1). The
//! validator checks, for every robot and step:
//! - the first position is the start, the last is within `epsilon` of the goal, and a robot that
//!   has arrived (within `epsilon`) no longer moves (the paper: robots within ε stop);
//! - a step is at most the robot's speed long, and the disc stays in the workspace;
//! - **swept discs**: along every step's segment, not only at its ends, the disc keeps its radius
//!   from every obstacle, and two robots moving over the same step never come closer than the sum
//!   of their radii (closest approach of two linear motions, [`crate::geometry::closest_approach`]).
//!
//! Touching (distance exactly equal) is allowed; a shortfall beyond 1e-9 is a collision.
//! Metrics (§5): total path traversed (the paper's ATPT for one run), total path deviation from the
//! ideal paths (ATPD for one run, `Σ_i (traversed_i − ideal_i)`, [`crate::ideal`]), the uncovered
//! target distance `UTD(t) = Σ_i ‖g_i − p_i(t)‖` averaged over the steps (the AUTD curve is
//! [`NavProblem::utd_series`]) and the steps to arrival. The paper's AUTD (§5.2, "for k runs of
//! the program, we evaluate the average of UTDs") is per step, `AUTD(t) = (1/k) Σ_runs UTD_run(t)`,
//! a curve over the runs; [`NavMetrics::mean_utd`] is one run's UTD averaged over its steps, a
//! per-run summary that favours runs which crawl the last stretch (the `hbmo` experiment also
//! reports `Σ_t UTD(t)`, the area under the run's curve).

use std::sync::Arc;

use serde::Serialize;

use crate::geometry::{Point, bounding_box, closest_approach, dist, segment_polygon};
use crate::ideal::{corner_nodes, ideal_path};
use crate::world::World;
use mrpp_core::Problem;

/// Tolerance of every distance rule.
pub const TOLERANCE: f64 = 1e-9;

/// A continuous navigation problem: a checked world and each robot's ideal path length.
#[derive(Debug, Clone)]
pub struct NavProblem {
    world: Arc<World>,
    /// Per robot: its ideal path (points, length), `None` when its goal cannot be reached.
    ideal: Vec<Option<(Vec<Point>, f64)>>,
    /// Per obstacle: its bounding box.
    boxes: Vec<[f64; 4]>,
}

/// Positions per robot per step: `positions[i][t]`, the same number of steps for every robot.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Trajectories {
    pub positions: Vec<Vec<Point>>,
}

/// What the validator measures on a valid plan.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NavMetrics {
    /// Steps until the last robot arrived (the plan's length).
    pub steps: usize,
    /// Σ over robots of the path length traversed (ATPT of one run).
    pub total_path: f64,
    /// Σ over robots of traversed − ideal path length (ATPD of one run); NaN when a goal has no
    /// ideal path.
    pub total_deviation: f64,
    /// The uncovered target distance averaged over steps `0..=T`: `(1/(T+1)) Σ_t UTD(t)` (not
    /// the paper's per-step AUTD curve; see the module doc).
    pub mean_utd: f64,
    /// The least clearance between a disc and an obstacle or another disc over all swept steps.
    pub min_clearance: f64,
}

/// The first rule a plan breaks.
#[derive(Debug, Clone, PartialEq)]
pub enum NavViolation {
    WrongRobots {
        expected: usize,
        got: usize,
    },
    WrongLength {
        robot: usize,
        expected: usize,
        got: usize,
    },
    NotFinite {
        robot: usize,
        step: usize,
    },
    WrongStart {
        robot: usize,
    },
    NotArrived {
        robot: usize,
        distance: f64,
    },
    MovedAfterArrival {
        robot: usize,
        step: usize,
    },
    TooFast {
        robot: usize,
        step: usize,
        length: f64,
        speed: f64,
    },
    LeftWorkspace {
        robot: usize,
        step: usize,
    },
    HitsObstacle {
        robot: usize,
        step: usize,
        obstacle: usize,
        clearance: f64,
    },
    RobotsCollide {
        a: usize,
        b: usize,
        step: usize,
        distance: f64,
    },
}

impl std::fmt::Display for NavViolation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        use NavViolation::*;
        match *self {
            WrongRobots { expected, got } => write!(f, "{got} trajectories for {expected} robots"),
            WrongLength {
                robot,
                expected,
                got,
            } => write!(
                f,
                "robot {robot}: {got} positions, the others have {expected}"
            ),
            NotFinite { robot, step } => write!(
                f,
                "robot {robot}: position at step {step} is not a finite point"
            ),
            WrongStart { robot } => write!(
                f,
                "robot {robot}: the trajectory does not begin at its start"
            ),
            NotArrived { robot, distance } => write!(
                f,
                "robot {robot}: ends {distance:.3} from its goal (more than epsilon)"
            ),
            MovedAfterArrival { robot, step } => {
                write!(f, "robot {robot}: moves at step {step} after arriving")
            }
            TooFast {
                robot,
                step,
                length,
                speed,
            } => write!(
                f,
                "robot {robot}: step {step} is {length:.4} long, its speed is {speed}"
            ),
            LeftWorkspace { robot, step } => {
                write!(f, "robot {robot}: leaves the workspace at step {step}")
            }
            HitsObstacle {
                robot,
                step,
                obstacle,
                clearance,
            } => write!(
                f,
                "robot {robot}: step {step} sweeps within {clearance:.4} of obstacle {obstacle} (less than its radius)"
            ),
            RobotsCollide {
                a,
                b,
                step,
                distance,
            } => write!(
                f,
                "robots {a} and {b}: centres {distance:.4} apart during step {step} (less than the sum of radii)"
            ),
        }
    }
}

impl NavProblem {
    /// The problem of a checked world (ideal paths computed here).
    pub fn new(world: World) -> Self {
        let ideal = world
            .robots
            .iter()
            .map(|r| {
                let nodes = corner_nodes(&world, r.radius);
                ideal_path(&world, &nodes, r.start, r.goal, r.radius)
            })
            .collect();
        NavProblem {
            boxes: world.obstacles.iter().map(|o| bounding_box(o)).collect(),
            world: Arc::new(world),
            ideal,
        }
    }

    pub fn world(&self) -> &World {
        &self.world
    }

    /// Each obstacle's bounding box `[x_min, y_min, x_max, y_max]`.
    pub fn obstacle_boxes(&self) -> &[[f64; 4]] {
        &self.boxes
    }

    /// Each robot's ideal path length (`None`: its goal cannot be reached).
    pub fn ideal(&self) -> Vec<Option<f64>> {
        self.ideal
            .iter()
            .map(|i| i.as_ref().map(|(_, l)| *l))
            .collect()
    }

    /// Each robot's ideal path: its points from start to goal (`None`: unreachable).
    pub fn ideal_paths(&self) -> &[Option<(Vec<Point>, f64)>] {
        &self.ideal
    }

    /// `UTD(t) = Σ_i ‖g_i − p_i(t)‖` for every step of a plan whose trajectories have equal
    /// length.
    pub fn utd_series(&self, plan: &Trajectories) -> Vec<f64> {
        let steps = plan.positions.first().map_or(0, Vec::len);
        (0..steps)
            .map(|t| {
                plan.positions
                    .iter()
                    .zip(&self.world.robots)
                    .map(|(p, r)| dist(p[t], r.goal))
                    .sum()
            })
            .collect()
    }

    fn check_shapes(&self, plan: &Trajectories) -> Result<usize, NavViolation> {
        let w = &self.world;
        if plan.positions.len() != w.robots.len() {
            return Err(NavViolation::WrongRobots {
                expected: w.robots.len(),
                got: plan.positions.len(),
            });
        }
        let len = plan.positions[0].len();
        for (i, (path, r)) in plan.positions.iter().zip(&w.robots).enumerate() {
            if path.len() != len || len == 0 {
                return Err(NavViolation::WrongLength {
                    robot: i,
                    expected: len,
                    got: path.len(),
                });
            }
            if let Some(t) = path.iter().position(|p| !p.iter().all(|v| v.is_finite())) {
                return Err(NavViolation::NotFinite { robot: i, step: t });
            }
            if dist(path[0], r.start) > TOLERANCE {
                return Err(NavViolation::WrongStart { robot: i });
            }
            let end = dist(path[len - 1], r.goal);
            if end > w.epsilon + TOLERANCE {
                return Err(NavViolation::NotArrived {
                    robot: i,
                    distance: end,
                });
            }
        }
        Ok(len)
    }

    /// One robot's moves: length, arrival, workspace, obstacles; its least obstacle clearance.
    fn check_moves(&self, i: usize, path: &[Point]) -> Result<f64, NavViolation> {
        let w = &self.world;
        let r = &w.robots[i];
        let mut clearance = f64::INFINITY;
        let mut arrived = dist(path[0], r.goal) <= w.epsilon;
        for t in 1..path.len() {
            let (a, b) = (path[t - 1], path[t]);
            let length = dist(a, b);
            if arrived && length > 0.0 {
                return Err(NavViolation::MovedAfterArrival { robot: i, step: t });
            }
            if length > r.speed + TOLERANCE {
                return Err(NavViolation::TooFast {
                    robot: i,
                    step: t,
                    length,
                    speed: r.speed,
                });
            }
            // The workspace is convex: both ends inside keep the whole segment inside.
            if !w.disc_in_workspace(b, r.radius - TOLERANCE) {
                return Err(NavViolation::LeftWorkspace { robot: i, step: t });
            }
            for (k, poly) in w.obstacles.iter().enumerate() {
                let c = segment_polygon(a, b, poly);
                if c < r.radius - TOLERANCE {
                    return Err(NavViolation::HitsObstacle {
                        robot: i,
                        step: t,
                        obstacle: k,
                        clearance: c,
                    });
                }
                clearance = clearance.min(c - r.radius);
            }
            arrived = arrived || dist(b, r.goal) <= w.epsilon;
        }
        Ok(clearance)
    }
}

impl Problem for NavProblem {
    type Plan = Trajectories;
    type Metrics = NavMetrics;
    type Violation = NavViolation;

    fn num_agents(&self) -> usize {
        self.world.robots.len()
    }

    fn validate(&self, plan: &Trajectories) -> Result<NavMetrics, NavViolation> {
        let len = self.check_shapes(plan)?;
        let w = &self.world;
        let mut min_clearance = f64::INFINITY;
        for (i, path) in plan.positions.iter().enumerate() {
            min_clearance = min_clearance.min(self.check_moves(i, path)?);
        }
        for t in 1..len {
            for a in 0..w.robots.len() {
                for b in a + 1..w.robots.len() {
                    let (pa, pb) = (&plan.positions[a], &plan.positions[b]);
                    let d = closest_approach(pa[t - 1], pa[t], pb[t - 1], pb[t]);
                    let need = w.robots[a].radius + w.robots[b].radius;
                    if d < need - TOLERANCE {
                        return Err(NavViolation::RobotsCollide {
                            a,
                            b,
                            step: t,
                            distance: d,
                        });
                    }
                    min_clearance = min_clearance.min(d - need);
                }
            }
        }
        let lengths: Vec<f64> = plan
            .positions
            .iter()
            .map(|p| p.windows(2).map(|s| dist(s[0], s[1])).sum())
            .collect();
        let total_path = lengths.iter().sum();
        let total_deviation = lengths
            .iter()
            .zip(&self.ideal)
            .map(|(l, ideal)| ideal.as_ref().map_or(f64::NAN, |(_, d)| l - d))
            .sum();
        let utd = self.utd_series(plan);
        Ok(NavMetrics {
            steps: len - 1,
            total_path,
            total_deviation,
            mean_utd: utd.iter().sum::<f64>() / utd.len() as f64,
            min_clearance,
        })
    }
}
