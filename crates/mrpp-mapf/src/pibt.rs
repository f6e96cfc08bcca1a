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

use mrpp_core::mapf::search::distance::{GoalDistances, UNREACHABLE};
use mrpp_core::{Ctx, Graph, MapfProblem, Param, Plan, Planner, PlannerEntry, Unsolved, VertexId};

/// Registry name.
pub const NAME: &str = "pibt";

/// PIBT in the planner registry.
pub const ENTRY: PlannerEntry<MapfProblem> = PlannerEntry {
    name: NAME,
    about: "PIBT: priority inheritance with backtracking, one step at a time (Okumura et al., AIJ 2022)",
    params: &[
        Param {
            name: "max_steps",
            default: "0",
            doc: "steps before giving up (0: 20 x (vertices + agents))",
        },
        Param {
            name: "swap",
            default: "false",
            doc: "true = the swap technique of Engineering LaCAM* (AAMAS 2024): pairs pass each other at branches",
        },
        Param {
            name: "hindrance",
            default: "false",
            doc: "true = ties go to the candidate fewer neighbouring agents need (Engineering LaCAM*)",
        },
    ],
    build: |p| {
        Ok(Box::new(Pibt {
            max_steps: p.get_in("max_steps", 0..=100_000_000)?,
            tricks: Tricks::from_params(p)?,
        }))
    },
};

impl Tricks {
    /// The `swap` and `hindrance` parameters.
    ///
    /// # Errors
    /// A value other than `true` or `false`.
    pub fn from_params(p: &mrpp_core::registry::Params) -> mrpp_core::Result<Tricks> {
        Ok(Tricks {
            swap: p.choice("swap", &["false", "true"])? == 1,
            hindrance: p.choice("hindrance", &["false", "true"])? == 1,
        })
    }
}

/// The PIBT planner.
#[derive(Debug, Clone, Copy, Default)]
pub struct Pibt {
    /// Steps before giving up (0: 20 · (|V| + agents)).
    pub max_steps: usize,
    pub tricks: Tricks,
}

/// No agent.
pub(crate) const NIL: usize = usize::MAX;

/// Refinements of PIBT's single step (K. Okumura, "Engineering LaCAM*: towards real-time,
/// large-scale, and near-optimal multi-agent pathfinding", AAMAS 2024), both off in plain PIBT.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Tricks {
    /// *Swap*: when an agent and the agent on its preferred vertex must pass each other in a
    /// corridor (pushing would only lead both into a dead end) and a branch behind the first
    /// agent allows it, the first agent moves away from its goal and pulls the other one after
    /// it, so that the pair can swap at the branch.
    pub swap: bool,
    /// *Hindrance*: among candidates at equal distance, prefer the one that fewer neighbouring
    /// agents need for their own progress.
    pub hindrance: bool,
}

/// One PIBT step's state (also LaCAM's configuration generator, [`crate::lacam`]). The buffers
/// are borrowed so that a caller running many steps allocates them once.
pub(crate) struct Step<'a> {
    pub(crate) graph: &'a Graph,
    pub(crate) dist: &'a GoalDistances<'a>,
    pub(crate) goals: &'a [VertexId],
    pub(crate) tricks: Tricks,
    pub(crate) now: &'a [VertexId],
    /// Each agent's next vertex (`VertexId::MAX`: not chosen yet).
    pub(crate) next: &'a mut [VertexId],
    /// Per vertex: the agent on it now, and the agent that will be on it next.
    pub(crate) occupied_now: &'a [usize],
    pub(crate) occupied_next: &'a mut [usize],
    pub(crate) rng: &'a mut ChaCha8Rng,
    /// Preferred paths ([`crate::scatter`]): an agent on its path tries the path's next vertex
    /// first (LaCAM* with `-p scatter`).
    pub(crate) scatter: Option<&'a crate::scatter::Scatter>,
    /// Each agent's guidance ([`crate::guidance`]): tried first, before the scatter path's next
    /// vertex (LaCAM with `-p local_guidance`).
    pub(crate) guide: Option<&'a [VertexId]>,
}

/// Candidates of one agent: its vertex and its neighbours, on the stack for degree < 8.
const INLINE: usize = 8;

/// Not chosen yet.
const UNSET: VertexId = VertexId::MAX;

impl Step<'_> {
    /// PIBT(i): gives agent `i` its next vertex; false when it has to stay where it is because
    /// every candidate was taken.
    pub(crate) fn assign(&mut self, i: usize) -> bool {
        let here = self.now[i];
        let nbrs = self.graph.neighbors(here);
        // (cost, hindrance, position after the shuffle, vertex): sorting by the first three is a
        // stable sort of the shuffled candidates by cost, then hindrance.
        let mut inline = [(0i64, 0u32, 0usize, 0 as VertexId); INLINE];
        let mut heap = Vec::new();
        let cands: &mut [(i64, u32, usize, VertexId)] = if nbrs.len() < INLINE {
            inline[0].3 = here;
            for (c, &v) in inline[1..=nbrs.len()].iter_mut().zip(nbrs) {
                c.3 = v;
            }
            &mut inline[..=nbrs.len()]
        } else {
            heap.push((0, 0, 0, here));
            heap.extend(nbrs.iter().map(|&v| (0, 0, 0, v)));
            &mut heap
        };
        cands.shuffle(self.rng);
        // Hindrance: the agents on `here`'s neighbours with their distances now, looked up once
        // for all candidates.
        let mut inline_around = [(0 as VertexId, 0usize, 0u32); INLINE];
        let mut heap_around = Vec::new();
        let around: &[(VertexId, usize, u32)] = if self.tricks.hindrance {
            let buf: &mut [_] = if nbrs.len() < INLINE {
                &mut inline_around
            } else {
                heap_around.resize(nbrs.len(), (0, 0, 0));
                &mut heap_around
            };
            let mut n = 0;
            for &w in nbrs {
                let j = self.occupied_now[w as usize];
                if j != NIL && j != i {
                    buf[n] = (w, j, self.dist.get(j, w));
                    n += 1;
                }
            }
            &buf[..n]
        } else {
            &[]
        };
        for (k, c) in cands.iter_mut().enumerate() {
            // Neighbouring agents for whom the candidate is a step towards their goal.
            let u = c.3;
            let hindrance = around
                .iter()
                .filter(|&&(w, j, dw)| w != u && self.dist.get(j, u) < dw)
                .count() as u32;
            *c = (i64::from(self.dist.get(i, u)), hindrance, k, u);
        }
        cands.sort_unstable();
        // Preferred next vertices, each moved to the front in turn: the guidance wins.
        let preferred = [
            self.scatter.and_then(|s| s.next(i, here)),
            self.guide.map(|g| g[i]),
        ];
        for w in preferred.into_iter().flatten() {
            if let Some(k) = cands.iter().position(|c| c.3 == w) {
                cands[..=k].rotate_right(1);
            }
        }
        let swap_agent = if self.tricks.swap {
            self.swap_partner(i, cands[0].3)
        } else {
            NIL
        };
        if swap_agent != NIL {
            // Move away from the goal, to the branch where the pair can swap.
            for c in cands.iter_mut() {
                *c = (-i64::from(self.dist.get(i, c.3)), 0, c.2, c.3);
            }
            cands.sort_unstable();
        }
        for (k, &(_, _, _, v)) in cands.iter().enumerate() {
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
            if j != NIL && j != i && self.next[j] == UNSET && !self.assign(j) {
                continue;
            }
            if k == 0
                && swap_agent != NIL
                && self.next[swap_agent] == UNSET
                && self.occupied_next[here as usize] == NIL
            {
                // Pull the partner into the vertex just left.
                self.next[swap_agent] = here;
                self.occupied_next[here as usize] = swap_agent;
            }
            return true;
        }
        self.next[i] = here;
        self.occupied_next[here as usize] = i;
        false
    }

    /// The agent `i` should swap with when it wants `target`, or [`NIL`]: the undecided agent on
    /// `target` when the two must pass each other and can; else (the *clear* case) a neighbour
    /// of `i` that would have to pass `i` once `i` stands on `target`.
    fn swap_partner(&self, i: usize, target: VertexId) -> usize {
        let here = self.now[i];
        let j = self.occupied_now[target as usize];
        if j != NIL
            && j != i
            && self.next[j] == UNSET
            && self.swap_required(i, j, here, target)
            && self.swap_possible(target, here)
        {
            return j;
        }
        if target != here {
            for &u in self.graph.neighbors(here) {
                let k = self.occupied_now[u as usize];
                if k != NIL
                    && target != self.now[k]
                    && self.swap_required(k, i, here, target)
                    && self.swap_possible(target, here)
                {
                    return k;
                }
            }
        }
        NIL
    }

    /// Neighbours of `v` other than `from` and other than dead ends holding an agent on its
    /// goal: how many, and one of them.
    fn exits(&self, v: VertexId, from: VertexId) -> (usize, VertexId) {
        let mut n = 0;
        let mut one = UNSET;
        for &u in self.graph.neighbors(v) {
            let a = self.occupied_now[u as usize];
            let parked_dead_end = self.graph.degree(u) == 1 && a != NIL && self.goals[a] == u;
            if u != from && !parked_dead_end {
                n += 1;
                one = u;
            }
        }
        (n, one)
    }

    /// Whether `pusher` (at `pusher_at`) pushing `puller` (at `puller_at`) towards the pusher's
    /// goal leads into a corridor without a branch, while the puller wants the other way.
    fn swap_required(
        &self,
        pusher: usize,
        puller: usize,
        pusher_at: VertexId,
        puller_at: VertexId,
    ) -> bool {
        let (mut v_pusher, mut v_puller) = (pusher_at, puller_at);
        let mut steps = 0;
        while self.dist.get(pusher, v_puller) < self.dist.get(pusher, v_pusher) {
            let (n, next) = self.exits(v_puller, v_pusher);
            if n >= 2 {
                return false; // the puller can step aside at a branch
            }
            if n == 0 {
                break;
            }
            v_pusher = v_puller;
            v_puller = next;
            steps += 1;
            if steps > self.graph.num_vertices() {
                break;
            }
        }
        self.dist.get(puller, v_pusher) < self.dist.get(puller, v_puller)
            && (self.dist.get(pusher, v_pusher) == 0
                || self.dist.get(pusher, v_puller) < self.dist.get(pusher, v_pusher))
    }

    /// Whether pulling back from `puller_at`, away from `pusher_at`, reaches a branch where two
    /// agents can swap.
    fn swap_possible(&self, pusher_at: VertexId, puller_at: VertexId) -> bool {
        let (mut v_pusher, mut v_puller) = (pusher_at, puller_at);
        let mut steps = 0;
        while v_puller != pusher_at && steps <= self.graph.num_vertices() {
            let (n, next) = self.exits(v_puller, v_pusher);
            if n >= 2 {
                return true;
            }
            if n == 0 {
                return false;
            }
            v_pusher = v_puller;
            v_puller = next;
            steps += 1;
        }
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
        ctx.report(mrpp_core::Progress {
            stage: "PIBT",
            done: 0,
            total: 0,
            note: format!("goal distances of {n} agents"),
        });
        let mut dist = GoalDistances::new(g, &inst.goals);
        if !dist.warm_up(&inst.starts, ctx.deadline) {
            return Err(Unsolved::TimeLimit);
        }
        if let Some(i) = (0..n).find(|&i| dist.get(i, inst.starts[i]) == UNREACHABLE) {
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
        let mut next = vec![VertexId::MAX; n];
        let mut occupied_next = vec![NIL; g.num_vertices()];
        let mut throttle = mrpp_core::Throttle::new();
        for step in 0..=max_steps {
            if (0..n).all(|i| now[i] == inst.goals[i]) {
                return Ok(Plan { paths });
            }
            throttle.report(ctx, || mrpp_core::Progress {
                stage: "PIBT step",
                done: step as u64,
                total: max_steps as u64,
                note: format!(
                    "{} of {n} agents on their goals",
                    (0..n).filter(|&i| now[i] == inst.goals[i]).count()
                ),
            });
            if step == max_steps {
                break;
            }
            if step % 16 == 0 && ctx.deadline.expired() {
                return Err(Unsolved::TimeLimit);
            }
            order.sort_by(|&a, &b| elapsed[b].cmp(&elapsed[a]).then(tie[b].total_cmp(&tie[a])));
            let mut st = Step {
                graph: g,
                dist: &dist,
                goals: &inst.goals,
                tricks: self.tricks,
                now: &now,
                next: &mut next,
                occupied_now: &occupied_now,
                occupied_next: &mut occupied_next,
                rng: &mut rng,
                scatter: None,
                guide: None,
            };
            for &i in &order {
                if st.next[i] == VertexId::MAX {
                    st.assign(i);
                }
            }
            for i in 0..n {
                occupied_now[now[i] as usize] = NIL;
                occupied_next[next[i] as usize] = NIL;
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
            std::mem::swap(&mut now, &mut next);
            next.fill(VertexId::MAX);
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
