//! LaCAM result text (`parse_lacam_with_claims`) against a fixed map; a plan that parses is
//! validated and its claims checked, as `mrpp validate` does.
#![no_main]
use libfuzzer_sys::fuzz_target;
use mrpp_core::Problem as _;

#[path = "common.rs"]
mod common;

fuzz_target!(|text: &str| {
    let map = common::map();
    let path = std::path::Path::new("fuzz.txt");
    if let Ok((inst, plan, claims)) = mrpp_grid::io::lacam::parse_lacam_with_claims(text, path, map)
    {
        let problem = mrpp_grid::problem_on(map, inst);
        if let Ok(m) = problem.validate(&plan) {
            let _ = claims.check(
                path,
                &plan,
                &problem.instance().goals,
                m.sum_of_costs,
                m.makespan,
            );
        }
    }
});
