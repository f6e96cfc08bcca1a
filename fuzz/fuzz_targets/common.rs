//! Shared by the grid targets: a small fixed map (8 x 4, two walls) that agent, LaCAM and plan
//! texts are read against.
use mrpp_grid::GridMap;

pub fn map() -> GridMap {
    let text = "type octile\nheight 4\nwidth 8\nmap\n........\n..@.....\n.....@..\n........\n";
    GridMap::parse(text, std::path::Path::new("fuzz.map"))
        .expect("the fixed map parses")
        .0
}
