//! Continuous world JSON (`World::parse`).
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|text: &str| {
    let _ = mrpp_continuous::world::World::parse(text, std::path::Path::new("fuzz.json"));
});
