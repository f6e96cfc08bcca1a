//! The League of Robot Runners' output JSON, written from a trace and read back into one (start
//! kit v2.1.2, `src/CompetitionSystem.cpp` `saveResults`; `docs/lorr-semantics.md` §5), so that
//! the kit's viewer PlanViz plays mrpp's runs and `mrpp validate` judges the kit's.
//!
//! Written in the 2024 layout (`"version": "2024 LoRR"`, the one PlanViz 2.x and 3.x read), keys
//! in the kit's order: `actionModel`, `version`, `teamSize`, `numTaskFinished`, `makespan`,
//! `numPlannerErrors`, `numScheduleErrors`, `numEntryTimeouts`, `start` (`[row, col, "E"]`),
//! `actualPaths` and `plannerPaths` (one comma-separated letter per step and robot),
//! `plannerTimes` (seconds per call), `errors` (`[robot, robot, t, message]`), `actualSchedule`
//! and `plannerSchedule` (per robot `"t:task,t:task"`, `-1` for none), `scheduleErrors`
//! (`[task, robot, robot, t, message]`), `events` (`[t, robot, task, errands done]`) and `tasks`
//! (`[id, t revealed, [row, col, row, col, ...]]`). Like the kit it writes no `sumOfCost` (the
//! kit's documentation lists one, its code does not). `makespan` is, as in the kit, the most
//! steps any robot spent holding a task. Under `MAPF` the `actionModel` is `"MAPF"` and moves
//! are `U`, `D`, `L`, `R` as PlanViz reads them (`U` = row + 1; [`crate::model`]); the kit never
//! writes that model.

use std::path::Path;

use serde_json::{Value, json};

use mrpp_core::error::{Error, Result};

use crate::execution::{TickRecord, replay_ticks};
use crate::model::{Action, ActionModel};
use crate::model::{EAST, State};
use crate::problem::{Assign, LifelongProblem, ScheduleErrorRecord, StepError, Trace, replay};
use crate::ticks::{TickState, after_tick};

/// The `version` mrpp writes for runs in steps.
pub const VERSION: &str = "2024 LoRR";

/// The `version` mrpp writes for runs in ticks (the 2026 execution model).
pub const VERSION_2026: &str = "2026 LoRR";

/// Ticks per path segment in the 2026 layout (the kit's, fixed).
pub const SEGMENT: usize = 100;

/// LoRR's output JSON for `trace` on `problem` (module doc).
///
/// # Errors
/// The validator's message when `trace` breaks a rule (only valid traces are written).
pub fn to_json(problem: &LifelongProblem, trace: &Trace) -> std::result::Result<Value, String> {
    if let Some(record) = &trace.ticks {
        return to_json_2026(problem, trace, record);
    }
    let n = problem.starts().len();
    let mut held = vec![0u32; n];
    let sim = replay(problem, trace, |sim| {
        for (h, a) in held.iter_mut().zip(&sim.assignment) {
            *h += u32::from(a.is_some());
        }
    })
    .map_err(|e| e.to_string())?;
    let paths = |per_robot: &Vec<Vec<Action>>| -> Vec<String> {
        per_robot
            .iter()
            .map(|a| {
                a.iter()
                    .map(|x| x.letter().to_string())
                    .collect::<Vec<_>>()
                    .join(",")
            })
            .collect()
    };
    Ok(json!({
        "actionModel": problem.model().name(),
        "version": VERSION,
        "teamSize": n,
        "numTaskFinished": sim.finished,
        "makespan": held.iter().copied().max().unwrap_or(0),
        "numPlannerErrors": trace.errors.len(),
        "numScheduleErrors": trace.schedule_errors.len(),
        "numEntryTimeouts": trace.late_steps.len(),
        "start": starts_json(problem),
        "actualPaths": paths(&trace.actions),
        "plannerPaths": paths(&trace.planned),
        "plannerTimes": trace.planner_times,
        "errors": trace.errors.iter().map(|e| json!([e.agent1, e.agent2, e.t, e.message])).collect::<Vec<_>>(),
        "actualSchedule": schedules(&trace.schedule, n),
        "plannerSchedule": schedules(&trace.proposed_schedule, n),
        "scheduleErrors": trace.schedule_errors.iter().map(|e| json!([e.task, e.agent1, e.agent2, e.t, e.message])).collect::<Vec<_>>(),
        "events": sim.events.iter().map(|e| json!([e.t, e.agent, e.task, e.done])).collect::<Vec<_>>(),
        "tasks": tasks_json(problem, &sim),
    }))
}

/// Each robot's per-tick actions as the 2026 layout's segments: per [`SEGMENT`] ticks
/// `[(t0,row,col,orientation,counter):(A n,A n,...)]` (run-length pairs), the header holding the
/// robot's state at the segment's first tick (the kit writes segment 0's state in every header;
/// PlanViz ignores headers).
fn segments(
    problem: &LifelongProblem,
    record: &TickRecord,
    per_robot: &[Vec<Action>],
) -> Vec<String> {
    let map = problem.map();
    per_robot
        .iter()
        .zip(problem.starts())
        .map(|(actions, &start)| {
            let mut s = TickState::idle(State {
                vertex: start,
                orientation: EAST,
            });
            let mut out = String::new();
            for (k, chunk) in actions.chunks(SEGMENT).enumerate() {
                let (x, y) = map.cell(s.state.vertex);
                out.push_str(&format!(
                    "[({},{y},{x},{},{}):(",
                    k * SEGMENT,
                    s.state.orientation,
                    s.counter
                ));
                let mut runs: Vec<(char, usize)> = Vec::new();
                for &a in chunk {
                    match runs.last_mut() {
                        Some((c, count)) if *c == a.letter() => *count += 1,
                        _ => runs.push((a.letter(), 1)),
                    }
                    s = after_tick(map, s, a, record.agent_counter).unwrap_or(s);
                }
                let body: Vec<String> = runs.iter().map(|(c, k)| format!("{c} {k}")).collect();
                out.push_str(&body.join(","));
                out.push_str(")]");
            }
            out
        })
        .collect()
}

/// LoRR's 2026 output JSON (`"version": "2026 LoRR"`, start kit v3.1.0 `saveResults`; keys in
/// its order) for a run in ticks: `makespan` is the ticks run, paths are segments
/// ([`segments`]), `delayIntervals` per robot `[start, end]` (held during `start..end-1`),
/// `errors` every robot made to wait, every tick (the kit keeps only the last tick's).
fn to_json_2026(
    problem: &LifelongProblem,
    trace: &Trace,
    record: &TickRecord,
) -> std::result::Result<Value, String> {
    let n = problem.starts().len();
    let sim = replay_ticks(problem, trace, record, |_| {}).map_err(|e| e.to_string())?;
    Ok(json!({
        "actionModel": problem.model().name(),
        "version": VERSION_2026,
        "teamSize": n,
        "numTaskFinished": sim.finished,
        "makespan": trace.steps(),
        "numPlannerErrors": trace.errors.len(),
        "numScheduleErrors": trace.schedule_errors.len(),
        "numEntryTimeouts": record.entry_timeouts,
        "agentMaxCounter": record.agent_counter,
        "outputSegmentSize": SEGMENT,
        "delayIntervals": record.delays,
        "start": starts_json(problem),
        "actualPaths": segments(problem, record, &trace.actions),
        "events": sim.events.iter().map(|e| json!([e.t, e.agent, e.task, e.done])).collect::<Vec<_>>(),
        "tasks": tasks_json(problem, &sim),
        "plannerPaths": segments(problem, record, &trace.planned),
        "plannerTimes": trace.planner_times,
        "errors": trace.errors.iter().map(|e| json!([e.agent1, e.agent2, e.t, e.message])).collect::<Vec<_>>(),
        "actualSchedule": schedules(&trace.schedule, n),
        "plannerSchedule": schedules(&trace.proposed_schedule, n),
        "scheduleErrors": trace.schedule_errors.iter().map(|e| json!([e.task, e.agent1, e.agent2, e.t, e.message])).collect::<Vec<_>>(),
    }))
}

/// Per-tick actions of one robot's 2026 path string (segments; headers ignored).
///
/// # Errors
/// A message naming the segment: no `):(`, a pair that is not `letter count`, a letter outside
/// the model.
fn parse_segments(model: ActionModel, s: &str) -> std::result::Result<Vec<Action>, String> {
    let mut out = Vec::new();
    for (k, seg) in s
        .split(']')
        .map(str::trim)
        .filter(|x| !x.is_empty())
        .enumerate()
    {
        let body = seg
            .split_once("):(")
            .map(|(_, b)| b.trim_end_matches(')'))
            .ok_or_else(|| format!("segment {} has no `):(`", k + 1))?;
        for pair in body.split(',').map(str::trim).filter(|x| !x.is_empty()) {
            let bad = || format!("segment {}: `{pair}` is not `letter count`", k + 1);
            let (letter, count) = pair.split_once(' ').ok_or_else(bad)?;
            let count: usize = count.trim().parse().map_err(|_| bad())?;
            let mut chars = letter.chars();
            let action = match (chars.next(), chars.next()) {
                (Some(c), None) => Action::from_letter(model, c),
                _ => None,
            }
            .ok_or_else(|| {
                format!(
                    "segment {}: `{letter}` is not a {} action",
                    k + 1,
                    model.name()
                )
            })?;
            if out.len() + count > 10_000_000 {
                return Err(format!("segment {}: more than 10,000,000 ticks", k + 1));
            }
            out.extend(std::iter::repeat_n(action, count));
        }
    }
    Ok(out)
}

/// Per robot, its schedule changes as the kit writes them: `"t:task,t:task"`, `-1` for none.
fn schedules(changes: &[Assign], n: usize) -> Vec<String> {
    let mut per = vec![Vec::new(); n];
    for c in changes {
        per[c.agent].push(format!("{}:{}", c.t, c.task.map_or(-1, |k| k as i64)));
    }
    per.into_iter().map(|v| v.join(",")).collect()
}

/// `start`: `[row, col, "E"]` per robot (every robot starts facing east).
fn starts_json(problem: &LifelongProblem) -> Vec<Value> {
    let map = problem.map();
    problem
        .starts()
        .iter()
        .map(|&v| {
            let (x, y) = map.cell(v);
            json!([y, x, "E"])
        })
        .collect()
}

/// `tasks`: `[id, t revealed, [row, col, row, col, ...]]` per revealed task.
fn tasks_json(problem: &LifelongProblem, sim: &crate::sim::Simulation<'_>) -> Vec<Value> {
    let map = problem.map();
    sim.tasks
        .iter()
        .map(|t| {
            let cells: Vec<u32> = t
                .errands
                .iter()
                .flat_map(|&v| {
                    let (x, y) = map.cell(v);
                    [y, x]
                })
                .collect();
            json!([t.id, t.revealed, cells])
        })
        .collect()
}

/// What an output JSON says besides its trace, for comparing with a replay.
#[derive(Debug, Clone, PartialEq)]
pub struct Claims {
    /// The file's action model.
    pub model: ActionModel,
    /// Its `numTaskFinished`.
    pub tasks_finished: u64,
}

/// Reads LoRR's output JSON (`text`, from `path`) back into a trace for `problem` (whose action
/// model must be the file's: see [`model_of`]). Steps on which every robot's executed action is
/// `T` are the kit's late steps. A task's finish frees its robot without an `actualSchedule`
/// entry, as in the kit (which writes a `-1` only when a later schedule differs from the last
/// value it wrote; applying it then changes nothing).
///
/// # Errors
/// The file and rule: not JSON, a missing or mistyped key, a path of another robot count or
/// length, a letter outside the model, a malformed schedule entry.
pub fn from_json(problem: &LifelongProblem, text: &str, path: &Path) -> Result<(Trace, Claims)> {
    let json: Value = serde_json::from_str(text.trim_start_matches('\u{feff}'))
        .map_err(|e| Error::parse(path, e.line(), format!("not a LoRR output JSON: {e}")))?;
    let model = model_of(&json, path)?;
    let n = problem.starts().len();
    let team = json
        .get("teamSize")
        .and_then(Value::as_u64)
        .ok_or_else(|| Error::invalid(path, "no `teamSize` (an integer)"))?;
    if team != n as u64 {
        return Err(Error::invalid(
            path,
            format!("`teamSize` is {team}, the problem has {n} robots"),
        ));
    }
    let in_ticks = json.get("version").and_then(Value::as_str) == Some(VERSION_2026);
    let paths = |key: &str| -> Result<Option<Vec<Vec<Action>>>> {
        let Some(v) = json.get(key) else {
            return Ok(None);
        };
        let list = v
            .as_array()
            .filter(|l| l.len() == n)
            .ok_or_else(|| Error::invalid(path, format!("`{key}` must list {n} paths")))?;
        list.iter()
            .enumerate()
            .map(|(i, p)| {
                let s = p
                    .as_str()
                    .ok_or_else(|| Error::invalid(path, format!("`{key}`[{i}] is not a string")))?;
                if in_ticks {
                    return parse_segments(model, s)
                        .map_err(|e| Error::invalid(path, format!("`{key}`[{i}]: {e}")));
                }
                s.split(',')
                    .filter(|l| !l.is_empty())
                    .enumerate()
                    .map(|(k, l)| {
                        let c = l.trim();
                        let mut chars = c.chars();
                        match (chars.next(), chars.next()) {
                            (Some(ch), None) => Action::from_letter(model, ch),
                            _ => None,
                        }
                        .ok_or_else(|| {
                            Error::invalid(
                                path,
                                format!(
                                    "`{key}`[{i}], step {}: `{c}` is not a {} action",
                                    k + 1,
                                    model.name()
                                ),
                            )
                        })
                    })
                    .collect()
            })
            .collect::<Result<Vec<Vec<Action>>>>()
            .map(Some)
    };
    let actions = paths("actualPaths")?.ok_or_else(|| {
        Error::invalid(path, "no `actualPaths`: run the kit with --outputScreen 1")
    })?;
    let steps = actions.first().map_or(0, Vec::len);
    if let Some(i) = actions.iter().position(|a| a.len() != steps) {
        return Err(Error::invalid(
            path,
            format!(
                "`actualPaths`[{i}] has {} steps, [0] has {steps}",
                actions[i].len()
            ),
        ));
    }
    let planned = paths("plannerPaths")?.unwrap_or_else(|| actions.clone());
    let late_steps = (0..steps)
        .filter(|&k| !in_ticks && n > 0 && actions.iter().all(|a| a[k] == Action::NoAction))
        .map(|k| k as u32)
        .collect();
    // The kit v3.1.0 stamps the first assignment with its task manager's clock before that
    // clock is set (an uninitialised int, e.g. 741946930 or -1350986528); the first plan is
    // applied at tick 0, so in the 2026 layout a first entry outside the run is read as 0
    // (docs/lorr-semantics.md §5).
    let first_past = in_ticks.then(|| json.get("makespan").and_then(Value::as_u64).unwrap_or(0));
    let schedule = schedule_changes(&json, "actualSchedule", n, path, first_past)?;
    let proposed_schedule = schedule_changes(&json, "plannerSchedule", n, path, first_past)?;
    let planner_times = json
        .get("plannerTimes")
        .and_then(Value::as_array)
        .map(|l| l.iter().filter_map(Value::as_f64).collect())
        .unwrap_or_default();
    let tuple = |v: &Value, k: usize| v.get(k).and_then(Value::as_i64).unwrap_or(-1);
    let text_at = |v: &Value, k: usize| v.get(k).and_then(Value::as_str).unwrap_or("").to_string();
    let list = |key: &str| {
        json.get(key)
            .and_then(Value::as_array)
            .cloned()
            .unwrap_or_default()
    };
    let errors = list("errors")
        .iter()
        .map(|e| StepError {
            agent1: tuple(e, 0),
            agent2: tuple(e, 1),
            t: tuple(e, 2).max(0) as u32,
            message: text_at(e, 3),
        })
        .collect();
    let schedule_errors = list("scheduleErrors")
        .iter()
        .map(|e| ScheduleErrorRecord {
            task: tuple(e, 0),
            agent1: tuple(e, 1),
            agent2: tuple(e, 2),
            t: tuple(e, 3).max(0) as u32,
            message: text_at(e, 4),
        })
        .collect();
    let tasks_finished = json
        .get("numTaskFinished")
        .and_then(Value::as_u64)
        .ok_or_else(|| Error::invalid(path, "no `numTaskFinished` (an integer)"))?;
    let trace = Trace {
        actions,
        planned,
        schedule,
        proposed_schedule,
        late_steps,
        planner_times,
        errors,
        schedule_errors,
        preprocess_time: 0.0,
        ticks: in_ticks
            .then(|| tick_record(problem, &json, n, path))
            .transpose()?,
    };
    Ok((
        trace,
        Claims {
            model,
            tasks_finished,
        },
    ))
}

/// The tick record of a 2026 output JSON: `agentMaxCounter` (default 10), `delayIntervals`,
/// `numEntryTimeouts`, and the footprint of the problem (`agentSize`, default 1; the output
/// does not say).
fn tick_record(
    problem: &LifelongProblem,
    json: &Value,
    n: usize,
    path: &Path,
) -> Result<TickRecord> {
    let agent_counter = json
        .get("agentMaxCounter")
        .and_then(Value::as_u64)
        .unwrap_or(10)
        .clamp(1, 1000) as u32;
    let agent_size = match problem.execution() {
        Some(m) => m.agent_size,
        None => crate::execution::ExecutionModel::of_problem(problem.files())?.agent_size,
    };
    let mut delays = vec![Vec::new(); n];
    if let Some(list) = json.get("delayIntervals").and_then(Value::as_array) {
        if list.len() != n {
            return Err(Error::invalid(
                path,
                format!(
                    "`delayIntervals` lists {} robots, the problem has {n}",
                    list.len()
                ),
            ));
        }
        for (i, per) in list.iter().enumerate() {
            for iv in per.as_array().into_iter().flatten() {
                let pair = iv
                    .as_array()
                    .and_then(|p| Some([p.first()?.as_u64()?, p.get(1)?.as_u64()?]));
                match pair {
                    Some([a, b]) if a < b => delays[i].push([a, b]),
                    _ => {
                        return Err(Error::invalid(
                            path,
                            format!(
                                "`delayIntervals`[{i}]: `{iv}` is not [start, end] with start < end"
                            ),
                        ));
                    }
                }
            }
        }
    }
    Ok(TickRecord {
        agent_counter,
        agent_size,
        delays,
        entry_timeouts: json
            .get("numEntryTimeouts")
            .and_then(Value::as_u64)
            .unwrap_or(0) as u32,
        executor: String::new(),
        plan_every: 0,
    })
}

/// The action model an output JSON declares (`actionModel`).
///
/// # Errors
/// No `actionModel`, or one other than `MAPF` and `MAPF_T`.
pub fn model_of(json: &Value, path: &Path) -> Result<ActionModel> {
    let name = json
        .get("actionModel")
        .and_then(Value::as_str)
        .ok_or_else(|| Error::invalid(path, "no `actionModel` (a string): not a LoRR output"))?;
    ActionModel::parse(name).ok_or_else(|| {
        Error::invalid(
            path,
            format!("`actionModel` is `{name}`: expected `MAPF_T` or `MAPF`"),
        )
    })
}

/// Per-robot `"t:task,t:task"` strings as changes in time order (robot order within a step).
fn schedule_changes(
    json: &Value,
    key: &str,
    n: usize,
    path: &Path,
    first_past: Option<u64>,
) -> Result<Vec<Assign>> {
    let Some(v) = json.get(key) else {
        return Ok(Vec::new());
    };
    let list = v
        .as_array()
        .filter(|l| l.len() == n)
        .ok_or_else(|| Error::invalid(path, format!("`{key}` must list {n} schedules")))?;
    let mut out = Vec::new();
    for (agent, s) in list.iter().enumerate() {
        let s = s
            .as_str()
            .ok_or_else(|| Error::invalid(path, format!("`{key}`[{agent}] is not a string")))?;
        for (k, entry) in s.split(',').filter(|e| !e.trim().is_empty()).enumerate() {
            let bad = || {
                Error::invalid(
                    path,
                    format!("`{key}`[{agent}]: `{entry}` is not `step:task`"),
                )
            };
            let (t, task) = entry.trim().split_once(':').ok_or_else(bad)?;
            let t: i64 = t.trim().parse().map_err(|_| bad())?;
            let t = match first_past {
                Some(end) if k == 0 && (t < 0 || t as u64 > end) => 0,
                _ => u32::try_from(t).map_err(|_| bad())?,
            };
            let task: i64 = task.parse().map_err(|_| bad())?;
            out.push(Assign {
                t,
                agent,
                task: usize::try_from(task).ok(),
            });
        }
    }
    out.sort_by_key(|c| (c.t, c.agent));
    Ok(out)
}
