//! Differential fuzzing of every tree planner (issue 27, item 7): the bytes make a tree of
//! 2..=10 nodes (node i > 0 hangs from an earlier node) and 1..=3 robots with distinct starts and
//! goals; PSW and GP run through `mrpp_core::solve` (the validator) with a 1 ms limit, following
//! allowed or not. No panic, no invalid plan, and a claim of "no plan" must agree with a
//! brute-force search over joint configurations (`brute.rs`, `visit` semantics).
#![no_main]
use libfuzzer_sys::fuzz_target;
use mrpp_core::Instance;
use mrpp_trees::instance::TreeInstance;
use mrpp_trees::{PLANNERS, tree_problem};

#[path = "brute.rs"]
mod brute;

fuzz_target!(|bytes: &[u8]| {
    let [size, flags, rest @ ..] = bytes else {
        return;
    };
    let nodes = 2 + usize::from(size % 9);
    if rest.len() < nodes - 1 + 2 {
        return;
    }
    let (parents, robots) = rest.split_at(nodes - 1);
    let edges: Vec<(u32, u32)> = parents
        .iter()
        .enumerate()
        .map(|(i, &p)| ((usize::from(p) % (i + 1)) as u32, (i + 1) as u32))
        .collect();
    let count = (robots.len() / 2).min(3);
    let pick = |b: u8| (usize::from(b) % nodes) as u32;
    let starts = (0..count).map(|i| pick(robots[2 * i])).collect();
    let goals = (0..count).map(|i| pick(robots[2 * i + 1])).collect();
    let Ok(inst) = Instance::new(starts, goals) else {
        return;
    };
    let Ok(tree) = TreeInstance::new(nodes, edges, inst) else {
        return;
    };
    let following = flags & 1 == 0;
    let problem = tree_problem(&tree, following);
    brute::check_planners(PLANNERS, &problem, u64::from(*flags));
});
