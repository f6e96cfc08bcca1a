//! Every continuous planner on seeded worlds: only valid plans (the validator inside `solve`), and
//! every failure to arrive is a deadlock or the step limit, never an invalid plan.

use mrpp_continuous::generator::random_world;
use mrpp_continuous::{NavProblem, PLANNERS};
use mrpp_core::{Ctx, Deadline, Unsolved, solve};

#[test]
fn planners_emit_only_valid_plans_on_random_worlds() {
    for seed in 0..4u64 {
        let world = random_world(4, 3, seed).unwrap();
        let p = NavProblem::new(world);
        for entry in PLANNERS {
            // ORCA has no heading mode: it runs once, with its defaults.
            let modes: &[&str] = if entry.params.iter().any(|p| p.name == "mode") {
                &["joint", "per-robot"]
            } else {
                &["default"]
            };
            for &mode in modes {
                let given: Vec<(String, String)> = if mode == "default" {
                    vec![]
                } else {
                    vec![("mode".into(), mode.into())]
                };
                let planner = entry.instantiate(&given).unwrap();
                let ctx = Ctx::new(seed, Deadline::none());
                match solve(planner.as_ref(), &p, &ctx) {
                    Ok(s) => assert!(s.metrics.min_clearance >= -1e-9),
                    Err(Unsolved::Invalid(why)) => {
                        panic!("{} {mode} seed {seed}: {why}", entry.name)
                    }
                    Err(Unsolved::GaveUp(why)) => {
                        assert!(
                            why.contains("deadlock") || why.contains("step limit"),
                            "{why}"
                        )
                    }
                    Err(Unsolved::TimeLimit | Unsolved::MemoryLimit | Unsolved::Interrupted) => {
                        panic!("no limit was set")
                    }
                }
            }
        }
    }
}

#[test]
fn same_seed_same_trajectories() {
    let p = NavProblem::new(random_world(5, 4, 7).unwrap());
    for entry in PLANNERS {
        let planner = entry.instantiate(&[]).unwrap();
        let a = solve(planner.as_ref(), &p, &Ctx::new(3, Deadline::none()));
        let b = solve(planner.as_ref(), &p, &Ctx::new(3, Deadline::none()));
        match (a, b) {
            (Ok(a), Ok(b)) => assert_eq!(a.plan, b.plan, "{}", entry.name),
            (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string()),
            _ => panic!("{}: different outcomes for one seed", entry.name),
        }
    }
}

/// The long check (`cargo test --release -p mrpp-continuous -- --ignored`): 1000 generated
/// episodes per planner (2–10 robots, 2–10 obstacles, seed = episode), zero invalid plans, every
/// failure to arrive a deadlock or the step limit; prints the tally.
#[test]
#[ignore]
fn a_thousand_episodes_per_planner_without_a_collision() {
    for entry in PLANNERS {
        let planner = entry.instantiate(&[]).unwrap();
        let (mut arrived, mut deadlock, mut limit) = (0, 0, 0);
        for episode in 0..1000u64 {
            let robots = 2 + (episode % 9) as usize;
            let obstacles = 2 + (episode / 9 % 9) as usize;
            let Some(world) = random_world(robots, obstacles, episode) else {
                continue;
            };
            let p = NavProblem::new(world);
            match solve(planner.as_ref(), &p, &Ctx::new(episode, Deadline::none())) {
                Ok(_) => arrived += 1,
                Err(Unsolved::GaveUp(why)) if why.starts_with("deadlock") => deadlock += 1,
                Err(Unsolved::GaveUp(why)) if why.starts_with("step limit") => limit += 1,
                Err(other) => panic!("{} episode {episode}: {other}", entry.name),
            }
        }
        println!(
            "{}: {arrived} arrived, {deadlock} deadlocks, {limit} step limits, 0 invalid",
            entry.name
        );
        assert_eq!(
            arrived + deadlock + limit,
            1000,
            "{}: every world generated",
            entry.name
        );
    }
}

/// baselines §6's per-step tests, for every optimiser: one robot from (0, 0) to (10, 0) with
/// v = 1 heads at θ ≈ 0; a head-on pair 2 apart keeps its next positions at least 2r apart.
#[test]
fn per_step_tests_of_every_optimiser() {
    use mrpp_continuous::navigate::{Guide, Navigation};
    use mrpp_continuous::objective::next_position;
    use mrpp_continuous::{Robot, World};
    use mrpp_evo::space::Minimizer;
    use rand::SeedableRng;
    let world = |robots: Vec<Robot>| {
        NavProblem::new(World {
            workspace: [-50.0, -50.0, 50.0, 50.0],
            obstacles: vec![],
            robots,
            epsilon: 0.1,
            step_limit: 100,
            source: None,
        })
    };
    let robot = |start: [f64; 2], goal: [f64; 2]| Robot {
        start,
        goal,
        radius: 0.5,
        speed: 1.0,
    };
    let nav = Navigation {
        guide: Guide::Goal,
        ..Navigation::default()
    };
    let optimisers: [Box<dyn Minimizer>; 3] = [
        Box::new(mrpp_evo::hbmo::Hbmo::default()),
        Box::new(mrpp_evo::de::De::default()),
        Box::new(mrpp_evo::pso::Pso::default()),
    ];
    for opt in &optimisers {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        let one = world(vec![robot([0.0, 0.0], [10.0, 0.0])]);
        let theta = nav.headings(
            &one,
            &[[0.0, 0.0]],
            &[[10.0, 0.0]],
            &[0],
            opt.as_ref(),
            &mut rng,
        );
        assert!(theta[0].abs() < 0.01, "{}: θ = {}", opt.name(), theta[0]);
        let pair = world(vec![
            robot([0.0, 0.0], [10.0, 0.0]),
            robot([2.0, 0.0], [-8.0, 0.0]),
        ]);
        let pos = [[0.0, 0.0], [2.0, 0.0]];
        let t = nav.headings(
            &pair,
            &pos,
            &[[10.0, 0.0], [-8.0, 0.0]],
            &[0, 1],
            opt.as_ref(),
            &mut rng,
        );
        let (a, b) = (
            next_position(pos[0], 1.0, t[0]),
            next_position(pos[1], 1.0, t[1]),
        );
        let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
        assert!(d >= 0.99, "{}: next positions {d} apart", opt.name());
    }
}
