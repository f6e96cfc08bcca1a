//! The continuous family on the command line: `--world W.json` (workspace, polygon obstacles,
//! robots with radius, speed, start and goal), plans as the envelope with `[x, y]` positions per
//! step, `info` (the world and each robot's ideal path) and `render` (obstacles, trajectories,
//! final discs as SVG).

use std::path::Path;

use mrpp_continuous::plan_file::{continuous_envelope, read_continuous_plan};
use mrpp_continuous::render::render_svg;
use mrpp_continuous::{NavProblem, World};

use crate::family::{Def, Inputs, Loaded, ReadPlan};
use crate::output::{Fail, file_name, out};

/// The continuous family.
pub(crate) static CONTINUOUS: Def<NavProblem> = Def {
    name: mrpp_continuous::FAMILY,
    planners: mrpp_continuous::PLANNERS,
    claims: |i| i.world.is_some(),
    load,
    read_plan,
    info: Some(info),
    render: Some(render),
    scene: Some(scene),
    lacam: false,
};

fn world(inputs: &Inputs) -> Result<(NavProblem, &Path), Fail> {
    let path = inputs
        .world
        .as_deref()
        .ok_or_else(|| Fail("continuous problems need --world".into()))?;
    Ok((NavProblem::new(World::load(path)?), path))
}

fn load(inputs: &Inputs) -> Result<Loaded<NavProblem>, Fail> {
    let (problem, path) = world(inputs)?;
    let file = file_name(path);
    let w = problem.world();
    let summary = format!(
        "world {file} | robots {} | obstacles {} | epsilon {} | step limit {}",
        w.robots.len(),
        w.obstacles.len(),
        w.epsilon,
        w.step_limit
    );
    Ok(Loaded {
        problem,
        summary,
        write: Box::new(move |p, info, outcome, notes, _| {
            let mut env = continuous_envelope(&file, p, info, outcome);
            env.extra.extend(notes);
            Ok(env.to_json())
        }),
    })
}

fn read_plan(inputs: &Inputs, plan_path: &Path) -> Result<ReadPlan<NavProblem>, Fail> {
    let (problem, _) = world(inputs)?;
    let text = mrpp_core::error::read_file(plan_path)?;
    mrpp_core::envelope::check_family(&text, mrpp_continuous::FAMILY, plan_path)?;
    let (plan, env) = read_continuous_plan(&problem, &text, plan_path)?;
    let planner = if env.planner.is_empty() {
        "?"
    } else {
        env.planner.as_str()
    };
    Ok(ReadPlan {
        problem,
        plan,
        claims: env.metrics,
        about: format!("planner {planner} | seed {}", env.seed),
    })
}

/// `mrpp info --world W`: the world and every robot's straight and ideal distance.
fn info(inputs: &Inputs) -> Result<u8, Fail> {
    let (p, path) = world(inputs)?;
    let w = p.world();
    out!(
        "world {} | workspace {:?} | obstacles {} | robots {} | epsilon {} | step limit {}",
        file_name(path),
        w.workspace,
        w.obstacles.len(),
        w.robots.len(),
        w.epsilon,
        w.step_limit
    );
    for (i, (r, ideal)) in w.robots.iter().zip(p.ideal()).enumerate() {
        let straight = mrpp_continuous::geometry::dist(r.start, r.goal);
        let ideal = ideal.map_or("unreachable".to_string(), |d| format!("{d:.2}"));
        out!(
            "robot {i}: radius {} speed {} | straight {straight:.2} | ideal path {ideal}",
            r.radius,
            r.speed
        );
    }
    Ok(0)
}

/// `mrpp render --world W --plan P --out F.svg`.
/// A file that says `solved: false` is drawn as the world with the robots' starts and goals.
fn render(inputs: &Inputs, plan_path: &Path) -> Result<String, Fail> {
    if crate::verbs::unsolved_status(plan_path).is_some() {
        let (problem, _) = world(inputs)?;
        return Ok(render_svg(problem.world(), None));
    }
    let read = read_plan(inputs, plan_path)?;
    Ok(render_svg(read.problem.world(), Some(&read.plan)))
}

/// `mrpp view`: the viewer's scene of a continuous plan ([`crate::view`]): the workspace and
/// obstacle polygons (y up), each robot's disc along its positions, and the validator's verdict.
fn scene(inputs: &Inputs, plan_path: &Path) -> Result<serde_json::Value, Fail> {
    use mrpp_core::Problem;
    use serde_json::json;
    // A file that says `solved: false`: every robot on its start, its goal marked.
    if let Some(status) = crate::verbs::unsolved_status(plan_path) {
        let (problem, _) = world(inputs)?;
        let w = problem.world();
        let agents: Vec<serde_json::Value> = w
            .robots
            .iter()
            .map(|r| json!({"radius": r.radius, "start": r.start, "goal": r.goal, "path": [r.start]}))
            .collect();
        return Ok(json!({
            "family": "continuous",
            "title": format!("{} | {}", crate::output::file_name(inputs.world.as_deref().unwrap_or(Path::new("world"))), crate::output::file_name(plan_path)),
            "about": format!("no plan (solved=false, status {status})"),
            "bounds": w.workspace,
            "y_up": true,
            "polygons": w.obstacles,
            "agents": agents,
            "verdict": {"valid": false, "text": format!("the file holds no plan (status {status})")},
        }));
    }
    let read = read_plan(inputs, plan_path)?;
    let w = read.problem.world();
    let agents: Vec<serde_json::Value> = w
        .robots
        .iter()
        .zip(&read.plan.positions)
        .map(
            |(r, path)| json!({"radius": r.radius, "start": r.start, "goal": r.goal, "path": path}),
        )
        .collect();
    let verdict = match read.problem.validate(&read.plan) {
        Ok(m) => json!({"valid": true, "metrics": m}),
        Err(v) => json!({"valid": false, "text": v.to_string()}),
    };
    Ok(json!({
        "family": "continuous",
        "title": format!("{} | {}", crate::output::file_name(inputs.world.as_deref().unwrap_or(Path::new("world"))), crate::output::file_name(plan_path)),
        "about": read.about,
        "bounds": w.workspace,
        "y_up": true,
        "polygons": w.obstacles,
        "agents": agents,
        "verdict": verdict,
    }))
}
