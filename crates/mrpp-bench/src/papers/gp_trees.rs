//! The GP paper's experiments (Trudeau & Clark, §7): Table 3 (a program evolved per problem vs
//! PSW), Table 4 (a program trained on |X| problems, tested on new ones) and Table 5 (robots =
//! 0.25–1.5 × leaves), with the numbers behind its Fig. 4–7.
//!
//! Problems come from the paper's generator ([`generate_problem`], b = 4) with the depth budget
//! ("seed value") drawn uniformly from 4–10 for training problems and 4–9 for test problems
//! (§7.1). Problem `i` of a set is fully determined by the user's seed and the set's key
//! ([`draw_problem`]), and every GP run gets its own derived seed, so every number here is the
//! same whatever the thread count. PSW and GP plans are both passed through the validator once
//! ([`mrpp_core::solve`] / [`mrpp_core::accept`] on [`tree_problem`], `visit` semantics); a
//! problem's *time steps* are the makespan of the validated plan (the step at which the last
//! robot first reaches its goal, the paper's τ).
//!
//! Choices where the paper is silent:
//! - **Comparisons** count a problem solved by one method only as a win for that method; the
//!   time-step totals are over problems both solved (in Table 3 PSW solves all of them).
//! - **Table 4 without a solving program.** When no program solves the whole training set, the
//!   program of lowest fitness (the champion) is tested, as EpochX would return it.
//! - **Table 4's test sets** are drawn afresh for each (|X|, trial), 100 problems each in the
//!   paper.
//! - **Running a program on a test problem** uses the paper's cap M = |N|²·|R|² with the exact
//!   cycle cut of [`mrpp_trees::gp::simulate`]; [`GpExperimentConfig::run_time_limit`] bounds
//!   the wall time of one such run (a run cut by it counts as unsolved and is reported).

use std::ops::RangeInclusive;
use std::time::{Duration, Instant};

use rayon::prelude::*;

use mrpp_core::error::{Error, Result};
use mrpp_core::mapf::plan::Plan;
use mrpp_core::seeds::derive_seed;
use mrpp_core::{Ctx, Deadline, Unsolved, accept, solve};
use mrpp_trees::generator::{ProblemSpec, RobotCount, generate_problem};
use mrpp_trees::gp::{Gp, GpParams, Problem, Program, evolve, plan_program};
use mrpp_trees::instance::TreeInstance;
use mrpp_trees::psw::Psw;
use mrpp_trees::tree_problem;

/// The paper's Table 3: GP better, equal, PSW better (%), and the total time steps of PSW and GP
/// over its 1000 problems.
pub const PAPER_TABLE3: (f64, f64, f64) = (73.3, 12.1, 14.6);
pub const PAPER_TABLE3_TOTALS: (u64, u64) = (18633, 8552);
/// The paper's Table 4: |X|, # GP solved (of 1000), % GP better, % equal, % PSW better.
pub const PAPER_TABLE4: [(usize, usize, f64, f64, f64); 3] = [
    (5, 695, 36.69, 11.65, 51.65),
    (10, 866, 30.37, 15.24, 54.39),
    (20, 872, 32.80, 11.12, 56.08),
];
/// The paper's Table 5: leaf multiplier, % GP solved, % PSW solved (200 problems each).
pub const PAPER_TABLE5: [(f64, f64, f64); 4] = [
    (0.25, 100.0, 100.0),
    (0.5, 100.0, 100.0),
    (1.0, 82.0, 68.5),
    (1.5, 58.0, 34.0),
];

/// What every GP experiment shares.
#[derive(Debug, Clone)]
pub struct GpExperimentConfig {
    pub seed: u64,
    pub params: GpParams,
    /// Depth budgets of training problems (paper: 4–10) and of test problems (paper: 4–9).
    pub train_depths: RangeInclusive<u32>,
    pub test_depths: RangeInclusive<u32>,
    pub psw: Psw,
    /// Wall-clock bound of one PSW run or one run of a program on a test problem.
    pub run_time_limit: Duration,
    /// Wall-clock bound of one evolution (ψ* so far is kept when it strikes; `None` = no bound,
    /// which keeps results independent of the machine).
    pub evolve_time_limit: Option<Duration>,
}

impl Default for GpExperimentConfig {
    /// The paper's problems (depth budgets 4–10, tests 4–9) with [`GpParams::default`].
    fn default() -> Self {
        GpExperimentConfig {
            seed: 0,
            params: GpParams::default(),
            train_depths: 4..=10,
            test_depths: 4..=9,
            psw: Psw::default(),
            run_time_limit: Duration::from_secs(60),
            evolve_time_limit: None,
        }
    }
}

impl GpExperimentConfig {
    /// The scaled-down setting the CLI runs by default, minutes per table on 2 cores:
    /// - **depth budgets 3–4** (trees of 15 nodes and 7 robots on average). The paper's PSW
    ///   needed 18.6 time steps per problem (18 633 over 1000); ours needs 432 on our reading of
    ///   its depth budgets 4–10 and 37 on budgets 3–4, so 3–4 is still the larger of the two
    ///   scales (see `docs/reproduction/gp-trees.md`);
    /// - **GP |P| = 1000, 3 runs of 50 generations**: 1/27 of the paper's evaluations.
    pub fn scaled_down() -> Self {
        GpExperimentConfig {
            params: GpParams {
                population: 1000,
                generations: 50,
                runs: 3,
                ..GpParams::default()
            },
            train_depths: 3..=4,
            test_depths: 3..=4,
            ..GpExperimentConfig::default()
        }
    }

    /// The paper's §7 setting: [`GpParams::paper`] on depth budgets 4–10 (tests 4–9).
    pub fn paper() -> Self {
        GpExperimentConfig {
            params: GpParams::paper(),
            ..GpExperimentConfig::default()
        }
    }
}

/// Problem `index` of the set named `set`: the depth budget is drawn uniformly from `depths`, the
/// tree and robots from the generator, both from seeds derived from `seed` and the set's key.
pub fn draw_problem(
    seed: u64,
    set: &str,
    index: usize,
    depths: &RangeInclusive<u32>,
    robots: RobotCount,
) -> Result<(u32, TreeInstance)> {
    let span = u64::from(depths.end() - depths.start() + 1);
    let depth = depths.start() + (derive_seed(seed, &format!("{set}/{index}/depth")) % span) as u32;
    let spec = ProblemSpec::paper(depth, robots);
    let t = generate_problem(&spec, derive_seed(seed, &format!("{set}/{index}")))?;
    Ok((depth, t))
}

/// PSW's run on one problem: time steps when solved (validated), and the number of swaps. PSW's
/// internals run directly (for the swap count) and the plan goes through [`accept`].
fn run_psw(cfg: &GpExperimentConfig, t: &TreeInstance) -> Result<(Option<u64>, usize)> {
    let started = Instant::now();
    let run = cfg
        .psw
        .run(&t.graph, &t.instance, Deadline::after(cfg.run_time_limit));
    let steps = if run.solved() {
        let problem = tree_problem(t, cfg.psw.allow_following);
        Some(time_steps(accept(
            &problem,
            Plan::new(run.paths),
            mrpp_trees::psw::NAME,
            started.elapsed(),
        ))?)
    } else {
        None
    };
    Ok((steps, run.swaps.len()))
}

/// The time steps of a validated plan (the makespan under `visit` semantics); a plan the
/// validator rejected is an internal error (a bug), an honest "not solved" is `None`.
fn time_steps(
    outcome: std::result::Result<mrpp_core::Solved<mrpp_core::MapfProblem>, Unsolved>,
) -> Result<u64> {
    match outcome {
        Ok(s) => Ok(s.metrics.makespan),
        Err(why) => Err(Error::Internal(why.to_string())),
    }
}

/// Runs `program` on a test problem; time steps when it solves (validated).
fn run_program_on(
    cfg: &GpExperimentConfig,
    program: &Program,
    t: &TreeInstance,
    problem: &Problem,
) -> Result<Option<u64>> {
    let started = Instant::now();
    let deadline = Deadline::after(cfg.run_time_limit);
    match plan_program(program, problem, &cfg.params.sim, deadline) {
        Ok((plan, _)) => {
            let judged = tree_problem(t, cfg.params.sim.allow_following);
            Ok(Some(time_steps(accept(
                &judged,
                plan,
                mrpp_trees::gp::NAME,
                started.elapsed(),
            ))?))
        }
        Err(_) => Ok(None),
    }
}

/// Who needed fewer time steps on one problem (a method that did not solve it loses).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    GpBetter,
    Equal,
    PswBetter,
    /// Neither solved it.
    Neither,
}

pub fn verdict(gp: Option<u64>, psw: Option<u64>) -> Verdict {
    match (gp, psw) {
        (Some(g), Some(p)) if g < p => Verdict::GpBetter,
        (Some(g), Some(p)) if g == p => Verdict::Equal,
        (Some(_), Some(_)) | (None, Some(_)) => Verdict::PswBetter,
        (Some(_), None) => Verdict::GpBetter,
        (None, None) => Verdict::Neither,
    }
}

/// One problem of Table 3 or Table 5: a program evolved for it, and PSW.
#[derive(Debug, Clone, PartialEq)]
pub struct ProblemRow {
    /// Leaf multiplier (Table 5), `None` for #leaves − 1 robots (Table 3).
    pub multiplier: Option<f64>,
    pub index: usize,
    pub depth: u32,
    pub nodes: usize,
    pub leaves: usize,
    pub robots: usize,
    /// The longest start–goal distance: no plan takes fewer time steps.
    pub lower_bound: u64,
    pub psw_steps: Option<u64>,
    pub psw_swaps: usize,
    pub gp_steps: Option<u64>,
    pub gp_generations: usize,
    pub gp_evaluations: u64,
    /// Wall time of the evolution (machine-dependent).
    pub gp_seconds: f64,
    /// ψ*, one line, when one solved the problem.
    pub program: Option<String>,
}

impl ProblemRow {
    pub fn verdict(&self) -> Verdict {
        verdict(self.gp_steps, self.psw_steps)
    }
}

/// Evolves a program for problem `index` of the set `set` and runs PSW on it.
fn per_problem(
    cfg: &GpExperimentConfig,
    set: &str,
    index: usize,
    robots: RobotCount,
    multiplier: Option<f64>,
) -> Result<ProblemRow> {
    let (depth, t) = draw_problem(cfg.seed, set, index, &cfg.train_depths, robots)?;
    let (psw_steps, psw_swaps) = run_psw(cfg, &t)?;
    let started = Instant::now();
    let deadline = cfg
        .evolve_time_limit
        .map_or_else(Deadline::none, Deadline::after);
    let gp_seed = derive_seed(cfg.seed, &format!("{set}/{index}/gp"));
    let planner = Gp::new(cfg.params.clone());
    let outcome = solve(
        &planner,
        &tree_problem(&t, cfg.params.sim.allow_following),
        &Ctx::new(gp_seed, deadline),
    );
    let gp_seconds = started.elapsed().as_secs_f64();
    let problem = Problem::from_tree_instance(&t);
    let mut row = ProblemRow {
        multiplier,
        index,
        depth,
        nodes: t.num_nodes(),
        leaves: t.num_leaves(),
        robots: t.num_robots(),
        lower_bound: problem.lower_bound(),
        psw_steps,
        psw_swaps,
        gp_steps: None,
        gp_generations: 0,
        gp_evaluations: 0,
        gp_seconds,
        program: None,
    };
    if let Some(s) = planner.evolved() {
        row.gp_steps = Some(time_steps(outcome)?);
        row.gp_generations = s.result.generations;
        row.gp_evaluations = s.result.evaluations;
        row.program = Some(s.program.to_string());
    }
    Ok(row)
}

/// Table 3 (§7.2): `problems` problems with #leaves − 1 robots, a program evolved for each.
/// `done` is called (from any thread) after each problem.
pub fn run_table3(
    cfg: &GpExperimentConfig,
    problems: usize,
    done: &(dyn Fn(&ProblemRow) + Sync),
) -> Result<Vec<ProblemRow>> {
    cfg.params.check()?;
    (0..problems)
        .into_par_iter()
        .map(|i| {
            let row = per_problem(cfg, "table3", i, RobotCount::LeavesMinusOne, None)?;
            done(&row);
            Ok(row)
        })
        .collect()
}

/// Table 5 (§7.4): for each leaf multiplier, `problems` problems with ⌊m · #leaves⌋ robots
/// (capped at |N| − 2).
pub fn run_table5(
    cfg: &GpExperimentConfig,
    multipliers: &[f64],
    problems: usize,
    done: &(dyn Fn(&ProblemRow) + Sync),
) -> Result<Vec<ProblemRow>> {
    cfg.params.check()?;
    if let Some(m) = multipliers.iter().find(|m| !(m.is_finite() && **m > 0.0)) {
        return Err(Error::Param(format!(
            "leaf multipliers must be positive, got {m}"
        )));
    }
    let jobs: Vec<(f64, usize)> = multipliers
        .iter()
        .flat_map(|&m| (0..problems).map(move |i| (m, i)))
        .collect();
    jobs.into_par_iter()
        .map(|(m, i)| {
            let row = per_problem(
                cfg,
                &format!("table5/{m}"),
                i,
                RobotCount::PerLeaf(m),
                Some(m),
            )?;
            done(&row);
            Ok(row)
        })
        .collect()
}

/// Better / equal / worse shares and totals of a set of per-problem rows.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Comparison {
    pub problems: usize,
    pub gp_solved: usize,
    pub psw_solved: usize,
    pub gp_better: usize,
    pub equal: usize,
    pub psw_better: usize,
    /// Over problems both solved.
    pub both: usize,
    pub gp_total: u64,
    pub psw_total: u64,
}

impl Comparison {
    pub fn of(pairs: impl IntoIterator<Item = (Option<u64>, Option<u64>)>) -> Self {
        let mut c = Comparison::default();
        for (g, p) in pairs {
            c.problems += 1;
            c.gp_solved += usize::from(g.is_some());
            c.psw_solved += usize::from(p.is_some());
            match verdict(g, p) {
                Verdict::GpBetter => c.gp_better += 1,
                Verdict::Equal => c.equal += 1,
                Verdict::PswBetter => c.psw_better += 1,
                Verdict::Neither => {}
            }
            if let (Some(g), Some(p)) = (g, p) {
                c.both += 1;
                c.gp_total += g;
                c.psw_total += p;
            }
        }
        c
    }

    /// `part` as a percentage of `whole` (0 when `whole` is 0).
    pub fn pct(part: usize, whole: usize) -> f64 {
        if whole == 0 {
            0.0
        } else {
            100.0 * part as f64 / whole as f64
        }
    }
}

/// One (|X|, trial) of Table 4: the program trained on |X| problems.
#[derive(Debug, Clone, PartialEq)]
pub struct TrainedProgram {
    pub train_size: usize,
    pub trial: usize,
    /// ψ* when a program solved the whole training set, else the champion.
    pub program: String,
    pub solved_training_set: bool,
    pub generations: usize,
    pub evaluations: u64,
    pub seconds: f64,
}

/// One test problem of Table 4.
#[derive(Debug, Clone, PartialEq)]
pub struct TestRow {
    pub train_size: usize,
    pub trial: usize,
    pub index: usize,
    pub depth: u32,
    pub nodes: usize,
    pub robots: usize,
    pub lower_bound: u64,
    pub psw_steps: Option<u64>,
    pub psw_swaps: usize,
    pub gp_steps: Option<u64>,
}

/// Table 4 (§7.3): for each |X| in `train_sizes` and each of `trials` trials, a program evolved on
/// |X| training problems is run on `tests` new problems. `done` is called after each trial.
pub fn run_table4(
    cfg: &GpExperimentConfig,
    train_sizes: &[usize],
    trials: usize,
    tests: usize,
    done: &(dyn Fn(&TrainedProgram) + Sync),
) -> Result<(Vec<TrainedProgram>, Vec<TestRow>)> {
    cfg.params.check()?;
    if train_sizes.contains(&0) {
        return Err(Error::Param(
            "a training set needs at least 1 problem".into(),
        ));
    }
    let jobs: Vec<(usize, usize)> = train_sizes
        .iter()
        .flat_map(|&x| (0..trials).map(move |t| (x, t)))
        .collect();
    let results: Vec<(TrainedProgram, Vec<TestRow>)> = jobs
        .into_par_iter()
        .map(|(x, trial)| {
            let key = format!("table4/{x}/{trial}");
            let training: Vec<Problem> = (0..x)
                .map(|j| {
                    draw_problem(
                        cfg.seed,
                        &format!("{key}/train"),
                        j,
                        &cfg.train_depths,
                        RobotCount::LeavesMinusOne,
                    )
                    .map(|(_, t)| Problem::from_tree_instance(&t))
                })
                .collect::<Result<_>>()?;
            let started = Instant::now();
            let deadline = cfg
                .evolve_time_limit
                .map_or_else(Deadline::none, Deadline::after);
            let r = evolve(
                &training,
                &cfg.params,
                derive_seed(cfg.seed, &format!("{key}/gp")),
                deadline,
                &mut |_| {},
            )?;
            let solved_training_set = r.best.is_some();
            let program = r.best.clone().unwrap_or_else(|| r.champion.clone());
            let trained = TrainedProgram {
                train_size: x,
                trial,
                program: program.to_string(),
                solved_training_set,
                generations: r.generations,
                evaluations: r.evaluations,
                seconds: started.elapsed().as_secs_f64(),
            };
            let rows = (0..tests)
                .into_par_iter()
                .map(|i| {
                    let (depth, t) = draw_problem(
                        cfg.seed,
                        &format!("{key}/test"),
                        i,
                        &cfg.test_depths,
                        RobotCount::LeavesMinusOne,
                    )?;
                    let (psw_steps, psw_swaps) = run_psw(cfg, &t)?;
                    let problem = Problem::from_tree_instance(&t);
                    let gp_steps = run_program_on(cfg, &program, &t, &problem)?;
                    Ok(TestRow {
                        train_size: x,
                        trial,
                        index: i,
                        depth,
                        nodes: t.num_nodes(),
                        robots: t.num_robots(),
                        lower_bound: problem.lower_bound(),
                        psw_steps,
                        psw_swaps,
                        gp_steps,
                    })
                })
                .collect::<Result<Vec<_>>>()?;
            done(&trained);
            Ok((trained, rows))
        })
        .collect::<Result<_>>()?;
    let (programs, rows): (Vec<_>, Vec<Vec<_>>) = results.into_iter().unzip();
    Ok((programs, rows.into_iter().flatten().collect()))
}

/// Mean and standard deviation of `y` for each distinct `x` (the paper's plots: "each data point
/// is the average y-value across examples sharing an x-value"), sorted by x.
pub fn mean_by_x(points: impl IntoIterator<Item = (f64, f64)>) -> Vec<(f64, f64, f64)> {
    let mut pts: Vec<(f64, f64)> = points.into_iter().collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out = Vec::new();
    for group in pts.chunk_by(|a, b| a.0 == b.0) {
        let n = group.len() as f64;
        let mean = group.iter().map(|p| p.1).sum::<f64>() / n;
        let var = group.iter().map(|p| (p.1 - mean).powi(2)).sum::<f64>() / n;
        out.push((group[0].0, mean, var.sqrt()));
    }
    out
}

/// `swaps / robots` rounded to a quarter, the x of the paper's Fig. 5 and Fig. 7 (binned so that
/// "examples sharing an x-value" have company).
pub fn swap_ratio(swaps: usize, robots: usize) -> f64 {
    let r = swaps as f64 / robots.max(1) as f64;
    (r * 4.0).round() / 4.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tiny() -> GpExperimentConfig {
        GpExperimentConfig {
            seed: 5,
            params: GpParams {
                population: 30,
                generations: 4,
                runs: 1,
                ..GpParams::default()
            },
            train_depths: 3..=5,
            test_depths: 3..=5,
            ..GpExperimentConfig::default()
        }
    }

    #[test]
    fn problems_are_drawn_from_the_seed_and_key() {
        let d = 4..=10;
        let a = draw_problem(1, "s", 3, &d, RobotCount::LeavesMinusOne).unwrap();
        let b = draw_problem(1, "s", 3, &d, RobotCount::LeavesMinusOne).unwrap();
        assert_eq!(a.0, b.0);
        assert_eq!(a.1.to_json(), b.1.to_json());
        assert!(d.contains(&a.0));
        let depths: std::collections::BTreeSet<u32> = (0..60)
            .map(|i| {
                draw_problem(1, "s", i, &d, RobotCount::LeavesMinusOne)
                    .unwrap()
                    .0
            })
            .collect();
        assert_eq!(depths.len(), 7, "every depth budget 4..=10 is drawn");
    }

    #[test]
    fn verdicts_and_comparison() {
        assert_eq!(verdict(Some(3), Some(4)), Verdict::GpBetter);
        assert_eq!(verdict(Some(4), Some(4)), Verdict::Equal);
        assert_eq!(verdict(None, Some(4)), Verdict::PswBetter);
        assert_eq!(verdict(Some(9), None), Verdict::GpBetter);
        let c = Comparison::of([(Some(3), Some(4)), (Some(5), Some(5)), (None, Some(2))]);
        assert_eq!((c.gp_better, c.equal, c.psw_better), (1, 1, 1));
        assert_eq!((c.both, c.gp_total, c.psw_total), (2, 8, 9));
        assert_eq!((c.gp_solved, c.psw_solved), (2, 3));
        let m = mean_by_x([(1.0, 2.0), (1.0, 4.0), (2.0, 5.0)]);
        assert_eq!(m, vec![(1.0, 3.0, 1.0), (2.0, 5.0, 0.0)]);
        assert_eq!(swap_ratio(5, 4), 1.25);
    }

    #[test]
    fn table3_rows_are_validated_and_independent_of_threads() {
        let cfg = tiny();
        let go = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| run_table3(&cfg, 6, &|_| {}).unwrap())
        };
        let one = go(1);
        let two = go(2);
        let strip = |rows: &[ProblemRow]| -> Vec<ProblemRow> {
            rows.iter()
                .map(|r| ProblemRow {
                    gp_seconds: 0.0,
                    ..r.clone()
                })
                .collect()
        };
        assert_eq!(strip(&one), strip(&two));
        // PSW is complete with #leaves − 1 robots.
        assert!(one.iter().all(|r| r.psw_steps.is_some()));
        for r in &one {
            for s in [r.psw_steps, r.gp_steps].into_iter().flatten() {
                assert!(s >= r.lower_bound);
            }
        }
    }

    #[test]
    fn table4_and_table5_run_small() {
        let cfg = tiny();
        let (progs, rows) = run_table4(&cfg, &[1, 2], 1, 3, &|_| {}).unwrap();
        assert_eq!(progs.len(), 2);
        assert_eq!(rows.len(), 6);
        assert!(rows.iter().all(|r| r.psw_steps.is_some()));
        for p in &progs {
            assert!(p.program.parse::<Program>().is_ok());
        }
        let rows5 = run_table5(&cfg, &[0.5, 1.5], 3, &|_| {}).unwrap();
        assert_eq!(rows5.len(), 6);
        assert!(run_table5(&cfg, &[0.0], 1, &|_| {}).is_err());
        assert!(run_table4(&cfg, &[0], 1, 1, &|_| {}).is_err());
    }
}
