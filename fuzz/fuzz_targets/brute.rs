//! Shared by the planner targets: the exact answer to "does this tiny instance have a plan?", by
//! breadth-first search over joint configurations (every agent waits or moves to a neighbour; no
//! two agents on one vertex, no two swapping, following only where the rules allow it). With
//! `stay` semantics a plan ends with every agent on its goal; with `visit` semantics every agent
//! has stood on its goal at some step. Meant for a few agents on a few vertices only.
use std::collections::{HashSet, VecDeque};

use std::time::Duration;

use mrpp_core::mapf::plan::{GoalSemantics, Rules};
use mrpp_core::{
    Ctx, Deadline, Graph, Instance, MapfProblem, PlannerEntry, Unsolved, VertexId, solve,
};

/// Whether any plan exists (`None` when the joint space exceeds `cap` configurations).
pub fn solvable(g: &Graph, inst: &Instance, rules: Rules, cap: usize) -> Option<bool> {
    let n = inst.num_agents();
    let visit = rules.semantics == GoalSemantics::Visit;
    let done_mask = (1u32 << n) - 1;
    let mask_of = |c: &[VertexId]| -> u32 {
        (0..n)
            .filter(|&i| c[i] == inst.goals[i])
            .fold(0, |m, i| m | 1 << i)
    };
    let start = (inst.starts.clone(), mask_of(&inst.starts));
    let finished = |(c, m): &(Vec<VertexId>, u32)| {
        if visit {
            *m == done_mask
        } else {
            c == &inst.goals
        }
    };
    if finished(&start) {
        return Some(true);
    }
    let mut seen = HashSet::new();
    let mut queue = VecDeque::new();
    seen.insert(start.clone());
    queue.push_back(start);
    while let Some((c, m)) = queue.pop_front() {
        // Every joint move: each agent's options are waiting or one of its neighbours.
        let options: Vec<Vec<VertexId>> = (0..n)
            .map(|i| {
                let mut o = vec![c[i]];
                o.extend_from_slice(g.neighbors(c[i]));
                o
            })
            .collect();
        let mut pick = vec![0usize; n];
        loop {
            let next: Vec<VertexId> = (0..n).map(|i| options[i][pick[i]]).collect();
            if legal(&c, &next, rules.allow_following) {
                let state = (next.clone(), if visit { m | mask_of(&next) } else { 0 });
                if finished(&state) {
                    return Some(true);
                }
                if seen.len() >= cap {
                    return None;
                }
                if seen.insert(state.clone()) {
                    queue.push_back(state);
                }
            }
            // The next combination of options.
            let mut i = 0;
            while i < n {
                pick[i] += 1;
                if pick[i] < options[i].len() {
                    break;
                }
                pick[i] = 0;
                i += 1;
            }
            if i == n {
                break;
            }
        }
    }
    Some(false)
}

fn legal(from: &[VertexId], to: &[VertexId], following: bool) -> bool {
    let n = from.len();
    for i in 0..n {
        for j in i + 1..n {
            if to[i] == to[j] || (to[i] == from[j] && to[j] == from[i]) {
                return false;
            }
            if !following
                && ((to[i] == from[j] && to[i] != from[i])
                    || (to[j] == from[i] && to[j] != from[j]))
            {
                return false;
            }
        }
    }
    true
}

/// Whether a planner's "not solved" message claims the instance has no plan.
pub fn claims_unsolvable(why: &str) -> bool {
    why.contains("no solution") || why.contains("cannot reach its goal")
}

/// Runs every planner of `planners` on `problem` through `solve` (the validator) with a 1 ms
/// limit and checks what it says against `truth` ([`solvable`]): no invalid plan, no plan for an
/// unsolvable instance, no "no solution" claim for a solvable one.
pub fn check_planners(planners: &[PlannerEntry<MapfProblem>], problem: &MapfProblem, seed: u64) {
    let inst = problem.instance();
    let truth = solvable(problem.graph(), inst, problem.rules(), 200_000);
    for entry in planners {
        let planner = entry.instantiate(&[]).expect("defaults build");
        let ctx = Ctx::new(seed, Deadline::after(Duration::from_millis(1)));
        match solve(planner.as_ref(), problem, &ctx) {
            Ok(_) => assert_ne!(
                truth,
                Some(false),
                "{} solved an unsolvable instance",
                entry.name
            ),
            Err(Unsolved::Invalid(why)) => panic!("{}: {why}", entry.name),
            Err(Unsolved::GaveUp(why)) if claims_unsolvable(&why) => {
                assert_ne!(
                    truth,
                    Some(true),
                    "{} says `{why}` but a plan exists",
                    entry.name
                )
            }
            Err(_) => {}
        }
    }
}
