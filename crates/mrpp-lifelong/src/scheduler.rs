//! Task scheduling: which robot does which revealed task (`-p scheduler=greedy|hungarian|matching`).
//!
//! - `greedy`, the start kit's default scheduler (`default_planner/scheduler.cpp`, v2.1.2):
//!   every robot without a task, in index order (the kit's order is a hash set's), takes the free
//!   task with the smallest `d(robot, e1) + d(e1, e2) + ...` (breadth-first distances that ignore
//!   orientation; ties to the lower task id). A task once given is never moved.
//! - `hungarian`: a minimum-cost assignment (Kuhn-Munkres, H. W. Kuhn, "The Hungarian method for
//!   the assignment problem", Naval Research Logistics Quarterly 2, 1955; `pathfinding`'s
//!   `kuhn_munkres`) of the same cost over every robot that has not yet reached its task's first
//!   errand (free robots and robots still on their way, which the kit's rules let one re-assign)
//!   and every task not yet started. Re-planned at every step, so a robot freed near a task
//!   takes it from one still far away. It costs O(n^3) in the robots and tasks involved; above
//!   `hungarian_max` of either it falls back to `matching` for that step (the default 400 keeps a
//!   step at a few milliseconds here).
//! - `matching`: greedy matching over the same robots and tasks: all pairs in increasing cost
//!   (ties to the lower task, then robot, position), each taken when neither end is taken yet
//!   (no optimality guarantee, unlike `hungarian`, but O(pairs) memory, 2 bytes a pair, and
//!   time, so it scales to thousands of robots). Above
//!   [`REASSIGN_MAX_PAIRS`] pairs it matches only free robots with free tasks (robots on their way
//!   keep their task); when the step's scheduling time runs out while pairs are costed, the tasks
//!   costed so far (the first revealed) are matched. Compared with `greedy` on the kit's
//!   `sortation_large_2000` it raised the tasks finished in 300 steps by 11% (docs/lifelong.md).
//!
//! **Re-assignment margin** (`-p reassign_margin=M`, default 0). `hungarian` and `matching`
//! move a task from a robot on its way to another whenever that lowers the total cost by a
//! step; the robot then turns back, and under `MAPF_T` turning costs actions (on the kit's
//! `warehouse_large_5000` a quarter of all actions were turns by step 900, docs/performance.md).
//! With a margin `M`, a robot's own task costs `M` less for it, so a re-assignment must save
//! more than `M` steps (the League does not say; 0 keeps the plain minimum-cost rule).
//!
//! **Look-ahead** (`-p lookahead=L`, default 0 = off; the League does not say). `hungarian`
//! and `matching` assign only robots without a task or still on their way to one, so a free
//! robot may take a task beside which another robot is about to finish its own. With `L` > 0
//! every robot whose task is started and which will stand on its last errand within `L` steps
//! (by the distances, ignoring traffic) bids too, from that errand, its cost raised by the steps
//! it still needs; a task it wins is left free this step (the League gives a robot one task at a
//! time). It bids only for tasks left over beyond one per robot that can take one now, so no such
//! robot goes without, and a robot left without a task it can reach takes one a bidder won. In
//! the congestion-free reference over 1,000 steps ([`crate::bound`]) it changed little: `sortation_large_2000` 8,122 -> 8,182 at `L` = 25
//! (+0.7%), `paris_1_256_250` 1,033 -> 1,037, and 993 at `L` = 100 (docs/performance.md).
//!
//! **The cost** of giving task `k` to robot `r` is `d(r, e1) + w x (d(e1, e2) + d(e2, e3) + ...)`
//! from the task's next errand on, `w` the `chain_weight` (`-p chain_weight=W`, default 1: the
//! kit's cost). The errand chain is work the task needs whoever does it, so `w` says how much
//! the scheduler prefers short tasks over near ones. Where the League is silent mrpp keeps the
//! kit's 1; 0 (pickup distance only) finished more tasks on the kit's `random_32_32_20_100` over
//! 1,000 steps (2,683 against 2,519 with `lifelong-lns`), where the 150 open tasks are replaced
//! about 18 times and short tasks picked first leave long ones to clog the open set; on
//! `sortation_large_2000` and `brc202d_500`, where the open set is replaced 3 times or less, its
//! congestion-free reference is 7% and 11% lower (docs/performance.md).

use pathfinding::kuhn_munkres::kuhn_munkres_min;
use pathfinding::matrix::Matrix;

use mrpp_core::Deadline;
use mrpp_core::mapf::graph::VertexId;
use mrpp_core::mapf::search::distance::UNREACHABLE;

use crate::distances::{Distances, plus};
use crate::sim::Simulation;

/// Which scheduler (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SchedulerKind {
    #[default]
    Greedy,
    Hungarian,
    Matching,
}

/// The cost of an unreachable task: larger than any real one, small enough to add up.
const FAR: i64 = 1 << 40;

/// A scheduler and its options (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scheduler {
    pub kind: SchedulerKind,
    /// Above this many robots or tasks in a batch, `hungarian` falls back to `matching`.
    pub hungarian_max: usize,
    /// The weight `w` of a task's errand chain in its cost (module doc); 1 = the kit's.
    pub chain_weight: f64,
    /// Steps a re-assignment must save (module doc, "Re-assignment margin"): the cost of a
    /// robot's own task is lowered by this much when `hungarian` and `matching` re-assign; 0 =
    /// the plain minimum-cost rule.
    pub reassign_margin: u32,
    /// Look-ahead in steps (module doc, "Look-ahead"): robots that will finish their task within
    /// this many steps bid for open tasks from their last errand, and a task one of them wins is
    /// left free this step; 0 = off.
    pub lookahead: u32,
}

impl Scheduler {
    /// `kind` with the planners' defaults (`hungarian_max` 400, `chain_weight` 1).
    pub fn new(kind: SchedulerKind) -> Self {
        Scheduler {
            kind,
            hungarian_max: 400,
            chain_weight: 1.0,
            reassign_margin: 0,
            lookahead: 0,
        }
    }

    /// Proposes an assignment (robot -> task id) for the current state (module doc). Stops
    /// adding robots when `deadline` passes (checked every 16 robots); robots left out keep
    /// their task.
    pub fn propose(
        &self,
        sim: &Simulation<'_>,
        dist: &mut Distances,
        deadline: Deadline,
    ) -> Vec<Option<usize>> {
        let w = self.chain_weight;
        let m = self.reassign_margin;
        let l = self.lookahead;
        match self.kind {
            SchedulerKind::Greedy => greedy(sim, dist, w, deadline),
            SchedulerKind::Hungarian => hungarian(sim, dist, w, m, l, self.hungarian_max, deadline)
                .or_else(|| matching(sim, dist, w, m, l, deadline))
                .unwrap_or_else(|| greedy(sim, dist, w, deadline)),
            SchedulerKind::Matching => matching(sim, dist, w, m, l, deadline)
                .unwrap_or_else(|| greedy(sim, dist, w, deadline)),
        }
    }
}

/// Above this many (robot, task) pairs, [`matching`] leaves robots on their way to a task
/// alone and matches only robots without one (module doc).
pub const REASSIGN_MAX_PAIRS: usize = 1 << 23;

/// Robots whose task is started (they cannot be re-assigned) and that will stand on its last
/// errand within `lookahead` steps, as `(last errand, steps until it is done)`, soonest first
/// (ties to the lower robot), at most `max` (module doc, "Look-ahead").
fn finishing_soon(
    sim: &Simulation<'_>,
    dist: &mut Distances,
    lookahead: u32,
    max: usize,
) -> Vec<(VertexId, u32)> {
    if lookahead == 0 || max == 0 {
        return Vec::new();
    }
    let graph = sim.problem().map().graph();
    let mut soon: Vec<(u32, usize, VertexId)> = Vec::new();
    for (i, task) in sim.assignment.iter().enumerate() {
        let Some(k) = *task else { continue };
        let t = &sim.tasks[k];
        if t.done == 0 || t.done >= t.errands.len() {
            continue;
        }
        let mut left = dist.get(graph, sim.states[i].vertex, t.errands[t.done]);
        for e in t.errands[t.done..].windows(2) {
            if left > lookahead {
                break;
            }
            left = plus(dist.get(graph, e[0], e[1]), left);
        }
        if left <= lookahead {
            soon.push((left, i, *t.errands.last().expect("a task has errands")));
        }
    }
    soon.sort_unstable();
    soon.truncate(max);
    soon.into_iter().map(|(left, _, v)| (v, left)).collect()
}

/// Greedy matching (module doc); `None` when `deadline` passes first (checked every 64 tasks).
fn matching(
    sim: &Simulation<'_>,
    dist: &mut Distances,
    w: f64,
    margin: u32,
    lookahead: u32,
    deadline: Deadline,
) -> Option<Vec<Option<usize>>> {
    let graph = sim.problem().map().graph();
    let mut proposal = sim.assignment.clone();
    let movable = |k: usize| sim.tasks[k].done == 0;
    let candidates = |reassign: bool| {
        let agents: Vec<usize> = (0..proposal.len())
            .filter(|&i| proposal[i].is_none_or(|k| reassign && movable(k)))
            .collect();
        let tasks: Vec<usize> = sim
            .open
            .iter()
            .copied()
            .filter(|&k| {
                if reassign {
                    movable(k)
                } else {
                    sim.tasks[k].agent.is_none()
                }
            })
            .collect();
        (agents, tasks)
    };
    let (mut agents, mut tasks) = candidates(true);
    if agents.len() * tasks.len() > REASSIGN_MAX_PAIRS {
        (agents, tasks) = candidates(false);
    }
    if agents.is_empty() || tasks.is_empty() {
        return Some(proposal);
    }
    // Robots finishing soon bid too (rows after the real ones), no more of them than there are
    // tasks left over, so that every real robot can still be matched.
    let real = agents.len();
    // Within the pair cap too: the bidders add rows to the cost table.
    let room = (REASSIGN_MAX_PAIRS / tasks.len()).saturating_sub(real);
    let soon = finishing_soon(
        sim,
        dist,
        lookahead,
        tasks.len().saturating_sub(real).min(room),
    );
    // Every pair's cost, task-major, capped at u16::MAX - 1 (u16::MAX: unreachable). When
    // the deadline passes, the tasks costed so far (the first revealed) are matched.
    let na = real + soon.len();
    let cells: Vec<_> = agents
        .iter()
        .map(|&i| sim.states[i].vertex)
        .chain(soon.iter().map(|&(v, _)| v))
        .collect();
    let offset = |a: usize| if a < real { 0 } else { soon[a - real].1 };
    let mut costs: Vec<u16> = Vec::with_capacity(na * tasks.len());
    let mut count = vec![0u32; u16::MAX as usize + 1];
    let mut row = Vec::with_capacity(na);
    for (pos, &k) in tasks.iter().enumerate() {
        if pos % 16 == 15 && deadline.expired() {
            tasks.truncate(pos);
            break;
        }
        let chain = errand_chain(sim, dist, k, w);
        let t = &sim.tasks[k];
        dist.to(graph, t.errands[t.done], &cells, &mut row);
        for (a, &d) in row.iter().enumerate() {
            let d = plus(d, offset(a));
            let c = if d == UNREACHABLE || chain == UNREACHABLE {
                u16::MAX
            } else if a < real && proposal[agents[a]] == Some(k) {
                plus(d, chain)
                    .saturating_sub(margin)
                    .min(u32::from(u16::MAX) - 1) as u16
            } else {
                plus(d, chain).min(u32::from(u16::MAX) - 1) as u16
            };
            count[c as usize] += 1;
            costs.push(c);
        }
    }
    let nt = tasks.len();
    for &i in &agents {
        proposal[i] = None;
    }
    // Greedy matching: pairs in increasing cost (ties by task, then robot position), taken
    // when both ends are free. Pairs are sorted a cost window at a time, each window twice as
    // large as the last, so that only the cheap pairs are ever sorted.
    let mut agent_done = vec![false; na];
    // When the deadline cut the tasks, only as many bidders as tasks left over take part.
    let bidders = nt.saturating_sub(real).min(na - real);
    for done in &mut agent_done[real + bidders..] {
        *done = true;
    }
    let mut task_done = vec![false; nt];
    let mut won_by_bidder: Vec<usize> = Vec::new();
    let mut matched = 0;
    let mut window_pairs = 8 * na.max(nt);
    let mut lo = 0usize;
    let mut pairs: Vec<u64> = Vec::new();
    while matched < (real + bidders).min(nt) && lo < u16::MAX as usize {
        let mut hi = lo;
        let mut inside = 0usize;
        while hi < u16::MAX as usize && inside < window_pairs {
            inside += count[hi] as usize;
            hi += 1;
        }
        pairs.clear();
        for (t, chunk) in costs.chunks_exact(na).enumerate() {
            if task_done[t] {
                continue;
            }
            for (a, &c) in chunk.iter().enumerate() {
                if (lo..hi).contains(&(c as usize)) && !agent_done[a] {
                    pairs.push((u64::from(c) << 40) | ((t as u64) << 20) | a as u64);
                }
            }
        }
        pairs.sort_unstable();
        for &p in &pairs {
            let (t, a) = (((p >> 20) & 0xf_ffff) as usize, (p & 0xf_ffff) as usize);
            if agent_done[a] || task_done[t] {
                continue;
            }
            agent_done[a] = true;
            task_done[t] = true;
            if a < real {
                proposal[agents[a]] = Some(tasks[t]);
            } else {
                won_by_bidder.push(t);
            }
            matched += 1;
        }
        lo = hi;
        window_pairs *= 2;
    }
    // A robot that can take a task now never goes without one for a bidder: one left unmatched
    // (every task it can reach was won) takes the cheapest it can reach of the bidders' tasks.
    for a in (0..real).filter(|&a| !agent_done[a]) {
        let best = won_by_bidder
            .iter()
            .enumerate()
            .filter(|&(_, &t)| costs[t * na + a] != u16::MAX)
            .min_by_key(|&(_, &t)| (costs[t * na + a], t));
        if let Some((pos, &t)) = best {
            proposal[agents[a]] = Some(tasks[t]);
            won_by_bidder.swap_remove(pos);
        }
    }
    Some(proposal)
}

/// `w x (d(e1, e2) + d(e2, e3) + ...)` of a task's errands from its next one on, rounded
/// (`UNREACHABLE` when an errand cannot be reached from the one before).
fn errand_chain(sim: &Simulation<'_>, dist: &mut Distances, task: usize, w: f64) -> u32 {
    let graph = sim.problem().map().graph();
    let t = &sim.tasks[task];
    let chain = t.errands[t.done..].windows(2).fold(0u32, |acc, e| {
        let d = dist.get(graph, e[0], e[1]);
        if acc == UNREACHABLE {
            acc
        } else {
            plus(d, acc)
        }
    });
    if chain == UNREACHABLE || w == 1.0 {
        chain
    } else {
        // Below UNREACHABLE: chain < UNREACHABLE and w <= 10 (the parameter's range) keep it
        // a real cost that `plus` can add.
        (f64::from(chain) * w)
            .round()
            .min(f64::from(UNREACHABLE - 1)) as u32
    }
}

fn cost(sim: &Simulation<'_>, dist: &mut Distances, agent: usize, task: usize, chain: u32) -> i64 {
    let graph = sim.problem().map().graph();
    let t = &sim.tasks[task];
    let d = dist.get(graph, sim.states[agent].vertex, t.errands[t.done]);
    let total = if chain == UNREACHABLE {
        UNREACHABLE
    } else {
        plus(d, chain)
    };
    if total == UNREACHABLE {
        FAR
    } else {
        i64::from(total)
    }
}

fn greedy(
    sim: &Simulation<'_>,
    dist: &mut Distances,
    w: f64,
    deadline: Deadline,
) -> Vec<Option<usize>> {
    let mut proposal = sim.assignment.clone();
    let mut free: Vec<usize> = sim
        .open
        .iter()
        .copied()
        .filter(|&k| sim.tasks[k].agent.is_none())
        .collect();
    let chains: Vec<u32> = free
        .iter()
        .map(|&k| errand_chain(sim, dist, k, w))
        .collect();
    let mut chain_of: rustc_hash::FxHashMap<usize, u32> =
        free.iter().copied().zip(chains).collect();
    let idle: Vec<usize> = (0..proposal.len())
        .filter(|&i| proposal[i].is_none())
        .collect();
    for (n, i) in idle.into_iter().enumerate() {
        if free.is_empty() || (n % 16 == 15 && deadline.expired()) {
            break;
        }
        let best = free
            .iter()
            .enumerate()
            .min_by_key(|&(_, &k)| (cost(sim, dist, i, k, chain_of[&k]), k))
            .map(|(pos, _)| pos)
            .expect("free is not empty");
        let k = free.swap_remove(best);
        chain_of.remove(&k);
        proposal[i] = Some(k);
    }
    proposal
}

/// `None` when the batch is larger than `max` (the caller falls back to [`greedy`]).
fn hungarian(
    sim: &Simulation<'_>,
    dist: &mut Distances,
    w: f64,
    margin: u32,
    lookahead: u32,
    max: usize,
    deadline: Deadline,
) -> Option<Vec<Option<usize>>> {
    let mut proposal = sim.assignment.clone();
    let movable = |k: usize| sim.tasks[k].done == 0;
    let agents: Vec<usize> = (0..proposal.len())
        .filter(|&i| proposal[i].is_none_or(movable))
        .collect();
    if agents.len() > max {
        return None;
    }
    // Every task held by a movable robot is movable too (its first errand is not reached).
    let tasks: Vec<usize> = sim.open.iter().copied().filter(|&k| movable(k)).collect();
    if agents.is_empty() || tasks.is_empty() {
        return Some(proposal);
    }
    if tasks.len() > max {
        return None;
    }
    let chains: Vec<u32> = tasks
        .iter()
        .map(|&k| errand_chain(sim, dist, k, w))
        .collect();
    let mut costs = Vec::with_capacity(agents.len() * tasks.len());
    for &i in &agents {
        if deadline.expired() {
            return None;
        }
        for (&k, &chain) in tasks.iter().zip(&chains) {
            let c = cost(sim, dist, i, k, chain);
            costs.push(if proposal[i] == Some(k) && c < FAR {
                (c - i64::from(margin)).max(0)
            } else {
                c
            });
        }
    }
    // Robots finishing soon bid as extra rows (module doc, "Look-ahead"); no more than the tasks
    // left over, so every real robot still gets one, and within `max` rows.
    let real = agents.len();
    let spare = tasks.len().saturating_sub(real).min(max - real);
    let soon = finishing_soon(sim, dist, lookahead, spare);
    let graph = sim.problem().map().graph();
    for &(v, left) in &soon {
        for (&k, &chain) in tasks.iter().zip(&chains) {
            let t = &sim.tasks[k];
            let d = plus(plus(dist.get(graph, v, t.errands[t.done]), left), chain);
            costs.push(if chain == UNREACHABLE || d == UNREACHABLE {
                FAR
            } else {
                i64::from(d)
            });
        }
    }
    let rows = real + soon.len();
    let matrix = Matrix::from_vec(rows, tasks.len(), costs).expect("rows x columns");
    // kuhn_munkres needs no more rows than columns.
    let pairs: Vec<(usize, usize)> = if rows <= tasks.len() {
        let (_, cols) = kuhn_munkres_min(&matrix);
        cols.into_iter().enumerate().collect()
    } else {
        let (_, rows) = kuhn_munkres_min(&matrix.transposed());
        rows.into_iter().enumerate().map(|(t, a)| (a, t)).collect()
    };
    for &i in &agents {
        proposal[i] = None;
    }
    let mut assigned: Vec<Option<usize>> = vec![None; rows];
    for (a, t) in pairs {
        assigned[a] = Some(t);
    }
    // A robot that can take a task now never goes without a reachable one for a bidder: one
    // given an unreachable task (cost FAR) swaps with the bidder whose task it can reach at the
    // least cost.
    let cost_at = |a: usize, t: usize| matrix[(a, t)];
    for a in 0..real {
        if assigned[a].is_some_and(|t| cost_at(a, t) < FAR) {
            continue;
        }
        let swap = (real..rows)
            .filter_map(|b| assigned[b].map(|t| (b, t)))
            .filter(|&(_, t)| cost_at(a, t) < FAR)
            .min_by_key(|&(b, t)| (cost_at(a, t), b));
        if let Some((b, t)) = swap {
            assigned[b] = assigned[a];
            assigned[a] = Some(t);
        }
    }
    for (a, t) in assigned.into_iter().enumerate().take(real) {
        if let Some(t) = t {
            proposal[agents[a]] = Some(tasks[t]);
        }
    }
    Some(proposal)
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use mrpp_core::mapf::graph::VertexId;
    use mrpp_core::mapf::search::distance::bfs_distances;
    use mrpp_mapf::GridMap;
    use proptest::prelude::*;

    use super::*;
    use crate::model::ActionModel;
    use crate::problem::{LifelongProblem, test_problem};

    /// A 6 x 6 map with the blocked cells of `walls` (0..36), robots on `starts` and tasks of
    /// two errands each (vertex indices modulo the free cells), 1.5 tasks per robot revealed.
    fn problem(walls: &[usize], starts: &[usize], tasks: &[(usize, usize)]) -> LifelongProblem {
        let rows: Vec<Vec<bool>> = (0..6)
            .map(|r| (0..6).map(|c| !walls.contains(&(r * 6 + c))).collect())
            .collect();
        let map = GridMap::from_free_rows(&rows);
        let n = map.graph().num_vertices();
        let mut seen = Vec::new();
        let starts: Vec<VertexId> = starts
            .iter()
            .map(|&s| (s % n) as VertexId)
            .filter(|s| {
                let new = !seen.contains(s);
                seen.push(*s);
                new
            })
            .collect();
        let tasks = tasks
            .iter()
            .map(|&(a, b)| vec![(a % n) as VertexId, (b % n) as VertexId])
            .collect();
        test_problem(map, starts, tasks, 1.5, ActionModel::Mapf)
    }

    /// The rule written out plainly: every (robot, task) pair with its cost, sorted by (cost,
    /// task position, robot position), taken when both ends are free.
    fn reference(sim: &Simulation<'_>) -> Vec<Option<usize>> {
        let graph = sim.problem().map().graph();
        let tasks: Vec<usize> = sim.open.iter().copied().collect();
        let mut pairs = Vec::new();
        for (tp, &k) in tasks.iter().enumerate() {
            let e = &sim.tasks[k].errands;
            let to_first = bfs_distances(graph, e[0]);
            let chain = bfs_distances(graph, e[1])[e[0] as usize];
            for (a, s) in sim.states.iter().enumerate() {
                let d = to_first[s.vertex as usize];
                if d != UNREACHABLE && chain != UNREACHABLE {
                    pairs.push((d + chain, tp, a));
                }
            }
        }
        pairs.sort();
        let mut out = vec![None; sim.states.len()];
        let mut taken = vec![false; tasks.len()];
        for (_, tp, a) in pairs {
            if out[a].is_none() && !taken[tp] {
                out[a] = Some(tasks[tp]);
                taken[tp] = true;
            }
        }
        out
    }

    proptest! {
        /// At step 0 (every robot free, every revealed task free), `matching` is exactly the
        /// greedy matching of its module doc, on maps with walls (some pairs unreachable).
        #[test]
        fn matching_takes_the_cheapest_free_pairs_first(
            walls in proptest::collection::vec(0usize..36, 0..10),
            starts in proptest::collection::vec(0usize..64, 1..8),
            tasks in proptest::collection::vec((0usize..64, 0usize..64), 1..16),
        ) {
            let problem = problem(&walls, &starts, &tasks);
            let sim = Simulation::new(&problem);
            let mut dist = Distances::new(problem.map().graph().num_vertices(), 1 << 20);
            let far = Deadline::after(Duration::from_secs(60));
            let got = Scheduler::new(SchedulerKind::Matching).propose(&sim, &mut dist, far);
            prop_assert_eq!(got, reference(&sim));
        }
    }

    /// Greedy matching is not optimal: on a corridor with robot 0 at cell 0, robot 1 at cell 6
    /// and tasks starting at cells 5 and 10, it gives robot 1 the task at 5 (cost 1) and robot
    /// 0 the one at 10 (cost 10), total 11, where `hungarian` finds 5 + 4 = 9 (and `greedy` in
    /// robot order happens to find it too).
    #[test]
    fn matching_and_hungarian_differ_where_greedy_matching_is_short_sighted() {
        let rows = vec![vec![true; 11]];
        let map = GridMap::from_free_rows(&rows);
        let problem = test_problem(
            map,
            vec![0, 6],
            vec![vec![5, 5], vec![10, 10]],
            1.0,
            ActionModel::Mapf,
        );
        let sim = Simulation::new(&problem);
        let mut dist = Distances::new(11, 1 << 20);
        let far = Deadline::after(Duration::from_secs(60));
        let mut run = |kind| Scheduler::new(kind).propose(&sim, &mut dist, far);
        assert_eq!(run(SchedulerKind::Matching), vec![Some(1), Some(0)]);
        assert_eq!(run(SchedulerKind::Hungarian), vec![Some(0), Some(1)]);
        assert_eq!(run(SchedulerKind::Greedy), vec![Some(0), Some(1)]);
    }

    /// The chain weight trades near pickups for short tasks: on a corridor with the robot at
    /// cell 4, task 0 picks up at 5 and delivers at 15 (cost 1 + 10 w) and task 1 picks up at 0
    /// and delivers at 1 (cost 4 + w). Every scheduler takes task 1 at w = 1 (5 < 11) and task
    /// 0 at w = 0 (1 < 4).
    #[test]
    fn the_chain_weight_trades_near_pickups_for_short_tasks() {
        let rows = vec![vec![true; 16]];
        let map = GridMap::from_free_rows(&rows);
        let problem = test_problem(
            map,
            vec![4],
            vec![vec![5, 15], vec![0, 1]],
            2.0,
            ActionModel::Mapf,
        );
        let sim = Simulation::new(&problem);
        let mut dist = Distances::new(16, 1 << 20);
        let far = Deadline::after(Duration::from_secs(60));
        for kind in [
            SchedulerKind::Greedy,
            SchedulerKind::Hungarian,
            SchedulerKind::Matching,
        ] {
            for (w, task) in [(1.0, 1), (0.0, 0), (0.2, 0)] {
                let scheduler = Scheduler {
                    chain_weight: w,
                    ..Scheduler::new(kind)
                };
                assert_eq!(
                    scheduler.propose(&sim, &mut dist, far),
                    vec![Some(task)],
                    "{kind:?} at w = {w}"
                );
            }
        }
    }

    /// A re-assignment must save more than the margin: on a corridor, robot 0 at cell 0 holds
    /// the task at 12 and robot 1 at cell 9 the task at 5 (12 + 4 = 16 steps); swapping them
    /// costs 5 + 3 = 8. With a margin of 3 (own tasks 9 + 1 = 10) `hungarian` swaps, and greedy
    /// matching keeps them (it takes robot 1's own task first, at 1); with 10 (own tasks 2 + 0)
    /// both keep the tasks where they are; with 0 both swap.
    #[test]
    fn a_reassignment_must_save_more_than_the_margin() {
        let map = GridMap::from_free_rows(&[vec![true; 16]]);
        let problem = test_problem(
            map,
            vec![0, 9],
            vec![vec![5, 5], vec![12, 12]],
            1.0,
            ActionModel::Mapf,
        );
        let mut sim = Simulation::new(&problem);
        sim.apply_schedule(&[Some(1), Some(0)]);
        assert_eq!(sim.assignment, vec![Some(1), Some(0)]);
        let mut dist = Distances::new(16, 1 << 20);
        let far = Deadline::after(Duration::from_secs(60));
        let (swap, keep) = (vec![Some(0), Some(1)], vec![Some(1), Some(0)]);
        for (kind, margin, expected) in [
            (SchedulerKind::Hungarian, 0, &swap),
            (SchedulerKind::Hungarian, 3, &swap),
            (SchedulerKind::Hungarian, 10, &keep),
            (SchedulerKind::Matching, 0, &swap),
            (SchedulerKind::Matching, 3, &keep),
            (SchedulerKind::Matching, 10, &keep),
        ] {
            let scheduler = Scheduler {
                reassign_margin: margin,
                ..Scheduler::new(kind)
            };
            assert_eq!(
                &scheduler.propose(&sim, &mut dist, far),
                expected,
                "{kind:?} with a margin of {margin}"
            );
        }
    }

    /// Proposals on a one-row map (`row` of free cells) where robot 0 stands on the first
    /// errand of task 0 (done at once) and robot 1 is free, for each scheduler and look-ahead:
    /// `expect(lookahead)` is robot 1's task.
    fn check_lookahead(
        row: Vec<bool>,
        starts: Vec<VertexId>,
        tasks: Vec<Vec<VertexId>>,
        expect: impl Fn(u32) -> usize,
    ) {
        let map = GridMap::from_free_rows(&[row]);
        let n = map.graph().num_vertices();
        let problem = test_problem(map, starts, tasks, 1.5, ActionModel::Mapf);
        let mut sim = Simulation::new(&problem);
        sim.apply_schedule(&[Some(0), None]);
        sim.complete_and_reveal();
        assert_eq!(sim.tasks[0].done, 1, "robot 0 did its first errand");
        let mut dist = Distances::new(n, 1 << 20);
        let far = Deadline::after(Duration::from_secs(60));
        for kind in [SchedulerKind::Hungarian, SchedulerKind::Matching] {
            for lookahead in [0, 1, 10, 20] {
                let scheduler = Scheduler {
                    lookahead,
                    ..Scheduler::new(kind)
                };
                assert_eq!(
                    scheduler.propose(&sim, &mut dist, far),
                    vec![Some(0), Some(expect(lookahead))],
                    "{kind:?} with a look-ahead of {lookahead}"
                );
            }
        }
    }

    /// A bidder never takes the only task a free robot can reach: on a corridor cut in two by a
    /// wall, robot 0 is one step from ending its task on cell 4 and robot 1 at cell 6 is free;
    /// the open tasks are at 4 (1 step for robot 0's bid, 2 for robot 1) and beyond the wall.
    /// The bidder would win the task at 4 and leave robot 1 nothing it can reach; robot 1 gets
    /// it, at every look-ahead, with both schedulers.
    #[test]
    fn a_bidder_never_takes_the_only_task_a_free_robot_can_reach() {
        let mut row = vec![true; 16];
        row[7] = false;
        // Vertices 0..=6 are cells 0..=6, vertices 7..=14 cells 8..=15.
        check_lookahead(
            row,
            vec![3, 6],
            vec![vec![3, 4], vec![4, 4], vec![10, 10]],
            |_| 1,
        );
    }

    /// With a look-ahead, a task is left for a robot about to finish beside it: on a corridor,
    /// robot 0 stands on the first errand of its task (12, 13), one step from its end at 13;
    /// robot 1 at 8 is free, the open tasks are at 13 (5 steps from it) and 0 (8 steps). Alone,
    /// robot 1 takes the task at 13; with a look-ahead of 1 or more robot 0 bids for it from 13
    /// (1 + 0 steps) and robot 1 takes the one at 0 (8 + 1 < 5 + 14).
    #[test]
    fn a_lookahead_leaves_a_task_for_a_robot_about_to_finish_beside_it() {
        check_lookahead(
            vec![true; 16],
            vec![12, 8],
            vec![vec![12, 13], vec![13, 13], vec![0, 0]],
            |lookahead| if lookahead == 0 { 1 } else { 2 },
        );
    }
}
