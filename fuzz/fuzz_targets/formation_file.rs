//! Formation files (`FormationFile::parse`). The roadmap built on a parsed file is not fuzzed
//! here: building it for every input held the target to under 2,000 executions per second.
#![no_main]
use libfuzzer_sys::fuzz_target;
use mrpp_formation::world::FormationFile;

fuzz_target!(|text: &str| {
    let _ = FormationFile::parse(text, std::path::Path::new("fuzz.json"));
});
