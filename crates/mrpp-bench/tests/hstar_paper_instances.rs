//! H* on every bundled instance of the paper's Table I (and the other Scenario-2 map): every plan
//! it calls solved passes the validator.

use std::path::PathBuf;

use mrpp_bench::papers::hstar_instances::{Scenario2Map, table1_instances};
use mrpp_core::{Ctx, Planner, Problem, Unsolved, solve};
use mrpp_grid::hstar::HStar;

fn data() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/hstar-paper")
}

#[test]
fn hstar_solves_every_table1_instance() {
    for sc2 in [Scenario2Map::OpenRooms, Scenario2Map::ObstacleRooms] {
        for pi in table1_instances(&data(), sc2) {
            let (_, problem) = mrpp_grid::load_problem(&pi.map, &pi.robots_file, None).unwrap();
            assert_eq!(problem.num_agents(), pi.robots);
            let m = solve(&HStar::default(), &problem, &Ctx::default())
                .unwrap_or_else(|e| panic!("SC{} {}: {e}", pi.scenario, pi.label))
                .metrics;
            eprintln!(
                "SC{} {:>6} {:?}: max {} sum {}",
                pi.scenario, pi.label, sc2, m.makespan, m.sum_of_costs
            );
        }
    }
}

#[test]
fn paper_variant_never_returns_an_invalid_plan() {
    let mut solved = 0;
    for pi in table1_instances(&data(), Scenario2Map::OpenRooms) {
        let (_, problem) = mrpp_grid::load_problem(&pi.map, &pi.robots_file, None).unwrap();
        // Called directly, not through `solve`, so an invalid plan would not be hidden.
        match HStar::paper().plan(&problem, &Ctx::default()) {
            Ok(plan) => {
                problem
                    .validate(&plan)
                    .unwrap_or_else(|v| panic!("SC{} {}: {v}", pi.scenario, pi.label));
                solved += 1;
            }
            Err(Unsolved::GaveUp(why)) => {
                eprintln!("paper SC{} {}: not solved: {why}", pi.scenario, pi.label)
            }
            Err(Unsolved::TimeLimit | Unsolved::MemoryLimit | Unsolved::Interrupted) => {
                panic!("no limit was set")
            }
            Err(Unsolved::Invalid(why)) => panic!("not through solve, so never Invalid: {why}"),
        }
    }
    // The paper's steps alone do finish some instances (e.g. Scenario 1 with 6 robots).
    assert!(solved > 0);
}
