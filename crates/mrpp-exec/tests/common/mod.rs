//! Helpers shared by this crate's test files (each includes this module with `mod common;`):
//! bundled MovingAI instances and their plans.

use std::path::{Path, PathBuf};

use mrpp_core::mapf::plan::Plan;
use mrpp_core::{Ctx, MapfProblem, solve};
use mrpp_grid::{GridMap, PLANNERS};

/// A bundled MovingAI file: `data/movingai/{rel}`.
#[allow(dead_code)]
pub fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/movingai")
        .join(rel)
}

/// The first `agents` agents of the bundled `scen` on the bundled `map`: the grid and the problem.
#[allow(dead_code)]
pub fn bundled(map: &str, scen: &str, agents: usize) -> (GridMap, MapfProblem) {
    mrpp_grid::load_problem(&data(map), &data(scen), Some(agents)).unwrap()
}

/// [`bundled`] with the plan the registry's `planner` (default parameters, `Ctx::default()`)
/// finds for it.
#[allow(dead_code)]
pub fn planned(
    map: &str,
    scen: &str,
    agents: usize,
    planner: &str,
) -> (GridMap, MapfProblem, Plan) {
    let (grid, problem) = bundled(map, scen, agents);
    let entry = PLANNERS.iter().find(|e| e.name == planner).unwrap();
    let plan = solve(
        entry.instantiate(&[]).unwrap().as_ref(),
        &problem,
        &Ctx::default(),
    )
    .unwrap()
    .plan;
    (grid, problem, plan)
}
