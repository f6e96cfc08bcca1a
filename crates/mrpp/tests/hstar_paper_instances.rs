//! H* on every bundled instance of the paper's Table I (and the other Scenario-2 map): every plan
//! it calls solved passes the validator.

use std::path::PathBuf;

use mrpp::experiments::hstar_instances::{Scenario2Map, table1_instances};
use mrpp::grid_mapf::hstar::HStar;
use mrpp::solve::{SolveOptions, solve};
use mrpp::{GridMap, Instance, ValidateOptions};

fn data() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/hstar-paper")
}

#[test]
fn hstar_solves_every_table1_instance() {
    for sc2 in [Scenario2Map::OpenRooms, Scenario2Map::ObstacleRooms] {
        for pi in table1_instances(&data(), sc2) {
            let map = GridMap::load(&pi.map).unwrap();
            let inst = Instance::load(&pi.robots_file, &map, None).unwrap();
            assert_eq!(inst.num_agents(), pi.robots);
            let plan = solve(
                &HStar::default(),
                map.graph(),
                &inst,
                &SolveOptions::default(),
            )
            .unwrap_or_else(|e| panic!("SC{} {}: {e}", pi.scenario, pi.label));
            let m = plan
                .validate(map.graph(), &inst, ValidateOptions::default())
                .unwrap();
            eprintln!(
                "SC{} {:>6} {:?}: max {} sum {}",
                pi.scenario, pi.label, sc2, m.makespan, m.sum_of_costs
            );
        }
    }
}

#[test]
fn paper_variant_never_returns_an_invalid_plan() {
    use mrpp::solve::{Planner, Unsolved};
    let mut solved = 0;
    for pi in table1_instances(&data(), Scenario2Map::OpenRooms) {
        let map = GridMap::load(&pi.map).unwrap();
        let inst = Instance::load(&pi.robots_file, &map, None).unwrap();
        // Called directly, not through `solve`, so an invalid plan would not be hidden.
        match HStar::paper().plan(map.graph(), &inst, &SolveOptions::default()) {
            Ok(plan) => {
                plan.validate(map.graph(), &inst, ValidateOptions::default())
                    .unwrap_or_else(|v| {
                        panic!(
                            "SC{} {}: {}",
                            pi.scenario,
                            pi.label,
                            v.describe(map.graph())
                        )
                    });
                solved += 1;
            }
            Err(Unsolved::GaveUp(why)) => {
                eprintln!("paper SC{} {}: not solved: {why}", pi.scenario, pi.label)
            }
            Err(Unsolved::TimeLimit) => panic!("no time limit was set"),
        }
    }
    // The paper's steps alone do finish some instances (e.g. Scenario 1 with 6 robots).
    assert!(solved > 0);
}
