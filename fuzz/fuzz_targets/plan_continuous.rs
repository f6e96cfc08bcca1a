//! Differential fuzzing of every continuous planner (issue 27, item 7): the bytes make a small
//! world (100 x 100 workspace, 1..=4 robots with starts, goals, radii and speeds from the bytes,
//! up to two box obstacles, a short step limit); worlds the reader's checks refuse are skipped.
//! HBMO, DE, PSO and ORCA run through `mrpp_core::solve` (the swept-disc validator) with a 2 ms
//! limit: no panic, no invalid plan.
#![no_main]
use std::time::Duration;

use libfuzzer_sys::fuzz_target;
use mrpp_continuous::PLANNERS;
use mrpp_continuous::problem::NavProblem;
use mrpp_continuous::world::{Robot, World};
use mrpp_core::{Ctx, Deadline, Unsolved, solve};

fuzz_target!(|bytes: &[u8]| {
    let [head, rest @ ..] = bytes else {
        return;
    };
    let at = |b: u8| f64::from(b) / 255.0 * 100.0;
    let robots: Vec<Robot> = rest
        .chunks_exact(6)
        .take(1 + usize::from(head % 4))
        .map(|c| Robot {
            start: [at(c[0]), at(c[1])],
            goal: [at(c[2]), at(c[3])],
            radius: 0.5 + f64::from(c[4] % 16) / 4.0,
            speed: 0.5 + f64::from(c[5] % 32) / 2.0,
        })
        .collect();
    if robots.is_empty() {
        return;
    }
    let boxes = rest
        .chunks_exact(6)
        .skip(robots.len())
        .take(usize::from(head / 4 % 3));
    let obstacles = boxes
        .map(|c| {
            let (x, y) = (at(c[0]), at(c[1]));
            let (w, h) = (1.0 + f64::from(c[2] % 30), 1.0 + f64::from(c[3] % 30));
            vec![[x, y], [x + w, y], [x + w, y + h], [x, y + h]]
        })
        .collect();
    let world = World {
        workspace: [0.0, 0.0, 100.0, 100.0],
        obstacles,
        robots,
        epsilon: 1.0,
        step_limit: 40 + usize::from(head / 16),
        source: None,
    };
    if world.check().is_err() {
        return;
    }
    let problem = NavProblem::new(world);
    for entry in PLANNERS {
        let planner = entry.instantiate(&[]).expect("defaults build");
        let ctx = Ctx::new(u64::from(*head), Deadline::after(Duration::from_millis(2)));
        if let Err(Unsolved::Invalid(why)) = solve(planner.as_ref(), &problem, &ctx) {
            panic!("{}: {why}", entry.name);
        }
    }
});
