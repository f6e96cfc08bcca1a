//! The formation family on the command line: `--formation F.json` (map, robots, Q_ini, Q_goal,
//! radius, cost model), plans as the envelope with roadmap vertex ids (the roadmap and the problem
//! embedded, so the independent checker needs only the plan), `info` (roadmap statistics) and
//! `render` (map, roadmap, paths as SVG).

use std::path::Path;

use mrpp_formation::world::{Formation, formation_envelope, read_formation_plan};
use mrpp_formation::{FormationProblem, render::render_svg};

use crate::family::{Def, Inputs, Loaded, ReadPlan};
use crate::output::{Fail, file_name, out};

/// The formation family.
pub(crate) static FORMATION: Def<FormationProblem> = Def {
    name: mrpp_formation::FAMILY,
    planners: mrpp_formation::PLANNERS,
    claims: |i| i.formation.is_some(),
    load,
    read_plan,
    info: Some(info),
    render: Some(render),
    scene: Some(scene),
    lacam: false,
};

fn formation(inputs: &Inputs) -> Result<(Formation, &Path), Fail> {
    let path = inputs
        .formation
        .as_deref()
        .ok_or_else(|| Fail("formation problems need --formation".into()))?;
    Ok((Formation::load(path)?, path))
}

fn load(inputs: &Inputs) -> Result<Loaded<FormationProblem>, Fail> {
    let (f, path) = formation(inputs)?;
    let file = file_name(path);
    let r = f.problem.roadmap();
    let summary = format!(
        "formation {file} | map {} | robots {} | roadmap {} vertices, {} corridors ({:.1} ms) | cost {}",
        file_name(&f.file.map),
        f.problem.robots(),
        r.num_vertices(),
        r.edges.len(),
        f.build_ms,
        f.problem.cost_model().label()
    );
    Ok(Loaded {
        problem: f.problem.clone(),
        summary,
        write: Box::new(move |_, info, outcome, notes, _| {
            let mut env = formation_envelope(&file, &f, info, outcome);
            env.extra.extend(notes);
            Ok(env.to_json())
        }),
    })
}

fn read_plan(inputs: &Inputs, plan_path: &Path) -> Result<ReadPlan<FormationProblem>, Fail> {
    let (f, _) = formation(inputs)?;
    let text = mrpp_core::error::read_file(plan_path)?;
    mrpp_core::envelope::check_family(&text, mrpp_formation::FAMILY, plan_path)?;
    let (plan, env) = read_formation_plan(&f, &text, plan_path)?;
    let planner = if env.planner.is_empty() {
        "?"
    } else {
        env.planner.as_str()
    };
    Ok(ReadPlan {
        problem: f.problem,
        plan,
        claims: env.metrics,
        about: format!("planner {planner} | seed {}", env.seed),
    })
}

/// `mrpp info --formation F`: the roadmap and its corridors.
fn info(inputs: &Inputs) -> Result<u8, Fail> {
    let (f, path) = formation(inputs)?;
    let r = f.problem.roadmap();
    let (components, cycles) = r.components_and_cycles();
    let narrow = r
        .edges
        .iter()
        .filter(|e| mrpp_formation::cost::capacity(e, f.problem.radius()) < f.problem.robots())
        .count();
    out!(
        "formation {} | map {} ({} obstacles) | robots {} | radius {}",
        file_name(path),
        file_name(&f.file.map),
        f.map.obstacles.len(),
        f.problem.robots(),
        f.problem.radius()
    );
    out!(
        "roadmap: {} vertices, {} corridors ({narrow} narrower than the formation), {components} component(s), {cycles} independent cycle(s), built in {:.1} ms",
        r.num_vertices(),
        r.edges.len(),
        f.build_ms
    );
    Ok(0)
}

/// `mrpp render --formation F --plan P --out F.svg`.
/// A file that says `solved: false` is drawn as the formation at Q_ini and its goal Q_goal.
fn render(inputs: &Inputs, plan_path: &Path) -> Result<String, Fail> {
    let (f, _) = formation(inputs)?;
    if crate::verbs::unsolved_status(plan_path).is_some() {
        return Ok(render_svg(&f.map, &f.problem, None));
    }
    let read = read_plan(inputs, plan_path)?;
    Ok(render_svg(&f.map, &read.problem, Some(&read.plan)))
}

/// Frames a formation plan is sampled at for the viewer.
const FRAMES: usize = 240;

/// The point at arc length fraction `f` (0..=1) along `line`.
fn along(line: &[[f64; 2]], f: f64) -> [f64; 2] {
    let total: f64 = line.windows(2).map(|w| dist(w[0], w[1])).sum();
    let mut left = f.clamp(0.0, 1.0) * total;
    for w in line.windows(2) {
        let d = dist(w[0], w[1]);
        if left <= d && d > 0.0 {
            let g = left / d;
            return [
                w[0][0] + (w[1][0] - w[0][0]) * g,
                w[0][1] + (w[1][1] - w[0][1]) * g,
            ];
        }
        left -= d;
    }
    *line.last().unwrap_or(&[0.0, 0.0])
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// `mrpp view`: the viewer's scene of a formation plan ([`crate::view`]): the map's obstacles,
/// the roadmap's corridors, and each robot along its corridors' centre lines under the paper's
/// timing (waiting at merges), sampled at 240 frames from 0 to `c_max`.
fn scene(inputs: &Inputs, plan_path: &Path) -> Result<serde_json::Value, Fail> {
    use mrpp_core::Problem;
    use serde_json::json;
    let (f, path) = formation(inputs)?;
    let r = f.problem.roadmap();
    // A file that says `solved: false`: every robot standing at Q_ini, Q_goal marked.
    let read = match crate::verbs::unsolved_status(plan_path) {
        Some(status) => ReadPlan {
            problem: f.problem.clone(),
            plan: mrpp_formation::FormationPlan {
                paths: vec![vec![f.problem.start()]; f.problem.robots()],
            },
            claims: serde_json::Map::new(),
            about: format!("no plan (solved=false, status {status})"),
        },
        None => read_plan(inputs, plan_path)?,
    };
    let (lo, hi) = f.map.bounds();
    let mut polygons: Vec<Vec<[f64; 2]>> =
        f.map.obstacles.iter().map(|o| o.vertices.clone()).collect();
    polygons.retain(|p| p.len() >= 3);
    let segments: Vec<[[f64; 2]; 2]> = r
        .edges
        .iter()
        .flat_map(|e| e.polyline.windows(2).map(|w| [w[0], w[1]]))
        .collect();
    let verdict = match read.problem.validate(&read.plan) {
        Ok(m) => json!({"valid": true, "metrics": m}),
        Err(v) => json!({"valid": false, "text": v.to_string()}),
    };
    let radius = f.problem.radius();
    let unsolved = crate::verbs::unsolved_status(plan_path).is_some();
    let agents: Vec<serde_json::Value> = match f.problem.schedule(&read.plan.paths) {
        Err(_) if unsolved => (0..f.problem.robots())
            .map(|_| {
                let (s, g) = (
                    r.points[f.problem.start() as usize],
                    r.points[f.problem.goal() as usize],
                );
                json!({"radius": radius, "start": s, "goal": g, "path": [s]})
            })
            .collect(),
        Err(_) => Vec::new(),
        Ok(schedule) => {
            let end = schedule
                .iter()
                .filter_map(|s| s.last().map(|&(_, a)| a))
                .fold(0.0, f64::max);
            read.plan
                .paths
                .iter()
                .zip(&schedule)
                .map(|(p, times)| {
                    let at = |tau: f64| -> [f64; 2] {
                        for (k, &(depart, arrive)) in times.iter().enumerate() {
                            if tau < depart {
                                return r.points[p[k] as usize];
                            }
                            if tau < arrive {
                                let e = r.edge_between(p[k], p[k + 1]).expect("a validated path");
                                let edge = &r.edges[e as usize];
                                let frac = (tau - depart) / (arrive - depart).max(1e-12);
                                let frac = if edge.u == p[k] { frac } else { 1.0 - frac };
                                return along(&edge.polyline, frac);
                            }
                        }
                        r.points[*p.last().expect("a path") as usize]
                    };
                    let frames: Vec<[f64; 2]> = (0..=FRAMES)
                        .map(|k| at(end * k as f64 / FRAMES as f64))
                        .collect();
                    json!({
                        "radius": radius,
                        "start": r.points[p[0] as usize],
                        "goal": r.points[*p.last().expect("a path") as usize],
                        "path": frames,
                    })
                })
                .collect()
        }
    };
    Ok(json!({
        "family": "formation",
        "title": format!("{} | {}", file_name(path), file_name(plan_path)),
        "about": read.about,
        "bounds": [lo[0], lo[1], hi[0], hi[1]],
        "y_up": true,
        "polygons": polygons,
        "segments": segments,
        "agents": agents,
        "verdict": verdict,
    }))
}
