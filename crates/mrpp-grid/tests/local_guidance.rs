//! LaCAM with local guidance (`-p local_guidance`, Arita & Okumura, AAAI 2026;
//! `mrpp_mapf::guidance`) on a dense MovingAI instance: random-32-32-20 (its `random-1`
//! scenario, bundled in `data/movingai`) with 300 agents, 37% of the free cells.
//!
//! For three seeds, the plans with and without guidance pass the validator (`mrpp_core::solve`)
//! and the guided plan has the lower sum of costs (measured in release builds, 400 agents, three
//! seeds: 27,378 without guidance, 20,638 with a 10-step window, docs/performance.md). The search
//! is deterministic for a seed, so the comparison is not a timing.

use std::path::Path;
use std::time::Duration;

use mrpp_core::registry::find;
use mrpp_core::{Ctx, Deadline, solve};
use mrpp_grid::{PLANNERS, load_problem};

fn root(rel: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

#[test]
fn local_guidance_lowers_the_first_plans_sum_of_costs_on_a_dense_map() {
    let (_, problem) = load_problem(
        &root("data/movingai/random-32-32-20.map"),
        &root("data/movingai/random-32-32-20-random-1.scen"),
        Some(300),
    )
    .expect("bundled files load");
    let entry = find(PLANNERS, "lacam").expect("lacam is registered");
    let plain = entry.instantiate(&[]).expect("defaults");
    let guided = entry
        .instantiate(&[("local_guidance".to_string(), "10".to_string())])
        .expect("a window of 10");
    for seed in 0..3 {
        let ctx = || Ctx::new(seed, Deadline::after(Duration::from_secs(60)));
        let a = solve(plain.as_ref(), &problem, &ctx()).expect("solved and valid");
        let b = solve(guided.as_ref(), &problem, &ctx()).expect("solved and valid");
        assert!(
            b.metrics.sum_of_costs < a.metrics.sum_of_costs,
            "seed {seed}: guided {} against {} without guidance",
            b.metrics.sum_of_costs,
            a.metrics.sum_of_costs
        );
    }
}
