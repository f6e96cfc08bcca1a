//! In-memory entry points for bindings (the Python package in `crates/mrpp-py`): the command
//! line's one family table, loaders, planner registry, validator and viewer page, without
//! printing or writing files. A problem is named by its input files ([`Inputs`], the same fields
//! as the command line's flags), so a plan made here equals `mrpp solve`'s for the same files,
//! planner, parameters and seed.
//!
//! Every error is the command line's one-line message (file, line and rule for bad inputs).

use std::path::Path;

use serde_json::Value;

pub use crate::family::Inputs;
use crate::family::{FAMILIES, Format, SolveRequest, family_of_inputs};

/// One planner of the registry.
#[derive(Debug, Clone)]
pub struct PlannerInfo {
    /// The family it plans for: `grid`, `trees`, `formation` or `continuous`.
    pub family: &'static str,
    pub name: &'static str,
    /// One line: what it is and its source (paper, section).
    pub about: &'static str,
    /// `(name, default, doc)` of each `-p` parameter.
    pub params: Vec<(&'static str, &'static str, &'static str)>,
}

/// A planner run's outcome.
#[derive(Debug, Clone)]
pub struct Solution {
    /// True when the plan is complete and passed the family's validator.
    pub solved: bool,
    /// `solved`, or why not (e.g. `time limit reached`).
    pub status: String,
    /// The plan envelope (`format: "mrpp-plan/1"`) as JSON text, exactly what `mrpp solve
    /// --out plan.json` writes.
    pub envelope: String,
}

/// A valid plan's check.
#[derive(Debug, Clone)]
pub struct Validated {
    pub agents: usize,
    /// The validator's metrics (e.g. `sum_of_costs`, `makespan`, `sum_of_moves` on grids).
    pub metrics: serde_json::Map<String, Value>,
}

/// Every registered planner (the order of `mrpp planners`).
pub fn planners() -> Vec<PlannerInfo> {
    FAMILIES
        .iter()
        .flat_map(|f| {
            f.planners()
                .into_iter()
                .map(|(name, about, params)| PlannerInfo {
                    family: f.name(),
                    name,
                    about,
                    params: params.iter().map(|p| (p.name, p.default, p.doc)).collect(),
                })
        })
        .collect()
}

/// Loads the inputs: `(family, summary, number of agents)`.
///
/// # Errors
/// Inputs of no family, or a file that does not read (file, line and rule).
pub fn load(inputs: &Inputs) -> Result<(&'static str, String, usize), String> {
    let family = family_of_inputs(inputs).map_err(|f| f.0)?;
    let (summary, agents) = family.describe(inputs).map_err(|f| f.0)?;
    Ok((family.name(), summary, agents))
}

/// The lifelong problem the inputs name (`lorr`, with `steps`, `step_time_limit`,
/// `action_model`), for a run driven step by step by the caller ([`mrpp_lifelong::runner::Run`]).
///
/// # Errors
/// No `lorr` file, or a file that does not read (file, line and rule), or a bad option.
pub fn load_lifelong(inputs: &Inputs) -> Result<mrpp_lifelong::LifelongProblem, String> {
    crate::lifelong_family::load_problem(inputs).map_err(|f| f.0)
}

/// Plans with `planner` (with `params` as `-p key=value` pairs), `seed` and `time_limit`
/// seconds; the plan went through the family's validator when `solved`.
///
/// # Errors
/// An unknown planner or parameter, inputs of another family, a bad time limit, unreadable
/// inputs, or an invalid plan (a bug in mrpp).
pub fn solve(
    inputs: &Inputs,
    planner: &str,
    params: &[(String, String)],
    seed: u64,
    time_limit: f64,
) -> Result<Solution, String> {
    let family = crate::family::family_of_planner(planner).map_err(|f| f.0)?;
    let mut inputs = inputs.clone();
    inputs.lifelong |= family.name() == mrpp_lifelong::FAMILY;
    let req = SolveRequest {
        inputs,
        planner: planner.to_string(),
        params: params.to_vec(),
        seed,
        time_limit,
        out: None,
        format: Format::Json,
        save_program: None,
        command: "api",
    };
    let (solved, status, envelope) = family.solve_quietly(&req).map_err(|f| f.0)?;
    Ok(Solution {
        solved,
        status,
        envelope,
    })
}

/// Validates the plan file `plan` (envelope or LaCAM text) against the inputs, claims included.
///
/// # Errors
/// The first violation (agents, cell or node, time step), a claim the paths contradict, or an
/// unreadable file.
pub fn validate(inputs: &Inputs, plan: &Path) -> Result<Validated, String> {
    let inputs = &crate::verbs::with_plan_kind(inputs, plan);
    let c = family_of_inputs(inputs)
        .and_then(|f| f.check(inputs, plan))
        .map_err(|f| f.0)?;
    Ok(Validated {
        agents: c.agents,
        metrics: c.metrics,
    })
}

/// The viewer's self-contained HTML page (what `mrpp view` writes) for the plan file `plan`.
///
/// # Errors
/// Unreadable inputs or plan, or a family without a viewer scene.
pub fn view_page(inputs: &Inputs, plan: &Path) -> Result<String, String> {
    let scene = family_of_inputs(inputs)
        .and_then(|f| f.scene(inputs, plan))
        .map_err(|f| f.0)?;
    Ok(crate::view::page(&scene))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn data(rel: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../data")
            .join(rel)
    }

    #[test]
    fn solve_then_validate_and_view_in_memory() {
        let inputs = Inputs {
            map: Some(data("movingai/random-32-32-20.map")),
            scen: Some(data("movingai/random-32-32-20-random-1.scen")),
            agents: Some(20),
            ..Inputs::default()
        };
        let (family, summary, agents) = load(&inputs).unwrap();
        assert_eq!((family, agents), ("grid", 20));
        assert!(summary.contains("random-32-32-20.map"), "{summary}");
        let s = solve(&inputs, "lacam", &[], 0, 10.0).unwrap();
        assert!(s.solved, "{}", s.status);
        let env: Value = serde_json::from_str(&s.envelope).unwrap();
        assert_eq!(env["format"], "mrpp-plan/1");
        let path = std::env::temp_dir().join(format!("mrpp-api-{}.json", std::process::id()));
        std::fs::write(&path, &s.envelope).unwrap();
        let v = validate(&inputs, &path).unwrap();
        assert_eq!(v.agents, 20);
        assert_eq!(v.metrics["sum_of_costs"], env["metrics"]["sum_of_costs"]);
        assert!(
            view_page(&inputs, &path)
                .unwrap()
                .starts_with("<!doctype html>")
        );
        std::fs::remove_file(&path).unwrap();
        assert!(
            planners()
                .iter()
                .any(|p| p.family == "trees" && p.name == "psw")
        );
        let bad = solve(&inputs, "psw", &[], 0, 1.0).unwrap_err();
        assert!(bad.contains("plans trees problems"), "{bad}");
        let bad = solve(&inputs, "lacam", &[], 0, -1.0).unwrap_err();
        assert!(bad.contains("--time-limit must be more than 0"), "{bad}");
    }
}
