//! Property tests of the tree planners on random generated tree problems (any robot count from 1
//! to |N| − 2, following allowed or not):
//!
//! 1. PSW and GP (a small evolution, and random programs run as planners) never return a plan the
//!    validator rejects (`visit` semantics), and a plan they return reaches every goal.
//! 2. PSW solves every problem with fewer robots than leaves (its completeness condition).
//! 3. A run of any program records only legal positions: one robot per node, moves along edges,
//!    no swaps, even when the instance is not solved.
//!
//! A failing case prints its instance as the JSON `mrpp trees solve --instance` reads.

use mrpp_core::mapf::plan::Plan;
use mrpp_core::{
    Ctx, Deadline, Instance, MapfProblem, Planner, Problem as _, Rules, VertexId, solve,
};
use mrpp_trees::generator::{ProblemSpec, RobotCount, generate_problem};
use mrpp_trees::gp::{Problem, Program, SimOptions, plan_program, run_program};
use mrpp_trees::{PLANNERS, Psw, TreeInstance, tree_problem};
use proptest::prelude::*;
use rand::SeedableRng;

/// A random problem: depth budget 2..=5, generator seed, robot share of |N| − 2.
fn problem() -> impl Strategy<Value = TreeInstance> {
    (2u32..=5, any::<u64>(), 0.0f64..=1.0).prop_map(|(depth, seed, share)| {
        let probe = generate_problem(&ProblemSpec::paper(depth, RobotCount::Exactly(1)), seed)
            .expect("a tree with 2 leaves exists");
        let max = probe.num_nodes().saturating_sub(2).max(1);
        let robots = 1 + (share * (max - 1) as f64).round() as usize;
        generate_problem(
            &ProblemSpec::paper(depth, RobotCount::Exactly(robots)),
            seed,
        )
        .expect("same tree, more robots")
    })
}

fn opts() -> Ctx {
    Ctx::new(1, Deadline::after(std::time::Duration::from_secs(10)))
}

/// Small budgets for the registered planners that take them (keys a planner does not declare
/// are skipped), so that 256 cases stay quick.
const SMALL: &[(&str, &str)] = &[("population", "20"), ("generations", "3"), ("runs", "1")];

/// Every registered tree planner ([`PLANNERS`]) with [`SMALL`] budgets: a planner is tested by
/// being registered.
fn registered() -> Vec<(&'static str, Box<dyn Planner<MapfProblem>>)> {
    PLANNERS
        .iter()
        .map(|e| {
            let params: Vec<(String, String)> = SMALL
                .iter()
                .filter(|(k, _)| e.params.iter().any(|p| p.name == *k))
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect();
            (
                e.name,
                e.instantiate(&params).expect("small budgets are valid"),
            )
        })
        .collect()
}

proptest! {
    // A fixed seed: the same cases on every run, so CI is deterministic.
    #![proptest_config(ProptestConfig {
        cases: 256,
        rng_seed: proptest::test_runner::RngSeed::Fixed(20_261_122),
        ..ProptestConfig::default()
    })]

    #[test]
    fn psw_and_gp_only_return_valid_plans(t in problem(), following in any::<bool>()) {
        let problem = tree_problem(&t, following);
        for (name, planner) in registered() {
            // Called directly, so an invalid plan would not be hidden by `solve`.
            if let Ok(plan) = planner.plan(&problem, &opts()) {
                let v = problem.validate(&plan);
                prop_assert!(v.is_ok(), "{name}: {}\n{}", v.unwrap_err(), t.to_json());
            }
            // `solve` never hands out an invalid plan either.
            if let Ok(solved) = solve(planner.as_ref(), &problem, &opts()) {
                prop_assert!(problem.validate(&solved.plan).is_ok());
            }
        }
        if t.num_robots() < t.num_leaves() {
            let psw = Psw { allow_following: following, ..Psw::default() };
            let run = psw.run(&t.graph, &t.instance, Deadline::none());
            prop_assert!(run.solved(), "PSW left a problem with |R| < #leaves unsolved\n{}", t.to_json());
        }
    }

    #[test]
    fn any_program_moves_robots_legally(t in problem(), seed in any::<u64>(), depth in 1usize..=4) {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let program = Program::grow(&mut rng, depth);
        let p = Problem::from_tree_instance(&t);
        let out = run_program(&program, &p, &SimOptions::default(), 300, true, Deadline::none());
        // Judge the recorded moves as a plan whose goals are the final positions.
        let last: Vec<VertexId> = out.paths.iter().map(|q| *q.last().unwrap()).collect();
        let inst = Instance::new(t.instance.starts.clone(), last).unwrap();
        let v = MapfProblem::on(&t.graph, &inst, Rules::visit(true)).validate(&Plan::new(out.paths.clone()));
        prop_assert!(v.is_ok(), "{program}: {}\n{}", v.unwrap_err(), t.to_json());
        // As a planner (cap M, up to 10⁸ steps here): bounded in time, judged when it solves.
        let deadline = Deadline::after(std::time::Duration::from_secs(2));
        if let Ok((plan, _)) = plan_program(&program, &p, &SimOptions::default(), deadline) {
            prop_assert!(tree_problem(&t, true).validate(&plan).is_ok());
        }
    }
}
