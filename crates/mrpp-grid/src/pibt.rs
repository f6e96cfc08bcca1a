//! PIBT: priority inheritance with backtracking (K. Okumura, M. Machida, X. Défago, Y. Tamura,
//! "Priority inheritance with backtracking for iterative multi-agent path finding", Artificial
//! Intelligence 310, 2022; IJCAI 2019), baselines §7.
//!
//! One step at a time, agents choose their next vertex in priority order. An agent takes the free
//! candidate (its neighbours and its own vertex) nearest to its goal by a BFS distance table; if
//! that vertex holds an agent that has not moved yet, the lower agent inherits the priority and
//! must move away first (recursively); if it cannot, the higher agent backtracks to its next
//! candidate. An agent never takes a vertex whose occupant is coming to its own (no swaps). An
//! agent's priority is the number of steps since it was last on its goal, ties broken by a seeded
//! random fraction; equal candidate distances are broken by a seeded shuffle (the paper's random
//! tie-breaking). PIBT is fast and incomplete in general (it reaches every goal on graphs where
//! every adjacent pair lies on a cycle, the paper's Theorem 2); it stops at `max_steps`
//! (`0` = 20 · (|V| + agents)) and reports that as giving up, never as a plan.

use rand::seq::SliceRandom;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use mrpp_core::mapf::search::distance::goal_distance_tables;
use mrpp_core::{Ctx, MapfProblem, Param, Plan, Planner, PlannerEntry, Unsolved, VertexId};

/// Registry name.
pub const NAME: &str = "pibt";

/// PIBT in the planner registry.
pub const ENTRY: PlannerEntry<MapfProblem> = PlannerEntry {
    name: NAME,
    about: "PIBT: priority inheritance with backtracking, one step at a time (Okumura et al., AIJ 2022)",
    params: &[Param {
        name: "max_steps",
        default: "0",
        doc: "steps before giving up (0: 20 x (vertices + agents))",
    }],
    build: |p| {
        Ok(Box::new(Pibt {
            max_steps: p.get_in("max_steps", 0..=100_000_000)?,
        }))
    },
};

/// The PIBT planner.
#[derive(Debug, Clone, Copy, Default)]
pub struct Pibt {
    /// Steps before giving up (0: 20 · (|V| + agents)).
    pub max_steps: usize,
}

/// No agent.
pub(crate) const NIL: usize = usize::MAX;

/// One PIBT step's state (also LaCAM's configuration generator, [`crate::lacam`]).
pub(crate) struct Step<'a> {
    pub(crate) problem: &'a MapfProblem,
    pub(crate) dist: &'a [Vec<u32>],
    pub(crate) now: &'a [VertexId],
    /// Each agent's next vertex (`VertexId::MAX`: not chosen yet).
    pub(crate) next: Vec<VertexId>,
    /// Per vertex: the agent on it now, and the agent that will be on it next.
    pub(crate) occupied_now: &'a [usize],
    pub(crate) occupied_next: Vec<usize>,
    pub(crate) rng: &'a mut ChaCha8Rng,
}

impl Step<'_> {
    /// PIBT(i): gives agent `i` its next vertex; false when it has to stay where it is because
    /// every candidate was taken.
    pub(crate) fn assign(&mut self, i: usize) -> bool {
        let g = self.problem.graph();
        let here = self.now[i];
        let mut cands: Vec<VertexId> = std::iter::once(here)
            .chain(g.neighbors(here).iter().copied())
            .collect();
        cands.shuffle(self.rng);
        cands.sort_by_key(|&v| self.dist[i][v as usize]);
        for v in cands {
            if self.occupied_next[v as usize] != NIL {
                continue;
            }
            let j = self.occupied_now[v as usize];
            // No swap: the occupant of `v` is not coming to `here`.
            if j != NIL && j != i && self.next[j] == here {
                continue;
            }
            self.next[i] = v;
            self.occupied_next[v as usize] = i;
            if j != NIL && j != i && self.next[j] == VertexId::MAX && !self.assign(j) {
                continue;
            }
            return true;
        }
        self.next[i] = here;
        self.occupied_next[here as usize] = i;
        false
    }
}

impl Planner<MapfProblem> for Pibt {
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
        let max_steps = if self.max_steps == 0 {
            20 * (g.num_vertices() + n)
        } else {
            self.max_steps
        };
        let mut rng = ChaCha8Rng::seed_from_u64(ctx.seed);
        let tie: Vec<f64> = (0..n).map(|_| rng.random::<f64>()).collect();
        let mut elapsed = vec![0usize; n];
        let mut now = inst.starts.clone();
        let mut paths: Vec<Vec<VertexId>> = now.iter().map(|&v| vec![v]).collect();
        let mut occupied_now = vec![NIL; g.num_vertices()];
        for (i, &v) in now.iter().enumerate() {
            occupied_now[v as usize] = i;
        }
        let mut order: Vec<usize> = (0..n).collect();
        for step in 0..=max_steps {
            if (0..n).all(|i| now[i] == inst.goals[i]) {
                return Ok(Plan { paths });
            }
            if step == max_steps {
                break;
            }
            if step % 16 == 0 && ctx.deadline.expired() {
                return Err(Unsolved::TimeLimit);
            }
            order.sort_by(|&a, &b| elapsed[b].cmp(&elapsed[a]).then(tie[b].total_cmp(&tie[a])));
            let mut st = Step {
                problem,
                dist: &dist,
                now: &now,
                next: vec![VertexId::MAX; n],
                occupied_now: &occupied_now,
                occupied_next: vec![NIL; g.num_vertices()],
                rng: &mut rng,
            };
            for &i in &order {
                if st.next[i] == VertexId::MAX {
                    st.assign(i);
                }
            }
            let next = st.next;
            for i in 0..n {
                occupied_now[now[i] as usize] = NIL;
            }
            for i in 0..n {
                occupied_now[next[i] as usize] = i;
                paths[i].push(next[i]);
                elapsed[i] = if next[i] == inst.goals[i] {
                    0
                } else {
                    elapsed[i] + 1
                };
            }
            now = next;
        }
        Err(Unsolved::GaveUp(format!(
            "PIBT did not bring every agent to its goal within {max_steps} steps"
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrpp_core::mapf::graph::Graph;
    use mrpp_core::{Instance, Rules, solve};

    /// A 4x4 open grid.
    fn grid4() -> Graph {
        let id = |x: u32, y: u32| y * 4 + x;
        let mut edges = Vec::new();
        for y in 0..4 {
            for x in 0..4 {
                if x + 1 < 4 {
                    edges.push((id(x, y), id(x + 1, y)));
                }
                if y + 1 < 4 {
                    edges.push((id(x, y), id(x, y + 1)));
                }
            }
        }
        Graph::from_edges(16, &edges)
    }

    #[test]
    fn swaps_and_rotations_on_an_open_grid() {
        let g = grid4();
        // Agents swap ends of rows and columns, and one starts on its goal.
        let inst = Instance::new(vec![0, 3, 12, 15, 5], vec![3, 0, 15, 12, 5]).unwrap();
        let p = MapfProblem::on(&g, &inst, Rules::default());
        for seed in 0..8 {
            let s = solve(
                &Pibt::default(),
                &p,
                &Ctx::new(seed, mrpp_core::Deadline::none()),
            )
            .unwrap_or_else(|e| panic!("seed {seed}: {e}"));
            assert!(s.metrics.makespan >= 3);
        }
    }

    #[test]
    fn an_unreachable_goal_is_reported() {
        let g = Graph::from_edges(4, &[(0, 1), (2, 3)]);
        let inst = Instance::new(vec![0], vec![3]).unwrap();
        let p = MapfProblem::on(&g, &inst, Rules::default());
        assert!(matches!(
            solve(&Pibt::default(), &p, &Ctx::default()),
            Err(Unsolved::GaveUp(_))
        ));
    }
}
