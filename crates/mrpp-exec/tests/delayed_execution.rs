//! Issue 29's property: ADG execution of a valid plan has no collision and no deadlock under every
//! delay model, over many delay seeds, on bundled MovingAI instances; the naive executor collides
//! on some of the same runs (so the test can fail). Every execution's record is replayed by
//! `check`, which must find the collisions the execution reported.

mod common;

use mrpp_exec::execute::Ending;
use mrpp_exec::{DelayConfig, ExecConfig, ExecutorKind, check::check, execute};

/// Footprint side: at most 0.5, so that rings and robots following each other round a corner in
/// lockstep never overlap (module doc of `mrpp_exec::execute`); the naive executor still
/// collides when a delay breaks the lockstep.
const SIZE: f64 = 0.5;

#[test]
fn adg_never_collides_or_deadlocks_and_naive_does_collide() {
    let cases = [
        ("random-32-32-20.map", "random-32-32-20-random-1.scen", 60),
        ("empty-8-8.map", "empty-8-8-random-1.scen", 20),
    ];
    let models = [
        "bernoulli:p=0.02,min=1,max=4",
        "poisson:p=0.01,min=2,max=8,duration=gaussian,mean=0.5,std=0.22",
        "bernoulli:p=0.2,min=1,max=2",
    ];
    let (mut naive_runs, mut naive_colliding) = (0, 0);
    for (map, scen, agents) in cases {
        let (grid, _, plan) = common::planned(map, scen, agents, "lacam");
        let rings = mrpp_exec::Adg::new(&plan).rotation_cycles();
        eprintln!("{map}: {} rings executed jointly", rings.len());
        for spec in models {
            for counter in [1, 3] {
                for seed in 0..1000u64 {
                    for executor in [ExecutorKind::Adg, ExecutorKind::Naive] {
                        if executor == ExecutorKind::Naive && seed >= 100 {
                            continue;
                        }
                        let cfg = ExecConfig {
                            executor,
                            ticks_per_move: counter,
                            delays: DelayConfig::parse(spec).unwrap(),
                            seed,
                            agent_size: SIZE,
                            max_ticks: 100_000,
                        };
                        let run = execute(&grid, &plan, &cfg);
                        let what =
                            format!("{map} {spec} x{counter} seed {seed} {}", executor.name());
                        let replayed = check(&grid, &plan, &run, counter, SIZE)
                            .unwrap_or_else(|e| panic!("{what}: {e}"));
                        assert_eq!(replayed.len(), run.collisions.len(), "{what}");
                        assert_eq!(run.ending, Ending::Finished, "{what}");
                        if executor == ExecutorKind::Adg {
                            assert!(run.collisions.is_empty(), "{what}: {:?}", run.collisions[0]);
                        } else {
                            naive_runs += 1;
                            naive_colliding += usize::from(!run.collisions.is_empty());
                        }
                    }
                }
            }
        }
    }
    eprintln!("naive executor: {naive_colliding} of {naive_runs} runs collided");
    assert!(
        naive_colliding > 0,
        "the naive executor never collided: the test could not fail"
    );
}

#[test]
fn without_delays_both_executors_keep_the_plan_and_its_costs() {
    let (grid, _, plan) = common::planned(
        "random-32-32-20.map",
        "random-32-32-20-random-1.scen",
        40,
        "lacam",
    );
    for counter in [1, 2] {
        for executor in [ExecutorKind::Naive, ExecutorKind::Adg] {
            let cfg = ExecConfig {
                executor,
                ticks_per_move: counter,
                delays: DelayConfig::none(),
                seed: 0,
                agent_size: SIZE,
                max_ticks: 100_000,
            };
            let run = execute(&grid, &plan, &cfg);
            assert!(run.collisions.is_empty(), "{counter} {}", executor.name());
            assert_eq!(run.metrics.ticks_lost_to_delays, 0);
            if executor == ExecutorKind::Naive {
                // The plan's own timing: executed = planned.
                assert_eq!(run.metrics.makespan, run.metrics.planned_makespan);
                assert_eq!(run.metrics.sum_of_costs, run.metrics.planned_sum_of_costs);
                assert_eq!(run.metrics.waits_added, 0);
            }
            check(&grid, &plan, &run, counter, SIZE).unwrap();
        }
    }
}

#[test]
fn check_refuses_a_tampered_record() {
    let (grid, _, plan) = common::planned("empty-8-8.map", "empty-8-8-random-1.scen", 10, "lacam");
    let cfg = ExecConfig {
        executor: ExecutorKind::Adg,
        ticks_per_move: 3,
        delays: DelayConfig::parse("bernoulli:p=0.1,min=1,max=3").unwrap(),
        seed: 4,
        agent_size: SIZE,
        max_ticks: 100_000,
    };
    let run = execute(&grid, &plan, &cfg);
    check(&grid, &plan, &run, 3, SIZE).unwrap();
    let i = (0..run.moves.len())
        .find(|&i| !run.moves[i].is_empty())
        .unwrap();
    // A move made faster than a move takes.
    let mut fast = run.clone();
    fast.moves[i][0][1] -= 1;
    let e = check(&grid, &plan, &fast, 3, SIZE).unwrap_err();
    assert!(
        e.contains("ticks of progress") || e.contains("overlap"),
        "{e}"
    );
    // A delay removed: the robot would have moved while held... or the move is now too long.
    let mut dropped = run.clone();
    if let Some(j) =
        (0..run.delays.len()).find(|&j| !run.delays[j].is_empty() && !run.moves[j].is_empty())
    {
        dropped.delays[j].clear();
        assert!(
            check(&grid, &plan, &dropped, 3, SIZE).is_err()
                || run.moves[j]
                    .iter()
                    .all(|m| { run.delays[j].iter().all(|d| d[1] <= m[0] || d[0] >= m[1]) })
        );
    }
    // A collision left out of the record.
    let mut quiet = run.clone();
    quiet.collisions.push(mrpp_exec::execute::Collision {
        tick: 0,
        robots: [0, 1],
        at: [[0.0, 0.0]; 2],
    });
    assert!(
        check(&grid, &plan, &quiet, 3, SIZE)
            .unwrap_err()
            .contains("collisions")
    );
}

/// The League's default executor (`tpg`) keeps the plan's order of passage with per-cell queues:
/// on a plan without rings it executes exactly as the ADG, delay for delay; at a ring of the plan
/// (robots each entering the cell the next leaves) it waits forever, where the ADG executes the
/// ring jointly.
#[test]
fn tpg_executes_ring_free_plans_as_the_adg_and_stops_at_a_ring() {
    let (mut ring_free, mut ringed) = (0, 0);
    for (name, agents) in [("eecbs", 30), ("lacam", 60)] {
        let (grid, _, plan) = common::planned(
            "random-32-32-20.map",
            "random-32-32-20-random-1.scen",
            agents,
            name,
        );
        let rings = mrpp_exec::Adg::new(&plan).rotation_cycles();
        for seed in 0..40u64 {
            let cfg = |executor| ExecConfig {
                executor,
                ticks_per_move: 1 + (seed % 3) as u32,
                delays: DelayConfig::parse("bernoulli:p=0.05,min=1,max=4").unwrap(),
                seed,
                agent_size: SIZE,
                max_ticks: 20_000,
            };
            let adg = execute(&grid, &plan, &cfg(ExecutorKind::Adg));
            let tpg = execute(&grid, &plan, &cfg(ExecutorKind::Tpg));
            assert_eq!(adg.ending, Ending::Finished);
            if rings.is_empty() {
                assert_eq!(tpg.ending, Ending::Finished, "{name} seed {seed}");
                assert_eq!(tpg.moves, adg.moves, "{name} seed {seed}");
                assert_eq!(tpg.delays, adg.delays);
                check(
                    &grid,
                    &plan,
                    &tpg,
                    cfg(ExecutorKind::Tpg).ticks_per_move,
                    SIZE,
                )
                .unwrap();
            } else {
                assert!(
                    matches!(tpg.ending, Ending::Deadlock { .. }),
                    "{name} seed {seed}: {:?}",
                    tpg.ending
                );
                assert!(tpg.collisions.is_empty());
            }
        }
        if rings.is_empty() {
            ring_free += 1;
        } else {
            ringed += 1;
        }
    }
    // A ring by hand: four robots turning round a 2 x 2 block at step 0.
    let (empty, _) = common::bundled("empty-8-8.map", "empty-8-8-random-1.scen", 1);
    let at = |x, y| empty.vertex_at(x, y).unwrap();
    let square = [at(0, 0), at(1, 0), at(1, 1), at(0, 1)];
    let plan = mrpp_core::mapf::plan::Plan {
        paths: (0..4)
            .map(|i| vec![square[i], square[(i + 1) % 4]])
            .collect(),
    };
    let cfg = |executor| ExecConfig {
        executor,
        ticks_per_move: 2,
        delays: DelayConfig::none(),
        seed: 0,
        agent_size: SIZE,
        max_ticks: 1_000,
    };
    assert_eq!(
        execute(&empty, &plan, &cfg(ExecutorKind::Adg)).ending,
        Ending::Finished
    );
    assert_eq!(
        execute(&empty, &plan, &cfg(ExecutorKind::Tpg)).ending,
        Ending::Deadlock { tick: 0 }
    );
    eprintln!(
        "tpg: {ring_free} ring-free plan(s) executed as the ADG, {ringed} with rings stopped"
    );
    assert!(
        ring_free > 0,
        "no ring-free plan: the equality was never checked"
    );
    assert!(
        ringed > 0,
        "no plan with a ring: the deadlock was never checked"
    );
}
