//! The tree family on the command line: `--instance I [--no-following]`, plans as the envelope
//! with node ids (a GP plan also records its program), and the `mrpp trees ...` commands:
//! `gen` (the GP paper's Algorithm 2) and `solve` / `run` / `validate`, which are the generic
//! verbs under their old names (every flag of earlier versions still works).

use std::path::{Path, PathBuf};

use clap::{Args, Subcommand, ValueEnum};

use mrpp_core::MapfProblem;
use mrpp_trees::gp::GpParams;
use mrpp_trees::plan_json::{read_tree_plan, read_tree_plan_to_draw, tree_envelope};
use mrpp_trees::{ProblemSpec, RobotCount, TreeInstance, generate_problem, tree_problem};

use crate::family::{Def, Format, Inputs, Loaded, ReadPlan, SolveRequest};
use crate::output::{Fail, file_name, guard, out, say, write_atomic};

/// Largest depth budget `trees gen` accepts (the paper uses 4–10).
const MAX_DEPTH: u32 = 30;
/// Largest branching factor `trees gen` accepts (the paper uses 4).
const MAX_BRANCHING: u32 = 16;

/// The tree family.
pub(crate) static TREES: Def<MapfProblem> = def();

/// The tree family's definition (a `const fn` so that tests can build variants of it).
pub(crate) const fn def() -> Def<MapfProblem> {
    Def {
        name: mrpp_trees::FAMILY,
        planners: mrpp_trees::PLANNERS,
        claims: |i| i.instance.is_some(),
        load,
        read_plan,
        info: Some(info),
        render: Some(render),
        scene: Some(scene),
        lacam: false,
    }
}

fn instance_path(inputs: &Inputs) -> Result<&Path, Fail> {
    inputs
        .instance
        .as_deref()
        .ok_or_else(|| Fail("tree problems need --instance".into()))
}

fn load(inputs: &Inputs) -> Result<Loaded<MapfProblem>, Fail> {
    let path = instance_path(inputs)?;
    let tree = TreeInstance::load(path)?;
    let following = !inputs.no_following;
    let instance_file = file_name(path);
    Ok(Loaded {
        summary: format!(
            "instance {instance_file} | nodes {} | robots {} | following {}",
            tree.num_nodes(),
            tree.num_robots(),
            if following { "allowed" } else { "forbidden" }
        ),
        problem: tree_problem(&tree, following),
        write: Box::new(move |problem, info, outcome, notes, _| {
            Ok(tree_envelope(&instance_file, problem, info, outcome, notes).to_json())
        }),
    })
}

/// `mrpp info`: the tree's size and shape, its robots, and lower bounds on any valid plan (each
/// robot alone on the tree).
fn info(inputs: &Inputs) -> Result<u8, Fail> {
    let path = instance_path(inputs)?;
    let tree = TreeInstance::load(path)?;
    let g = &tree.graph;
    let max_degree = (0..g.num_vertices() as mrpp_core::VertexId)
        .map(|v| g.neighbors(v).len())
        .max()
        .unwrap_or(0);
    out!(
        "instance {} | nodes {} | leaves {} | largest degree {} | robots {} (leaves - 1 = {})",
        file_name(path),
        tree.num_nodes(),
        tree.num_leaves(),
        max_degree,
        tree.num_robots(),
        tree.num_leaves().saturating_sub(1)
    );
    let inst = &tree.instance;
    let (sum, max) = mrpp_core::mapf::search::distance::lower_bounds(g, &inst.starts, &inst.goals)
        .map_err(|i| {
            Fail(format!(
                "{}: robot {i} cannot reach its goal",
                path.display()
            ))
        })?;
    out!("lower bounds: sum_of_costs >= {sum} | makespan >= {max}");
    Ok(0)
}

fn read_plan(inputs: &Inputs, plan_path: &Path) -> Result<ReadPlan<MapfProblem>, Fail> {
    read_plan_with(inputs, plan_path, false)
}

/// [`read_plan`]; with `to_draw`, a file that says `solved: false` is read as its robots
/// standing on their starts (pictures of an unsolved instance).
fn read_plan_with(
    inputs: &Inputs,
    plan_path: &Path,
    to_draw: bool,
) -> Result<ReadPlan<MapfProblem>, Fail> {
    let tree = TreeInstance::load(instance_path(inputs)?)?;
    let text = mrpp_core::error::read_file(plan_path)?;
    let read = if to_draw {
        read_tree_plan_to_draw
    } else {
        read_tree_plan
    };
    let (problem, plan, env) = read(&tree, &text, plan_path, inputs.no_following)?;
    let planner = if env.planner.is_empty() {
        "?"
    } else {
        env.planner.as_str()
    };
    let about = format!(
        "following {} | planner {planner} | seed {}",
        if problem.rules().allow_following {
            "allowed"
        } else {
            "forbidden"
        },
        env.seed
    );
    Ok(ReadPlan {
        problem,
        plan,
        claims: env.metrics,
        about,
    })
}

#[derive(Subcommand)]
pub(crate) enum Trees {
    /// Generate a random tree problem (the paper's Algorithm 2 and random robots) as JSON.
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp trees gen -s 0 --depth 5 --robots 8 -o tree.json"
    )]
    Gen {
        /// Seed of the random stream (the same seed and parameters give the same file).
        #[arg(short = 's', long, allow_negative_numbers = true, value_parser = crate::output::parse_seed)]
        seed: u64,
        /// Depth budget, Algorithm 2's "seed" (paper: 4–10; at most 30).
        #[arg(allow_negative_numbers = true, long)]
        depth: u32,
        /// Maximum branching factor b: a node gets 0..b-1 children (paper: 4; 3 to 16).
        #[arg(allow_negative_numbers = true, long, default_value_t = 4)]
        branching: u32,
        /// Number of robots (at most the node count minus 2).
        #[arg(allow_negative_numbers = true, value_parser = crate::output::parse_whole, long)]
        robots: Option<usize>,
        /// Robots = floor(M x leaves), capped at the node count minus 2 (paper: 0.25 to 1.5).
        #[arg(long, allow_negative_numbers = true)]
        leaf_multiplier: Option<f64>,
        /// Refuse trees with more nodes than this: with b = 4 the tree size varies wildly with the
        /// seed at large depths (depth 30 gives from a few nodes to millions), and neither
        /// planner can do anything useful on such trees. The generator itself stops at 2^22.
        #[arg(allow_negative_numbers = true, value_parser = crate::output::parse_count, long, default_value_t = 100_000)]
        max_nodes: usize,
        /// Write the instance here.
        #[arg(short = 'o', long)]
        out: PathBuf,
    },
    /// Solve a tree instance with PSW or GP and write the plan (same as `mrpp solve --instance`).
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp trees solve --instance data/trees/example.json -P psw -o plan.json\n  mrpp trees solve --instance data/trees/example.json -P gp -s 1 --save-program best.gp -o plan.json"
    )]
    Solve {
        #[arg(long)]
        instance: PathBuf,
        /// psw (Push-Swap-Wait) or gp (evolve a program for this instance).
        #[arg(short = 'P', long, value_enum)]
        planner: TreePlanner,
        /// With --planner gp: run this saved program instead of evolving one (`-p program=P`).
        #[arg(long)]
        program: Option<PathBuf>,
        /// Seed of the GP evolution (PSW is deterministic; the seed is only recorded).
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
        /// Forbid following (entering a node that another robot leaves in the same step).
        #[arg(long)]
        no_following: bool,
        #[command(flatten)]
        gp: Box<GpParamArgs>,
        /// Write the evolved program here (S-expression; `mrpp trees run --program` reads it).
        #[arg(long)]
        save_program: Option<PathBuf>,
        /// Planner parameters `key=value` (see `mrpp planners --family trees`).
        #[arg(short = 'p', long = "param", value_name = "KEY=VALUE")]
        params: Vec<String>,
        /// Write the plan here (also written when not solved, with "solved": false).
        #[arg(short = 'o', long)]
        out: Option<PathBuf>,
    },
    /// Run a saved GP program on a tree instance and write its plan (`--planner gp -p program=P`).
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp trees run --program data/trees/example-program.gp --instance data/trees/example.json -o plan.json"
    )]
    Run {
        /// GP program file (S-expression, as written by `trees solve --save-program`).
        #[arg(long)]
        program: PathBuf,
        #[arg(long)]
        instance: PathBuf,
        #[arg(
            short = 't',
            long,
            default_value_t = 60.0,
            allow_negative_numbers = true
        )]
        time_limit: f64,
        #[arg(long)]
        no_following: bool,
        #[arg(short = 'o', long)]
        out: Option<PathBuf>,
    },
    /// Check a tree plan against its instance: exit 0 when valid, 1 naming the first violation.
    #[command(
        after_help = "Examples (from the repository's root):\n  mrpp trees validate --instance data/trees/example.json --plan plan.json"
    )]
    Validate {
        #[arg(long)]
        instance: PathBuf,
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
    /// What a robot's path becomes on reaching the branch node it set its path to: resume (back
    /// to its objective at once; default) or hold (kept until If-Robot-At-Branch sees the robot
    /// there; the authors' code).
    #[arg(long, value_parser = ["resume", "hold"])]
    pub(crate) branch_arrival: Option<String>,
}

impl GpParamArgs {
    /// The flags as registry parameters of the `gp` planner (`-p key=value`).
    pub(crate) fn pairs(&self) -> Vec<(String, String)> {
        let mut out = Vec::new();
        let mut put = |k: &str, v: Option<String>| {
            if let Some(v) = v {
                out.push((k.to_string(), v));
            }
        };
        put("paper_settings", self.paper_settings.then(|| "true".into()));
        put("population", self.population.map(|v| v.to_string()));
        put("generations", self.generations.map(|v| v.to_string()));
        put("runs", self.runs.map(|v| v.to_string()));
        put("evolution_cap", self.evolution_cap.map(|v| v.to_string()));
        put("p_reproduction", self.p_reproduction.map(|v| v.to_string()));
        put("p_crossover", self.p_crossover.map(|v| v.to_string()));
        put("p_mutation", self.p_mutation.map(|v| v.to_string()));
        put("min_depth", self.min_depth.map(|v| v.to_string()));
        put("max_depth", self.max_depth.map(|v| v.to_string()));
        put("init_depth", self.init_depth.map(|v| v.to_string()));
        put("branch_arrival", self.branch_arrival.clone());
        out
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
        if let Some(a) = &self.branch_arrival {
            p.sim.branch_arrival = mrpp_trees::gp::simulate::BranchArrival::parse(a)
                .ok_or_else(|| Fail(format!("--branch-arrival {a}: expected resume or hold")))?;
        }
        p.sim.allow_following = allow_following;
        p.check()?;
        Ok(p)
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
            let size = GenSize {
                depth,
                branching,
                max_nodes,
            };
            cmd_gen(seed, size, robots, leaf_multiplier, &out)
        }
        Trees::Solve { .. } => solve_alias(cmd),
        Trees::Run {
            program,
            instance,
            time_limit,
            no_following,
            out,
        } => crate::verbs::solve(&SolveRequest {
            inputs: tree_inputs(instance, no_following),
            planner: mrpp_trees::gp::NAME.into(),
            params: vec![("program".into(), program.to_string_lossy().into_owned())],
            seed: 0,
            time_limit,
            out,
            format: Format::Json,
            save_program: None,
            command: "trees run",
        }),
        Trees::Validate {
            instance,
            plan,
            no_following,
        } => crate::verbs::validate(&tree_inputs(instance, no_following), &plan),
    }
}

fn tree_inputs(instance: PathBuf, no_following: bool) -> Inputs {
    Inputs {
        instance: Some(instance),
        no_following,
        ..Inputs::default()
    }
}

/// `trees solve`: the generic solve, with the old flags turned into registry parameters.
fn solve_alias(cmd: Trees) -> Result<u8, Fail> {
    let Trees::Solve {
        instance,
        planner,
        program,
        seed,
        time_limit,
        no_following,
        gp,
        save_program,
        params,
        out,
    } = cmd
    else {
        unreachable!("called for trees solve only")
    };
    let mut pairs = gp.pairs();
    if let Some(p) = &program {
        pairs.push(("program".into(), p.to_string_lossy().into_owned()));
    }
    let name = match planner {
        TreePlanner::Psw if !pairs.is_empty() || save_program.is_some() => {
            return Err(Fail("--program, --population, --generations, --runs, --paper-settings and --save-program are for --planner gp".into()));
        }
        TreePlanner::Psw => mrpp_trees::psw::NAME,
        TreePlanner::Gp => mrpp_trees::gp::NAME,
    };
    if program.is_some() && (pairs.len() > 1 || save_program.is_some()) {
        return Err(Fail("--program runs a saved program: --population, --generations, --runs, --paper-settings and --save-program only apply when evolving one".into()));
    }
    for p in &params {
        pairs.push(mrpp_core::registry::parse_key_value(p)?);
    }
    crate::verbs::solve(&SolveRequest {
        inputs: tree_inputs(instance, no_following),
        planner: name.into(),
        params: pairs,
        seed,
        time_limit,
        out,
        format: Format::Json,
        save_program,
        command: "trees solve",
    })
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
    guard([], &[out])?;
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
    write_atomic(out, tree.to_json())?;
    let branches = (0..n as u32).filter(|&v| tree.graph.degree(v) >= 3).count();
    say!(
        "mrpp {} | trees gen | seed {seed} | depth {depth} | branching {branching} | nodes {n} | \
         leaves {} | branch nodes {branches} | robots {} | written to {}",
        env!("CARGO_PKG_VERSION"),
        tree.num_leaves(),
        tree.num_robots(),
        out.display()
    );
    Ok(0)
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

/// A tidy layout of the tree rooted at node 0: depth down the y axis (1.2 apart), leaves one
/// apart in depth-first order, every parent centred over its children.
fn tidy_layout(tree: &TreeInstance) -> Vec<[f64; 2]> {
    let n = tree.num_nodes();
    let mut adj = vec![Vec::new(); n];
    for &(a, b) in tree.edges() {
        adj[a as usize].push(b as usize);
        adj[b as usize].push(a as usize);
    }
    for a in &mut adj {
        a.sort_unstable();
    }
    let mut pos = vec![[0.0, 0.0]; n];
    let mut next_leaf = 0.0;
    // Iterative post-order from the root: (node, parent, children done).
    let mut stack = vec![(0usize, usize::MAX, false)];
    let mut depth = vec![0usize; n];
    while let Some((v, parent, done)) = stack.pop() {
        let children: Vec<usize> = adj[v].iter().copied().filter(|&c| c != parent).collect();
        if !done {
            stack.push((v, parent, true));
            for &c in children.iter().rev() {
                depth[c] = depth[v] + 1;
                stack.push((c, v, false));
            }
            continue;
        }
        let x = if children.is_empty() {
            next_leaf += 1.0;
            next_leaf - 1.0
        } else {
            (pos[children[0]][0] + pos[children[children.len() - 1]][0]) / 2.0
        };
        pos[v] = [x, depth[v] as f64 * 1.2];
    }
    pos
}

/// `mrpp view`: the viewer's scene of a tree plan ([`crate::view`]): the tree in a tidy layout
/// (edges as segments, nodes as dots), robots on nodes, and the validator's verdict.
fn scene(inputs: &Inputs, plan_path: &Path) -> Result<serde_json::Value, Fail> {
    use mrpp_core::Problem;
    use serde_json::json;
    let tree = TreeInstance::load(instance_path(inputs)?)?;
    let read = read_plan_with(inputs, plan_path, true)?;
    let pos = tidy_layout(&tree);
    let inst = read.problem.instance();
    let at = |v: mrpp_core::VertexId| pos[v as usize];
    let agents: Vec<serde_json::Value> = (0..inst.num_agents())
        .map(|i| {
            json!({
                "radius": 0.3,
                "start": at(inst.starts[i]),
                "goal": at(inst.goals[i]),
                "path": read.plan.paths[i].iter().map(|&v| at(v)).collect::<Vec<_>>(),
            })
        })
        .collect();
    let segments: Vec<[[f64; 2]; 2]> = tree.edges().iter().map(|&(a, b)| [at(a), at(b)]).collect();
    let max_x = pos.iter().map(|p| p[0]).fold(0.0, f64::max);
    let max_y = pos.iter().map(|p| p[1]).fold(0.0, f64::max);
    let verdict = match read.problem.validate(&read.plan) {
        Ok(m) => json!({"valid": true, "metrics": m}),
        Err(v) => json!({"valid": false, "text": v.text}),
    };
    Ok(json!({
        "family": "trees",
        "title": format!("{} | {}", file_name(instance_path(inputs)?), file_name(plan_path)),
        "about": read.about,
        "bounds": [-0.8, -0.8, max_x + 0.8, max_y + 0.8],
        "y_up": false,
        "polygons": [],
        "segments": segments,
        "nodes": pos,
        "agents": agents,
        "verdict": verdict,
    }))
}

/// `mrpp render`: the tree (tidy layout), every robot's route, starts as discs, goals as squares.
fn render(inputs: &Inputs, plan_path: &Path) -> Result<String, Fail> {
    Ok(crate::picture::paths_svg(&scene(inputs, plan_path)?))
}
