//! Differential fuzzing of every grid planner (issue 27, item 7): the bytes make a tiny grid map
//! (2..=5 x 2..=4 cells, walls from the bits) and 1..=3 agents with distinct starts and goals;
//! every registered planner runs through `mrpp_core::solve` (so through the validator) with a 1 ms
//! limit. It must not panic or return an invalid plan, and a claim that the instance has no plan
//! must agree with a brute-force search over joint configurations (`brute.rs`).
#![no_main]
use libfuzzer_sys::fuzz_target;
use mrpp_core::Instance;
use mrpp_grid::{GridMap, PLANNERS};

#[path = "brute.rs"]
mod brute;

fuzz_target!(|bytes: &[u8]| {
    let [shape, walls_lo, walls_hi, agents @ ..] = bytes else {
        return;
    };
    let (w, h) = (2 + usize::from(shape % 4), 2 + usize::from(shape / 4 % 3));
    let walls = u32::from(*walls_lo) | u32::from(*walls_hi) << 8;
    let rows: Vec<Vec<bool>> = (0..h)
        .map(|y| {
            (0..w)
                .map(|x| walls >> ((y * w + x) % 16) & 1 == 0 || (x + y) % 5 == 0)
                .collect()
        })
        .collect();
    let map = GridMap::from_free_rows(&rows);
    let n = map.graph().num_vertices();
    if n < 2 {
        return;
    }
    let count = agents.len() / 2;
    if count == 0 {
        return;
    }
    let count = count.min(3);
    let pick = |b: u8| (usize::from(b) % n) as u32;
    let starts = (0..count).map(|i| pick(agents[2 * i])).collect();
    let goals = (0..count).map(|i| pick(agents[2 * i + 1])).collect();
    let Ok(inst) = Instance::new(starts, goals) else {
        return;
    };
    let problem = mrpp_grid::problem_on(&map, inst);
    brute::check_planners(PLANNERS, &problem, u64::from(*shape));
});
