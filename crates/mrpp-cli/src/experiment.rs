//! `mrpp experiment ...`: a paper's table as a sweep on the harness (`mrpp-bench`): the flags
//! become the sweep, [`crate::sweeps::drive`] runs it (whole or one `--shard i/N`) and writes its
//! files. No presentation lives here: tables and figures come from `mrpp-bench`.

use std::ops::RangeInclusive;
use std::path::PathBuf;
use std::time::Duration;

use clap::{Subcommand, ValueEnum};

use mrpp_bench::Shard;
use mrpp_bench::execution::{ExecutionConfig, ExecutionSweep, Instance};
use mrpp_bench::lorr::{LorrConfig, LorrSweep};
use mrpp_bench::papers::ga_formation::{FormationConfig, GaFormation};
use mrpp_bench::papers::gp_trees::{GpExperimentConfig, GpTable3, GpTable4, GpTable5};
use mrpp_bench::papers::hbmo_navigation::{HbmoConfig, HbmoNavigation, SweepWorlds};
use mrpp_bench::papers::hstar_instances::Scenario2Map;
use mrpp_bench::papers::hstar_table2::{Table2, Table2Config, table2_methods};

use crate::embedded::{self, data_dir};
use crate::output::{Fail, seconds, time_limit};
use crate::sweeps::{Mode, drive, drive_on};

#[derive(Clone, Copy, ValueEnum)]
pub enum Sc2Map {
    /// `scenery_4rooms_B.txt`: four open rooms (the paper's description; default).
    Open,
    /// `scenery_4rooms.txt`: each room holds the Scenario-1 obstacles.
    Obstacles,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum Fitness {
    Intended,
    Inverted,
}

#[derive(Subcommand)]
pub enum Experiment {
    /// Table II of the H* paper: Enol2023, WHCA*, NSGA-III and H* on Table I's instances.
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp experiment hstar-table2 --runs 10 -o out/hstar-table2\n  mrpp experiment hstar-table2 --runs 10 --shard 1/4 -o out/part-1"
    )]
    HstarTable2(HstarTable2Args),
    /// Table 3 of the GP paper: a program evolved per tree problem vs Push-Swap-Wait.
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp experiment gp-table3 --problems 10 -s 0 -o out/gp-table3\n  mrpp experiment gp-table3 --paper-settings --depths 4-7 --shard 3/100 -o out/part-3"
    )]
    GpTable3(GpTable3Args),
    /// Table 4 of the GP paper: programs trained on |X| problems, tested on new ones, vs PSW.
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp experiment gp-table4 --problems 20 -o out/gp-table4"
    )]
    GpTable4(GpTable4Args),
    /// Table 5 of the GP paper: % solved by GP and PSW with 0.25–1.5 × leaves robots.
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp experiment gp-table5 -o out/gp-table5"
    )]
    GpTable5(GpTable5Args),
    /// The GA formation paper's Fig. 4: sequential and GA against the proven optimum on random
    /// configurations over 7 polygon maps.
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp experiment ga-formation --pairs 10 --robots 1,2,3 -o out/ga-formation"
    )]
    GaFormation(GaFormationArgs),
    /// The HBMO navigation paper's Figs. 5–12: HBMO, DE, PSO and ORCA step by step on seeded
    /// continuous worlds (steps, ATPT, ATPD, AUTD, Mann–Whitney p-values).
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp experiment hbmo --runs 5 -o out/hbmo\n  mrpp experiment hbmo --runs 30 --planners hbmo,orca -p guide=goal -o out/hbmo-goal"
    )]
    Hbmo(HbmoArgs),
    /// League of Robot Runners problems run lifelong: each lifelong planner per scheduler x
    /// guidance x run, and optionally a peer program (the League's start kit) on the same files, in tasks
    /// finished; every run replayed by the lifelong validator.
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp experiment lorr data/robot-runners/lorr2026-maze/maze-example_40.json --steps 500 --schedulers greedy,hungarian -o out/lorr\n  mrpp experiment lorr data/robot-runners/lorr2026-maze/maze-example_40.json --steps 300 --planners lifelong-pibt,lifelong-lns --schedulers hungarian --jobs 1 -o out/lorr-lns\n  mrpp experiment lorr data/robot-runners/lorr2023-warehouse_small/warehouse_small_10.json --steps 200 --runs 3 --jobs 1 -o out/lorr-small\n\nA peer, e.g. the League's start kit built by hand: --peer 'kit=cd /path/Start-Kit && ./build/lifelong -i {problem} -o {out} --simulationTime {steps} --planTimeLimit {step_ms} --preprocessTimeLimit {preprocess_ms}' (placeholders: {problem} {steps} {step_ms} {preprocess_ms} {out}, the League's output JSON it must write). Runs go in parallel on the machine's cores; --jobs 1 runs them one at a time (each run is timed per step)."
    )]
    Lorr(LorrArgs),
    /// One-shot grid plans executed on robots that are late: each instance x planner x delay
    /// probability x executor (the action dependency graph, adg; the League's default, tpg; or
    /// the plan's timing, naive) x
    /// run; collisions, deadlocks, executed makespan and sum of costs over the plan's.
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp experiment execution --runs 20 -o out/execution\n  mrpp experiment execution --instance data/movingai/random-32-32-20.map:data/movingai/random-32-32-20-random-1.scen:100 --planners lacam,lacam*,eecbs --delays 0,0.01,0.05 -o out/execution-random"
    )]
    Execution(ExecutionArgs),
}

#[derive(clap::Args)]
pub struct ExecutionArgs {
    /// A grid instance `MAP:SCEN:AGENTS` (repeatable). Default: three bundled MovingAI
    /// instances (random-32-32-20 with 60 agents, room-32-32-4 with 40, warehouse-10-20-10-2-1
    /// with 100; random-1 scenarios), read from the current folder's data/movingai.
    #[arg(long = "instance")]
    instances: Vec<String>,
    /// Grid planners (comma-separated registry names; lacam* = LaCAM*).
    #[arg(long, value_delimiter = ',', default_value = "lacam,eecbs")]
    planners: Vec<String>,
    /// Bernoulli delay probabilities per robot per tick (comma-separated).
    #[arg(
        long,
        value_delimiter = ',',
        allow_negative_numbers = true,
        default_value = "0,0.005,0.01,0.02,0.05"
    )]
    delays: Vec<f64>,
    /// Shortest delay, ticks.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true, value_parser = crate::output::parse_count)]
    min_delay: usize,
    /// Longest delay, ticks.
    #[arg(long, default_value_t = 10, allow_negative_numbers = true, value_parser = crate::output::parse_count)]
    max_delay: usize,
    /// Executors (comma-separated): adg, tpg (the League's default executor), naive.
    #[arg(long, value_delimiter = ',', default_value = "naive,adg")]
    executors: Vec<String>,
    /// Plans re-timed to be k-robust before execution (comma-separated k; 0 = as planned): no
    /// robot enters a cell another left fewer than k steps earlier (Atzmon et al., JAIR 2020).
    #[arg(long, value_delimiter = ',', default_value = "0,2")]
    robust: Vec<u32>,
    /// Re-planning on drift (comma-separated drift thresholds in ticks; 0 = never): when a robot
    /// is this many ticks behind its plan's timing, the run's planner plans again from where the
    /// robots stand (planning charged no ticks; mrpp_exec::replan).
    #[arg(long, value_delimiter = ',', default_value = "0")]
    replan: Vec<u64>,
    /// Ticks per move (the League's agentCounter).
    #[arg(long, default_value_t = 3, allow_negative_numbers = true, value_parser = crate::output::parse_count)]
    ticks_per_move: usize,
    /// Side of a robot's square, cells, in (0, 1].
    #[arg(long, default_value_t = 0.5, allow_negative_numbers = true)]
    agent_size: f64,
    /// Runs (delay seeds) per point.
    #[arg(long, default_value_t = 20, allow_negative_numbers = true, value_parser = crate::output::parse_count)]
    runs: usize,
    /// Planning time per plan, seconds.
    #[arg(long, default_value_t = 10.0, allow_negative_numbers = true)]
    time_limit: f64,
    #[arg(short = 's', long, default_value_t = 0, allow_negative_numbers = true, value_parser = crate::output::parse_seed)]
    seed: u64,
    /// Output directory (results.csv, execution.md, execution.svg, records.csv, manifest.json).
    #[arg(short = 'o', long, default_value = "out/execution")]
    out: PathBuf,
    /// Run only shard i of N (`i/N`); `mrpp bench merge` joins the parts.
    #[arg(long)]
    shard: Option<Shard>,
    /// Runs at a time (default: one per core).
    #[arg(long, allow_negative_numbers = true, value_parser = crate::output::parse_count)]
    jobs: Option<usize>,
}

#[derive(clap::Args)]
pub struct LorrArgs {
    /// League of Robot Runners problem JSON files (any start-kit layout).
    #[arg(required = true)]
    problems: Vec<PathBuf>,
    /// Horizon in steps.
    #[arg(long, default_value_t = 1000, allow_negative_numbers = true, value_parser = crate::output::parse_count)]
    steps: usize,
    /// Run in ticks under the League's 2026 execution model for N ticks instead of --steps
    /// (each problem's agentCounter, agentSize and delayConfig; a peer's {steps} is N).
    #[arg(long, allow_negative_numbers = true, value_parser = crate::output::parse_count)]
    ticks: Option<usize>,
    /// With --ticks: tpg (the League's default executor) or naive.
    #[arg(long, default_value = "tpg", requires = "ticks")]
    executor: String,
    /// With --ticks: ticks between planner calls.
    #[arg(long, default_value_t = 10, allow_negative_numbers = true, value_parser = crate::output::parse_count, requires = "ticks")]
    plan_every: usize,
    /// With --ticks: delays for mrpp's runs instead of each problem's delayConfig, e.g.
    /// `bernoulli:p=0.01,min=1,max=4` (a peer reads the problem file).
    #[arg(long, requires = "ticks")]
    delays: Option<String>,
    /// With --ticks: delay probabilities to sweep (comma-separated, each in [0, 1]): every
    /// problem runs once per value, its delays (--delays, else its delayConfig) with pDelay
    /// replaced; a peer reads a copy of the problem file that says the same. Adds delays.svg.
    #[arg(
        long,
        value_delimiter = ',',
        allow_negative_numbers = true,
        requires = "ticks"
    )]
    delay_probabilities: Vec<f64>,
    /// With --ticks: actions of slack to sweep (comma-separated, 0 to 1000): every planner
    /// configuration runs once per value, each planned step filtered so that no robot enters a
    /// cell another left fewer than K actions earlier (k-robust, Atzmon et al., JAIR 2020);
    /// shown as PLANNER+K-robust. Default: 0 only (plans as made).
    #[arg(
        long,
        value_delimiter = ',',
        allow_negative_numbers = true,
        requires = "ticks"
    )]
    k_robust: Vec<i64>,
    /// Planning time per step, in seconds.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    step_time_limit: f64,
    /// Time before step 0, in seconds.
    #[arg(long, default_value_t = 30.0, allow_negative_numbers = true)]
    preprocess_time_limit: f64,
    /// MAPF_T (orientation, the League's) or MAPF.
    #[arg(long, default_value = "MAPF_T")]
    action_model: String,
    /// Lifelong planners to run (comma-separated; `mrpp planners --family lifelong`).
    #[arg(long, value_delimiter = ',', default_value = "lifelong-pibt")]
    planners: Vec<String>,
    /// The planners' schedulers to run (comma-separated).
    #[arg(long, value_delimiter = ',', default_value = "greedy,hungarian")]
    schedulers: Vec<String>,
    /// The planners' guidance values to run (comma-separated).
    #[arg(long, value_delimiter = ',', default_value = "auto")]
    guidance: Vec<String>,
    /// Runs (seeds) per configuration.
    #[arg(allow_negative_numbers = true, value_parser = crate::output::parse_count, long, default_value_t = 1)]
    runs: usize,
    #[arg(short = 's', long, default_value_t = 0, allow_negative_numbers = true, value_parser = crate::output::parse_seed)]
    seed: u64,
    /// A peer program, `name=command template` (see the placeholders below), run once per problem.
    #[arg(long)]
    peer: Option<mrpp_bench::sweep::PeerSpec>,
    /// Output directory (results.csv, lorr.md, throughput.svg, records.csv, manifest.json).
    #[arg(short = 'o', long, default_value = "out/lorr")]
    out: PathBuf,
    /// Run only shard i of N (`i/N`); `mrpp bench merge` joins the parts.
    #[arg(long)]
    shard: Option<Shard>,
    /// Runs at a time (default: one per core); `--jobs 1` runs them one at a time, so each
    /// run's time per step is its own.
    #[arg(long, allow_negative_numbers = true, value_parser = crate::output::parse_count)]
    jobs: Option<usize>,
}

#[derive(clap::Args)]
pub struct HbmoArgs {
    /// Runs per (world, method); the paper: 5 (use 30 for the significance tests).
    #[arg(allow_negative_numbers = true, value_parser = crate::output::parse_count, long, default_value_t = 5)]
    runs: usize,
    #[arg(short = 's', long, default_value_t = 0, allow_negative_numbers = true, value_parser = crate::output::parse_seed)]
    seed: u64,
    /// Methods (comma-separated registry names).
    #[arg(long, value_delimiter = ',', default_value = "hbmo,de,pso,orca")]
    planners: Vec<String>,
    /// A parameter for every method that has it, e.g. `-p guide=goal` or `-p preset=paper`
    /// (an error if none has it), or for one method, e.g. `-p hbmo:flights=72` (repeatable).
    #[arg(short = 'p', long = "param", value_name = "KEY=VALUE")]
    params: Vec<String>,
    /// Wall-clock limit per run, in seconds.
    #[arg(
        short = 't',
        long,
        default_value_t = 60.0,
        allow_negative_numbers = true
    )]
    time_limit: f64,
    /// The sweeps' worlds: `fresh`, one generated world per value; `fixed`, one world of 10
    /// robots and 10 obstacles whose first robots and obstacles every value takes, so obstacles
    /// are added to the same world (the paper).
    #[arg(long, default_value = "fresh", value_parser = ["fresh", "fixed"])]
    sweep_worlds: String,
    /// The folder of six-robots-four-obstacles.json (default: the copy embedded in mrpp, the
    /// repository's data/continuous).
    #[arg(long)]
    data: Option<PathBuf>,
    #[arg(short = 'o', long, default_value = "out/hbmo")]
    out: PathBuf,
    /// Run only shard i of N (`i/N`); `mrpp bench merge` joins the parts.
    #[arg(long)]
    shard: Option<Shard>,
}

#[derive(clap::Args)]
pub struct GaFormationArgs {
    /// Start/goal pairs per map (default 10; --paper-settings: 95, about 2000 configurations).
    #[arg(allow_negative_numbers = true, value_parser = crate::output::parse_count, long)]
    pairs: Option<usize>,
    /// Formation sizes R (comma-separated).
    #[arg(long, value_delimiter = ',', default_value = "1,2,3")]
    robots: Vec<usize>,
    #[arg(short = 's', long, default_value_t = 0, allow_negative_numbers = true, value_parser = crate::output::parse_seed)]
    seed: u64,
    /// The paper's scale: 95 pairs per map x 7 maps x R = 1..3.
    #[arg(long)]
    paper_settings: bool,
    /// The corridor cost model (the paper gives none; mrpp_formation::cost): lanes = every
    /// extra wave of robots slows the group by --kappa of the corridor's length; waves = waves
    /// follow each other one robot's spacing apart; hard = a corridor's capacity is a wall.
    #[arg(long, value_parser = ["lanes", "waves", "hard"], default_value = "lanes")]
    cost: String,
    /// With --cost lanes: the share of a corridor's length each extra wave costs, in [0, 10].
    #[arg(long, default_value_t = 0.5, allow_negative_numbers = true)]
    kappa: f64,
    /// The GA's initial population: sequential = the sequential plan and its variants (the
    /// paper's); random = every robot on its own shortest path under randomly scaled edge lengths (the
    /// random start the paper says needs more generations).
    #[arg(long, value_parser = ["sequential", "random"], default_value = "sequential")]
    ga_initial: String,
    /// Wall-clock limit of the exact planner per configuration, in seconds.
    #[arg(long, default_value_t = 30.0, allow_negative_numbers = true)]
    exact_time_limit: f64,
    /// The folder of the polygon maps (default: the copy embedded in mrpp, the repository's
    /// data/polygon-maps: the three public maps and the gen-* stand-ins).
    #[arg(long)]
    data: Option<PathBuf>,
    #[arg(short = 'o', long, default_value = "out/ga-formation")]
    out: PathBuf,
    /// Also write every plan as plans/<map>-<pair>-r<R>-<planner>.json (for
    /// tools/check/formation.py, `mrpp validate` and `mrpp render`).
    #[arg(long)]
    save_plans: bool,
    /// Run only shard i of N (`i/N`); `mrpp bench merge` joins the parts.
    #[arg(long)]
    shard: Option<Shard>,
}

#[derive(clap::Args)]
pub struct HstarTable2Args {
    /// Runs per (instance, method); the paper uses 10.
    #[arg(allow_negative_numbers = true, value_parser = crate::output::parse_count, long, default_value_t = 10)]
    runs: usize,
    #[arg(short = 's', long, default_value_t = 0, allow_negative_numbers = true, value_parser = crate::output::parse_seed)]
    seed: u64,
    /// Output directory (results.csv, table2.md, fig5.svg, plans/).
    #[arg(short = 'o', long, default_value = "out/hstar-table2")]
    out: PathBuf,
    /// Also write every solved plan as plans/<scenario>-<robots>-<planner>-<run>.json.
    #[arg(long)]
    save_plans: bool,
    /// Directory holding scenario1/ .. scenario3/ and table2-paper.csv (default: the copy
    /// embedded in mrpp, the repository's data/hstar-paper).
    #[arg(long)]
    data: Option<PathBuf>,
    #[arg(long, value_enum, default_value_t = Sc2Map::Open)]
    sc2_map: Sc2Map,
    /// Wall-clock limit of one run, in seconds.
    #[arg(
        short = 't',
        long,
        default_value_t = 30.0,
        allow_negative_numbers = true
    )]
    time_limit: f64,
    /// Only these planners (comma-separated: coevolution, whca, nsga3, hstar, hstar-paper = H* with the paper's steps only).
    #[arg(long, value_delimiter = ',')]
    planners: Option<Vec<String>>,
    /// Enol2023's collision count: intended, or inverted as in the authors' code.
    #[arg(long, value_enum, default_value_t = Fitness::Intended)]
    coevolution_fitness: Fitness,
    /// Run only shard i of N (`i/N`); `mrpp bench merge` joins the parts.
    #[arg(long)]
    shard: Option<Shard>,
}

/// What the three experiments share.
#[derive(clap::Args)]
pub struct GpCommon {
    /// Problems: Table 3 — problems (default 100, paper 1000); Table 4 — test problems per trial
    /// (default 50, paper 100); Table 5 — problems per leaf multiplier (default 40, paper 200).
    #[arg(allow_negative_numbers = true, value_parser = crate::output::parse_count, long)]
    problems: Option<usize>,
    #[arg(short = 's', long, default_value_t = 0, allow_negative_numbers = true, value_parser = crate::output::parse_seed)]
    seed: u64,
    /// GP parameters; `--paper-settings` also sets the paper's problem counts (days of CPU time
    /// on 2 cores).
    #[command(flatten)]
    gp: crate::tree_family::GpParamArgs,
    /// Wall-clock bound of one evolution in seconds (ψ* so far is kept; makes results depend on
    /// the machine, so it is off by default).
    #[arg(long, allow_negative_numbers = true)]
    evolve_time_limit: Option<f64>,
    /// Wall-clock bound, in seconds, of one PSW run or one run of a program on a test problem.
    #[arg(long, default_value_t = 60.0, allow_negative_numbers = true)]
    run_time_limit: f64,
    /// Depth budgets of the generated trees, `MIN-MAX` (default 3-4, trees of the paper's scale;
    /// with --paper-settings the paper's 4-10, and 4-9 for Table 4's test problems).
    #[arg(long, value_parser = parse_depths)]
    depths: Option<RangeInclusive<u32>>,
    /// Where problems come from: paper = the paper's text (Algorithm 2 with b = 4 on a depth
    /// budget, |R| = #leaves - 1); authors = the authors' public code (a node budget, 1-3
    /// children a node, |R| uniform in 2..#leaves - 1; the paper's problem sizes, about 15
    /// nodes and 4 robots), where --depths are node budgets (default 4-10, tests 4-9).
    #[arg(long, value_parser = ["paper", "authors"], default_value = "paper")]
    distribution: String,
    /// Output directory (default out/gp-tableN).
    #[arg(short = 'o', long)]
    out: Option<PathBuf>,
    /// Run only shard i of N (`i/N`); `mrpp bench merge` joins the parts.
    #[arg(long)]
    shard: Option<Shard>,
}

fn parse_depths(s: &str) -> Result<RangeInclusive<u32>, String> {
    let bad = || format!("expected MIN-MAX with 1 <= MIN <= MAX <= 12, got `{s}`");
    let (a, b) = s.split_once('-').ok_or_else(bad)?;
    let (a, b): (u32, u32) = (
        a.trim().parse().map_err(|_| bad())?,
        b.trim().parse().map_err(|_| bad())?,
    );
    if (1..=b).contains(&a) && b <= 12 {
        Ok(a..=b)
    } else {
        Err(bad())
    }
}

#[derive(clap::Args)]
pub struct GpTable3Args {
    #[command(flatten)]
    common: GpCommon,
}

#[derive(clap::Args)]
pub struct GpTable4Args {
    #[command(flatten)]
    common: GpCommon,
    /// Training-set sizes |X|.
    #[arg(long, value_delimiter = ',', default_value = "5,10,20")]
    train_sizes: Vec<usize>,
    /// Trials per |X| (default 2, paper 10).
    #[arg(allow_negative_numbers = true, value_parser = crate::output::parse_count, long)]
    trials: Option<usize>,
}

#[derive(clap::Args)]
pub struct GpTable5Args {
    #[command(flatten)]
    common: GpCommon,
    /// Leaf multipliers l_m: ⌊l_m · #leaves⌋ robots.
    #[arg(long, value_delimiter = ',', default_value = "0.25,0.5,1.0,1.5")]
    multipliers: Vec<f64>,
}

/// Runs (or, with `merge`, joins the parts of) an experiment.
pub fn run(cmd: Experiment, merge: Option<Mode>) -> Result<u8, Fail> {
    match cmd {
        Experiment::HstarTable2(a) => {
            let mode = merge.unwrap_or(Mode::run(a.shard, a.out.clone()));
            drive(&hstar_table2(&a)?, &mode, a.seed, "runs")
        }
        Experiment::GpTable3(a) => {
            let (cfg, n) = a.common.config(100, 1000)?;
            let mode = merge.unwrap_or(Mode::run(a.common.shard, a.common.out("gp-table3")));
            drive(&GpTable3::new(cfg, n)?, &mode, a.common.seed, "problems")
        }
        Experiment::GpTable4(a) => {
            let sweep = gp_table4(&a)?;
            let mode = merge.unwrap_or(Mode::run(a.common.shard, a.common.out("gp-table4")));
            drive(&sweep, &mode, a.common.seed, "trainings")
        }
        Experiment::GpTable5(a) => {
            let (cfg, n) = a.common.config(40, 200)?;
            if a.multipliers.is_empty() {
                return Err(Fail("--multipliers needs at least one value".into()));
            }
            let mode = merge.unwrap_or(Mode::run(a.common.shard, a.common.out("gp-table5")));
            drive(
                &GpTable5::new(cfg, a.multipliers.clone(), n)?,
                &mode,
                a.common.seed,
                "problems",
            )
        }
        Experiment::GaFormation(a) => ga_formation(&a, merge),
        Experiment::Execution(a) => {
            let instances = if a.instances.is_empty() {
                [
                    ("random-32-32-20", 60),
                    ("room-32-32-4", 40),
                    ("warehouse-10-20-10-2-1", 100),
                ]
                .into_iter()
                .map(|(m, n)| Instance {
                    map: PathBuf::from(format!("data/movingai/{m}.map")),
                    scen: PathBuf::from(format!("data/movingai/{m}-random-1.scen")),
                    agents: n,
                })
                .collect()
            } else {
                a.instances
                    .iter()
                    .map(|spec| {
                        let parts: Vec<&str> = spec.rsplitn(3, ':').collect();
                        match parts.as_slice() {
                            [n, scen, map] => n
                                .parse::<usize>()
                                .ok()
                                .filter(|&n| n > 0)
                                .map(|agents| Instance {
                                    map: PathBuf::from(map),
                                    scen: PathBuf::from(scen),
                                    agents,
                                })
                                .ok_or_else(|| {
                                    Fail(format!(
                                        "--instance {spec}: AGENTS must be a whole number above 0"
                                    ))
                                }),
                            _ => Err(Fail(format!("--instance {spec}: expected MAP:SCEN:AGENTS"))),
                        }
                    })
                    .collect::<Result<Vec<_>, Fail>>()?
            };
            let executors = a
                .executors
                .iter()
                .map(|e| {
                    mrpp_exec::ExecutorKind::parse(e)
                        .ok_or_else(|| Fail(format!("--executors: {e} is not adg, tpg or naive")))
                })
                .collect::<Result<Vec<_>, Fail>>()?;
            let ticks = |v: usize, flag: &str| {
                u32::try_from(v)
                    .ok()
                    .filter(|t| (1..=1000).contains(t))
                    .ok_or_else(|| Fail(format!("--{flag} {v}: expected 1 to 1000 ticks")))
            };
            if !(a.agent_size > 0.0 && a.agent_size <= 1.0) {
                return Err(Fail(format!(
                    "--agent-size {}: expected more than 0 and at most 1 cell",
                    a.agent_size
                )));
            }
            let cfg = ExecutionConfig {
                seed: a.seed,
                instances,
                planners: a.planners.clone(),
                delays: a.delays.clone(),
                min_delay: ticks(a.min_delay, "min-delay")?,
                max_delay: ticks(a.max_delay, "max-delay")?,
                executors,
                robust: a.robust.clone(),
                replan: a.replan.clone(),
                ticks_per_move: ticks(a.ticks_per_move, "ticks-per-move")?,
                agent_size: a.agent_size,
                runs: a.runs,
                time_limit: seconds("time-limit", a.time_limit)?,
            };
            let mode = merge.unwrap_or(Mode::run(a.shard, a.out.clone()));
            drive_on(&ExecutionSweep::new(cfg)?, &mode, a.seed, "runs", a.jobs)
        }
        Experiment::Hbmo(a) => {
            let cfg = HbmoConfig {
                seed: a.seed,
                runs: a.runs,
                planners: a.planners.clone(),
                params: a
                    .params
                    .iter()
                    .map(|p| mrpp_core::registry::parse_key_value(p))
                    .collect::<Result<_, _>>()?,
                time_limit: seconds("time-limit", a.time_limit)?,
                sweep_worlds: if a.sweep_worlds == "fixed" {
                    SweepWorlds::Fixed
                } else {
                    SweepWorlds::Fresh
                },
            };
            let mode = merge.unwrap_or(Mode::run(a.shard, a.out.clone()));
            let (data, _unpacked) = data_dir(a.data.clone(), &embedded::CONTINUOUS)?;
            let experiment = HbmoNavigation::new(cfg, &data)?;
            drive(&experiment, &mode, a.seed, "runs")
        }
        Experiment::Lorr(a) => {
            let model = mrpp_lifelong::ActionModel::parse(&a.action_model).ok_or_else(|| {
                Fail(format!(
                    "--action-model {}: expected MAPF_T or MAPF",
                    a.action_model
                ))
            })?;
            let (flag, horizon) = match a.ticks {
                Some(t) => ("--ticks", t),
                None => ("--steps", a.steps),
            };
            let steps = u32::try_from(horizon)
                .ok()
                .filter(|&s| (1..=10_000_000).contains(&s))
                .ok_or_else(|| Fail(format!("{flag} {horizon}: expected 1 to 10000000")))?;
            let ticks = match a.ticks {
                None => None,
                Some(_) => Some(mrpp_bench::lorr::TicksConfig {
                    executor: mrpp_lifelong::executor::ExecutorKind::parse(&a.executor)
                        .ok_or_else(|| {
                            Fail(format!("--executor {}: expected tpg or naive", a.executor))
                        })?,
                    plan_every: u32::try_from(a.plan_every)
                        .ok()
                        .filter(|k| (1..=100_000).contains(k))
                        .ok_or_else(|| {
                            Fail(format!(
                                "--plan-every {}: expected 1 to 100000",
                                a.plan_every
                            ))
                        })?,
                    delays: a
                        .delays
                        .as_deref()
                        .map(mrpp_exec::DelayConfig::parse)
                        .transpose()
                        .map_err(Fail)?,
                    delay_probabilities: a.delay_probabilities.clone(),
                    k_robust: a
                        .k_robust
                        .iter()
                        .map(|&k| {
                            u32::try_from(k).ok().filter(|&k| k <= 1000).ok_or_else(|| {
                                Fail(format!("--k-robust {k}: expected 0 to 1000 actions"))
                            })
                        })
                        .collect::<Result<_, _>>()?,
                }),
            };
            let cfg = LorrConfig {
                seed: a.seed,
                problems: a.problems.clone(),
                steps,
                step_time: seconds("step-time-limit", a.step_time_limit)?,
                preprocess_time: seconds("preprocess-time-limit", a.preprocess_time_limit)?,
                model,
                planners: a.planners.clone(),
                schedulers: a.schedulers.clone(),
                guidance: a.guidance.clone(),
                runs: a.runs,
                peer: a.peer.clone(),
                ticks,
            };
            let mode = merge.unwrap_or(Mode::run(a.shard, a.out.clone()));
            drive_on(&LorrSweep::new(cfg)?, &mode, a.seed, "runs", a.jobs)
        }
    }
}

/// The GA formation experiment from its flags.
fn ga_formation(a: &GaFormationArgs, merge: Option<Mode>) -> Result<u8, Fail> {
    let pairs = a.pairs.unwrap_or(if a.paper_settings { 95 } else { 10 });
    if !(1..=10_000).contains(&pairs) {
        return Err(Fail(format!(
            "--pairs must be between 1 and 10000, got {pairs}"
        )));
    }
    if !(0.0..=10.0).contains(&a.kappa) {
        return Err(Fail(format!(
            "--kappa must be between 0 and 10, got {}",
            a.kappa
        )));
    }
    let cost = match a.cost.as_str() {
        "waves" => mrpp_formation::CostModel::Waves,
        "hard" => mrpp_formation::CostModel::Hard,
        _ => mrpp_formation::CostModel::Lanes { kappa: a.kappa },
    };
    let cfg = FormationConfig {
        seed: a.seed,
        pairs,
        robots: a.robots.clone(),
        cost,
        ga: mrpp_formation::ga::Ga {
            random_start: a.ga_initial == "random",
            ..mrpp_formation::ga::Ga::default()
        },
        exact_limit: seconds("exact-time-limit", a.exact_time_limit)?,
        save_plans: a.save_plans,
        ..FormationConfig::default()
    };
    let mode = merge.unwrap_or(Mode::run(a.shard, a.out.clone()));
    let (data, _unpacked) = data_dir(a.data.clone(), &embedded::POLYGON_MAPS)?;
    drive(
        &GaFormation::new(cfg, &data)?,
        &mode,
        a.seed,
        "configurations",
    )
}

/// Table II from its flags.
fn hstar_table2(a: &HstarTable2Args) -> Result<Table2, Fail> {
    if !(1..=1000).contains(&a.runs) {
        return Err(Fail(format!(
            "--runs must be between 1 and 1000, got {}",
            a.runs
        )));
    }
    let limit = time_limit(a.time_limit)?;
    let (data, _unpacked) = data_dir(a.data.clone(), &embedded::HSTAR_PAPER)?;
    if !data.join("scenario1").is_dir() {
        return Err(Fail(format!(
            "{}: no scenario1/ here; pass --data with the directory of the H* paper's files (the repository's data/hstar-paper), or leave --data out to use the copy embedded in mrpp",
            data.display()
        )));
    }
    let mut methods = table2_methods();
    if let Some(keep) = &a.planners {
        if let Some(k) = keep
            .iter()
            .find(|k| !methods.iter().any(|m| m.key == k.as_str()))
        {
            return Err(Fail(format!(
                "--planners: unknown planner `{k}` (known: coevolution, whca, nsga3, hstar, hstar-paper)"
            )));
        }
        methods.retain(|m| keep.iter().any(|k| k == m.key));
    }
    if let Fitness::Inverted = a.coevolution_fitness {
        for m in methods
            .iter_mut()
            .filter(|m| m.planner == mrpp_grid::coevolution::NAME)
        {
            m.params.push(("variant".into(), "inverted".into()));
        }
    }
    let cfg = Table2Config {
        runs: a.runs,
        seed: a.seed,
        scenario2_map: match a.sc2_map {
            Sc2Map::Open => Scenario2Map::OpenRooms,
            Sc2Map::Obstacles => Scenario2Map::ObstacleRooms,
        },
        methods,
        time_limit: limit,
        save_plans: a.save_plans,
    };
    Ok(Table2::new(cfg, &data)?)
}

/// Table 4 from its flags.
fn gp_table4(a: &GpTable4Args) -> Result<GpTable4, Fail> {
    let (cfg, tests) = a.common.config(50, 100)?;
    let trials = a
        .trials
        .unwrap_or(if a.common.gp.paper_settings { 10 } else { 2 });
    if !(1..=1000).contains(&trials) {
        return Err(Fail(format!(
            "--trials must be between 1 and 1000, got {trials}"
        )));
    }
    if a.train_sizes.is_empty() || a.train_sizes.iter().any(|&x| !(1..=1000).contains(&x)) {
        return Err(Fail(format!(
            "--train-sizes must be between 1 and 1000, got {:?}",
            a.train_sizes
        )));
    }
    Ok(GpTable4::new(cfg, a.train_sizes.clone(), trials, tests)?)
}

/// A duration flag in seconds, checked like every time limit ([`seconds`]).
fn positive_seconds(what: &str, s: f64) -> Result<Duration, Fail> {
    seconds(what, s)
}

impl GpCommon {
    /// The configuration and the problem count (`default` / `paper` when not given).
    fn config(&self, default: usize, paper: usize) -> Result<(GpExperimentConfig, usize), Fail> {
        let base = if self.gp.paper_settings {
            GpExperimentConfig::paper()
        } else {
            GpExperimentConfig::scaled_down()
        };
        let params = self.gp.params_over(base.params.clone(), true)?;
        let problems = self.problems.unwrap_or(if self.gp.paper_settings {
            paper
        } else {
            default
        });
        if !(1..=100_000).contains(&problems) {
            return Err(Fail(format!(
                "--problems must be between 1 and 100000, got {problems}"
            )));
        }
        let distribution = mrpp_bench::papers::gp_trees::Distribution::parse(&self.distribution)
            .ok_or_else(|| {
                Fail(format!(
                    "--distribution {}: expected paper or authors",
                    self.distribution
                ))
            })?;
        // The authors' node budgets are 4-10 at every scale (their problems are small).
        let (train, test) = match distribution {
            mrpp_bench::papers::gp_trees::Distribution::Authors => (4..=10, 4..=9),
            mrpp_bench::papers::gp_trees::Distribution::Paper => {
                (base.train_depths.clone(), base.test_depths.clone())
            }
        };
        let cfg = GpExperimentConfig {
            train_depths: self.depths.clone().unwrap_or(train),
            test_depths: self.depths.clone().unwrap_or(test),
            distribution,
            seed: self.seed,
            params,
            run_time_limit: positive_seconds("run-time-limit", self.run_time_limit)?,
            evolve_time_limit: self
                .evolve_time_limit
                .map(|s| positive_seconds("evolve-time-limit", s))
                .transpose()?,
            ..base
        };
        Ok((cfg, problems))
    }

    /// The output folder (default `out/<name>`).
    fn out(&self, name: &str) -> PathBuf {
        self.out
            .clone()
            .unwrap_or_else(|| PathBuf::from(format!("out/{name}")))
    }
}
