//! Task scheduling: which robot does which revealed task (`-p scheduler=greedy|hungarian`).
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
//!   `hungarian_max` of either it falls back to `greedy` for that step (the default 400 keeps a
//!   step at a few milliseconds here).

use pathfinding::kuhn_munkres::kuhn_munkres_min;
use pathfinding::matrix::Matrix;

use mrpp_core::Deadline;
use mrpp_core::mapf::search::distance::UNREACHABLE;

use crate::distances::{Distances, plus};
use crate::sim::Simulation;

/// Which scheduler (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SchedulerKind {
    #[default]
    Greedy,
    Hungarian,
}

/// The cost of an unreachable task: larger than any real one, small enough to add up.
const FAR: i64 = 1 << 40;

/// Proposes an assignment (robot -> task id) for the current state (module doc). Stops adding
/// robots when `deadline` passes (checked every 16 robots); robots left out keep their task.
pub fn schedule(
    kind: SchedulerKind,
    hungarian_max: usize,
    sim: &Simulation<'_>,
    dist: &mut Distances,
    deadline: Deadline,
) -> Vec<Option<usize>> {
    match kind {
        SchedulerKind::Greedy => greedy(sim, dist, deadline),
        SchedulerKind::Hungarian => hungarian(sim, dist, hungarian_max, deadline)
            .unwrap_or_else(|| greedy(sim, dist, deadline)),
    }
}

/// `d(e1, e2) + d(e2, e3) + ...` of a task's errands from its next one on.
fn errand_chain(sim: &Simulation<'_>, dist: &mut Distances, task: usize) -> u32 {
    let graph = sim.problem().map().graph();
    let t = &sim.tasks[task];
    t.errands[t.done..].windows(2).fold(0u32, |acc, w| {
        let d = dist.get(graph, w[0], w[1]);
        if acc == UNREACHABLE {
            acc
        } else {
            plus(d, acc)
        }
    })
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

fn greedy(sim: &Simulation<'_>, dist: &mut Distances, deadline: Deadline) -> Vec<Option<usize>> {
    let mut proposal = sim.assignment.clone();
    let mut free: Vec<usize> = sim
        .open
        .iter()
        .copied()
        .filter(|&k| sim.tasks[k].agent.is_none())
        .collect();
    let chains: Vec<u32> = free.iter().map(|&k| errand_chain(sim, dist, k)).collect();
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
    let chains: Vec<u32> = tasks.iter().map(|&k| errand_chain(sim, dist, k)).collect();
    let mut costs = Vec::with_capacity(agents.len() * tasks.len());
    for &i in &agents {
        if deadline.expired() {
            return None;
        }
        for (&k, &chain) in tasks.iter().zip(&chains) {
            costs.push(cost(sim, dist, i, k, chain));
        }
    }
    let matrix = Matrix::from_vec(agents.len(), tasks.len(), costs).expect("rows x columns");
    // kuhn_munkres needs no more rows than columns.
    let pairs: Vec<(usize, usize)> = if agents.len() <= tasks.len() {
        let (_, cols) = kuhn_munkres_min(&matrix);
        cols.into_iter().enumerate().collect()
    } else {
        let (_, rows) = kuhn_munkres_min(&matrix.transposed());
        rows.into_iter().enumerate().map(|(t, a)| (a, t)).collect()
    };
    for &i in &agents {
        proposal[i] = None;
    }
    for (a, t) in pairs {
        proposal[agents[a]] = Some(tasks[t]);
    }
    Some(proposal)
}
