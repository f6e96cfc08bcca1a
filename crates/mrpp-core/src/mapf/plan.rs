//! Plans, conflicts, validation and metrics: the one judge of every planner's output.
//!
//! A plan holds one vertex sequence per agent; index = time step, `path[0]` = start. A path may end
//! early: the agent then stays on its last vertex (and still occupies it). The rules are those of
//! MAPF convention: moves only along edges or waits, no vertex conflicts, no swap conflicts, following
//! allowed unless [`Rules::allow_following`] is off.

use serde::{Deserialize, Serialize};

use crate::mapf::graph::{Graph, VertexId};
use crate::mapf::instance::Instance;

/// One path per agent.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Plan {
    pub paths: Vec<Vec<VertexId>>,
}

impl Plan {
    /// Sum of loss (the objective of LaCAM\* and lacam3, Okumura, IJCAI 2023): per agent, its
    /// steps except the waits on its goal ([`path_loss`]), summed. `goals` holds one goal per
    /// path.
    pub fn sum_of_loss(&self, goals: &[VertexId]) -> u64 {
        self.paths
            .iter()
            .zip(goals)
            .map(|(p, &g)| path_loss(p, g))
            .sum()
    }
}

/// Agent `goal`'s loss on path `p`: its steps except those from `goal` to `goal` (its cost
/// minus the waits on its goal before its last arrival). A path that ends early stays on its
/// last vertex, which adds nothing.
pub fn path_loss(p: &[VertexId], goal: VertexId) -> u64 {
    p.windows(2)
        .filter(|w| !(w[0] == goal && w[1] == goal))
        .count() as u64
}

/// When an agent counts as done.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum GoalSemantics {
    /// The agent ends on its goal and stays there (still blocking it). MAPF's default.
    #[default]
    Stay,
    /// Solved once every agent has stood on its goal at least once (single-lane trees).
    Visit,
}

/// The rules a MAPF plan obeys, owned in this one place: when an agent counts as done, and
/// whether an agent may enter a vertex that another agent leaves in the same step. Grids use
/// [`Rules::default`] (`stay`, following allowed); single-lane trees use [`Rules::visit`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Rules {
    #[serde(rename = "goal")]
    pub semantics: GoalSemantics,
    /// Moving into a vertex another agent is leaving at the same step.
    #[serde(rename = "following")]
    pub allow_following: bool,
}

impl Default for Rules {
    fn default() -> Self {
        Rules {
            semantics: GoalSemantics::Stay,
            allow_following: true,
        }
    }
}

impl Rules {
    /// `visit` goal semantics (single-lane trees), following as given.
    pub fn visit(allow_following: bool) -> Self {
        Rules {
            semantics: GoalSemantics::Visit,
            allow_following,
        }
    }
}

/// Plan quality. Cost of an agent = the step at which it reaches its goal for the last time
/// (`stay`) or first time (`visit`), waits included.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Metrics {
    pub sum_of_costs: u64,
    pub makespan: u64,
    /// Moves along edges over the whole plan (waits excluded).
    pub sum_of_moves: u64,
}

/// A conflict between two agents `a < b`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Conflict {
    pub a: usize,
    pub b: usize,
    /// Time step at which the conflicting configuration is reached (for swaps and following:
    /// the step the agents arrive, i.e. the move happens between `t - 1` and `t`).
    pub t: usize,
    pub kind: ConflictKind,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConflictKind {
    /// Both on `v` at `t`.
    Vertex { v: VertexId },
    /// `a` moves `u -> v` while `b` moves `v -> u` between `t - 1` and `t`.
    Swap { u: VertexId, v: VertexId },
    /// One of the pair enters `v` that the other occupied at `t - 1` (only when following is forbidden).
    Following { v: VertexId },
}

/// The first rule a plan breaks.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Violation {
    AgentCount {
        plan: usize,
        instance: usize,
    },
    EmptyPath {
        agent: usize,
    },
    UnknownVertex {
        agent: usize,
        t: usize,
        v: VertexId,
    },
    WrongStart {
        agent: usize,
        expected: VertexId,
        found: VertexId,
    },
    NotAnEdge {
        agent: usize,
        t: usize,
        from: VertexId,
        to: VertexId,
    },
    Conflict(Conflict),
    GoalNotReached {
        agent: usize,
        goal: VertexId,
        last: VertexId,
    },
}

impl Violation {
    /// A one-line description in the graph's own terms (cells on grids).
    pub fn describe(&self, g: &Graph) -> String {
        match *self {
            Violation::AgentCount { plan, instance } => {
                format!("plan has {plan} agents but the instance has {instance}")
            }
            Violation::EmptyPath { agent } => format!("agent {agent} has an empty path"),
            Violation::UnknownVertex { agent, t, v } => {
                format!("agent {agent} at t={t} is on vertex {v}, which is not on the map")
            }
            Violation::WrongStart {
                agent,
                expected,
                found,
            } => format!(
                "agent {agent} starts at {} but its start is {}",
                g.label(found),
                g.label(expected)
            ),
            Violation::NotAnEdge { agent, t, from, to } => format!(
                "agent {agent} jumps from {} to {} between t={} and t={t} (not adjacent)",
                g.label(from),
                g.label(to),
                t - 1
            ),
            Violation::Conflict(c) => match c.kind {
                ConflictKind::Vertex { v } => {
                    format!(
                        "vertex conflict: agents {} and {} both at {} at t={}",
                        c.a,
                        c.b,
                        g.label(v),
                        c.t
                    )
                }
                ConflictKind::Swap { u, v } => format!(
                    "swap conflict: agents {} and {} exchange {} and {} between t={} and t={}",
                    c.a,
                    c.b,
                    g.label(u),
                    g.label(v),
                    c.t - 1,
                    c.t
                ),
                ConflictKind::Following { v } => format!(
                    "following conflict: agents {} and {} at {} between t={} and t={}",
                    c.a,
                    c.b,
                    g.label(v),
                    c.t - 1,
                    c.t
                ),
            },
            Violation::GoalNotReached { agent, goal, last } => format!(
                "agent {agent} does not reach its goal {} (it ends at {})",
                g.label(goal),
                g.label(last)
            ),
        }
    }
}

/// Position of a path at time `t` (the last vertex once the path has ended).
#[inline]
pub fn position(path: &[VertexId], t: usize) -> VertexId {
    path[t.min(path.len() - 1)]
}

/// The earliest conflict among `paths` (every path non-empty, vertices `< num_vertices`), scanning
/// time steps in order; at one step a swap/following conflict (arriving at `t`) is reported before a
/// vertex conflict at `t`, and lower agent ids first.
pub fn first_conflict(
    paths: &[Vec<VertexId>],
    num_vertices: usize,
    allow_following: bool,
) -> Option<Conflict> {
    first_conflict_from(paths, num_vertices, allow_following, 0)
}

/// [`first_conflict`] for paths known to have no conflict before time `from` (a vertex conflict
/// at a step `< from`, or a swap or following conflict arriving at one): the scan starts at
/// `from`, and the answer is the one [`first_conflict`] gives. H*'s collision elimination changes
/// two paths only after the conflict it clears, so it rescans from there.
pub fn first_conflict_from(
    paths: &[Vec<VertexId>],
    num_vertices: usize,
    allow_following: bool,
    from: usize,
) -> Option<Conflict> {
    let horizon = paths.iter().map(Vec::len).max().unwrap_or(0);
    const FREE: u32 = u32::MAX;
    let mut prev = vec![FREE; num_vertices];
    let mut cur = vec![FREE; num_vertices];
    if from > 0 {
        // The step before `from`, conflict-free: one agent per occupied vertex.
        for (i, p) in paths.iter().enumerate() {
            prev[position(p, from - 1) as usize] = i as u32;
        }
    }
    for t in from..horizon {
        for (i, p) in paths.iter().enumerate() {
            let v = position(p, t) as usize;
            if t > 0 {
                let u = position(p, t - 1);
                let w = prev[v];
                if w != FREE && w as usize != i {
                    let j = w as usize;
                    let other_now = position(&paths[j], t);
                    let (a, b) = (i.min(j), i.max(j));
                    if other_now == u && u as usize != v {
                        let (su, sv) = if a == i { (u, v as u32) } else { (v as u32, u) };
                        return Some(Conflict {
                            a,
                            b,
                            t,
                            kind: ConflictKind::Swap { u: su, v: sv },
                        });
                    }
                    if !allow_following && other_now as usize != v {
                        return Some(Conflict {
                            a,
                            b,
                            t,
                            kind: ConflictKind::Following { v: v as u32 },
                        });
                    }
                }
            }
        }
        for (i, p) in paths.iter().enumerate() {
            let v = position(p, t) as usize;
            if cur[v] != FREE {
                return Some(Conflict {
                    a: cur[v] as usize,
                    b: i,
                    t,
                    kind: ConflictKind::Vertex { v: v as u32 },
                });
            }
            cur[v] = i as u32;
        }
        for p in paths {
            if t > 0 {
                prev[position(p, t - 1) as usize] = FREE;
            }
        }
        std::mem::swap(&mut prev, &mut cur);
    }
    None
}

/// Whether two paths conflict at a step `>= from` (both non-empty): they share a vertex at a
/// step, or swap along an edge (following allowed). For two paths with no conflict before `from`
/// this is `first_conflict_from(&[p, q], _, true, from).is_some()`, without its tables.
pub fn pair_conflicts_from(p: &[VertexId], q: &[VertexId], from: usize) -> bool {
    let horizon = p.len().max(q.len());
    // A swap is `p: u -> v` while `q: v -> u` (with `u == v` it is a vertex conflict).
    (from..horizon).any(|t| {
        let (pv, qv) = (position(p, t), position(q, t));
        pv == qv || (t > 0 && pv == position(q, t - 1) && qv == position(p, t - 1))
    })
}

/// Cost of one path under `semantics`: last arrival (`stay`) or first arrival (`visit`);
/// `None` when the goal is not reached as required.
pub fn path_cost(path: &[VertexId], goal: VertexId, semantics: GoalSemantics) -> Option<usize> {
    match semantics {
        GoalSemantics::Stay => {
            if *path.last()? != goal {
                return None;
            }
            Some(path.iter().rposition(|&v| v != goal).map_or(0, |i| i + 1))
        }
        GoalSemantics::Visit => path.iter().position(|&v| v == goal),
    }
}

/// Number of moves along edges (waits excluded).
pub fn path_moves(path: &[VertexId]) -> usize {
    path.windows(2).filter(|w| w[0] != w[1]).count()
}

impl Plan {
    pub fn new(paths: Vec<Vec<VertexId>>) -> Self {
        Plan { paths }
    }

    /// Removes trailing repeats of the final vertex (they carry no information).
    pub fn trim(&mut self) {
        for p in &mut self.paths {
            while p.len() >= 2 && p[p.len() - 1] == p[p.len() - 2] {
                p.pop();
            }
        }
    }
}

/// The validator: judges `plan` under `opts`; on success returns its metrics. Callers go through
/// [`crate::contract::Problem::validate`] of [`crate::mapf::MapfProblem`] (so through
/// [`crate::contract::solve`] or a validate command), never directly.
pub fn judge(
    graph: &Graph,
    inst: &Instance,
    opts: Rules,
    plan: &Plan,
) -> Result<Metrics, Violation> {
    if plan.paths.len() != inst.num_agents() {
        return Err(Violation::AgentCount {
            plan: plan.paths.len(),
            instance: inst.num_agents(),
        });
    }
    let n = graph.num_vertices();
    for (agent, p) in plan.paths.iter().enumerate() {
        if p.is_empty() {
            return Err(Violation::EmptyPath { agent });
        }
        if let Some(t) = p.iter().position(|&v| v as usize >= n) {
            return Err(Violation::UnknownVertex { agent, t, v: p[t] });
        }
        if p[0] != inst.starts[agent] {
            return Err(Violation::WrongStart {
                agent,
                expected: inst.starts[agent],
                found: p[0],
            });
        }
        for (t, w) in p.windows(2).enumerate() {
            if w[0] != w[1] && !graph.has_edge(w[0], w[1]) {
                return Err(Violation::NotAnEdge {
                    agent,
                    t: t + 1,
                    from: w[0],
                    to: w[1],
                });
            }
        }
    }
    if let Some(c) = first_conflict(&plan.paths, n, opts.allow_following) {
        return Err(Violation::Conflict(c));
    }
    let mut m = Metrics {
        sum_of_costs: 0,
        makespan: 0,
        sum_of_moves: 0,
    };
    for (agent, p) in plan.paths.iter().enumerate() {
        let goal = inst.goals[agent];
        let cost = path_cost(p, goal, opts.semantics).ok_or(Violation::GoalNotReached {
            agent,
            goal,
            last: *p.last().expect("non-empty"),
        })? as u64;
        m.sum_of_costs += cost;
        m.makespan = m.makespan.max(cost);
        m.sum_of_moves += path_moves(p) as u64;
    }
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Plus graph: centre 0, arms W=1 E=2 N=3 S=4.
    fn plus() -> Graph {
        Graph::from_edges(5, &[(0, 1), (0, 2), (0, 3), (0, 4)])
    }

    #[test]
    fn plus_reference_plan_is_valid() {
        let g = plus();
        let inst = Instance::new(vec![1, 4], vec![2, 3]).unwrap();
        let plan = Plan::new(vec![vec![1, 0, 2], vec![4, 4, 0, 3]]);
        let m = judge(&g, &inst, Rules::default(), &plan).unwrap();
        assert_eq!(
            m,
            Metrics {
                sum_of_costs: 5,
                makespan: 3,
                sum_of_moves: 4
            }
        );
    }

    #[test]
    fn vertex_swap_following_and_goal_are_caught() {
        let g = plus();
        let inst = Instance::new(vec![1, 4], vec![2, 3]).unwrap();
        let opts = Rules::default();
        let v = judge(
            &g,
            &inst,
            opts,
            &Plan::new(vec![vec![1, 0, 2], vec![4, 0, 3]]),
        )
        .unwrap_err();
        assert_eq!(
            v,
            Violation::Conflict(Conflict {
                a: 0,
                b: 1,
                t: 1,
                kind: ConflictKind::Vertex { v: 0 }
            })
        );
        assert!(v.describe(&g).contains("both at #0 at t=1"));

        let inst2 = Instance::new(vec![1, 0], vec![0, 1]).unwrap();
        let v = judge(&g, &inst2, opts, &Plan::new(vec![vec![1, 0], vec![0, 1]])).unwrap_err();
        assert!(matches!(
            v,
            Violation::Conflict(Conflict {
                t: 1,
                kind: ConflictKind::Swap { u: 1, v: 0 },
                ..
            })
        ));

        // Following: agent 1 enters 0 as agent 0 leaves it.
        let inst3 = Instance::new(vec![0, 1], vec![2, 0]).unwrap();
        let follow = Plan::new(vec![vec![0, 2], vec![1, 0]]);
        assert!(judge(&g, &inst3, opts, &follow).is_ok());
        let strict = Rules {
            allow_following: false,
            ..opts
        };
        assert!(matches!(
            judge(&g, &inst3, strict, &follow),
            Err(Violation::Conflict(Conflict {
                kind: ConflictKind::Following { v: 0 },
                ..
            }))
        ));

        let v = judge(&g, &inst, opts, &Plan::new(vec![vec![1], vec![4, 4, 0, 3]])).unwrap_err();
        assert!(matches!(v, Violation::GoalNotReached { agent: 0, .. }));
        let v = judge(&g, &inst, opts, &Plan::new(vec![vec![1, 2], vec![4, 0, 3]])).unwrap_err();
        assert!(matches!(v, Violation::NotAnEdge { agent: 0, t: 1, .. }));
    }

    #[test]
    fn stay_agent_blocks_its_goal() {
        let g = plus();
        // Agent 0 parks on 0 at t=1; agent 1 passes through 0 at t=2.
        let inst = Instance::new(vec![1, 4], vec![0, 3]).unwrap();
        let v = judge(
            &g,
            &inst,
            Rules::default(),
            &Plan::new(vec![vec![1, 0], vec![4, 4, 0, 3]]),
        );
        assert!(matches!(v, Err(Violation::Conflict(Conflict { t: 2, .. }))));
    }

    #[test]
    fn costs_count_last_arrival_and_visit() {
        assert_eq!(path_cost(&[1, 0, 2, 0, 2], 2, GoalSemantics::Stay), Some(4));
        assert_eq!(
            path_cost(&[1, 0, 2, 0, 2], 2, GoalSemantics::Visit),
            Some(2)
        );
        assert_eq!(path_cost(&[2], 2, GoalSemantics::Stay), Some(0));
        assert_eq!(path_cost(&[2, 0], 2, GoalSemantics::Stay), None);
        assert_eq!(path_moves(&[1, 1, 0, 0, 2]), 2);
    }
}
