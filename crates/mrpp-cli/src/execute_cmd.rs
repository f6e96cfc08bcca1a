//! `mrpp execute`: a grid plan executed tick by tick under seeded delays by an executor
//! ([`mrpp_exec`]; issue 29, item 3), checked by the executed-record validator, written as an
//! `mrpp-execution/1` record.
//!
//! The record: `{"format": "mrpp-execution/1", "plan", "executor", "k_robust", "replan_drift",
//! "replans" (ticks at which a re-plan took over; the agents' moves are then the executed plan's),
//! "delays", "seed",
//! "ticks_per_move", "agent_size", "ending", "metrics", "rings", "collisions" (the first 100),
//! "agents": [{"start": [x, y], "moves": [[first tick, tick after, [x, y], [x, y]], ...],
//! "delays": [[first tick, tick after], ...]}]}`; ticks from 0, cells as `[x, y]`.

use std::path::PathBuf;

use serde_json::{Value, json};

use mrpp_exec::check::check;
use mrpp_exec::execute::Ending;
use mrpp_exec::{DelayConfig, ExecConfig, ExecutorKind};

use crate::family::Inputs;
use crate::output::{Fail, file_name, say, write_atomic};

#[derive(clap::Args)]
pub(crate) struct ExecuteArgs {
    #[command(flatten)]
    inputs: Inputs,
    /// The grid plan to execute (mrpp's plan JSON or LaCAM text).
    #[arg(long)]
    plan: PathBuf,
    /// Re-plan when a robot is this many ticks behind its plan's timing: the re-planner plans
    /// again from where the robots will stand once their moves in progress are done, and its
    /// plan takes over (mrpp_exec::replan; planning is charged no ticks). Default: never.
    #[arg(long, allow_negative_numbers = true, value_parser = crate::output::parse_count)]
    replan_drift: Option<usize>,
    /// The grid planner that re-plans (`mrpp planners --family grid`).
    #[arg(long, default_value = "lacam", requires = "replan_drift")]
    replan_planner: String,
    /// Planning time per re-plan, seconds.
    #[arg(
        long,
        default_value_t = 1.0,
        allow_negative_numbers = true,
        requires = "replan_drift"
    )]
    replan_time_limit: f64,
    /// The delays' seed.
    #[arg(short = 's', long, default_value_t = 0, allow_negative_numbers = true, value_parser = crate::output::parse_seed)]
    seed: u64,
    /// The executed record (JSON).
    #[arg(short = 'o', long)]
    out: PathBuf,
}

/// `mrpp execute` (module doc).
pub(crate) fn execute(a: &ExecuteArgs) -> Result<u8, Fail> {
    a.inputs.guard(&[a.plan.as_path()], &[a.out.as_path()])?;
    let delays = DelayConfig::parse(a.inputs.delays.as_deref().unwrap_or("none")).map_err(Fail)?;
    let name = a.inputs.executor.as_deref().unwrap_or("adg");
    let executor = ExecutorKind::parse(name)
        .ok_or_else(|| Fail(format!("--executor {name}: expected adg, tpg or naive")))?;
    let ticks_per_move = crate::family::ticks_per_move(&a.inputs)?.unwrap_or(1);
    let agent_size = crate::family::agent_size(&a.inputs)?.unwrap_or(1.0);
    if a.inputs.lorr.is_some() && a.inputs.lifelong {
        return Err(Fail(
            "mrpp execute runs one-shot grid plans; executing lifelong runs is not built yet"
                .into(),
        ));
    }
    let (map, problem, plan) = crate::grid_family::read_valid_plan(&a.inputs, &a.plan)?;
    let k = crate::family::k_robust(&a.inputs)?;
    let plan = mrpp_exec::robust::k_robust(&plan, k);
    // k = 0 leaves the plan as read (and validated); a re-timed one is checked again.
    if k > 0 {
        mrpp_core::Problem::validate(&problem, &plan).map_err(|v| {
            Fail(format!(
                "the {k}-robust re-timing of {} is not valid (a bug in mrpp): {v}",
                a.plan.display()
            ))
        })?;
    }
    let makespan = plan.paths.iter().map(Vec::len).max().unwrap_or(1) as u64;
    let cfg = ExecConfig {
        executor,
        ticks_per_move,
        delays,
        seed: a.seed,
        agent_size,
        // Generous: the plan's length x ticks, with room for every robot to be held often.
        max_ticks: (makespan + 1) * u64::from(ticks_per_move) * 50 + 100_000,
    };
    let (run, plan) = if let Some(drift) = a.replan_drift {
        let entry =
            mrpp_core::registry::find(mrpp_grid::PLANNERS, &a.replan_planner).ok_or_else(|| {
                let known: Vec<&str> = mrpp_grid::PLANNERS.iter().map(|e| e.name).collect();
                Fail(format!(
                    "--replan-planner {}: not a grid planner (known: {})",
                    a.replan_planner,
                    known.join(", ")
                ))
            })?;
        let planner = entry.instantiate(&[]).map_err(|e| Fail(e.to_string()))?;
        let budget = crate::output::seconds("replan-time-limit", a.replan_time_limit)?;
        let live = crate::progress::Live::start("execute, re-planning");
        let mut replanner = mrpp_exec::Replanner::new(&problem, planner.as_ref(), a.seed, budget)
            .with_progress(Some(live.callback()));
        let mut replan = |at: &[mrpp_core::mapf::graph::VertexId]| replanner.plan(at);
        let replanning = mrpp_exec::Replanning {
            drift: drift as u64,
            planner: &mut replan,
        };
        let done = mrpp_exec::execute_replanning(&map, &plan, &cfg, Some(replanning));
        live.finish();
        if let Some(why) = replanner.invalid {
            return Err(Fail(format!(
                "--replan-planner {}: {why} (a bug in the planner; nothing written)",
                a.replan_planner
            )));
        }
        done
    } else {
        (mrpp_exec::execute(&map, &plan, &cfg), plan)
    };
    // A plan read from a file was validated when read; only a re-planned one is new. Under the
    // ADG it is valid (mrpp_exec::replan); the naive executor may have broken it.
    if executor == ExecutorKind::Adg && a.replan_drift.is_some() {
        mrpp_core::Problem::validate(&problem, &plan).map_err(|v| {
            Fail(format!(
                "the executed plan of {} is not valid (a bug in mrpp): {v}",
                a.plan.display()
            ))
        })?;
    }
    let replayed = check(&map, &plan, &run, ticks_per_move, agent_size).map_err(|e| {
        Fail(format!(
            "the executed record does not replay (a bug in mrpp): {e}"
        ))
    })?;
    debug_assert_eq!(replayed.len(), run.collisions.len());
    let xy = |v| {
        let (x, y) = map.cell(v);
        json!([x, y])
    };
    let agents: Vec<Value> = plan
        .paths
        .iter()
        .enumerate()
        .map(|(i, path)| {
            let moves: Vec<(u32, u32)> = path
                .windows(2)
                .filter(|w| w[0] != w[1])
                .map(|w| (w[0], w[1]))
                .collect();
            json!({
                "start": xy(path[0]),
                "moves": run.moves[i].iter().zip(&moves)
                    .map(|(t, &(f, to))| json!([t[0], t[1], xy(f), xy(to)]))
                    .collect::<Vec<_>>(),
                "delays": run.delays[i],
            })
        })
        .collect();
    let record = json!({
        "format": "mrpp-execution/1",
        "mrpp_version": env!("CARGO_PKG_VERSION"),
        "plan": file_name(&a.plan),
        "executor": executor.name(),
        "k_robust": k,
        "replan_drift": a.replan_drift,
        "replans": run.replans,
        "delays": cfg.delays.spec(),
        "seed": a.seed,
        "ticks_per_move": ticks_per_move,
        "agent_size": agent_size,
        "ending": run.ending,
        "ticks": run.ticks,
        "metrics": run.metrics,
        "rings": run.rotations,
        "collisions": run.collisions.iter().take(100).collect::<Vec<_>>(),
        "agents": agents,
    });
    write_atomic(&a.out, serde_json::to_string(&record).expect("json") + "\n")?;
    let m = run.metrics;
    say!(
        "mrpp {} | execute {} | {}{} | delays {} | {} ticks per move | seed {} | makespan {} ticks ({:.3}x planned), sum of costs {} ({:.3}x) | {} ticks lost to delays, {} waits added | {} collisions | written to {}",
        env!("CARGO_PKG_VERSION"),
        file_name(&a.plan),
        executor.name(),
        a.replan_drift.map_or_else(String::new, |d| format!(
            " + re-planning by {} at {d} ticks of drift ({} re-plans, {} found nothing)",
            a.replan_planner, m.replans, m.failed_replans
        )),
        cfg.delays.spec(),
        ticks_per_move,
        a.seed,
        m.makespan,
        m.makespan_ratio,
        m.sum_of_costs,
        m.sum_of_costs_ratio,
        m.ticks_lost_to_delays,
        m.waits_added,
        m.collisions,
        a.out.display()
    );
    let bad = match run.ending {
        Ending::Finished => None,
        Ending::Deadlock { tick } => Some(format!("deadlock at tick {tick}")),
        Ending::TickLimit => Some(format!("still moving after {} ticks", run.ticks)),
    };
    if let Some(first) = run.collisions.first() {
        // Collisions inside a ring rotating together: the plan's geometry, not lateness.
        let in_ring = run
            .collisions
            .iter()
            .filter(|c| {
                run.rotations.iter().any(|ring| {
                    c.robots
                        .iter()
                        .all(|r| ring.iter().any(|&(robot, _)| robot == *r))
                })
            })
            .count();
        if in_ring > 0 {
            eprintln!(
                "mrpp: {in_ring} of the collisions are between robots of a ring rotating together (the plan moves them into each other's cells at one step; with --agent-size above 0.5 a ring's corners overlap however it is executed)"
            );
        }
        eprintln!(
            "mrpp: the execution collided {} times; first at tick {}: robots {} and {} at ({:.2}, {:.2}) and ({:.2}, {:.2})",
            run.collisions.len(),
            first.tick,
            first.robots[0],
            first.robots[1],
            first.at[0][0],
            first.at[0][1],
            first.at[1][0],
            first.at[1][1]
        );
    }
    if let Some(why) = &bad {
        eprintln!("mrpp: the execution did not finish: {why}");
    }
    Ok(if run.collisions.is_empty() && bad.is_none() {
        0
    } else {
        3
    })
}

/// Whether the file at `path` is an executed record (`mrpp-execution/1`).
pub(crate) fn is_execution_record(path: &std::path::Path) -> bool {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|t| {
            let head = &t[..t.len().min(200)];
            head.contains("\"mrpp-execution/1\"").then_some(())
        })
        .is_some()
}

/// The viewer's scene of an executed record ([`crate::view`]): the grid, every robot's point at
/// the end of each tick (replayed from the record), its start and last cell, `held` change lists
/// (`[tick, 1]` while a delay holds it, `[tick, 0]` after) that the page marks, and the first
/// collision as the verdict's conflict.
pub(crate) fn scene(inputs: &Inputs, record_path: &std::path::Path) -> Result<Value, Fail> {
    let (map, _) = crate::grid_family::map_of(inputs)?;
    let text = mrpp_core::error::read_file(record_path)?;
    let bad = |why: String| Fail(format!("{}: {why}", record_path.display()));
    let record: Value = serde_json::from_str(&text).map_err(|e| bad(format!("not JSON: {e}")))?;
    let cell = |v: &Value| -> Result<u32, Fail> {
        let (x, y) = (v[0].as_i64(), v[1].as_i64());
        match (x, y) {
            (Some(x), Some(y)) => map
                .vertex_at(x, y)
                .ok_or_else(|| bad(format!("[{x}, {y}] is not a free cell of the map"))),
            _ => Err(bad(format!("{v} is not a cell [x, y]"))),
        }
    };
    let pair = |v: &Value| -> Result<[u64; 2], Fail> {
        match (v[0].as_u64(), v[1].as_u64()) {
            (Some(a), Some(b)) => Ok([a, b]),
            _ => Err(bad(format!("{v} is not a pair of ticks"))),
        }
    };
    let agents = record["agents"]
        .as_array()
        .ok_or_else(|| bad("no `agents`".into()))?;
    let mut starts = Vec::new();
    let (mut moves, mut ticks, mut delays) = (Vec::new(), Vec::new(), Vec::new());
    for a in agents {
        starts.push(cell(&a["start"])?);
        let (mut m, mut t) = (Vec::new(), Vec::new());
        for mv in a["moves"].as_array().into_iter().flatten() {
            t.push(pair(mv)?);
            m.push((cell(&mv[2])?, cell(&mv[3])?));
        }
        moves.push(m);
        ticks.push(t);
        delays.push(
            a["delays"]
                .as_array()
                .into_iter()
                .flatten()
                .map(pair)
                .collect::<Result<Vec<_>, _>>()?,
        );
    }
    let rings: Vec<Vec<(usize, usize)>> =
        serde_json::from_value(record["rings"].clone()).unwrap_or_default();
    let ring_of = rings
        .iter()
        .enumerate()
        .flat_map(|(g, r)| r.iter().map(move |&m| (m, g)))
        .collect();
    let replay = mrpp_exec::check::Replay {
        map: &map,
        starts: &starts,
        moves: &moves,
        ticks: &ticks,
        delays: &delays,
        rings: &rings,
        ring_of,
        c: record["ticks_per_move"].as_u64().unwrap_or(1).max(1),
    };
    let total = record["ticks"].as_u64().unwrap_or(0);
    let n = starts.len();
    let centre = |v: u32| {
        let (x, y) = map.cell(v);
        [f64::from(x) + 0.5, f64::from(y) + 0.5]
    };
    let mut paths: Vec<Vec<[f64; 2]>> = starts.iter().map(|&s| vec![centre(s)]).collect();
    let mut held: Vec<Vec<[u64; 2]>> = vec![Vec::new(); n];
    for t in 0..total {
        for (i, p) in replay.at(t).into_iter().enumerate() {
            paths[i].push([
                (p[0] * 1000.0).round() / 1000.0,
                (p[1] * 1000.0).round() / 1000.0,
            ]);
            let h = u64::from(replay.held_at(i, t));
            if held[i].last().map_or(h == 1, |l| l[1] != h) {
                // Path index t + 1 shows the end of tick t.
                held[i].push([t + 1, h]);
            }
        }
    }
    let size = record["agent_size"].as_f64().unwrap_or(1.0);
    let agents: Vec<Value> = (0..n)
        .map(|i| {
            json!({
                "radius": (size / 2.0).clamp(0.1, 0.5),
                "start": centre(starts[i]),
                "goal": paths[i].last().copied().unwrap_or(centre(starts[i])),
                "path": paths[i],
                "held": held[i],
            })
        })
        .collect();
    let collisions = record["metrics"]["collisions"].as_u64().unwrap_or(0);
    let verdict = match record["collisions"].get(0) {
        Some(c) => json!({
            "valid": false,
            "text": format!("{collisions} collisions; first at tick {}", c["tick"]),
            "conflict": {"t": c["tick"].as_u64().unwrap_or(0) + 1, "agents": c["robots"], "at": c["at"][0]},
        }),
        None => json!({"valid": true, "metrics": record["metrics"]}),
    };
    Ok(json!({
        "family": "execution",
        "title": format!("{} | {} | delays {}", file_name(record_path), record["executor"].as_str().unwrap_or("?"), record["delays"].as_str().unwrap_or("?")),
        "about": "",
        "unit": "tick",
        "bounds": [0.0, 0.0, f64::from(map.width()), f64::from(map.height())],
        "y_up": false,
        "cells": {"width": map.width(), "height": map.height(), "rows": crate::grid_family::scene_rows(&map)},
        "polygons": [],
        "agents": agents,
        "verdict": verdict,
    }))
}
