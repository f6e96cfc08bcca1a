//! The lifelong family on the command line: a League of Robot Runners problem `--lorr P.json`
//! run step by step (`--lifelong`, implied by a lifelong planner), with `--steps`,
//! `--step-time-limit` and `--action-model`. The plan file is LoRR's own output JSON (2024
//! layout, [`mrpp_lifelong::lorr_output`]), which the kit's viewer PlanViz reads, with one more
//! key, `mrpp`, holding mrpp's run record (format `mrpp-lifelong/1`, planner, parameters, seed,
//! status, metrics, runtime, horizon, planning time per step). `validate` reads mrpp's files and
//! the kit's own output alike.

use std::path::Path;
use std::time::Duration;

use serde_json::{Map, Value, json};

use mrpp_bench::report::{Panel, Series, line_panels};
use mrpp_core::Deadline;
use mrpp_core::Problem;
use mrpp_core::mapf::plan_file::RunInfo;
use mrpp_lifelong::execution::ExecutionModel;
use mrpp_lifelong::executor::ExecutorKind;
use mrpp_lifelong::lorr_output::{from_json, model_of, to_json};
use mrpp_lifelong::problem::{DEFAULT_PREPROCESS_TIME, DEFAULT_STEP_TIME, DEFAULT_STEPS};
use mrpp_lifelong::scheduler::{Scheduler, SchedulerKind};
use mrpp_lifelong::{ActionModel, LifelongProblem};
use mrpp_mapf::lorr_files;

use crate::family::{Def, Inputs, Loaded, Outcome, ReadPlan};
use crate::output::{Fail, file_name, out};

/// The format tag of the `mrpp` record in a lifelong plan file.
pub(crate) const FORMAT: &str = "mrpp-lifelong/1";

/// The lifelong family.
pub(crate) static LIFELONG: Def<LifelongProblem> = Def {
    name: mrpp_lifelong::FAMILY,
    planners: mrpp_lifelong::PLANNERS,
    claims: |i| i.lorr.is_some() && i.lifelong && i.instance.is_none(),
    load,
    read_plan,
    info: Some(info),
    render: Some(render),
    scene: Some(scene),
    lacam: false,
};

/// Whether the file at `plan` is LoRR output JSON (it has an `actionModel`), so that `validate
/// --lorr P --plan F` judges it as a lifelong run.
pub(crate) fn is_lorr_output(plan: &Path) -> bool {
    std::fs::read_to_string(plan)
        .ok()
        .and_then(|t| serde_json::from_str::<Value>(&t).ok())
        .is_some_and(|v| v.get("actionModel").is_some())
}

fn seconds(given: Option<f64>, default: Duration, flag: &str) -> Result<Duration, Fail> {
    match given {
        None => Ok(default),
        Some(s) if s.is_finite() && s > 0.0 && s <= 3600.0 => Ok(Duration::from_secs_f64(s)),
        Some(s) => Err(Fail(format!(
            "{flag} must be a number of seconds in (0, 3600], got {s}"
        ))),
    }
}

fn step_time(inputs: &Inputs) -> Result<Duration, Fail> {
    seconds(
        inputs.step_time_limit,
        DEFAULT_STEP_TIME,
        "--step-time-limit",
    )
}

fn steps(inputs: &Inputs) -> Result<u32, Fail> {
    match inputs.steps {
        None => Ok(DEFAULT_STEPS),
        Some(n) if (1..=10_000_000).contains(&n) => Ok(n as u32),
        Some(n) => Err(Fail(format!("--steps must be 1..=10000000, got {n}"))),
    }
}

fn model(inputs: &Inputs) -> Result<ActionModel, Fail> {
    match &inputs.action_model {
        None => Ok(ActionModel::MapfT),
        Some(m) => ActionModel::parse(m).ok_or_else(|| {
            Fail(format!(
                "--action-model must be MAPF_T (orientation, the League's) or MAPF, got `{m}`"
            ))
        }),
    }
}

fn lorr_path(inputs: &Inputs) -> Result<&Path, Fail> {
    inputs
        .lorr
        .as_deref()
        .ok_or_else(|| Fail("lifelong problems need --lorr P.json".into()))
}

/// The lifelong problem the inputs name (`--lorr` with the run's flags), checked.
pub(crate) fn load_problem(inputs: &Inputs) -> Result<LifelongProblem, Fail> {
    let path = lorr_path(inputs)?;
    if inputs.agents.is_some() {
        return Err(Fail(
            "--agents does not apply to lifelong runs: the team is the problem's teamSize".into(),
        ));
    }
    let preprocess = seconds(
        inputs.preprocess_time_limit,
        DEFAULT_PREPROCESS_TIME,
        "--preprocess-time-limit",
    )?;
    let horizon = match inputs.ticks {
        None => steps(inputs)?,
        Some(n) if (1..=10_000_000).contains(&n) => n as u32,
        Some(n) => return Err(Fail(format!("--ticks must be 1..=10000000, got {n}"))),
    };
    let problem = LifelongProblem::load(path, model(inputs)?, horizon, step_time(inputs)?)?
        .with_preprocess_time(preprocess);
    if inputs.ticks.is_none() {
        if let Some(flag) = inputs.execution_flag() {
            return Err(Fail(format!(
                "{flag} applies to lifelong runs in ticks: add --ticks N (the League's 2026 execution model)"
            )));
        }
        return Ok(problem);
    }
    let execution = execution_model(inputs, problem.files())?;
    Ok(problem.with_execution(execution))
}

/// The 2026 execution model of a run in ticks: the problem file's, with the flags given.
fn execution_model(inputs: &Inputs, files: &lorr_files::LorrFiles) -> Result<ExecutionModel, Fail> {
    let mut m = ExecutionModel::of_problem(files)?;
    if let Some(spec) = &inputs.delays {
        m.delays = mrpp_exec::DelayConfig::parse(spec).map_err(Fail)?;
    }
    if let Some(name) = &inputs.executor {
        m.executor = ExecutorKind::parse(name)
            .ok_or_else(|| Fail(format!("--executor {name}: expected tpg (the League's default executor) or naive for lifelong runs")))?;
    }
    if let Some(t) = crate::family::ticks_per_move(inputs)? {
        m.agent_counter = t;
    }
    if let Some(s) = crate::family::agent_size(inputs)? {
        m.agent_size = s;
    }
    m.k_robust = crate::family::k_robust(inputs)?;
    if let Some(k) = inputs.plan_every {
        m.plan_every = u32::try_from(k)
            .ok()
            .filter(|k| (1..=100_000).contains(k))
            .ok_or_else(|| Fail(format!("--plan-every {k}: expected 1 to 100000 ticks")))?;
    }
    Ok(m)
}

fn load(inputs: &Inputs) -> Result<Loaded<LifelongProblem>, Fail> {
    let path = lorr_path(inputs)?;
    let problem = load_problem(inputs)?;
    let f = problem.files();
    let horizon = match problem.execution() {
        None => format!(
            "{} steps, {} s per step",
            problem.steps(),
            problem.step_time().as_secs_f64()
        ),
        Some(m) => format!(
            "{} ticks, {} per action | a plan every {} ticks, {} s each | executor {}{} | delays {}",
            problem.steps(),
            m.agent_counter,
            m.plan_every,
            problem.step_time().as_secs_f64(),
            m.executor.name(),
            if m.k_robust > 0 {
                format!(" | {}-robust plans", m.k_robust)
            } else {
                String::new()
            },
            m.delays.spec()
        ),
    };
    let summary = format!(
        "map {} | robots {} | {} tasks in the file, {} open at a time | {} | {horizon}",
        file_name(&f.map_path),
        f.team_size(),
        f.tasks.len(),
        f.reveal_pool(),
        problem.model().name(),
    );
    let problem_file = file_name(path);
    Ok(Loaded {
        summary,
        problem,
        write: Box::new(move |problem, info, outcome, notes, _format| {
            write_plan(&problem_file, problem, info, outcome, notes)
        }),
    })
}

fn write_plan(
    problem_file: &str,
    problem: &LifelongProblem,
    info: RunInfo,
    outcome: &Outcome<LifelongProblem>,
    notes: Map<String, Value>,
) -> Result<String, Fail> {
    let (mut json, status, metrics, preprocess) = match outcome {
        Ok(s) => (
            to_json(problem, &s.plan).map_err(Fail)?,
            if s.metrics.steps < problem.steps() {
                // The run's --time-limit (or Ctrl-C) stopped it before the horizon.
                let unit = if problem.execution().is_some() {
                    "ticks"
                } else {
                    "steps"
                };
                eprintln!(
                    "mrpp: warning: the run stopped at the time limit after {} of {} {unit} (--time-limit covers the whole run)",
                    s.metrics.steps,
                    problem.steps()
                );
                format!(
                    "stopped after {} of {} {unit} (time limit)",
                    s.metrics.steps,
                    problem.steps()
                )
            } else {
                "solved".to_string()
            },
            serde_json::to_value(s.metrics).unwrap_or(Value::Null),
            s.plan.preprocess_time,
        ),
        Err(why) => (
            json!({
                "actionModel": problem.model().name(),
                "version": mrpp_lifelong::lorr_output::VERSION,
                "teamSize": problem.num_agents(),
                "numTaskFinished": 0,
            }),
            why.to_string(),
            json!({}),
            0.0,
        ),
    };
    json["mrpp"] = json!({
        "format": FORMAT,
        "family": mrpp_lifelong::FAMILY,
        "problem": problem_file,
        "planner": info.planner,
        "params": info.params,
        "seed": info.seed,
        "status": status,
        "steps": problem.steps(),
        "step_time_limit_s": problem.step_time().as_secs_f64(),
        "execution": problem.execution().map(|m| json!({
            "ticks": problem.steps(),
            "agent_counter": m.agent_counter,
            "agent_size": m.agent_size,
            "delays": m.delays.spec(),
            "delay_seed": m.delay_seed,
            "plan_every": m.plan_every,
            "executor": m.executor.name(),
            "k_robust": m.k_robust,
        })),
        "metrics": metrics,
        "runtime_ms": info.runtime_ms,
        "preprocess_s": preprocess,
        "notes": notes,
    });
    serde_json::to_string(&json).map_err(|e| Fail(e.to_string()))
}

/// Reads mrpp's lifelong plan file or the kit's output JSON against the `--lorr` problem.
fn read_plan(inputs: &Inputs, plan_path: &Path) -> Result<ReadPlan<LifelongProblem>, Fail> {
    let path = lorr_path(inputs)?;
    let text = mrpp_core::error::read_file(plan_path)?;
    let json: Value = serde_json::from_str(&text).map_err(|e| {
        Fail(format!(
            "{}:{}: not a LoRR output JSON: {e}",
            plan_path.display(),
            e.line()
        ))
    })?;
    let model = model_of(&json, plan_path)?;
    if let Some(asked) = &inputs.action_model
        && ActionModel::parse(asked) != Some(model)
    {
        return Err(Fail(format!(
            "{}: the run's actionModel is {}, --action-model says {asked}",
            plan_path.display(),
            model.name()
        )));
    }
    let files = lorr_files::load(path)?;
    // The horizon: --steps, else the run's own length (a run may stop early).
    let in_ticks = json.get("version").and_then(Value::as_str)
        == Some(mrpp_lifelong::lorr_output::VERSION_2026);
    let run_steps = if in_ticks {
        // Ticks: the 2026 layout's `makespan` (its paths may be shorter, never longer).
        json.get("makespan").and_then(Value::as_u64).unwrap_or(0) as usize
    } else {
        json.get("actualPaths")
            .and_then(|p| p.get(0))
            .and_then(Value::as_str)
            .map_or(0, |s| s.split(',').filter(|l| !l.is_empty()).count())
    };
    let horizon = match inputs.steps {
        Some(_) => steps(inputs)?,
        None => (run_steps as u32).max(1),
    };
    let problem = LifelongProblem::new(files, model, horizon, step_time(inputs)?);
    let (plan, claims) = from_json(&problem, &text, plan_path)?;
    let mut claimed = Map::new();
    claimed.insert("tasks_finished".into(), json!(claims.tasks_finished));
    let about = match json.get("mrpp") {
        Some(m) => format!(
            "planner {} | seed {} | {}",
            m.get("planner").and_then(Value::as_str).unwrap_or("?"),
            m.get("seed").and_then(Value::as_u64).unwrap_or(0),
            model.name()
        ),
        None => format!(
            "LoRR output ({}) | {}",
            json.get("version")
                .and_then(Value::as_str)
                .unwrap_or("no version"),
            model.name()
        ),
    };
    Ok(ReadPlan {
        problem,
        plan,
        claims: claimed,
        about,
    })
}

/// The viewer's scene of a lifelong run ([`crate::view`]; also `render --out run.gif`): the grid,
/// each robot's cell at every step (replayed under the kit's rules), its start, as its goal the
/// errand it was heading for at the end, and the lifelong parts (change lists, `[step, ...]`,
/// each entry holding from its step on): `headings` `[t, orientation]` (0 east, 1 south, 2 west,
/// 3 north; `MAPF_T` only), `goals` `[t, cell or -1, task id or -1]` (the next errand of the
/// robot's task), and the scene's `series` of tasks finished after each step.
fn scene(inputs: &Inputs, plan: &Path) -> Result<Value, Fail> {
    let read = read_plan(inputs, plan)?;
    let problem = &read.problem;
    let map = problem.map();
    let n = problem.num_agents();
    let cell = |v: mrpp_core::VertexId| {
        let (x, y) = map.cell(v);
        u64::from(y) * u64::from(map.width()) + u64::from(x)
    };
    let centre = |v: mrpp_core::VertexId| {
        let (x, y) = map.cell(v);
        json!([f64::from(x) + 0.5, f64::from(y) + 0.5])
    };
    let mut cells: Vec<Vec<u64>> = problem.starts().iter().map(|&v| vec![cell(v)]).collect();
    let rotations = problem.model() == mrpp_lifelong::ActionModel::MapfT;
    let mut headings: Vec<Vec<[i64; 2]>> = vec![vec![[0, 0]]; n];
    let mut goal_changes: Vec<Vec<[i64; 3]>> = vec![vec![[0, -1, -1]]; n];
    let mut finished = vec![0usize];
    let mut on_step = |sim: &mrpp_lifelong::sim::Simulation<'_>| {
        let t = i64::from(sim.t);
        for (i, (c, s)) in cells.iter_mut().zip(&sim.states).enumerate() {
            c.push(cell(s.vertex));
            let o = i64::from(s.orientation);
            if rotations && headings[i].last().is_some_and(|h| h[1] != o) {
                headings[i].push([t, o]);
            }
            let goal = sim.goal(i).map_or(-1, |v| cell(v) as i64);
            let task = sim.assignment[i].map_or(-1, |k| k as i64);
            if goal_changes[i]
                .last()
                .is_some_and(|g| g[1] != goal || g[2] != task)
            {
                goal_changes[i].push([t, goal, task]);
            }
        }
        finished.push(sim.finished);
    };
    // Runs in ticks: each robot's point at the end of every tick, part way along a move in
    // progress (the cell it stands on changes only when the move completes).
    let mut points: Vec<Vec<[f64; 2]>> = problem
        .starts()
        .iter()
        .map(|&v| {
            let (x, y) = map.cell(v);
            vec![[f64::from(x) + 0.5, f64::from(y) + 0.5]]
        })
        .collect();
    let replayed = match &read.plan.ticks {
        None => mrpp_lifelong::problem::replay(problem, &read.plan, on_step),
        Some(record) => {
            let counter = f64::from(record.agent_counter.max(1));
            let at = |v: mrpp_core::VertexId| {
                let (x, y) = map.cell(v);
                [f64::from(x) + 0.5, f64::from(y) + 0.5]
            };
            mrpp_lifelong::execution::replay_tick_states(
                problem,
                &read.plan,
                record,
                |sim, states| {
                    on_step(sim);
                    for (p, s) in points.iter_mut().zip(states) {
                        let from = at(s.state.vertex);
                        let to = s
                            .current
                            .and_then(|a| mrpp_lifelong::ticks::target(map, s, a))
                            .map_or(from, at);
                        let f = f64::from(s.counter) / counter;
                        p.push([
                            from[0] + (to[0] - from[0]) * f,
                            from[1] + (to[1] - from[1]) * f,
                        ]);
                    }
                },
            )
        }
    };
    let (verdict, goals) = match replayed {
        Ok(sim) => {
            let goals: Vec<Value> = (0..n)
                .map(|i| centre(sim.goal(i).unwrap_or(sim.states[i].vertex)))
                .collect();
            let m = problem
                .validate(&read.plan)
                .map_err(|v| Fail(v.to_string()))?;
            (json!({"valid": true, "metrics": m}), goals)
        }
        Err(v) => (
            json!({"valid": false, "text": v.to_string()}),
            problem.starts().iter().map(|&v| centre(v)).collect(),
        ),
    };
    let agents: Vec<Value> = (0..n)
        .map(|i| {
            let mut a = json!({
                "radius": 0.38,
                "start": centre(problem.starts()[i]),
                "goal": goals[i],
                "cells": cells[i],
                "goals": goal_changes[i],
            });
            if rotations {
                a["headings"] = json!(headings[i]);
            }
            if read.plan.ticks.is_some() {
                // Between cells (the page draws "path" points, not cells).
                a.as_object_mut().expect("an object").remove("cells");
                a["path"] = json!(points[i]);
            }
            if let Some(record) = &read.plan.ticks {
                // Runs in ticks: a red ring while a delay holds the robot (path index t + 1
                // shows the end of tick t).
                let mut held: Vec<[u64; 2]> = Vec::new();
                for iv in record.delays.get(i).into_iter().flatten() {
                    match held.last_mut() {
                        Some(last) if last[1] == 0 && last[0] > iv[0] => {
                            last[0] = last[0].max(iv[1] + 1);
                        }
                        _ => {
                            held.push([iv[0] + 1, 1]);
                            held.push([iv[1] + 1, 0]);
                        }
                    }
                }
                a["held"] = json!(held);
            }
            a
        })
        .collect();
    let rows = crate::grid_family::scene_rows(map);
    let mut scene = json!({
        "family": mrpp_lifelong::FAMILY,
        "title": format!("{} | {}", file_name(&problem.files().path), file_name(plan)),
        "about": read.about,
        "bounds": [0.0, 0.0, f64::from(map.width()), f64::from(map.height())],
        "y_up": false,
        "cells": {"width": map.width(), "height": map.height(), "rows": rows},
        "polygons": [],
        "agents": agents,
        "series": {"name": "tasks finished", "values": finished},
        "verdict": verdict,
    });
    if read.plan.ticks.is_some() {
        // The page counts the run's time in ticks, not steps.
        scene["unit"] = json!("tick");
    }
    Ok(scene)
}

/// Steps over which `render`'s throughput panel averages.
const THROUGHPUT_WINDOW: usize = 20;

/// `mrpp render` of a lifelong run: its throughput figure (SVG), two panels over the steps: tasks
/// finished so far, and tasks finished per step (the mean over the last [`THROUGHPUT_WINDOW`]
/// steps), from a replay of the run under the kit's rules.
fn render(inputs: &Inputs, plan: &Path) -> Result<String, Fail> {
    let read = read_plan(inputs, plan)?;
    let problem = &read.problem;
    let mut finished = vec![0usize];
    mrpp_lifelong::problem::replay(problem, &read.plan, |sim| finished.push(sim.finished))
        .map_err(|v| Fail(format!("{}: {v}", plan.display())))?;
    // At most about 150 points a line (the figure draws a marker on each), the last step kept.
    let last = finished.len() - 1;
    let stride = last.div_ceil(150).max(1);
    let at = |from: usize| (from..=last).filter(move |t| t % stride == 0 || *t == last);
    let cumulative = at(0).map(|t| (t as f64, finished[t] as f64)).collect();
    let w = THROUGHPUT_WINDOW.min(last).max(1);
    let rate = at(w)
        .map(|t| (t as f64, (finished[t] - finished[t - w]) as f64 / w as f64))
        .collect();
    let unit = if read.plan.ticks.is_some() {
        "tick"
    } else {
        "step"
    };
    let name = read.about.clone();
    let series = |points| Series {
        name: name.clone(),
        points,
        ..Series::default()
    };
    let panels = [
        Panel {
            title: "tasks finished so far".into(),
            series: vec![series(cumulative)],
        },
        Panel {
            title: format!("tasks finished per {unit} (mean of the last {w})"),
            series: vec![series(rate)],
        },
    ];
    let title = format!(
        "{} | {} robots | {} tasks finished in {} {unit}s",
        file_name(&problem.files().path),
        problem.num_agents(),
        finished[last],
        last
    );
    line_panels(&title, unit, "tasks", &panels)
        .map_err(|e| Fail(format!("{}: {e}", plan.display())))
}

fn info(inputs: &Inputs) -> Result<u8, Fail> {
    let path = lorr_path(inputs)?;
    let f = lorr_files::load(path)?;
    let errands: usize = f.tasks.iter().map(Vec::len).sum();
    out!(
        "lifelong problem {} | map {} {}x{}, {} free cells | robots {} | tasks {} ({} errands, {:.2} per task), numTasksReveal {} ({} open at a time) | version {}",
        path.display(),
        file_name(&f.map_path),
        f.map.width(),
        f.map.height(),
        f.map.graph().num_vertices(),
        f.team_size(),
        f.tasks.len(),
        errands,
        errands as f64 / f.tasks.len() as f64,
        f.num_tasks_reveal,
        f.reveal_pool(),
        f.version
    );
    if inputs.steps.is_some() {
        // The congestion-free reference over the asked horizon (mrpp_lifelong::bound).
        let problem = LifelongProblem::new(f, model(inputs)?, steps(inputs)?, step_time(inputs)?);
        let limit = Deadline::after(Duration::from_secs(600));
        let pickup_only = Scheduler {
            chain_weight: 0.0,
            ..Scheduler::new(SchedulerKind::Hungarian)
        };
        let mut variants = vec![
            (
                Scheduler::new(SchedulerKind::Greedy),
                "greedy scheduler".to_string(),
            ),
            (
                Scheduler::new(SchedulerKind::Hungarian),
                "hungarian scheduler".to_string(),
            ),
            (
                pickup_only,
                "hungarian scheduler with -p chain_weight=0".to_string(),
            ),
        ];
        if let Some(spec) = &inputs.reference_scheduler {
            let mut given = Vec::new();
            for part in spec.split(',').filter(|p| !p.trim().is_empty()) {
                let Some((k, v)) = part.split_once('=') else {
                    return Err(Fail(format!(
                        "--reference-scheduler: `{part}` is not KEY=VALUE (e.g. scheduler=hungarian,lookahead=25)"
                    )));
                };
                given.push((k.trim().to_string(), v.trim().to_string()));
            }
            let scheduler = mrpp_lifelong::runner::scheduler_from(&given)
                .map_err(|e| Fail(format!("--reference-scheduler: {e}")))?;
            variants.push((scheduler, format!("scheduler {spec}")));
        }
        for (scheduler, name) in variants {
            let name = name.as_str();
            let live = crate::progress::Live::start(name);
            let ctx = mrpp_core::Ctx {
                seed: 0,
                deadline: limit,
                progress: Some(live.callback()),
            };
            let bound = mrpp_lifelong::bound::congestion_free(&problem, &scheduler, &ctx);
            live.finish();
            match bound {
                Some(n) => out!(
                    "congestion-free reference ({name}, {}, {} steps): {n} tasks finished if robots never got in each other's way",
                    problem.model().name(),
                    problem.steps()
                ),
                None => out!("congestion-free reference ({name}): not computed within 10 minutes"),
            }
        }
    }
    Ok(0)
}
