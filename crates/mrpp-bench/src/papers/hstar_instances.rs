//! The instances of the H* paper's Table I, found under a directory laid out like the bundled
//! `data/hstar-paper/` (`scenario1/`, `scenario2/`, `scenario3/`).

use std::path::{Path, PathBuf};

/// Which Scenario-2 map: the paper describes four *open* rooms (`_B`), the default.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Scenario2Map {
    #[default]
    OpenRooms,
    /// `scenery_4rooms.txt`: each room holds the Scenario-1 obstacles.
    ObstacleRooms,
}

/// One Table I instance.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PaperInstance {
    /// 1, 2 or 3.
    pub scenario: u8,
    /// Robots in the instance (Scenario 2: 4 × robots per room).
    pub robots: usize,
    /// Table II's row label: `6`, `3 × 4`, `10`, ...
    pub label: String,
    pub map: PathBuf,
    pub robots_file: PathBuf,
}

/// Table I: scenario 1 with 6–15 robots, scenario 2 with 3–6 per room, scenario 3 with 10–30 step 5.
pub fn table1_instances(root: &Path, sc2: Scenario2Map) -> Vec<PaperInstance> {
    let mut out = Vec::new();
    for n in 6..=15 {
        out.push(PaperInstance {
            scenario: 1,
            robots: n,
            label: n.to_string(),
            map: root.join("scenario1/scenery.txt"),
            robots_file: root.join(format!("scenario1/{n}coordinates.txt")),
        });
    }
    let sc2_map = match sc2 {
        Scenario2Map::OpenRooms => "scenario2/scenery_4rooms_B.txt",
        Scenario2Map::ObstacleRooms => "scenario2/scenery_4rooms.txt",
    };
    for k in 3..=6 {
        out.push(PaperInstance {
            scenario: 2,
            robots: 4 * k,
            label: format!("{k} × 4"),
            map: root.join(sc2_map),
            robots_file: root.join(format!("scenario2/{k}robots-per-room.txt")),
        });
    }
    for n in (10..=30).step_by(5) {
        out.push(PaperInstance {
            scenario: 3,
            robots: n,
            label: n.to_string(),
            map: root.join("scenario3/scenery_warehouse.txt"),
            robots_file: root.join(format!("scenario3/{n}warehouse")),
        });
    }
    out
}
