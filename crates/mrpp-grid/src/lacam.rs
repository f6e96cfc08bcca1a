//! LaCAM: lazy constraints addition search for MAPF (K. Okumura, "LaCAM: search-based algorithm
//! for quick multi-agent pathfinding", AAAI 2023), baselines §7, with [`crate::pibt`] as its
//! configuration generator.
//!
//! A depth-first search over configurations (one vertex per agent). Each configuration node keeps
//! an agent order (farthest from its goal first, ties by id) and a queue of low-level constraint
//! nodes, each fixing the next vertices of the first `d` agents of that order. Taking a constraint
//! node from the top configuration expands its children (the next agent in the order, at each of
//! its neighbours and its own vertex, in a seeded random order) and asks PIBT for a successor
//! configuration that obeys the constraint; a successor seen before is pushed again instead of
//! being created. A configuration whose constraint queue runs dry leaves the stack. LaCAM is
//! complete: on a solvable instance it finds a plan (given time), and on an unsolvable one it
//! reports so once every configuration is exhausted. This is LaCAM without the anytime
//! refinement of LaCAM* (still to come); the first plan it finds is returned.

use std::collections::VecDeque;

use rand::SeedableRng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;
use rustc_hash::FxHashMap;

use crate::pibt::{NIL, Step};
use mrpp_core::mapf::search::distance::goal_distance_tables;
use mrpp_core::{Ctx, MapfProblem, Plan, Planner, PlannerEntry, Unsolved, VertexId};

/// Registry name.
pub const NAME: &str = "lacam";

/// LaCAM in the planner registry.
pub const ENTRY: PlannerEntry<MapfProblem> = PlannerEntry {
    name: NAME,
    about: "LaCAM: lazy constraints addition search with PIBT as configuration generator (Okumura, AAAI 2023); first plan",
    params: &[],
    build: |_| Ok(Box::new(Lacam)),
};

/// The LaCAM planner.
#[derive(Debug, Clone, Copy, Default)]
pub struct Lacam;

/// A low-level node: the next vertices of the first agents of the configuration's order.
struct Constraint {
    who: Vec<usize>,
    at: Vec<VertexId>,
}

/// A high-level node.
struct Node {
    config: Vec<VertexId>,
    parent: Option<usize>,
    order: Vec<usize>,
    tree: VecDeque<Constraint>,
}

impl Planner<MapfProblem> for Lacam {
    fn name(&self) -> &str {
        NAME
    }

    fn plan(&self, problem: &MapfProblem, ctx: &Ctx) -> Result<Plan, Unsolved> {
        let (g, inst) = (problem.graph(), problem.instance());
        let n = inst.num_agents();
        let dist = goal_distance_tables(g, &inst.goals);
        if let Some(i) = (0..n).find(|&i| dist[i][inst.starts[i] as usize] == u32::MAX) {
            return Err(Unsolved::GaveUp(format!("agent {i} cannot reach its goal")));
        }
        let mut rng = ChaCha8Rng::seed_from_u64(ctx.seed);
        let order_of = |config: &[VertexId]| {
            let mut order: Vec<usize> = (0..n).collect();
            order.sort_by(|&a, &b| {
                dist[b][config[b] as usize]
                    .cmp(&dist[a][config[a] as usize])
                    .then(a.cmp(&b))
            });
            order
        };
        let root = Node {
            config: inst.starts.clone(),
            parent: None,
            order: order_of(&inst.starts),
            tree: VecDeque::from([Constraint {
                who: vec![],
                at: vec![],
            }]),
        };
        let mut nodes = vec![root];
        let mut explored: FxHashMap<Vec<VertexId>, usize> = FxHashMap::default();
        explored.insert(inst.starts.clone(), 0);
        let mut open = vec![0usize];
        let mut occupied_now = vec![NIL; g.num_vertices()];
        let mut steps = 0u64;
        while let Some(&top) = open.last() {
            steps += 1;
            if steps.is_multiple_of(64) && ctx.deadline.expired() {
                return Err(Unsolved::TimeLimit);
            }
            if nodes[top].config == inst.goals {
                return Ok(extract(&nodes, top, n));
            }
            let Some(c) = nodes[top].tree.pop_front() else {
                open.pop();
                continue;
            };
            // Low-level expansion: the next agent of the order, at each of its candidates.
            if c.who.len() < n {
                let i = nodes[top].order[c.who.len()];
                let v = nodes[top].config[i];
                let mut cands: Vec<VertexId> = std::iter::once(v)
                    .chain(g.neighbors(v).iter().copied())
                    .collect();
                cands.shuffle(&mut rng);
                for u in cands {
                    let mut who = c.who.clone();
                    let mut at = c.at.clone();
                    who.push(i);
                    at.push(u);
                    nodes[top].tree.push_back(Constraint { who, at });
                }
            }
            let Some(next) = generate(problem, &dist, &nodes[top], &c, &mut occupied_now, &mut rng)
            else {
                continue;
            };
            if let Some(&seen) = explored.get(&next) {
                open.push(seen);
                continue;
            }
            let id = nodes.len();
            nodes.push(Node {
                order: order_of(&next),
                config: next.clone(),
                parent: Some(top),
                tree: VecDeque::from([Constraint {
                    who: vec![],
                    at: vec![],
                }]),
            });
            explored.insert(next, id);
            open.push(id);
        }
        Err(Unsolved::GaveUp(
            "LaCAM exhausted every reachable configuration: the instance has no solution".into(),
        ))
    }
}

/// PIBT's successor of `node`'s configuration under constraint `c`, or `None` when the
/// constraint itself breaks a rule (two agents on one vertex, a swap, a non-edge) or PIBT fails.
fn generate(
    problem: &MapfProblem,
    dist: &[Vec<u32>],
    node: &Node,
    c: &Constraint,
    occupied_now: &mut [usize],
    rng: &mut ChaCha8Rng,
) -> Option<Vec<VertexId>> {
    let n = node.config.len();
    for (i, &v) in node.config.iter().enumerate() {
        occupied_now[v as usize] = i;
    }
    let mut st = Step {
        problem,
        dist,
        now: &node.config,
        next: vec![VertexId::MAX; n],
        occupied_now,
        occupied_next: vec![NIL; problem.graph().num_vertices()],
        rng,
    };
    let mut ok = true;
    for (&i, &u) in c.who.iter().zip(&c.at) {
        let j = st.occupied_now[u as usize];
        if st.occupied_next[u as usize] != NIL
            || (j != NIL && j != i && st.next[j] == node.config[i])
        {
            ok = false;
            break;
        }
        st.next[i] = u;
        st.occupied_next[u as usize] = i;
    }
    if ok {
        for &i in &node.order {
            if st.next[i] == VertexId::MAX && !st.assign(i) {
                ok = false;
                break;
            }
        }
    }
    let next = st.next;
    for &v in &node.config {
        occupied_now[v as usize] = NIL;
    }
    // The generator may leave an agent where an earlier one is bound: only a conflict-free
    // successor counts.
    (ok && valid_step(problem, &node.config, &next)).then_some(next)
}

/// Whether moving from `from` to `to` keeps one agent per vertex, uses edges and swaps nothing.
fn valid_step(problem: &MapfProblem, from: &[VertexId], to: &[VertexId]) -> bool {
    let g = problem.graph();
    let mut seen = FxHashMap::default();
    for (i, (&a, &b)) in from.iter().zip(to).enumerate() {
        if b == VertexId::MAX || (a != b && !g.has_edge(a, b)) || seen.insert(b, i).is_some() {
            return false;
        }
    }
    let at: FxHashMap<VertexId, usize> = from.iter().enumerate().map(|(i, &v)| (v, i)).collect();
    from.iter()
        .zip(to)
        .enumerate()
        .all(|(i, (&a, &b))| a == b || at.get(&b).is_none_or(|&j| j == i || to[j] != a))
}

/// The plan from the root to node `goal`: one configuration per step.
fn extract(nodes: &[Node], goal: usize, n: usize) -> Plan {
    let mut configs = Vec::new();
    let mut k = Some(goal);
    while let Some(id) = k {
        configs.push(&nodes[id].config);
        k = nodes[id].parent;
    }
    configs.reverse();
    Plan {
        paths: (0..n)
            .map(|i| configs.iter().map(|c| c[i]).collect())
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrpp_core::mapf::graph::Graph;
    use mrpp_core::{Instance, Rules, solve};

    #[test]
    fn solves_a_corridor_swap_that_needs_a_side_pocket() {
        // 0-1-2-3 with a pocket 4 off vertex 1: two agents swap ends.
        let g = Graph::from_edges(5, &[(0, 1), (1, 2), (2, 3), (1, 4)]);
        let inst = Instance::new(vec![0, 3], vec![3, 0]).unwrap();
        let p = MapfProblem::on(&g, &inst, Rules::default());
        let s = solve(&Lacam, &p, &Ctx::default()).unwrap();
        assert!(s.metrics.makespan >= 4);
        // Without the pocket there is no solution, and LaCAM says so.
        let g = Graph::from_edges(4, &[(0, 1), (1, 2), (2, 3)]);
        let p = MapfProblem::on(&g, &inst, Rules::default());
        assert!(matches!(
            solve(&Lacam, &p, &Ctx::default()),
            Err(Unsolved::GaveUp(_))
        ));
    }
}
