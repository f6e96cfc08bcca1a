//! mrpp-grid: the grid MAPF family. MovingAI `.map`/`.scen` and the H* paper's map and robot
//! files become a [`MapfProblem`] with `stay` rules; the planners (H*, CA*/HCA*/WHCA*, Enol2023,
//! NSGA-III, PIBT, LaCAM/LaCAM*, CBS, EECBS) work on any graph with cell coordinates. [`PLANNERS`] is the family's registry;
//! [`io`] holds the LaCAM text result, the SVG picture and the grid plan file.

pub mod cbs;
pub mod coevolution;
pub mod cooperative;
pub mod corridors;
pub mod hstar;
pub mod instance_rules;
pub mod io;
pub mod lacam;
pub mod lns;
pub mod lorr;
pub mod map;
pub mod nsga3;
pub mod pibt;
pub mod scen;

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
