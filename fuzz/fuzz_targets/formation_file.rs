//! Formation files (`FormationFile::parse`); one that parses is placed on a small fixed polygon
//! map (`Formation::on`: roadmap, linking Q_ini and Q_goal, problem checks).
#![no_main]
use libfuzzer_sys::fuzz_target;
use mrpp_formation::polymap::PolygonMap;
use mrpp_formation::world::{Formation, FormationFile};
use std::path::Path;

const MAP: &str = "[SCALE]\n1\n[BORDER]\n0 0\n12 0\n12 8\n0 8\n[OBSTACLE]\n5 3\n7 3\n7 5\n5 5\n";

fuzz_target!(|text: &str| {
    let path = Path::new("fuzz.json");
    if let Ok(file) = FormationFile::parse(text, path) {
        let map = PolygonMap::parse(MAP, Path::new("fuzz.txt")).expect("the fixed map parses");
        let _ = Formation::on(file, map, path);
    }
});
