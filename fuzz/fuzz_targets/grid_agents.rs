//! MovingAI `.scen` and H* robot files (`scen::parse_agents`) against a fixed map.
#![no_main]
use libfuzzer_sys::fuzz_target;

#[path = "common.rs"]
mod common;

fuzz_target!(|text: &str| {
    let map = common::map();
    let _ = mrpp_grid::scen::parse_agents(text, std::path::Path::new("fuzz.scen"), map, None);
});
