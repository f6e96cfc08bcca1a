//! Running a program on a tree instance: every time step the robots execute the program one after
//! the other in id order, each seeing the moves the robots before it just made (§3, §7: "the
//! robots sequentially execute the learned program"), until every robot has visited its goal or
//! the step cap is reached. The semantics of each conditional and action, and the choices made
//! where the paper is silent, are listed in the documentation of [`super`].
//!
//! The run also gives the fitness of equation (1): 0 when the instance is solved, else the sum
//! over robots of the squared tree distance from where the robot stands at the cap to its goal.
//! A program is deterministic, so when the whole simulation state (positions, path targets,
//! visited sets, branch lists, solved flags) repeats, the run would cycle until the cap without
//! ever solving: the cycle is found with Brent's method and the positions at the cap are reached by
//! running only `(cap − step) mod period` more steps, which gives exactly the fitness a run to the
//! cap would give, in a fraction of the time (the paper's cap M = |N|²·|R|² runs to 10⁵–10⁷ steps).

use std::borrow::Cow;
use std::sync::OnceLock;

use crate::gp::program::{Action, Conditional, Program};
use crate::instance::TreeInstance;
use crate::psw::step_cap;
use crate::rooted::RootedTree;
use mrpp_core::contract::{Deadline, Unsolved};
use mrpp_core::mapf::graph::{Graph, VertexId};
use mrpp_core::mapf::instance::Instance;
use mrpp_core::mapf::plan::Plan;

const NONE: u32 = u32::MAX;

/// Branch nodes cached per node, nearest first (bounds the cache at 64·|N| entries).
const CACHED_BRANCHES: usize = 64;

/// Robot decisions between two polls of the deadline (one decision is a fraction of a
/// microsecond to a few microseconds, so a run notices its deadline within about a millisecond,
/// however many robots a step moves, and a poll costs nothing measurable).
const POLL_DECISIONS: u32 = 256;

/// Trees of at most this many nodes get a next-hop table of |N|² entries (8 MiB at the limit);
/// larger ones answer path questions from [`RootedTree`] (DFS intervals, O(log degree)).
pub const HOP_TABLE_MAX_NODES: usize = 2048;

/// What becomes of a robot's path once it stands on the branch node it set its path to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BranchArrival {
    /// The path stays set to the branch (the robot's current path is empty, so
    /// Move-Toward-Objective leaves it there) until If-Robot-At-Branch sees the robot on it, which
    /// resets the path to the objective (the authors' code).
    Hold,
    /// The path goes back to the objective on arrival; If-Robot-At-Branch stays true while the
    /// robot stands on the branch it reached. Default.
    #[default]
    Resume,
}

impl BranchArrival {
    /// `resume` or `hold`.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "resume" => Some(BranchArrival::Resume),
            "hold" => Some(BranchArrival::Hold),
            _ => None,
        }
    }
}

/// Which node Move-To-Free-Neighbor takes (in adjacency order within each tier; when every
/// adjacent node has been visited, they are all forgotten first).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FreeNeighbor {
    /// Only nodes the robot has never stood on (Table 2 as written): off its current path first,
    /// then the next node of its path.
    Unvisited,
    /// The authors' code: a never-visited node off the current path, else a visited one (any).
    /// Default.
    #[default]
    OffPathThenVisited,
}

/// Simulation switches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SimOptions {
    /// ρ: robots within this many hops are in a robot's direct communication network c(r_i)
    /// (paper: 2).
    pub radius: u32,
    /// A robot may move into a node that another robot left earlier in the same step. With
    /// `false`, such a node counts as occupied for the rest of the step (validate the plan with
    /// following forbidden then).
    pub allow_following: bool,
    pub branch_arrival: BranchArrival,
    pub free_neighbor: FreeNeighbor,
    /// Stop a run as soon as its state repeats (exact: the fitness at the cap is still computed).
    pub detect_cycles: bool,
}

impl Default for SimOptions {
    fn default() -> Self {
        SimOptions {
            radius: 2,
            allow_following: true,
            branch_arrival: BranchArrival::Resume,
            free_neighbor: FreeNeighbor::OffPathThenVisited,
            detect_cycles: true,
        }
    }
}

/// A tree instance prepared for simulation (the tree rooted at node 0, its branch nodes, the cap).
#[derive(Debug, Clone)]
pub struct Problem {
    graph: Graph,
    inst: Instance,
    tree: RootedTree,
    /// The next-hop table, up to [`HOP_TABLE_MAX_NODES`] nodes.
    hops: Option<HopTable>,
    is_branch: Vec<bool>,
    has_branch: bool,
    /// Per node, the branch nodes in BFS order from it (adjacency order), computed on first use
    /// and shared by every run and thread (If-Two-Robots-On-Each-Others-Path and
    /// Move-Toward-Branch ask for the nearest untried one all the time).
    branch_order: Vec<OnceLock<Box<[VertexId]>>>,
}

impl Problem {
    /// Fails when the graph is not a tree or a start/goal is not one of its nodes.
    pub fn new(graph: &Graph, inst: &Instance) -> Result<Self, String> {
        let tree = RootedTree::new(graph, 0)?;
        let n = graph.num_vertices();
        if let Some(&v) = inst
            .starts
            .iter()
            .chain(&inst.goals)
            .find(|&&v| v as usize >= n)
        {
            return Err(format!(
                "node {v} of the instance is not a node of the tree"
            ));
        }
        if inst.starts.len() != inst.goals.len() {
            return Err("as many goals as starts are needed".into());
        }
        let is_branch: Vec<bool> = (0..n as VertexId).map(|v| tree.is_branch(v)).collect();
        let has_branch = is_branch.iter().any(|&b| b);
        let hops = (n <= HOP_TABLE_MAX_NODES).then(|| HopTable::new(graph));
        Ok(Problem {
            graph: graph.clone(),
            inst: inst.clone(),
            tree,
            hops,
            is_branch,
            has_branch,
            branch_order: (0..n).map(|_| OnceLock::new()).collect(),
        })
    }

    pub fn from_tree_instance(t: &TreeInstance) -> Self {
        Problem::new(&t.graph, &t.instance).expect("a TreeInstance holds a tree and its robots")
    }

    pub fn graph(&self) -> &Graph {
        &self.graph
    }

    pub fn instance(&self) -> &Instance {
        &self.inst
    }

    pub fn num_robots(&self) -> usize {
        self.inst.num_agents()
    }

    /// The branch nodes in BFS order from `v` (neighbours in adjacency order), nearest first, at
    /// most [`CACHED_BRANCHES`] of them (cached), or all of them (`all`, not cached).
    fn branches_by_distance(&self, v: VertexId, all: bool) -> Cow<'_, [VertexId]> {
        let bfs = |limit: usize| -> Vec<VertexId> {
            let mut order = Vec::new();
            let mut queue = vec![(v, NONE)];
            let mut head = 0;
            while head < queue.len() && order.len() < limit && self.has_branch {
                let (x, from) = queue[head];
                head += 1;
                if self.is_branch[x as usize] {
                    order.push(x);
                }
                queue.extend(
                    self.graph
                        .neighbors(x)
                        .iter()
                        .filter(|&&w| w != from)
                        .map(|&w| (w, x)),
                );
            }
            order
        };
        if all {
            Cow::Owned(bfs(usize::MAX))
        } else {
            Cow::Borrowed(self.branch_order[v as usize].get_or_init(|| bfs(CACHED_BRANCHES).into()))
        }
    }

    /// The paper's cap M = |N|²·|R|².
    pub fn step_cap(&self) -> u64 {
        step_cap(self.graph.num_vertices(), self.num_robots())
    }

    /// No program solves the instance in fewer steps: the longest start–goal distance.
    pub fn lower_bound(&self) -> u64 {
        self.inst
            .starts
            .iter()
            .zip(&self.inst.goals)
            .map(|(&s, &g)| u64::from(self.tree.distance(s, g)))
            .max()
            .unwrap_or(0)
    }

    /// Equation (1) for an unsolved run: Σ_j dist(A(r_j), g(r_j))².
    pub fn squared_distances(&self, positions: &[VertexId]) -> u64 {
        positions
            .iter()
            .zip(&self.inst.goals)
            .map(|(&p, &g)| {
                let d = u64::from(self.tree.distance(p, g));
                d * d
            })
            .sum()
    }
}

/// The path questions the simulator asks of the tree (paths are unique), answered by a
/// [`HopTable`] on trees of up to [`HOP_TABLE_MAX_NODES`] nodes and by the [`RootedTree`] (DFS
/// intervals, O(log degree)) on larger ones; the simulator is compiled once for each.
trait TreePaths {
    /// The node after `u` on the path from `u` to `v` (`u` itself when `u == v`).
    fn next_hop(&self, u: VertexId, v: VertexId) -> VertexId;
    /// Whether `x` lies on the path from `u` to `v`, ends included; `u != v` is required.
    fn on_path(&self, x: VertexId, u: VertexId, v: VertexId) -> bool;
}

impl TreePaths for RootedTree {
    #[inline]
    fn next_hop(&self, u: VertexId, v: VertexId) -> VertexId {
        RootedTree::next_hop(self, u, v)
    }

    #[inline]
    fn on_path(&self, x: VertexId, u: VertexId, v: VertexId) -> bool {
        RootedTree::on_path(self, x, u, v)
    }
}

/// `hop[u·|N| + v]`: the node after `u` on the path from `u` to `v` (`u` when `u == v`), |N|²
/// entries of 2 bytes.
#[derive(Debug, Clone)]
struct HopTable {
    n: usize,
    hop: Box<[u16]>,
}

impl HopTable {
    /// For every node `u`, a walk from each neighbour `w` labels everything beyond it with `w`.
    /// O(|N|²); `g` must be a tree of at most [`HOP_TABLE_MAX_NODES`] nodes.
    fn new(g: &Graph) -> Self {
        let n = g.num_vertices();
        assert!(n <= HOP_TABLE_MAX_NODES);
        let mut hop = vec![0u16; n * n];
        let mut stack: Vec<(VertexId, VertexId)> = Vec::new();
        for u in 0..n as VertexId {
            let row = &mut hop[u as usize * n..(u as usize + 1) * n];
            row[u as usize] = u as u16;
            for &w in g.neighbors(u) {
                stack.push((w, u));
                while let Some((x, from)) = stack.pop() {
                    row[x as usize] = w as u16;
                    stack.extend(
                        g.neighbors(x)
                            .iter()
                            .filter(|&&y| y != from)
                            .map(|&y| (y, x)),
                    );
                }
            }
        }
        HopTable {
            n,
            hop: hop.into_boxed_slice(),
        }
    }
}

impl TreePaths for HopTable {
    #[inline]
    fn next_hop(&self, u: VertexId, v: VertexId) -> VertexId {
        VertexId::from(self.hop[u as usize * self.n + v as usize])
    }

    /// The first steps from `x` toward `u` and toward `v` differ exactly when `x` is on the path
    /// (at an end, one of them is `x` itself).
    #[inline]
    fn on_path(&self, x: VertexId, u: VertexId, v: VertexId) -> bool {
        debug_assert_ne!(u, v);
        let row = x as usize * self.n;
        self.hop[row + u as usize] != self.hop[row + v as usize]
    }
}

/// Why a run stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// Every robot has visited its goal.
    Solved,
    /// The step cap was reached.
    StepCap,
    /// The state at `step` repeats the one `period` steps before: the run would cycle until the cap.
    Cycle { step: u64, period: u64 },
    /// The deadline passed (or the memory limit was exceeded) before the run ended: the run is
    /// incomplete, so it has neither a fitness nor a plan ([`Outcome::fitness`] is `u64::MAX`).
    TimeLimit,
}

/// The result of one run.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Outcome {
    pub stop: Stop,
    /// Time steps used: the solve time τ when solved, the cap when the step cap or a cycle ended
    /// the run, the steps completed when the deadline stopped it.
    pub steps: u64,
    /// Equation (1): 0 when solved, else Σ_j dist(A(r_j, cap), g(r_j))²; `u64::MAX` for a run
    /// stopped by the deadline ([`Stop::TimeLimit`]), which has no fitness.
    pub fitness: u64,
    /// Positions of every robot at every step (only when asked for; up to the stop, not beyond a
    /// detected cycle).
    pub paths: Vec<Vec<VertexId>>,
}

impl Outcome {
    pub fn solved(&self) -> bool {
        self.stop == Stop::Solved
    }
}

/// Runs `program` on `problem` for at most `cap` steps, recording every robot's positions when
/// `record` is set. The deadline is polled every few hundred robot decisions (within a time step
/// too) and once before the run starts, so a run with an expired deadline stops at once with
/// [`Stop::TimeLimit`] (unless every robot starts on its goal).
pub fn run_program(
    program: &Program,
    problem: &Problem,
    opts: &SimOptions,
    cap: u64,
    record: bool,
    deadline: Deadline,
) -> Outcome {
    run_marking(program, problem, opts, cap, record, deadline, &mut [])
}

/// [`run_program`] without recording, also setting in `reached` (a bitset over the program's
/// node indices, at least `program.len().div_ceil(64)` words, or empty for no marking; bits
/// already set stay set) every node that some decision of the run passes through. A program that differs from `program` only
/// inside a subtree whose root is not in `reached` makes the same decisions, so its run (and
/// fitness) is identical. Not meaningful for a run stopped by the deadline ([`Stop::TimeLimit`]).
pub fn run_program_marking(
    program: &Program,
    problem: &Problem,
    opts: &SimOptions,
    cap: u64,
    deadline: Deadline,
    reached: &mut [u64],
) -> Outcome {
    assert!(reached.is_empty() || reached.len() >= program.len().div_ceil(64));
    run_marking(program, problem, opts, cap, false, deadline, reached)
}

fn run_marking(
    program: &Program,
    problem: &Problem,
    opts: &SimOptions,
    cap: u64,
    record: bool,
    deadline: Deadline,
    reached: &mut [u64],
) -> Outcome {
    // Before building the simulation (ball tables, bitsets), which takes a millisecond on trees
    // of thousands of nodes: a generation cut by the deadline then ends without building one per
    // program still to evaluate.
    if problem.inst.starts != problem.inst.goals && deadline.expired() {
        return Outcome {
            stop: Stop::TimeLimit,
            steps: 0,
            fitness: u64::MAX,
            paths: Vec::new(),
        };
    }
    match &problem.hops {
        Some(table) => Sim::new(problem, table, opts, record).run(program, cap, deadline, reached),
        None => Sim::new(problem, &problem.tree, opts, record).run(program, cap, deadline, reached),
    }
}

/// Runs `program` with the paper's cap M and returns its plan when every robot visits its goal.
/// The plan passes [`crate::validate_tree_plan`] (with following as in `opts`). Both the first
/// run and the replay that records the plan are under `deadline`: [`Unsolved::TimeLimit`] when
/// it passes in either.
pub fn plan_program(
    program: &Program,
    problem: &Problem,
    opts: &SimOptions,
    deadline: Deadline,
) -> Result<(Plan, Outcome), Unsolved> {
    let cap = problem.step_cap();
    // A first run records nothing (an unsolved run may last M ≈ 10⁷ steps); only a solving run is
    // replayed, with its positions recorded, up to its solve time.
    let out = run_program(program, problem, opts, cap, false, deadline);
    match out.stop {
        Stop::Solved => {
            let mut rec = run_program(program, problem, opts, out.steps, true, deadline);
            if rec.stop == Stop::TimeLimit {
                return Err(Unsolved::TimeLimit);
            }
            debug_assert_eq!(rec.stop, Stop::Solved);
            let plan = Plan::new(std::mem::take(&mut rec.paths));
            Ok((plan, rec))
        }
        Stop::TimeLimit => Err(Unsolved::TimeLimit),
        Stop::StepCap => Err(Unsolved::GaveUp(format!(
            "the program did not solve the instance within the step cap M = {cap}"
        ))),
        Stop::Cycle { step, period } => Err(Unsolved::GaveUp(format!(
            "the program cycles (the state at step {step} repeats every {period} steps) without \
             solving the instance, so it would not solve it within the step cap M = {cap}"
        ))),
    }
}

/// Everything a run changes; two equal states lead to equal futures.
#[derive(Debug, Clone, PartialEq, Eq)]
struct State {
    pos: Vec<VertexId>,
    /// The branch node each robot has set its path to, or NONE (path to the objective).
    branch: Vec<VertexId>,
    /// [`BranchArrival::Resume`]: the branch each robot reached and still stands on, or NONE.
    at_branch: Vec<VertexId>,
    /// Goal visited (If-Robot-Is-Solved; the instance is solved when all are).
    solved: Vec<bool>,
    /// Per robot, a bitset of the nodes it has stood on (Move-To-Free-Neighbor).
    visited: Vec<u64>,
    /// Per robot, a bitset of the branch nodes it has already chosen.
    tried: Vec<u64>,
}

struct Sim<'a, T: TreePaths> {
    p: &'a Problem,
    paths_of: &'a T,
    o: &'a SimOptions,
    s: State,
    words: usize,
    /// Robot on each node, or NONE.
    occ: Vec<u32>,
    /// Stamp of the step in which a robot last left each node (for `allow_following = false`).
    vacated: Vec<u64>,
    stamp: u64,
    step: u64,
    unsolved: usize,
    record: bool,
    paths: Vec<Vec<VertexId>>,
    /// Robot decisions left before the next poll of the deadline.
    poll_in: u32,
    /// Where each robot's current path leads: `branch` when set, else its goal (kept in step with
    /// `s.branch` by [`Sim::set_path`]).
    tgt: Vec<VertexId>,
    /// The nodes within ρ hops of each node, in BFS order (adjacency order), node `v`'s at
    /// `ball[ball_at[v]..ball_at[v + 1]]`: the robots on them (but `v`'s own) are the network c(r)
    /// of a robot on `v`.
    ball: Vec<VertexId>,
    ball_at: Vec<u32>,
}

/// For every node, the nodes within `radius` hops in BFS order (the node first), flattened.
fn balls(g: &Graph, radius: u32) -> (Vec<VertexId>, Vec<u32>) {
    let mut ball = Vec::new();
    let mut ball_at = vec![0u32];
    let mut queue: Vec<(VertexId, VertexId, u32)> = Vec::new();
    for v in 0..g.num_vertices() as VertexId {
        queue.clear();
        queue.push((v, NONE, 0));
        let mut head = 0;
        while head < queue.len() {
            let (x, from, d) = queue[head];
            head += 1;
            ball.push(x);
            if d < radius {
                queue.extend(
                    g.neighbors(x)
                        .iter()
                        .filter(|&&w| w != from)
                        .map(|&w| (w, x, d + 1)),
                );
            }
        }
        ball_at.push(ball.len() as u32);
    }
    (ball, ball_at)
}

impl<'a, T: TreePaths> Sim<'a, T> {
    fn new(p: &'a Problem, paths_of: &'a T, o: &'a SimOptions, record: bool) -> Self {
        let n = p.graph.num_vertices();
        let r = p.num_robots();
        let words = n.div_ceil(64);
        let mut occ = vec![NONE; n];
        let mut visited = vec![0u64; r * words];
        for (i, &s) in p.inst.starts.iter().enumerate() {
            occ[s as usize] = i as u32;
            visited[i * words + s as usize / 64] |= 1 << (s % 64);
        }
        let solved: Vec<bool> = (0..r)
            .map(|i| p.inst.starts[i] == p.inst.goals[i])
            .collect();
        let unsolved = solved.iter().filter(|&&b| !b).count();
        let (ball, ball_at) = balls(&p.graph, o.radius);
        Sim {
            p,
            paths_of,
            o,
            s: State {
                pos: p.inst.starts.clone(),
                branch: vec![NONE; r],
                at_branch: vec![NONE; r],
                solved,
                visited,
                tried: vec![0u64; r * words],
            },
            words,
            occ,
            vacated: vec![0; n],
            stamp: 0,
            step: 0,
            unsolved,
            record,
            paths: if record {
                p.inst.starts.iter().map(|&s| vec![s]).collect()
            } else {
                Vec::new()
            },
            poll_in: POLL_DECISIONS,
            tgt: p.inst.goals.clone(),
            ball,
            ball_at,
        }
    }

    /// `reached`: empty, or the bitset of [`run_program_marking`].
    fn run(
        &mut self,
        program: &Program,
        cap: u64,
        deadline: Deadline,
        reached: &mut [u64],
    ) -> Outcome {
        // Brent's cycle detection: compare with a snapshot taken at steps 1, 2, 4, 8, ...
        let mut saved = self.s.clone();
        let (mut power, mut lam) = (1u64, 0u64);
        loop {
            if self.unsolved == 0 {
                return self.outcome(Stop::Solved, self.step, 0);
            }
            if self.step >= cap {
                let f = self.p.squared_distances(&self.s.pos);
                return self.outcome(Stop::StepCap, cap, f);
            }
            if !self.time_step(program, reached, deadline) {
                return self.outcome(Stop::TimeLimit, self.step, u64::MAX);
            }
            if !self.o.detect_cycles || self.unsolved == 0 {
                continue;
            }
            lam += 1;
            if self.s == saved {
                // The run repeats every `lam` steps from here on and never solves: the positions
                // at the cap are those `(cap - step) mod lam` steps ahead.
                let at = self.step;
                if at < cap {
                    let ahead = (cap - at) % lam;
                    self.record = false;
                    for _ in 0..ahead {
                        if !self.time_step(program, reached, deadline) {
                            return self.outcome(Stop::TimeLimit, self.step, u64::MAX);
                        }
                    }
                }
                let f = self.p.squared_distances(&self.s.pos);
                return self.outcome(
                    Stop::Cycle {
                        step: at,
                        period: lam,
                    },
                    cap,
                    f,
                );
            }
            if lam == power {
                saved.clone_from(&self.s);
                power *= 2;
                lam = 0;
            }
        }
    }

    fn outcome(&mut self, stop: Stop, steps: u64, fitness: u64) -> Outcome {
        Outcome {
            stop,
            steps,
            fitness,
            paths: std::mem::take(&mut self.paths),
        }
    }

    /// One time step: every robot runs the program once, in id order. Polls `deadline` every
    /// [`POLL_DECISIONS`] robot decisions (counted across steps); `false` when it has passed,
    /// with the step left half done (the run is then abandoned).
    fn time_step(&mut self, program: &Program, reached: &mut [u64], deadline: Deadline) -> bool {
        self.stamp += 1;
        let mark = !reached.is_empty();
        for i in 0..self.p.num_robots() {
            self.poll_in -= 1;
            if self.poll_in == 0 {
                self.poll_in = POLL_DECISIONS;
                if deadline.expired() {
                    return false;
                }
            }
            let a = program.decide_visiting(
                |c| self.test(c, i),
                |k| {
                    if mark {
                        reached[k / 64] |= 1 << (k % 64);
                    }
                },
            );
            self.act(a, i);
        }
        self.step += 1;
        if self.record {
            for (path, &v) in self.paths.iter_mut().zip(&self.s.pos) {
                path.push(v);
            }
        }
        true
    }

    // ---- robot state helpers ----

    /// Where robot `i`'s current path leads: the branch it set its path to, else its goal.
    #[inline]
    fn target(&self, i: usize) -> VertexId {
        self.tgt[i]
    }

    /// Sets robot `i`'s path to branch `b`, or back to its goal with `NONE`.
    #[inline]
    fn set_path(&mut self, i: usize, b: VertexId) {
        self.s.branch[i] = b;
        self.tgt[i] = if b != NONE { b } else { self.p.inst.goals[i] };
    }

    /// The next node on robot `i`'s current path (None when the path is empty).
    #[inline]
    fn next_on_path(&self, i: usize) -> Option<VertexId> {
        let (u, t) = (self.s.pos[i], self.target(i));
        (u != t).then(|| self.paths_of.next_hop(u, t))
    }

    /// Robot `j` is travelling to a branch node it has not reached yet.
    #[inline]
    fn moving_to_branch(&self, j: usize) -> bool {
        let b = self.s.branch[j];
        b != NONE && b != self.s.pos[j]
    }

    #[inline]
    fn free(&self, v: VertexId) -> bool {
        self.occ[v as usize] == NONE
            && (self.o.allow_following || self.vacated[v as usize] != self.stamp)
    }

    #[inline]
    fn bit(set: &[u64], words: usize, i: usize, v: VertexId) -> bool {
        set[i * words + v as usize / 64] >> (v % 64) & 1 == 1
    }

    #[inline]
    fn set_bit(set: &mut [u64], words: usize, i: usize, v: VertexId, on: bool) {
        let w = &mut set[i * words + v as usize / 64];
        if on {
            *w |= 1 << (v % 64);
        } else {
            *w &= !(1 << (v % 64));
        }
    }

    /// The first robot of c(r_i) (the robots within ρ hops of robot `i`, nearest first: BFS in
    /// adjacency order) for which `hit` holds.
    #[inline]
    fn find_in_network(
        &self,
        i: usize,
        mut hit: impl FnMut(VertexId, usize) -> bool,
    ) -> Option<usize> {
        let v = self.s.pos[i] as usize;
        // The ball starts with `v` itself, where robot `i` stands.
        let ball = &self.ball[self.ball_at[v] as usize + 1..self.ball_at[v + 1] as usize];
        ball.iter().find_map(|&w| {
            let r = self.occ[w as usize];
            (r != NONE && hit(w, r as usize)).then_some(r as usize)
        })
    }

    /// Robot `j`, standing on `w`, has node `x` (not `w`) on its current path.
    #[inline]
    fn on_path_at(&self, j: usize, w: VertexId, x: VertexId) -> bool {
        let t = self.target(j);
        t != w && self.paths_of.on_path(x, w, t)
    }

    /// The branch node nearest to robot `i` that it has not chosen before (ties: BFS order). When
    /// it has chosen them all, its list is cleared and the nearest one is taken.
    fn nearest_branch(&mut self, i: usize) -> Option<VertexId> {
        let (pos, w) = (self.s.pos[i], self.words);
        let mut order = self.p.branches_by_distance(pos, false);
        if order.len() == CACHED_BRANCHES {
            let tried = &self.s.tried;
            if order.iter().all(|&b| Self::bit(tried, w, i, b)) {
                // The cached prefix is used up: look further.
                order = self.p.branches_by_distance(pos, true);
            }
        }
        let tried = &self.s.tried;
        if let Some(&b) = order.iter().find(|&&b| !Self::bit(tried, w, i, b)) {
            return Some(b);
        }
        // Every branch node tried: forget them and start over with the nearest.
        let first = order.first().copied();
        self.s.tried[i * w..(i + 1) * w].fill(0);
        first
    }

    /// Robot `i` picks the nearest branch node it has not chosen before, records it as chosen
    /// and sets its path to it.
    fn choose_branch(&mut self, i: usize) -> Option<VertexId> {
        let b = self.nearest_branch(i)?;
        Self::set_bit(&mut self.s.tried, self.words, i, b, true);
        self.set_branch(i, b);
        Some(b)
    }

    /// Robot `i` sets its path to branch `b`.
    fn set_branch(&mut self, i: usize, b: VertexId) {
        match self.o.branch_arrival {
            BranchArrival::Hold => self.set_path(i, b),
            BranchArrival::Resume => {
                if self.s.pos[i] == b {
                    self.set_path(i, NONE);
                    self.s.at_branch[i] = b;
                } else {
                    self.set_path(i, b);
                    self.s.at_branch[i] = NONE;
                }
            }
        }
    }

    /// The collision-checked move of every action: robot `i` moves to the adjacent node `v`
    /// unless another robot holds it (or, without following, left it this step); then it stays.
    fn try_move(&mut self, i: usize, v: VertexId) -> bool {
        let u = self.s.pos[i];
        debug_assert!(self.p.graph.has_edge(u, v));
        if !self.free(v) {
            return false;
        }
        self.occ[u as usize] = NONE;
        self.vacated[u as usize] = self.stamp;
        self.occ[v as usize] = i as u32;
        self.s.pos[i] = v;
        Self::set_bit(&mut self.s.visited, self.words, i, v, true);
        if v == self.p.inst.goals[i] && !self.s.solved[i] {
            self.s.solved[i] = true;
            self.unsolved -= 1;
        }
        if self.o.branch_arrival == BranchArrival::Resume {
            self.s.at_branch[i] = NONE;
            if self.s.branch[i] == v {
                self.set_path(i, NONE);
                self.s.at_branch[i] = v;
            }
        }
        true
    }

    // ---- Table 1 ----

    fn test(&mut self, c: Conditional, i: usize) -> bool {
        match c {
            Conditional::TwoRobotsOnEachOthersPath => {
                let me = self.s.pos[i];
                let partner = self.find_in_network(i, |w, j| {
                    self.on_path_at(j, w, me) && self.on_path_at(i, me, w)
                });
                let Some(j) = partner else {
                    return false;
                };
                if let Some(b) = self.choose_branch(i) {
                    self.set_branch(j, b);
                }
                true
            }
            Conditional::NeighborIsSurrounded => {
                let g = &self.p.graph;
                g.neighbors(self.s.pos[i]).iter().any(|&v| {
                    self.occ[v as usize] != NONE
                        && g.neighbors(v).iter().all(|&w| self.occ[w as usize] != NONE)
                })
            }
            Conditional::RobotAtBranch => match self.o.branch_arrival {
                BranchArrival::Hold => {
                    let b = self.s.branch[i];
                    if b != NONE && b == self.s.pos[i] {
                        // Arrived: the path goes back to the objective.
                        self.set_path(i, NONE);
                        true
                    } else {
                        false
                    }
                }
                BranchArrival::Resume => {
                    let b = self.s.at_branch[i];
                    b != NONE && b == self.s.pos[i]
                }
            },
            Conditional::RobotAtDestination => self.s.pos[i] == self.p.inst.goals[i],
            Conditional::RobotMovingToBranch => self.moving_to_branch(i),
            Conditional::NeighborOnPathIsFree => self.next_on_path(i).is_some_and(|v| self.free(v)),
            Conditional::RobotIsSolved => self.s.solved[i],
            Conditional::OnPathOfRobotInNetwork => {
                let me = self.s.pos[i];
                self.find_in_network(i, |w, j| self.on_path_at(j, w, me))
                    .is_some()
            }
            Conditional::RobotInNetworkMovingToBranch => self
                .find_in_network(i, |_, j| self.moving_to_branch(j))
                .is_some(),
        }
    }

    // ---- Table 2 ----

    fn act(&mut self, a: Action, i: usize) {
        match a {
            Action::MoveTowardBranch => {
                if self.s.branch[i] == NONE {
                    self.choose_branch(i);
                }
                let b = self.s.branch[i];
                if b != NONE && b != self.s.pos[i] {
                    let v = self.paths_of.next_hop(self.s.pos[i], b);
                    self.try_move(i, v);
                }
            }
            Action::MoveToFreeNeighbor => {
                let u = self.s.pos[i];
                let words = self.words;
                let p = self.p;
                let nbrs = p.graph.neighbors(u);
                if nbrs
                    .iter()
                    .all(|&v| Self::bit(&self.s.visited, words, i, v))
                {
                    // Every neighbour visited: forget them (the authors' reset).
                    for &v in nbrs {
                        Self::set_bit(&mut self.s.visited, words, i, v, false);
                    }
                }
                let ahead = self.next_on_path(i);
                let free = |v: &VertexId| self.free(*v);
                let seen = |v: &VertexId| Self::bit(&self.s.visited, words, i, *v);
                let mut unvisited = nbrs.iter().copied().filter(free).filter(|v| !seen(v));
                let pick = match self.o.free_neighbor {
                    FreeNeighbor::Unvisited => {
                        let first = unvisited.clone().find(|&v| Some(v) != ahead);
                        first.or_else(|| unvisited.next())
                    }
                    FreeNeighbor::OffPathThenVisited => unvisited
                        .find(|&v| Some(v) != ahead)
                        .or_else(|| nbrs.iter().copied().filter(free).find(seen)),
                };
                if let Some(v) = pick {
                    self.try_move(i, v);
                }
            }
            Action::MoveTowardObjective => {
                if let Some(v) = self.next_on_path(i) {
                    self.try_move(i, v);
                }
            }
            Action::Stay => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::validate_tree_plan;

    /// The T-tree reference instance: A(0)–B(1)–C(2), C–D(3), C–E(4); r0: A→B, r1: B→A.
    fn t_tree() -> Problem {
        let g = Graph::from_edges(5, &[(0, 1), (1, 2), (2, 3), (2, 4)]);
        let inst = Instance::new(vec![0, 1], vec![1, 0]).unwrap();
        Problem::new(&g, &inst).unwrap()
    }

    #[test]
    fn hop_table_answers_like_the_rooted_tree() {
        use crate::generator::{ProblemSpec, RobotCount, generate_problem};
        let mut spec = ProblemSpec::paper(7, RobotCount::Exactly(3));
        spec.branching = 5;
        let t = generate_problem(&spec, 1).unwrap();
        let p = Problem::from_tree_instance(&t);
        let n = p.graph().num_vertices() as VertexId;
        assert!(n > 64, "{n} nodes");
        let h = p.hops.as_ref().expect("a table for a small tree");
        for u in 0..n {
            for v in 0..n {
                assert_eq!(h.next_hop(u, v), p.tree.next_hop(u, v), "{u}->{v}");
                if u != v {
                    for x in 0..n {
                        assert_eq!(
                            h.on_path(x, u, v),
                            p.tree.on_path(x, u, v),
                            "{x} on {u}-{v}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn move_toward_objective_solves_a_free_instance() {
        // A path 0-1-2-3 with a spur 1-4; robots that never meet.
        let g = Graph::from_edges(5, &[(0, 1), (1, 2), (2, 3), (1, 4)]);
        let inst = Instance::new(vec![0, 4], vec![3, 1]).unwrap();
        let p = Problem::new(&g, &inst).unwrap();
        let prog = Program::action(Action::MoveTowardObjective);
        let (plan, out) =
            plan_program(&prog, &p, &SimOptions::default(), Deadline::none()).unwrap();
        assert_eq!(out.steps, 3);
        assert_eq!(out.fitness, 0);
        let m = validate_tree_plan(&g, &inst, &plan, true).unwrap();
        assert_eq!(m.makespan, 3);
    }

    #[test]
    fn head_on_robots_cycle_and_get_equation_one_fitness() {
        let p = t_tree();
        let prog = Program::action(Action::MoveTowardObjective);
        // Robots 0 (at A, goal B) and 1 (at B, goal A) block each other for ever: each stays 1
        // edge from its goal, so f = 1² + 1² = 2.
        let out = run_program(
            &prog,
            &p,
            &SimOptions::default(),
            1000,
            false,
            Deadline::none(),
        );
        assert!(matches!(out.stop, Stop::Cycle { .. }));
        assert_eq!(out.fitness, 2);
        assert_eq!(out.steps, 1000);
        let no_cycle = SimOptions {
            detect_cycles: false,
            ..SimOptions::default()
        };
        let out2 = run_program(&prog, &p, &no_cycle, 1000, false, Deadline::none());
        assert_eq!(out2.stop, Stop::StepCap);
        assert_eq!(out2.fitness, 2);
        assert!(plan_program(&prog, &p, &SimOptions::default(), Deadline::none()).is_err());
    }

    /// Issue 27 A: a run given a deadline that has already passed stops before its first step
    /// and says so; it never reports a fitness or a plan (before, the deadline was polled every
    /// 256 steps only, so this run solved, and a step of many robots was never interrupted).
    #[test]
    fn a_run_with_an_expired_deadline_stops_and_reports_it() {
        let expired = Deadline::after(std::time::Duration::ZERO);
        assert!(expired.expired());
        // A path 0-1-2-3 with a spur 1-4 that one step-toward-goal program solves in 3 steps.
        let g = Graph::from_edges(5, &[(0, 1), (1, 2), (2, 3), (1, 4)]);
        let inst = Instance::new(vec![0, 4], vec![3, 1]).unwrap();
        let p = Problem::new(&g, &inst).unwrap();
        let prog = Program::action(Action::MoveTowardObjective);
        let opts = SimOptions::default();
        for record in [false, true] {
            let out = run_program(&prog, &p, &opts, 1000, record, expired);
            assert_eq!(out.stop, Stop::TimeLimit);
            assert!(!out.solved());
            assert_eq!(out.fitness, u64::MAX, "an interrupted run has no fitness");
        }
        let mut reached = vec![0u64; 1];
        let out = run_program_marking(&prog, &p, &opts, 1000, expired, &mut reached);
        assert_eq!(out.stop, Stop::TimeLimit);
        assert_eq!(
            plan_program(&prog, &p, &opts, expired).unwrap_err(),
            Unsolved::TimeLimit
        );
        // Without a deadline the same run solves.
        assert!(run_program(&prog, &p, &opts, 1000, false, Deadline::none()).solved());
    }

    /// The deadline is polled inside a time step, not only between steps: a step of many robots
    /// stops part way.
    #[test]
    fn one_time_step_of_many_robots_is_interrupted() {
        // A path of 1200 nodes, 600 robots on its first half, goals on the second.
        let n = 1200u32;
        let edges: Vec<(u32, u32)> = (0..n - 1).map(|v| (v, v + 1)).collect();
        let g = Graph::from_edges(n as usize, &edges);
        let r = 600u32;
        let inst = Instance::new((0..r).collect(), (0..r).map(|i| n - 1 - i).collect()).unwrap();
        let p = Problem::new(&g, &inst).unwrap();
        assert!(r as usize > POLL_DECISIONS as usize);
        let prog = Program::action(Action::MoveTowardObjective);
        let opts = SimOptions::default();
        let expired = Deadline::after(std::time::Duration::ZERO);
        let mut sim = Sim::new(&p, &p.tree, &opts, false);
        assert!(!sim.time_step(&prog, &mut [], expired));
        assert_eq!(sim.step, 0, "the step was left unfinished");
        let mut sim = Sim::new(&p, &p.tree, &opts, false);
        assert!(sim.time_step(&prog, &mut [], Deadline::none()));
        assert_eq!(sim.step, 1);
    }

    #[test]
    fn swap_at_a_branch_solves_the_t_tree() {
        let p = t_tree();
        // Robots on each other's path go to the branch C; the one at the branch steps aside
        // (to a free neighbour it has not visited), the other passes.
        let prog: Program = "(if-robot-at-branch move-to-free-neighbor \
            (if-two-robots-on-each-others-path move-toward-branch \
            (if-robot-moving-to-branch move-toward-branch move-toward-objective)))"
            .parse()
            .unwrap();
        for arrival in [BranchArrival::Hold, BranchArrival::Resume] {
            let opts = SimOptions {
                branch_arrival: arrival,
                ..SimOptions::default()
            };
            let res = plan_program(&prog, &p, &opts, Deadline::none());
            let (plan, out) = res.unwrap_or_else(|e| panic!("{arrival:?}: {e}"));
            validate_tree_plan(p.graph(), p.instance(), &plan, true).unwrap();
            // The optimum with following is 5 (by exhaustive search). Traced by hand (both modes): r1
            // reaches C at step 1 and steps aside to D at step 2 while r0 visits its goal B; r0
            // moves on to C (3) and aside to E (4) so that r1 passes C (4), B (5), A (6).
            assert_eq!(out.steps, 6, "{arrival:?}");
        }
    }
}
