//! `mrpp._native`: the Rust side of the Python package `mrpp` (`python/mrpp/__init__.py` is
//! the public API). Problems are named by their input files, passed as a JSON object with the
//! command line's input flags (`map`, `scen`, `agents`, `lorr`, `instance`, `no_following`,
//! `formation`, `world`); every call goes through [`mrpp_cli::api`], so results equal the
//! command line's. Planning releases the GIL.

use std::path::PathBuf;

use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use serde::Deserialize;

use mrpp_cli::api;

mod simulation;

create_exception!(
    mrpp,
    MrppError,
    PyValueError,
    "A bad input, parameter or plan; the message names the file, line and rule."
);

/// The input flags of a problem (JSON object; unknown keys are refused).
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct InputsJson {
    map: Option<PathBuf>,
    scen: Option<PathBuf>,
    agents: Option<usize>,
    lorr: Option<PathBuf>,
    instance: Option<PathBuf>,
    #[serde(default)]
    no_following: bool,
    formation: Option<PathBuf>,
    world: Option<PathBuf>,
    #[serde(default)]
    lifelong: bool,
    steps: Option<usize>,
    step_time_limit: Option<f64>,
    preprocess_time_limit: Option<f64>,
    action_model: Option<String>,
}

fn inputs(json: &str) -> PyResult<api::Inputs> {
    let i: InputsJson = serde_json::from_str(json)
        .map_err(|e| MrppError::new_err(format!("bad problem inputs: {e}")))?;
    Ok(api::Inputs {
        map: i.map,
        scen: i.scen,
        agents: i.agents,
        lorr: i.lorr,
        instance: i.instance,
        no_following: i.no_following,
        formation: i.formation,
        world: i.world,
        lifelong: i.lifelong,
        steps: i.steps,
        step_time_limit: i.step_time_limit,
        preprocess_time_limit: i.preprocess_time_limit,
        action_model: i.action_model,
        ..api::Inputs::default()
    })
}

/// Every planner: a list of `(family, name, about, [(param, default, doc)])`.
#[pyfunction]
#[allow(clippy::type_complexity)]
fn planners() -> Vec<(
    &'static str,
    &'static str,
    &'static str,
    Vec<(&'static str, &'static str, &'static str)>,
)> {
    api::planners()
        .into_iter()
        .map(|p| (p.family, p.name, p.about, p.params))
        .collect()
}

/// Loads a problem: `(family, summary, number of agents)`.
#[pyfunction]
fn load(inputs_json: &str) -> PyResult<(&'static str, String, usize)> {
    api::load(&inputs(inputs_json)?).map_err(MrppError::new_err)
}

/// Plans (without the GIL): `(solved, status, plan envelope JSON)`.
#[pyfunction]
fn solve(
    py: Python<'_>,
    inputs_json: &str,
    planner: &str,
    params: Vec<(String, String)>,
    seed: u64,
    time_limit: f64,
) -> PyResult<(bool, String, String)> {
    let inputs = inputs(inputs_json)?;
    let planner = planner.to_string();
    py.detach(move || api::solve(&inputs, &planner, &params, seed, time_limit))
        .map(|s| (s.solved, s.status, s.envelope))
        .map_err(MrppError::new_err)
}

/// Validates a plan file (without the GIL): `(agents, metrics JSON)`.
#[pyfunction]
fn validate(py: Python<'_>, inputs_json: &str, plan_path: PathBuf) -> PyResult<(usize, String)> {
    let inputs = inputs(inputs_json)?;
    py.detach(move || api::validate(&inputs, &plan_path))
        .map(|v| (v.agents, serde_json::Value::Object(v.metrics).to_string()))
        .map_err(MrppError::new_err)
}

/// The viewer's HTML page for a plan file.
#[pyfunction]
fn view_page(py: Python<'_>, inputs_json: &str, plan_path: PathBuf) -> PyResult<String> {
    let inputs = inputs(inputs_json)?;
    py.detach(move || api::view_page(&inputs, &plan_path))
        .map_err(MrppError::new_err)
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("MrppError", m.py().get_type::<MrppError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(planners, m)?)?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(solve, m)?)?;
    m.add_function(wrap_pyfunction!(validate, m)?)?;
    m.add_function(wrap_pyfunction!(view_page, m)?)?;
    m.add_class::<simulation::Simulation>()?;
    Ok(())
}
