//! k-robust plans in runs in ticks (`--k-robust K`, [`crate::execution`]).
//!
//! A plan is *k-robust* (D. Atzmon, R. Stern, A. Felner, G. Wagner, R. Barták, N.-F. Zhou,
//! "Robust multi-agent path finding and executing", JAIR 67, 2020) when no robot enters a cell
//! that another robot left fewer than `k` actions earlier; then a robot may be up to `k` actions
//! late without another robot waiting on it. One-shot plans are re-timed afterwards
//! (`mrpp_exec::robust`); a lifelong run plans a few actions at a time from states the executor
//! predicts, so here every planned step of the multi-step plan is filtered as it is rolled out:
//!
//! - a move into a cell another robot left fewer than `k` actions before the step, or leaves at
//!   the step (following), is held (the robot waits instead; a turn is never held);
//! - a move into the cell of a robot that now waits is held too, in a chain (so the filtered
//!   step is valid whenever the planner's was: no robot enters an occupied cell, and a ring of
//!   robots moving together is held as a whole);
//! - the moves that remain are recorded as cells left at the step.
//!
//! Times are ticks: step `s` of a plan asked for at tick `t` starts at tick
//! `t + plan_every + s x agent_counter` (where it is staged), and a move executed at tick `τ`
//! left its cell at `τ - agent_counter` (the tick it would have started, undelayed). Cells a robot
//! will leave while its staged actions are carried out count as left when the plan is staged.
//! "Fewer than `k` actions" is fewer than `k x agent_counter` ticks. Where the paper is silent
//! (it plans one-shot, with CBS): the rollout's planner is not told which moves were held, it
//! plans the next step from where the robots are; `k = 0` changes nothing.

use mrpp_core::mapf::graph::VertexId;
use mrpp_mapf::GridMap;
use rustc_hash::FxHashMap;

use crate::model::{Action, State, apply};

/// Who left a cell last, and when (tick).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Left {
    robot: u32,
    tick: u64,
}

/// The cells robots left, as executed, and the filter of planned steps (module doc).
#[derive(Debug, Clone)]
pub struct KRobust {
    /// Actions of slack, at least 1.
    k: u32,
    /// Ticks per action.
    agent_counter: u32,
    /// Per vertex, the last executed (or staged) leave.
    executed: Vec<Option<Left>>,
    /// Leaves planned by the rollout in progress (cleared by [`Self::begin_rollout`]).
    planned: FxHashMap<VertexId, Left>,
    /// Moves held so far by the filter.
    held: u64,
}

impl KRobust {
    /// The filter for `k >= 1` actions of slack on a map of `num_vertices` cells, actions of
    /// `agent_counter` ticks; `None` for `k = 0`.
    pub fn new(k: u32, agent_counter: u32, num_vertices: usize) -> Option<Self> {
        (k > 0).then(|| KRobust {
            k,
            agent_counter: agent_counter.max(1),
            executed: vec![None; num_vertices],
            planned: FxHashMap::default(),
            held: 0,
        })
    }

    /// Moves the filter has held (turned into waits) so far.
    pub fn held(&self) -> u64 {
        self.held
    }

    /// Robot `robot`'s move out of `cell` completed at tick `tick` (module doc: it left at
    /// `tick - agent_counter`).
    pub fn executed_move(&mut self, robot: usize, cell: VertexId, tick: u64) {
        let left = Left {
            robot: robot as u32,
            tick: tick.saturating_sub(u64::from(self.agent_counter)),
        };
        if let Some(slot) = self.executed.get_mut(cell as usize) {
            *slot = Some(left);
        }
    }

    /// A rollout starts: robots now at `now` will stand at `predicted` when the plan is staged at
    /// tick `staged_at`; the cells they leave on the way count as left then.
    pub fn begin_rollout(&mut self, now: &[State], predicted: &[State], staged_at: u64) {
        self.planned.clear();
        for (i, (a, b)) in now.iter().zip(predicted).enumerate() {
            if a.vertex != b.vertex
                && let Some(slot) = self.executed.get_mut(a.vertex as usize)
            {
                *slot = Some(Left {
                    robot: i as u32,
                    tick: staged_at,
                });
            }
        }
    }

    /// The last leave of `cell` known to the rollout.
    fn last_left(&self, cell: VertexId) -> Option<Left> {
        self.planned
            .get(&cell)
            .copied()
            .or_else(|| self.executed.get(cell as usize).copied().flatten())
    }

    /// Filters one planned step (module doc): robots at `states` were planned `actions`, the
    /// step starting at tick `tick`. Held moves become waits; returns how many were held.
    pub fn filter_step(
        &mut self,
        map: &GridMap,
        states: &[State],
        actions: &mut [Action],
        tick: u64,
    ) -> usize {
        let slack = u64::from(self.k) * u64::from(self.agent_counter);
        // Each mover's target cell, and which robot stands on each cell.
        let target: Vec<Option<VertexId>> = states
            .iter()
            .zip(actions.iter())
            .map(|(&s, &a)| {
                apply(map, s, a)
                    .map(|n| n.vertex)
                    .filter(|&v| v != s.vertex)
            })
            .collect();
        let mover_into: FxHashMap<VertexId, usize> = target
            .iter()
            .enumerate()
            .filter_map(|(i, t)| t.map(|v| (v, i)))
            .collect();
        // Cells left at this very step: entering one is following, 0 actions of slack.
        let leaving: FxHashMap<VertexId, usize> = target
            .iter()
            .enumerate()
            .filter(|(_, t)| t.is_some())
            .map(|(i, _)| (states[i].vertex, i))
            .collect();
        let mut held = vec![false; states.len()];
        let mut chain = Vec::new();
        for (i, t) in target.iter().enumerate() {
            let Some(c) = *t else { continue };
            let follows = leaving.get(&c).is_some_and(|&j| j != i);
            let recent = self
                .last_left(c)
                .is_some_and(|l| l.robot as usize != i && tick < l.tick.saturating_add(slack));
            if follows || recent {
                held[i] = true;
                chain.push(i);
            }
        }
        // A held robot stays on its cell: whoever planned to enter it waits too.
        while let Some(j) = chain.pop() {
            if let Some(&i) = mover_into.get(&states[j].vertex)
                && !held[i]
            {
                held[i] = true;
                chain.push(i);
            }
        }
        let mut count = 0;
        for (i, t) in target.iter().enumerate() {
            if held[i] {
                actions[i] = Action::Wait;
                count += 1;
            } else if t.is_some() {
                self.planned.insert(
                    states[i].vertex,
                    Left {
                        robot: i as u32,
                        tick,
                    },
                );
            }
        }
        self.held += count as u64;
        count
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::EAST;

    fn corridor(len: usize) -> GridMap {
        GridMap::from_free_rows(&[vec![true; len]])
    }

    fn at(v: VertexId) -> State {
        State {
            vertex: v,
            orientation: EAST,
        }
    }

    #[test]
    fn following_is_held_and_the_hold_runs_down_the_chain() {
        // Robots on 0, 1, 2 all moving east: 2 enters a free cell, 1 would follow 2 into the
        // cell 2 leaves at the same step, 0 would follow 1. With k = 1 following is not allowed:
        // 1 is held, so 0 is held too.
        let map = corridor(5);
        let mut f = KRobust::new(1, 10, 5).unwrap();
        let states = [at(0), at(1), at(2)];
        let mut actions = [Action::Move(0); 3];
        assert_eq!(f.filter_step(&map, &states, &mut actions, 100), 2);
        assert_eq!(actions, [Action::Wait, Action::Wait, Action::Move(0)]);
        // Robot 2 left cell 2 at tick 100: half an action later robot 1 may not enter it (and
        // robot 0 may not enter robot 1's cell); a whole action later both go.
        let states = [at(0), at(1), at(3)];
        let mut actions = [Action::Move(0), Action::Move(0), Action::Wait];
        assert_eq!(f.filter_step(&map, &states, &mut actions, 105), 2);
        assert_eq!(f.held(), 4);
        let mut actions = [Action::Move(0), Action::Move(0), Action::Wait];
        assert_eq!(f.filter_step(&map, &states, &mut actions, 110), 1);
        assert_eq!(actions, [Action::Wait, Action::Move(0), Action::Wait]);
        // An executed leave counts from its start: cell 3 left by robot 2, done at tick 120.
        f.executed_move(2, 3, 120);
        let states = [at(2)];
        let mut actions = [Action::Move(0)];
        assert_eq!(f.filter_step(&map, &states, &mut actions, 119), 1);
        let mut actions = [Action::Move(0)];
        assert_eq!(f.filter_step(&map, &states, &mut actions, 120), 0);
    }

    #[test]
    fn a_robot_may_reenter_the_cell_it_left_and_turns_are_never_held() {
        let map = corridor(3);
        let mut f = KRobust::new(2, 1, 3).unwrap();
        f.executed_move(0, 1, 5); // robot 0 left cell 1 at tick 4
        let states = [at(0)];
        let mut actions = [Action::Move(0)];
        assert_eq!(f.filter_step(&map, &states, &mut actions, 5), 0);
        let mut turn = [Action::Clockwise];
        f.executed_move(1, 0, 5);
        assert_eq!(f.filter_step(&map, &states, &mut turn, 5), 0);
        assert_eq!(turn, [Action::Clockwise]);
    }

    #[test]
    fn cells_left_while_staged_actions_run_count_as_left_when_staged() {
        let map = corridor(4);
        let mut f = KRobust::new(1, 10, 4).unwrap();
        // Robot 0 stands on 1 and will be on 2 when the plan is staged at tick 50.
        f.begin_rollout(&[at(1), at(0)], &[at(2), at(0)], 50);
        let states = [at(2), at(0)];
        let mut actions = [Action::Wait, Action::Move(0)];
        assert_eq!(f.filter_step(&map, &states, &mut actions, 50), 1);
        assert_eq!(actions[1], Action::Wait);
        let mut actions = [Action::Wait, Action::Move(0)];
        assert_eq!(f.filter_step(&map, &states, &mut actions, 60), 0);
    }

    #[test]
    fn zero_slack_builds_no_filter() {
        assert!(KRobust::new(0, 10, 4).is_none());
    }
}
