//! `mrpp`: the command line of the mrpp toolkit. A thin layer: parse arguments, pick the family
//! ([`family::FAMILIES`], the one family table), call the library, write files atomically, print
//! one summary, and map outcomes to exit codes: 0 = solved / valid, 1 = bad input, usage or an
//! invalid plan (a bug), 3 = not solved.
//!
//! The crate is a library too: [`main`] is the whole command line (the `mrpp` binary calls it),
//! and [`api`] gives bindings (the Python package `crates/mrpp-py`) the same family table,
//! loaders, planners, validator and viewer without printing.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

pub mod api;
mod bench;
mod continuous_family;
mod data;
mod embedded;
mod execute_cmd;
mod experiment;
mod family;
mod formation_family;
mod gen_cmd;
mod grid_family;
mod lifelong_family;
mod output;
mod picture;
mod progress;
#[cfg(feature = "raster")]
mod raster;
mod sweeps;
#[cfg(test)]
mod toy_family;
mod tree_family;
mod verbs;
mod view;

use family::{Format, Inputs, SolveRequest};
use output::Fail;

#[derive(Parser)]
#[command(
    name = "mrpp",
    version,
    about = "Multi-robot path planning: plan, validate and draw"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Print only errors (and what `planners`, `info` and `completions` exist to print); the
    /// exit code still tells the outcome.
    #[arg(short, long, global = true, conflicts_with = "verbose")]
    quiet: bool,
    /// Print more: the resolved planner parameters, load time and the planner's full notes
    /// (`solve`), the claims checked (`validate`), one line per finished job (sweeps).
    #[arg(short, long, global = true, action = clap::ArgAction::Count)]
    verbose: u8,
    /// Heap memory every planner may use, in MB (default: three quarters of the machine's
    /// memory). A planner that reaches it stops as at its time limit: exit 3, "memory limit".
    #[arg(long, global = true, value_name = "MB", allow_negative_numbers = true, value_parser = output::parse_count)]
    memory_limit: Option<usize>,
    /// How a planner's progress (and `data get`'s downloads, unpacking, checks and writes) is
    /// shown on stderr: auto (a spinner or bar on a terminal), plain (a line every half second,
    /// for logs), none.
    #[arg(long, global = true, value_enum, default_value = "auto")]
    progress: progress::Mode,
}

#[derive(Subcommand)]
enum Command {
    /// Plan paths for a problem of any family (the planner names the family; see `mrpp planners`).
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp solve -m data/movingai/random-32-32-20.map -i data/movingai/random-32-32-20-random-1.scen -N 100 -P lacam -o plan.json\n  mrpp solve --lorr data/robot-runners/lorr2026-maze/maze-example_40.json -P lacam -p anytime=true -t 10 -o plan.json\n  mrpp solve --world data/continuous/six-robots-four-obstacles.json -P hbmo -s 1 -o plan.json"
    )]
    Solve(SolveArgs),
    /// Check a plan (the mrpp plan envelope, or LaCAM text on grids): exit 0 when valid, 1 naming
    /// the first violation.
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp validate -m data/movingai/random-32-32-20.map --plan plan.json\n  mrpp validate -m data/movingai/random-32-32-20.map -i data/movingai/random-32-32-20-random-1.scen --plan plan.txt"
    )]
    Validate {
        #[command(flatten)]
        inputs: Inputs,
        #[arg(long)]
        plan: PathBuf,
    },
    /// List the planners of every family (or of one) with their parameters.
    #[command(after_help = "Examples (from the repository's root):\n  mrpp planners --family grid")]
    Planners {
        /// Only this family (grid, trees, formation, continuous, lifelong).
        #[arg(long, value_parser = output::Offer(output::family_names))]
        family: Option<String>,
    },
    /// Describe an instance: map size, free cells, corridor nodes, and lower bounds on any valid
    /// plan's sum of costs and makespan (each agent's shortest distance, ignoring the others).
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp info -m data/movingai/random-32-32-20.map -i data/movingai/random-32-32-20-random-1.scen -N 100\n  mrpp info --world data/continuous/six-robots-four-obstacles.json"
    )]
    Info {
        #[command(flatten)]
        inputs: Inputs,
    },
    /// Reproduce a paper's table (see docs/reproduction/); `--shard i/N` runs one part.
    #[command(subcommand)]
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp experiment hstar-table2 --runs 10 -o out/hstar-table2\n  mrpp experiment hbmo --runs 5 -o out/hbmo"
    )]
    Experiment(experiment::Experiment),
    /// Benchmark sweeps: `bench run` (TOML config or flags, `--shard i/N`), `bench merge`.
    #[command(subcommand)]
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp bench run --config bench/configs/example.toml -o out/bench"
    )]
    Bench(bench::Bench),
    /// Write a grid map (MovingAI or the H* paper's text format) as a MovingAI `.map`, and with
    /// --scen its agents as a MovingAI `.scen`, so any MovingAI tool (e.g. the MAPF visualizer)
    /// reads them; or, with --plan, a grid plan in another format (--to): the plan envelope,
    /// LaCAM text, a MAPF Tracker result CSV or PlanViz's LoRR JSON (the input's format is
    /// detected from its content; it must validate against --map/--scen before anything is
    /// written).
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp convert -m data/hstar-paper/scenario3/scenery_warehouse.txt -i data/hstar-paper/scenario3/30warehouse --out-map warehouse.map --out-scen warehouse-30.scen\n  mrpp convert -m data/movingai/random-32-32-20.map -i data/movingai/random-32-32-20-random-1.scen -N 100 --plan plan.json --to tracker --out plan.csv\n  mrpp convert -m data/movingai/random-32-32-20.map -i data/movingai/random-32-32-20-random-1.scen --plan plan.csv --to planviz --out planviz.json"
    )]
    Convert {
        #[arg(short = 'm', long)]
        map: PathBuf,
        /// Agents to write as `.scen` (MovingAI `.scen` or the H* paper's robot file); with
        /// --plan, the scenario the plan solves.
        #[arg(short = 'i', long)]
        scen: Option<PathBuf>,
        /// Only the first N agents (with --plan: the plan's agent count, which picks a MAPF
        /// Tracker CSV's row).
        #[arg(short = 'N', long, allow_negative_numbers = true, value_parser = crate::output::parse_count)]
        agents: Option<usize>,
        #[arg(long, required_unless_present = "plan", conflicts_with = "plan")]
        out_map: Option<PathBuf>,
        /// Where the `.scen` goes (needs --scen).
        #[arg(long, conflicts_with = "plan")]
        out_scen: Option<PathBuf>,
        /// A grid plan to convert: plan envelope, LaCAM text, MAPF Tracker CSV or PlanViz JSON
        /// (detected from the content).
        #[arg(long, requires_all = ["to", "out", "scen"])]
        plan: Option<PathBuf>,
        /// The format to write the plan in.
        #[arg(long, value_enum, requires = "plan")]
        to: Option<gen_cmd::PlanFormat>,
        /// Where the converted plan goes (`-` for stdout; never one of the inputs).
        #[arg(short = 'o', long, requires = "plan")]
        out: Option<PathBuf>,
    },
    /// Print a shell completion script (bash, zsh, fish, elvish, powershell).
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp completions bash > ~/.local/share/bash-completion/completions/mrpp\n  mrpp completions zsh > ~/.zfunc/_mrpp"
    )]
    Completions {
        /// bash, zsh, fish, elvish or powershell.
        shell: clap_complete::Shell,
    },
    /// Benchmark data: `data get movingai` downloads (or unpacks with --from) the MovingAI MAPF
    /// benchmark and checks every file against the checksums in the repository.
    #[command(subcommand)]
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp data get movingai --into data/movingai"
    )]
    Data(data::Data),
    /// Problem files from seeds: random grid maps and scenarios, polygon worlds, formation files.
    #[command(subcommand)]
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp gen scen -m data/movingai/random-32-32-20.map -N 100 -s 1 -o random-100.scen"
    )]
    Gen(gen_cmd::Gen),
    /// Single-lane tree problems: generate, solve (PSW or GP), run a GP program, validate.
    #[command(subcommand)]
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp trees solve --instance data/trees/example.json -P psw -o plan.json"
    )]
    Trees(tree_family::Trees),
    /// Watch a plan: one self-contained HTML page (play, step, scrub, zoom), written to --out
    /// (default: the plan's name with .html) or served on 127.0.0.1 with --serve.
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp view -m data/movingai/random-32-32-20.map --plan plan.json -o plan.html\n  mrpp view -m data/movingai/random-32-32-20.map --plan plan.json --serve --port 8000"
    )]
    View {
        #[command(flatten)]
        inputs: Inputs,
        #[arg(long)]
        plan: PathBuf,
        #[arg(short = 'o', long)]
        out: Option<PathBuf>,
        /// Serve the page on 127.0.0.1 (the address is printed) until interrupted.
        #[arg(long)]
        serve: bool,
        /// Port for --serve (0: any free port).
        #[arg(long, default_value_t = 0)]
        port: u16,
    },
    /// Execute a grid plan tick by tick on robots that are late: seeded delays (the League of
    /// Robot Runners' models), moves of --ticks-per-move ticks, and an executor: the action
    /// dependency graph (adg: the plan's order of passage at every cell is kept), the League's
    /// default executor (tpg: per-cell queues; it stops at a ring of the plan) or naive (the
    /// plan's timing; it may collide). Writes the executed record; exit 3 if it collided.
    #[command(
        after_help = "Examples (from the repository's root), after mrpp solve -m data/movingai/random-32-32-20.map -i data/movingai/random-32-32-20-random-1.scen -N 100 -P lacam -o plan.json:\n  mrpp execute -m data/movingai/random-32-32-20.map --plan plan.json --delays bernoulli:p=0.01,min=1,max=4 --executor adg --ticks-per-move 3 -s 1 -o trace.json\n  mrpp execute -m data/movingai/random-32-32-20.map --plan plan.json --delays poisson:p=0.002,min=5,max=12,duration=gaussian --executor naive --ticks-per-move 3 -o naive.json"
    )]
    Execute(Box<execute_cmd::ExecuteArgs>),
    /// Draw a plan (map, starts, goals, paths): an SVG picture, a PNG, or an animated GIF, by
    /// --out's extension.
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp render -m data/movingai/random-32-32-20.map --plan plan.json -o plan.png\n  mrpp render -m data/movingai/random-32-32-20.map --plan plan.json -o plan.gif"
    )]
    Render {
        #[command(flatten)]
        inputs: Inputs,
        #[arg(long)]
        plan: PathBuf,
        /// The picture, by extension: .svg, .png, or .gif (animated, one frame per step).
        #[arg(short = 'o', long)]
        out: PathBuf,
        /// An animated GIF (the same as an --out ending in .gif, which it requires).
        #[arg(long)]
        gif: bool,
    },
}

#[derive(clap::Args)]
struct SolveArgs {
    #[command(flatten)]
    inputs: Inputs,
    /// Planner (`mrpp planners` describes each, with its parameters).
    #[arg(short = 'P', long, value_parser = output::Offer(output::planner_names))]
    planner: String,
    /// Planner parameter `key=value`, repeatable (unknown keys are refused with the valid ones).
    #[arg(short = 'p', long = "param", value_name = "KEY=VALUE")]
    params: Vec<String>,
    /// Seed of every random choice.
    #[arg(short = 's', long, default_value_t = 0, allow_negative_numbers = true, value_parser = crate::output::parse_seed)]
    seed: u64,
    /// Wall-clock limit in seconds.
    #[arg(
        short = 't',
        long,
        default_value_t = 60.0,
        allow_negative_numbers = true
    )]
    time_limit: f64,
    /// Same as `-p window=W` (WHCA*).
    #[arg(long)]
    window: Option<u32>,
    /// Same as `-p variant=V` (H*: repaired or paper; coevolution: intended or inverted).
    #[arg(long)]
    variant: Option<String>,
    /// Write the plan here (also written when not solved, with "solved": false).
    #[arg(short = 'o', long)]
    out: Option<PathBuf>,
    /// Write a program the planner made (GP) here.
    #[arg(long)]
    save_program: Option<PathBuf>,
    /// Plan file format (default: from --out's extension: .json the plan envelope, .txt or
    /// .lacam LaCAM text; JSON for stdout `-`).
    #[arg(long, value_enum)]
    format: Option<Format>,
}

impl SolveArgs {
    /// The request, with `--window`/`--variant` turned into parameters (before `-p`, which wins).
    fn request(self) -> Result<SolveRequest, Fail> {
        let mut params = Vec::new();
        if let Some(w) = self.window {
            params.push(("window".to_string(), w.to_string()));
        }
        if let Some(v) = self.variant {
            params.push(("variant".to_string(), v));
        }
        for p in &self.params {
            let (k, v) = mrpp_core::registry::parse_key_value(p)?;
            if params.iter().any(|(key, _)| *key == k) {
                return Err(Fail(format!(
                    "`{k}` is given twice (a flag and -p, or two -p)"
                )));
            }
            params.push((k, v));
        }
        let format = match self.format {
            Some(f) => f,
            None => output::format_of(self.out.as_deref())?,
        };
        Ok(SolveRequest {
            inputs: self.inputs,
            planner: self.planner,
            params,
            seed: self.seed,
            time_limit: self.time_limit,
            out: self.out,
            format,
            save_program: self.save_program,
            command: "solve",
        })
    }
}

/// The `mrpp` command line: parses `std::env::args`, runs the command, returns its exit code.
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let code = if e.use_stderr() { 1 } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    output::set_verbosity(cli.quiet, cli.verbose);
    progress::set_mode(cli.progress);
    mrpp_core::memory::set_limit(match cli.memory_limit {
        Some(mb) => Some(mb.saturating_mul(1 << 20)),
        None => mrpp_core::memory::default_limit(),
    });
    // Ctrl-C: the first asks every planner to stop as at its deadline (anytime planners write
    // their best plan, sweeps keep their finished jobs); a second quits at once.
    let _ = ctrlc::set_handler(|| {
        if mrpp_core::stop_requested() {
            std::process::exit(130);
        }
        mrpp_core::request_stop();
        eprintln!(
            "\nmrpp: interrupted: stopping and keeping what is done (Ctrl-C again quits at once)"
        );
    });
    match run(cli.command) {
        Ok(code) => ExitCode::from(code),
        Err(Fail(msg)) => {
            eprintln!("mrpp: error: {msg}");
            ExitCode::from(if mrpp_core::stop_requested() { 130 } else { 1 })
        }
    }
}

fn run(command: Command) -> Result<u8, Fail> {
    match command {
        Command::Solve(args) => verbs::solve(&args.request()?),
        Command::Validate { inputs, plan } => verbs::validate(&inputs, &plan),
        Command::Execute(args) => execute_cmd::execute(&args),
        Command::Planners { family } => family::list_planners(family.as_deref()),
        Command::Info { inputs } => verbs::info(&inputs),
        Command::Render {
            inputs,
            plan,
            out,
            gif,
        } => verbs::render(&inputs, &plan, &out, gif),
        Command::View {
            inputs,
            plan,
            out,
            serve,
            port,
        } => view::view(&inputs, &plan, out, serve, port),
        Command::Experiment(e) => experiment::run(e, None),
        Command::Bench(bench::Bench::Run(a)) => bench::run(*a, None),
        Command::Bench(bench::Bench::Merge { out, parts }) => merge(out, parts),
        Command::Trees(t) => tree_family::run(t),
        Command::Gen(g) => gen_cmd::run(g),
        Command::Data(data::Data::Get(a)) => data::run(a),
        Command::Completions { shell } => {
            use clap::CommandFactory as _;
            use std::io::Write as _;
            // Written whole from a buffer: a closed pipe (`| head`) ends the output, not in a panic.
            let mut script = Vec::new();
            clap_complete::generate(shell, &mut Cli::command(), "mrpp", &mut script);
            let _ = std::io::stdout().write_all(&script);
            Ok(0)
        }
        Command::Convert {
            map,
            scen,
            agents,
            out_map,
            out_scen,
            plan,
            to,
            out,
        } => match (plan, to, out, out_map) {
            (Some(plan), Some(to), Some(out), _) => {
                gen_cmd::convert_plan(&map, scen.as_deref(), agents, &plan, to, &out)
            }
            (_, _, _, Some(out_map)) => {
                gen_cmd::convert(&map, scen.as_deref(), agents, &out_map, out_scen.as_deref())
            }
            _ => Err(Fail(
                "convert: give --out-map (a map and agents) or --plan, --to and --out (a plan)"
                    .into(),
            )),
        },
    }
}

/// `mrpp bench merge`: rebuilds the sweep from the command its parts recorded, then joins them.
fn merge(out: PathBuf, parts: Vec<PathBuf>) -> Result<u8, Fail> {
    // The parts are inputs: the merged folder may not be one of them or hold one.
    output::declare_inputs(parts.iter().map(PathBuf::as_path));
    let manifest = mrpp_bench::harness::merged_manifest(&parts)?;
    let argv = std::iter::once("mrpp".to_string()).chain(manifest.sweep_command());
    let cli = Cli::try_parse_from(argv)
        .map_err(|e| Fail(format!("the parts' command does not parse any more: {e}")))?;
    let mode = sweeps::Mode::Merge {
        parts,
        manifest: Box::new(manifest),
        out,
    };
    match cli.command {
        Command::Experiment(e) => experiment::run(e, Some(mode)),
        Command::Bench(bench::Bench::Run(a)) => bench::run(*a, Some(mode)),
        _ => Err(Fail(
            "the parts were not made by `mrpp experiment` or `mrpp bench run`".into(),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    /// Every subcommand's `--help` ends with examples, and every example parses (a shell
    /// redirection `> file` is cut off first): the examples cannot rot as flags change.
    #[test]
    fn every_subcommand_has_examples_that_parse() {
        Cli::command().debug_assert();
        fn walk(cmd: &clap::Command, path: &str, seen: &mut usize) {
            for sub in cmd.get_subcommands().filter(|s| s.get_name() != "help") {
                let name = format!("{path} {}", sub.get_name());
                let help = sub
                    .get_after_help()
                    .map(|h| h.to_string())
                    .unwrap_or_default();
                assert!(help.starts_with("Examples"), "`{name}` has no examples");
                let examples: Vec<&str> = help
                    .lines()
                    .filter_map(|l| l.strip_prefix("  mrpp "))
                    .collect();
                assert!(!examples.is_empty(), "`{name}`: no example lines");
                for ex in examples {
                    let ex = ex.split(" > ").next().unwrap_or(ex);
                    let args = std::iter::once("mrpp").chain(ex.split_whitespace());
                    if let Err(e) = Cli::try_parse_from(args) {
                        panic!("`{name}`: example `mrpp {ex}` does not parse: {e}");
                    }
                    assert!(
                        ex.starts_with(name.trim_start()),
                        "`{name}`: example `mrpp {ex}` runs another command"
                    );
                    *seen += 1;
                }
                walk(sub, &name, seen);
            }
        }
        let mut seen = 0;
        walk(&Cli::command(), "", &mut seen);
        assert!(seen >= 30, "{seen} examples");
    }

    /// The short flags of the common options, as lacam3 spells them where it has them.
    #[test]
    fn short_flags_of_the_common_options() {
        let cli = Cli::try_parse_from(
            "mrpp solve -m a.map -i a.scen -N 5 -P lacam -s 7 -t 2.5 -o p.json -q".split(' '),
        )
        .unwrap_or_else(|e| panic!("{e}"));
        assert!(cli.quiet && cli.verbose == 0);
        let Command::Solve(a) = cli.command else {
            panic!("not solve")
        };
        assert_eq!(a.inputs.map.as_deref(), Some(std::path::Path::new("a.map")));
        assert_eq!(
            a.inputs.scen.as_deref(),
            Some(std::path::Path::new("a.scen"))
        );
        assert_eq!(a.inputs.agents, Some(5));
        assert_eq!(
            (a.planner.as_str(), a.seed, a.time_limit),
            ("lacam", 7, 2.5)
        );
        assert_eq!(a.out.as_deref(), Some(std::path::Path::new("p.json")));
        let cli =
            Cli::try_parse_from("mrpp -vv planners".split(' ')).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(cli.verbose, 2);
        assert!(Cli::try_parse_from("mrpp solve -q -v -P lacam".split(' ')).is_err());
    }
}
