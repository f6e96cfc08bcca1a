//! `mrpp`: the command line of the mrpp toolkit. A thin layer: parse arguments, read files, call
//! the library, write files atomically, print one summary, and map outcomes to exit codes:
//! 0 = solved / valid, 1 = bad input, usage or an invalid plan, 3 = not solved.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

use clap::{Parser, Subcommand, ValueEnum};

mod experiment;
mod gp_experiment;
mod plots;
mod trees_cmd;

use mrpp::grid_mapf::{PlannerSpec, build_planner};
use mrpp::io::lacam::{parse_lacam, write_lacam};
use mrpp::io::plan_json::PlanFile;
use mrpp::io::render::render_svg;
use mrpp::search::distance::lower_bounds;
use mrpp::solve::{Deadline, SolveOptions, Unsolved, solve};
use mrpp::{GridMap, Instance, Plan, ValidateOptions};

#[derive(Parser)]
#[command(
    name = "mrpp",
    version,
    about = "Multi-robot path planning: plan, validate and draw"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Clone, Copy, ValueEnum)]
enum Format {
    Json,
    Lacam,
}

#[derive(Subcommand)]
enum Command {
    /// Plan paths for the agents of a scenario on a grid map.
    Solve {
        /// Grid map: MovingAI `.map` or the H* paper's ASCII map (detected from the content).
        #[arg(long)]
        map: PathBuf,
        /// Agents: MovingAI `.scen` or an H* robot file `x,y;x,y` (detected from the content).
        #[arg(long)]
        scen: PathBuf,
        /// Use the first N agents of the scenario (default: all).
        #[arg(long)]
        agents: Option<usize>,
        /// Planner: hstar, ca, hca, whca, coevolution, nsga3.
        #[arg(long)]
        planner: String,
        /// Seed of every random choice.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Wall-clock limit in seconds.
        #[arg(long, default_value_t = 60.0)]
        time_limit: f64,
        /// WHCA* window.
        #[arg(long)]
        window: Option<u32>,
        /// H* variant: repaired (default) or paper (the paper's steps only); coevolution variant:
        /// intended (default) or inverted (the authors' inverted collision count).
        #[arg(long)]
        variant: Option<String>,
        /// Write the plan here (also written when not solved, with "solved": false).
        #[arg(long)]
        out: Option<PathBuf>,
        #[arg(long, value_enum, default_value_t = Format::Json)]
        format: Format,
    },
    /// Check a plan (mrpp JSON or LaCAM text): exit 0 when valid, 1 naming the first violation.
    Validate {
        #[arg(long)]
        map: PathBuf,
        #[arg(long)]
        plan: PathBuf,
        /// Also check the plan's starts and goals against this scenario.
        #[arg(long)]
        scen: Option<PathBuf>,
        #[arg(long, requires = "scen")]
        agents: Option<usize>,
    },
    /// Describe an instance: map size, free cells, corridor nodes, and lower bounds on any valid
    /// plan's sum of costs and makespan (each agent's shortest distance, ignoring the others).
    Info {
        #[arg(long)]
        map: PathBuf,
        #[arg(long)]
        scen: PathBuf,
        #[arg(long)]
        agents: Option<usize>,
    },
    /// Reproduce a paper's table (see docs/reproduction/).
    #[command(subcommand)]
    Experiment(experiment::Experiment),
    /// Single-lane tree problems: generate, solve (PSW or GP), run a GP program, validate.
    #[command(subcommand)]
    Trees(trees_cmd::Trees),
    /// Draw a plan (map, starts, goals, paths) as an SVG picture.
    Render {
        #[arg(long)]
        map: PathBuf,
        #[arg(long)]
        plan: PathBuf,
        #[arg(long)]
        out: PathBuf,
    },
}

/// A failure that ends the command with exit code 1 and one message.
pub(crate) struct Fail(pub(crate) String);

impl<E: std::fmt::Display> From<E> for Fail {
    fn from(e: E) -> Self {
        Fail(e.to_string())
    }
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let code = if e.use_stderr() { 1 } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    let result = match cli.command {
        Command::Solve {
            map,
            scen,
            agents,
            planner,
            seed,
            time_limit,
            window,
            variant,
            out,
            format,
        } => {
            let spec = PlannerSpec {
                name: planner,
                window,
                variant,
            };
            cmd_solve(
                &map,
                &scen,
                agents,
                &spec,
                seed,
                time_limit,
                out.as_deref(),
                format,
            )
        }
        Command::Validate {
            map,
            plan,
            scen,
            agents,
        } => cmd_validate(&map, &plan, scen.as_deref(), agents),
        Command::Info { map, scen, agents } => cmd_info(&map, &scen, agents),
        Command::Render { map, plan, out } => cmd_render(&map, &plan, &out),
        Command::Experiment(e) => experiment::run(e),
        Command::Trees(t) => trees_cmd::run(t),
    };
    match result {
        Ok(code) => ExitCode::from(code),
        Err(Fail(msg)) => {
            eprintln!("mrpp: error: {msg}");
            ExitCode::from(1)
        }
    }
}

/// Writes `contents` to `path` through a temporary file in the same directory, so a reader never
/// sees half a file.
pub(crate) fn write_atomic(path: &Path, contents: &str) -> Result<(), Fail> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .ok_or_else(|| Fail(format!("{}: not a file name", path.display())))?;
    let tmp = dir.join(format!(
        ".{}.tmp{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    std::fs::write(&tmp, contents)
        .map_err(|e| Fail(format!("{}: cannot write: {e}", path.display())))?;
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        Fail(format!("{}: cannot write: {e}", path.display()))
    })
}

fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

#[allow(clippy::too_many_arguments)]
fn cmd_solve(
    map_path: &Path,
    scen_path: &Path,
    agents: Option<usize>,
    spec: &PlannerSpec,
    seed: u64,
    time_limit: f64,
    out: Option<&Path>,
    format: Format,
) -> Result<u8, Fail> {
    if !(time_limit.is_finite() && time_limit > 0.0 && time_limit <= 1e7) {
        return Err(Fail(format!(
            "--time-limit must be a positive number of seconds, got {time_limit}"
        )));
    }
    let planner = build_planner(spec)?;
    let map = GridMap::load(map_path)?;
    let inst = Instance::load(scen_path, &map, agents)?;
    let opts = SolveOptions {
        seed,
        deadline: Deadline::after(Duration::from_secs_f64(time_limit)),
    };
    let started = Instant::now();
    let outcome = solve(planner.as_ref(), map.graph(), &inst, &opts);
    let runtime_ms = started.elapsed().as_secs_f64() * 1e3;
    let solved = match &outcome {
        Ok(plan) => {
            let m = plan
                .validate(map.graph(), &inst, ValidateOptions::default())
                .map_err(|v| Fail(v.describe(map.graph())))?;
            Some((plan, m))
        }
        Err(_) => None,
    };
    println!(
        "mrpp {} | planner {} | seed {} | map {} | agents {}",
        env!("CARGO_PKG_VERSION"),
        planner.name(),
        seed,
        file_name(map_path),
        inst.num_agents()
    );
    match (&outcome, &solved) {
        (_, Some((_, m))) => println!(
            "solved: sum_of_costs {} | makespan {} | sum_of_moves {} | runtime {:.1} ms",
            m.sum_of_costs, m.makespan, m.sum_of_moves, runtime_ms
        ),
        (Err(why), None) => println!("not solved: {why} | runtime {runtime_ms:.1} ms"),
        (Ok(_), None) => unreachable!("a solved outcome always has metrics"),
    }
    if let Some(out) = out {
        let map_file = file_name(map_path);
        let text = match format {
            Format::Json => PlanFile::new(
                &map,
                &map_file,
                &planner.name(),
                seed,
                &inst,
                solved,
                runtime_ms,
            )
            .to_json(),
            Format::Lacam => {
                write_lacam(&map, &map_file, &planner.name(), &inst, solved, runtime_ms)
            }
        };
        write_atomic(out, &text)?;
        println!("plan written to {}", out.display());
    }
    Ok(match outcome {
        Ok(_) => 0,
        Err(Unsolved::TimeLimit | Unsolved::GaveUp(_)) => 3,
    })
}

/// Reads a plan file in either format (JSON starts with `{`).
fn read_plan(map: &GridMap, plan_path: &Path) -> Result<(Instance, Plan, Option<PlanFile>), Fail> {
    let text = mrpp::error::read_file(plan_path)?;
    if text.trim_start().starts_with('{') {
        let file = PlanFile::parse(&text, plan_path)?;
        let (inst, plan) = file.to_instance_and_plan(map, plan_path)?;
        Ok((inst, plan, Some(file)))
    } else {
        let (inst, plan) = parse_lacam(&text, plan_path, map)?;
        Ok((inst, plan, None))
    }
}

fn cmd_validate(
    map_path: &Path,
    plan_path: &Path,
    scen: Option<&Path>,
    agents: Option<usize>,
) -> Result<u8, Fail> {
    let map = GridMap::load(map_path)?;
    let (inst, plan, file) = read_plan(&map, plan_path)?;
    let g = map.graph();
    if let Some(scen) = scen {
        let expected = Instance::load(scen, &map, agents.or(Some(inst.num_agents())))?;
        if expected.num_agents() != inst.num_agents() {
            return Err(Fail(format!(
                "{}: plan has {} agents but the scenario has {}",
                plan_path.display(),
                inst.num_agents(),
                expected.num_agents()
            )));
        }
        for i in 0..inst.num_agents() {
            for (what, a, b) in [
                ("start", inst.starts[i], expected.starts[i]),
                ("goal", inst.goals[i], expected.goals[i]),
            ] {
                if a != b {
                    return Err(Fail(format!(
                        "{}: agent {i} has {what} {} but the scenario says {}",
                        plan_path.display(),
                        g.label(a),
                        g.label(b)
                    )));
                }
            }
        }
    }
    let m = plan
        .validate(g, &inst, ValidateOptions::default())
        .map_err(|v| {
            Fail(format!(
                "{}: invalid plan: {}",
                plan_path.display(),
                v.describe(g)
            ))
        })?;
    if let Some(claimed) = file.as_ref().map(|f| &f.metrics) {
        for (what, claim, real) in [
            ("sum_of_costs", claimed.sum_of_costs, m.sum_of_costs),
            ("makespan", claimed.makespan, m.makespan),
            ("sum_of_moves", claimed.sum_of_moves, m.sum_of_moves),
        ] {
            if claim.is_some_and(|c| c != real) {
                return Err(Fail(format!(
                    "{}: plan claims {what} {} but its paths give {real}",
                    plan_path.display(),
                    claim.unwrap_or_default()
                )));
            }
        }
    }
    println!(
        "valid: {} agents | sum_of_costs {} | makespan {} | sum_of_moves {}",
        inst.num_agents(),
        m.sum_of_costs,
        m.makespan,
        m.sum_of_moves
    );
    Ok(0)
}

fn cmd_render(map_path: &Path, plan_path: &Path, out: &Path) -> Result<u8, Fail> {
    let map = GridMap::load(map_path)?;
    let (inst, plan, _) = read_plan(&map, plan_path)?;
    write_atomic(out, &render_svg(&map, &inst, Some(&plan)))?;
    println!("picture written to {}", out.display());
    Ok(0)
}

fn cmd_info(map_path: &Path, scen_path: &Path, agents: Option<usize>) -> Result<u8, Fail> {
    let map = GridMap::load(map_path)?;
    let inst = Instance::load(scen_path, &map, agents)?;
    let g = map.graph();
    let corridors = mrpp::grid_mapf::corridors::Corridors::build(g);
    let (sum, max) = lower_bounds(g, &inst.starts, &inst.goals).map_err(|i| {
        Fail(format!(
            "{}: agent {i} cannot reach its goal {} from {}",
            scen_path.display(),
            g.label(inst.goals[i]),
            g.label(inst.starts[i])
        ))
    })?;
    println!(
        "map {} {}x{} | free cells {} | corridor-compressed nodes {} | agents {}",
        file_name(map_path),
        map.width(),
        map.height(),
        g.num_vertices(),
        corridors.num_nodes(),
        inst.num_agents()
    );
    println!("lower bounds: sum_of_costs >= {sum} | makespan >= {max}");
    Ok(0)
}
