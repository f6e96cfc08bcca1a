//! `mrpp trees …`: single-lane tree problems (Trudeau & Clark; issue 4). Generate a random tree
//! instance, solve it with Push-Swap-Wait or genetic programming, run a saved GP program on it,
//! and validate a tree plan. Same conventions as the grid commands: one summary line with the
//! mrpp version and the seed, files written atomically, exit 0 = solved / valid, 1 = bad input
//! or an invalid plan, 3 = not solved (the plan file is still written, with "solved": false).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use clap::{Args, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};

use mrpp::io::tree_plan_json::TreePlanFile;
use mrpp::plan::{Metrics, Plan};
use mrpp::solve::{Deadline, SolveOptions, Unsolved};
use mrpp::trees::gp::{GpParams, GpProgress, Problem, Program, SimOptions, gp, plan_program};
use mrpp::trees::{
    ProblemSpec, Psw, RobotCount, TreeInstance, generate_problem, solve_tree, validate_tree_plan,
};

use crate::{Fail, file_name, write_atomic};

/// Largest depth budget `trees gen` accepts (the paper uses 4–10).
const MAX_DEPTH: u32 = 30;
/// Largest branching factor `trees gen` accepts (the paper uses 4).
const MAX_BRANCHING: u32 = 16;

#[derive(Subcommand)]
pub(crate) enum Trees {
    /// Generate a random tree problem (the paper's Algorithm 2 and random robots) as JSON.
    Gen {
        /// Seed of the random stream (the same seed and parameters give the same file).
        #[arg(long)]
        seed: u64,
        /// Depth budget, Algorithm 2's "seed" (paper: 4–10; at most 30).
        #[arg(long)]
        depth: u32,
        /// Maximum branching factor b: a node gets 0..b-1 children (paper: 4; 3 to 16).
        #[arg(long, default_value_t = 4)]
        branching: u32,
        /// Number of robots (at most the node count minus 2).
        #[arg(long)]
        robots: Option<usize>,
        /// Robots = floor(M x leaves), capped at the node count minus 2 (paper: 0.25 to 1.5).
        #[arg(long, allow_negative_numbers = true)]
        leaf_multiplier: Option<f64>,
        /// Refuse trees with more nodes than this: with b = 4 the tree size varies wildly with the
        /// seed at large depths (depth 30 gives from a few nodes to millions), and neither
        /// planner can do anything useful on such trees. The generator itself stops at 2^22.
        #[arg(long, default_value_t = 100_000)]
        max_nodes: usize,
        /// Write the instance here.
        #[arg(long)]
        out: PathBuf,
    },
    /// Solve a tree instance with PSW or GP and write the plan (node ids, visit semantics).
    Solve {
        /// Tree instance JSON: {"nodes": N, "edges": [[u, v], ...], "robots": [{"start", "goal"}]}.
        #[arg(long)]
        instance: PathBuf,
        /// psw (Push-Swap-Wait) or gp (evolve a program for this instance).
        #[arg(long, value_enum)]
        planner: TreePlanner,
        /// With --planner gp: run this saved program instead of evolving one.
        #[arg(long)]
        program: Option<PathBuf>,
        /// Seed of the GP evolution (PSW is deterministic; the seed is only recorded).
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Wall-clock limit in seconds.
        #[arg(long, default_value_t = 60.0, allow_negative_numbers = true)]
        time_limit: f64,
        /// Forbid following (entering a node that another robot leaves in the same step).
        #[arg(long)]
        no_following: bool,
        #[command(flatten)]
        gp: Box<GpArgs>,
        /// Write the plan here (also written when not solved, with "solved": false).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Run a saved GP program on a tree instance and write its plan.
    Run {
        /// GP program file (S-expression, as written by `trees solve --save-program`).
        #[arg(long)]
        program: PathBuf,
        /// Tree instance JSON.
        #[arg(long)]
        instance: PathBuf,
        #[arg(long, default_value_t = 60.0, allow_negative_numbers = true)]
        time_limit: f64,
        #[arg(long)]
        no_following: bool,
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Check a tree plan against its instance: exit 0 when valid, 1 naming the first violation.
    Validate {
        /// The tree instance the plan was made for.
        #[arg(long)]
        instance: PathBuf,
        /// Tree plan JSON (as written by `trees solve` / `trees run`).
        #[arg(long)]
        plan: PathBuf,
        /// Judge with following forbidden even when the plan file allows it.
        #[arg(long)]
        no_following: bool,
    },
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum TreePlanner {
    Psw,
    Gp,
}

/// The GP evolution's parameters, shared by `trees solve` and the GP experiments.
#[derive(Args)]
pub(crate) struct GpParamArgs {
    /// |P|: programs per generation (default 200, experiments 1000; paper 2000).
    #[arg(long)]
    pub(crate) population: Option<usize>,
    /// i_g: generations per run (default 25, experiments 50; paper 400).
    #[arg(long)]
    pub(crate) generations: Option<usize>,
    /// i_r: independent runs (default 2, experiments 3; paper 5).
    #[arg(long)]
    pub(crate) runs: Option<usize>,
    /// Start from the paper's settings (|P| = 2000, 5 runs of 400 generations, cap M).
    #[arg(long)]
    pub(crate) paper_settings: bool,
    /// Step cap of each example during evolution, in steps per tree node (default 20, i.e.
    /// 20·|N|); 0 = the paper's M = |N|²·|R|².
    #[arg(long)]
    pub(crate) evolution_cap: Option<u64>,
    /// p_a, p_c, p_m: shares of the next generation made by reproduction, crossover and
    /// mutation (default 0.1, 0.8, 0.1; they must sum to 1).
    #[arg(long)]
    pub(crate) p_reproduction: Option<f64>,
    #[arg(long)]
    pub(crate) p_crossover: Option<f64>,
    #[arg(long)]
    pub(crate) p_mutation: Option<f64>,
    /// Depth bounds of every program (default 1 and 50) and of the initial ones (default 2).
    #[arg(long)]
    pub(crate) min_depth: Option<usize>,
    #[arg(long)]
    pub(crate) max_depth: Option<usize>,
    #[arg(long)]
    pub(crate) init_depth: Option<usize>,
}

impl GpParamArgs {
    fn any(&self) -> bool {
        self.population.is_some()
            || self.generations.is_some()
            || self.runs.is_some()
            || self.paper_settings
            || self.evolution_cap.is_some()
            || self.p_reproduction.is_some()
            || self.p_crossover.is_some()
            || self.p_mutation.is_some()
            || self.min_depth.is_some()
            || self.max_depth.is_some()
            || self.init_depth.is_some()
    }

    /// The parameters, checked with [`GpParams::validate`].
    pub(crate) fn params(&self, allow_following: bool) -> Result<GpParams, Fail> {
        self.params_over(GpParams::default(), allow_following)
    }

    /// The flags applied over `default` (ignored with `--paper-settings`, which starts from the
    /// paper's values).
    pub(crate) fn params_over(
        &self,
        default: GpParams,
        allow_following: bool,
    ) -> Result<GpParams, Fail> {
        let mut p = if self.paper_settings {
            GpParams::paper()
        } else {
            default
        };
        p.population = self.population.unwrap_or(p.population);
        p.generations = self.generations.unwrap_or(p.generations);
        p.runs = self.runs.unwrap_or(p.runs);
        if let Some(k) = self.evolution_cap {
            p.cap_factor = (k > 0).then_some(k);
        }
        p.p_reproduction = self.p_reproduction.unwrap_or(p.p_reproduction);
        p.p_crossover = self.p_crossover.unwrap_or(p.p_crossover);
        p.p_mutation = self.p_mutation.unwrap_or(p.p_mutation);
        p.min_depth = self.min_depth.unwrap_or(p.min_depth);
        p.max_depth = self.max_depth.unwrap_or(p.max_depth);
        p.init_depth = self.init_depth.unwrap_or(p.init_depth);
        p.sim.allow_following = allow_following;
        p.validate()?;
        Ok(p)
    }
}

/// The GP evolution's settings (only with `--planner gp` and no `--program`).
#[derive(Args)]
pub(crate) struct GpArgs {
    #[command(flatten)]
    params: GpParamArgs,
    /// Write the evolved program here (S-expression; `mrpp trees run --program` reads it).
    #[arg(long)]
    save_program: Option<PathBuf>,
}

impl GpArgs {
    fn any(&self) -> bool {
        self.params.any() || self.save_program.is_some()
    }

    fn params(&self, allow_following: bool) -> Result<GpParams, Fail> {
        self.params.params(allow_following)
    }
}

pub(crate) fn run(cmd: Trees) -> Result<u8, Fail> {
    match cmd {
        Trees::Gen {
            seed,
            depth,
            branching,
            robots,
            leaf_multiplier,
            max_nodes,
            out,
        } => {
            let limits = GenSize {
                depth,
                branching,
                max_nodes,
            };
            cmd_gen(seed, limits, robots, leaf_multiplier, &out)
        }
        Trees::Solve {
            instance,
            planner,
            program,
            seed,
            time_limit,
            no_following,
            gp,
            out,
        } => {
            let deadline = deadline(time_limit)?;
            let tree = TreeInstance::load(&instance)?;
            let ctx = Ctx {
                command: "solve",
                tree: &tree,
                instance_path: &instance,
                seed,
                allow_following: !no_following,
            };
            match (planner, program) {
                (TreePlanner::Psw, Some(_)) => Err(Fail("--program needs --planner gp".into())),
                (TreePlanner::Psw, None) if gp.any() => Err(Fail(
                    "--population, --generations, --runs, --paper-settings and --save-program \
                     are for --planner gp"
                        .into(),
                )),
                (TreePlanner::Psw, None) => solve_psw(&ctx, deadline, out.as_deref()),
                (TreePlanner::Gp, Some(_)) if gp.any() => Err(Fail(
                    "--program runs a saved program: --population, --generations, --runs, \
                     --paper-settings and --save-program only apply when evolving one"
                        .into(),
                )),
                (TreePlanner::Gp, Some(p)) => {
                    let program = Program::load(&p)?;
                    run_saved(&ctx, &program, deadline, out.as_deref())
                }
                (TreePlanner::Gp, None) => {
                    let params = gp.params(ctx.allow_following)?;
                    solve_gp(
                        &ctx,
                        &params,
                        deadline,
                        gp.save_program.as_deref(),
                        out.as_deref(),
                    )
                }
            }
        }
        Trees::Run {
            program,
            instance,
            time_limit,
            no_following,
            out,
        } => {
            let deadline = deadline(time_limit)?;
            let program = Program::load(&program)?;
            let tree = TreeInstance::load(&instance)?;
            let ctx = Ctx {
                command: "run",
                tree: &tree,
                instance_path: &instance,
                // A program run draws nothing at random; 0 is recorded.
                seed: 0,
                allow_following: !no_following,
            };
            run_saved(&ctx, &program, deadline, out.as_deref())
        }
        Trees::Validate {
            instance,
            plan,
            no_following,
        } => cmd_validate(&instance, &plan, no_following),
    }
}

fn deadline(time_limit: f64) -> Result<Deadline, Fail> {
    if !(time_limit.is_finite() && time_limit > 0.0 && time_limit <= 1e7) {
        return Err(Fail(format!(
            "--time-limit must be a positive number of seconds, got {time_limit}"
        )));
    }
    Ok(Deadline::after(Duration::from_secs_f64(time_limit)))
}

/// Checks the parameters before generating, so that nothing is written for absurd ones.
fn robot_count(robots: Option<usize>, leaf_multiplier: Option<f64>) -> Result<RobotCount, Fail> {
    match (robots, leaf_multiplier) {
        (Some(_), Some(_)) => Err(Fail(
            "give either --robots or --leaf-multiplier, not both".into(),
        )),
        (None, None) => Err(Fail(
            "give the robot count: --robots N or --leaf-multiplier M".into(),
        )),
        (Some(0), None) => Err(Fail("--robots must be at least 1".into())),
        (Some(n), None) => Ok(RobotCount::Exactly(n)),
        (None, Some(m)) if !(m.is_finite() && m > 0.0) => Err(Fail(format!(
            "--leaf-multiplier must be a positive number, got {m}"
        ))),
        (None, Some(m)) => Ok(RobotCount::PerLeaf(m)),
    }
}

/// The tree-shape parameters of `trees gen`.
struct GenSize {
    depth: u32,
    branching: u32,
    max_nodes: usize,
}

fn cmd_gen(
    seed: u64,
    size: GenSize,
    robots: Option<usize>,
    leaf_multiplier: Option<f64>,
    out: &Path,
) -> Result<u8, Fail> {
    let GenSize {
        depth,
        branching,
        max_nodes,
    } = size;
    if depth == 0 || depth > MAX_DEPTH {
        return Err(Fail(format!(
            "--depth must be between 1 and {MAX_DEPTH}, got {depth}"
        )));
    }
    // With b < 3 a node has at most one child, so no tree has the 2 leaves a problem needs.
    if !(3..=MAX_BRANCHING).contains(&branching) {
        return Err(Fail(format!(
            "--branching must be between 3 and {MAX_BRANCHING} (a node gets 0..b-1 children, so \
             b < 3 only makes paths), got {branching}"
        )));
    }
    let count = robot_count(robots, leaf_multiplier)?;
    let spec = ProblemSpec {
        branching,
        ..ProblemSpec::paper(depth, count)
    };
    let tree = generate_problem(&spec, seed)?;
    let n = tree.num_nodes();
    if n > max_nodes {
        return Err(Fail(format!(
            "the tree for seed {seed} (depth {depth}, branching {branching}) has {n} nodes, more \
             than --max-nodes {max_nodes}; lower --depth or --branching, or raise --max-nodes"
        )));
    }
    // The generator caps an explicit count at |N| - 2; asking for more is an error here.
    if let Some(k) = robots.filter(|&k| k + 2 > n) {
        return Err(Fail(format!(
            "--robots {k} is more than this tree allows: it has {n} nodes and at least 2 must \
             stay free (at most {})",
            n - 2
        )));
    }
    write_atomic(out, &tree.to_json())?;
    let branches = (0..n as u32).filter(|&v| tree.graph.degree(v) >= 3).count();
    println!(
        "mrpp {} | trees gen | seed {seed} | depth {depth} | branching {branching} | nodes {n} | \
         leaves {} | branch nodes {branches} | robots {} | written to {}",
        env!("CARGO_PKG_VERSION"),
        tree.num_leaves(),
        tree.num_robots(),
        out.display()
    );
    Ok(0)
}

/// What every plan report needs besides the plan.
struct Ctx<'a> {
    /// `solve` or `run`, for the summary line.
    command: &'static str,
    tree: &'a TreeInstance,
    instance_path: &'a Path,
    seed: u64,
    allow_following: bool,
}

fn solve_psw(ctx: &Ctx, deadline: Deadline, out: Option<&Path>) -> Result<u8, Fail> {
    let psw = Psw {
        allow_following: ctx.allow_following,
        ..Psw::default()
    };
    let opts = SolveOptions {
        seed: ctx.seed,
        deadline,
    };
    let started = Instant::now();
    let outcome = solve_tree(
        &psw,
        &ctx.tree.graph,
        &ctx.tree.instance,
        &opts,
        ctx.allow_following,
    );
    report(ctx, "psw", None, outcome, started, out)
}

fn solve_gp(
    ctx: &Ctx,
    params: &GpParams,
    deadline: Deadline,
    save_program: Option<&Path>,
    out: Option<&Path>,
) -> Result<u8, Fail> {
    // Hidden when stderr is not a terminal, so scripts and tests see only real messages.
    let bar = ProgressBar::new((params.runs * params.generations) as u64);
    bar.set_style(
        ProgressStyle::with_template(
            "{bar:40} {pos}/{len} generations  {elapsed_precise} (eta {eta})  {msg}",
        )
        .expect("static template"),
    );
    let started = Instant::now();
    let result = gp(
        &ctx.tree.graph,
        &ctx.tree.instance,
        params,
        ctx.seed,
        deadline,
        &mut |p: &GpProgress| {
            bar.set_length(p.total as u64);
            bar.set_position(p.done as u64);
            bar.set_message(match p.best_steps {
                Some(s) => format!("run {} | best {s} steps", p.run + 1),
                None => format!("run {} | best fitness {}", p.run + 1, p.best_fitness),
            });
        },
    );
    bar.finish_and_clear();
    let seconds = started.elapsed().as_secs_f64();
    let (outcome, program, stats) = match result {
        Ok(s) => (
            Ok(s.plan),
            Some(s.program),
            Some((s.result.generations, s.result.evaluations)),
        ),
        Err(e) => (Err(e), None, None),
    };
    let code = report(ctx, "gp", program.as_ref(), outcome, started, out)?;
    if let (Some((generations, evaluations)), Some(p)) = (stats, &program) {
        println!(
            "gp: {generations} generations | {evaluations} program evaluations ({:.0} per second) | program of {} nodes, depth {}",
            evaluations as f64 / seconds.max(1e-9),
            p.len(),
            p.depth()
        );
    }
    match (save_program, &program) {
        (Some(path), Some(p)) => {
            // Through a temporary file, as every other output, then renamed into place.
            let tmp = tmp_beside(path);
            p.save(&tmp).inspect_err(|_| {
                let _ = std::fs::remove_file(&tmp);
            })?;
            std::fs::rename(&tmp, path).map_err(|e| {
                let _ = std::fs::remove_file(&tmp);
                Fail(format!("{}: cannot write: {e}", path.display()))
            })?;
            println!("program written to {}", path.display());
        }
        (Some(path), None) => println!(
            "no program solved the instance: {} not written",
            path.display()
        ),
        (None, _) => {}
    }
    Ok(code)
}

/// A temporary name next to `path` (same directory, so the rename is atomic).
fn tmp_beside(path: &Path) -> PathBuf {
    let name = file_name(path);
    path.with_file_name(format!(".{name}.tmp{}", std::process::id()))
}

fn run_saved(
    ctx: &Ctx,
    program: &Program,
    deadline: Deadline,
    out: Option<&Path>,
) -> Result<u8, Fail> {
    let problem = Problem::from_tree_instance(ctx.tree);
    let sim = SimOptions {
        allow_following: ctx.allow_following,
        ..SimOptions::default()
    };
    let started = Instant::now();
    let outcome = plan_program(program, &problem, &sim, deadline).map(|(plan, _)| plan);
    report(ctx, "gp", Some(program), outcome, started, out)
}

/// Validates a planner's plan, prints the summary, writes the plan file, and maps the outcome
/// to the exit code (0 solved, 3 not solved). A plan the validator rejects is a bug, reported as
/// an error rather than written.
fn report(
    ctx: &Ctx,
    planner: &str,
    program: Option<&Program>,
    outcome: Result<Plan, Unsolved>,
    started: Instant,
    out: Option<&Path>,
) -> Result<u8, Fail> {
    let runtime_ms = started.elapsed().as_secs_f64() * 1e3;
    let (tree, inst) = (ctx.tree, &ctx.tree.instance);
    println!(
        "mrpp {} | trees {} | planner {planner} | seed {} | instance {} | nodes {} | robots {}",
        env!("CARGO_PKG_VERSION"),
        ctx.command,
        ctx.seed,
        file_name(ctx.instance_path),
        tree.num_nodes(),
        tree.num_robots()
    );
    let solved: Option<(Plan, Metrics)> = match outcome {
        Ok(mut plan) => {
            plan.trim();
            let m =
                validate_tree_plan(&tree.graph, inst, &plan, ctx.allow_following).map_err(|v| {
                    Fail(format!(
                        "internal error: the {planner} plan is invalid: {}",
                        v.describe(&tree.graph)
                    ))
                })?;
            println!(
                "solved: time_steps {} | sum_of_costs {} | makespan {} | sum_of_moves {} | \
                 runtime {runtime_ms:.1} ms",
                m.makespan, m.sum_of_costs, m.makespan, m.sum_of_moves
            );
            Some((plan, m))
        }
        Err(why) => {
            println!("not solved: {why} | runtime {runtime_ms:.1} ms");
            None
        }
    };
    if let Some(out) = out {
        let mut file = TreePlanFile::new(inst, solved.as_ref().map(|(p, m)| (p, *m)), runtime_ms);
        file.instance_file = file_name(ctx.instance_path);
        file.planner = planner.to_string();
        file.seed = ctx.seed;
        file.program = program.map(|p| p.to_string());
        file.allow_following = ctx.allow_following;
        write_atomic(out, &file.to_json())?;
        println!("plan written to {}", out.display());
    }
    Ok(if solved.is_some() { 0 } else { 3 })
}

fn cmd_validate(instance: &Path, plan_path: &Path, no_following: bool) -> Result<u8, Fail> {
    let tree = TreeInstance::load(instance)?;
    let file = TreePlanFile::load(plan_path)?;
    let plan = file.to_plan(&tree.instance, tree.num_nodes(), plan_path)?;
    let allow_following = file.allow_following && !no_following;
    let m =
        validate_tree_plan(&tree.graph, &tree.instance, &plan, allow_following).map_err(|v| {
            Fail(format!(
                "{}: invalid plan: {}",
                plan_path.display(),
                v.describe(&tree.graph)
            ))
        })?;
    let claimed = &file.metrics;
    for (what, claim, real) in [
        ("sum_of_costs", claimed.sum_of_costs, m.sum_of_costs),
        ("makespan", claimed.makespan, m.makespan),
        ("sum_of_moves", claimed.sum_of_moves, m.sum_of_moves),
        ("time_steps", claimed.time_steps, m.makespan),
    ] {
        if let Some(c) = claim.filter(|&c| c != real) {
            return Err(Fail(format!(
                "{}: plan claims {what} {c} but its paths give {real}",
                plan_path.display()
            )));
        }
    }
    println!(
        "mrpp {} | valid: {} robots | time_steps {} | sum_of_costs {} | makespan {} | \
         sum_of_moves {} | following {} | planner {} | seed {}",
        env!("CARGO_PKG_VERSION"),
        tree.num_robots(),
        m.makespan,
        m.sum_of_costs,
        m.makespan,
        m.sum_of_moves,
        if allow_following {
            "allowed"
        } else {
            "forbidden"
        },
        if file.planner.is_empty() {
            "?"
        } else {
            &file.planner
        },
        file.seed
    );
    Ok(0)
}
