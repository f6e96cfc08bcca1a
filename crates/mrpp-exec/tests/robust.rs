//! k-robust re-timing (`mrpp_exec::robust`) of LaCAM's and PIBT's plans on bundled MovingAI
//! instances: every re-timed plan is valid (the grid validator), k-robust outside rings (gaps
//! recounted from the paths), never shorter, and executed naively under delays it collides less
//! often than the plan it came from (so robustness is measured, not just offered).

mod common;

use mrpp_core::Problem;
use mrpp_exec::robust::{k_robust, min_gap};
use mrpp_exec::{DelayConfig, ExecConfig, ExecutorKind, execute};

#[test]
fn re_timed_plans_are_valid_k_robust_and_collide_less_when_late() {
    for (map, scen, agents, planner) in [
        (
            "random-32-32-20.map",
            "random-32-32-20-random-1.scen",
            60,
            "lacam",
        ),
        (
            "room-32-32-4.map",
            "room-32-32-4-random-1.scen",
            40,
            "lacam",
        ),
        (
            "random-32-32-20.map",
            "random-32-32-20-random-2.scen",
            50,
            "pibt",
        ),
    ] {
        let (grid, problem, plan) = common::planned(map, scen, agents, planner);
        let mut last = problem.validate(&plan).unwrap();
        let mut collided = Vec::new();
        for k in 0..=3u32 {
            let what = format!("{map} {planner} k={k}");
            let robust = k_robust(&plan, k);
            let m = problem
                .validate(&robust)
                .unwrap_or_else(|v| panic!("{what}: {v}"));
            let (gap, rings) = min_gap(&robust);
            assert!(gap.is_none_or(|g| g >= k), "{what}: gap {gap:?}");
            assert!(
                m.makespan >= last.makespan && m.sum_of_costs >= last.sum_of_costs,
                "{what}"
            );
            last = m;
            // Executed on its own timing, robots up to 2 steps late (3 ticks a move).
            let mut collisions = 0;
            for seed in 0..20 {
                let cfg = ExecConfig {
                    executor: ExecutorKind::Naive,
                    ticks_per_move: 3,
                    delays: DelayConfig::parse("bernoulli:p=0.005,min=1,max=6").unwrap(),
                    seed,
                    agent_size: 0.5,
                    max_ticks: 1_000_000,
                };
                collisions += usize::from(!execute(&grid, &robust, &cfg).collisions.is_empty());
            }
            eprintln!(
                "{what}: makespan {}, sum of costs {}, min gap {gap:?} ({rings} ring entries), naive runs collided {collisions}/20",
                m.makespan, m.sum_of_costs
            );
            collided.push(collisions);
        }
        assert!(
            collided[3] < collided[0],
            "{map} {planner}: 3-robust plans collide as often as the plan ({collided:?})"
        );
    }
}
