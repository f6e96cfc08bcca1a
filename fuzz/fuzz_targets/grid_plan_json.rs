//! The JSON plan envelope of grids (`read_grid_plan`) against a fixed map, then the validator.
#![no_main]
use libfuzzer_sys::fuzz_target;
use mrpp_core::Problem as _;

#[path = "common.rs"]
mod common;

fuzz_target!(|text: &str| {
    let map = common::map();
    if let Ok((problem, plan, _)) =
        mrpp_grid::io::plan_json::read_grid_plan(map, text, std::path::Path::new("fuzz.json"))
    {
        let _ = problem.validate(&plan);
    }
});
