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
    for pi in table1_instances(&data(), Scenario2Map::OpenRooms) {
        let map = GridMap::load(&pi.map).unwrap();
        let inst = Instance::load(&pi.robots_file, &map, None).unwrap();
        let r = HStar::paper().plan_checked(&map, &inst);
        eprintln!("paper SC{} {:>6}: {}", pi.scenario, pi.label, r);
    }
}

trait PlanChecked {
    fn plan_checked(&self, map: &GridMap, inst: &Instance) -> String;
}

impl PlanChecked for HStar {
    fn plan_checked(&self, map: &GridMap, inst: &Instance) -> String {
        use mrpp::solve::Planner;
        match self.plan(map.graph(), inst, &SolveOptions::default()) {
            Ok(plan) => {
                let m = plan
                    .validate(map.graph(), inst, ValidateOptions::default())
                    .unwrap();
                format!("solved, max {} sum {}", m.makespan, m.sum_of_costs)
            }
            Err(e) => format!("not solved: {e}"),
        }
    }
}
