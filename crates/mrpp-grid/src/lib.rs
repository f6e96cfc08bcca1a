//! mrpp-grid: the grid MAPF family. MovingAI `.map`/`.scen` and the H* paper's map and robot
//! files, and League of Robot Runners problems read as one-shot instances ([`lorr`]), become a
//! [`MapfProblem`] with `stay` rules. The H* paper's planners and its baselines (H*, CA*/HCA*/WHCA*,
//! Enol2023, NSGA-III) live here; the graph-MAPF planners (PIBT, LaCAM/LaCAM*, LNS, CBS, EECBS)
//! and the grid map reader live in `mrpp-mapf`, shared with the other graph families, and are
//! re-exported under their old paths. [`PLANNERS`] is the family's registry; [`io`] holds the
//! LaCAM text result, the SVG picture and the grid plan file.

pub mod coevolution;
pub mod cooperative;
pub mod corridors;
pub mod hstar;
pub mod io;
pub mod lorr;
pub mod nsga3;
pub mod scen;

/// The graph-MAPF planners and grid maps shared with the other graph families (crate
/// `mrpp-mapf`), under the paths they had here.
pub use mrpp_mapf::{cbs, instance_rules, lacam, lns, map, pibt};

use std::path::Path;

use mrpp_core::{MapfProblem, PlannerEntry, Result, Rules};

pub use map::GridMap;

/// The grid family's name in plan files and `mrpp planners --family`.
pub const FAMILY: &str = "grid";

/// Every grid planner, in the order `mrpp planners` lists them.
pub static PLANNERS: &[PlannerEntry<MapfProblem>] = &[
    hstar::ENTRY,
    cooperative::CA_ENTRY,
    cooperative::HCA_ENTRY,
    cooperative::WHCA_ENTRY,
    coevolution::ENTRY,
    nsga3::ENTRY,
    pibt::ENTRY,
    lacam::ENTRY,
    cbs::CBS_ENTRY,
    cbs::EECBS_ENTRY,
];

/// A grid problem: `map` with the agents of `scen` (the first `agents` of them; all when
/// `None`), `stay` rules.
///
/// # Errors
/// File errors naming file and line ([`map::GridMap::load`], [`scen::load_agents`]).
pub fn load_problem(
    map_path: &Path,
    scen_path: &Path,
    agents: Option<usize>,
) -> Result<(GridMap, MapfProblem)> {
    let map = GridMap::load(map_path)?;
    let inst = scen::load_agents(scen_path, &map, agents)?;
    let problem = problem_on(&map, inst);
    Ok((map, problem))
}

/// The [`MapfProblem`] of `inst` on `map` with grid rules (`stay`, following allowed).
pub fn problem_on(map: &GridMap, inst: mrpp_core::Instance) -> MapfProblem {
    MapfProblem::new(map.graph_arc().clone(), inst, Rules::default())
        .expect("instances parsed against the map name only its vertices")
}
