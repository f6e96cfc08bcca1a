//! MovingAI `.map` and H* paper maps (`GridMap::parse`): never a panic, whatever the bytes.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|text: &str| {
    let _ = mrpp_grid::GridMap::parse(text, std::path::Path::new("fuzz.map"));
});
