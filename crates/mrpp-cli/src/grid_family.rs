//! The grid family on the command line: `--map M --scen S [--agents N]` or a League of Robot
//! Runners problem `--lorr P.json` ([`mrpp_grid::lorr`]), plans as the envelope with `[x, y]`
//! cells or as LaCAM text, `info` (lower bounds) and `render` (SVG).

use std::path::{Path, PathBuf};

use serde_json::{Map, Value, json};

use mrpp_core::mapf::plan_file::RunInfo;
use mrpp_core::mapf::search::distance::lower_bounds;
use mrpp_core::{Instance, MapfProblem, Problem, VertexId};
use mrpp_grid::GridMap;
use mrpp_grid::io::lacam::{parse_lacam_with_claims, write_lacam};
use mrpp_grid::io::plan_json::{grid_envelope, read_grid_plan, read_grid_plan_to_draw};
use mrpp_grid::io::render::render_svg;
use mrpp_grid::io::tracker;
use mrpp_lifelong::lorr_output::one_shot_from_json;

use crate::family::{Def, Format, Inputs, Loaded, Outcome, ReadPlan};
use crate::output::{Fail, file_name, out};

/// The grid family.
pub(crate) static GRID: Def<MapfProblem> = def();

/// The grid family's definition (a `const fn` so that tests can build variants of it).
pub(crate) const fn def() -> Def<MapfProblem> {
    Def {
        name: mrpp_grid::FAMILY,
        planners: mrpp_grid::PLANNERS,
        claims: |i| (i.map.is_some() || i.lorr.is_some()) && !i.lifelong && i.instance.is_none(),
        load,
        read_plan,
        info: Some(info),
        render: Some(render),
        scene: Some(scene),
        lacam: true,
    }
}

fn need<'a>(path: &'a Option<PathBuf>, flag: &str) -> Result<&'a Path, Fail> {
    path.as_deref()
        .ok_or_else(|| Fail(format!("grid problems need {flag}")))
}

/// The map of the grid inputs (`--map`, or the map a `--lorr` problem names) and its path.
pub(crate) fn map_of(inputs: &Inputs) -> Result<(GridMap, PathBuf), Fail> {
    if let Some(lorr) = &inputs.lorr {
        let p = mrpp_grid::lorr::load(lorr)?;
        return Ok((p.map, p.map_path));
    }
    let path = need(&inputs.map, "--map (or --lorr)")?;
    Ok((GridMap::load(path)?, path.to_path_buf()))
}

/// The grid problem of the inputs: `--map` with `--scen`, or a `--lorr` problem; both keep the
/// first `--agents` agents. Returns the map, its path, the problem and the file the agents came
/// from, with a note for the summary (LoRR: tasks passed over).
fn problem_of(inputs: &Inputs) -> Result<(GridMap, PathBuf, MapfProblem, PathBuf, String), Fail> {
    if let Some(lorr) = &inputs.lorr {
        let p = mrpp_grid::lorr::load(lorr)?;
        let mut inst = p.instance;
        if let Some(n) = inputs.agents {
            if n == 0 || n > inst.num_agents() {
                return Err(Fail(format!(
                    "--agents must be 1..={} for {} (its teamSize)",
                    inst.num_agents(),
                    lorr.display()
                )));
            }
            inst.starts.truncate(n);
            inst.goals.truncate(n);
        }
        let note = format!(
            " | {} one-shot: goal = first task{}",
            // The 2026 layout's `version` already says "LoRR" ("2026 LoRR").
            if p.version.contains("LoRR") {
                p.version.clone()
            } else {
                format!("LoRR {}", p.version)
            },
            match p.skipped_tasks {
                0 => String::new(),
                k => format!(" ({k} task(s) passed over: first errand already a goal)"),
            }
        );
        let problem = mrpp_grid::problem_on(&p.map, inst);
        return Ok((p.map, p.map_path, problem, lorr.clone(), note));
    }
    let map_path = need(&inputs.map, "--map (or --lorr)")?;
    let scen_path = need(&inputs.scen, "--scen")?;
    let (map, problem) = mrpp_grid::load_problem(map_path, scen_path, inputs.agents)?;
    Ok((
        map,
        map_path.to_path_buf(),
        problem,
        scen_path.to_path_buf(),
        String::new(),
    ))
}

fn load(inputs: &Inputs) -> Result<Loaded<MapfProblem>, Fail> {
    let (map, map_path, problem, _, note) = problem_of(inputs)?;
    let map_file = file_name(&map_path);
    Ok(Loaded {
        summary: format!("map {map_file} | agents {}{note}", problem.num_agents()),
        problem,
        write: Box::new(move |problem, info, outcome, notes, format| {
            Ok(write_plan(
                &map, &map_file, problem, info, outcome, notes, format,
            ))
        }),
    })
}

fn write_plan(
    map: &GridMap,
    map_file: &str,
    problem: &MapfProblem,
    info: RunInfo,
    outcome: &Outcome<MapfProblem>,
    notes: Map<String, Value>,
    format: Format,
) -> String {
    match format {
        Format::Json => {
            let mut env = grid_envelope(map, map_file, problem, info, outcome);
            env.extra.extend(notes);
            env.to_json()
        }
        Format::Lacam => {
            let solved = outcome.as_ref().ok().map(|s| (&s.plan, s.metrics));
            write_lacam(
                map,
                map_file,
                &info.planner,
                problem.instance(),
                solved,
                info.runtime_ms,
                info.seed,
            )
        }
    }
}

/// Reads a plan file in any grid format, detected from the content: PlanViz's LoRR JSON (JSON
/// with `actionModel`), the plan envelope (other JSON), a MAPF Tracker CSV (a header naming
/// `solution_cost`; needs `--scen`) or LaCAM text; checked against `--scen` (or the `--lorr`
/// problem) when given.
pub(crate) fn read_plan(inputs: &Inputs, plan_path: &Path) -> Result<ReadPlan<MapfProblem>, Fail> {
    read_plan_with(inputs, plan_path, false)
}

/// [`read_plan`]; with `to_draw`, a JSON file that says `solved: false` is read as its agents
/// standing on their starts (pictures of an unsolved instance).
fn read_plan_with(
    inputs: &Inputs,
    plan_path: &Path,
    to_draw: bool,
) -> Result<ReadPlan<MapfProblem>, Fail> {
    let (map, _) = map_of(inputs)?;
    let text = mrpp_core::error::read_file(plan_path)?;
    let (problem, plan, claims, about) = if text
        .trim_start_matches('\u{feff}')
        .trim_start()
        .starts_with('{')
        && text.contains("\"actionModel\"")
    {
        let (inst, plan) = one_shot_from_json(&map, &text, plan_path)?;
        let problem = mrpp_grid::problem_on(&map, inst);
        (problem, plan, Map::new(), "PlanViz (LoRR) JSON".into())
    } else if tracker::is_tracker(&text) {
        let (problem, plan) = tracker_plan(inputs, &map, &text, plan_path)?;
        (problem, plan, Map::new(), "MAPF Tracker CSV".into())
    } else if text.trim_start().starts_with('{') {
        let (problem, plan, env) = if to_draw {
            read_grid_plan_to_draw(&map, &text, plan_path)?
        } else {
            read_grid_plan(&map, &text, plan_path)?
        };
        let about = format!("planner {} | seed {}", or_unknown(&env.planner), env.seed);
        (problem, plan, env.metrics, about)
    } else {
        let (inst, plan, claims) = parse_lacam_with_claims(&text, plan_path, &map)?;
        let problem = mrpp_grid::problem_on(&map, inst);
        // The claims are checked here, against a valid plan's metrics; an invalid plan is the
        // validator's to report (with its first violation).
        if let Ok(m) = problem.validate(&plan) {
            claims.check(
                plan_path,
                &plan,
                &problem.instance().goals,
                m.sum_of_costs,
                m.makespan,
            )?;
        }
        (problem, plan, Map::new(), String::new())
    };
    if let Some(scen) = &inputs.scen {
        let n = problem.num_agents();
        if let Some(k) = inputs.agents.filter(|&k| k != n) {
            return Err(Fail(format!(
                "{}: the plan has {n} agents but --agents asks for {k}",
                plan_path.display()
            )));
        }
        let mut expected = mrpp_grid::scen::load_agents(scen, &map, None)?;
        if expected.num_agents() < n {
            return Err(Fail(format!(
                "{}: the plan has {n} agents but {} has only {}",
                plan_path.display(),
                scen.display(),
                expected.num_agents()
            )));
        }
        expected.starts.truncate(n);
        expected.goals.truncate(n);
        check_against(&map, problem.instance(), &expected, plan_path)?;
    } else if inputs.lorr.is_some() {
        let inputs = Inputs {
            agents: inputs.agents.or(Some(problem.num_agents())),
            ..inputs.clone()
        };
        let (_, _, expected, _, _) = problem_of(&inputs)?;
        check_against(&map, problem.instance(), expected.instance(), plan_path)?;
    }
    Ok(ReadPlan {
        problem,
        plan,
        claims,
        about,
    })
}

/// The instance and plan of a MAPF Tracker CSV (`text`, from `plan_path`): its row for
/// `--agents` (or its only row; among rows of that agent count, the one whose
/// `{map_name}-{scen_type}-{type_id}` is the `--scen` file's name), the scenario's first
/// `agents` agents, the moves replayed from their starts. A valid plan must have the row's
/// `solution_cost` as its sum of costs.
fn tracker_plan(
    inputs: &Inputs,
    map: &GridMap,
    text: &str,
    plan_path: &Path,
) -> Result<(MapfProblem, mrpp_core::mapf::plan::Plan), Fail> {
    let scen = inputs.scen.as_deref().ok_or_else(|| {
        Fail(format!(
            "{}: a MAPF Tracker CSV holds moves only: give --scen (the scenario it was solved on)",
            plan_path.display()
        ))
    })?;
    let rows = tracker::parse_tracker(text, plan_path)?;
    let mut picked: Vec<&tracker::TrackerRow> = rows
        .iter()
        .filter(|r| inputs.agents.is_none_or(|n| r.agents == n))
        .collect();
    if picked.len() > 1 {
        let stem = file_name(scen);
        let stem = stem.strip_suffix(".scen").unwrap_or(&stem).to_string();
        picked.retain(|r| format!("{}-{}-{}", r.map_name, r.scen_type, r.type_id) == stem);
    }
    let row = match picked.as_slice() {
        [row] => *row,
        [] => {
            return Err(Fail(format!(
                "{}: no row for {} agents{}",
                plan_path.display(),
                inputs.agents.map_or("any".into(), |n| n.to_string()),
                if rows.len() > 1 {
                    format!(" and scenario {}", file_name(scen))
                } else {
                    String::new()
                }
            )));
        }
        _ => {
            return Err(Fail(format!(
                "{}: {} rows fit: choose one with --agents N",
                plan_path.display(),
                picked.len()
            )));
        }
    };
    let inst = mrpp_grid::scen::load_agents(scen, map, Some(row.agents))?;
    let plan = row.to_plan(map, &inst.starts, plan_path)?;
    let lengths: u64 = row.plan.iter().map(|m| m.len() as u64).sum();
    if lengths != row.solution_cost {
        return Err(Fail(format!(
            "{}:{}: the row claims solution_cost={} but its move strings hold {lengths} moves \
             (each agent's string runs to its last arrival at its goal)",
            plan_path.display(),
            row.line,
            row.solution_cost
        )));
    }
    let problem = mrpp_grid::problem_on(map, inst);
    if let Ok(m) = problem.validate(&plan)
        && m.sum_of_costs != row.solution_cost
    {
        return Err(Fail(format!(
            "{}:{}: the row claims solution_cost={} but its plan gives {}",
            plan_path.display(),
            row.line,
            row.solution_cost,
            m.sum_of_costs
        )));
    }
    Ok((problem, plan))
}

/// The map and a plan the grid validator accepts (for `mrpp execute`).
///
/// # Errors
/// What `read_plan` refuses, or the plan's first violation.
pub(crate) fn read_valid_plan(
    inputs: &Inputs,
    plan_path: &Path,
) -> Result<(GridMap, MapfProblem, mrpp_core::mapf::plan::Plan), Fail> {
    let read = read_plan(inputs, plan_path)?;
    read.problem
        .validate(&read.plan)
        .map_err(|v| Fail(format!("{}: not a valid plan: {v}", plan_path.display())))?;
    let (map, _) = map_of(inputs)?;
    Ok((map, read.problem, read.plan))
}

fn or_unknown(s: &str) -> &str {
    if s.is_empty() { "?" } else { s }
}

/// The plan's starts and goals must be the scenario's (or LoRR problem's) first agents.
fn check_against(
    map: &GridMap,
    inst: &Instance,
    expected: &Instance,
    plan_path: &Path,
) -> Result<(), Fail> {
    if expected.num_agents() != inst.num_agents() {
        return Err(Fail(format!(
            "{}: plan has {} agents but the scenario has {}",
            plan_path.display(),
            inst.num_agents(),
            expected.num_agents()
        )));
    }
    let g = map.graph();
    for i in 0..inst.num_agents() {
        for (what, a, b) in [
            ("start", inst.starts[i], expected.starts[i]),
            ("goal", inst.goals[i], expected.goals[i]),
        ] {
            if a != b {
                return Err(Fail(format!(
                    "{}: agent {i} has {what} {} but the scenario says {}",
                    plan_path.display(),
                    g.label(a),
                    g.label(b)
                )));
            }
        }
    }
    Ok(())
}

/// `mrpp info`: map size, corridor nodes, and lower bounds on any valid plan; for `--map`
/// alone, the map's size, free cells and its largest connected area.
fn info(inputs: &Inputs) -> Result<u8, Fail> {
    if inputs.lorr.is_none() && inputs.scen.is_none() {
        let (map, map_path) = map_of(inputs)?;
        let g = map.graph();
        let largest = mrpp_mapf::map::largest_component(&map).len();
        out!(
            "map {} {}x{} | free cells {} | largest connected area {} cells ({}%) | corridor-compressed nodes {}",
            file_name(&map_path),
            map.width(),
            map.height(),
            g.num_vertices(),
            largest,
            crate::output::number(100.0 * largest as f64 / g.num_vertices() as f64),
            mrpp_grid::corridors::Corridors::build(g).num_nodes()
        );
        out!("no agents given: add --scen (or use --lorr) for lower bounds on a plan");
        return Ok(0);
    }
    let (map, map_path, problem, scen_path, _) = problem_of(inputs)?;
    let (g, inst) = (problem.graph(), problem.instance());
    let corridors = mrpp_grid::corridors::Corridors::build(g);
    let (sum, max) = lower_bounds(g, &inst.starts, &inst.goals).map_err(|i| {
        Fail(format!(
            "{}: agent {i} cannot reach its goal {} from {}",
            scen_path.display(),
            g.label(inst.goals[i]),
            g.label(inst.starts[i])
        ))
    })?;
    out!(
        "map {} {}x{} | free cells {} | corridor-compressed nodes {} | agents {}",
        file_name(&map_path),
        map.width(),
        map.height(),
        g.num_vertices(),
        corridors.num_nodes(),
        inst.num_agents()
    );
    out!("lower bounds: sum_of_costs >= {sum} | makespan >= {max}");
    Ok(0)
}

/// `mrpp render`: the map, starts, goals and paths as SVG.
fn render(inputs: &Inputs, plan: &Path) -> Result<String, Fail> {
    let read = read_plan_with(inputs, plan, true)?;
    let (map, _) = map_of(inputs)?;
    Ok(render_svg(&map, read.problem.instance(), Some(&read.plan)))
}

/// `mrpp view`: the viewer's scene of a grid plan ([`crate::view`]): blocked cells as rows of
/// `#`/`.`, agents at cell centres (cell `(x, y)` spans `[x, x+1] x [y, y+1]`), and the
/// validator's verdict.
/// The viewer scene's `cells.rows` of a grid map: one string per row, `#` blocked, `.` free
/// (also the lifelong family's).
pub(crate) fn scene_rows(map: &GridMap) -> Vec<String> {
    (0..map.height())
        .map(|y| {
            (0..map.width())
                .map(|x| if map.is_free(x, y) { '.' } else { '#' })
                .collect()
        })
        .collect()
}

fn scene(inputs: &Inputs, plan: &Path) -> Result<Value, Fail> {
    let read = read_plan_with(inputs, plan, true)?;
    let (map, map_path) = map_of(inputs)?;
    let inst = read.problem.instance();
    let centre = |v: VertexId| {
        let (x, y) = map.cell(v);
        json!([f64::from(x) + 0.5, f64::from(y) + 0.5])
    };
    let rows = scene_rows(&map);
    // Paths as cell indices `y * width + x` (the page puts agents at cell centres): a third of
    // the size of coordinate pairs, which matters for 10,000 agents.
    let agents: Vec<Value> = (0..inst.num_agents())
        .map(|i| {
            json!({
                "radius": 0.38,
                "start": centre(inst.starts[i]),
                "goal": centre(inst.goals[i]),
                "cells": read.plan.paths[i].iter().map(|&v| {
                    let (x, y) = map.cell(v);
                    u64::from(y) * u64::from(map.width()) + u64::from(x)
                }).collect::<Vec<_>>(),
            })
        })
        .collect();
    let verdict = match read.problem.validate(&read.plan) {
        Ok(m) => json!({"valid": true, "metrics": m}),
        Err(v) => {
            let mut out = json!({"valid": false, "text": v.text});
            if let mrpp_core::Violation::Conflict(c) = v.violation {
                let at = match c.kind {
                    mrpp_core::mapf::plan::ConflictKind::Vertex { v }
                    | mrpp_core::mapf::plan::ConflictKind::Following { v } => centre(v),
                    mrpp_core::mapf::plan::ConflictKind::Swap { u, v } => {
                        let (a, b) = (centre(u), centre(v));
                        json!([
                            (a[0].as_f64().unwrap_or(0.0) + b[0].as_f64().unwrap_or(0.0)) / 2.0,
                            (a[1].as_f64().unwrap_or(0.0) + b[1].as_f64().unwrap_or(0.0)) / 2.0
                        ])
                    }
                };
                out["conflict"] = json!({"t": c.t, "agents": [c.a, c.b], "at": at});
            }
            out
        }
    };
    Ok(json!({
        "family": "grid",
        "title": format!("{} | {}", file_name(&map_path), file_name(plan)),
        "about": read.about,
        "bounds": [0.0, 0.0, f64::from(map.width()), f64::from(map.height())],
        "y_up": false,
        "cells": {"width": map.width(), "height": map.height(), "rows": rows},
        "polygons": [],
        "agents": agents,
        "verdict": verdict,
    }))
}
