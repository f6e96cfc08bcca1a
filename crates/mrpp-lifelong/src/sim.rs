//! The League of Robot Runners' system state and its step (start kit v2.1.2,
//! `src/CompetitionSystem.cpp`, `src/ActionModel.cpp`, `src/TaskManager.cpp`;
//! `docs/lorr-semantics.md` §2-§3): robots' states, the task pool, the assignment, and the rules
//! that judge a joint action and a schedule.
//!
//! One step, as the kit runs it: the planner's joint action is checked ([`Simulation::check_actions`]:
//! agents in index order, the first violation wins: an action outside the model or a move off the
//! map or into an obstacle, then a vertex conflict with an earlier agent, then a swap with an
//! earlier agent; following and rotating cycles are allowed) and applied, or every robot waits;
//! the clock advances; then the task update at the new time: the proposed schedule is checked
//! ([`Simulation::check_schedule`]) and applied, or the old assignment is kept; every robot
//! standing on its task's next errand completes it (one errand per robot per step); a task whose
//! last errand is done is finished and its robot freed; and new tasks are revealed until
//! `numTasksReveal x teamSize` are open, task `k` being line `k mod m` of the task file (the file
//! is cycled). A late planner's step ([`Simulation::idle_step`]) moves nobody and updates no task.
//!
//! The same state machine runs a lifelong planner ([`crate::runner`]) and replays a trace for the
//! validator ([`crate::LifelongProblem`]), so a trace is judged by the rules it was run under.

use std::collections::BTreeSet;

use mrpp_core::mapf::graph::VertexId;

use crate::model::{Action, EAST, State, apply};
use crate::problem::LifelongProblem;

/// A revealed task.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Task {
    /// Id: the order of reveal (0, 1, 2, ...).
    pub id: usize,
    /// Errand vertices, in the order they must be visited.
    pub errands: Vec<VertexId>,
    /// Step at which it was revealed.
    pub revealed: u32,
    /// Errands done so far (the index of the next errand).
    pub done: usize,
    /// The robot it is assigned to.
    pub agent: Option<usize>,
    /// Step at which its last errand was done.
    pub finished: Option<u32>,
}

/// An errand completed: `[t, agent, task, errands done]` in LoRR's `events`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Event {
    /// The step count after the move that brought the robot there.
    pub t: u32,
    /// The robot.
    pub agent: usize,
    /// The task id.
    pub task: usize,
    /// Errands of the task done with this one (1-based; the task's length when it finishes).
    pub done: usize,
}

/// Why a joint action was refused (the kit's messages, [`ActionError::message`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ActionError {
    /// Not one action per robot.
    Size,
    /// An action outside the model, a move off the map or into an obstacle.
    Unallowed { agent: usize },
    /// Two robots on one cell after the step (`agent` and the earlier `other`).
    Vertex { agent: usize, other: usize },
    /// Two robots swap cells (`agent` and the earlier `other`).
    Edge { agent: usize, other: usize },
}

impl ActionError {
    /// The kit's message.
    pub fn message(self) -> &'static str {
        match self {
            ActionError::Size => "incorrect vector size",
            ActionError::Unallowed { .. } => "unallowed move",
            ActionError::Vertex { .. } => "vertex conflict",
            ActionError::Edge { .. } => "edge conflict",
        }
    }

    /// The two robots of LoRR's error tuple (`-1` for none).
    pub fn agents(self) -> (i64, i64) {
        match self {
            ActionError::Size => (-1, -1),
            ActionError::Unallowed { agent } => (agent as i64, -1),
            ActionError::Vertex { agent, other } | ActionError::Edge { agent, other } => {
                (agent as i64, other as i64)
            }
        }
    }
}

/// Why a schedule was refused (the kit's messages, [`ScheduleError::message`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScheduleError {
    /// Not one entry per robot.
    Size,
    /// A task that is not open (never revealed, or finished).
    NotOpen { agent: usize, task: usize },
    /// One task for two robots (`agent` and the earlier `other`).
    Twice {
        agent: usize,
        other: usize,
        task: usize,
    },
    /// A robot that has done an errand of its task must keep it until it is finished.
    Locked { agent: usize, task: usize },
}

impl ScheduleError {
    /// The kit's message.
    pub fn message(self) -> &'static str {
        match self {
            ScheduleError::Size => "Invalid schedule size",
            ScheduleError::NotOpen { .. } => "task already finished",
            ScheduleError::Twice { .. } => {
                "task is already assigned by the second agent at the same time"
            }
            ScheduleError::Locked { .. } => "task is already opened by the second agent",
        }
    }

    /// `(task, agent1, agent2)` of LoRR's schedule error tuple (`-1` for none).
    pub fn ids(self) -> (i64, i64, i64) {
        match self {
            ScheduleError::Size => (-1, -1, -1),
            ScheduleError::NotOpen { agent, task } | ScheduleError::Locked { agent, task } => {
                (task as i64, agent as i64, -1)
            }
            ScheduleError::Twice { agent, other, task } => {
                (task as i64, agent as i64, other as i64)
            }
        }
    }
}

/// The system state of a lifelong run (module doc).
#[derive(Debug, Clone)]
pub struct Simulation<'p> {
    problem: &'p LifelongProblem,
    /// Steps executed so far (timeout steps included).
    pub t: u32,
    /// Each robot's state.
    pub states: Vec<State>,
    /// Every revealed task, by id.
    pub tasks: Vec<Task>,
    /// Ids of the open (revealed, unfinished) tasks, ascending.
    pub open: BTreeSet<usize>,
    /// Each robot's task.
    pub assignment: Vec<Option<usize>>,
    /// Every errand completed, in order.
    pub events: Vec<Event>,
    /// Tasks finished.
    pub finished: usize,
    /// Per vertex: the robot on it (`usize::MAX`: none); scratch for [`Self::check_actions`].
    on: Vec<usize>,
    next_on: Vec<usize>,
}

const NONE: usize = usize::MAX;

impl<'p> Simulation<'p> {
    /// The state at step 0: robots on their starts facing east, no assignment, the first
    /// `numTasksReveal x teamSize` tasks revealed.
    pub fn new(problem: &'p LifelongProblem) -> Self {
        let n = problem.map().graph().num_vertices();
        let states: Vec<State> = problem
            .starts()
            .iter()
            .map(|&vertex| State {
                vertex,
                orientation: EAST,
            })
            .collect();
        let mut on = vec![NONE; n];
        for (i, s) in states.iter().enumerate() {
            on[s.vertex as usize] = i;
        }
        let mut sim = Simulation {
            problem,
            t: 0,
            assignment: vec![None; states.len()],
            states,
            tasks: Vec::new(),
            open: BTreeSet::new(),
            events: Vec::new(),
            finished: 0,
            on,
            next_on: vec![NONE; n],
        };
        sim.reveal();
        sim
    }

    /// The problem being run.
    pub fn problem(&self) -> &'p LifelongProblem {
        self.problem
    }

    /// The next errand of robot `i`'s task, if it has one.
    pub fn goal(&self, i: usize) -> Option<VertexId> {
        self.assignment[i].map(|k| {
            let task = &self.tasks[k];
            task.errands[task.done]
        })
    }

    /// The robots' states after `actions`, or the first rule it breaks (module doc).
    ///
    /// # Errors
    /// [`ActionError`] for the first robot, in index order, whose action breaks a rule.
    pub fn check_actions(&mut self, actions: &[Action]) -> Result<Vec<State>, ActionError> {
        if actions.len() != self.states.len() {
            return Err(ActionError::Size);
        }
        let model = self.problem.model();
        let map = self.problem.map();
        let mut next = Vec::with_capacity(actions.len());
        let mut result = Ok(());
        for (i, (&s, &a)) in self.states.iter().zip(actions).enumerate() {
            let Some(to) = a.belongs_to(model).then(|| apply(map, s, a)).flatten() else {
                result = Err(ActionError::Unallowed { agent: i });
                break;
            };
            let taken = self.next_on[to.vertex as usize];
            if taken != NONE {
                result = Err(ActionError::Vertex {
                    agent: i,
                    other: taken,
                });
                break;
            }
            let j = self.on[to.vertex as usize];
            if j != NONE && j < i && to.vertex != s.vertex && next_of(&next, j) == Some(s.vertex) {
                result = Err(ActionError::Edge { agent: i, other: j });
                break;
            }
            self.next_on[to.vertex as usize] = i;
            next.push(to);
        }
        for s in &next {
            self.next_on[s.vertex as usize] = NONE;
        }
        result.map(|()| next)
    }

    /// Moves the robots to `next` (states [`Self::check_actions`] returned) and advances the clock.
    pub fn step(&mut self, next: Vec<State>) {
        for s in &self.states {
            self.on[s.vertex as usize] = NONE;
        }
        for (i, s) in next.iter().enumerate() {
            self.on[s.vertex as usize] = i;
        }
        self.states = next;
        self.t += 1;
    }

    /// A late planner's step: nobody moves, no task update, the clock advances.
    pub fn idle_step(&mut self) {
        self.t += 1;
    }

    /// Checks a proposed assignment (robot -> task id) against the kit's rules (module doc).
    ///
    /// # Errors
    /// [`ScheduleError`] for the first robot, in index order, whose entry breaks a rule.
    pub fn check_schedule(&self, schedule: &[Option<usize>]) -> Result<(), ScheduleError> {
        if schedule.len() != self.states.len() {
            return Err(ScheduleError::Size);
        }
        let mut holder: rustc_hash::FxHashMap<usize, usize> = rustc_hash::FxHashMap::default();
        for (i, &proposal) in schedule.iter().enumerate() {
            if let Some(k) = proposal {
                if !self.open.contains(&k) {
                    return Err(ScheduleError::NotOpen { agent: i, task: k });
                }
                if let Some(&other) = holder.get(&k) {
                    return Err(ScheduleError::Twice {
                        agent: i,
                        other,
                        task: k,
                    });
                }
                holder.insert(k, i);
            }
            if let Some(held) = self.assignment[i]
                && self.tasks[held].done > 0
                && proposal != Some(held)
            {
                return Err(ScheduleError::Locked {
                    agent: i,
                    task: held,
                });
            }
        }
        Ok(())
    }

    /// The task update at the current step: applies `schedule` (already checked; `None` keeps
    /// the assignment), completes errands, finishes tasks and reveals new ones. Returns the
    /// robots whose task changed with the schedule, as `(robot, task)`.
    pub fn update_tasks(
        &mut self,
        schedule: Option<&[Option<usize>]>,
    ) -> Vec<(usize, Option<usize>)> {
        let changed = schedule.map_or_else(Vec::new, |s| self.apply_schedule(s));
        self.complete_and_reveal();
        changed
    }

    /// Applies `schedule` (already checked): each robot's task. Returns the robots whose task
    /// changed, as `(robot, task)`.
    pub fn apply_schedule(&mut self, schedule: &[Option<usize>]) -> Vec<(usize, Option<usize>)> {
        let mut changed = Vec::new();
        for (i, &proposal) in schedule.iter().enumerate() {
            if self.assignment[i] != proposal {
                if let Some(old) = self.assignment[i]
                    && self.tasks[old].agent == Some(i)
                {
                    self.tasks[old].agent = None;
                }
                changed.push((i, proposal));
            }
        }
        for &(i, proposal) in &changed {
            self.assignment[i] = proposal;
            if let Some(k) = proposal {
                self.tasks[k].agent = Some(i);
            }
        }
        changed
    }

    /// Completes the errands robots stand on (one per robot), finishes tasks, frees their
    /// robots and reveals new tasks. Returns the robots that finished a task.
    pub fn complete_and_reveal(&mut self) -> Vec<usize> {
        let mut freed = Vec::new();
        for i in 0..self.states.len() {
            let Some(k) = self.assignment[i] else {
                continue;
            };
            let task = &mut self.tasks[k];
            if task.errands[task.done] != self.states[i].vertex {
                continue;
            }
            task.done += 1;
            self.events.push(Event {
                t: self.t,
                agent: i,
                task: k,
                done: task.done,
            });
            if task.done == task.errands.len() {
                task.finished = Some(self.t);
                task.agent = None;
                self.assignment[i] = None;
                self.open.remove(&k);
                self.finished += 1;
                freed.push(i);
            }
        }
        self.reveal();
        freed
    }

    /// Reveals tasks until the pool is full.
    fn reveal(&mut self) {
        let file = self.problem.task_file();
        while self.open.len() < self.problem.reveal_pool() {
            let id = self.tasks.len();
            self.tasks.push(Task {
                id,
                errands: file[id % file.len()].clone(),
                revealed: self.t,
                done: 0,
                agent: None,
                finished: None,
            });
            self.open.insert(id);
        }
    }
}

/// Agent `j`'s next vertex, if decided (agents before the current one are).
fn next_of(next: &[State], j: usize) -> Option<VertexId> {
    next.get(j).map(|s| s.vertex)
}
