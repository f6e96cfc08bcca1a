//! The action dependency graph of a grid plan (W. Hönig, S. Kiesel, A. Tinka, J. W. Durham,
//! N. Ayanian, "Persistent and robust execution of MAPF schedules in warehouses", IEEE RA-L 4(2),
//! 2019, §III-A).
//!
//! Its vertices are the plan's moves, waits dropped: robot `i`'s `k`-th move goes from one cell
//! to the next. Type-1 dependencies are each robot's own order (move `k` after move `k - 1`,
//! implicit here). Type-2 dependencies keep the plan's order of passage at every cell: when robot
//! `j` enters a cell that robot `i` stood on earlier in the plan, `j`'s move into it depends on
//! `i`'s move out of it. Only the next visit after each is recorded (the rest follows by
//! transitivity). A robot starts a move only when every move it depends on is *finished*, so two
//! robots are never in one cell, however late either is.

use mrpp_core::mapf::graph::VertexId;
use mrpp_core::mapf::plan::Plan;

/// One move of a robot's plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Move {
    pub from: VertexId,
    pub to: VertexId,
    /// The plan's step at which the move starts (path index of `from`).
    pub step: u32,
}

/// A robot's stay on a cell: (cell, arrival step, robot, the move that brings it there or `None`
/// at its start, the move that takes it away or `None` when it never leaves).
type Stay = (VertexId, u32, usize, Option<usize>, Option<usize>);

/// The graph (module doc): each robot's moves, and per move the moves it waits for.
#[derive(Debug, Clone, Default)]
pub struct Adg {
    pub moves: Vec<Vec<Move>>,
    /// `deps[i][k]`: `(j, m)` pairs — robot `j`'s move `m` must be finished before robot `i`
    /// starts its move `k`.
    pub deps: Vec<Vec<Vec<(usize, usize)>>>,
}

impl Adg {
    /// The graph of `plan` (a valid plan: the type-2 order is its order of passage).
    pub fn new(plan: &Plan) -> Self {
        let moves: Vec<Vec<Move>> = plan
            .paths
            .iter()
            .map(|p| {
                p.windows(2)
                    .enumerate()
                    .filter(|(_, w)| w[0] != w[1])
                    .map(|(t, w)| Move {
                        from: w[0],
                        to: w[1],
                        step: t as u32,
                    })
                    .collect()
            })
            .collect();
        let mut stays: Vec<Stay> = Vec::new();
        for (i, (path, ms)) in plan.paths.iter().zip(&moves).enumerate() {
            let Some(&start) = path.first() else { continue };
            stays.push((start, 0, i, None, (!ms.is_empty()).then_some(0)));
            for (k, m) in ms.iter().enumerate() {
                let leave = (k + 1 < ms.len()).then_some(k + 1);
                stays.push((m.to, m.step + 1, i, Some(k), leave));
            }
        }
        stays.sort_unstable_by_key(|s| (s.0, s.1, s.2));
        let mut deps: Vec<Vec<Vec<(usize, usize)>>> =
            moves.iter().map(|ms| vec![Vec::new(); ms.len()]).collect();
        for w in stays.windows(2) {
            let (a, b) = (w[0], w[1]);
            if a.0 != b.0 || a.2 == b.2 {
                continue;
            }
            // b enters the cell after a stood on it: b's arrival waits for a's departure.
            if let (Some(leave), Some(enter)) = (a.4, b.3) {
                deps[b.2][enter].push((a.2, leave));
            }
        }
        Adg { moves, deps }
    }

    /// Groups of moves that wait for each other in a ring: robots rotating together at one step
    /// (each enters the cell the next leaves). No executor can start any of them first; with
    /// square footprints of side above 0.5 such a rotation overlaps at its corners anyway. Each
    /// group lists its `(robot, move)` pairs.
    pub fn rotation_cycles(&self) -> Vec<Vec<(usize, usize)>> {
        // A move's dependency at its own step (the robot leaving the cell it enters).
        let same_step = |i: usize, k: usize| {
            self.deps[i][k]
                .iter()
                .copied()
                .find(|&(j, m)| self.moves[j][m].step == self.moves[i][k].step)
        };
        let mut seen = std::collections::HashSet::new();
        let mut cycles = Vec::new();
        for i in 0..self.moves.len() {
            for k in 0..self.moves[i].len() {
                if seen.contains(&(i, k)) {
                    continue;
                }
                let mut chain = vec![(i, k)];
                let mut at = (i, k);
                while let Some(next) = same_step(at.0, at.1) {
                    if next == (i, k) {
                        cycles.push(chain.clone());
                        break;
                    }
                    if chain.contains(&next) || seen.contains(&next) {
                        break;
                    }
                    chain.push(next);
                    at = next;
                }
                seen.extend(chain);
            }
        }
        cycles
    }

    /// Type-2 dependencies in all.
    pub fn num_dependencies(&self) -> usize {
        self.deps.iter().flatten().map(Vec::len).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_follower_waits_for_the_leader_to_leave_each_cell() {
        // A corridor 0-1-2-3: robot 0 goes 1 -> 3, robot 1 follows from 0 to 2.
        let plan = Plan {
            paths: vec![vec![1, 2, 3], vec![0, 1, 2]],
        };
        let g = Adg::new(&plan);
        assert_eq!(g.moves[0].len(), 2);
        assert_eq!(g.moves[1].len(), 2);
        // Robot 1's move into 1 waits for robot 0's move out of 1; into 2, for out of 2.
        assert_eq!(g.deps[1][0], vec![(0, 0)]);
        assert_eq!(g.deps[1][1], vec![(0, 1)]);
        assert!(g.deps[0].iter().all(Vec::is_empty));
        assert_eq!(g.num_dependencies(), 2);
    }

    #[test]
    fn waits_are_dropped_and_later_visits_wait_for_earlier_ones() {
        // Robot 0 waits on 5 then moves to 6; robot 1 passes 5 after it has left.
        let plan = Plan {
            paths: vec![vec![5, 5, 6, 7], vec![4, 4, 4, 5, 9]],
        };
        let g = Adg::new(&plan);
        assert_eq!(
            g.moves[0],
            vec![
                Move {
                    from: 5,
                    to: 6,
                    step: 1
                },
                Move {
                    from: 6,
                    to: 7,
                    step: 2
                }
            ]
        );
        assert_eq!(g.moves[1].len(), 2);
        assert_eq!(g.deps[1][0], vec![(0, 0)]);
    }
}
