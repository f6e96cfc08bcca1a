//! Polygon maps of the formation family (`PolygonMap::parse`).
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|text: &str| {
    let _ = mrpp_formation::polymap::PolygonMap::parse(text, std::path::Path::new("fuzz.txt"));
});
