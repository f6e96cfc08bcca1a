//! Multi-valued decision diagrams (Sharon et al., ICTS; used by ICBS, Boyarski et al. IJCAI 2015,
//! to classify conflicts): for an agent, a cost `c` and its constraints, the set of vertices at
//! each step `0..=c` that lie on some path of cost exactly `c` obeying the constraints. A conflict
//! at a step where an agent's MDD has a single vertex cannot be avoided by that agent without
//! raising its cost.

use mrpp_core::{Graph, VertexId};

use super::low_level::Constraints;

/// Level `t` holds the vertices the agent may occupy at step `t` on a cost-`c` path.
#[derive(Debug, Clone)]
pub struct Mdd {
    levels: Vec<Vec<VertexId>>,
}

impl Mdd {
    /// The MDD of cost `cost` from `start` to `goal` (`h` = distance to the goal).
    pub fn build(
        graph: &Graph,
        start: VertexId,
        goal: VertexId,
        cost: u32,
        h: &dyn Fn(VertexId) -> u32,
        constraints: &Constraints,
    ) -> Mdd {
        let c = cost as usize;
        let mut levels: Vec<Vec<VertexId>> = vec![vec![start]];
        for t in 1..=c {
            let mut next: Vec<VertexId> = Vec::new();
            for &u in &levels[t - 1] {
                for &v in std::iter::once(&u).chain(graph.neighbors(u)) {
                    let hv = h(v);
                    if hv != u32::MAX
                        && hv as usize <= c - t
                        && constraints.allows(u, v, t as u32)
                        && !next.contains(&v)
                    {
                        next.push(v);
                    }
                }
            }
            levels.push(next);
        }
        // Backwards: keep only vertices that lead to the goal at step c.
        levels[c].retain(|&v| v == goal);
        for t in (0..c).rev() {
            let (lo, hi) = levels.split_at_mut(t + 1);
            let below = &hi[0];
            lo[t].retain(|&u| {
                below.iter().any(|&v| {
                    (u == v || graph.has_edge(u, v)) && constraints.allows(u, v, t as u32 + 1)
                })
            });
        }
        Mdd { levels }
    }

    /// Whether the agent must be at one vertex at step `t` (steps past the cost: on its goal).
    pub fn singleton(&self, t: u32) -> bool {
        self.levels.get(t as usize).is_none_or(|l| l.len() == 1)
    }
}
