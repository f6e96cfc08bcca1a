//! Tree instance JSON (`TreeInstance::parse`).
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|text: &str| {
    let _ = mrpp_trees::instance::TreeInstance::parse(text, std::path::Path::new("fuzz.json"));
});
