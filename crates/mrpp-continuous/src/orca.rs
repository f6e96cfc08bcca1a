//! ORCA (optimal reciprocal collision avoidance; J. van den Berg, S. J. Guy, M. Lin, D. Manocha,
//! "Reciprocal n-body collision avoidance", ISRR 2009), the practical baseline of continuous
//! navigation today, through `dodgy_2d` (a Rust port of the RVO2 library, f32).
//!
//! Each step every moving robot prefers the velocity toward its target (the goal or, with the
//! waypoint guide, the farthest visible point of its ideal path; [`crate::navigate`]) at its speed,
//! or less when the target is nearer than one step; ORCA turns the preferred velocities into
//! avoiding ones given its `neighbours` nearest robots within `neighbour_distance` (their current
//! velocities) and the obstacles (made counter-clockwise; the workspace border as a clockwise ring
//! that keeps robots in), after a seeded perturbation of 1e-4 of the speed that breaks perfect
//! symmetries (as RVO2's circle example does). Robots that have arrived are neighbours with zero velocity and no share
//! of the avoidance. The velocities (Δt = 1) then go through the loop's repair like every other
//! planner's moves, so the plan is collision-free even where ORCA's f32 arithmetic or its
//! half-plane approximation would graze an obstacle. RVO2's defaults are scaled to steps: time
//! horizon 10 steps for robots, 5 for obstacles, 10 neighbours within 10 step lengths.

use std::borrow::Cow;

use dodgy_2d::{Agent, AvoidanceOptions, Obstacle, Vec2};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use crate::geometry::{Point, PointGrid, dist, signed_area2};
use crate::navigate::{Navigation, Propose};
use crate::problem::NavProblem;

/// ORCA's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orca {
    /// How far ahead (steps) collisions between robots are avoided.
    pub time_horizon: f64,
    /// How far ahead (steps) collisions with obstacles are avoided.
    pub obstacle_time_horizon: f64,
    /// Most neighbours each robot considers.
    pub neighbours: usize,
    /// Neighbours within this many step lengths of the robot.
    pub neighbour_distance: f64,
    /// ORCA plans with radii this share larger, so its f32 velocities keep clear of the exact
    /// swept-disc check (0.1: a tenth of a radius).
    pub margin: f64,
}

impl Default for Orca {
    fn default() -> Self {
        Orca {
            time_horizon: 10.0,
            obstacle_time_horizon: 5.0,
            neighbours: 10,
            neighbour_distance: 10.0,
            margin: 0.1,
        }
    }
}

/// ORCA's state across steps: every robot's velocity and the obstacles in `dodgy_2d`'s form.
pub struct OrcaRun {
    orca: Orca,
    /// Positions at the previous step (velocities are the moves actually made, after repair).
    last: Option<Vec<Point>>,
    obstacles: Vec<Cow<'static, Obstacle>>,
}

fn v2(p: Point) -> Vec2 {
    Vec2::new(p[0] as f32, p[1] as f32)
}

impl OrcaRun {
    /// The state at the start of a run on `problem`.
    pub fn new(orca: Orca, problem: &NavProblem) -> Self {
        let w = problem.world();
        let mut obstacles: Vec<Cow<'static, Obstacle>> = w
            .obstacles
            .iter()
            .map(|poly| {
                let mut vertices: Vec<Vec2> = poly.iter().map(|&p| v2(p)).collect();
                if signed_area2(poly) < 0.0 {
                    vertices.reverse();
                }
                Cow::Owned(Obstacle::Closed { vertices })
            })
            .collect();
        let [x0, y0, x1, y1] = w.workspace;
        // Clockwise: the inside of the ring is free.
        obstacles.push(Cow::Owned(Obstacle::Closed {
            vertices: vec![v2([x0, y0]), v2([x0, y1]), v2([x1, y1]), v2([x1, y0])],
        }));
        OrcaRun {
            orca,
            last: None,
            obstacles,
        }
    }
}

impl Propose for OrcaRun {
    fn propose(
        &mut self,
        _nav: &Navigation,
        problem: &NavProblem,
        pos: &[Point],
        targets: &[Point],
        moving: &[usize],
        rng: &mut ChaCha8Rng,
    ) -> Vec<Point> {
        let w = problem.world();
        let mut is_moving = vec![false; pos.len()];
        for &i in moving {
            is_moving[i] = true;
        }
        let agents: Vec<Agent> = w
            .robots
            .iter()
            .enumerate()
            .map(|(i, r)| Agent {
                position: v2(pos[i]),
                velocity: self.last.as_ref().map_or(Vec2::ZERO, |last| {
                    v2([pos[i][0] - last[i][0], pos[i][1] - last[i][1]])
                }),
                radius: (r.radius * (1.0 + self.orca.margin)) as f32,
                avoidance_responsibility: if is_moving[i] { 1.0 } else { 1e-6 },
            })
            .collect();
        let mut out = Vec::with_capacity(moving.len());
        let mut near: Vec<(f64, usize)> = Vec::new();
        let reach_max = w
            .robots
            .iter()
            .map(|r| self.orca.neighbour_distance * r.speed)
            .fold(0.0, f64::max);
        let grid = PointGrid::new(pos, w.workspace, reach_max);
        for &i in moving {
            let r = &w.robots[i];
            let reach = self.orca.neighbour_distance * r.speed;
            near.clear();
            near.extend(
                grid.near(pos[i], reach)
                    .filter(|&j| j != i)
                    .map(|j| (dist(pos[i], pos[j]), j))
                    .filter(|&(d, _)| d <= reach),
            );
            // The nearest `neighbours` (ties by index), nearest first.
            let by = |a: &(f64, usize), b: &(f64, usize)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
            if near.len() > self.orca.neighbours && self.orca.neighbours > 0 {
                near.select_nth_unstable_by(self.orca.neighbours - 1, by);
            }
            near.truncate(self.orca.neighbours);
            near.sort_unstable_by(by);
            let neighbours: Vec<Cow<Agent>> = near
                .iter()
                .map(|&(_, j)| Cow::Borrowed(&agents[j]))
                .collect();
            let to = [targets[i][0] - pos[i][0], targets[i][1] - pos[i][1]];
            let len = (to[0] * to[0] + to[1] * to[1]).sqrt();
            let scale = if len > 0.0 {
                len.min(r.speed) / len
            } else {
                0.0
            };
            // RVO2's circle example perturbs every preferred velocity a little "to avoid deadlocks
            // due to perfect symmetry"; so does this (by 1e-4 of the speed, from the run's seed).
            let (angle, tiny) = (
                rng.random_range(0.0..std::f64::consts::TAU),
                rng.random_range(0.0..1e-4 * r.speed),
            );
            let preferred = v2([
                to[0] * scale + tiny * angle.cos(),
                to[1] * scale + tiny * angle.sin(),
            ]);
            let v = agents[i].compute_avoiding_velocity(
                &neighbours,
                &self.obstacles,
                preferred,
                (r.speed * (1.0 - 1e-6)) as f32,
                1.0,
                &AvoidanceOptions {
                    obstacle_margin: (r.radius * (1.0 + self.orca.margin)) as f32,
                    time_horizon: self.orca.time_horizon as f32,
                    obstacle_time_horizon: self.orca.obstacle_time_horizon as f32,
                },
            );
            out.push([f64::from(v.x), f64::from(v.y)]);
        }
        self.last = Some(pos.to_vec());
        out
    }
}
