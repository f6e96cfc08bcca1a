//! NSGA-III route selection, the multi-objective baseline of the H* paper's Table II (González et
//! al., SOCO 2023, cited there as [22]; H* paper §V-D).
//!
//! The H* paper describes it in one sentence: NSGA-III "starts from a set of pregenerated
//! randomized routes and applies multi-objective evolutionary optimization to identify a
//! combination of routes that minimize the path length and number of collisions", and the answer is
//! the best member "from a set of non-dominated feasible solutions which have no collisions". The
//! SOCO paper itself was not readable here, so everything below that sentence is reconstructed
//! (**[R]**), each choice an option of [`Nsga3Planner`]. The evolutionary engine is the generic,
//! unmodified NSGA-III of [`mrpp_evo::nsga3`] (Deb & Jain 2014); only the encoding, the
//! objectives and the operators are specific to MAPF.
//!
//! The steps, each a function named after it:
//! 1. [`pregenerate_routes`] **[R]**: per robot up to `K` = [`Nsga3Planner::routes_per_robot`]
//!    (default 8) distinct start–goal routes, duplicates dropped: the shortest route (always
//!    candidate 0); the shortest among the routes that enter the fewest *other robots' goal
//!    cells*; then routes through 1–2 random waypoints, with loops cut ([`loop_elimination`], as
//!    H*'s Algorithm 2). A robot that starts on its goal gets step-aside routes instead
//!    ([`step_aside_routes`]: out to a cell one or two steps away, a wait, and back, not
//!    loop-trimmed), so another robot can pass through its goal. "Randomized routes" needs some randomness; waypoints give detours that
//!    differ in where they leave the shortest route, and loop cutting keeps them simple paths. A
//!    waypoint route is at most `detour_factor` × shortest + `detour_slack` long (defaults 2 and
//!    10): unbounded waypoints on a large map produce routes that no sensible answer would use and
//!    only dilute the gene's alphabet. Its legs are least-crossing routes (entering no more goal
//!    cells than necessary), except on every 4th draw, which uses plain shortest legs.
//!    Keeping off goal cells ([`Nsga3Planner::avoid_other_goals`]) matters under `stay`
//!    semantics: a route through another robot's goal forces that robot to arrive later, an order
//!    that start delays can rarely arrange. The plain draws keep some candidates that do pass
//!    goal cells, which instances where every start is another robot's goal need (the test grid
//!    of three swapping pairs: solved for 20 of 20 seeds with them, 0 of 20 without).
//! 2. Encoding **[R]**: a genome picks, per robot, one route index and a start delay (waits at the
//!    start, `0..=max_delay`, default 40). The issue asks for "a genome that picks one route per
//!    robot (plus waits)"; without waits two robots whose only sensible routes cross at the same
//!    moment could never both be served, and waits at the start are the simplest kind that keeps
//!    the genome a fixed-length integer vector. The delay must be long enough to let a robot go
//!    deep into a dead end before another parks at its mouth (Scenario 1's top corridor needs
//!    about 20 steps).
//! 3. Objectives **[R]** ([`Objectives`]): f1 = number of conflicts ([`count_conflicts`]: vertex
//!    conflicts plus swap conflicts under `stay` semantics, a robot that has arrived keeps its goal),
//!    f2 = sum of arrival times (waits included, the paper's "Sum"); optionally f3 = makespan
//!    ("Max"). f1 and f2 are "the number of collisions and the path length" of §V-D.
//!    The count is defined stepwise ([`count_conflicts_stepwise`], O(n·T) with a time-stamped
//!    occupancy array); [`count_conflicts`] reads the same number from a table of robot-pair
//!    conflicts per route pair and start-delay difference, filled as genomes need it (module
//!    `pair_table`), which makes an evaluation a few hundred table reads.
//! 4. Operators **[R]**: uniform crossover with probability 0.9 and per-gene
//!    reset mutation with rate `1/n`, where robot `i`'s gene is its (route, delay) pair: the pair
//!    comes whole from either parent, and a reset redraws both uniformly. A route and the delay that
//!    times it belong together; resetting them independently made two-part repairs (another route
//!    *and* another delay) a `1/n²` event. The initial population is uniformly random, as in Deb &
//!    Jain; it is not seeded with the all-shortest genome, so the baseline finds its answers
//!    itself.
//! 5. [`select_answer`]: among the final population's non-dominated members with f1 = 0, the one
//!    with least f2 (ties: least makespan, then the earlier member). None collision-free →
//!    [`Unsolved::GaveUp`].
//!
//! Population and generations: with two objectives NSGA-III's reference points are `p + 1`
//! Das–Dennis points on a line; `p = 91` gives `H = 92` and so `N = 92`; with three objectives
//! `p = 12` gives `H = 91`, `N = 92` (Deb & Jain's setting). 250 generations take at most about
//! 0.1 s on the H* paper's instances in release (98 ms mean on the 30-robot warehouse in the
//! Table II experiment of 2026-12-02).
//!
//! Measured on the 19 Table I instances × seeds 0–9 (190 runs), runs solved with the defaults: 146
//! (mean 51 ms, at most 98 ms). Changing one option: `avoid_other_goals = false` 105;
//! `plain_detour_every` 0: 143, 2: 132; `max_delay` 10: 127, 20: 134, 30: 139; `generations` 150:
//! 141 (mean 32 ms, at most 65 ms), 400: 151 (mean 77 ms, at most 143 ms). Each row is `python3
//! tools/perf/table1-sweep.py target/release/mrpp -p KEY=VALUE` (at `3631a79` plus these options on
//! the command line, 2026-12-02 08:09 UTC, 2-core AMD EPYC VM, load average 0.8).
//!
//! What is left unsolved: the conflicts NSGA-III cannot remove are arrival orders (a robot parked
//! on its goal in a dead end or in a row of goals blocks a later robot) and head-on meetings in
//! Scenario 2's one-cell doors; no single gene change fixes them, and the population, pulled
//! towards small f2, rarely makes the several coordinated changes they need.
//!
//! Time limit: the deadline is polled while routes are generated and before every evaluation. When
//! it expires during evolution, the answer is chosen by step 5 from the last complete population
//! (the best collision-free non-dominated member found so far); if that holds none, or the deadline
//! expired before evolution started, the result is [`Unsolved::TimeLimit`].
//!
//! The run is determined by `opts.seed`: one `ChaCha8Rng` draws the waypoints, then drives the
//! evolution.

use std::cell::RefCell;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rustc_hash::FxHashMap;

use crate::hstar::loop_elimination;
use mrpp_core::contract::{Ctx, Deadline, Planner, Unsolved};
use mrpp_core::mapf::graph::{Graph, VertexId};
use mrpp_core::mapf::plan::Plan;
use mrpp_core::mapf::search::distance::{descend_weighted, dijkstra_distances_until};
use mrpp_core::{MapfProblem, Param, PlannerEntry};
use mrpp_evo::nsga3::{Individual, Nsga3, Problem};

mod pair_table;
use pair_table::PairTable;

/// Registry name of the NSGA-III route selection.
pub const NAME: &str = "nsga3";

/// NSGA-III route selection in the planner registry.
pub const ENTRY: PlannerEntry<MapfProblem> = PlannerEntry {
    name: NAME,
    about: "NSGA-III over pre-generated routes with start delays (Deb & Jain 2014; H* paper's baseline [22])",
    params: &[
        Param {
            name: "routes_per_robot",
            default: "8",
            doc: "randomised routes pre-generated per robot",
        },
        Param {
            name: "generations",
            default: "250",
            doc: "NSGA-III generations after the initial population",
        },
        Param {
            name: "max_delay",
            default: "40",
            doc: "largest start delay (waits at the start) a genome may give a robot",
        },
        Param {
            name: "avoid_other_goals",
            default: "true",
            doc: "detour routes enter as few other robots' goal cells as possible (true/false)",
        },
        Param {
            name: "plain_detour_every",
            default: "4",
            doc: "with avoid_other_goals: every this many detours is built of plain shortest legs (0 = never)",
        },
    ],
    build: |p| {
        Ok(Box::new(Nsga3Planner {
            routes_per_robot: p.get_in("routes_per_robot", 1..=1000)?,
            generations: p.get_in("generations", 0..=1_000_000)?,
            max_delay: p.get_in("max_delay", 0..=100_000)?,
            avoid_other_goals: [true, false][p.choice("avoid_other_goals", &["true", "false"])?],
            plain_detour_every: p.get_in("plain_detour_every", 0..=1000)?,
            ..Nsga3Planner::default()
        }))
    },
};

/// Which objectives NSGA-III minimises **[R]**.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Objectives {
    /// f1 = conflicts, f2 = sum of arrival times (the two criteria of the H* paper's §V-D).
    #[default]
    ConflictsAndSum,
    /// f1, f2 and f3 = makespan.
    ConflictsSumAndMakespan,
}

impl Objectives {
    pub fn count(self) -> usize {
        match self {
            Objectives::ConflictsAndSum => 2,
            Objectives::ConflictsSumAndMakespan => 3,
        }
    }
}

/// The NSGA-III route-selection planner and its options (module notes give the reasons).
#[derive(Debug, Clone, PartialEq)]
pub struct Nsga3Planner {
    /// `K`: candidate routes per robot, the shortest included (fewer when not enough distinct
    /// routes exist).
    pub routes_per_robot: usize,
    /// Waypoints per detour route: each detour draws 1..=`max_waypoints` (0 = shortest route only).
    pub max_waypoints: usize,
    /// A detour route may be at most `detour_factor` × shortest + `detour_slack` long.
    pub detour_factor: f64,
    pub detour_slack: u32,
    /// Candidates other than the shortest route enter as few other robots' goal cells as possible
    /// (the least such route is a candidate too); off = the whole graph for every candidate.
    pub avoid_other_goals: bool,
    /// With `avoid_other_goals`: every this many waypoint draws, one builds its detour of plain
    /// shortest legs instead (0 = never), so that candidates still pass through goal cells.
    pub plain_detour_every: usize,
    /// Waypoint draws per robot before giving up on reaching `K` routes.
    pub route_attempts: usize,
    /// Largest start delay (waits at the start).
    pub max_delay: u32,
    pub objectives: Objectives,
    /// NSGA-III generations after the initial population.
    pub generations: usize,
    /// Das–Dennis divisions `p`; `None` = 91 for two objectives, 12 for three (`N` = 92 either way).
    pub divisions: Option<usize>,
    /// Population size; `None` = the smallest multiple of 4 at least the number of reference points.
    pub population: Option<usize>,
    /// Probability that a pair of parents is crossed (else the children are copies).
    pub crossover_probability: f64,
    /// Per-gene reset probability; `None` = 1/n for n robots.
    pub mutation_rate: Option<f64>,
}

impl Default for Nsga3Planner {
    fn default() -> Self {
        Nsga3Planner {
            routes_per_robot: 8,
            max_waypoints: 2,
            detour_factor: 2.0,
            detour_slack: 10,
            avoid_other_goals: true,
            plain_detour_every: 4,
            route_attempts: 80,
            max_delay: 40,
            objectives: Objectives::ConflictsAndSum,
            generations: 250,
            divisions: None,
            population: None,
            crossover_probability: 0.9,
            mutation_rate: None,
        }
    }
}

impl Nsga3Planner {
    /// The NSGA-III driver these options describe.
    pub fn engine(&self) -> Nsga3 {
        let divisions = self.divisions.unwrap_or(match self.objectives {
            Objectives::ConflictsAndSum => 91,
            Objectives::ConflictsSumAndMakespan => 12,
        });
        Nsga3 {
            generations: self.generations,
            divisions,
            population: self.population,
        }
    }
}

/// Cost of a route that keeps off marked cells where it can: `crossings << 32 | length`, so routes
/// compare first by how many marked cells they enter, then by length.
type KeepOffCost = u64;
const UNREACHED: KeepOffCost = u64::MAX;

#[inline]
fn route_length(c: KeepOffCost) -> u32 {
    c as u32
}

#[inline]
fn crossings(c: KeepOffCost) -> u32 {
    (c >> 32) as u32
}

/// Dijkstra from `source` where entering a cell `x` costs `1 + (avoid(x) << 32)` (see
/// [`KeepOffCost`]). With unmarked endpoints a route costs the same in both directions, so the table
/// also gives routes *to* `source`.
fn keep_off_distances(
    g: &Graph,
    source: VertexId,
    avoid: &dyn Fn(VertexId) -> bool,
    deadline: Deadline,
) -> Result<Vec<KeepOffCost>, Unsolved> {
    dijkstra_distances_until(g, source, &|v| 1 + ((avoid(v) as u64) << 32), deadline)
        .ok_or(Unsolved::TimeLimit)
}

/// The route from `from` to the table's source (first neighbour on a least-cost route).
fn keep_off_descend(
    g: &Graph,
    table: &[KeepOffCost],
    from: VertexId,
    avoid: &dyn Fn(VertexId) -> bool,
) -> Vec<VertexId> {
    descend_weighted(g, table, from, &|v| 1 + ((avoid(v) as u64) << 32))
}

/// The tables for waypoint routes of one kind (keeping off marked cells or not).
struct Legs<'a> {
    avoid: &'a dyn Fn(VertexId) -> bool,
    from_start: Vec<KeepOffCost>,
    to_goal: Vec<KeepOffCost>,
    /// Marked cells a route must enter at least.
    need: u32,
    /// Waypoints whose route start -> w -> goal fits.
    eligible: Vec<VertexId>,
}

/// Step 1: up to `p.routes_per_robot` distinct routes from `start` to `goal` (the shortest first,
/// then by length, stable), or `None` when the goal is unreachable. Candidates: the shortest
/// route; the least route among those entering the fewest cells marked in `avoid` (other robots'
/// goals); then detours through random waypoints, at most `detour_factor` × shortest +
/// `detour_slack` long, built of such least-crossing legs (no more crossings than needed) except
/// on every `plain_detour_every`-th draw, which uses plain shortest legs.
///
/// # Errors
/// [`Unsolved::TimeLimit`] once `deadline` passes (checked inside every graph search, so one
/// robot's routes on a large map cannot overrun the limit).
pub fn pregenerate_routes(
    g: &Graph,
    start: VertexId,
    goal: VertexId,
    avoid: &[bool],
    p: &Nsga3Planner,
    rng: &mut ChaCha8Rng,
    deadline: Deadline,
) -> Result<Option<Vec<Vec<VertexId>>>, Unsolved> {
    let plain_cost = |_: VertexId| 1u64;
    let to_goal_plain =
        dijkstra_distances_until(g, goal, &plain_cost, deadline).ok_or(Unsolved::TimeLimit)?;
    let shortest = descend_weighted(g, &to_goal_plain, start, &plain_cost);
    drop(to_goal_plain);
    if shortest.is_empty() {
        return Ok(None);
    }
    let d = shortest.len() as u32 - 1;
    let mut routes = vec![shortest];
    if p.routes_per_robot <= 1 {
        return Ok(Some(routes));
    }
    if d == 0 {
        routes.extend(step_aside_routes(g, start, p.routes_per_robot - 1));
        return Ok(Some(routes));
    }
    let bound = (p.detour_factor * d as f64).floor() as u64 + p.detour_slack as u64;
    let fits = |legs: &[KeepOffCost], need: u32| {
        legs.iter().all(|&c| c != UNREACHED)
            && legs.iter().map(|&c| crossings(c)).sum::<u32>() == need
            && legs.iter().map(|&c| route_length(c) as u64).sum::<u64>() <= bound
    };
    let marked = |v: VertexId| v != start && v != goal && avoid.get(v as usize) == Some(&true);
    let plain = |_: VertexId| false;
    let keep_off = avoid.iter().any(|&a| a);
    let kinds: Vec<&dyn Fn(VertexId) -> bool> = if keep_off {
        vec![&marked, &plain]
    } else {
        vec![&plain]
    };
    let legs: Vec<Legs> = kinds
        .into_iter()
        .map(|avoid| {
            let from_start = keep_off_distances(g, start, avoid, deadline)?;
            let to_goal = keep_off_distances(g, goal, avoid, deadline)?;
            let need = crossings(to_goal[start as usize]);
            let eligible = (0..g.num_vertices() as VertexId)
                .filter(|&w| {
                    !avoid(w) && fits(&[from_start[w as usize], to_goal[w as usize]], need)
                })
                .collect();
            Ok(Legs {
                avoid,
                from_start,
                to_goal,
                need,
                eligible,
            })
        })
        .collect::<Result<_, Unsolved>>()?;
    let least = keep_off_descend(g, &legs[0].to_goal, start, legs[0].avoid);
    if !routes.contains(&least) {
        routes.push(least);
    }
    if p.max_waypoints == 0 {
        return Ok(Some(routes));
    }
    let mut second = Vec::new();
    for attempt in 0..p.route_attempts {
        if routes.len() >= p.routes_per_robot {
            break;
        }
        if deadline.expired() {
            return Err(Unsolved::TimeLimit);
        }
        let plain_turn =
            p.plain_detour_every > 0 && attempt % p.plain_detour_every == p.plain_detour_every - 1;
        let l = &legs[if plain_turn { legs.len() - 1 } else { 0 }];
        if l.eligible.is_empty() {
            continue;
        }
        let w1 = l.eligible[rng.random_range(0..l.eligible.len())];
        let mut route;
        if rng.random_range(1..=p.max_waypoints) == 1 {
            // start -> w1 -> goal.
            route = keep_off_descend(g, &l.from_start, w1, l.avoid);
            route.reverse();
            route.extend_from_slice(&keep_off_descend(g, &l.to_goal, w1, l.avoid)[1..]);
        } else {
            // start -> w1 -> w2 -> goal, w2 drawn so that the whole still fits.
            let from_w1 = keep_off_distances(g, w1, l.avoid, deadline)?;
            let s1 = l.from_start[w1 as usize];
            second.clear();
            second.extend((0..g.num_vertices() as VertexId).filter(|&w| {
                !(l.avoid)(w) && fits(&[s1, from_w1[w as usize], l.to_goal[w as usize]], l.need)
            }));
            let w2 = second[rng.random_range(0..second.len())];
            route = keep_off_descend(g, &from_w1, start, l.avoid);
            let mut leg = keep_off_descend(g, &from_w1, w2, l.avoid);
            leg.reverse();
            route.extend_from_slice(&leg[1..]);
            route.extend_from_slice(&keep_off_descend(g, &l.to_goal, w2, l.avoid)[1..]);
        }
        loop_elimination(&mut route);
        if !routes.contains(&route) {
            routes.push(route);
        }
    }
    routes.sort_by_key(Vec::len);
    Ok(Some(routes))
}

/// Waits at the far end of a step-aside route: long enough for another robot to pass through
/// the vacated cell, which the start delay then times.
const STEP_ASIDE_WAIT: usize = 1;

/// Routes for a robot that starts on its goal **[R]**: step out to a cell one or two steps away
/// (breadth-first order, up to `count` cells), wait [`STEP_ASIDE_WAIT`] steps and come back, so
/// another robot can pass through the goal; with the start delay this picks when. They are not
/// loop-trimmed (trimming would reduce each to the start cell, leaving a robot on its goal no
/// way to let others through).
fn step_aside_routes(g: &Graph, start: VertexId, count: usize) -> Vec<Vec<VertexId>> {
    let mut out = Vec::new();
    let mut ring: Vec<Vec<VertexId>> = g.neighbors(start).iter().map(|&n| vec![start, n]).collect();
    let mut second = Vec::new();
    for path in &ring {
        let n = path[1];
        for &m in g.neighbors(n) {
            if m != start && !g.neighbors(start).contains(&m) {
                second.push(vec![start, n, m]);
            }
        }
    }
    ring.extend(second);
    for out_path in ring.into_iter().take(count) {
        let far = *out_path.last().expect("a path of two or three cells");
        let mut route = out_path.clone();
        route.extend(std::iter::repeat_n(far, STEP_ASIDE_WAIT));
        route.extend(out_path.iter().rev().skip(1));
        out.push(route);
    }
    out
}

/// Step 2: one robot's gene pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Choice {
    /// Index into the robot's candidate routes.
    pub route: u32,
    /// Waits at the start before the route begins.
    pub delay: u32,
}

/// The MAPF route-selection problem NSGA-III optimises (steps 2–4).
pub struct RouteSelection<'a> {
    /// `routes[i]` = robot `i`'s candidate routes.
    pub routes: &'a [Vec<Vec<VertexId>>],
    pub num_vertices: usize,
    pub max_delay: u32,
    pub objectives: Objectives,
    pub crossover_probability: f64,
    pub mutation_rate: f64,
    scratch: RefCell<Occupancy>,
    /// Remembered pair conflicts for [`count_conflicts`] (`None`: it counts stepwise).
    pairs: Option<RefCell<PairTable<'a>>>,
    /// Objectives of genomes evaluated before: offspring often repeat a genome once the
    /// population has converged, and an evaluation is a pure function of the genome.
    memo: RefCell<FxHashMap<Vec<Choice>, Vec<f64>>>,
}

/// Genomes remembered by [`RouteSelection`] before the memo is emptied (about 10 MB at 24 robots).
const MEMO_LIMIT: usize = 100_000;

/// Time-stamped occupancy of the current and previous step (reused across evaluations).
#[derive(Default)]
struct Occupancy {
    /// Per layer (`t % 2`) and vertex.
    cells: Vec<OccupiedAt>,
    /// Stamp of step 0 of the current evaluation.
    base: u64,
}

/// One vertex at one step of [`Occupancy`].
#[derive(Clone, Copy)]
struct OccupiedAt {
    /// The stamp of the step the vertex was last occupied at.
    stamp: u64,
    /// The first robot seen there at that step, and how many robots.
    who: u32,
    count: u32,
}

impl<'a> RouteSelection<'a> {
    pub fn new(
        routes: &'a [Vec<Vec<VertexId>>],
        num_vertices: usize,
        planner: &Nsga3Planner,
    ) -> Self {
        let n = routes.len().max(1);
        RouteSelection {
            routes,
            num_vertices,
            max_delay: planner.max_delay,
            objectives: planner.objectives,
            crossover_probability: planner.crossover_probability,
            mutation_rate: planner.mutation_rate.unwrap_or(1.0 / n as f64),
            scratch: RefCell::new(Occupancy::default()),
            pairs: PairTable::new(routes, planner.max_delay).map(RefCell::new),
            memo: RefCell::new(FxHashMap::default()),
        }
    }

    fn route(&self, i: usize, c: Choice) -> &[VertexId] {
        &self.routes[i][c.route as usize]
    }

    /// Robot `i`'s cost: the step it reaches its goal (0 when it starts there).
    pub fn arrival(&self, i: usize, c: Choice) -> usize {
        let len = self.route(i, c).len();
        if len == 1 {
            0
        } else {
            c.delay as usize + len - 1
        }
    }

    /// The robots' paths (waits at the start, then the route).
    pub fn paths(&self, genome: &[Choice]) -> Vec<Vec<VertexId>> {
        genome
            .iter()
            .enumerate()
            .map(|(i, &c)| {
                let r = self.route(i, c);
                if r.len() == 1 {
                    return r.to_vec();
                }
                let mut p = vec![r[0]; c.delay as usize];
                p.extend_from_slice(r);
                p
            })
            .collect()
    }

    /// Sum of costs and makespan.
    pub fn sum_and_makespan(&self, genome: &[Choice]) -> (usize, usize) {
        genome
            .iter()
            .enumerate()
            .map(|(i, &c)| self.arrival(i, c))
            .fold((0, 0), |(s, m), a| (s + a, m.max(a)))
    }
}

/// Step 3, f1: conflicts of the joint plan a genome encodes, as [`count_conflicts_stepwise`]
/// defines them. It is read from the selection's table of remembered robot-pair conflicts when
/// the instance allows one (see the `pair_table` module), else counted stepwise; the two agree on
/// every genome.
pub fn count_conflicts(sel: &RouteSelection, genome: &[Choice]) -> u64 {
    match sel
        .pairs
        .as_ref()
        .and_then(|t| t.borrow_mut().count(genome))
    {
        Some(c) => {
            debug_assert_eq!(c, count_conflicts_stepwise(sel, genome), "{genome:?}");
            c
        }
        None => count_conflicts_stepwise(sel, genome),
    }
}

/// f1 counted step by step, in O(n·T). Each step adds, per robot, the robots already standing on
/// its vertex (so `k` robots on one vertex count `k(k-1)/2`), and each swap once. Swaps are
/// detected through the first robot recorded on a vertex at `t - 1`, so they are exact whenever
/// `t - 1` has no vertex conflict; the count is zero exactly when the plan has no vertex and no
/// swap conflict (a swap next to a vertex conflict may go uncounted, but that vertex conflict is
/// counted).
pub fn count_conflicts_stepwise(sel: &RouteSelection, genome: &[Choice]) -> u64 {
    // Each robot's route and delay, looked up once: where robot i stands at t.
    // (route, delay, arrival): before `delay` the robot is on the route's first vertex, from
    // `arrival` on on its last.
    let tracks: Vec<(&[VertexId], usize, usize)> = genome
        .iter()
        .enumerate()
        .map(|(i, &c)| {
            let r = sel.route(i, c);
            (r, c.delay as usize, c.delay as usize + r.len() - 1)
        })
        .collect();
    let at = |i: usize, t: usize| {
        let (r, d, a) = tracks[i];
        if t <= d {
            r[0]
        } else if t >= a {
            r[r.len() - 1]
        } else {
            r[t - d]
        }
    };
    let horizon = tracks.iter().map(|&(_, _, a)| a).max().unwrap_or(0);
    let v = sel.num_vertices;
    let mut guard = sel.scratch.borrow_mut();
    let occ = &mut *guard;
    if occ.cells.len() != 2 * v {
        let empty = OccupiedAt {
            stamp: u64::MAX,
            who: 0,
            count: 0,
        };
        occ.cells = vec![empty; 2 * v];
    }
    let base = occ.base;
    occ.base += horizon as u64 + 2;
    let mut conflicts = 0u64;
    for t in 0..=horizon {
        let stamp = base + t as u64;
        let cur = (t & 1) * v;
        let prev = v - cur;
        for i in 0..tracks.len() {
            let p = at(i, t) as usize;
            let cell = &mut occ.cells[cur + p];
            if cell.stamp == stamp {
                conflicts += u64::from(cell.count);
                cell.count += 1;
            } else {
                *cell = OccupiedAt {
                    stamp,
                    who: i as u32,
                    count: 1,
                };
            }
            let before = occ.cells[prev + p];
            if t > 0 && before.stamp == stamp - 1 {
                let u = at(i, t - 1);
                let j = before.who as usize;
                if u as usize != p && j > i && at(j, t) == u {
                    conflicts += 1;
                }
            }
        }
    }
    conflicts
}

impl Problem for RouteSelection<'_> {
    type Genome = Vec<Choice>;

    fn num_objectives(&self) -> usize {
        self.objectives.count()
    }

    fn evaluate(&self, genome: &Vec<Choice>) -> Vec<f64> {
        if let Some(f) = self.memo.borrow().get(genome) {
            return f.clone();
        }
        let conflicts = count_conflicts(self, genome) as f64;
        let (sum, makespan) = self.sum_and_makespan(genome);
        let f = match self.objectives {
            Objectives::ConflictsAndSum => vec![conflicts, sum as f64],
            Objectives::ConflictsSumAndMakespan => vec![conflicts, sum as f64, makespan as f64],
        };
        let mut memo = self.memo.borrow_mut();
        if memo.len() >= MEMO_LIMIT {
            memo.clear();
        }
        memo.insert(genome.clone(), f.clone());
        f
    }

    fn random_genome(&self, rng: &mut ChaCha8Rng) -> Vec<Choice> {
        self.routes
            .iter()
            .map(|r| Choice {
                route: rng.random_range(0..r.len() as u32),
                delay: rng.random_range(0..=self.max_delay),
            })
            .collect()
    }

    /// Uniform crossover: with probability `crossover_probability`, each robot's pair is swapped
    /// between the children with probability 1/2.
    fn crossover(
        &self,
        a: &Vec<Choice>,
        b: &Vec<Choice>,
        rng: &mut ChaCha8Rng,
    ) -> (Vec<Choice>, Vec<Choice>) {
        let (mut c1, mut c2) = (a.clone(), b.clone());
        if rng.random::<f64>() < self.crossover_probability {
            for (x, y) in c1.iter_mut().zip(c2.iter_mut()) {
                if rng.random::<bool>() {
                    std::mem::swap(x, y);
                }
            }
        }
        (c1, c2)
    }

    /// Reset mutation: each robot's gene (route index and delay) is redrawn with probability
    /// `mutation_rate`.
    fn mutate(&self, genome: &mut Vec<Choice>, rng: &mut ChaCha8Rng) {
        for (i, c) in genome.iter_mut().enumerate() {
            if rng.random::<f64>() < self.mutation_rate {
                c.route = rng.random_range(0..self.routes[i].len() as u32);
                c.delay = rng.random_range(0..=self.max_delay);
            }
        }
    }
}

/// Step 5: the collision-free member of `front` with least sum of costs (ties: least makespan, then
/// the earlier member).
pub fn select_answer<'g>(
    sel: &RouteSelection,
    front: &[&'g Individual<Vec<Choice>>],
) -> Option<&'g Individual<Vec<Choice>>> {
    front
        .iter()
        .copied()
        .filter(|ind| ind.objectives[0] == 0.0)
        .min_by_key(|ind| sel.sum_and_makespan(&ind.genome))
}

impl Planner<MapfProblem> for Nsga3Planner {
    fn name(&self) -> &str {
        NAME
    }

    fn plan(&self, problem: &MapfProblem, opts: &Ctx) -> Result<Plan, Unsolved> {
        let (g, inst) = (problem.graph(), problem.instance());
        let deadline: Deadline = opts.deadline;
        if deadline.expired() {
            return Err(Unsolved::TimeLimit);
        }
        let n = inst.num_agents();
        if n == 0 {
            return Ok(Plan::default());
        }
        let mut rng = ChaCha8Rng::seed_from_u64(opts.seed);
        opts.report(mrpp_core::Progress {
            stage: "NSGA-III routes",
            done: 0,
            total: n as u64,
            note: format!("pre-generating routes for {n} robots"),
        });
        let mut routes = Vec::with_capacity(n);
        let mut goal_cells = vec![false; g.num_vertices()];
        if self.avoid_other_goals {
            for &v in &inst.goals {
                goal_cells[v as usize] = true;
            }
        }
        for i in 0..n {
            if deadline.expired() {
                return Err(Unsolved::TimeLimit);
            }
            let r = pregenerate_routes(
                g,
                inst.starts[i],
                inst.goals[i],
                &goal_cells,
                self,
                &mut rng,
                deadline,
            )?
            .ok_or_else(|| {
                Unsolved::GaveUp(format!(
                    "agent {i} cannot reach its goal {} from {} (not connected)",
                    g.label(inst.goals[i]),
                    g.label(inst.starts[i])
                ))
            })?;
            routes.push(r);
        }
        let problem = RouteSelection::new(&routes, g.num_vertices(), self);
        let mut throttle = mrpp_core::Throttle::new();
        let total = self.generations as u64;
        let mut report = |g: &mrpp_evo::nsga3::Generation<'_, _>| {
            throttle.report(opts, || mrpp_core::Progress {
                stage: "NSGA-III generation",
                done: g.index as u64,
                total,
                note: String::new(),
            });
        };
        let outcome = self
            .engine()
            .run(&problem, &mut rng, deadline, Some(&mut report));
        let front = outcome.first_front();
        match select_answer(&problem, &front) {
            Some(best) => Ok(Plan::new(problem.paths(&best.genome))),
            None if outcome.interrupted => Err(Unsolved::TimeLimit),
            None => Err(Unsolved::GaveUp(
                "no collision-free solution in the final front".into(),
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::GridMap;
    use mrpp_core::mapf::plan::first_conflict;
    use mrpp_core::mapf::search::distance::bfs_distances;
    use mrpp_core::solve;
    use mrpp_core::{Instance, Problem as _, Rules};
    use std::path::{Path, PathBuf};

    fn data() -> PathBuf {
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/hstar-paper")
    }

    fn small() -> (GridMap, Instance) {
        let m = GridMap::parse(
            "#########\n#       #\n# ## ## #\n#       #\n# ## ## #\n#       #\n#########",
            Path::new("m.txt"),
        )
        .unwrap()
        .0;
        let inst = crate::scen::parse_agents(
            "1,1;7,5\n7,5;1,1\n1,5;7,1\n7,1;1,5\n4,1;4,5\n4,5;4,1",
            Path::new("r.txt"),
            &m,
            None,
        )
        .unwrap();
        (m, inst)
    }

    #[test]
    fn routes_are_simple_bounded_and_start_with_the_shortest() {
        let (m, inst) = small();
        let g = m.graph();
        let p = Nsga3Planner::default();
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let routes = pregenerate_routes(
            g,
            inst.starts[0],
            inst.goals[0],
            &[],
            &p,
            &mut rng,
            Deadline::none(),
        )
        .unwrap()
        .unwrap();
        assert!(routes.len() > 1 && routes.len() <= p.routes_per_robot);
        let d = bfs_distances(g, inst.goals[0])[inst.starts[0] as usize] as usize;
        assert_eq!(routes[0].len(), d + 1);
        for (k, r) in routes.iter().enumerate() {
            assert_eq!(r[0], inst.starts[0]);
            assert_eq!(*r.last().unwrap(), inst.goals[0]);
            assert!(r.windows(2).all(|w| g.has_edge(w[0], w[1])));
            let mut cells = r.clone();
            cells.sort_unstable();
            cells.dedup();
            assert_eq!(cells.len(), r.len(), "route {k} repeats a cell");
            assert!(r.len() - 1 <= 2 * d + 10);
            assert!(!routes[..k].contains(r));
        }
        // A marked cell on the shortest route: a candidate keeps off it, most detours too.
        let mut avoid = vec![false; g.num_vertices()];
        let marked = routes[0][2];
        avoid[marked as usize] = true;
        let kept = pregenerate_routes(
            g,
            inst.starts[0],
            inst.goals[0],
            &avoid,
            &p,
            &mut rng,
            Deadline::none(),
        )
        .unwrap()
        .unwrap();
        assert_eq!(kept[0], routes[0]);
        let off = kept.iter().filter(|r| !r.contains(&marked)).count();
        assert!(off * 2 > kept.len(), "{off} of {} keep off", kept.len());
    }

    #[test]
    fn conflict_count_by_hand() {
        // Plus graph: centre 0, arms W=1 E=2 N=3 S=4.
        let at = |delays: &[u32]| -> Vec<Choice> {
            delays
                .iter()
                .map(|&d| Choice { route: 0, delay: d })
                .collect()
        };
        let p = Nsga3Planner::default();
        // Three robots on the centre at t = 1: three pairs.
        let routes = vec![
            vec![vec![1, 0, 2]],
            vec![vec![4, 0, 3]],
            vec![vec![3, 0, 4]],
        ];
        let sel = RouteSelection::new(&routes, 5, &p);
        assert_eq!(count_conflicts(&sel, &at(&[0, 0, 0])), 3);
        // Robot 0 waits on 1, then moves 1 -> 0 while robot 1 moves 0 -> 1: one swap.
        let routes = vec![vec![vec![1, 0, 2]], vec![vec![2, 0, 1]]];
        let sel = RouteSelection::new(&routes, 5, &p);
        assert_eq!(count_conflicts(&sel, &at(&[1, 0])), 1);
        // Robot 1 parks on 3 at t = 2; robot 0 passes 3 at t = 4: `stay` makes it a conflict.
        let routes = vec![vec![vec![1, 0, 3, 0, 2]], vec![vec![4, 0, 3]]];
        let sel = RouteSelection::new(&routes, 5, &p);
        assert_eq!(count_conflicts(&sel, &at(&[2, 0])), 1);
        assert_eq!(sel.sum_and_makespan(&at(&[2, 0])), (6 + 2, 6));
    }

    #[test]
    fn pair_table_leaves_out_the_swaps_the_stepwise_count_leaves_out() {
        // Robot 0 swaps with robot 2 between t = 1 and t = 2 while robot 1 stands on robot 2's
        // vertex at t = 1: the stepwise count finds robot 1 first on that vertex and counts only
        // the vertex conflict.
        let routes = vec![
            vec![vec![4, 3, 2, 10]],
            vec![vec![5, 2, 12]],
            vec![vec![1, 2, 3, 11]],
        ];
        let sel = RouteSelection::new(&routes, 13, &Nsga3Planner::default());
        assert!(sel.pairs.is_some());
        let genome = vec![Choice { route: 0, delay: 0 }; 3];
        assert_eq!(count_conflicts_stepwise(&sel, &genome), 1);
        assert_eq!(count_conflicts(&sel, &genome), 1);
        // Without robot 1 the swap counts.
        let two = vec![routes[0].clone(), routes[2].clone()];
        let sel = RouteSelection::new(&two, 13, &Nsga3Planner::default());
        assert!(sel.pairs.is_some());
        assert_eq!(count_conflicts(&sel, &genome[..2]), 1);
    }

    #[test]
    fn pair_table_counts_like_the_stepwise_count() {
        let dir = data().join("scenario2");
        let m = GridMap::load(&dir.join("scenery_4rooms_B.txt")).unwrap();
        let inst = crate::scen::load_agents(&dir.join("6robots-per-room.txt"), &m, None).unwrap();
        let g = m.graph();
        let p = Nsga3Planner::default();
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let mut goal_cells = vec![false; g.num_vertices()];
        for &v in &inst.goals {
            goal_cells[v as usize] = true;
        }
        let routes: Vec<_> = (0..inst.num_agents())
            .map(|i| {
                let (s, t) = (inst.starts[i], inst.goals[i]);
                pregenerate_routes(g, s, t, &goal_cells, &p, &mut rng, Deadline::none())
                    .unwrap()
                    .unwrap()
            })
            .collect();
        let (mut counted, mut fewest, mut most) = (0, u64::MAX, 0);
        for k in 0..3000 {
            // All 24 robots, or a random few of them (so that conflict-free genomes occur too).
            let keep: Vec<usize> = (0..inst.num_agents())
                .filter(|_| k % 2 == 0 || rng.random::<f64>() < 0.2)
                .collect();
            let sub_routes: Vec<_> = keep.iter().map(|&i| routes[i].clone()).collect();
            let sel = RouteSelection::new(&sub_routes, g.num_vertices(), &p);
            let Some(table) = sel.pairs.as_ref() else {
                continue;
            };
            let genome = sel.random_genome(&mut rng);
            let stepwise = count_conflicts_stepwise(&sel, &genome);
            if let Some(c) = table.borrow_mut().count(&genome) {
                assert_eq!(c, stepwise, "robots {keep:?}, genome {genome:?}");
                counted += 1;
                fewest = fewest.min(c);
                most = most.max(c);
            }
        }
        assert!(
            counted > 2500 && fewest == 0 && most > 20,
            "{counted} counted, {fewest} to {most} conflicts"
        );
    }

    #[test]
    fn conflict_count_is_zero_exactly_when_the_validator_agrees() {
        let (m, inst) = small();
        let g = m.graph();
        let p = Nsga3Planner {
            max_delay: 4,
            ..Nsga3Planner::default()
        };
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let routes: Vec<_> = (0..inst.num_agents())
            .map(|i| {
                pregenerate_routes(
                    g,
                    inst.starts[i],
                    inst.goals[i],
                    &[],
                    &p,
                    &mut rng,
                    Deadline::none(),
                )
                .unwrap()
                .unwrap()
            })
            .collect();
        let sel = RouteSelection::new(&routes, g.num_vertices(), &p);
        let mut free = 0;
        for _ in 0..3000 {
            // Random subsets of robots, so that conflict-free genomes occur too.
            let keep: Vec<usize> = (0..inst.num_agents())
                .filter(|_| rng.random::<f64>() < 0.4)
                .collect();
            let sub_routes: Vec<_> = keep.iter().map(|&i| routes[i].clone()).collect();
            let sub = RouteSelection::new(&sub_routes, g.num_vertices(), &p);
            let genome = sub.random_genome(&mut rng);
            let c = count_conflicts(&sub, &genome);
            let valid = first_conflict(&sub.paths(&genome), g.num_vertices(), true).is_none();
            assert_eq!(
                c == 0,
                valid,
                "robots {keep:?}, genome {genome:?}: count {c}"
            );
            free += valid as usize;
        }
        assert!(free > 100, "only {free} conflict-free samples");
        assert_eq!(sel.num_objectives(), 2);
    }

    fn run(p: &Nsga3Planner, m: &GridMap, inst: &Instance, seed: u64) -> Result<Plan, Unsolved> {
        let opts = Ctx {
            seed,
            ..Ctx::default()
        };
        let plan = p.plan(&MapfProblem::on(m.graph(), inst, Rules::default()), &opts)?;
        MapfProblem::on(m.graph(), inst, Rules::default())
            .validate(&plan)
            .unwrap_or_else(|v| panic!("invalid plan: {}", v));
        Ok(plan)
    }

    #[test]
    fn small_grid_is_solved_and_deterministic() {
        let (m, inst) = small();
        let p = Nsga3Planner::default();
        let a = run(&p, &m, &inst, 5).unwrap();
        let b = run(&p, &m, &inst, 5).unwrap();
        assert_eq!(a, b);
        let three = Nsga3Planner {
            objectives: Objectives::ConflictsSumAndMakespan,
            ..Nsga3Planner::default()
        };
        run(&three, &m, &inst, 5).unwrap();
        assert_eq!(p.name(), "nsga3");
    }

    /// Issue 14, kind 4: a robot on its goal in a corridor must step into the pocket beside it
    /// to let another pass. Every seed solves it (before the step-aside routes, none did).
    #[test]
    fn a_robot_on_its_goal_steps_aside_to_let_another_pass() {
        let (m, _) = GridMap::parse(
            "#######\n#.....#\n###.###\n#######\n",
            Path::new("pocket.txt"),
        )
        .unwrap();
        let cell = |x, y| m.vertex_at(x, y).unwrap();
        let inst =
            Instance::new(vec![cell(1, 1), cell(3, 1)], vec![cell(5, 1), cell(3, 1)]).unwrap();
        let p = Nsga3Planner::default();
        for seed in 0..10 {
            let plan = run(&p, &m, &inst, seed).unwrap_or_else(|e| panic!("seed {seed}: {e}"));
            assert!(
                plan.paths[1].contains(&cell(3, 2)),
                "robot 1 steps into the pocket"
            );
        }
        let routes = pregenerate_routes(
            m.graph(),
            cell(3, 1),
            cell(3, 1),
            &[],
            &p,
            &mut ChaCha8Rng::seed_from_u64(0),
            Deadline::none(),
        )
        .unwrap()
        .unwrap();
        assert_eq!(routes[0], vec![cell(3, 1)]);
        assert!(routes.contains(&vec![cell(3, 1), cell(3, 2), cell(3, 2), cell(3, 1)]));
    }

    #[test]
    fn paper_scenario1_six_robots_is_solved() {
        let m = GridMap::load(&data().join("scenario1/scenery.txt")).unwrap();
        let inst =
            crate::scen::load_agents(&data().join("scenario1/6coordinates.txt"), &m, None).unwrap();
        let p = Nsga3Planner::default();
        let plan = run(&p, &m, &inst, 1).unwrap();
        let metrics = MapfProblem::on(m.graph(), &inst, Rules::default())
            .validate(&plan)
            .unwrap();
        // The plan cannot beat the sum of shortest distances.
        let lower: u64 = (0..6)
            .map(|i| bfs_distances(m.graph(), inst.goals[i])[inst.starts[i] as usize] as u64)
            .sum();
        assert!(metrics.sum_of_costs >= lower);
        assert!(
            solve(
                &p,
                &MapfProblem::on(m.graph(), &inst, Rules::default()),
                &Ctx::default()
            )
            .is_ok()
        );
    }

    #[test]
    fn deadline_and_impossible_instances() {
        let (m, inst) = small();
        let expired = Ctx::new(0, Deadline::after(std::time::Duration::ZERO));
        assert_eq!(
            Nsga3Planner::default().plan(
                &MapfProblem::on(m.graph(), &inst, Rules::default()),
                &expired
            ),
            Err(Unsolved::TimeLimit)
        );
        // Two robots swap ends of a dead-end corridor: no route/delay combination avoids a swap.
        let c = GridMap::parse("#####\n#   #\n#####", Path::new("c.txt"))
            .unwrap()
            .0;
        let swap =
            crate::scen::parse_agents("1,1;3,1\n3,1;1,1", Path::new("r.txt"), &c, None).unwrap();
        assert_eq!(
            Nsga3Planner::default().plan(
                &MapfProblem::on(c.graph(), &swap, Rules::default()),
                &Ctx::default()
            ),
            Err(Unsolved::GaveUp(
                "no collision-free solution in the final front".into()
            ))
        );
    }
}
