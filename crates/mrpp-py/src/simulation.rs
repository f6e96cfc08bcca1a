//! `mrpp._native.Simulation`: a lifelong run driven step by step from Python (issue 28, item 9),
//! so that a Python planner or learned policy plays the League of Robot Runners' loop. The run is
//! mrpp's own [`Run`] (the kit's rules; the same code as `mrpp solve -P lifelong-pibt`): each
//! step the caller gives one action per robot and, optionally, each robot's task; the joint
//! action is checked before anything is executed, so a refused step changes nothing.

use std::time::Duration;

use pyo3::prelude::*;
use serde_json::{Value, json};

use mrpp_cli::api;
use mrpp_core::Deadline;
use mrpp_lifelong::distances::{DEFAULT_BUDGET, Distances, TableKind};
use mrpp_lifelong::lorr_output::to_json;
use mrpp_lifelong::runner::Run;
use mrpp_lifelong::scheduler::{Scheduler, SchedulerKind};
use mrpp_lifelong::{Action, LifelongProblem};

use crate::{MrppError, inputs};

self_cell::self_cell!(
    /// The problem and the run that borrows it.
    struct Cell {
        owner: LifelongProblem,
        #[covariant]
        dependent: Run,
    }
);

/// A lifelong run in progress (see the Python class `mrpp.Simulation`).
#[pyclass(module = "mrpp._native")]
pub struct Simulation {
    cell: Cell,
    dist: Distances,
}

#[pymethods]
impl Simulation {
    /// Step 0 of the lifelong problem the inputs name (JSON, as `load`).
    #[new]
    fn new(inputs_json: &str) -> PyResult<Self> {
        let problem = api::load_lifelong(&inputs(inputs_json)?).map_err(MrppError::new_err)?;
        let vertices = problem.map().graph().num_vertices();
        let robots = problem.starts().len();
        Ok(Simulation {
            cell: Cell::new(problem, |p| Run::new(p)),
            // The planners' default (`distance_tables=auto`): Manhattan distances where 4 GiB of
            // tables would not hold twice the robots' goals.
            dist: Distances::of_kind(TableKind::Auto, vertices, robots, DEFAULT_BUDGET),
        })
    }

    /// The map: `(width, height, free)` with `free[y * width + x]` true on a free cell.
    fn grid(&self) -> (usize, usize, Vec<bool>) {
        let map = self.cell.borrow_owner().map();
        let (w, h) = (map.width() as usize, map.height() as usize);
        let free = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .map(|(x, y)| map.vertex_at(x as i64, y as i64).is_some())
            .collect();
        (w, h, free)
    }

    /// The state as JSON text (the Python class documents the fields).
    fn state(&self) -> String {
        let run = self.cell.borrow_dependent();
        let sim = &run.sim;
        let map = self.cell.borrow_owner().map();
        let xy = |v| {
            let (x, y) = map.cell(v);
            json!([x, y])
        };
        let robots: Vec<Value> = sim
            .states
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let (x, y) = map.cell(s.vertex);
                json!({
                    "x": x,
                    "y": y,
                    "orientation": s.orientation,
                    "task": sim.assignment[i],
                    "goal": sim.goal(i).map(xy),
                })
            })
            .collect();
        let open: Vec<Value> = sim
            .open
            .iter()
            .map(|&k| {
                let t = &sim.tasks[k];
                json!({
                    "id": t.id,
                    "errands": t.errands.iter().map(|&v| xy(v)).collect::<Vec<_>>(),
                    "done": t.done,
                    "agent": t.agent,
                    "revealed": t.revealed,
                })
            })
            .collect();
        json!({
            "t": sim.t,
            "steps": self.cell.borrow_owner().steps(),
            "action_model": self.cell.borrow_owner().model().name(),
            "robots": robots,
            "open_tasks": open,
            "tasks_finished": sim.finished,
            "errands_done": sim.events.len(),
        })
        .to_string()
    }

    /// Executes one step: `actions` one letter per robot, `schedule` each robot's task id (or
    /// None) or None to keep the assignment. Refused (MrppError, nothing executed): a letter
    /// outside the action model, a count other than one per robot, a step beyond the horizon,
    /// a joint action that breaks a rule (the message names the rule and both robots).
    #[pyo3(signature = (actions, schedule=None))]
    fn step(&mut self, actions: Vec<String>, schedule: Option<Vec<Option<usize>>>) -> PyResult<()> {
        self.cell.with_dependent_mut(|problem, run| {
            if run.sim.t >= problem.steps() {
                return Err(MrppError::new_err(format!(
                    "the run is over: its horizon is {} steps",
                    problem.steps()
                )));
            }
            let model = problem.model();
            let actions = actions
                .iter()
                .enumerate()
                .map(|(i, a)| {
                    let mut chars = a.chars();
                    match (chars.next(), chars.next()) {
                        (Some(c), None) if c != 'T' => Action::from_letter(model, c),
                        _ => None,
                    }
                    .ok_or_else(|| {
                        MrppError::new_err(format!(
                            "robot {i}: {a:?} is not an action of the {} model ({})",
                            model.name(),
                            letters(model)
                        ))
                    })
                })
                .collect::<PyResult<Vec<Action>>>()?;
            let proposal = schedule.unwrap_or_else(|| run.sim.assignment.clone());
            run.trace.planner_times.push(0.0);
            run.advance(&actions, &proposal).map_err(|e| {
                run.trace.planner_times.pop();
                MrppError::new_err(e.to_string())
            })
        })
    }

    /// A proposed assignment (each robot's task id or None) by mrpp's scheduler `kind`
    /// (`greedy`: the start kit's; `hungarian`; `matching`), within `time_limit` seconds;
    /// a task costs d(robot, next errand) + `chain_weight` x its later errands' distances
    /// (1: the start kit's cost; 0: pickup distance only). Distances are breadth-first hop
    /// counts, or Manhattan distances on maps where 4 GiB of tables would not hold twice the
    /// robots' goals (the planners' `distance_tables=auto`).
    #[pyo3(signature = (kind="greedy", time_limit=0.5, chain_weight=1.0))]
    fn schedule(
        &mut self,
        kind: &str,
        time_limit: f64,
        chain_weight: f64,
    ) -> PyResult<Vec<Option<usize>>> {
        let kind = match kind {
            "greedy" => SchedulerKind::Greedy,
            "hungarian" => SchedulerKind::Hungarian,
            "matching" => SchedulerKind::Matching,
            _ => {
                return Err(MrppError::new_err(format!(
                    "unknown scheduler {kind:?}: greedy, hungarian or matching"
                )));
            }
        };
        if !(time_limit.is_finite() && time_limit > 0.0) {
            return Err(MrppError::new_err(format!(
                "time_limit must be a positive number of seconds, got {time_limit}"
            )));
        }
        if !(0.0..=10.0).contains(&chain_weight) {
            return Err(MrppError::new_err(format!(
                "chain_weight must be between 0 and 10, got {chain_weight}"
            )));
        }
        let run = self.cell.borrow_dependent();
        let scheduler = Scheduler {
            chain_weight,
            ..Scheduler::new(kind)
        };
        Ok(scheduler.propose(
            &run.sim,
            &mut self.dist,
            Deadline::after(Duration::from_secs_f64(time_limit.min(1e6))),
        ))
    }

    /// The run so far as the League's output JSON text (what `mrpp solve` writes for a
    /// lifelong run, without mrpp's record): `mrpp validate`, `mrpp view` and PlanViz read it.
    fn to_json(&self) -> PyResult<String> {
        let run = self.cell.borrow_dependent();
        to_json(self.cell.borrow_owner(), &run.trace)
            .map(|v| v.to_string())
            .map_err(MrppError::new_err)
    }
}

fn letters(model: mrpp_lifelong::ActionModel) -> &'static str {
    match model {
        mrpp_lifelong::ActionModel::MapfT => "F, R, C, W",
        mrpp_lifelong::ActionModel::Mapf => {
            "R = x+1, U = y+1, L = x-1, D = y-1 (PlanViz's letters), W"
        }
    }
}
