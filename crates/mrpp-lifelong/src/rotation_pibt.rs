//! One step of PIBT for lifelong runs, with rotations (the start kit's default planner's PIBT,
//! `default_planner/pibt.cpp` v2.1.2, whose guide paths are [`crate::guide_paths`]; PIBT:
//! K. Okumura, M. Machida, X. Défago, Y. Tamura, "Priority inheritance with backtracking for
//! iterative multi-agent path finding", Artificial Intelligence 310, 2022).
//!
//! Each robot's goal is its task's next errand; a robot without a task has its own cell as goal
//! (it moves only when pushed). Priorities: steps spent on the current goal (reset when the goal
//! changes), ties broken by a seeded random fraction drawn once per robot. In priority order each
//! robot not yet decided runs PIBT: its candidates are its cell and the free neighbouring cells,
//! nearest to its goal first by breadth-first distance, ties to fewer turns (the cell ahead
//! first), then seeded at random; a candidate another robot reserved, or whose robot is coming to
//! this robot's cell (a swap), is skipped; a robot on the chosen cell inherits the priority and
//! must move first, else the next candidate is tried; with none left the robot stays.
//!
//! Under `MAPF` the chosen cells are the moves. Under `MAPF_T` a robot moves forward only if its
//! chosen cell is ahead; otherwise it turns towards it (clockwise for a U-turn) and stays. The
//! cell it turned towards (or was held back from) is *held*: at the next step it is reserved
//! for that robot before PIBT runs, so a robot standing on it must move away, until the robot
//! gets there, gets a new goal or has stood still [`STUCK_AFTER`] steps (the kit's `decided`,
//! `default_planner/planner.cpp`; `-p commitment=hold`, the default). With `commitment=prefer`
//! the cell only goes first among equally good candidates at the next step. On the kit's
//! `warehouse_large_5000` over 1,000 steps, holding raised lifelong-pibt's tasks finished from
//! 11,346 to 13,057: without it robots in dense crowds turned back and forth (28% of all
//! actions were turns by step 900, 14% with it). A robot that stays anyway turns towards its
//! best neighbouring cell closer to its goal, so that it can move as soon as the cell is free;
//! and a
//! robot moves forward only if the robot on its target cell moves away this step too (the kit's
//! `moveCheck`), which is settled by stopping, transitively, every robot headed for the cell of
//! a robot that stays. Cycles of robots moving forward together are kept (the kit allows them).
//! A robot that has stood still for [`STUCK_AFTER`] steps with somewhere to go takes its
//! candidates in a seeded random order for one step (mrpp's escape: without it, dense crowds on
//! random-32-32-20 froze for good, every robot waiting, after about 400 steps). The joint action
//! never has a vertex or a swap conflict.

use rand::seq::SliceRandom;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use mrpp_core::mapf::graph::VertexId;

use crate::distances::{Distances, TurnDistances, plus};
use crate::guide_paths::GuidePaths;
use crate::model::{Action, ActionModel, State, direction, turns};
use crate::problem::LifelongProblem;

const NIL: usize = usize::MAX;
const UNSET: VertexId = VertexId::MAX;

/// PIBT's state kept from step to step: priorities, the random tie-breaks and the buffers.
#[derive(Debug, Clone)]
pub struct RotationPibt {
    rng: ChaCha8Rng,
    tie: Vec<f64>,
    elapsed: Vec<u32>,
    last_goal: Vec<VertexId>,
    now: Vec<VertexId>,
    next: Vec<VertexId>,
    occupied_now: Vec<usize>,
    occupied_next: Vec<usize>,
    /// Candidates of each robot, best first (at most 5: its cell and 4 neighbours).
    cands: Vec<[VertexId; 5]>,
    count: Vec<u8>,
    /// The cell a robot turned towards at the last step (kept first among equals, so that a
    /// U-turn is not undone half way), or `UNSET`.
    committed: Vec<VertexId>,
    /// Each robot's best neighbouring cell closer to its goal (`UNSET`: none), which a robot
    /// that stays turns towards.
    wish: Vec<VertexId>,
    /// Steps each robot has stood on its cell while it had somewhere to go.
    still: Vec<u32>,
    last_vertex: Vec<VertexId>,
    /// The robot heading for each cell from another cell this step (`NIL`: none).
    heading: Vec<usize>,
    /// Whether a robot keeps the cell it turned towards (or was held back from) reserved at
    /// the next step, as the kit's `decided` does; else that cell only goes first among equally
    /// good candidates.
    pub hold: bool,
}

/// Steps a robot may stand still with somewhere to go before it takes its candidates in a
/// random order for a step (an escape from the jams PIBT with rotations can freeze in).
pub const STUCK_AFTER: u32 = 8;

impl RotationPibt {
    /// State for `robots` robots on a graph of `vertices` vertices; every random choice comes
    /// from `seed`.
    pub fn new(robots: usize, vertices: usize, seed: u64) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let tie = (0..robots).map(|_| rng.random::<f64>()).collect();
        RotationPibt {
            rng,
            tie,
            elapsed: vec![0; robots],
            last_goal: vec![UNSET; robots],
            now: vec![UNSET; robots],
            next: vec![UNSET; robots],
            occupied_now: vec![NIL; vertices],
            occupied_next: vec![NIL; vertices],
            cands: vec![[UNSET; 5]; robots],
            count: vec![0; robots],
            committed: vec![UNSET; robots],
            wish: vec![UNSET; robots],
            still: vec![0; robots],
            last_vertex: vec![UNSET; robots],
            heading: vec![NIL; vertices],
            hold: true,
        }
    }

    /// The joint action of one step towards `goals` (one vertex per robot: its next errand, or
    /// its own cell when it has no task). With `guide`, a robot that has a guide path to its
    /// goal ranks its candidates by their distance along that path
    /// ([`crate::guide_paths`]) instead of their distance to the goal; else, with `turn_tables`
    /// (`MAPF_T`), by the actions to the goal counting quarter turns ([`TurnDistances`]).
    pub fn step(
        &mut self,
        problem: &LifelongProblem,
        states: &[State],
        goals: &[VertexId],
        dist: &mut Distances,
        mut guide: Option<&mut GuidePaths>,
        mut turn_tables: Option<&mut TurnDistances>,
    ) -> Vec<Action> {
        let map = problem.map();
        let graph = map.graph();
        let n = states.len();
        for (i, s) in states.iter().enumerate() {
            self.now[i] = s.vertex;
            self.next[i] = UNSET;
            self.occupied_now[s.vertex as usize] = i;
            if goals[i] != self.last_goal[i] {
                self.last_goal[i] = goals[i];
                self.elapsed[i] = 0;
                self.committed[i] = UNSET;
            } else if goals[i] != s.vertex {
                self.elapsed[i] += 1;
            }
            if s.vertex == self.last_vertex[i] && goals[i] != s.vertex {
                self.still[i] += 1;
            } else {
                self.still[i] = 0;
            }
            self.last_vertex[i] = s.vertex;
        }
        // Candidates, best first.
        let mut verts = Vec::with_capacity(5);
        let mut d = Vec::with_capacity(5);
        for (i, (&s, &goal)) in states.iter().zip(goals).enumerate() {
            verts.clear();
            verts.push(s.vertex);
            verts.extend_from_slice(graph.neighbors(s.vertex));
            if goal == s.vertex {
                // A robot without a task (or on its errand) stays unless pushed: no table needed.
                d.clear();
                d.extend(verts.iter().map(|&w| u32::from(w != goal)));
            } else {
                match (guide.as_deref_mut(), turn_tables.as_deref_mut()) {
                    (Some(g), _) if g.follows(i, goal) => g.distances(i, &verts, &mut d),
                    (_, Some(td)) => {
                        // Actions to the goal: staying, the state's own; a neighbour, the turns
                        // to face it plus the actions from there facing that way.
                        d.clear();
                        d.push(td.get(s.vertex, s.orientation, goal));
                        for &w in &verts[1..] {
                            let o = direction(map, s.vertex, w).expect("a neighbour");
                            d.push(plus(td.get(w, o, goal), turns(s.orientation, o)));
                        }
                    }
                    _ => dist.to(graph, goal, &verts, &mut d),
                }
            }
            let committed = self.committed[i];
            let stuck = self.still[i] >= STUCK_AFTER;
            let mut c: Vec<(u32, u32, u32, u32, VertexId)> = verts
                .iter()
                .zip(&d)
                .map(|(&w, &dw)| {
                    let turn = if w == s.vertex {
                        0
                    } else {
                        direction(map, s.vertex, w).map_or(2, |d| turns(s.orientation, d))
                    };
                    if stuck {
                        (0, 0, 0, 0, w)
                    } else {
                        (dw, turn, u32::from(w != committed), 0, w)
                    }
                })
                .collect();
            c.shuffle(&mut self.rng);
            for (k, e) in c.iter_mut().enumerate() {
                e.3 = k as u32;
            }
            c.sort_unstable();
            self.count[i] = c.len() as u8;
            for (slot, e) in self.cands[i].iter_mut().zip(&c) {
                *slot = e.4;
            }
            let here = d[0];
            self.wish[i] = c
                .iter()
                .find(|e| e.4 != s.vertex && e.0 < here)
                .map_or(UNSET, |e| e.4);
        }
        // The kit's commitment: a robot that turned towards a cell (or was held back from it)
        // keeps that cell this step, unless it has been stuck too long.
        if self.hold {
            for i in 0..n {
                let c = self.committed[i];
                // (A caller may have executed other actions than PIBT's, e.g. windowed LNS:
                // then the cell may no longer be a neighbour.)
                // Two robots holding each other's cells would swap: neither holds.
                let k = if c == UNSET {
                    NIL
                } else {
                    self.occupied_now[c as usize]
                };
                let mutual = k != NIL && k != i && self.committed[k] == self.now[i];
                if c != UNSET
                    && !mutual
                    && self.still[i] < STUCK_AFTER
                    && self.occupied_next[c as usize] == NIL
                    && graph.has_edge(self.now[i], c)
                {
                    self.next[i] = c;
                    self.occupied_next[c as usize] = i;
                }
            }
        }
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| {
            (f64::from(self.elapsed[b]) + self.tie[b])
                .total_cmp(&(f64::from(self.elapsed[a]) + self.tie[a]))
        });
        for &i in &order {
            if self.next[i] == UNSET {
                self.pibt(i, NIL);
            }
        }
        let actions = match problem.model() {
            ActionModel::Mapf => (0..n)
                .map(|i| {
                    if self.next[i] == self.now[i] {
                        Action::Wait
                    } else {
                        Action::Move(
                            direction(map, self.now[i], self.next[i]).expect("a neighbour"),
                        )
                    }
                })
                .collect(),
            ActionModel::MapfT => self.with_rotations(problem, states),
        };
        for i in 0..n {
            self.occupied_now[self.now[i] as usize] = NIL;
            self.occupied_next[self.next[i] as usize] = NIL;
        }
        actions
    }

    /// PIBT(i) with `parent` the robot that pushed it (module doc); false when `i` stays.
    fn pibt(&mut self, i: usize, parent: usize) -> bool {
        for k in 0..self.count[i] as usize {
            let c = self.cands[i][k];
            if self.occupied_next[c as usize] != NIL {
                continue;
            }
            if parent != NIL && self.now[parent] == c {
                continue;
            }
            let j = self.occupied_now[c as usize];
            if j != NIL && j != i && self.next[j] == self.now[i] {
                continue;
            }
            self.occupied_next[c as usize] = i;
            self.next[i] = c;
            if j != NIL && j != i && self.next[j] == UNSET && !self.pibt(j, i) {
                continue;
            }
            return true;
        }
        self.next[i] = self.now[i];
        self.occupied_next[self.now[i] as usize] = i;
        false
    }

    /// The `MAPF_T` joint action of the chosen cells (module doc).
    fn with_rotations(&mut self, problem: &LifelongProblem, states: &[State]) -> Vec<Action> {
        let map = problem.map();
        let n = states.len();
        let mut actions = vec![Action::Wait; n];
        let mut stays = Vec::new();
        for i in 0..n {
            if self.next[i] != self.now[i] {
                self.heading[self.next[i] as usize] = i;
            }
        }
        let turn_to = |o, d| {
            if (o + 1) % 4 == d || turns(o, d) == 2 {
                Action::Clockwise
            } else {
                Action::CounterClockwise
            }
        };
        for (i, &s) in states.iter().enumerate() {
            self.committed[i] = UNSET;
            if self.next[i] == s.vertex {
                stays.push(i);
                // Staying anyway: turn towards the cell it would rather be in.
                if self.wish[i] != UNSET
                    && let Some(d) = direction(map, s.vertex, self.wish[i])
                    && d != s.orientation
                {
                    actions[i] = turn_to(s.orientation, d);
                }
                continue;
            }
            let d = direction(map, s.vertex, self.next[i]).expect("a neighbour");
            self.committed[i] = self.next[i];
            actions[i] = if d == s.orientation {
                Action::Forward
            } else {
                stays.push(i);
                turn_to(s.orientation, d)
            };
        }
        // Whoever heads for the cell of a robot that stays stays too, transitively (the kit's
        // `moveCheck`). The robot heading for a cell is the one whose chosen cell it is and
        // that is not standing on it.
        while let Some(j) = stays.pop() {
            let c = self.now[j];
            let k = self.occupied_next[c as usize];
            let k = if k != NIL && self.now[k] != c {
                k
            } else {
                // The cell's own robot stays there and took the entry back: a robot holding
                // the cell from the last step may still head for it.
                match self.heading[c as usize] {
                    h if h != NIL && h != j => h,
                    _ => continue,
                }
            };
            if actions[k] == Action::Forward {
                actions[k] = Action::Wait;
                stays.push(k);
            }
        }
        // A robot that moves forward has reached its chosen cell: nothing held.
        for (i, a) in actions.iter().enumerate() {
            if *a == Action::Forward {
                self.committed[i] = UNSET;
            }
            if self.next[i] != self.now[i] {
                self.heading[self.next[i] as usize] = NIL;
            }
        }
        actions
    }
}

#[cfg(test)]
mod tests {
    use mrpp_mapf::GridMap;

    use super::*;
    use crate::problem::test_problem;

    /// A 1 x 4 corridor under `MAPF_T` with robots on cells 1 and 2.
    fn corridor() -> LifelongProblem {
        let map = GridMap::from_free_rows(&[vec![true; 4]]);
        test_problem(
            map,
            vec![1, 2],
            vec![vec![3, 0], vec![0, 3]],
            1.0,
            ActionModel::MapfT,
        )
    }

    /// Two robots facing each other whose held cells are each other's (a caller executed other
    /// actions than PIBT's, as windowed LNS may): neither holds, so they do not swap.
    #[test]
    fn robots_holding_each_others_cells_do_not_swap() {
        let problem = corridor();
        // Robot 0 on cell 1 facing east (0), robot 1 on cell 2 facing west (2); each heads past
        // the other.
        let states = [
            State {
                vertex: 1,
                orientation: 0,
            },
            State {
                vertex: 2,
                orientation: 2,
            },
        ];
        let goals = [3, 0];
        let mut dist = Distances::new(4, 1 << 20);
        for seed in 0..20 {
            let mut pibt = RotationPibt::new(2, 4, seed);
            // A first step sets the goals; then each robot holds the other's cell.
            pibt.step(&problem, &states, &goals, &mut dist, None, None);
            pibt.committed = vec![2, 1];
            let actions = pibt.step(&problem, &states, &goals, &mut dist, None, None);
            assert!(
                !(actions[0] == Action::Forward && actions[1] == Action::Forward),
                "seed {seed}: {actions:?}"
            );
        }
    }
}
