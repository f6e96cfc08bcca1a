//! Windowed planning refined by large neighbourhood search (LNS), one step per call: the
//! planner `lifelong-lns` (`lifelong-pibt -p window=W`; WPPL, the 2023 League of Robot Runners winner:
//! H. Jiang, Y. Zhang, R. Veerapaneni, J. Li, "Scaling Lifelong Multi-Agent Path Finding to More
//! Realistic Settings: Research Challenges and Opportunities", SoCS 2024, arXiv 2404.16162,
//! §"Windowed Parallel PIBT-LNS"; LNS for MAPF: J. Li, Z. Chen, D. Harabor, P. J. Stuckey,
//! S. Koenig, "MAPF-LNS2: Fast Repairing for Multi-Agent Path Finding via Large Neighborhood
//! Search", AAAI 2022).
//!
//! Each step every robot holds a path of `W` steps from its current state (a state is a cell and,
//! under `MAPF_T`, an orientation). The cost of a path is the step at which it first stands on
//! the robot's goal, or, if it does not within the window, `W` plus the actions still needed from
//! its last state (hop distances under `MAPF`, the rotation-aware [`TurnDistances`] under
//! `MAPF_T`); a robot without a task has its own cell as goal and costs 0. The joint plan starts
//! as the cheaper of two: `W` steps of [`RotationPibt`] rolled out from the current states (the
//! first of them is PIBT's real step, so its priorities follow the run), and the plan of the
//! previous step shifted by one with a wait at the end (when the robots did what it said). LNS
//! then repeats, up to `iterations` times and while the step's time lasts: pick at random a
//! robot whose path costs more than its distance to the goal; its neighbourhood is that robot
//! and the robots whose paths come within one step of the cells along its shortest route (up to
//! `group` robots); their paths are re-planned one by one in a seeded random order by
//! space-time A* over (state, step, goal reached) against everyone else's paths (no vertex and no
//! swap conflict, the kit's rules; following is allowed); the new paths are kept when their total
//! cost is lower, else the old ones are put back. The first step of every path is the answer.
//!
//! Choices where WPPL's description leaves room (named here so they can be changed): one LNS
//! thread (WPPL runs several; results must not depend on the thread count); no guidance graph
//! (edge weights learned offline): the initial rollout follows the traffic-flow guide paths when
//! `guidance` says so, and LNS minimises plain distances unless told otherwise (below); an A* search stops after
//! [`MAX_EXPANSIONS`] states and the neighbourhood is then left as it was. With a count of
//! iterations that fits the step's time, a run is reproducible from its seed; when the time runs
//! out first the count depends on the machine, as with `guide_replans`. When the step's time
//! runs out during the rollout itself (thousands of robots, e.g. 10,000 on the kit v3's
//! `iron-example_10000`), the rollout stops there and every robot waits for the rest of the
//! window: the first step is always PIBT's, so the call answers in time.
//!
//! **Guided cost** (`lns_guide_weight`, [`LnsOptions::guide_weight`]). With plain distances
//! LNS is free to move a robot off its guide path into the lane of the oncoming flow whenever
//! that is as short, and on the kit's 5,000-robot warehouse the corridors then jam head on
//! (docs/performance.md, "Why the warehouse slows down"). With a weight `k` > 0, the actions
//! still needed from a path's last state to a robot's first errand gain the detour of its guide
//! path from there: `k` x the hops to the guide path + the guide path's moves left from where
//! it is met - the hop distance (never negative; 0 for a robot without a guide path to that
//! errand). At `k` = 1 a robot one row off its lane costs no more than one on it, since it could
//! step across at the end of the window; `k` >= 2 charges it for every hop it stays off.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use rand::seq::SliceRandom;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rustc_hash::FxHashSet;

use mrpp_core::Deadline;
use mrpp_core::mapf::graph::{Graph, VertexId};
use mrpp_core::mapf::search::distance::UNREACHABLE;

use crate::distances::{Distances, TurnDistances};
use crate::guide_paths::GuidePaths;
use crate::model::{Action, ActionModel, State, direction, neighbour};
use crate::problem::LifelongProblem;
use crate::rotation_pibt::RotationPibt;

const NIL: u32 = u32::MAX;

/// States one A* search may expand before it gives up (its neighbourhood keeps its paths).
pub const MAX_EXPANSIONS: usize = 20_000;

/// A cost far above any path's, for goals out of reach (kept small enough to sum).
const FAR: u32 = 1 << 20;

/// The options of windowed LNS (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LnsOptions {
    /// Steps planned ahead, `W` (1..=64).
    pub window: usize,
    /// LNS iterations per step at most.
    pub iterations: usize,
    /// Robots re-planned together at most.
    pub group: usize,
    /// Above this share of the free cells covered by robots, plan one PIBT step per call
    /// instead (no window): at 26% on a 10,000-robot warehouse the window's rollouts left the
    /// guide paths too little time (docs/lifelong.md).
    pub max_density: f64,
    /// What a path's cost counts beyond its steps and the actions still needed to the goal
    /// (module doc, "Guided cost"): with a weight `k` > 0, also the detour of the robot's
    /// traffic-flow guide path from where the path ends, each hop off the guide path counted
    /// `k` times (the named option `lns_guide_weight`; 0 = plain distances).
    pub guide_weight: u32,
}

/// Windowed LNS's state from step to step: the joint plan, the reservation table and scratch.
#[derive(Debug, Clone)]
pub struct WindowLns {
    options: LnsOptions,
    rng: ChaCha8Rng,
    vertices: usize,
    /// Neighbour of each vertex in each direction (0 east, 1 south, 2 west, 3 north), or `NIL`.
    next: Vec<[VertexId; 4]>,
    /// Each robot's states at steps 0..=W from now (empty before the first step).
    plan: Vec<Vec<State>>,
    /// Robot on each vertex at each step of the window: entry `t * vertices + v`, or `NIL`.
    table: Vec<u32>,
    /// What LNS did at the last step: iterations run and kept.
    pub last_iterations: usize,
    pub last_kept: usize,
}

/// How far a state is from a goal, in the action model's steps: rotation-aware for the goals
/// in `turn_goals` (those whose table was built when the step began), else hops (a lower bound
/// of the same). Fixed for the step, so that every cost of a step is measured alike.
struct Heuristic<'a> {
    dist: &'a mut Distances,
    graph: &'a Graph,
    turns: Option<&'a mut TurnDistances>,
    turn_goals: &'a FxHashSet<VertexId>,
    /// The guide paths whose detours a path's cost counts, with the weight of a hop off them
    /// ([`LnsOptions::guide_weight`]), else `None`.
    guide: Option<(&'a mut GuidePaths, u32)>,
}

impl Heuristic<'_> {
    fn get(&mut self, s: State, goal: VertexId) -> u32 {
        let d = match self.turns.as_deref_mut() {
            Some(t) if self.turn_goals.contains(&goal) => t.get(s.vertex, s.orientation, goal),
            _ => self.dist.get(self.graph, s.vertex, goal),
        };
        if d == UNREACHABLE { FAR } else { d.min(FAR) }
    }

    /// How much longer robot `robot`'s way from `v` to `goal` is along its guide path (`k`
    /// times the hops to the path, then the path) than the hop distance; 0 without a guide path
    /// to `goal`.
    fn detour(&mut self, robot: u32, v: VertexId, goal: VertexId) -> u32 {
        let Some((g, k)) = self.guide.as_mut() else {
            return 0;
        };
        if robot == NIL || !g.follows(robot as usize, goal) {
            return 0;
        }
        let (off, togo) = g.path_distance(robot as usize, v);
        let hops = self.dist.get(self.graph, v, goal);
        if off == UNREACHABLE || hops == UNREACHABLE {
            0
        } else {
            (off.saturating_mul(*k).saturating_add(togo))
                .saturating_sub(hops)
                .min(FAR)
        }
    }
}

impl WindowLns {
    /// State for a run on `problem`; every random choice comes from `seed`.
    ///
    /// # Panics
    /// If `options.window` is 0 (the registry only builds 1..=64).
    pub fn new(problem: &LifelongProblem, options: LnsOptions, seed: u64) -> Self {
        Self::on_map(problem.map(), options, seed)
    }

    fn on_map(map: &mrpp_mapf::GridMap, options: LnsOptions, seed: u64) -> Self {
        assert!(options.window >= 1, "a window of at least one step");
        let vertices = map.graph().num_vertices();
        WindowLns {
            options,
            rng: ChaCha8Rng::seed_from_u64(seed ^ 0x9e37_79b9_7f4a_7c15),
            vertices,
            next: (0..vertices as VertexId)
                .map(|v| std::array::from_fn(|d| neighbour(map, v, d as u8).unwrap_or(NIL)))
                .collect(),
            plan: Vec::new(),
            table: vec![NIL; (options.window + 1) * vertices],
            last_iterations: 0,
            last_kept: 0,
        }
    }

    /// The joint action of one step towards `goals` (one vertex per robot, as for
    /// [`RotationPibt::step`], which rolls out the first plan with `guide`, and with `turns`
    /// when `pibt_turns`); `turns` are the rotation-aware tables LNS measures `MAPF_T` paths
    /// with (hop distances without them). LNS stops at `deadline`.
    #[allow(clippy::too_many_arguments)]
    pub fn step(
        &mut self,
        problem: &LifelongProblem,
        states: &[State],
        goals: &[VertexId],
        seconds: &[VertexId],
        pibt: &mut RotationPibt,
        dist: &mut Distances,
        mut guide: Option<&mut GuidePaths>,
        mut turns: Option<&mut TurnDistances>,
        pibt_turns: bool,
        deadline: Deadline,
    ) -> Vec<Action> {
        let w = self.options.window;
        let n = states.len();
        let model = problem.model();
        let map = problem.map();
        // The previous plan shifted, if the robots followed it.
        let shifted: Option<Vec<Vec<State>>> = (self.plan.len() == n
            && self.plan.iter().zip(states).all(|(p, s)| p[1] == *s))
        .then(|| {
            self.plan
                .iter()
                .map(|p| {
                    let mut q = p[1..].to_vec();
                    q.push(p[w]);
                    q
                })
                .collect()
        });
        // The PIBT rollout.
        let mut rollout: Vec<Vec<State>> = states.iter().map(|&s| vec![s]).collect();
        let mut now = states.to_vec();
        let mut ghost: Option<RotationPibt> = None;
        for k in 0..w {
            if k > 0 && deadline.expired() {
                // Out of time: the rest of the window waits (module doc).
                for r in &mut rollout {
                    let last = *r.last().expect("the start state");
                    r.push(last);
                }
                continue;
            }
            let p = if k == 0 {
                &mut *pibt
            } else {
                ghost.get_or_insert_with(|| pibt.clone())
            };
            let actions = p.step(
                problem,
                &now,
                goals,
                dist,
                guide.as_deref_mut(),
                turns.as_deref_mut().filter(|_| pibt_turns),
            );
            for (i, a) in actions.into_iter().enumerate() {
                now[i] = crate::model::apply(map, now[i], a).expect("PIBT proposes legal actions");
                rollout[i].push(now[i]);
            }
        }
        // Rotation-aware distances for the goals whose tables are built; the others' are
        // built after LNS if time is left (building them now could make the step late).
        let turns = turns.filter(|_| model == ActionModel::MapfT);
        let mut turn_goals = FxHashSet::default();
        let mut missing = Vec::new();
        if let Some(t) = turns.as_deref() {
            let mut asked = FxHashSet::default();
            for &g in goals.iter().chain(seconds).filter(|&&g| g != NIL) {
                if !asked.insert(g) {
                    continue;
                }
                if t.has(g) {
                    turn_goals.insert(g);
                } else {
                    missing.push(g);
                }
            }
        }
        let mut h = Heuristic {
            dist,
            graph: map.graph(),
            turns,
            turn_goals: &turn_goals,
            guide: guide
                .filter(|_| self.options.guide_weight > 0)
                .map(|g| (g, self.options.guide_weight)),
        };
        let errands: Vec<Errands> = goals
            .iter()
            .zip(seconds)
            .enumerate()
            .map(|(i, (&first, &second))| Errands {
                robot: i as u32,
                first,
                second,
                // The most actions from the first errand, whichever way the robot faces
                // there: a path that reaches it never looks worse than one that does not.
                between: if second == NIL {
                    0
                } else {
                    (0..4)
                        .map(|o| {
                            h.get(
                                State {
                                    vertex: first,
                                    orientation: o,
                                },
                                second,
                            )
                        })
                        .max()
                        .unwrap_or(0)
                },
            })
            .collect();
        let mut costs: Vec<u32> = rollout
            .iter()
            .zip(&errands)
            .map(|(p, &e)| path_cost(p, e, &mut h))
            .collect();
        if let Some(sh) = shifted {
            let c: Vec<u32> = sh
                .iter()
                .zip(&errands)
                .map(|(p, &e)| path_cost(p, e, &mut h))
                .collect();
            if sum(&c) < sum(&costs) {
                rollout = sh;
                costs = c;
            }
        }
        self.plan = rollout;
        self.table.fill(NIL);
        for i in 0..n {
            self.reserve(i, true);
        }
        // Lower bounds: each robot's cost without a delay.
        let floor: Vec<u32> = states
            .iter()
            .zip(&errands)
            .map(|(&s, &e)| e.left(e.stage_after(0, s.vertex), s, &mut h))
            .collect();
        self.last_iterations = 0;
        self.last_kept = 0;
        let mut group = Vec::new();
        let mut seen = FxHashSet::default();
        for _ in 0..self.options.iterations {
            if deadline.expired() {
                break;
            }
            let delayed: Vec<usize> = (0..n).filter(|&i| costs[i] > floor[i]).collect();
            let Some(&a) = delayed.get(self.rng.random_range(0..delayed.len().max(1))) else {
                break;
            };
            self.last_iterations += 1;
            self.neighbourhood(a, goals[a], &mut h, &mut group, &mut seen);
            group.shuffle(&mut self.rng);
            let old: Vec<Vec<State>> = group.iter().map(|&i| self.plan[i].clone()).collect();
            let old_cost: u64 = group.iter().map(|&i| u64::from(costs[i])).sum();
            for &i in &group {
                self.reserve(i, false);
            }
            let mut new_costs = Vec::with_capacity(group.len());
            let mut ok = true;
            for &i in &group {
                match self.search(model, states[i], errands[i], &mut h) {
                    Some((path, c)) => {
                        self.plan[i] = path;
                        self.reserve(i, true);
                        new_costs.push(c);
                    }
                    None => {
                        ok = false;
                        break;
                    }
                }
            }
            let new_cost: u64 = new_costs.iter().map(|&c| u64::from(c)).sum();
            if ok && new_cost <= old_cost {
                self.last_kept += 1;
                for (&i, &c) in group.iter().zip(&new_costs) {
                    costs[i] = c;
                }
            } else {
                for (k, &i) in group.iter().enumerate() {
                    if k < new_costs.len() {
                        self.reserve(i, false);
                    }
                }
                for (&i, p) in group.iter().zip(old) {
                    self.plan[i] = p;
                    self.reserve(i, true);
                }
            }
        }
        if let Some(t) = h.turns {
            t.warm(&missing, &[deadline]);
        }
        self.plan
            .iter()
            .map(|p| action_between(map, model, p[0], p[1]))
            .collect()
    }

    /// Writes (or, with `on` false, clears) robot `i`'s path in the reservation table.
    fn reserve(&mut self, i: usize, on: bool) {
        for (t, s) in self.plan[i].iter().enumerate() {
            let slot = &mut self.table[t * self.vertices + s.vertex as usize];
            if on {
                debug_assert_eq!(*slot, NIL, "a vertex conflict in the windowed plan");
                *slot = i as u32;
            } else if *slot == i as u32 {
                *slot = NIL;
            }
        }
    }

    /// Robot `a` and the robots whose paths come within one step of the cells of `a`'s
    /// shortest route (greedy descent of the distance to `goal`), at most `group` in all.
    fn neighbourhood(
        &mut self,
        a: usize,
        goal: VertexId,
        h: &mut Heuristic<'_>,
        group: &mut Vec<usize>,
        seen: &mut FxHashSet<usize>,
    ) {
        group.clear();
        seen.clear();
        group.push(a);
        seen.insert(a);
        let w = self.options.window;
        let mut s = self.plan[a][0];
        for t in 0..=w {
            if group.len() >= self.options.group {
                break;
            }
            for dt in [t, t + 1, t.saturating_sub(1)] {
                if dt > w {
                    continue;
                }
                let j = self.table[dt * self.vertices + s.vertex as usize];
                if j != NIL && group.len() < self.options.group && seen.insert(j as usize) {
                    group.push(j as usize);
                }
            }
            // One step along the route: the neighbour nearest the goal.
            let best = self.next[s.vertex as usize]
                .iter()
                .filter(|&&v| v != NIL)
                .map(|&v| State { vertex: v, ..s })
                .min_by_key(|&c| h.get(c, goal));
            match best {
                Some(c) if h.get(c, goal) < h.get(s, goal) || s.vertex == goal => s = c,
                _ => break,
            }
        }
    }

    /// Space-time A* for one robot from `start` against the reservation table (module doc):
    /// its path of W + 1 states and the path's cost, or `None` when no path exists within
    /// [`MAX_EXPANSIONS`] states.
    fn search(
        &self,
        model: ActionModel,
        start: State,
        errands: Errands,
        h: &mut Heuristic<'_>,
    ) -> Option<(Vec<State>, u32)> {
        #[derive(Clone, Copy)]
        struct Node {
            s: State,
            t: u8,
            stage: u8,
            g: u32,
            parent: u32,
        }
        let w = self.options.window;
        let v = self.vertices;
        let mut nodes = vec![Node {
            s: start,
            t: 0,
            stage: errands.stage_after(0, start.vertex),
            g: 0,
            parent: NIL,
        }];
        let f0 = errands.left(nodes[0].stage, start, h);
        let mut open = BinaryHeap::new();
        open.push(Reverse((f0, w as u8, 0u32)));
        let mut closed = FxHashSet::default();
        let mut succ = Vec::with_capacity(5);
        while let Some(Reverse((f, _, k))) = open.pop() {
            let node = nodes[k as usize];
            let key = (node.s, node.t, node.stage);
            if !closed.insert(key) {
                continue;
            }
            if node.t as usize == w {
                let mut path = vec![node.s; w + 1];
                let mut k = k;
                while k != NIL {
                    let nd = nodes[k as usize];
                    path[nd.t as usize] = nd.s;
                    k = nd.parent;
                }
                return Some((path, f));
            }
            if closed.len() > MAX_EXPANSIONS {
                return None;
            }
            succ.clear();
            let (u, o) = (node.s.vertex, node.s.orientation);
            succ.push(node.s);
            match model {
                ActionModel::MapfT => {
                    succ.push(State {
                        vertex: u,
                        orientation: (o + 1) % 4,
                    });
                    succ.push(State {
                        vertex: u,
                        orientation: (o + 3) % 4,
                    });
                    let ahead = self.next[u as usize][o as usize];
                    if ahead != NIL {
                        succ.push(State {
                            vertex: ahead,
                            orientation: o,
                        });
                    }
                }
                ActionModel::Mapf => {
                    for &x in &self.next[u as usize] {
                        if x != NIL {
                            succ.push(State {
                                vertex: x,
                                orientation: o,
                            });
                        }
                    }
                }
            }
            let t = node.t as usize;
            for &c in &succ {
                let x = c.vertex as usize;
                if self.table[(t + 1) * v + x] != NIL {
                    continue;
                }
                if c.vertex != u {
                    let j = self.table[t * v + x];
                    if j != NIL && self.table[(t + 1) * v + u as usize] == j {
                        continue; // a swap
                    }
                }
                let stage = errands.stage_after(node.stage, c.vertex);
                if closed.contains(&(c, node.t + 1, stage)) {
                    continue;
                }
                let g = if node.stage == DONE {
                    node.g
                } else {
                    t as u32 + 1
                };
                let f = g + errands.left(stage, c, h);
                nodes.push(Node {
                    s: c,
                    t: node.t + 1,
                    stage,
                    g,
                    parent: k,
                });
                open.push(Reverse((f, (w - t - 1) as u8, (nodes.len() - 1) as u32)));
            }
        }
        None
    }
}

/// A path's cost (module doc): the step it finishes its errands, else its length plus the
/// actions left.
fn path_cost(path: &[State], errands: Errands, h: &mut Heuristic<'_>) -> u32 {
    let mut stage = errands.stage_after(0, path[0].vertex);
    if stage == DONE {
        return 0;
    }
    for (t, s) in path.iter().enumerate().skip(1) {
        stage = errands.stage_after(stage, s.vertex);
        if stage == DONE {
            return t as u32;
        }
    }
    let end = path[path.len() - 1];
    (path.len() as u32 - 1) + errands.left(stage, end, h)
}

/// The stage a path has reached: heading for the first errand, for the second, or done.
const DONE: u8 = 2;

/// A robot's errands within reach of a window: its next errand and the one after it in the same
/// task (`NIL`: none), and the hop distance between them.
#[derive(Debug, Clone, Copy)]
pub struct Errands {
    /// The robot, whose guide path's detour counts with a guide weight (`u32::MAX`: none).
    pub robot: u32,
    /// The next errand (the robot's own cell when it has no task).
    pub first: VertexId,
    /// The errand after it in the same task, or `u32::MAX`.
    pub second: VertexId,
    /// Actions from `first` to `second`, facing the worst way at `first` (0 without a second).
    pub between: u32,
}

impl Errands {
    /// The stage after standing on `v` in stage `stage` (one errand per step, as the kit counts).
    fn stage_after(self, stage: u8, v: VertexId) -> u8 {
        match stage {
            0 if v == self.first => {
                if self.second == NIL {
                    DONE
                } else {
                    1
                }
            }
            1 if v == self.second => DONE,
            _ => stage,
        }
    }

    /// The actions left from `s` in `stage`: to the errand it heads for, plus `between` when both
    /// errands are ahead.
    fn left(self, stage: u8, s: State, h: &mut Heuristic<'_>) -> u32 {
        match stage {
            0 if self.second == NIL => {
                h.get(s, self.first) + h.detour(self.robot, s.vertex, self.first)
            }
            0 => h.get(s, self.first) + h.detour(self.robot, s.vertex, self.first) + self.between,
            1 => h.get(s, self.second),
            _ => 0,
        }
    }
}

fn sum(costs: &[u32]) -> u64 {
    costs.iter().map(|&c| u64::from(c)).sum()
}

/// The action that takes a robot from `a` to `b` (a legal step of `model`).
fn action_between(map: &mrpp_mapf::GridMap, model: ActionModel, a: State, b: State) -> Action {
    if a.vertex != b.vertex {
        return match model {
            ActionModel::MapfT => Action::Forward,
            ActionModel::Mapf => {
                Action::Move(direction(map, a.vertex, b.vertex).expect("a neighbour"))
            }
        };
    }
    if b.orientation == (a.orientation + 1) % 4 {
        Action::Clockwise
    } else if b.orientation == (a.orientation + 3) % 4 {
        Action::CounterClockwise
    } else {
        Action::Wait
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::EAST;
    use mrpp_mapf::GridMap;

    const OPTIONS: LnsOptions = LnsOptions {
        max_density: 1.0,
        window: 6,
        iterations: 10,
        group: 4,
        guide_weight: 0,
    };

    fn at(vertex: VertexId, orientation: u8) -> State {
        State {
            vertex,
            orientation,
        }
    }

    /// A corridor of 5 cells, 0..=4 from west to east.
    fn corridor() -> (GridMap, Distances) {
        let map = GridMap::from_free_rows(&[vec![true; 5]]);
        let dist = Distances::new(5, 1 << 20);
        (map, dist)
    }

    #[test]
    fn a_free_corridor_is_walked_straight_and_costs_its_length() {
        let (map, mut dist) = corridor();
        let lns = WindowLns::on_map(&map, OPTIONS, 1);
        let empty = FxHashSet::default();
        let mut h = Heuristic {
            dist: &mut dist,
            graph: map.graph(),
            turns: None,
            turn_goals: &empty,
            guide: None,
        };
        let e = Errands {
            robot: NIL,
            first: 3,
            second: NIL,
            between: 0,
        };
        let (path, cost) = lns
            .search(ActionModel::MapfT, at(0, EAST), e, &mut h)
            .unwrap();
        assert_eq!(cost, 3);
        assert_eq!(path.len(), 7);
        assert_eq!(&path[..4], &[at(0, 0), at(1, 0), at(2, 0), at(3, 0)]);
        assert_eq!(path_cost(&path, e, &mut h), 3);
    }

    #[test]
    fn a_reserved_cell_makes_the_robot_wait_and_a_swap_is_refused() {
        let (map, mut dist) = corridor();
        let mut lns = WindowLns::on_map(&map, OPTIONS, 1);
        // Robot 0 stands on cell 2 for two steps, then leaves eastwards.
        lns.plan = vec![vec![
            at(2, 0),
            at(2, 0),
            at(2, 0),
            at(3, 0),
            at(4, 0),
            at(4, 0),
            at(4, 0),
        ]];
        lns.reserve(0, true);
        let empty = FxHashSet::default();
        let mut h = Heuristic {
            dist: &mut dist,
            graph: map.graph(),
            turns: None,
            turn_goals: &empty,
            guide: None,
        };
        let e = Errands {
            robot: NIL,
            first: 3,
            second: NIL,
            between: 0,
        };
        let (path, cost) = lns
            .search(ActionModel::Mapf, at(1, EAST), e, &mut h)
            .unwrap();
        // Cell 2 is free from step 3, cell 3 from step 5 (robot 0 passes it at step 3).
        for (t, s) in path.iter().enumerate() {
            assert_ne!(
                s.vertex, lns.plan[0][t].vertex,
                "vertex conflict at step {t}"
            );
        }
        assert_eq!(cost, 4, "{path:?}");
        // Towards robot 0 head on: the only way is through it, so no path.
        lns.reserve(0, false);
        lns.plan = vec![vec![at(2, 2); 7]];
        for (k, s) in [at(2, 2), at(1, 2), at(0, 2)].into_iter().enumerate() {
            lns.plan[0][k] = s;
        }
        lns.plan[0][3..].fill(at(0, 2));
        lns.reserve(0, true);
        assert!(
            lns.search(ActionModel::Mapf, at(1, EAST), e, &mut h)
                .is_none()
        );
    }

    #[test]
    fn two_errands_count_from_the_first_and_finish_one_per_step() {
        let (map, mut dist) = corridor();
        let empty = FxHashSet::default();
        let mut h = Heuristic {
            dist: &mut dist,
            graph: map.graph(),
            turns: None,
            turn_goals: &empty,
            guide: None,
        };
        let e = Errands {
            robot: NIL,
            first: 2,
            second: 0,
            between: 2,
        };
        assert_eq!(e.stage_after(0, 2), 1);
        assert_eq!(e.stage_after(1, 2), 1);
        assert_eq!(e.stage_after(1, 0), DONE);
        // From cell 1: 1 step to errand 2, 2 back to cell 0.
        let there_and_back = [1, 2, 1, 0, 0].map(|v| at(v, EAST));
        assert_eq!(path_cost(&there_and_back, e, &mut h), 3);
        // Not reaching the first errand: the window plus both distances left.
        let waiting = [at(1, EAST); 3];
        assert_eq!(path_cost(&waiting, e, &mut h), 2 + 1 + 2);
        // No task: goal is its own cell, cost 0 however it moves.
        let idle = Errands {
            robot: NIL,
            first: 1,
            second: NIL,
            between: 0,
        };
        assert_eq!(path_cost(&[1, 2, 3].map(|v| at(v, EAST)), idle, &mut h), 0);
    }

    #[test]
    fn a_guided_cost_keeps_the_guide_paths_lane_and_a_plain_one_does_not() {
        // Three rows of 16: robot 0's guide path runs east along the middle row, so robot 1's,
        // going west along the same row, leaves it (contraflow). Plain costs send robot 1 down
        // the middle row; guided costs (weight 2) keep it on its guide path's lane.
        let map = GridMap::from_free_rows(&[vec![true; 16], vec![true; 16], vec![true; 16]]);
        let g = map.graph();
        let v = |x, y| map.vertex_at(x, y).unwrap();
        let mut dist = Distances::new(g.num_vertices(), 1 << 20);
        let mut guide = GuidePaths::new(&map, 2, 0);
        guide.update(&[v(0, 1)], &[v(15, 1)], 0, &mut dist, g, Deadline::none());
        let (cells, goals) = ([v(0, 1), v(15, 1)], [v(15, 1), v(0, 1)]);
        guide.update(&cells, &goals, 0, &mut dist, g, Deadline::none());
        let lns = WindowLns::on_map(&map, OPTIONS, 1);
        let empty = FxHashSet::default();
        let e = Errands {
            robot: 1,
            first: v(0, 1),
            second: NIL,
            between: 0,
        };
        let start = at(v(15, 1), 2);
        let mut plain = Heuristic {
            dist: &mut dist,
            graph: g,
            turns: None,
            turn_goals: &empty,
            guide: None,
        };
        let (path, cost) = lns.search(ActionModel::Mapf, start, e, &mut plain).unwrap();
        assert_eq!(cost, 15);
        assert!(path.iter().all(|s| map.cell(s.vertex).1 == 1), "{path:?}");
        let mut guided = Heuristic {
            guide: Some((&mut guide, 2)),
            ..plain
        };
        let (path, cost) = lns
            .search(ActionModel::Mapf, start, e, &mut guided)
            .unwrap();
        let end = map.cell(path[OPTIONS.window].vertex);
        assert_ne!(
            end.1, 1,
            "the window ends on the guide path's lane: {path:?}"
        );
        // The guide path is two moves longer than the middle row, and that is the cost's excess.
        assert_eq!(cost, 17);
        assert_eq!(guided.detour(1, v(15, 1), v(0, 1)), 2);
        // One hop off the lane counts twice; robot 0 has no guide path to robot 1's goal.
        assert_eq!(guided.detour(1, v(9, 1), v(0, 1)), 2 + 10 - 9);
        assert_eq!(guided.detour(0, v(9, 1), v(0, 1)), 0);
    }
}
