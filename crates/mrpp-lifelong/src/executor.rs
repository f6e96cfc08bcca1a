//! Executors of the 2026 execution model: what a planner's multi-step plan becomes on robots
//! that are late ([`crate::execution`]). An executor *stages* part of each new plan (the actions
//! robots will carry out until the next plan arrives), *predicts* where robots will stand when
//! the staged actions are done (the planner plans from there), and each tick says *go* or
//! *stop* for each robot (start kit v3.1.0, `inc/Executor.h`; `docs/lorr-semantics.md` §4, §6).
//!
//! - `tpg` — the start kit's default executor (`default_planner/default_executor.cpp`), a
//!   temporal plan graph after Ma, Kumar & Koenig, "Multi-agent path finding with delay
//!   probabilities", AAAI 2017: per cell, the queue of robots planned to enter it. A new plan's
//!   first `window` actions (waits dropped) are appended to each robot's stage and queued at the
//!   cells they enter; then the stage is simulated without delays for `window` actions (a move
//!   goes only when its robot heads the target cell's queue), each stage is cut to what that
//!   simulation carried out, and the queues are rebuilt in the order it visited cells. Each tick a
//!   robot that left a cell leaves its queue; a robot goes when its next staged action is a turn,
//!   or a move whose target cell's queue is empty or headed by it. `window` = actions per planning
//!   period + 1, as in the kit.
//! - `naive` — every staged action goes as soon as the robot is free (the simulator still makes
//!   it wait rather than collide); stages are the plans' first `window` actions, not cut.
//!
//! Both drop the plan beyond `window` actions: the next plan replaces it. mrpp's stricter choice
//! where the kit would fail an assertion (a robot missing from the queue it should head): the
//! robot stops.

use std::collections::VecDeque;

use mrpp_mapf::GridMap;

use crate::model::{Action, State, apply};
use crate::ticks::{TickState, is_wait, target};

/// Which executor (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ExecutorKind {
    /// The start kit's default: a temporal plan graph.
    #[default]
    Tpg,
    /// Go whenever there is a staged action.
    Naive,
}

impl ExecutorKind {
    /// Its name on the command line and in records.
    pub fn name(self) -> &'static str {
        match self {
            ExecutorKind::Tpg => "tpg",
            ExecutorKind::Naive => "naive",
        }
    }

    /// `tpg` or `naive`.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "tpg" => Some(ExecutorKind::Tpg),
            "naive" => Some(ExecutorKind::Naive),
            _ => None,
        }
    }
}

/// An executor's state between ticks.
#[derive(Debug, Clone)]
pub struct Executor {
    kind: ExecutorKind,
    window: usize,
    /// Per cell (vertex id), the robots queued to enter it, in order.
    queues: Vec<VecDeque<u32>>,
    /// Per robot, the cell it was last seen on (to leave that queue when it moves on).
    last: Vec<u32>,
    /// Where robots will stand when their stages are done.
    predicted: Vec<State>,
    first: bool,
}

impl Executor {
    /// An executor of `kind` for robots at `starts` on `map`, staging `window` actions per plan.
    pub fn new(kind: ExecutorKind, map: &GridMap, starts: &[State], window: usize) -> Self {
        Executor {
            kind,
            window: window.max(1),
            queues: vec![VecDeque::new(); map.graph().num_vertices()],
            last: starts.iter().map(|s| s.vertex).collect(),
            predicted: starts.to_vec(),
            first: true,
        }
    }

    /// Stages `plan` (`plan[i]`: robot `i`'s actions, waits included) after what is staged,
    /// given the robots' true states `now`; returns where the robots will stand when the stages
    /// are done (the planner's next start).
    pub fn process_new_plan(
        &mut self,
        map: &GridMap,
        plan: &[Vec<Action>],
        staged: &mut [VecDeque<Action>],
        now: &[TickState],
    ) -> Vec<State> {
        let n = now.len();
        if self.first {
            for (i, s) in now.iter().enumerate() {
                let q = &mut self.queues[s.state.vertex as usize];
                if q.is_empty() {
                    q.push_back(i as u32);
                }
            }
            self.first = false;
        }
        for (i, s) in now.iter().enumerate() {
            self.last[i] = s.state.vertex;
        }
        let mut at = self.predicted.clone();
        let len = plan
            .iter()
            .map(Vec::len)
            .min()
            .unwrap_or(0)
            .min(self.window);
        for k in 0..len {
            for (i, row) in plan.iter().enumerate() {
                let a = row[k];
                if is_wait(a) {
                    continue;
                }
                let Some(next) = apply(map, at[i], a) else {
                    continue;
                };
                if next.vertex != at[i].vertex && self.kind == ExecutorKind::Tpg {
                    self.queues[next.vertex as usize].push_back(i as u32);
                }
                at[i] = next;
                staged[i].push_back(a);
            }
        }
        if self.kind == ExecutorKind::Naive {
            let mut at: Vec<State> = now.iter().map(|s| s.state).collect();
            for (i, stage) in staged.iter().enumerate() {
                for &a in stage {
                    at[i] = apply(map, at[i], a).unwrap_or(at[i]);
                }
            }
            self.predicted = at.clone();
            return at;
        }
        // The stage simulated without delays for `window` actions.
        let mut done = vec![0usize; n];
        let mut at: Vec<State> = now.iter().map(|s| s.state).collect();
        let mut rebuilt: Vec<(u32, u32)> = Vec::new();
        for t in 0..self.window {
            let before = at.clone();
            for i in 0..n {
                let Some(&a) = staged[i].get(done[i]) else {
                    continue;
                };
                let Some(next) = apply(map, at[i], a) else {
                    continue;
                };
                if next.vertex == at[i].vertex
                    || self.queues[next.vertex as usize].front() == Some(&(i as u32))
                {
                    at[i] = next;
                    done[i] += 1;
                }
            }
            for i in 0..n {
                if t == 0 {
                    rebuilt.push((before[i].vertex, i as u32));
                }
                if before[i].vertex != at[i].vertex {
                    let q = &mut self.queues[before[i].vertex as usize];
                    if q.front() == Some(&(i as u32)) {
                        q.pop_front();
                    }
                    rebuilt.push((at[i].vertex, i as u32));
                }
            }
        }
        for (stage, &d) in staged.iter_mut().zip(&done) {
            stage.truncate(d);
        }
        for q in &mut self.queues {
            q.clear();
        }
        for (v, i) in rebuilt {
            self.queues[v as usize].push_back(i);
        }
        self.predicted = at.clone();
        at
    }

    /// This tick's command per robot (`true` = go), given the robots' true states `now`.
    pub fn next_command(
        &mut self,
        map: &GridMap,
        staged: &[VecDeque<Action>],
        now: &[TickState],
    ) -> Vec<bool> {
        if self.kind == ExecutorKind::Naive {
            return staged.iter().map(|s| !s.is_empty()).collect();
        }
        for (i, s) in now.iter().enumerate() {
            let (was, is) = (self.last[i], s.state.vertex);
            if was != is {
                let q = &mut self.queues[was as usize];
                if q.front() == Some(&(i as u32)) {
                    q.pop_front();
                    self.last[i] = is;
                }
            }
        }
        now.iter()
            .zip(staged)
            .enumerate()
            .map(|(i, (s, stage))| match stage.front() {
                None => false,
                Some(&a) => match target(map, s, a) {
                    None => true,
                    Some(v) => {
                        let q = &self.queues[v as usize];
                        q.is_empty() || q.front() == Some(&(i as u32))
                    }
                },
            })
            .collect()
    }
}
