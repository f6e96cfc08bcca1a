//! Shared by the grid targets: a small fixed map (8 x 4, two walls) that agent, LaCAM and plan
//! texts are read against, parsed once per process.
use std::sync::LazyLock;

use mrpp_grid::GridMap;

static MAP: LazyLock<GridMap> = LazyLock::new(|| {
    let text = "type octile\nheight 4\nwidth 8\nmap\n........\n..@.....\n.....@..\n........\n";
    GridMap::parse(text, std::path::Path::new("fuzz.map"))
        .expect("the fixed map parses")
        .0
});

pub fn map() -> &'static GridMap {
    &MAP
}
