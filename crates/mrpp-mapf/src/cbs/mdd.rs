//! Multi-valued decision diagrams (Sharon et al., ICTS; used by ICBS, Boyarski et al. IJCAI 2015,
//! to classify conflicts): for an agent, a cost `c` and its constraints, the set of vertices at
//! each step `0..=c` that lie on some path of cost exactly `c` obeying the constraints. A conflict
//! at a step where an agent's MDD has a single vertex cannot be avoided by that agent without
//! raising its cost.

use mrpp_core::{Graph, VertexId};

use super::low_level::Constraints;

/// Level `t` holds the vertices (sorted) the agent may occupy at step `t` on a cost-`c` path.
#[derive(Debug, Clone, PartialEq, Eq)]
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
        for l in &mut levels {
            l.sort_unstable();
            l.shrink_to_fit();
        }
        Mdd { levels }
    }

    /// Whether adding the negative constraint `c` (a `Vertex` or `Edge` one) could remove a
    /// vertex or edge from this MDD of an agent bound for `goal`: false means the MDD is the
    /// same with it. Past the MDD's cost the agent is on its goal. Conservative: an `Edge`
    /// constraint counts when both of its ends are at their levels.
    pub fn touched_by(&self, c: &super::low_level::Constraint, goal: VertexId) -> bool {
        use super::low_level::Constraint;
        let holds = |v: VertexId, t: u32| {
            self.levels
                .get(t as usize)
                .map_or(v == goal, |l| l.contains(&v))
        };
        match *c {
            Constraint::Vertex { v, t } => holds(v, t),
            Constraint::Edge { u, v, t } => t > 0 && holds(u, t - 1) && holds(v, t),
            Constraint::VertexFrom { v, t } => {
                self.levels.iter().skip(t as usize).any(|l| l.contains(&v))
                    || (v == goal && t as usize >= self.levels.len())
            }
            // Positive, length and barrier constraints are never added to other agents.
            Constraint::AtVertex { .. }
            | Constraint::Traverses { .. }
            | Constraint::FinishBy { .. }
            | Constraint::FinishAfter { .. }
            | Constraint::Barrier { .. } => true,
        }
    }

    /// Whether every path of this MDD is at one of `cells` (vertex, time) at its time (steps
    /// past the cost: on the goal, the last level's vertex): then forbidding them raises the
    /// agent's cost (rectangle reasoning's cardinality test).
    pub fn blocked_by(&self, graph: &Graph, cells: &[(VertexId, u32)]) -> bool {
        let last = self.levels.len() - 1;
        let goal = self.levels[last].first().copied();
        if cells
            .iter()
            .any(|&(v, t)| t as usize >= last && Some(v) == goal)
        {
            return true;
        }
        // Both lookups by binary search: `cells` sorted by (time, vertex) here, each `reach`
        // sorted as its level is.
        let mut blocked: Vec<(u32, VertexId)> = cells.iter().map(|&(v, t)| (t, v)).collect();
        blocked.sort_unstable();
        let hit = |v: VertexId, t: usize| blocked.binary_search(&(t as u32, v)).is_ok();
        let mut reach: Vec<VertexId> = self.levels[0]
            .iter()
            .copied()
            .filter(|&v| !hit(v, 0))
            .collect();
        for t in 1..=last {
            reach = self.levels[t]
                .iter()
                .copied()
                .filter(|&v| {
                    !hit(v, t)
                        && std::iter::once(&v)
                            .chain(graph.neighbors(v))
                            .any(|u| reach.binary_search(u).is_ok())
                })
                .collect();
            if reach.is_empty() {
                return true;
            }
        }
        false
    }

    /// Whether the agent must be at one vertex at step `t` (steps past the cost: on its goal).
    pub fn singleton(&self, t: u32) -> bool {
        self.levels.get(t as usize).is_none_or(|l| l.len() == 1)
    }
}

/// Most pairs of vertices one level of [`dependent`]'s joint search may hold; past it the two
/// agents are taken as independent (which keeps a heuristic built on it admissible).
const JOINT_LEVEL_CAP: usize = 4096;

/// Whether agents with MDDs `a` and `b` have no pair of paths (of their MDDs' costs, each staying
/// on its goal after its cost) free of vertex and swap conflicts: the *dependency* of the DG
/// heuristic (Li, Felner, Boyarski, Koenig, "Improved heuristics for multi-agent path finding with
/// conflict-based search", IJCAI 2019), found by a breadth-first search over pairs of MDD
/// vertices, level by level. Consecutive levels' vertices are joined where the graph has an edge
/// (or they are equal), which may allow a move the agent's constraints forbid: then a pair is
/// taken as independent when it is not, never the reverse.
pub fn dependent(graph: &Graph, a: &Mdd, b: &Mdd) -> bool {
    fn at(m: &Mdd, t: usize) -> &[VertexId] {
        m.levels
            .get(t)
            .or_else(|| m.levels.last())
            .map_or(&[], Vec::as_slice)
    }
    let horizon = a.levels.len().max(b.levels.len());
    // Pairs are indices into the two levels. Each agent's steps from a level to the next are
    // listed once per level (CSR: `starts`, `flat`), by binary search in the sorted next level:
    // recomputing them for every pair took a third of a WDG run's time on den520d.
    let mut pairs: Vec<(u32, u32)> = Vec::new();
    for (i, &u) in at(a, 0).iter().enumerate() {
        for (j, &v) in at(b, 0).iter().enumerate() {
            if u != v {
                pairs.push((i as u32, j as u32));
            }
        }
    }
    let successors = |m: &Mdd, t: usize, starts: &mut Vec<u32>, flat: &mut Vec<u32>| {
        let next = at(m, t);
        starts.clear();
        flat.clear();
        for &u in at(m, t - 1) {
            starts.push(flat.len() as u32);
            for x in std::iter::once(u).chain(graph.neighbors(u).iter().copied()) {
                if let Ok(j) = next.binary_search(&x) {
                    flat.push(j as u32);
                }
            }
        }
        starts.push(flat.len() as u32);
    };
    let (mut sa, mut fa, mut sb, mut fb) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut seen: rustc_hash::FxHashSet<(u32, u32)> = Default::default();
    for t in 1..horizon {
        let (pa, pb) = (at(a, t - 1), at(b, t - 1));
        let (la, lb) = (at(a, t), at(b, t));
        successors(a, t, &mut sa, &mut fa);
        successors(b, t, &mut sb, &mut fb);
        let mut next: Vec<(u32, u32)> = Vec::new();
        seen.clear();
        for &(i, j) in &pairs {
            let (u, v) = (pa[i as usize], pb[j as usize]);
            let xs = &fa[sa[i as usize] as usize..sa[i as usize + 1] as usize];
            let ys = &fb[sb[j as usize] as usize..sb[j as usize + 1] as usize];
            for &x in xs {
                for &y in ys {
                    let (xv, yv) = (la[x as usize], lb[y as usize]);
                    if xv != yv && !(xv == v && yv == u) && seen.insert((x, y)) {
                        next.push((x, y));
                        if next.len() > JOINT_LEVEL_CAP {
                            return false;
                        }
                    }
                }
            }
        }
        if next.is_empty() {
            return true;
        }
        pairs = next;
    }
    pairs.is_empty()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cbs::low_level::{Constraint, Constraints};

    /// An MDD that `touched_by` says a negative constraint leaves alone is the MDD built with
    /// that constraint added: every vertex and edge constraint at steps 0..=12 on a 5 x 5 grid,
    /// for an agent from a corner to the other at its shortest cost and two steps more, with no
    /// other constraint and with two.
    #[test]
    fn a_constraint_that_does_not_touch_an_mdd_leaves_it_as_it_is() {
        let map = crate::GridMap::from_free_rows(&vec![vec![true; 5]; 5]);
        let g = map.graph();
        let n = g.num_vertices() as VertexId;
        let edges: Vec<(VertexId, VertexId)> = (0..n)
            .flat_map(|u| g.neighbors(u).iter().map(move |&v| (u, v)))
            .collect();
        let (start, goal) = (0, n - 1);
        let to_goal = mrpp_core::mapf::search::distance::bfs_distances(g, goal);
        let h = |v: VertexId| to_goal[v as usize];
        let base_lists = [
            Vec::new(),
            vec![
                Constraint::Vertex { v: 6, t: 2 },
                Constraint::Edge { u: 1, v: 2, t: 2 },
            ],
        ];
        let mut kept = 0;
        for base in &base_lists {
            for cost in [8, 10] {
                let m = Mdd::build(g, start, goal, cost, &h, &Constraints::new(goal, base));
                let mut candidates = Vec::new();
                for t in 0..=12 {
                    for v in 0..n {
                        candidates.push(Constraint::Vertex { v, t });
                    }
                    // Both directions: `edges` lists every neighbour of every vertex.
                    for &(u, v) in &edges {
                        candidates.push(Constraint::Edge { u, v, t });
                    }
                }
                for c in candidates {
                    if m.touched_by(&c, goal) {
                        continue;
                    }
                    let mut list = base.clone();
                    list.push(c);
                    let with = Mdd::build(g, start, goal, cost, &h, &Constraints::new(goal, &list));
                    assert_eq!(with, m, "{c:?} at cost {cost}, base {base:?}");
                    kept += 1;
                }
            }
        }
        assert!(kept > 1000, "{kept}");
    }

    #[test]
    fn a_corridor_swap_is_dependent_and_parallel_lanes_are_not() {
        // Two parallel corridors 0-1-2 and 3-4-5 joined at 1-4.
        let g = Graph::from_edges(6, &[(0, 1), (1, 2), (3, 4), (4, 5), (1, 4)]);
        let none = |goal| Constraints::new(goal, &[]);
        let dist = |goal: VertexId| {
            // Breadth-first hops to `goal`.
            let mut d = [u32::MAX; 6];
            d[goal as usize] = 0;
            let mut queue = std::collections::VecDeque::from([goal]);
            while let Some(u) = queue.pop_front() {
                for &v in g.neighbors(u) {
                    if d[v as usize] == u32::MAX {
                        d[v as usize] = d[u as usize] + 1;
                        queue.push_back(v);
                    }
                }
            }
            move |v: VertexId| d[v as usize]
        };
        // Agent a 0 -> 2 and agent b 3 -> 5 at their shortest costs: independent lanes.
        let a = Mdd::build(&g, 0, 2, 2, &dist(2), &none(2));
        let b = Mdd::build(&g, 3, 5, 2, &dist(5), &none(5));
        assert!(!dependent(&g, &a, &b));
        // Agent a 0 -> 2 and agent c 2 -> 0 in one corridor, both at cost 2: they must swap.
        let c = Mdd::build(&g, 2, 0, 2, &dist(0), &none(0));
        assert!(dependent(&g, &a, &c));
        // A longer c cannot leave the corridor before a passes; a longer a can step aside into
        // 4 (0, 1, 4, 1, 2) while c (2, 2, 1, 0) goes by.
        let c4 = Mdd::build(&g, 2, 0, 4, &dist(0), &none(0));
        assert!(dependent(&g, &a, &c4));
        let a4 = Mdd::build(&g, 0, 2, 4, &dist(2), &none(2));
        let c3 = Mdd::build(&g, 2, 0, 3, &dist(0), &none(0));
        assert!(!dependent(&g, &a4, &c3));
    }
}
