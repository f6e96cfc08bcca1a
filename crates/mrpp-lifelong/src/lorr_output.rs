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
//!
//! A one-shot grid plan (MAPF: each agent goes from its start to one goal and stays) is written
//! in the same layout for PlanViz by [`one_shot_to_json`] and read back by
//! [`one_shot_from_json`]: `actionModel` `"MAPF"`, each agent's single goal its task (task `i`
//! for agent `i`, one errand, revealed and assigned at step 0, finished when the agent last
//! arrives), paths padded with `W` to the makespan. Checked against PlanViz commit `c03a1d6`
//! (MAPF-Competition/PlanViz, 2026-04-14, the 3.x line): `script/run.py` picks its 2024 loader
//! (`PlanConfig2024`) for `"version": "2024 LoRR"`; that loader needs `teamSize`, `makespan`,
//! `actionModel`, `start` (`[row, col, "E"]`: integers, then a key of its `DIRECTION`),
//! `actualPaths` and `plannerPaths` (one string per agent, comma-separated letters),
//! `tasks` (`[id, t, [row, col]]`, at least one: `load_events` asserts it), `actualSchedule`
//! (per agent a non-empty `"t:task"` list whose tasks are in `tasks`) and `events` (`[t, agent,
//! task, errands done]`); `errors` and `scheduleErrors` may be empty.

use std::path::Path;

use serde_json::{Value, json};

use mrpp_core::error::{Error, Result};
use mrpp_core::mapf::graph::VertexId;
use mrpp_core::mapf::plan::{GoalSemantics, path_cost};
use mrpp_core::{Instance, Plan};
use mrpp_mapf::GridMap;
use mrpp_mapf::lorr_files::LorrFiles;

use crate::execution::{TickRecord, replay_ticks};
use crate::model::{Action, ActionModel, apply, direction};
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

/// The lifelong problem a one-shot grid instance stands for (module doc): robots on the starts,
/// task `i` the single errand `goals[i]`, one task open per robot, `steps` steps (at least 1).
/// File names are made up (`one-shot.*`).
fn one_shot_problem(
    map: &GridMap,
    starts: &[VertexId],
    goals: &[VertexId],
    steps: u32,
) -> LifelongProblem {
    let files = LorrFiles {
        path: "one-shot.json".into(),
        map_path: "one-shot.map".into(),
        agent_path: "one-shot.agents".into(),
        task_path: "one-shot.tasks".into(),
        map: map.clone(),
        start_lines: (1..=starts.len()).collect(),
        starts: starts.to_vec(),
        task_lines: (1..=goals.len()).collect(),
        tasks: goals.iter().map(|&g| vec![g]).collect(),
        num_tasks_reveal: 1.0,
        version: VERSION.into(),
        json: Value::Null,
    };
    LifelongProblem::new(
        files,
        ActionModel::Mapf,
        steps,
        std::time::Duration::from_secs(1),
    )
}

/// PlanViz's JSON of a one-shot grid plan (module doc): `plan` on `map` for `inst`, each path
/// starting on its agent's start and ending on its goal (trailing waits carry nothing and are
/// padded back with `W`).
///
/// # Errors
/// A path that does not end on its goal, or a step that is neither a wait nor a move to a
/// 4-neighbour (naming agent and step).
pub fn one_shot_to_json(
    map: &GridMap,
    inst: &Instance,
    plan: &Plan,
) -> std::result::Result<Value, String> {
    let n = inst.num_agents();
    if plan.paths.len() != n {
        return Err(format!(
            "the plan has {} paths for {n} agents",
            plan.paths.len()
        ));
    }
    let mut costs = Vec::with_capacity(n);
    for (i, p) in plan.paths.iter().enumerate() {
        costs.push(
            path_cost(p, inst.goals[i], GoalSemantics::Stay)
                .ok_or_else(|| format!("agent {i} does not end on its goal"))?,
        );
    }
    let makespan = costs.iter().copied().max().unwrap_or(0);
    let mut actions = Vec::with_capacity(n);
    for (i, p) in plan.paths.iter().enumerate() {
        let at = |k: usize| p[k.min(p.len() - 1)];
        let mut a = Vec::with_capacity(makespan);
        for k in 0..makespan {
            let (v, w) = (at(k), at(k + 1));
            a.push(if v == w {
                Action::Wait
            } else {
                Action::Move(direction(map, v, w).ok_or_else(|| {
                    format!(
                        "agent {i}, step {}: not a wait or a move to a neighbouring cell",
                        k + 1
                    )
                })?)
            });
        }
        actions.push(a);
    }
    let problem = one_shot_problem(map, &inst.starts, &inst.goals, makespan as u32);
    let assigned: Vec<Assign> = (0..n)
        .map(|i| Assign {
            t: 0,
            agent: i,
            task: Some(i),
        })
        .collect();
    let letters: Vec<String> = actions
        .iter()
        .map(|a| {
            a.iter()
                .map(|x| x.letter().to_string())
                .collect::<Vec<_>>()
                .join(",")
        })
        .collect();
    let tasks: Vec<Value> = inst
        .goals
        .iter()
        .enumerate()
        .map(|(i, &g)| {
            let (x, y) = map.cell(g);
            json!([i, 0, [y, x]])
        })
        .collect();
    Ok(json!({
        "actionModel": ActionModel::Mapf.name(),
        "version": VERSION,
        "teamSize": n,
        "numTaskFinished": n,
        "makespan": makespan,
        "numPlannerErrors": 0,
        "numScheduleErrors": 0,
        "numEntryTimeouts": 0,
        "start": starts_json(&problem),
        "actualPaths": letters,
        "plannerPaths": letters,
        "plannerTimes": [],
        "errors": [],
        "actualSchedule": schedules(&assigned, n),
        "plannerSchedule": schedules(&assigned, n),
        "scheduleErrors": [],
        "events": costs.iter().enumerate().map(|(i, &c)| json!([c, i, i, 1])).collect::<Vec<_>>(),
        "tasks": tasks,
    }))
}

/// Reads PlanViz's JSON of a one-shot grid plan (module doc; any LoRR output of the `MAPF`
/// model in the 2024 layout: agent `i`'s goal is the last errand of task `i`) on `map`: the
/// instance and the plan its `actualPaths` give. Whether the plan is valid is the validator's
/// question.
///
/// # Errors
/// Naming `path`: not JSON, an action model other than `MAPF`, a `start` or `tasks` entry that
/// is not `[row, col, ...]` / `[id, t, [row, col, ...]]` on a free cell, fewer tasks than agents,
/// what [`from_json`] refuses in the paths, a move off the map or into a wall (agent and step).
pub fn one_shot_from_json(map: &GridMap, text: &str, path: &Path) -> Result<(Instance, Plan)> {
    let json: Value = serde_json::from_str(text.trim_start_matches('\u{feff}'))
        .map_err(|e| Error::parse(path, e.line(), format!("not a PlanViz JSON: {e}")))?;
    let model = model_of(&json, path)?;
    if model != ActionModel::Mapf {
        return Err(Error::invalid(
            path,
            format!(
                "`actionModel` is `{}`: a one-shot grid plan is `MAPF`",
                model.name()
            ),
        ));
    }
    let cell = |v: Option<&Value>, what: String| -> Result<VertexId> {
        let rc = v
            .and_then(Value::as_array)
            .and_then(|a| Some((a.first()?.as_i64()?, a.get(1)?.as_i64()?)));
        let (row, col) = rc.ok_or_else(|| {
            Error::invalid(path, format!("{what} is not [row, col, ...] of integers"))
        })?;
        map.vertex_at(col, row).ok_or_else(|| {
            Error::invalid(
                path,
                format!(
                    "{what} is row {row}, column {col}: {}",
                    map.cell_problem(col, row).unwrap_or_default()
                ),
            )
        })
    };
    let list = |key: &str| -> Result<&Vec<Value>> {
        json.get(key)
            .and_then(Value::as_array)
            .ok_or_else(|| Error::invalid(path, format!("no `{key}` (a list)")))
    };
    let starts = list("start")?
        .iter()
        .enumerate()
        .map(|(i, s)| cell(Some(s), format!("`start`[{i}]")))
        .collect::<Result<Vec<_>>>()?;
    let tasks = list("tasks")?;
    if tasks.len() < starts.len() {
        return Err(Error::invalid(
            path,
            format!(
                "`tasks` lists {} tasks for {} agents: agent i's goal is task i",
                tasks.len(),
                starts.len()
            ),
        ));
    }
    let goals = tasks[..starts.len()]
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let last = t
                .get(2)
                .and_then(Value::as_array)
                .filter(|e| e.len() >= 2)
                .map(|e| json!([e[e.len() - 2], e[e.len() - 1]]));
            cell(last.as_ref(), format!("`tasks`[{i}]'s last errand"))
        })
        .collect::<Result<Vec<_>>>()?;
    let inst = Instance::new(starts, goals).map_err(|e| Error::invalid(path, e))?;
    let problem = one_shot_problem(map, &inst.starts, &inst.goals, 1);
    let (trace, _) = from_json(&problem, text, path)?;
    let mut paths = Vec::with_capacity(inst.num_agents());
    for (i, (actions, &start)) in trace.actions.iter().zip(&inst.starts).enumerate() {
        let mut s = State {
            vertex: start,
            orientation: EAST,
        };
        let mut p = Vec::with_capacity(actions.len() + 1);
        p.push(start);
        for (k, &a) in actions.iter().enumerate() {
            s = apply(map, s, a).ok_or_else(|| {
                Error::invalid(
                    path,
                    format!(
                        "`actualPaths`[{i}], step {}: `{}` leaves the map or enters a wall",
                        k + 1,
                        a.letter()
                    ),
                )
            })?;
            p.push(s.vertex);
        }
        paths.push(p);
    }
    Ok((inst, Plan::new(paths)))
}

#[cfg(test)]
mod one_shot_tests {
    use super::*;

    fn map() -> GridMap {
        GridMap::parse("....\n.#..\n....", Path::new("m.txt"))
            .unwrap()
            .0
    }

    fn v(m: &GridMap, x: i64, y: i64) -> VertexId {
        m.vertex_at(x, y).unwrap()
    }

    fn instance(m: &GridMap) -> (Instance, Plan) {
        let inst =
            Instance::new(vec![v(m, 0, 0), v(m, 3, 2)], vec![v(m, 3, 0), v(m, 3, 1)]).unwrap();
        let a: Vec<VertexId> = (0..4).map(|x| v(m, x, 0)).collect();
        let b = vec![v(m, 3, 2), v(m, 3, 2), v(m, 3, 1)];
        (inst, Plan::new(vec![a, b]))
    }

    #[test]
    fn writes_what_planviz_reads() {
        let m = map();
        let (inst, plan) = instance(&m);
        let j = one_shot_to_json(&m, &inst, &plan).unwrap();
        assert_eq!(j["actionModel"], "MAPF");
        assert_eq!(j["version"], "2024 LoRR");
        assert_eq!(j["makespan"], 3);
        // `U` is row + 1 and `D` row - 1 in PlanViz: agent 1 goes up the screen with `D`.
        assert_eq!(j["actualPaths"], json!(["R,R,R", "W,D,W"]));
        assert_eq!(j["start"], json!([[0, 0, "E"], [2, 3, "E"]]));
        assert_eq!(j["tasks"], json!([[0, 0, [0, 3]], [1, 0, [1, 3]]]));
        assert_eq!(j["actualSchedule"], json!(["0:0", "0:1"]));
        assert_eq!(j["events"], json!([[3, 0, 0, 1], [2, 1, 1, 1]]));
    }

    #[test]
    fn round_trip_gives_the_same_paths() {
        let m = map();
        let (inst, plan) = instance(&m);
        let text = serde_json::to_string(&one_shot_to_json(&m, &inst, &plan).unwrap()).unwrap();
        let (back_inst, mut back) = one_shot_from_json(&m, &text, Path::new("p.json")).unwrap();
        assert_eq!(back_inst, inst);
        back.trim();
        let mut want = plan;
        want.trim();
        assert_eq!(back, want);
    }

    #[test]
    fn bad_files_name_the_rule() {
        let m = map();
        let (inst, plan) = instance(&m);
        let good = one_shot_to_json(&m, &inst, &plan).unwrap();
        let err = |f: &dyn Fn(&mut Value)| {
            let mut j = good.clone();
            f(&mut j);
            one_shot_from_json(&m, &j.to_string(), Path::new("p.json"))
                .unwrap_err()
                .to_string()
        };
        assert!(err(&|j| j["actionModel"] = json!("MAPF_T")).contains("`MAPF`"));
        assert!(err(&|j| j["start"][1] = json!([1, 1, "E"])).contains("`start`[1]"));
        assert!(
            err(&|j| j["actualPaths"][1] = json!("W,U,W")).contains("`actualPaths`[1], step 2")
        );
        assert!(
            err(&|j| j["actualPaths"][0] = json!("R,X,R")).contains("`X` is not a MAPF action")
        );
        assert!(err(&|j| j["tasks"] = json!([])).contains("`tasks` lists 0"));
        let e = one_shot_from_json(&m, "{", Path::new("p.json"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("not a PlanViz JSON"), "{e}");
        let far = Plan::new(vec![
            vec![v(&m, 0, 0), v(&m, 3, 0)],
            vec![v(&m, 3, 2), v(&m, 3, 1)],
        ]);
        assert!(
            one_shot_to_json(&m, &inst, &far)
                .unwrap_err()
                .contains("agent 0, step 1")
        );
    }
}
