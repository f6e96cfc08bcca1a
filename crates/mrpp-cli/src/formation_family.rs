//! The formation family on the command line: `--formation F.json` (map, robots, Q_ini, Q_goal,
//! radius, cost model), plans as the envelope with roadmap vertex ids (the roadmap and the problem
//! embedded, so the independent checker needs only the plan), `info` (roadmap statistics) and
//! `render` (map, roadmap, paths as SVG).

use std::path::Path;

use mrpp_formation::world::{Formation, formation_envelope, read_formation_plan};
use mrpp_formation::{FormationProblem, render::render_svg};

use crate::family::{Def, Inputs, Loaded, ReadPlan};
use crate::output::{Fail, file_name, write_atomic};

/// The formation family.
pub(crate) static FORMATION: Def<FormationProblem> = Def {
    name: mrpp_formation::FAMILY,
    planners: mrpp_formation::PLANNERS,
    claims: |i| i.formation.is_some(),
    load,
    read_plan,
    info: Some(info),
    render: Some(render),
    scene: None,
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
    println!(
        "formation {} | map {} ({} obstacles) | robots {} | radius {}",
        file_name(path),
        file_name(&f.file.map),
        f.map.obstacles.len(),
        f.problem.robots(),
        f.problem.radius()
    );
    println!(
        "roadmap: {} vertices, {} corridors ({narrow} narrower than the formation), {components} component(s), {cycles} independent cycle(s), built in {:.1} ms",
        r.num_vertices(),
        r.edges.len(),
        f.build_ms
    );
    Ok(0)
}

/// `mrpp render --formation F --plan P --out F.svg`.
fn render(inputs: &Inputs, plan_path: &Path, out: &Path) -> Result<u8, Fail> {
    let read = read_plan(inputs, plan_path)?;
    let (f, _) = formation(inputs)?;
    write_atomic(out, &render_svg(&f.map, &read.problem, Some(&read.plan)))?;
    println!("picture written to {}", out.display());
    Ok(0)
}
