//! H*: hybrid greedy planner of Kopacz, García González, Chira and Villar (IEEE Latin America
//! Transactions, "Hybrid Adaptive Greedy Algorithm Addressing the Multi-Robot Path Planning
//! Problem") §IV.
//!
//! The paper's steps, in order, each a function named after it:
//! 1. [`greedy_path_search`] (§IV-A, Algorithm 1 applied to all robots step by step): at every time
//!    step each robot not on its goal tries each free neighbour `n_k`, completes `[c_r, n_k]` to its
//!    target with A* on the corridor-compressed graph ([`Corridors`]) avoiding every node another
//!    robot currently occupies and its own cell, and moves to the `n_k` of the shortest route.
//! 2. [`loop_elimination`] (Algorithm 2): repeated cells cut out of each path.
//! 3. [`collision_elimination`] (Algorithms 3–4): while a conflict exists, the first one is resolved
//!    by inserting `i = 1, 2, ...` halts at position `t - i` of the first robot, else of the second.
//!
//! Where the paper is silent, the choices (all options of [`HStar`]):
//! - Neighbour order and ties: neighbours are tried up, right, down, left and the first strictly
//!   shortest wins (Algorithm 1's `shorter than`), so H* is deterministic as the paper's integer
//!   Table II values suggest; [`TieBreak::Random`] picks uniformly among the shortest (seeded).
//! - Update order: [`GreedyUpdate::Sequential`] (default) moves robots one after the other in id
//!   order, each seeing the positions the earlier robots just took; `Simultaneous` lets all robots
//!   decide on the positions at `t` (the paths may then hold conflicts for step 3 to resolve).
//! - A robot on its goal stays there; a robot with no usable neighbour (every route blocked) waits.
//! - The greedy stage stops when every robot is on its goal, when a joint configuration repeats
//!   (the stage is deterministic, so it would cycle for ever), or after `max_greedy_steps`.
//! - Algorithm 4 may find no number of halts that clears a conflict; Algorithm 3 would then loop
//!   for ever. We stop at the first such conflict, after `max_resolution_rounds` resolutions
//!   (default 100 + 10 per robot), or once halts have stretched the longest path past
//!   `max_stretch` times its length before this step (default 3): each resolution may add halts
//!   that cause new conflicts, and without these caps we saw makespans above 10 000 on a 63x31 map.
//!
//! [`Variant::Paper`] runs only those steps and reports "not solved" when a robot is short of its
//! goal or a conflict is left. The authors' public code ends that way on most of the paper's own
//! instances, while the paper reports collision-free plans for all of them. [`Variant::Repaired`]
//! (default) finishes the job with [`reservation_repair`], our documented extension: the robots
//! left short of their goals or in conflict are re-planned with space-time A* against a reservation
//! table holding every other robot's H* path. A robot that finds no path is planned first in the
//! next round, together with the robots in its way, which lose their H* paths too: those parked on
//! its shortest route, else those whose paths cross that route, else everyone (prioritised
//! planning with restarts, a bounded number of rounds). It then runs [`local_replanning`], a
//! stronger form of the paper's local search: single robots, then pairs of robots that cross, are
//! re-planned against all the others and keep their new paths only when the sum of costs drops
//! (`replanning_passes`, default 4; 0 turns it off).
//!
//! When the repair gives up (its prioritised planning is incomplete), [`HStar::complete`] (default
//! on, `-p complete=false` turns it off) finishes the job with [`crate::lacam`]: the paper's paths
//! are kept up to the step before their first conflict (or their end), and LaCAM plans from that
//! configuration to the goals. LaCAM is complete, so the repaired variant returns a valid plan on
//! every solvable instance, given time. The plan's notes say which stage finished it
//! (`finished_by`: `paper`, `repair` or `lacam`).

use rand::SeedableRng;
use rand::seq::IndexedRandom;
use rand_chacha::ChaCha8Rng;
use rustc_hash::FxHashSet;

use crate::corridors::{Corridors, NodeId, RegionScratch, RouteScratch};
use mrpp_core::contract::{Ctx, Deadline, Planner, Unsolved};
use mrpp_core::mapf::graph::{Graph, VertexId};
use mrpp_core::mapf::instance::Instance;
use mrpp_core::mapf::plan::{
    Plan, first_conflict, first_conflict_from, pair_conflicts_from, position,
};
use mrpp_core::mapf::search::distance::{GoalDistances, UNREACHABLE};
use mrpp_core::mapf::search::sipp;
use mrpp_core::mapf::search::spacetime::{Query, Reservations, Search, space_time_astar};
use mrpp_core::{MapfProblem, Param, PlannerEntry};

/// Registry name of H*.
pub const NAME: &str = "hstar";

/// H* in the planner registry.
pub const ENTRY: PlannerEntry<MapfProblem> = PlannerEntry {
    name: NAME,
    about: "H*: greedy path search, loop elimination, collision resolution, then mrpp's repair (Kopacz et al., IEEE Latin America Transactions)",
    params: &[
        Param {
            name: "variant",
            default: "repaired",
            doc: "repaired = the paper's steps, then reservation repair and local re-planning; paper = the paper's steps only",
        },
        Param {
            name: "replanning_passes",
            default: "4",
            doc: "passes of local re-planning after the repair (repaired variant; 0 = off)",
        },
        Param {
            name: "complete",
            default: "true",
            doc: "when the repair gives up, finish from the paper's conflict-free prefix with LaCAM (repaired variant)",
        },
        Param {
            name: "tie_break",
            default: "first",
            doc: "Algorithm 1's choice among equally short routes: first = the first neighbour in the order up, right, down, left; random = a seeded uniform one (the paper does not say)",
        },
        Param {
            name: "update",
            default: "sequential",
            doc: "how the greedy stage moves robots within one time step: sequential = one after another, each seeing the moves before it; simultaneous = all against the positions at the step's start (the paper does not say)",
        },
        Param {
            name: "target_occupancy",
            default: "when-parked",
            doc: "when a robot on another's target node blocks it: when-parked = only once it has arrived on its own goal; always = whenever any robot stands there (the paper read literally; it freezes Scenario 2, where every target is another robot's start)",
        },
    ],
    build: |p| {
        let variant =
            [Variant::Repaired, Variant::Paper][p.choice("variant", &["repaired", "paper"])?];
        Ok(Box::new(HStar {
            variant,
            replanning_passes: p.get_in("replanning_passes", 0..=1000)?,
            complete: [true, false][p.choice("complete", &["true", "false"])?],
            tie_break: [TieBreak::First, TieBreak::Random]
                [p.choice("tie_break", &["first", "random"])?],
            update: [GreedyUpdate::Sequential, GreedyUpdate::Simultaneous]
                [p.choice("update", &["sequential", "simultaneous"])?],
            target_occupancy: [TargetOccupancy::BlocksWhenParked, TargetOccupancy::Blocks]
                [p.choice("target_occupancy", &["when-parked", "always"])?],
            ..HStar::default()
        }))
    },
};

/// Which steps run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Variant {
    /// Only the paper's steps; "not solved" when they fall short.
    Paper,
    /// The paper's steps, then [`reservation_repair`] for whatever they leave unresolved.
    Repaired,
}

/// How the greedy stage moves robots within one time step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GreedyUpdate {
    Sequential,
    Simultaneous,
}

/// How Algorithm 1 breaks ties between equally short routes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TieBreak {
    /// The first neighbour in the order up, right, down, left.
    First,
    /// A uniformly random one among the shortest (seeded by the run's seed).
    Random,
}

/// When another robot on a robot's *target* node blocks its route.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TargetOccupancy {
    /// Whenever any robot stands there (the paper's rule read literally). When every target is
    /// another robot's start, as in Scenario 2, no robot can move at all.
    Blocks,
    /// Only when the robot there has arrived on its own goal (it will not leave); a robot merely
    /// passing or starting there is expected to move on.
    BlocksWhenParked,
}

/// The H* planner and its options.
#[derive(Debug, Clone)]
pub struct HStar {
    pub variant: Variant,
    pub target_occupancy: TargetOccupancy,
    pub update: GreedyUpdate,
    pub tie_break: TieBreak,
    /// Cap on greedy time steps; `None` = 4·|V| + 100.
    pub max_greedy_steps: Option<usize>,
    /// Cap on the number of conflicts Algorithm 3 resolves; `None` = 100 + 10 per robot.
    pub max_resolution_rounds: Option<usize>,
    /// Algorithm 3 stops once the longest path exceeds this factor times its initial length.
    pub max_stretch: usize,
    /// Passes of [`local_replanning`] after the repair (repaired variant; 0 = off).
    pub replanning_passes: usize,
    /// Restarts of the repair step (each puts a failing robot first).
    pub max_repair_rounds: usize,
    /// When the repair gives up, finish with LaCAM (repaired variant; module doc).
    pub complete: bool,
    /// Which stage finished the last plan.
    finished_by: std::sync::Arc<std::sync::Mutex<Option<&'static str>>>,
}

impl Default for HStar {
    fn default() -> Self {
        HStar {
            variant: Variant::Repaired,
            target_occupancy: TargetOccupancy::BlocksWhenParked,
            update: GreedyUpdate::Sequential,
            tie_break: TieBreak::First,
            max_greedy_steps: None,
            max_resolution_rounds: None,
            max_stretch: 3,
            max_repair_rounds: 16,
            replanning_passes: 4,
            complete: true,
            finished_by: Default::default(),
        }
    }
}

impl HStar {
    pub fn paper() -> Self {
        HStar {
            variant: Variant::Paper,
            ..Self::default()
        }
    }
}

/// How the greedy stage ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GreedyEnd {
    AllOnGoal,
    /// A joint configuration repeated: the deterministic stage would cycle.
    Cycle,
    StepCap,
}

/// Step 1: Algorithm 1 applied to all robots, step by step. Returns one path per robot (possibly
/// short of its goal) and how the stage ended.
pub fn greedy_path_search(
    g: &Graph,
    corridors: &Corridors,
    dist: &GoalDistances,
    inst: &Instance,
    cfg: &HStar,
    rng: &mut ChaCha8Rng,
    deadline: Deadline,
) -> Result<(Vec<Vec<VertexId>>, GreedyEnd), Unsolved> {
    let n = inst.num_agents();
    let mut pos = inst.starts.clone();
    let mut paths: Vec<Vec<VertexId>> = pos.iter().map(|&s| vec![s]).collect();
    // How many robots stand on each compressed node.
    let mut occupancy = vec![0u32; corridors.num_nodes()];
    for &p in &pos {
        occupancy[corridors.node_of(p) as usize] += 1;
    }
    // Robots standing on their own goal, per node (they never move again in this stage).
    let mut parked = vec![0u32; corridors.num_nodes()];
    for (p, g) in pos.iter().zip(&inst.goals) {
        if p == g {
            parked[corridors.node_of(*p) as usize] += 1;
        }
    }
    let cap = cfg.max_greedy_steps.unwrap_or(4 * g.num_vertices() + 100);
    let mut seen: FxHashSet<Vec<VertexId>> = FxHashSet::default();
    seen.insert(pos.clone());
    let mut choices: Vec<VertexId> = Vec::with_capacity(4);
    // Per robot and step: (lower bound, neighbour index, neighbour), and the shortest found.
    let mut candidates: Vec<(u32, usize, VertexId)> = Vec::with_capacity(4);
    let mut ties: Vec<(usize, VertexId)> = Vec::with_capacity(4);
    let mut scratch = RouteScratch::default();
    let mut region = RegionScratch::default();
    let mut sources: Vec<VertexId> = Vec::with_capacity(4);
    // Per robot, the proof that it had no route at its last decision (see `Sealed`).
    let mut sealed: Vec<Option<Sealed>> = vec![None; n];
    // Calls of `route_length` in this decision that found no route without a limit.
    let mut failed_calls: Vec<u32> = Vec::with_capacity(4);
    for _step in 0..cap {
        if pos.iter().zip(&inst.goals).all(|(p, g)| p == g) {
            return Ok((paths, GreedyEnd::AllOnGoal));
        }
        if deadline.expired() {
            return Err(Unsolved::TimeLimit);
        }
        let decided_on = occupancy.clone();
        let mut next = pos.clone();
        for r in 0..n {
            let cur = pos[r];
            let goal = inst.goals[r];
            if cur == goal {
                continue;
            }
            // One robot's routes can search much of a large map: the limit is checked per robot.
            if deadline.expired() {
                return Err(Unsolved::TimeLimit);
            }
            let occ: &[u32] = match cfg.update {
                GreedyUpdate::Sequential => &occupancy,
                GreedyUpdate::Simultaneous => &decided_on,
            };
            let own = corridors.node_of(cur);
            // A node is occupied by others if someone other than r stands on it.
            let target = corridors.node_of(goal);
            let occupied = |node: NodeId| occ[node as usize] > u32::from(node == own);
            let blocked = |node: NodeId| match cfg.target_occupancy {
                TargetOccupancy::BlocksWhenParked if node == target => parked[node as usize] > 0,
                _ => occupied(node),
            };
            // Algorithm 1 takes the first strictly shortest route in neighbour order (or, with
            // random ties, any of the shortest). The neighbours are searched cheapest lower bound
            // first (the goal distance of `n_k`), so that once a route of the least possible
            // length is found the others cost no search; ties are then put back in neighbour
            // order, which leaves the choice (and the random stream) as in neighbour order.
            if sealed[r]
                .as_ref()
                .is_some_and(|s| s.holds(cur, &blocked, &occupied))
            {
                continue; // no route from any neighbour, as at the last decision: r waits
            }
            let h = heuristic(dist, r);
            candidates.clear();
            let mut taken: Vec<NodeId> = Vec::new();
            for (k, &nk) in g.neighbors(cur).iter().enumerate() {
                let lower = h(nk);
                if occupied(corridors.node_of(nk)) {
                    taken.push(corridors.node_of(nk));
                } else if lower != u32::MAX {
                    candidates.push((lower, k, nk));
                }
            }
            // A robot that found no route at its last decision (its proof no longer holds) most
            // likely finds none again: prove that first, for all neighbours at once, with a
            // breadth-first search from both ends, which costs little when either side is walled
            // in, whereas every search of `route_length` would explore the robot's whole side.
            if sealed[r].is_some() {
                sources.clear();
                sources.extend(candidates.iter().map(|c| c.2));
                if let Some(mut walls) =
                    corridors.cut_off(g, &sources, goal, cur, blocked, &mut region)
                {
                    walls.sort_unstable();
                    walls.dedup();
                    sealed[r] = Some(Sealed {
                        at: cur,
                        walls,
                        taken,
                    });
                    continue; // no route from any neighbour: r waits
                }
            }
            candidates.sort_unstable();
            let mut best = u32::MAX;
            ties.clear();
            scratch.walls.clear();
            failed_calls.clear();
            for &(lower, k, nk) in &candidates {
                if best != u32::MAX && 1 + lower > best {
                    break; // sorted by lower bound: no later neighbour can tie either
                }
                // With the first of the shortest taken, a neighbour that can at best tie is
                // searched only if it comes before every tie found so far.
                if cfg.tie_break == TieBreak::First
                    && 1 + lower == best
                    && ties.iter().all(|&(kt, _)| kt < k)
                {
                    continue;
                }
                // A neighbour inside the region a search without a limit exhausted in vain
                // has no route either (it would give that search one through it).
                if failed_calls.iter().any(|&c| scratch.reached_in(nk, c)) {
                    continue;
                }
                let limit = best.saturating_sub(1);
                let call = scratch.last_call();
                let Some(rest) =
                    corridors.route_length(g, nk, goal, cur, blocked, h, limit, &mut scratch)
                else {
                    if best == u32::MAX && scratch.last_call() != call {
                        failed_calls.push(scratch.last_call());
                    }
                    continue;
                };
                let len = 1 + rest;
                if len < best {
                    best = len;
                    ties.clear();
                }
                if len == best {
                    ties.push((k, nk));
                }
            }
            sealed[r] = (best == u32::MAX).then(|| {
                let mut walls = std::mem::take(&mut scratch.walls);
                walls.sort_unstable();
                walls.dedup();
                Sealed {
                    at: cur,
                    walls,
                    taken,
                }
            });
            ties.sort_unstable();
            choices.clear();
            match cfg.tie_break {
                TieBreak::First => choices.extend(ties.first().map(|&(_, nk)| nk)),
                TieBreak::Random => choices.extend(ties.iter().map(|&(_, nk)| nk)),
            }
            let chosen = match cfg.tie_break {
                TieBreak::First => choices.first().copied(),
                TieBreak::Random => choices.choose(rng).copied(),
            };
            if let Some(nk) = chosen {
                next[r] = nk;
                if cfg.update == GreedyUpdate::Sequential {
                    occupancy[own as usize] -= 1;
                    occupancy[corridors.node_of(nk) as usize] += 1;
                    pos[r] = nk;
                }
            }
        }
        if cfg.update == GreedyUpdate::Simultaneous {
            for r in 0..n {
                occupancy[corridors.node_of(pos[r]) as usize] -= 1;
                occupancy[corridors.node_of(next[r]) as usize] += 1;
            }
        }
        pos = next;
        for (r, (p, g)) in pos.iter().zip(&inst.goals).enumerate() {
            if p == g && paths[r].last() != Some(g) {
                parked[corridors.node_of(*p) as usize] += 1;
            }
        }
        for (p, &v) in paths.iter_mut().zip(&pos) {
            p.push(v);
        }
        if !seen.insert(pos.clone()) {
            return Ok((paths, GreedyEnd::Cycle));
        }
    }
    let end = if pos.iter().zip(&inst.goals).all(|(p, g)| p == g) {
        GreedyEnd::AllOnGoal
    } else {
        GreedyEnd::StepCap
    };
    Ok((paths, end))
}

/// Why a robot of the greedy stage had no route at its last decision: every search from its free
/// neighbours (avoiding its own cell `at`) ran out of cells, walled in by the blocked nodes
/// `walls` (or found the goal's node among them), and the neighbours in the `taken` nodes were
/// occupied. While the robot stays on `at` and all of these stay blocked and occupied, the
/// region its searches could enter can only shrink, so it still has no route: its searches are
/// skipped and it waits, as they would have made it do.
#[derive(Debug, Clone)]
struct Sealed {
    at: VertexId,
    walls: Vec<NodeId>,
    taken: Vec<NodeId>,
}

impl Sealed {
    fn holds(
        &self,
        at: VertexId,
        blocked: &dyn Fn(NodeId) -> bool,
        occupied: &dyn Fn(NodeId) -> bool,
    ) -> bool {
        self.at == at
            && self.walls.iter().all(|&n| blocked(n))
            && self.taken.iter().all(|&n| occupied(n))
    }
}

/// Step 2, Algorithm 2: from the end of the path backwards, whenever a cell appeared earlier, the
/// positions between its first and this occurrence are removed (waits count as loops too).
pub fn loop_elimination(path: &mut Vec<VertexId>) {
    let mut i = path.len();
    while i > 1 {
        i -= 1;
        if let Some(j) = path[..i].iter().position(|&v| v == path[i]) {
            path.drain(j + 1..=i);
            i = j + 1;
        }
    }
}

/// Inserts `count` halts at position `at` (the robot stays on `path[at]` `count` more steps).
fn insert_halts(path: &[VertexId], at: usize, count: usize) -> Vec<VertexId> {
    let at = at.min(path.len() - 1);
    let mut out = Vec::with_capacity(path.len() + count);
    out.extend_from_slice(&path[..=at]);
    out.extend(std::iter::repeat_n(path[at], count));
    out.extend_from_slice(&path[at + 1..]);
    out
}

/// Algorithm 4: resolve the collision of robots `a` and `b` at step `t` (their first conflict, as
/// [`first_conflict`] finds it) by inserting `i` halts at position `t - i` in `a`'s path, or
/// failing that in `b`'s, for `i = 1..=t`. Returns the number of halts, or `None` when no `i`
/// works. The paths agree with the old ones up to step `t - i`, so only later steps can conflict.
pub fn resolve_collision(
    paths: &mut [Vec<VertexId>],
    a: usize,
    b: usize,
    t: usize,
) -> Option<usize> {
    for i in 1..=t {
        let new_a = insert_halts(&paths[a], t - i, i);
        if !pair_conflicts_from(&new_a, &paths[b], t - i + 1) {
            paths[a] = new_a;
            return Some(i);
        }
        let new_b = insert_halts(&paths[b], t - i, i);
        if !pair_conflicts_from(&paths[a], &new_b, t - i + 1) {
            paths[b] = new_b;
            return Some(i);
        }
    }
    None
}

/// How collision elimination ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ResolutionEnd {
    NoConflict,
    /// Algorithm 4 found no halts that clear the first conflict.
    Stuck,
    RoundCap,
}

/// Step 3, Algorithm 3: resolve the first conflict with Algorithm 4 until none is left.
pub fn collision_elimination(
    paths: &mut [Vec<VertexId>],
    num_vertices: usize,
    max_rounds: usize,
    max_stretch: usize,
    deadline: Deadline,
) -> Result<ResolutionEnd, Unsolved> {
    let longest = |paths: &[Vec<VertexId>]| paths.iter().map(Vec::len).max().unwrap_or(0);
    let limit = longest(paths).saturating_mul(max_stretch.max(1));
    // No conflict before step `from`: a resolution with `i` halts leaves every path as it was up
    // to step `t - i`, and there was none before `t`.
    let mut from = 0;
    for _ in 0..max_rounds {
        if longest(paths) > limit {
            break;
        }
        let Some(c) = first_conflict_from(paths, num_vertices, true, from) else {
            return Ok(ResolutionEnd::NoConflict);
        };
        if deadline.expired() {
            return Err(Unsolved::TimeLimit);
        }
        match resolve_collision(paths, c.a, c.b, c.t) {
            Some(halts) => from = c.t - halts + 1,
            None => return Ok(ResolutionEnd::Stuck),
        }
    }
    Ok(if first_conflict(paths, num_vertices, true).is_none() {
        ResolutionEnd::NoConflict
    } else {
        ResolutionEnd::RoundCap
    })
}

/// The robots' single-robot searches, from their starts at time 0 against a reservation table,
/// guided by their goal distances.
struct Robots<'a> {
    g: &'a Graph,
    inst: &'a Instance,
    dist: &'a GoalDistances<'a>,
    deadline: Deadline,
}

impl Robots<'_> {
    /// Space-time A* for robot `i` against `res`, arriving by `max_time`.
    ///
    /// SIPP ([`Robots::arrival`]) answers first: it finds the same earliest arrival as
    /// space-time A* in far fewer states, so a robot that cannot arrive by `max_time` (most
    /// queries of [`local_replanning`]) costs one SIPP search. When it can, space-time A* runs
    /// with `max_time` set to that arrival ([`Robots::path`]).
    fn plan(&self, i: usize, res: &Reservations, max_time: u32) -> Search {
        match self.arrival(i, res, max_time) {
            Ok(arrival) => self.path(i, res, arrival),
            Err(other) => other,
        }
    }

    /// Robot `i`'s space-time A* path against `res`, bounded by its earliest `arrival` there:
    /// the states the bound skips could never be expanded before the goal, so the path is the
    /// one the unbounded search returns (plans do not depend on SIPP's tie-breaking).
    fn path(&self, i: usize, res: &Reservations, arrival: u32) -> Search {
        let h = heuristic(self.dist, i);
        space_time_astar(&self.query(i, &h, arrival), res)
    }

    /// The earliest time robot `i` can arrive for good against `res`, if it is at most
    /// `max_time` ([`sipp::earliest_arrival`]). `Err` holds SIPP's failure.
    fn arrival(&self, i: usize, res: &Reservations, max_time: u32) -> Result<u32, Search> {
        // No arrival before the distance to go or while the goal is still reserved: a query
        // whose bound is below that needs no search.
        let Some(goal_free) = res.free_for_good_from(self.inst.goals[i]) else {
            return Err(Search::NotFound);
        };
        if self.dist.get(i, self.inst.starts[i]).max(goal_free) > max_time {
            return Err(Search::NotFound);
        }
        let h = heuristic(self.dist, i);
        sipp::earliest_arrival(&self.query(i, &h, max_time), res)
    }

    /// The space-time query of robot `i` from its start at time 0, arriving by `max_time`.
    fn query<'q, H: Fn(VertexId) -> u32>(
        &'q self,
        i: usize,
        h: &'q H,
        max_time: u32,
    ) -> Query<'q, H> {
        Query {
            graph: self.g,
            start: self.inst.starts[i],
            goal: self.inst.goals[i],
            start_time: 0,
            h,
            max_time,
            window: None,
            deadline: self.deadline,
        }
    }
}

/// Robot `i`'s goal distances as a search heuristic, read straight from its table when that is
/// complete in 2-byte form (the searches ask for millions of them).
fn heuristic<'d>(dist: &'d GoalDistances, i: usize) -> impl Fn(VertexId) -> u32 + Copy + 'd {
    let table = dist.narrow(i);
    #[inline(always)]
    move |v| match table {
        Some(t) => match t[v as usize] {
            u16::MAX => UNREACHABLE,
            x => u32::from(x),
        },
        None => dist.get(i, v),
    }
}

/// Every robot's goal distances, grown to its start before `deadline` (lazy tables: memory per
/// robot follows what its searches touch, 2 bits per vertex on huge instances).
fn distances<'g>(
    g: &'g Graph,
    inst: &Instance,
    deadline: Deadline,
) -> Result<GoalDistances<'g>, Unsolved> {
    let mut dist = GoalDistances::new(g, &inst.goals);
    if !dist.warm_up(&inst.starts, deadline) {
        return Err(Unsolved::TimeLimit);
    }
    Ok(dist)
}

/// Our extension (module doc): re-plan the robots that are short of their goals or in conflict
/// with space-time A* against the other robots' paths; restart with a failing robot first.
pub fn reservation_repair(
    g: &Graph,
    inst: &Instance,
    dist: &GoalDistances,
    paths: &[Vec<VertexId>],
    max_rounds: usize,
    deadline: Deadline,
) -> Result<Vec<Vec<VertexId>>, Unsolved> {
    let n = inst.num_agents();
    let nv = g.num_vertices();
    let robots = Robots {
        g,
        inst,
        dist,
        deadline,
    };
    for i in 0..n {
        if dist.get(i, inst.starts[i]) == UNREACHABLE {
            return Err(Unsolved::GaveUp(format!(
                "agent {i} cannot reach its goal on this map"
            )));
        }
    }
    // Robots to re-plan: short of goal, then one robot of each remaining conflict.
    let mut replan: Vec<bool> = (0..n)
        .map(|i| paths[i].last() != Some(&inst.goals[i]))
        .collect();
    loop {
        let kept: Vec<usize> = (0..n).filter(|&i| !replan[i]).collect();
        let kept_paths: Vec<Vec<VertexId>> = kept.iter().map(|&i| paths[i].clone()).collect();
        match first_conflict(&kept_paths, nv, true) {
            None => break,
            Some(c) => replan[kept[c.b]] = true,
        }
    }
    // Longest remaining distance first among the re-planned robots.
    let mut order: Vec<usize> = (0..n).filter(|&i| replan[i]).collect();
    order.sort_by_key(|&i| (std::cmp::Reverse(dist.get(i, inst.starts[i])), i));
    let mut fixed: Vec<bool> = replan.iter().map(|r| !r).collect();
    for _round in 0..max_rounds.max(1) {
        let mut res = Reservations::new(nv);
        let mut out = paths.to_vec();
        for i in (0..n).filter(|&i| fixed[i]) {
            res.reserve_path(&paths[i], 0, true);
        }
        let mut failed = None;
        for &i in &order {
            let max_time = res.horizon() + nv as u32 + 1;
            match robots.plan(i, &res, max_time) {
                Search::Found(p) => {
                    res.reserve_path(&p, 0, true);
                    out[i] = p;
                }
                Search::TimedOut => return Err(Unsolved::TimeLimit),
                Search::NotFound => {
                    failed = Some(i);
                    break;
                }
            }
        }
        match failed {
            None => return Ok(out),
            Some(i) => {
                // Free the robots in i's way and plan i before them: first those parked on a
                // shortest route of i, else those whose paths cross it, else everyone.
                let route: FxHashSet<VertexId> =
                    dist.descend(i, inst.starts[i]).into_iter().collect();
                let candidates: Vec<usize> = (0..n).filter(|&j| fixed[j]).collect();
                let mut freed: Vec<usize> = candidates
                    .iter()
                    .copied()
                    .filter(|&j| route.contains(&inst.goals[j]))
                    .collect();
                if freed.is_empty() {
                    freed = candidates
                        .iter()
                        .copied()
                        .filter(|&j| paths[j].iter().any(|v| route.contains(v)))
                        .collect();
                }
                if freed.is_empty() {
                    freed = candidates;
                }
                freed.sort_by_key(|&j| (std::cmp::Reverse(dist.get(j, inst.starts[j])), j));
                for &j in &freed {
                    fixed[j] = false;
                }
                let mut next: Vec<usize> = vec![i];
                next.extend(freed);
                next.extend(order.iter().copied().filter(|&j| j != i));
                order = next;
            }
        }
        if deadline.expired() {
            return Err(Unsolved::TimeLimit);
        }
    }
    Err(Unsolved::GaveUp(format!(
        "repair found no conflict-free plan in {max_rounds} rounds"
    )))
}

/// What the paper's steps produced, for reports and tests.
#[derive(Debug, Clone)]
pub struct PaperStages {
    pub paths: Vec<Vec<VertexId>>,
    pub greedy_end: GreedyEnd,
    pub resolution_end: ResolutionEnd,
}

/// Runs the paper's three steps.
pub fn paper_stages(
    g: &Graph,
    dist: &GoalDistances,
    inst: &Instance,
    cfg: &HStar,
    opts: &Ctx,
) -> Result<PaperStages, Unsolved> {
    let corridors = Corridors::build_until(g, opts.deadline).ok_or(Unsolved::TimeLimit)?;
    let mut rng = ChaCha8Rng::seed_from_u64(opts.seed);
    stage(opts, 1, "greedy path search");
    let (mut paths, greedy_end) =
        greedy_path_search(g, &corridors, dist, inst, cfg, &mut rng, opts.deadline)?;
    stage(opts, 2, "loop elimination");
    for p in &mut paths {
        loop_elimination(p);
    }
    stage(opts, 3, "collision elimination");
    let resolution_end = collision_elimination(
        &mut paths,
        g.num_vertices(),
        cfg.max_resolution_rounds
            .unwrap_or(100 + 10 * inst.num_agents()),
        cfg.max_stretch,
        opts.deadline,
    )?;
    Ok(PaperStages {
        paths,
        greedy_end,
        resolution_end,
    })
}

/// Reports the H* stage about to run (`k` of 5, after 0 = the goal distances: the paper's three steps, then mrpp's repair and
/// local re-planning).
fn stage(opts: &Ctx, k: u64, name: &str) {
    opts.report(mrpp_core::Progress {
        stage: "H* stage",
        done: k,
        total: 5,
        note: name.to_string(),
    });
}

impl Planner<MapfProblem> for HStar {
    fn name(&self) -> &str {
        NAME
    }

    fn plan(&self, problem: &MapfProblem, opts: &Ctx) -> Result<Plan, Unsolved> {
        let (g, inst) = (problem.graph(), problem.instance());
        stage(opts, 0, "goal distances");
        // Every robot's goal distances, shared by all stages.
        let dist = distances(g, inst, opts.deadline)?;
        let stages = paper_stages(g, &dist, inst, self, opts)?;
        let short: Vec<usize> = (0..inst.num_agents())
            .filter(|&i| stages.paths[i].last() != Some(&inst.goals[i]))
            .collect();
        let clean = short.is_empty() && stages.resolution_end == ResolutionEnd::NoConflict;
        let mut finished_by = "paper";
        let mut paths = match (clean, self.variant) {
            (true, _) => stages.paths,
            (false, Variant::Paper) => {
                return Err(Unsolved::GaveUp(if !short.is_empty() {
                    format!(
                        "paper steps leave {} robot(s) short of their goals (greedy stage ended: {:?}), e.g. agent {} at {}",
                        short.len(),
                        stages.greedy_end,
                        short[0],
                        g.label(position(&stages.paths[short[0]], usize::MAX))
                    )
                } else {
                    format!(
                        "paper steps leave conflicts (collision elimination ended: {:?})",
                        stages.resolution_end
                    )
                }));
            }
            (false, Variant::Repaired) => {
                stage(opts, 4, "reservation repair");
                match reservation_repair(
                    g,
                    inst,
                    &dist,
                    &stages.paths,
                    self.max_repair_rounds,
                    opts.deadline,
                ) {
                    Ok(paths) => {
                        finished_by = "repair";
                        paths
                    }
                    Err(Unsolved::GaveUp(_)) if self.complete => {
                        finished_by = "lacam";
                        complete_with_lacam(g, inst, &stages.paths, opts)?
                    }
                    Err(e) => return Err(e),
                }
            }
        };
        if self.variant == Variant::Repaired {
            stage(opts, 5, "local re-planning");
            local_replanning(
                g,
                inst,
                &dist,
                &mut paths,
                self.replanning_passes,
                opts.deadline,
            )?;
        }
        if let Ok(mut slot) = self.finished_by.lock() {
            *slot = Some(finished_by);
        }
        Ok(Plan::new(paths))
    }

    /// `finished_by`: the stage that finished the last plan (`paper`, `repair` or `lacam`).
    fn notes(&self) -> serde_json::Map<String, serde_json::Value> {
        let mut m = serde_json::Map::new();
        if let Some(by) = self.finished_by.lock().ok().and_then(|s| *s) {
            m.insert("finished_by".into(), by.into());
        }
        m
    }
}

/// H* completed (module doc): `paths` up to the step before their first conflict (or their
/// end), then LaCAM from that configuration to the goals.
///
/// # Errors
/// LaCAM's: [`Unsolved::GaveUp`] when no plan exists, [`Unsolved::TimeLimit`].
pub fn complete_with_lacam(
    g: &Graph,
    inst: &Instance,
    paths: &[Vec<VertexId>],
    opts: &Ctx,
) -> Result<Vec<Vec<VertexId>>, Unsolved> {
    let horizon = paths.iter().map(Vec::len).max().unwrap_or(1);
    let keep = match first_conflict(paths, g.num_vertices(), true) {
        Some(c) => c.t,
        None => horizon,
    };
    let mut out: Vec<Vec<VertexId>> = paths
        .iter()
        .map(|p| (0..keep).map(|t| position(p, t)).collect())
        .collect();
    let from: Vec<VertexId> = out.iter().map(|p| *p.last().expect("keep >= 1")).collect();
    let (configs, _) =
        crate::lacam::search(&crate::lacam::Lacam::default(), g, &from, &inst.goals, opts)?;
    for config in &configs[1..] {
        for (p, &v) in out.iter_mut().zip(config) {
            p.push(v);
        }
    }
    Ok(out)
}

/// An order [`local_replanning`] re-planned: the paths of all but its last robot, in order, the
/// last robot's arrival, and the order's summed cost.
struct Planned {
    firsts: Vec<Vec<VertexId>>,
    last_arrival: u32,
    total: usize,
}

/// Our second extension of the local search (repaired variant only), in two moves, repeated while
/// either improves something (at most `passes` times):
/// - *single*: each robot in turn, most delayed first, is re-planned with space-time A* against
///   every other robot's path and keeps the new path only if it arrives strictly earlier;
/// - *pair*: a delayed robot and one robot whose path crosses its shortest route (at most
///   `PAIR_CANDIDATES` of them, most delayed first) are both re-planned, in both orders, and the
///   better pair of paths is kept if their summed cost drops. Two robots that hold each other up in
///   a corridor can only be untangled together.
///
/// Algorithm 4 clears a conflict with whatever number of halts works first, and the greedy stage's
/// detours around occupied corridors stay in the paths; these moves remove such waits and detours
/// when the other robots' timing allows. Neither makes the sum of costs larger and both keep the
/// plan conflict-free.
pub fn local_replanning(
    g: &Graph,
    inst: &Instance,
    dist: &GoalDistances,
    paths: &mut [Vec<VertexId>],
    passes: usize,
    deadline: Deadline,
) -> Result<(), Unsolved> {
    const PAIR_CANDIDATES: usize = 3;
    let n = inst.num_agents();
    let robots = Robots {
        g,
        inst,
        dist,
        deadline,
    };
    let ideal = |i: usize| dist.get(i, inst.starts[i]) as usize;
    let cost = |p: &[VertexId], i: usize| {
        mrpp_core::mapf::plan::path_cost(
            p,
            inst.goals[i],
            mrpp_core::mapf::plan::GoalSemantics::Stay,
        )
        .unwrap_or(usize::MAX)
    };
    let routes: Vec<FxHashSet<VertexId>> = (0..n)
        .map(|i| dist.descend(i, inst.starts[i]).into_iter().collect())
        .collect();
    // Plans `order` one after another against every path except theirs, their costs summing to at
    // most `budget` (each robot needs at least its distance); None if that is impossible.
    // Every path is reserved once; a re-planning takes its robots' paths out, plans them, and
    // puts the table back as it was (the table is the same as one built afresh, since each
    // vertex's reservations are kept sorted).
    let mut res = Reservations::new(g.num_vertices());
    for p in paths.iter() {
        res.reserve_path(p, 0, true);
    }
    // SIPP arrivals of robots planned alone against every path but those of `released` (sorted;
    // one robot twice): `Ok(a)` the earliest arrival, `Err(b)` none by `b`. The pair check and
    // both orders of a pair ask the same questions; emptied whenever a path changes.
    type Alone = rustc_hash::FxHashMap<([usize; 2], usize), Result<u32, u32>>;
    let alone: std::cell::RefCell<Alone> = Default::default();
    // What the memo answers for robot `i` by `bound`, if it knows.
    let remembered = |released: [usize; 2], i: usize, bound: u32| -> Option<Result<u32, Search>> {
        match *alone.borrow().get(&(released, i))? {
            Ok(a) if a <= bound => Some(Ok(a)),
            Ok(_) => Some(Err(Search::NotFound)),
            Err(b) if bound <= b => Some(Err(Search::NotFound)),
            Err(_) => None,
        }
    };
    let arrival_alone =
        |res: &Reservations, released: [usize; 2], i: usize, bound: u32| -> Result<u32, Search> {
            if let Some(known) = remembered(released, i, bound) {
                return known;
            }
            let key = (released, i);
            let found = robots.arrival(i, res, bound);
            match found {
                Ok(a) => alone.borrow_mut().insert(key, Ok(a)),
                Err(Search::NotFound) => alone.borrow_mut().insert(key, Err(bound)),
                Err(_) => None,
            };
            found
        };
    // The last robot of an order needs only its arrival to judge the order (its cost is its
    // arrival); its path is drawn by `finish` once the order is kept, against the same table, so
    // it is the path planning it in turn would have drawn. Orders that are not kept cost it one
    // SIPP search instead of SIPP and space-time A*.
    let replan = |res: &mut Reservations,
                  paths: &[Vec<VertexId>],
                  order: &[usize],
                  budget: usize|
     -> Result<Option<Planned>, Unsolved> {
        for &i in order {
            res.release_path(&paths[i], 0, true);
        }
        let mut firsts: Vec<Vec<VertexId>> = Vec::with_capacity(order.len() - 1);
        let mut left = budget;
        let mut outcome = Ok(None);
        // The last robot's arrival, once every robot is planned.
        let mut last = None;
        let released = [
            order[0].min(order[order.len() - 1]),
            order[0].max(order[order.len() - 1]),
        ];
        for (k, &i) in order.iter().enumerate() {
            let others: usize = order[k + 1..].iter().map(|&j| ideal(j)).sum();
            let Some(bound) = left.checked_sub(others) else {
                break;
            };
            // The first robot is planned against the table without the order's robots.
            let arrival = if k == 0 {
                arrival_alone(res, released, i, bound as u32)
            } else {
                robots.arrival(i, res, bound as u32)
            };
            if k + 1 == order.len() {
                match arrival {
                    Ok(arrival) => last = Some(arrival),
                    Err(Search::TimedOut) => outcome = Err(Unsolved::TimeLimit),
                    Err(_) => {}
                }
                break;
            }
            // What is known of the next robot alone against this table bounds it from below
            // (this robot's path can only delay it): an order it proves too slow needs no path.
            if let Ok(a) = arrival
                && k == 0
                && order.len() == 2
            {
                let rest = (left - a as usize) as u32;
                if let Some(Err(_)) = remembered(released, order[1], rest) {
                    break;
                }
            }
            let found = match arrival {
                Ok(arrival) => robots.path(i, res, arrival),
                Err(other) => other,
            };
            match found {
                Search::Found(p) => {
                    res.reserve_path(&p, 0, true);
                    left -= cost(&p, i).min(left);
                    firsts.push(p);
                }
                Search::TimedOut => {
                    outcome = Err(Unsolved::TimeLimit);
                    break;
                }
                Search::NotFound => break,
            }
        }
        for p in &firsts {
            res.release_path(p, 0, true);
        }
        for &i in order {
            res.reserve_path(&paths[i], 0, true);
        }
        match (outcome, last) {
            (Ok(None), Some(last_arrival)) => Ok(Some(Planned {
                total: budget - left + last_arrival as usize,
                firsts,
                last_arrival,
            })),
            (outcome, _) => outcome,
        }
    };
    // The paths of an order `replan` kept, the last robot's drawn now: space-time A* against the
    // table `replan` planned it against, bounded by the arrival SIPP found there.
    let finish = |res: &mut Reservations,
                  paths: &[Vec<VertexId>],
                  order: &[usize],
                  planned: Planned|
     -> Result<Option<Vec<Vec<VertexId>>>, Unsolved> {
        for &i in order {
            res.release_path(&paths[i], 0, true);
        }
        for p in &planned.firsts {
            res.reserve_path(p, 0, true);
        }
        let last = order[order.len() - 1];
        let found = robots.path(last, res, planned.last_arrival);
        for p in &planned.firsts {
            res.release_path(p, 0, true);
        }
        for &i in order {
            res.reserve_path(&paths[i], 0, true);
        }
        match found {
            Search::Found(p) => {
                debug_assert_eq!(cost(&p, last), planned.last_arrival as usize);
                let mut out = planned.firsts;
                out.push(p);
                Ok(Some(out))
            }
            Search::TimedOut => Err(Unsolved::TimeLimit),
            // SIPP found this arrival on the same table and space-time A* finds the same
            // (a property test checks); were they ever to disagree, the order is not kept.
            Search::NotFound => Ok(None),
        }
    };
    // Whether no order of the pair `[a, b]` can be re-planned within `budget`: planned alone
    // against every other path, their earliest arrivals sum past the budget (or one has none).
    // Planning one first only adds reservations for the other and lowers its bound to the
    // budget minus the first's arrival, so both orders would fail: two SIPP searches answer for
    // the four searches of the two orders. The first search is bounded by the budget less the
    // second robot's least possible arrival (its distance, and the time its goal stays
    // reserved), the second by the budget less the first's arrival: a search that fails within
    // that bound already proves the sum too large.
    let hopeless = |res: &mut Reservations,
                    paths: &[Vec<VertexId>],
                    [a, b]: [usize; 2],
                    budget: usize|
     -> Result<bool, Unsolved> {
        res.release_path(&paths[a], 0, true);
        res.release_path(&paths[b], 0, true);
        let released = [a.min(b), a.max(b)];
        let least = |k: usize| {
            res.free_for_good_from(inst.goals[k])
                .map(|t| (t as usize).max(ideal(k)))
        };
        let first_bound = least(b).and_then(|lb| budget.checked_sub(lb));
        let outcome = match first_bound {
            None => Ok(true),
            Some(bound) => match arrival_alone(res, released, a, bound as u32) {
                Ok(arrival) => {
                    let bound = budget - arrival as usize;
                    match arrival_alone(res, released, b, bound as u32) {
                        Ok(_) => Ok(false),
                        Err(Search::TimedOut) => Err(Unsolved::TimeLimit),
                        Err(_) => Ok(true),
                    }
                }
                Err(Search::TimedOut) => Err(Unsolved::TimeLimit),
                Err(_) => Ok(true),
            },
        };
        res.reserve_path(&paths[a], 0, true);
        res.reserve_path(&paths[b], 0, true);
        outcome
    };
    // Replaces robot i's path, in the paths and in the table.
    let replace = |res: &mut Reservations, paths: &mut [Vec<VertexId>], i: usize, p| {
        alone.borrow_mut().clear();
        res.release_path(&paths[i], 0, true);
        paths[i] = p;
        res.reserve_path(&paths[i], 0, true);
    };
    // A re-planning depends only on the paths: one that changed nothing is not tried again
    // until some path changes (`version` counts the changes).
    let mut version = 0u64;
    let mut fruitless: rustc_hash::FxHashMap<Vec<usize>, u64> = Default::default();
    for _ in 0..passes {
        let mut order: Vec<usize> = (0..n).filter(|&i| cost(&paths[i], i) > ideal(i)).collect();
        order.sort_by_key(|&i| (std::cmp::Reverse(cost(&paths[i], i) - ideal(i)), i));
        let mut improved = false;
        for &i in &order {
            let current = cost(&paths[i], i);
            if current <= ideal(i) || fruitless.get(&[i][..]) == Some(&version) {
                continue;
            }
            match replan(&mut res, paths, &[i], current - 1)? {
                Some(planned) if planned.total < current => {
                    if let Some(mut p) = finish(&mut res, paths, &[i], planned)? {
                        replace(&mut res, paths, i, p.remove(0));
                        version += 1;
                        improved = true;
                    }
                }
                _ => {
                    fruitless.insert(vec![i], version);
                }
            }
        }
        for &i in &order {
            if cost(&paths[i], i) <= ideal(i) {
                continue;
            }
            let mut partners: Vec<usize> = (0..n)
                .filter(|&j| j != i && paths[j].iter().any(|v| routes[i].contains(v)))
                .collect();
            partners.sort_by_key(|&j| (std::cmp::Reverse(cost(&paths[j], j) - ideal(j)), j));
            for &j in partners.iter().take(PAIR_CANDIDATES) {
                let before = cost(&paths[i], i) + cost(&paths[j], j);
                let untried = [[i, j], [j, i]]
                    .iter()
                    .any(|pair| fruitless.get(&pair[..]) != Some(&version));
                if untried && hopeless(&mut res, paths, [i, j], before - 1)? {
                    for pair in [[i, j], [j, i]] {
                        fruitless.insert(pair.to_vec(), version);
                    }
                    continue;
                }
                let mut best: Option<([usize; 2], Planned)> = None;
                for pair in [[i, j], [j, i]] {
                    if fruitless.get(&pair[..]) == Some(&version) {
                        continue;
                    }
                    let mut better = false;
                    // The second order counts only if it beats the first: bound it by that
                    // (a first order of total 0 cannot be beaten).
                    let beat = best.as_ref().map_or(before, |(_, b)| b.total);
                    let planned = match beat.checked_sub(1) {
                        Some(budget) => replan(&mut res, paths, &pair, budget)?,
                        None => None,
                    };
                    if let Some(planned) = planned {
                        let total = planned.total;
                        if total < before && best.as_ref().is_none_or(|(_, b)| total < b.total) {
                            best = Some((pair, planned));
                            better = true;
                        }
                    }
                    if !better {
                        fruitless.insert(pair.to_vec(), version);
                    }
                }
                let kept = match best {
                    Some((pair, planned)) => {
                        finish(&mut res, paths, &pair, planned)?.map(|ps| (pair, ps))
                    }
                    None => None,
                };
                if let Some((pair, mut ps)) = kept {
                    if pair[0] == j {
                        ps.swap(0, 1);
                    }
                    replace(&mut res, paths, j, ps.pop().expect("two paths"));
                    replace(&mut res, paths, i, ps.pop().expect("two paths"));
                    version += 1;
                    improved = true;
                    break;
                }
            }
        }
        if !improved {
            break;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::GridMap;
    use mrpp_core::{Instance, Problem as _, Rules};
    use std::path::Path;

    #[test]
    fn loop_elimination_cuts_cycles_and_waits() {
        let mut p = vec![1, 2, 3, 2, 4, 4, 5];
        loop_elimination(&mut p);
        assert_eq!(p, vec![1, 2, 4, 5]);
        let mut q = vec![1, 2, 1, 2, 3];
        loop_elimination(&mut q);
        assert_eq!(q, vec![1, 2, 3]);
        let mut r = vec![7];
        loop_elimination(&mut r);
        assert_eq!(r, vec![7]);
    }

    #[test]
    fn halts_are_inserted_before_the_collision() {
        assert_eq!(insert_halts(&[1, 2, 3], 1, 2), vec![1, 2, 2, 2, 3]);
        // Plus: centre 0, W=1 E=2 N=3 S=4; both cross the centre at t=1.
        let mut paths = vec![vec![1, 0, 2], vec![4, 0, 3]];
        assert_eq!(resolve_collision(&mut paths, 0, 1, 1), Some(1));
        assert_eq!(paths[0], vec![1, 1, 0, 2]);
        assert!(first_conflict(&paths, 5, true).is_none());
    }

    /// Algorithms 3 and 4 as written: every round rescans all paths from step 0, and each try of
    /// Algorithm 4 checks the pair with `first_conflict`.
    fn reference_elimination(paths: &mut [Vec<VertexId>], nv: usize, rounds: usize) -> bool {
        for _ in 0..rounds {
            let Some(c) = first_conflict(paths, nv, true) else {
                return true;
            };
            let mut done = false;
            for i in 1..=c.t {
                let new_a = insert_halts(&paths[c.a], c.t - i, i);
                if first_conflict(&[new_a.clone(), paths[c.b].clone()], nv, true).is_none() {
                    paths[c.a] = new_a;
                    done = true;
                    break;
                }
                let new_b = insert_halts(&paths[c.b], c.t - i, i);
                if first_conflict(&[paths[c.a].clone(), new_b.clone()], nv, true).is_none() {
                    paths[c.b] = new_b;
                    done = true;
                    break;
                }
            }
            if !done {
                return false;
            }
        }
        first_conflict(paths, nv, true).is_none()
    }

    /// Collision elimination, which rescans only from the steps a resolution changed and checks
    /// pairs directly, gives the paths of the plain algorithm, on random walks of 2-8 robots on
    /// a 4 x 4 grid (most with conflicts).
    #[test]
    fn collision_elimination_matches_the_plain_algorithm() {
        use rand::RngExt as _;
        use rand::seq::SliceRandom as _;
        let text = "######\n#    #\n#    #\n#    #\n#    #\n######";
        let m = GridMap::parse(text, Path::new("t.txt"))
            .expect("a 4 x 4 room")
            .0;
        let g = m.graph();
        let nv = g.num_vertices();
        let mut rng = ChaCha8Rng::seed_from_u64(15);
        let mut conflicted = 0;
        for case in 0..2000 {
            let n = rng.random_range(2..=8usize);
            let mut starts: Vec<VertexId> = (0..nv as VertexId).collect();
            starts.shuffle(&mut rng);
            let mut paths: Vec<Vec<VertexId>> = starts[..n]
                .iter()
                .map(|&s| {
                    let mut p = vec![s];
                    for _ in 0..rng.random_range(0..10) {
                        let v = *p.last().unwrap();
                        let w = *g.neighbors(v).choose(&mut rng).unwrap();
                        p.push(w);
                    }
                    p
                })
                .collect();
            conflicted += usize::from(first_conflict(&paths, nv, true).is_some());
            let mut reference = paths.clone();
            let ok = reference_elimination(&mut reference, nv, 200);
            let end =
                collision_elimination(&mut paths, nv, 200, usize::MAX, Deadline::none()).unwrap();
            assert_eq!(paths, reference, "case {case}");
            assert_eq!(end == ResolutionEnd::NoConflict, ok, "case {case}");
        }
        assert!(
            conflicted > 1000,
            "{conflicted} of 2000 cases had a conflict"
        );
    }

    fn solve_map(
        map: &str,
        robots: &str,
        planner: &HStar,
    ) -> (GridMap, Instance, Result<Plan, Unsolved>) {
        let m = GridMap::parse(map, Path::new("m.txt")).unwrap().0;
        let inst = crate::scen::parse_agents(robots, Path::new("r.txt"), &m, None).unwrap();
        let r = planner.plan(
            &MapfProblem::on(m.graph(), &inst, Rules::default()),
            &Ctx::default(),
        );
        (m, inst, r)
    }

    /// Algorithm 1 as plainly as it reads (sequential update, first shortest, a robot on its
    /// target node blocks only once parked): each free neighbour's route is a breadth-first
    /// search over the cells, avoiding the robot's own cell and every cell of a node another
    /// robot blocks. No corridor search, bounds, limits or skipped searches.
    fn reference_greedy(
        g: &Graph,
        c: &Corridors,
        inst: &Instance,
        cap: usize,
    ) -> (Vec<Vec<VertexId>>, GreedyEnd) {
        let n = inst.num_agents();
        let mut pos = inst.starts.clone();
        let mut paths: Vec<Vec<VertexId>> = pos.iter().map(|&s| vec![s]).collect();
        let mut parked_ever = vec![false; n];
        let mut seen = std::collections::HashSet::new();
        seen.insert(pos.clone());
        for _ in 0..cap {
            if pos == inst.goals {
                return (paths, GreedyEnd::AllOnGoal);
            }
            for r in 0..n {
                let (cur, goal) = (pos[r], inst.goals[r]);
                if cur == goal {
                    continue;
                }
                let node = |v: VertexId| c.node_of(v);
                let occupied = |x: NodeId| (0..n).any(|j| j != r && node(pos[j]) == x);
                let blocked = |x: NodeId| {
                    if x == node(goal) {
                        (0..n).any(|j| j != r && parked_ever[j] && node(pos[j]) == x)
                    } else {
                        occupied(x)
                    }
                };
                let route = |from: VertexId| -> Option<usize> {
                    if blocked(node(from)) || blocked(node(goal)) {
                        return None;
                    }
                    let mut d = vec![usize::MAX; g.num_vertices()];
                    let mut q = std::collections::VecDeque::from([from]);
                    d[from as usize] = 0;
                    while let Some(u) = q.pop_front() {
                        if u == goal {
                            return Some(d[u as usize]);
                        }
                        for &w in g.neighbors(u) {
                            if w != cur && d[w as usize] == usize::MAX && !blocked(node(w)) {
                                d[w as usize] = d[u as usize] + 1;
                                q.push_back(w);
                            }
                        }
                    }
                    None
                };
                let mut best: Option<(usize, VertexId)> = None;
                for &nk in g.neighbors(cur) {
                    if occupied(node(nk)) {
                        continue;
                    }
                    if let Some(len) = route(nk)
                        && best.is_none_or(|(b, _)| len < b)
                    {
                        best = Some((len, nk));
                    }
                }
                if let Some((_, nk)) = best {
                    pos[r] = nk;
                }
            }
            for r in 0..n {
                parked_ever[r] |= pos[r] == inst.goals[r];
                paths[r].push(pos[r]);
            }
            if !seen.insert(pos.clone()) {
                return (paths, GreedyEnd::Cycle);
            }
        }
        let end = if pos == inst.goals {
            GreedyEnd::AllOnGoal
        } else {
            GreedyEnd::StepCap
        };
        (paths, end)
    }

    #[test]
    fn greedy_stage_matches_a_plain_breadth_first_reference() {
        // Random maps with rooms, corridors and dead ends; robots crowded enough to wall each
        // other in (the case the greedy stage skips searches for).
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move |m: usize| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x % m as u64) as usize
        };
        let mut cases = 0;
        while cases < 150 {
            let (w, h) = (4 + next(9), 3 + next(7));
            let density = next(40);
            let rows: Vec<Vec<bool>> = (0..h)
                .map(|_| (0..w).map(|_| next(100) >= density).collect())
                .collect();
            let m = GridMap::from_free_rows(&rows);
            let g = m.graph();
            let nv = g.num_vertices();
            if nv < 4 {
                continue;
            }
            let agents = 2 + next((nv / 2).min(10));
            let mut cells: Vec<VertexId> = (0..nv as VertexId).collect();
            let mut pick = |cells: &mut Vec<VertexId>| {
                let mut out = Vec::new();
                for _ in 0..agents {
                    let i = next(cells.len());
                    out.push(cells.swap_remove(i));
                }
                out
            };
            let starts = pick(&mut cells.clone());
            let goals = pick(&mut cells);
            let dist = GoalDistances::new(g, &goals);
            if starts
                .iter()
                .enumerate()
                .any(|(i, &s)| dist.get(i, s) == UNREACHABLE)
            {
                continue;
            }
            let inst = Instance::new(starts, goals).unwrap();
            let c = Corridors::build(g);
            let cap = 4 * nv + 100;
            let mut rng = ChaCha8Rng::seed_from_u64(0);
            let got = greedy_path_search(
                g,
                &c,
                &dist,
                &inst,
                &HStar::default(),
                &mut rng,
                Deadline::none(),
            )
            .unwrap();
            let want = reference_greedy(g, &c, &inst, cap);
            assert_eq!(got, want, "map {rows:?}, robots {inst:?}");
            cases += 1;
        }
    }

    #[test]
    fn open_room_crossing_is_solved_and_valid() {
        let map = "#######\n#     #\n#     #\n#     #\n#######";
        let (m, inst, r) = solve_map(map, "1,2;5,2\n5,2;1,2\n3,1;3,3\n3,3;3,1", &HStar::default());
        let plan = r.unwrap();
        let metrics = MapfProblem::on(m.graph(), &inst, Rules::default())
            .validate(&plan)
            .unwrap();
        assert!(metrics.sum_of_costs >= 4 + 4 + 2 + 2);
    }

    #[test]
    fn head_on_in_a_corridor_needs_the_repair() {
        // Two robots must pass each other through a 1-wide corridor with a side pocket.
        let map = "#########\n## ######\n#       #\n#########";
        let robots = "1,2;7,2\n7,2;1,2";
        let (m, inst, r) = solve_map(map, robots, &HStar::default());
        let plan = r.unwrap();
        MapfProblem::on(m.graph(), &inst, Rules::default())
            .validate(&plan)
            .unwrap();
        let (_, _, paper) = solve_map(map, robots, &HStar::paper());
        match paper {
            Ok(p) => {
                MapfProblem::on(m.graph(), &inst, Rules::default())
                    .validate(&p)
                    .unwrap();
            }
            Err(Unsolved::GaveUp(_)) => {}
            Err(e) => panic!("unexpected {e}"),
        }
    }

    #[test]
    fn lacam_completes_from_the_conflict_free_prefix() {
        // The corridor with a side pocket; H*-like paths that run head-on into each other.
        let map = "#########\n## ######\n#       #\n#########";
        let m = GridMap::parse(map, Path::new("m.txt")).unwrap().0;
        let inst =
            crate::scen::parse_agents("1,2;7,2\n7,2;1,2", Path::new("r.txt"), &m, None).unwrap();
        let row = |xs: &[i64]| {
            xs.iter()
                .map(|&x| m.vertex_at(x, 2).unwrap())
                .collect::<Vec<_>>()
        };
        let paths = vec![row(&[1, 2, 3, 4, 5, 6, 7]), row(&[7, 6, 5, 4, 3, 2, 1])];
        let done = complete_with_lacam(m.graph(), &inst, &paths, &Ctx::default()).unwrap();
        // The prefix before the first conflict (t = 3: both on x = 4) is kept.
        for (p, d) in paths.iter().zip(&done) {
            assert_eq!(d[..3], p[..3]);
        }
        MapfProblem::on(m.graph(), &inst, Rules::default())
            .validate(&Plan::new(done))
            .unwrap();
    }

    #[test]
    fn expired_deadline_is_honoured() {
        let m = GridMap::parse("#######\n#     #\n#     #\n#######", Path::new("m.txt"))
            .unwrap()
            .0;
        let inst =
            crate::scen::parse_agents("1,1;5,2\n5,1;1,2", Path::new("r.txt"), &m, None).unwrap();
        let opts = Ctx::new(0, Deadline::after(std::time::Duration::ZERO));
        assert_eq!(
            HStar::default().plan(&MapfProblem::on(m.graph(), &inst, Rules::default()), &opts),
            Err(Unsolved::TimeLimit)
        );
    }
}
