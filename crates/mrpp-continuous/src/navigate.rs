//! The per-step navigation loop of the HBMO paper (§2 principles, §4 pseudo-code) around any
//! heading optimiser, and the repair that keeps every step collision-free.
//!
//! Each step:
//! 1. **Target** (`guide`; beyond the paper): `Goal` measures the distance term to the goal (the
//!    paper); `Waypoints` to the farthest point of the robot's ideal path ([`crate::ideal`]) that it
//!    can reach in a straight clear line from where it is, so robots go around obstacles instead
//!    of stalling behind them (the greedy per-step objective has local minima there).
//! 2. **Headings.** `Mode::Joint` (the text: "the centralized version ... determines next position
//!    of each robot by optimizing the given constrained single-objective function", one vector of
//!    all moving robots' headings) or `Mode::PerRobot` (the pseudo-code's `For robot i = 1 to N`
//!    loop: one optimisation per robot, the others at their latest positions). With `straight_init`
//!    (the default; beyond the paper, whose pseudo-code only says "Initialize all the bees") the
//!    optimiser starts from "every robot heads straight to its target" among its initial points;
//!    without it, its initial points are all its own random samples. Robots that have
//!    arrived (within ε of their goals) stay where they are (the paper: they stop).
//! 3. **Final approach** (`snap`, default on; the paper is silent): a robot within one step of its
//!    goal aims exactly at it, so that ε can be small.
//! 4. **Repair** (principle 2: "a new next position is to be resolved for which the robot has to
//!    be rotated left or right by certain angle"; principle 4: equal rotations are broken toward
//!    the goal). Robots commit their moves in index order, except that a robot whose proposed move
//!    enters the current disc of another lets that one commit first (recursively; a cycle falls
//!    back to the index order), so robots can follow each other closely. A move is free when the swept disc keeps
//!    its radius from every obstacle and the workspace border, keeps the sum of radii from every
//!    move already committed this step (closest approach of the two motions) and from the current
//!    disc of every robot still to move. A blocked move is rotated by ±k·[`ROTATION_STEP`]
//!    (k = 1, 2, … up to ±180°), the smaller rotation first and, between +k and −k, the end nearer
//!    the goal first; if no rotation is free the robot waits. Waiting is always free (no committed
//!    move enters a robot's current disc), so every step is valid by construction, and the
//!    validator checks it again.
//! 5. **Outcome.** All robots within ε: solved. No improvement of the remaining distance (the
//!    uncovered target distance, or with waypoints the distance to the target plus the ideal path
//!    left after it) for `deadlock_steps` steps: a **deadlock**, reported as such (never as
//!    success); the world's step limit: reported as such.

use std::f64::consts::PI;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::geometry::{
    Point, PointGrid, closest_approach, dist, norm, point_segment, segment_polygon,
};
use crate::ideal::clear_segment;
use crate::objective::{Objective, next_position};
use crate::problem::{NavProblem, Trajectories};
use crate::world::World;
use mrpp_core::{Ctx, Unsolved};
use mrpp_evo::space::Minimizer;
use mrpp_evo::space::Space;

/// The rotation increment of the repair: 5°.
pub const ROTATION_STEP: f64 = PI / 36.0;

/// How the headings of one step are optimised.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// One optimisation over all moving robots' headings (the paper's text).
    Joint,
    /// One optimisation per robot in index order (the paper's pseudo-code).
    PerRobot,
}

/// What the distance term of a robot measures to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Guide {
    /// The goal (the paper).
    Goal,
    /// The farthest visible point of the robot's ideal path.
    Waypoints,
}

/// The per-step loop's settings (the optimiser is passed separately).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Navigation {
    pub mode: Mode,
    pub guide: Guide,
    pub objective: Objective,
    /// Steps without progress that make a deadlock.
    pub deadlock_steps: usize,
    /// Aim exactly at the goal when within one step of it.
    pub snap: bool,
    /// Give the optimiser "every robot heads straight to its target" as an initial point
    /// (default `true`; the paper does not: `false`).
    pub straight_init: bool,
}

impl Default for Navigation {
    fn default() -> Self {
        Navigation {
            mode: Mode::Joint,
            guide: Guide::Waypoints,
            objective: Objective::default(),
            deadlock_steps: 50,
            snap: true,
            straight_init: true,
        }
    }
}

/// Where the robots would like to go this step: one displacement (at most the robot's speed
/// long) per moving robot, which the loop then repairs into collision-free moves.
pub trait Propose {
    fn propose(
        &mut self,
        nav: &Navigation,
        problem: &NavProblem,
        pos: &[Point],
        targets: &[Point],
        moving: &[usize],
        rng: &mut ChaCha8Rng,
    ) -> Vec<Point>;
}

/// The HBMO paper's proposal: optimised headings at full speed.
pub struct HeadingSearch<'a>(pub &'a dyn Minimizer);

impl Propose for HeadingSearch<'_> {
    fn propose(
        &mut self,
        nav: &Navigation,
        problem: &NavProblem,
        pos: &[Point],
        targets: &[Point],
        moving: &[usize],
        rng: &mut ChaCha8Rng,
    ) -> Vec<Point> {
        let headings = nav.headings(problem, pos, targets, moving, self.0, rng);
        moving
            .iter()
            .zip(headings)
            .map(|(&i, t)| next_position([0.0, 0.0], problem.world().robots[i].speed, t))
            .collect()
    }
}

/// The heading straight to the goal.
fn toward(p: Point, g: Point) -> f64 {
    (g[1] - p[1]).atan2(g[0] - p[0])
}

impl Navigation {
    /// Runs the loop from the starts until every robot arrives, a deadlock, the step limit or the
    /// deadline; the trajectories are valid by construction.
    pub fn run(
        &self,
        problem: &NavProblem,
        proposer: &mut dyn Propose,
        ctx: &Ctx,
    ) -> Result<Trajectories, Unsolved> {
        let w = problem.world();
        let n = w.robots.len();
        let mut rng = ChaCha8Rng::seed_from_u64(ctx.seed);
        let mut pos: Vec<Point> = w.robots.iter().map(|r| r.start).collect();
        let mut traj: Vec<Vec<Point>> = pos.iter().map(|&p| vec![p]).collect();
        let (mut best, mut since) = (f64::INFINITY, 0);
        let mut throttle = mrpp_core::Throttle::new();
        for step in 0..w.step_limit {
            let moving: Vec<usize> = (0..n)
                .filter(|&i| dist(pos[i], w.robots[i].goal) > w.epsilon)
                .collect();
            if moving.is_empty() {
                return Ok(Trajectories { positions: traj });
            }
            if ctx.deadline.expired() {
                return Err(Unsolved::TimeLimit);
            }
            throttle.report(ctx, || mrpp_core::Progress {
                stage: "step",
                done: step as u64,
                total: w.step_limit as u64,
                note: format!("{} of {n} robots arrived", n - moving.len()),
            });
            let (targets, left) = self.targets(problem, &pos);
            if left < best - 1e-9 {
                (best, since) = (left, 0);
            } else {
                since += 1;
                if since >= self.deadlock_steps {
                    let lost: Vec<String> = moving
                        .iter()
                        .filter(|&&i| problem.ideal_paths()[i].is_none())
                        .map(|i| i.to_string())
                        .collect();
                    let hint = if lost.is_empty() {
                        String::new()
                    } else {
                        format!(
                            "; no clear ideal path to the goal of robot(s) {}",
                            lost.join(", ")
                        )
                    };
                    return Err(Unsolved::GaveUp(format!(
                        "deadlock: no progress toward the goals for {since} steps ({} of {n} robots short{hint})",
                        moving.len()
                    )));
                }
            }
            let next = self.step(problem, &pos, &targets, &moving, proposer, &mut rng);
            for (i, p) in next.into_iter().enumerate() {
                pos[i] = p;
                traj[i].push(p);
            }
        }
        if (0..n).all(|i| dist(pos[i], w.robots[i].goal) <= w.epsilon) {
            return Ok(Trajectories { positions: traj });
        }
        Err(Unsolved::GaveUp(format!(
            "step limit {} reached before every robot arrived",
            w.step_limit
        )))
    }

    /// One step from positions `pos`: the `moving` robots' proposed moves toward their `targets`
    /// (from `proposer`), repaired into collision-free moves; every robot's next position.
    pub fn step(
        &self,
        problem: &NavProblem,
        pos: &[Point],
        targets: &[Point],
        moving: &[usize],
        proposer: &mut dyn Propose,
        rng: &mut ChaCha8Rng,
    ) -> Vec<Point> {
        let moves = proposer.propose(self, problem, pos, targets, moving, rng);
        self.repair(problem.world(), pos, moving, &moves)
    }

    /// Each robot's target (see the module doc, step 1) and the total distance left.
    pub fn targets(&self, problem: &NavProblem, pos: &[Point]) -> (Vec<Point>, f64) {
        let w = problem.world();
        let mut left = 0.0;
        let targets = w
            .robots
            .iter()
            .zip(problem.ideal_paths())
            .enumerate()
            .map(|(i, (r, ideal))| {
                let path = match (self.guide, ideal) {
                    (Guide::Waypoints, Some((path, _))) => path,
                    _ => {
                        left += dist(pos[i], r.goal);
                        return r.goal;
                    }
                };
                // The farthest point of the path in clear sight, and the path left after it.
                let k = (1..path.len())
                    .rev()
                    .find(|&k| clear_segment(w, pos[i], path[k], r.radius))
                    .unwrap_or(1);
                let rest: f64 = path[k..].windows(2).map(|s| dist(s[0], s[1])).sum();
                left += dist(pos[i], path[k]) + rest;
                path[k]
            })
            .collect();
        (targets, left)
    }

    /// The optimised heading of every moving robot (indexed like `moving`).
    pub fn headings(
        &self,
        problem: &NavProblem,
        pos: &[Point],
        targets: &[Point],
        moving: &[usize],
        optimizer: &dyn Minimizer,
        rng: &mut ChaCha8Rng,
    ) -> Vec<f64> {
        let w = problem.world();
        let speeds: Vec<f64> = w.robots.iter().map(|r| r.speed).collect();
        let straight: Vec<f64> = moving.iter().map(|&i| toward(pos[i], targets[i])).collect();
        // The initial points given to the optimiser: the straight headings, or none.
        let init = |x: Vec<f64>| {
            if self.straight_init {
                vec![x]
            } else {
                Vec::new()
            }
        };
        match self.mode {
            Mode::Joint => {
                let mut next = pos.to_vec();
                let mut f = |theta: &[f64]| {
                    for (k, &i) in moving.iter().enumerate() {
                        next[i] = next_position(pos[i], speeds[i], theta[k]);
                    }
                    self.objective.total(problem, &next, targets)
                };
                optimizer
                    .minimize_dyn(&Space::angles(moving.len()), &mut f, &init(straight), rng)
                    .x
            }
            Mode::PerRobot => {
                let mut latest = pos.to_vec();
                let mut out = Vec::with_capacity(moving.len());
                for (k, &i) in moving.iter().enumerate() {
                    let r = &w.robots[i];
                    let mut f = |theta: &[f64]| {
                        let p = next_position(pos[i], r.speed, theta[0]);
                        let mut v = self
                            .objective
                            .own(problem, r.speed, r.radius, p, targets[i]);
                        for (j, q) in w.robots.iter().enumerate() {
                            if j != i {
                                v += self.objective.pair(p, latest[j], r.radius + q.radius);
                            }
                        }
                        v
                    };
                    let theta = optimizer
                        .minimize_dyn(&Space::angles(1), &mut f, &init(vec![straight[k]]), rng)
                        .x[0];
                    latest[i] = next_position(pos[i], r.speed, theta);
                    out.push(theta);
                }
                out
            }
        }
    }

    /// The committed next position of every robot (see the module doc, step 4).
    fn repair(&self, w: &World, pos: &[Point], moving: &[usize], moves: &[Point]) -> Vec<Point> {
        // The farthest two robots can be and still touch this step.
        let reach = 2.0
            * w.robots
                .iter()
                .map(|r| r.speed + r.radius)
                .fold(0.0, f64::max);
        let mut state = Commits {
            grid: PointGrid::new(pos, w.workspace, reach),
            reach,
            next: pos.to_vec(),
            committed: vec![false; pos.len()],
            busy: vec![false; pos.len()],
            proposal: vec![None; pos.len()],
        };
        for (k, &i) in moving.iter().enumerate() {
            state.proposal[i] = Some(moves[k]);
        }
        for &i in moving {
            self.commit(w, pos, i, &mut state);
        }
        state.next
    }

    /// Commits robot `i`'s move (see the module doc, step 4): first every robot whose current
    /// disc its proposed move would sweep into (so a robot following another moves after it,
    /// into the space it leaves), then the first free rotation of its own proposal.
    fn commit(&self, w: &World, pos: &[Point], i: usize, st: &mut Commits) {
        if st.committed[i] || st.busy[i] {
            return;
        }
        let Some(m) = st.proposal[i] else {
            st.committed[i] = true;
            return;
        };
        st.busy[i] = true;
        let r = &w.robots[i];
        let a = pos[i];
        let near = near_robots(w, pos, &st.grid, st.reach, i);
        // Final approach: within one step of the goal, aim exactly at it.
        let snap = self.snap && dist(a, r.goal) <= r.speed;
        let wanted = if snap {
            r.goal
        } else {
            [a[0] + m[0], a[1] + m[1]]
        };
        for &j in &near {
            if !st.committed[j] && point_segment(pos[j], a, wanted) < r.radius + w.robots[j].radius
            {
                self.commit(w, pos, j, st);
            }
        }
        let free = |b: Point, st: &Commits| {
            self.free_move(w, i, a, b, pos, &st.next, &st.committed, &near)
        };
        let choice = if snap && free(r.goal, st) {
            Some(r.goal)
        } else {
            // The proposed move, rotated by ±d (its length kept, capped at the speed).
            let (len, base) = (norm(m).min(r.speed), m[1].atan2(m[0]));
            let target = |d: f64| next_position(a, len, base + d);
            let mut found = None;
            for step in 0..=36 {
                let d = step as f64 * ROTATION_STEP;
                let mut options = vec![target(d)];
                if step > 0 && step < 36 {
                    options.push(target(-d));
                    options.sort_by(|p, q| dist(*p, r.goal).total_cmp(&dist(*q, r.goal)));
                }
                if let Some(&b) = options.iter().find(|&&b| free(b, st)) {
                    found = Some(b);
                    break;
                }
                if len == 0.0 {
                    break;
                }
            }
            found
        };
        st.next[i] = choice.unwrap_or(a);
        st.committed[i] = true;
        st.busy[i] = false;
    }

    /// Whether robot `i` may move from `a` to `b` this step (`near`: the robots that can come
    /// within reach of it this step, the others cannot touch it).
    #[allow(clippy::too_many_arguments)]
    fn free_move(
        &self,
        w: &World,
        i: usize,
        a: Point,
        b: Point,
        pos: &[Point],
        next: &[Point],
        committed: &[bool],
        near: &[usize],
    ) -> bool {
        let r = &w.robots[i];
        if !w.disc_in_workspace(b, r.radius) {
            return false;
        }
        if w.obstacles
            .iter()
            .any(|poly| segment_polygon(a, b, poly) < r.radius)
        {
            return false;
        }
        near.iter().all(|&j| {
            let reach = r.radius + w.robots[j].radius;
            if committed[j] {
                closest_approach(a, b, pos[j], next[j]) >= reach
            } else {
                point_segment(pos[j], a, b) >= reach
            }
        })
    }
}

/// The repair's bookkeeping: committed next positions, robots being committed (a cycle of
/// robots following each other falls back to the index order), and proposed moves.
struct Commits {
    grid: PointGrid,
    reach: f64,
    next: Vec<Point>,
    committed: Vec<bool>,
    busy: Vec<bool>,
    proposal: Vec<Option<Point>>,
}

/// Robots other than `i` that can come within reach of it in one step: centres closer than both
/// speeds plus both radii (`grid` holds the current positions in cells of at least that size).
fn near_robots(w: &World, pos: &[Point], grid: &PointGrid, reach: f64, i: usize) -> Vec<usize> {
    let r = &w.robots[i];
    let mut out: Vec<usize> = grid
        .near(pos[i], reach)
        .filter(|&j| {
            let q = &w.robots[j];
            j != i && dist(pos[i], pos[j]) < r.speed + q.speed + r.radius + q.radius
        })
        .collect();
    out.sort_unstable();
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generator::random_world;
    use mrpp_evo::Minimum;
    use std::sync::Mutex;

    /// A minimiser that records the initial points it is given and returns the first of them
    /// (or zeros).
    struct Recorder(Mutex<Vec<Vec<Vec<f64>>>>);

    impl Minimizer for Recorder {
        fn minimize_dyn(
            &self,
            space: &Space,
            f: &mut dyn FnMut(&[f64]) -> f64,
            init: &[Vec<f64>],
            _rng: &mut ChaCha8Rng,
        ) -> Minimum {
            self.0.lock().unwrap().push(init.to_vec());
            let x = init.first().cloned().unwrap_or(vec![0.0; space.dim()]);
            Minimum {
                value: f(&x),
                x,
                evaluations: 1,
            }
        }
        fn name(&self) -> &'static str {
            "recorder"
        }
    }

    #[test]
    fn straight_init_gives_the_straight_headings_or_nothing() {
        let problem = NavProblem::new(random_world(3, 2, 7).unwrap());
        let w = problem.world();
        let pos: Vec<Point> = w.robots.iter().map(|r| r.start).collect();
        let goals: Vec<Point> = w.robots.iter().map(|r| r.goal).collect();
        let moving = [0, 1, 2];
        for mode in [Mode::Joint, Mode::PerRobot] {
            let straight: Vec<f64> = moving.iter().map(|&i| toward(pos[i], goals[i])).collect();
            for on in [true, false] {
                let nav = Navigation {
                    mode,
                    straight_init: on,
                    ..Navigation::default()
                };
                let rec = Recorder(Mutex::new(Vec::new()));
                let mut rng = ChaCha8Rng::seed_from_u64(0);
                let h = nav.headings(&problem, &pos, &goals, &moving, &rec, &mut rng);
                let calls = rec.0.into_inner().unwrap();
                let expect: Vec<Vec<Vec<f64>>> = match (mode, on) {
                    (Mode::Joint, true) => vec![vec![straight.clone()]],
                    (Mode::Joint, false) => vec![vec![]],
                    (Mode::PerRobot, true) => straight.iter().map(|&t| vec![vec![t]]).collect(),
                    (Mode::PerRobot, false) => vec![vec![]; 3],
                };
                assert_eq!(calls, expect, "{mode:?}, straight_init {on}");
                let want = if on { straight.clone() } else { vec![0.0; 3] };
                assert_eq!(h, want);
            }
        }
    }
}
