//! GP programs as S-expressions (`Program::parse`); a program that parses prints and parses back
//! to itself.
#![no_main]
use libfuzzer_sys::fuzz_target;
use mrpp_trees::gp::Program;

fuzz_target!(|text: &str| {
    let path = std::path::Path::new("fuzz.gp");
    if let Ok(p) = Program::parse(text, path) {
        let again = Program::parse(&p.to_string(), path).expect("a printed program parses");
        assert_eq!(again, p);
    }
});
