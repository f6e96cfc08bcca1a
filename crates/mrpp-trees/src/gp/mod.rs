//! Genetic programming for single-lane trees (A. Trudeau and C. M. Clark, "Multi-Robot Path
//! Planning Via Genetic Programming").
//!
//! The paper evolves one decision tree that every robot runs, in id order, at every time step:
//! internal nodes are the nine conditionals of its Table 1, leaves the four actions of Table 2.
//! [`program`] holds the trees and their file format, [`simulate`] runs a tree on an instance
//! (plans and the fitness of equation (1)), [`evolve`] is Algorithm 1, and [`Gp`] / [`gp`] evolve a
//! program for one instance and return its plan (the setting of the paper's Tables 3 and 5).
//!
//! # Robot state and the meaning of each primitive
//!
//! Each robot keeps: its node; its *current path*, which leads either to its goal (the
//! "objective") or to a branch node it has set its path to (paths are tree paths recomputed from
//! the current node, so they never go stale); the branch nodes it has chosen before; the nodes it
//! has stood on; and whether it has visited its goal ("solved"). A branch node has 3 or more
//! neighbours (§4.1). c(r_i) is the set of robots within ρ hops of r_i (ρ = 2,
//! [`SimOptions::radius`]), listed nearest first (BFS from r_i's node in adjacency order). "The
//! path of r_j" excludes r_j's own node.
//!
//! Conditionals (then-branch when true):
//! - `if-two-robots-on-each-others-path`: the first r_j of c(r_i) such that r_i's node is on r_j's
//!   path and r_j's node is on r_i's path (the paper's text says "A(r_i, t) is on r_i's path", a
//!   slip: the authors' code tests r_j's node). When found, both set their paths to the branch node
//!   nearest to r_i that r_i has not chosen before (when it has chosen them all, its list is
//!   cleared first; with no branch node in the tree the test is still true and nothing is set).
//! - `if-neighbor-is-surrounded`: some robot adjacent to r_i has every adjacent node occupied.
//! - `if-robot-at-branch`: r_i stands on the branch node it set its path to. What happens on
//!   arrival is a choice ([`BranchArrival`], `-p branch_arrival`): by default (`Resume`) the path
//!   goes back to the objective on arrival and this test stays true while the robot stands on
//!   that branch; with `Hold` (the authors' code) the path stays set to the branch until this
//!   test sees the robot there and resets it to the objective.
//! - `if-robot-at-destination`: r_i stands on its goal.
//! - `if-robot-moving-to-branch`: r_i has set its path to a branch node and is not on it yet.
//! - `if-neighbor-on-path-is-free`: the next node of r_i's current path exists and is free.
//! - `if-robot-is-solved`: r_i has visited its goal.
//! - `if-on-path-of-robot-in-network`: r_i's node is on the path of some r_j in c(r_i).
//! - `if-robot-in-network-moving-to-branch`: some r_j in c(r_i) is moving to a branch node (as
//!   `if-robot-moving-to-branch` for r_j).
//!
//! Actions, each with the collision check of §4.1 (a move into a node that another robot holds
//! now leaves the robot where it is; robots move one after the other, so no two robots ever use
//! one edge in a step):
//! - `move-toward-branch`: one step along the path to the branch node r_i set its path to; a robot
//!   with none first chooses the nearest branch node it has not chosen before (§5: "finding the
//!   closest branch node"), as `if-two-robots-on-each-others-path` does.
//! - `move-to-free-neighbor`: one step to a free adjacent node r_i has never stood on; nodes off
//!   its current path first, then adjacency order. When every adjacent node has been visited they
//!   are forgotten first (the authors' reset), so a robot is never stuck with a stale memory.
//! - `move-toward-objective`: one step along the current path (toward the goal, or toward the
//!   branch while one is set; the paper: "the next node on its current path").
//! - `stay`.
//!
//! Following (entering a node that a robot left earlier in the same step) is allowed by default,
//! like the validator's default and PSW's; [`SimOptions::allow_following`] turns it off.
//!
//! The paper's function set and the authors' code differ in one place: the code's syntax uses an
//! action-like `IF-TWO-BOTS-ON-EACH-OTHERS-PATH` leaf. We implement Table 1 as printed.
//!
//! # The run
//!
//! A run ends when every robot has visited its goal (solved, after τ steps), at the step cap
//! (the paper's M = |N|²·|R|² when a program is used as a planner; the remaining τ_B budget during
//! evolution), or as soon as the deterministic state repeats (the run would cycle until the cap;
//! the fitness at the cap is still computed exactly).

pub mod evolve;
pub mod program;
pub mod simulate;

pub use evolve::{
    Evaluation, GpParams, GpProgress, GpResult, GpStop, Init, calculate_fitness, evolve,
};
pub use program::{Action, Conditional, Gene, Program, SyntaxError};
pub use simulate::{
    BranchArrival, FreeNeighbor, Outcome, Problem, SimOptions, Stop, plan_program, run_program,
};

use mrpp_core::mapf::graph::Graph;
use mrpp_core::mapf::instance::Instance;
use mrpp_core::mapf::plan::Plan;
use std::sync::Mutex;

use mrpp_core::contract::{Ctx, Deadline, Planner, Progress, Unsolved};
use mrpp_core::{MapfProblem, Param, Params, PlannerEntry};

/// A program evolved for one instance, with its plan.
#[derive(Debug, Clone)]
pub struct GpSolution {
    /// The plan of ψ* (trimmed of nothing: one position per robot per step, τ + 1 positions).
    pub plan: Plan,
    /// ψ*.
    pub program: Program,
    /// τ_B: time steps ψ* takes to solve the instance.
    pub steps: u64,
    pub result: GpResult,
}

/// Evolves a program for one instance (X = {the instance}, the paper's §7.2 and §7.4 setting)
/// and returns the plan of ψ*. Errors: the deadline passed with no solving program
/// ([`Unsolved::TimeLimit`]), or no program solved the instance ([`Unsolved::GaveUp`]).
pub fn gp(
    graph: &Graph,
    inst: &Instance,
    params: &GpParams,
    seed: u64,
    deadline: Deadline,
    progress: &mut dyn FnMut(&GpProgress),
) -> Result<GpSolution, Unsolved> {
    gp_with_effort(graph, inst, params, seed, deadline, progress).0
}

/// [`gp`], with the evolution's effort `(generations, evaluations, inherited)` (see
/// [`GpResult`]) whether or not a program solved the instance (zeros when the evolution never
/// started).
pub fn gp_with_effort(
    graph: &Graph,
    inst: &Instance,
    params: &GpParams,
    seed: u64,
    deadline: Deadline,
    progress: &mut dyn FnMut(&GpProgress),
) -> (Result<GpSolution, Unsolved>, (usize, u64, u64)) {
    let problem = match Problem::new(graph, inst) {
        Ok(p) => p,
        Err(e) => {
            return (
                Err(Unsolved::GaveUp(format!("GP needs a tree: {e}"))),
                (0, 0, 0),
            );
        }
    };
    let result = match evolve(
        std::slice::from_ref(&problem),
        params,
        seed,
        deadline,
        progress,
    ) {
        Ok(r) => r,
        Err(e) => return (Err(Unsolved::GaveUp(e.to_string())), (0, 0, 0)),
    };
    let effort = (result.generations, result.evaluations, result.inherited);
    (solution_of(result, &problem, params, deadline), effort)
}

/// ψ*'s plan from an evolution's result (or why there is none). The replay that records the plan
/// is under `deadline` too ([`Unsolved::TimeLimit`] when it passes first).
fn solution_of(
    result: GpResult,
    problem: &Problem,
    params: &GpParams,
    deadline: Deadline,
) -> Result<GpSolution, Unsolved> {
    let Some(program) = result.best.clone() else {
        return Err(if result.stop == GpStop::TimeLimit {
            Unsolved::TimeLimit
        } else {
            Unsolved::GaveUp(format!(
                "no program solved the instance in {} generations (best fitness {})",
                result.generations, result.champion_fitness
            ))
        });
    };
    // ψ* solved the instance in τ_B steps during the evolution and runs are deterministic, so
    // one recorded run capped at τ_B gives its plan.
    let tau = result
        .best_steps
        .expect("a solving program has its step count");
    let mut out = run_program(&program, problem, &params.sim, tau, true, deadline);
    if out.stop == Stop::TimeLimit {
        return Err(Unsolved::TimeLimit);
    }
    if !out.solved() {
        return Err(Unsolved::GaveUp(format!(
            "internal error: ψ* did not repeat its {tau}-step solution"
        )));
    }
    Ok(GpSolution {
        plan: Plan::new(std::mem::take(&mut out.paths)),
        program,
        steps: out.steps,
        result,
    })
}

/// Registry name of the GP planner.
pub const NAME: &str = "gp";

/// The GP planner's parameters (`-p key=value`); defaults are [`GpParams::default`].
const PARAMS: &[Param] = &[
    Param {
        name: "population",
        default: "200",
        doc: "|P|: programs per generation (paper 2000)",
    },
    Param {
        name: "generations",
        default: "25",
        doc: "i_g: generations per run (paper 400)",
    },
    Param {
        name: "runs",
        default: "2",
        doc: "i_r: independent runs (paper 5)",
    },
    Param {
        name: "paper_settings",
        default: "false",
        doc: "start from the paper's settings (|P| 2000, 5 runs x 400 generations, cap M); other keys given override them",
    },
    Param {
        name: "evolution_cap",
        default: "20",
        doc: "step cap per example during evolution, in steps per tree node; 0 = the paper's M = |N|^2 |R|^2",
    },
    Param {
        name: "p_reproduction",
        default: "0.1",
        doc: "p_a: share of the next generation made by reproduction",
    },
    Param {
        name: "p_crossover",
        default: "0.8",
        doc: "p_c: share made by crossover",
    },
    Param {
        name: "p_mutation",
        default: "0.1",
        doc: "p_m: share made by mutation (p_a + p_c + p_m = 1)",
    },
    Param {
        name: "min_depth",
        default: "1",
        doc: "smallest program depth",
    },
    Param {
        name: "max_depth",
        default: "50",
        doc: "largest program depth",
    },
    Param {
        name: "init_depth",
        default: "2",
        doc: "largest depth of the initial programs",
    },
    Param {
        name: "branch_arrival",
        default: "resume",
        doc: "a robot's path on reaching the branch node it set it to: resume (back to the objective at once) or hold (until If-Robot-At-Branch sees it there; the authors' code)",
    },
    Param {
        name: "program",
        default: "",
        doc: "a saved program file (S-expression) to run instead of evolving one",
    },
];

/// GP in the planner registry.
pub const ENTRY: PlannerEntry<MapfProblem> = PlannerEntry {
    name: NAME,
    about: "GP: evolves one decision-tree program for the instance, Algorithm 1 (Trudeau & Clark, Multi-Robot Path Planning Via Genetic Programming)",
    params: PARAMS,
    build: |p| {
        let gp = Gp::new(gp_params(p)?);
        Ok(Box::new(match p.raw("program") {
            "" => gp,
            file => gp.running(Program::load(std::path::Path::new(file))?),
        }))
    },
};

/// [`GpParams`] from registry parameters: the defaults, or the paper's settings with
/// `paper_settings=true`, with every key the user gave applied on top; checked with
/// [`GpParams::check`].
pub fn gp_params(p: &Params) -> mrpp_core::Result<GpParams> {
    let paper = p.get::<bool>("paper_settings")?;
    let mut g = if paper {
        GpParams::paper()
    } else {
        GpParams::default()
    };
    let set = |key: &str| !paper || p.is_given(key);
    if set("population") {
        g.population = p.get("population")?;
    }
    if set("generations") {
        g.generations = p.get("generations")?;
    }
    if set("runs") {
        g.runs = p.get("runs")?;
    }
    if set("evolution_cap") {
        let k: u64 = p.get("evolution_cap")?;
        g.cap_factor = (k > 0).then_some(k);
    }
    g.p_reproduction = p.get("p_reproduction")?;
    g.p_crossover = p.get("p_crossover")?;
    g.p_mutation = p.get("p_mutation")?;
    g.min_depth = p.get("min_depth")?;
    g.max_depth = p.get("max_depth")?;
    g.init_depth = p.get("init_depth")?;
    let arrival = p.raw("branch_arrival");
    g.sim.branch_arrival = BranchArrival::parse(arrival).ok_or_else(|| {
        mrpp_core::Error::Param(format!("branch_arrival={arrival}: expected resume or hold"))
    })?;
    g.check()?;
    Ok(g)
}

/// The GP planner: [`gp`] behind the [`Planner`] interface (seed and deadline from the context,
/// following from the problem's rules, progress per generation through the context). The program
/// it evolved last, with its evolution's statistics, can be taken afterwards with
/// [`Gp::evolved`] (to save it, or to report generations and evaluations).
#[derive(Debug, Default)]
pub struct Gp {
    pub params: GpParams,
    /// A saved program to run instead of evolving one.
    saved: Option<Program>,
    evolved: Mutex<Option<GpSolution>>,
    /// `(generations, evaluations, inherited)` of the last evolution, solved or not.
    effort: Mutex<(usize, u64, u64)>,
}

impl Gp {
    pub fn new(params: GpParams) -> Self {
        Gp {
            params,
            saved: None,
            evolved: Mutex::new(None),
            effort: Mutex::new((0, 0, 0)),
        }
    }

    /// `(generations, evaluations, inherited)` of the last evolution (see [`GpResult`]), whether
    /// or not it solved the instance (a failed run's cost belongs in the results too).
    pub fn effort(&self) -> (usize, u64, u64) {
        self.effort.lock().map_or((0, 0, 0), |e| *e)
    }

    /// This planner running `program` (a saved ψ*) instead of evolving one: the plan of its run
    /// under the paper's cap M, or "not solved".
    pub fn running(self, program: Program) -> Self {
        Gp {
            saved: Some(program),
            ..self
        }
    }

    /// The solution of the last successful [`Planner::plan`] call (program, τ_B, statistics).
    pub fn evolved(&self) -> Option<GpSolution> {
        self.evolved.lock().ok()?.clone()
    }
}

impl Planner<MapfProblem> for Gp {
    fn name(&self) -> &str {
        NAME
    }

    fn plan(&self, problem: &MapfProblem, opts: &Ctx) -> Result<Plan, Unsolved> {
        let (graph, inst) = (problem.graph(), problem.instance());
        let mut params = self.params.clone();
        params.sim.allow_following = problem.rules().allow_following;
        if let Some(program) = &self.saved {
            let sim_problem = Problem::new(graph, inst)
                .map_err(|e| Unsolved::GaveUp(format!("GP needs a tree: {e}")))?;
            return plan_program(program, &sim_problem, &params.sim, opts.deadline)
                .map(|(plan, _)| plan);
        }
        let mut report = |g: &GpProgress| {
            opts.report(Progress {
                stage: "generation",
                done: g.done as u64,
                total: g.total as u64,
                note: match g.best_steps {
                    Some(t) => format!("best {t} steps"),
                    None => format!("best fitness {}", g.best_fitness),
                },
            })
        };
        let (solution, effort) =
            gp_with_effort(graph, inst, &params, opts.seed, opts.deadline, &mut report);
        if let Ok(mut slot) = self.effort.lock() {
            *slot = effort;
        }
        if let Ok(mut slot) = self.evolved.lock() {
            // A failed run must not leave an earlier run's program behind.
            *slot = None;
        }
        let solution = solution?;
        let plan = solution.plan.clone();
        if let Ok(mut slot) = self.evolved.lock() {
            *slot = Some(solution);
        }
        Ok(plan)
    }

    /// The program of the last plan (`program`, one-line S-expression; `program_nodes`,
    /// `program_depth`) and its evolution (`generations`, `evaluations`; absent for a saved
    /// program; `inherited`: evaluations taken from a parent without a simulation).
    fn notes(&self) -> serde_json::Map<String, serde_json::Value> {
        let mut m = serde_json::Map::new();
        if let Some(p) = &self.saved {
            m.insert("program".into(), p.to_string().into());
            m.insert("program_nodes".into(), p.len().into());
            m.insert("program_depth".into(), p.depth().into());
        } else {
            if let Some(s) = self.evolved() {
                m.insert("program".into(), s.program.to_string().into());
                m.insert("program_nodes".into(), s.program.len().into());
                m.insert("program_depth".into(), s.program.depth().into());
            }
            let (generations, evaluations, inherited) = self.effort();
            if evaluations > 0 {
                m.insert("generations".into(), generations.into());
                m.insert("evaluations".into(), evaluations.into());
                m.insert("inherited".into(), inherited.into());
            }
        }
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generator::{ProblemSpec, RobotCount, generate_problem};
    use crate::test_support::{solve_tree, validate_tree_plan};

    #[test]
    fn branch_arrival_is_a_named_option() {
        let resolve = |given: &[(&str, &str)]| {
            let given: Vec<(String, String)> = given
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect();
            Params::resolve(NAME, PARAMS, &given).and_then(|p| gp_params(&p))
        };
        assert_eq!(
            resolve(&[]).unwrap().sim.branch_arrival,
            BranchArrival::Resume
        );
        assert_eq!(
            resolve(&[("branch_arrival", "hold")])
                .unwrap()
                .sim
                .branch_arrival,
            BranchArrival::Hold
        );
        let e = resolve(&[("branch_arrival", "wait")]).unwrap_err();
        assert!(e.to_string().contains("expected resume or hold"), "{e}");
    }

    #[test]
    fn every_plan_passes_the_validator() {
        // Random programs on random problems: whenever a program solves, its plan is valid.
        use rand::SeedableRng;
        let mut solved = 0;
        for seed in 0..40u64 {
            let depth = 4 + (seed % 4) as u32;
            let t = generate_problem(&ProblemSpec::paper(depth, RobotCount::LeavesMinusOne), seed)
                .unwrap();
            let p = Problem::from_tree_instance(&t);
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            for k in 0..10 {
                let prog = Program::grow(&mut rng, 1 + k % 4);
                for follow in [true, false] {
                    let opts = SimOptions {
                        allow_following: follow,
                        branch_arrival: if k % 2 == 0 {
                            BranchArrival::Hold
                        } else {
                            BranchArrival::Resume
                        },
                        ..SimOptions::default()
                    };
                    // A short cap keeps the recorded paths small (M reaches 10⁷ steps).
                    let cap = p.step_cap().min(5_000);
                    let out = run_program(&prog, &p, &opts, cap, true, Deadline::none());
                    // Recorded paths are valid moves even when unsolved (checked as a plan whose
                    // goals are the final positions, which makes every robot "arrive").
                    let last: Vec<u32> = out.paths.iter().map(|q| *q.last().unwrap()).collect();
                    let mut seen = vec![false; p.graph().num_vertices()];
                    let ends_distinct = last
                        .iter()
                        .all(|&v| !std::mem::replace(&mut seen[v as usize], true));
                    assert!(ends_distinct);
                    let as_inst = Instance::new(p.instance().starts.clone(), last).unwrap();
                    let plan = Plan::new(out.paths.clone());
                    validate_tree_plan(p.graph(), &as_inst, &plan, follow)
                        .unwrap_or_else(|v| panic!("{prog}: {}", v));
                    if out.solved() {
                        solved += 1;
                        validate_tree_plan(p.graph(), p.instance(), &plan, follow).unwrap();
                    }
                }
            }
        }
        assert!(solved > 0);
    }

    #[test]
    fn planner_solves_small_problems_and_plans_validate() {
        let planner = Gp::new(GpParams {
            population: 80,
            generations: 10,
            runs: 1,
            ..GpParams::default()
        });
        let mut ok = 0;
        for seed in 0..6u64 {
            let t =
                generate_problem(&ProblemSpec::paper(5, RobotCount::LeavesMinusOne), seed).unwrap();
            let opts = Ctx::new(seed, Deadline::none());
            if let Ok(plan) = solve_tree(&planner, &t.graph, &t.instance, &opts, true) {
                validate_tree_plan(&t.graph, &t.instance, &plan, true).unwrap();
                ok += 1;
            }
        }
        assert!(ok >= 4, "{ok} of 6 solved");
    }

    /// Issue 14, kind 6: a run that found no solving program still reports what it spent.
    #[test]
    fn a_failed_evolution_reports_its_generations_and_evaluations() {
        let planner = Gp::new(GpParams {
            population: 4,
            generations: 2,
            runs: 1,
            ..GpParams::default()
        });
        let mut failed = 0;
        for seed in 0..20u64 {
            let t =
                generate_problem(&ProblemSpec::paper(7, RobotCount::LeavesMinusOne), seed).unwrap();
            let opts = Ctx::new(seed, Deadline::none());
            if solve_tree(&planner, &t.graph, &t.instance, &opts, true).is_err() {
                failed += 1;
                let (generations, evaluations, _) = planner.effort();
                assert_eq!(generations, 2, "seed {seed}");
                assert!(evaluations > 0, "seed {seed}");
                let notes = planner.notes();
                assert_eq!(notes["generations"], 2);
                assert!(notes.get("program").is_none(), "no program solved");
            }
        }
        assert!(
            failed > 0,
            "a 4-program, 2-generation GP should fail somewhere in 20 problems"
        );
    }

    #[test]
    fn program_files_round_trip_and_bad_files_are_errors() {
        let dir = std::env::temp_dir().join(format!("mrpp-gp-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let prog: Program = "(if-robot-at-branch move-to-free-neighbor \
            (if-two-robots-on-each-others-path move-toward-branch \
            (if-robot-moving-to-branch move-toward-branch (if-neighbor-is-surrounded stay \
            (if-on-path-of-robot-in-network (if-robot-in-network-moving-to-branch stay \
            move-to-free-neighbor) (if-robot-is-solved (if-robot-at-destination stay stay) \
            (if-neighbor-on-path-is-free move-toward-objective stay)))))))"
            .parse()
            .unwrap();
        let path = dir.join("p.gp");
        prog.save(&path).unwrap();
        assert_eq!(Program::load(&path).unwrap(), prog);
        let bad = dir.join("bad.gp");
        std::fs::write(&bad, "(if-robot-at-branch\n  stay\n").unwrap();
        let e = Program::load(&bad).unwrap_err().to_string();
        assert!(e.contains("bad.gp:1:") && e.contains("not closed"), "{e}");
        std::fs::write(&bad, [0xff, 0xfe]).unwrap();
        assert!(Program::load(&bad).is_err());
        assert!(Program::load(&dir.join("missing.gp")).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
