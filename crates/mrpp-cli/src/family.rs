//! The one family table of the command line, and the generic verbs every family gets from it.
//!
//! A family is a [`Def`]: its name, its planner registry, and how its files become a problem
//! ([`Def::load`]), how a plan file is read back ([`Def::read_plan`]), and what `info`/`render`
//! show. `solve`, `validate` and `planners` are written once here, generically; the family comes
//! from the planner name (names are unique across families) or from the inputs. Adding a family
//! is one line in [`FAMILIES`].

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use serde_json::{Map, Value};

use mrpp_core::mapf::plan_file::RunInfo;
use mrpp_core::registry::find;
use mrpp_core::{Ctx, Deadline, Params, PlannerEntry, Problem, Solved, Unsolved, solve};

use crate::output::{Fail, detail, metrics_object, out, pairs, say, time_limit, write_atomic};
use crate::progress;

/// Every family the binary knows, in the order `mrpp planners` lists them.
pub(crate) static FAMILIES: &[&dyn Family] = &[
    &crate::grid_family::GRID,
    &crate::tree_family::TREES,
    &crate::formation_family::FORMATION,
    &crate::continuous_family::CONTINUOUS,
    &crate::lifelong_family::LIFELONG,
    #[cfg(test)]
    &crate::toy_family::TOY,
    #[cfg(test)]
    &crate::toy_family::BROKEN_GRID,
    #[cfg(test)]
    &crate::toy_family::BROKEN_TREES,
];

/// The input files of any family (which ones a family reads is its own business).
#[derive(clap::Args, Debug, Clone, Default)]
pub struct Inputs {
    /// Grid map: MovingAI `.map` or the H* paper's ASCII map (detected from the content).
    #[arg(short = 'm', long)]
    pub map: Option<PathBuf>,
    /// Grid agents: MovingAI `.scen` or an H* robot file `x,y;x,y` (detected from the content).
    #[arg(short = 'i', long)]
    pub scen: Option<PathBuf>,
    /// Use the first N agents of the scenario (default: all).
    #[arg(short = 'N', long, allow_negative_numbers = true, value_parser = crate::output::parse_count)]
    pub agents: Option<usize>,
    /// Grid problem from the League of Robot Runners: its problem JSON (2023 or 2026 start-kit
    /// layout), read with its map, agents and tasks as a one-shot instance (goal = first task).
    #[arg(long, conflicts_with_all = ["map", "scen"])]
    pub lorr: Option<PathBuf>,
    /// Run the `--lorr` problem as a lifelong problem (robots get a new task when they finish
    /// one); implied by a lifelong planner, and by `validate` given LoRR output JSON.
    #[arg(long, requires = "lorr")]
    pub lifelong: bool,
    /// Lifelong: the horizon in steps (default 1000).
    #[arg(long, value_parser = crate::output::parse_count)]
    pub steps: Option<usize>,
    /// Lifelong `info` with --steps: also the congestion-free reference under this scheduler,
    /// given as the lifelong planners' scheduler options, e.g.
    /// `scheduler=hungarian,lookahead=25` (scheduler, hungarian_max, chain_weight,
    /// reassign_margin, lookahead; `mrpp planners --family lifelong`).
    #[arg(long, requires = "steps")]
    pub reference_scheduler: Option<String>,
    /// Lifelong: planning time per step in seconds (default 1, the League's); a planner that
    /// runs over loses one step per full budget, as in the League's start kit.
    #[arg(long, allow_negative_numbers = true)]
    pub step_time_limit: Option<f64>,
    /// Lifelong: preprocessing time in seconds before the first step (default 30, the
    /// League's); the planner builds distance tables then.
    #[arg(long, allow_negative_numbers = true)]
    pub preprocess_time_limit: Option<f64>,
    /// Lifelong: run under the League's 2026 execution model for N ticks instead of steps:
    /// every action takes the problem's agentCounter ticks, robots are delayed as its
    /// delayConfig says, an executor stages each plan and says go or stop every tick, and the
    /// planner is called every --plan-every ticks. The output is LoRR's 2026 JSON.
    #[arg(long, value_parser = crate::output::parse_count, conflicts_with = "steps")]
    pub ticks: Option<usize>,
    /// Lifelong in ticks: ticks between planner calls (default 10, the League's
    /// planCommTimeLimit over its actionMoveTimeLimit); each call gets --step-time-limit.
    #[arg(long, value_parser = crate::output::parse_count, requires = "ticks")]
    pub plan_every: Option<usize>,
    /// Execution: `none`, or `bernoulli:p=P,min=A,max=B` / `poisson:p=P,min=A,max=B`, with
    /// optional `duration=gaussian,mean=0.5,std=0.22` (the League's delayConfig). Default: none
    /// for `execute`; the problem's delayConfig for lifelong runs in ticks.
    #[arg(long)]
    pub delays: Option<String>,
    /// Execution: who says when a robot goes. `execute`: adg (the action dependency graph,
    /// default), tpg (the League's default executor: per-cell queues; a ring of the plan stops
    /// it) or naive (the plan's timing). Lifelong in ticks: tpg (the League's default
    /// executor, default) or naive.
    #[arg(long)]
    pub executor: Option<String>,
    /// Execution: keep K actions of slack, so that a robot up to K actions late makes no other
    /// wait (k-robust, Atzmon et al., JAIR 2020: no robot enters a cell another left fewer than
    /// K steps earlier). `execute`: the plan is re-timed, its order of passage kept (it matters
    /// to the naive executor; the ADG keeps the order anyway). Lifelong in ticks: every planned
    /// step is filtered, moves that would break it wait. 0 (default): plans as made.
    #[arg(long, allow_negative_numbers = true)]
    pub k_robust: Option<i64>,
    /// Execution: ticks per action (the League's agentCounter). Default 1 for `execute`; the
    /// problem's agentCounter (else 10) for lifelong runs in ticks.
    #[arg(long, allow_negative_numbers = true, value_parser = crate::output::parse_count)]
    pub ticks_per_move: Option<usize>,
    /// Execution: side of a robot's square footprint in cells, in (0, 1] (the League's
    /// agentSize). Default 1, or the problem's agentSize.
    #[arg(long, allow_negative_numbers = true)]
    pub agent_size: Option<f64>,
    /// Lifelong: the action model, MAPF_T (orientation: forward, turn, wait; the League's) or
    /// MAPF (4-neighbour moves).
    #[arg(long)]
    pub action_model: Option<String>,
    /// Tree instance JSON: {"nodes": N, "edges": [[u, v], ...], "robots": [{"start", "goal"}]}.
    #[arg(long)]
    pub instance: Option<PathBuf>,
    /// Formation file JSON: {"map": polygon map, "robots": R, "start": [x, y], "goal": [x, y],
    /// "radius", "cost": {"model": "lanes"|"waves"|"hard"}}.
    #[arg(long)]
    pub formation: Option<PathBuf>,
    /// Continuous world JSON: {"workspace": [x0, y0, x1, y1], "obstacles": [[[x, y], ...]],
    /// "robots": [{"start", "goal", "radius", "speed"}], "epsilon", "step_limit"}.
    #[arg(long)]
    pub world: Option<PathBuf>,
    /// The test family's world file (hidden).
    #[arg(long, hide = true)]
    pub line_world: Option<PathBuf>,
    /// Trees: forbid following (entering a node another robot leaves in the same step).
    #[arg(long)]
    pub no_following: bool,
}

/// `--ticks-per-move`, checked (1 to 1000), if given.
pub(crate) fn ticks_per_move(inputs: &Inputs) -> Result<Option<u32>, Fail> {
    inputs
        .ticks_per_move
        .map(|t| {
            u32::try_from(t)
                .ok()
                .filter(|t| (1..=1000).contains(t))
                .ok_or_else(|| Fail(format!("--ticks-per-move {t}: expected 1 to 1000")))
        })
        .transpose()
}

/// `--k-robust`, checked (0 to 1000 actions); 0 when not given.
pub(crate) fn k_robust(inputs: &Inputs) -> Result<u32, Fail> {
    let k = inputs.k_robust.unwrap_or(0);
    u32::try_from(k)
        .ok()
        .filter(|&k| k <= 1000)
        .ok_or_else(|| Fail(format!("--k-robust {k}: expected 0 to 1000 steps")))
}

/// `--agent-size`, checked (in (0, 1] cells), if given.
pub(crate) fn agent_size(inputs: &Inputs) -> Result<Option<f64>, Fail> {
    inputs
        .agent_size
        .map(|s| {
            if s > 0.0 && s <= 1.0 {
                Ok(s)
            } else {
                Err(Fail(format!(
                    "--agent-size {s}: expected more than 0 and at most 1 cell"
                )))
            }
        })
        .transpose()
}

impl Inputs {
    /// The input files given (outputs may not overwrite them).
    pub(crate) fn paths(&self) -> Vec<&Path> {
        [
            &self.map,
            &self.scen,
            &self.lorr,
            &self.instance,
            &self.formation,
            &self.world,
            &self.line_world,
        ]
        .into_iter()
        .filter_map(|p| p.as_deref())
        .collect()
    }

    /// Every file these inputs read: the files named, and the files they refer to (a League of
    /// Robot Runners problem's map, agents and tasks; a formation file's polygon map), resolved
    /// as their loaders resolve them. A file whose references cannot be read yet adds none (its
    /// load fails before anything is written). Declared before any work so that no output
    /// replaces any of them ([`crate::output::declare_inputs`]).
    pub(crate) fn read_set(&self) -> Vec<PathBuf> {
        let mut files: Vec<PathBuf> = self.paths().into_iter().map(Path::to_path_buf).collect();
        if let Some(lorr) = &self.lorr {
            files.extend(mrpp_grid::lorr::referenced_files(lorr).unwrap_or_default());
        }
        if let Some(formation) = &self.formation
            && let Ok(map) = mrpp_formation::world::FormationFile::map_of(formation)
        {
            files.push(map);
        }
        files
    }

    /// [`crate::output::guard`] with [`Self::read_set`] and `more` (a plan file, a program) as
    /// the command's inputs.
    pub(crate) fn guard(&self, more: &[&Path], outs: &[&Path]) -> Result<(), Fail> {
        let files = self.read_set();
        crate::output::guard(
            files
                .iter()
                .map(PathBuf::as_path)
                .chain(more.iter().copied()),
            outs,
        )
    }

    /// The families whose files are given, each with the flags that name them.
    fn families_given(&self) -> Vec<(&'static str, String)> {
        let flags = |named: &[(&str, bool)]| -> Option<String> {
            let given: Vec<&str> = named.iter().filter(|n| n.1).map(|n| n.0).collect();
            (!given.is_empty()).then(|| given.join(" "))
        };
        [
            (
                "grid",
                flags(&[
                    ("--map", self.map.is_some()),
                    ("--scen", self.scen.is_some()),
                    ("--lorr", self.lorr.is_some() && !self.lifelong),
                ]),
            ),
            (
                "lifelong",
                flags(&[("--lorr --lifelong", self.lorr.is_some() && self.lifelong)]),
            ),
            ("trees", flags(&[("--instance", self.instance.is_some())])),
            (
                "formation",
                flags(&[("--formation", self.formation.is_some())]),
            ),
            ("continuous", flags(&[("--world", self.world.is_some())])),
            (
                "line",
                flags(&[("--line-world", self.line_world.is_some())]),
            ),
        ]
        .into_iter()
        .filter_map(|(family, f)| f.map(|f| (family, f)))
        .collect()
    }

    /// Checks that the files given are one family's: `--map --scen --world` names two problems,
    /// and silently planning one of them would drop the other.
    pub(crate) fn one_family(&self) -> Result<(), Fail> {
        let given = self.families_given();
        if given.len() > 1 {
            let list: Vec<String> = given
                .iter()
                .map(|(family, flags)| format!("{flags} ({family})"))
                .collect();
            return Err(Fail(format!(
                "these inputs name problems of {} families: {}; give one problem's files",
                given.len(),
                list.join(" and ")
            )));
        }
        Ok(())
    }

    /// The first execution flag given (they apply to `mrpp execute` and lifelong runs in
    /// ticks), if any.
    pub(crate) fn execution_flag(&self) -> Option<&'static str> {
        [
            (self.delays.is_some(), "--delays"),
            (self.executor.is_some(), "--executor"),
            (self.k_robust.is_some(), "--k-robust"),
            (self.ticks_per_move.is_some(), "--ticks-per-move"),
            (self.agent_size.is_some(), "--agent-size"),
        ]
        .into_iter()
        .find_map(|(given, flag)| given.then_some(flag))
    }

    /// Refuses the execution flags when planning a `family` problem, rather than ignoring them.
    pub(crate) fn no_execution_flags(&self, family: &str) -> Result<(), Fail> {
        match self.execution_flag() {
            Some(flag) => Err(Fail(format!(
                "{flag} applies to `mrpp execute` and to lifelong runs in ticks (--lorr P.json, a lifelong planner, --ticks N), not to planning a {family} problem"
            ))),
            None => Ok(()),
        }
    }

    /// The files given, as `--flag path` pairs (for `-v`).
    pub(crate) fn files(&self) -> String {
        let named = [
            ("--map", &self.map),
            ("--scen", &self.scen),
            ("--lorr", &self.lorr),
            ("--instance", &self.instance),
            ("--formation", &self.formation),
            ("--world", &self.world),
        ];
        let mut out: Vec<String> = named
            .iter()
            .filter_map(|(flag, p)| p.as_ref().map(|p| format!("{flag} {}", p.display())))
            .collect();
        if let Some(n) = self.agents {
            out.push(format!("--agents {n}"));
        }
        out.join(" ")
    }
}

/// Output format of `solve`.
#[derive(Clone, Copy, PartialEq, Eq, Debug, clap::ValueEnum)]
pub(crate) enum Format {
    /// The plan envelope (every family).
    Json,
    /// The LaCAM/PIBT text result that MAPF visualizers read (grids).
    Lacam,
}

/// One `solve` request, whatever the family.
#[derive(Clone)]
pub(crate) struct SolveRequest {
    pub(crate) inputs: Inputs,
    pub(crate) planner: String,
    pub(crate) params: Vec<(String, String)>,
    pub(crate) seed: u64,
    pub(crate) time_limit: f64,
    pub(crate) out: Option<PathBuf>,
    pub(crate) format: Format,
    /// Where to write a program the planner made (GP), if it made one.
    pub(crate) save_program: Option<PathBuf>,
    /// The command name in the summary (`solve`, `trees solve`, ...).
    pub(crate) command: &'static str,
}

/// A family as the command line sees it, with its problem type erased.
pub(crate) trait Family: Sync {
    fn name(&self) -> &'static str;
    /// `(name, about, [(param, default, doc)])` of every planner.
    fn planners(&self) -> Vec<(&'static str, &'static str, Vec<mrpp_core::Param>)>;
    fn has_planner(&self, name: &str) -> bool;
    /// Whether `inputs` are this family's (for `validate`, `info`, `render`).
    fn claims(&self, inputs: &Inputs) -> bool;
    fn solve(&self, req: &SolveRequest) -> Result<u8, Fail>;
    /// Plans without printing: `(solved, status, the plan envelope as JSON)`.
    fn solve_quietly(&self, req: &SolveRequest) -> Result<(bool, String, String), Fail>;
    /// Loads the inputs: `(summary, number of agents)`.
    fn describe(&self, inputs: &Inputs) -> Result<(String, usize), Fail>;
    fn validate(&self, inputs: &Inputs, plan: &Path) -> Result<u8, Fail>;
    /// Checks a plan file without printing: `(agents, metrics, about)`.
    fn check(&self, inputs: &Inputs, plan: &Path) -> Result<Checked, Fail>;
    fn info(&self, inputs: &Inputs) -> Result<u8, Fail>;
    fn render(&self, inputs: &Inputs, plan: &Path) -> Result<String, Fail>;
    fn scene(&self, inputs: &Inputs, plan: &Path) -> Result<Value, Fail>;
}

/// A loaded problem, ready to plan on.
pub(crate) struct Loaded<P: Problem> {
    pub(crate) problem: P,
    /// One line about the world and the agents, e.g. `map room.map | agents 10`.
    pub(crate) summary: String,
    /// Writes the plan file of a run (given its header, outcome and the planner's notes).
    #[allow(clippy::type_complexity)]
    pub(crate) write:
        Box<dyn Fn(&P, RunInfo, &Outcome<P>, Map<String, Value>, Format) -> Result<String, Fail>>,
}

/// What a planner run gave.
pub(crate) type Outcome<P> = Result<Solved<P>, Unsolved>;

/// A plan file read back with its problem.
pub(crate) struct ReadPlan<P: Problem> {
    pub(crate) problem: P,
    pub(crate) plan: P::Plan,
    /// The metrics the file claims (compared with the validator's).
    pub(crate) claims: Map<String, Value>,
    /// Extra words for the summary, e.g. `planner gp | seed 5 | following allowed`.
    pub(crate) about: String,
}

/// `mrpp info` of a family.
pub(crate) type InfoFn = fn(&Inputs) -> Result<u8, Fail>;
/// `mrpp render` of a family: inputs and plan file to an SVG picture.
pub(crate) type RenderFn = fn(&Inputs, &Path) -> Result<String, Fail>;

/// `mrpp view` of a family: inputs and plan file to the viewer's scene ([`crate::view`]).
pub(crate) type SceneFn = fn(&Inputs, &Path) -> Result<Value, Fail>;

/// A family: its registry and how its files are read and written.
pub(crate) struct Def<P: Problem + 'static> {
    pub(crate) name: &'static str,
    pub(crate) planners: &'static [PlannerEntry<P>],
    pub(crate) claims: fn(&Inputs) -> bool,
    pub(crate) load: fn(&Inputs) -> Result<Loaded<P>, Fail>,
    pub(crate) read_plan: fn(&Inputs, &Path) -> Result<ReadPlan<P>, Fail>,
    pub(crate) info: Option<InfoFn>,
    pub(crate) render: Option<RenderFn>,
    pub(crate) scene: Option<SceneFn>,
    /// Whether plans can be written as LaCAM text (grids only).
    pub(crate) lacam: bool,
}

impl<P: Problem + 'static> Family for Def<P> {
    fn name(&self) -> &'static str {
        self.name
    }
    fn planners(&self) -> Vec<(&'static str, &'static str, Vec<mrpp_core::Param>)> {
        self.planners
            .iter()
            .map(|e| (e.name, e.about, e.params.to_vec()))
            .collect()
    }
    fn has_planner(&self, name: &str) -> bool {
        find(self.planners, name).is_some()
    }
    fn claims(&self, inputs: &Inputs) -> bool {
        (self.claims)(inputs)
    }
    fn solve(&self, req: &SolveRequest) -> Result<u8, Fail> {
        solve_with(self, req)
    }
    fn solve_quietly(&self, req: &SolveRequest) -> Result<(bool, String, String), Fail> {
        let run = run_planner(self, req, false)?;
        let status = match &run.outcome {
            Ok(_) => "solved".to_string(),
            Err(Unsolved::Invalid(why)) => {
                return Err(Fail(format!("invalid plan (a bug in mrpp): {why}")));
            }
            Err(why) => why.to_string(),
        };
        let json = (run.loaded.write)(
            &run.loaded.problem,
            run.info,
            &run.outcome,
            run.notes,
            Format::Json,
        )?;
        Ok((run.outcome.is_ok(), status, json))
    }
    fn describe(&self, inputs: &Inputs) -> Result<(String, usize), Fail> {
        let loaded = (self.load)(inputs)?;
        Ok((loaded.summary, loaded.problem.num_agents()))
    }
    fn validate(&self, inputs: &Inputs, plan: &Path) -> Result<u8, Fail> {
        validate_with(self, inputs, plan)
    }
    fn check(&self, inputs: &Inputs, plan: &Path) -> Result<Checked, Fail> {
        check_with(self, inputs, plan)
    }
    fn info(&self, inputs: &Inputs) -> Result<u8, Fail> {
        let info = self.info.ok_or_else(|| self.lacks("info"))?;
        info(inputs)
    }
    fn render(&self, inputs: &Inputs, plan: &Path) -> Result<String, Fail> {
        let render = self.render.ok_or_else(|| self.lacks("render"))?;
        render(inputs, plan)
    }
    fn scene(&self, inputs: &Inputs, plan: &Path) -> Result<Value, Fail> {
        let scene = self.scene.ok_or_else(|| self.lacks("view"))?;
        scene(inputs, plan)
    }
}

impl<P: Problem + 'static> Def<P> {
    fn lacks(&self, verb: &str) -> Fail {
        Fail(format!(
            "`mrpp {verb}` is not available for {} problems yet",
            self.name
        ))
    }
}

/// The family whose registry has `planner`.
pub(crate) fn family_of_planner(planner: &str) -> Result<&'static dyn Family, Fail> {
    FAMILIES
        .iter()
        .copied()
        .find(|f| f.has_planner(planner))
        .ok_or_else(|| {
            let known: Vec<&str> = FAMILIES
                .iter()
                .flat_map(|f| f.planners().into_iter().map(|p| p.0))
                .collect();
            Fail(format!(
                "unknown planner `{planner}` (known: {}; `mrpp planners` lists them)",
                known.join(", ")
            ))
        })
}

/// The files a family's problems are read from, as flags.
fn needs(family: &str) -> &'static str {
    match family {
        "grid" => "--map M --scen S (or --lorr P.json)",
        "trees" => "--instance I.json",
        "formation" => "--formation F.json",
        "continuous" => "--world W.json",
        "lifelong" => "--lorr P.json",
        _ => "the family's files",
    }
}

/// The family whose files `inputs` name.
pub(crate) fn family_of_inputs(inputs: &Inputs) -> Result<&'static dyn Family, Fail> {
    inputs.one_family()?;
    FAMILIES
        .iter()
        .copied()
        .find(|f| f.claims(inputs))
        .ok_or_else(|| {
            Fail(
                "name the problem's files: --map (and --scen) for grids, --lorr for League of Robot Runners problems (with --lifelong to run them lifelong), --instance for trees, --formation for formations, --world for continuous worlds"
                    .into(),
            )
        })
}

/// One planner run: the loaded problem, the run's header, its outcome and the planner's notes.
struct Run<P: Problem> {
    loaded: Loaded<P>,
    info: RunInfo,
    outcome: Outcome<P>,
    notes: Map<String, Value>,
    runtime_ms: f64,
    planner: String,
}

/// Loads, builds the planner from the registry and plans through the core `solve` (which
/// validates once); `announce` prints the header line and shows a progress bar.
fn run_planner<P: Problem + 'static>(
    def: &Def<P>,
    req: &SolveRequest,
    announce: bool,
) -> Result<Run<P>, Fail> {
    let limit = time_limit(req.time_limit)?;
    req.inputs.one_family()?;
    if !(def.claims)(&req.inputs) {
        let given = req.inputs.families_given();
        let had = match given.first() {
            Some((family, flags)) if *family == def.name => format!("{flags} alone is not enough"),
            Some((family, flags)) => format!("{flags} names a {family} problem"),
            None => "no problem file is given".into(),
        };
        return Err(Fail(format!(
            "planner `{}` plans {} problems, which need {}; {had} (see `mrpp solve --help`)",
            req.planner,
            def.name,
            needs(def.name)
        )));
    }
    if def.name != "lifelong" {
        req.inputs.no_execution_flags(def.name)?;
    }
    if req.format == Format::Lacam && !def.lacam {
        return Err(Fail(format!(
            "{} plans are written as JSON only (--format json)",
            def.name
        )));
    }
    let entry = find(def.planners, &req.planner).ok_or_else(|| {
        Fail(format!(
            "planner `{}` is not a {} planner",
            req.planner, def.name
        ))
    })?;
    let params = Params::resolve(entry.name, entry.params, &req.params)?;
    let planner = (entry.build)(&params)?;
    let load_started = Instant::now();
    // The time limit covers the whole command from here, loading included: a user's
    // `--time-limit 1` means an answer within a second.
    let deadline = Deadline::after(limit);
    let loaded = (def.load)(&req.inputs)?;
    let load_ms = load_started.elapsed().as_secs_f64() * 1e3;
    let live = announce.then(|| progress::Live::start(entry.name));
    let ctx = Ctx {
        progress: live.as_ref().map(progress::Live::callback),
        ..Ctx::new(req.seed, deadline)
    };
    if announce {
        say!(
            "mrpp {} | {} | family {} | planner {} | seed {} | {}",
            env!("CARGO_PKG_VERSION"),
            req.command,
            def.name,
            entry.name,
            req.seed,
            loaded.summary
        );
        detail!(
            "inputs: {} | parameters: {} | time limit {} s | loaded in {load_ms:.1} ms",
            req.inputs.files(),
            params
                .iter()
                .map(|(k, v)| format!("{k}={v}"))
                .collect::<Vec<_>>()
                .join(" "),
            req.time_limit
        );
    }
    let started = Instant::now();
    let outcome = solve(planner.as_ref(), &loaded.problem, &ctx);
    if let Some(live) = live {
        live.finish();
    }
    let runtime_ms = started.elapsed().as_secs_f64() * 1e3;
    let info = RunInfo {
        planner: entry.name.to_string(),
        params: params
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect::<BTreeMap<_, _>>(),
        seed: req.seed,
        runtime_ms,
        ..RunInfo::default()
    };
    Ok(Run {
        loaded,
        info,
        outcome,
        notes: planner.notes(),
        runtime_ms,
        planner: planner.name().to_string(),
    })
}

/// The generic `solve`: one [`run_planner`], print the summary, write the plan file, exit 0
/// solved, 3 not solved; an invalid plan (a bug) is an error (exit 1) and nothing is written.
fn solve_with<P: Problem + 'static>(def: &Def<P>, req: &SolveRequest) -> Result<u8, Fail> {
    // A saved program run by GP (`-p program=FILE`) is an input too.
    let programs: Vec<&Path> = req
        .params
        .iter()
        .filter(|(k, _)| k == "program")
        .map(|(_, v)| Path::new(v.as_str()))
        .collect();
    if req.format == Format::Lacam && req.out.is_none() {
        return Err(Fail(
            "--format lacam writes a file: give --out FILE (or --out - for stdout)".into(),
        ));
    }
    let outs: Vec<&Path> = [&req.out, &req.save_program]
        .into_iter()
        .flatten()
        .map(PathBuf::as_path)
        .collect();
    req.inputs.guard(&programs, &outs)?;
    for out in outs {
        if out.as_os_str() == "-" || out.as_os_str() == "/dev/stdout" {
            // stdout carries the file alone: no summaries around it.
            crate::output::set_verbosity(true, 0);
        }
    }
    let run = run_planner(def, req, true)?;
    report(
        &run.loaded.problem,
        &run.outcome,
        run.runtime_ms,
        &run.planner,
        &run.notes,
    )?;
    write_outputs(&run.loaded, req, run.info, &run.outcome, run.notes)?;
    if mrpp_core::stop_requested() {
        say!("interrupted: what was found before Ctrl-C is written (status interrupted)");
        return Ok(130);
    }
    Ok(if run.outcome.is_ok() { 0 } else { 3 })
}

/// Prints the outcome line, with each metric's lower bound where the problem knows one, and
/// the planner's notes: the short ones by default, all of them (once) with `-v`. An invalid plan
/// is an error.
fn report<P: Problem>(
    problem: &P,
    outcome: &Outcome<P>,
    runtime_ms: f64,
    planner: &str,
    notes: &Map<String, Value>,
) -> Result<(), Fail> {
    match outcome {
        Ok(s) => say!(
            "solved: {} | runtime {} ms",
            crate::output::metrics_with_bounds(
                &metrics_object(&s.metrics),
                &if crate::output::verbosity() >= 1 {
                    problem.lower_bounds()
                } else {
                    Vec::new()
                }
            ),
            crate::output::number(runtime_ms)
        ),
        Err(Unsolved::Invalid(why)) => {
            return Err(Fail(format!("invalid plan (a bug in mrpp): {why}")));
        }
        Err(why) => say!(
            "not solved: {why} | runtime {} ms",
            crate::output::number(runtime_ms)
        ),
    }
    if crate::output::verbosity() >= 2 {
        detail!("{planner} notes: {}", Value::Object(notes.clone()));
    } else {
        let short = pairs(&readable_notes(notes));
        if !short.is_empty() {
            say!("{planner}: {short}");
        }
    }
    Ok(())
}

/// The planner's notes with labels a person reads in a summary line (files keep the keys):
/// LaCAM's `first_cost`/`final_cost`/`search_cost` named after the objective they measure
/// (`first_sum_of_loss 2431`; the `objective` note is then implied), H*'s `finished_by` as
/// `solved_by` with what each value means.
fn readable_notes(notes: &Map<String, Value>) -> Map<String, Value> {
    let objective = notes.get("objective").and_then(Value::as_str);
    let mut out = Map::new();
    for (k, v) in notes {
        let (key, value) = match (k.as_str(), objective) {
            ("objective", Some(_)) if notes.contains_key("first_cost") => continue,
            ("first_cost" | "final_cost" | "search_cost", Some(o)) => {
                (format!("{}_{o}", k.trim_end_matches("_cost")), v.clone())
            }
            ("finished_by", _) => (
                "solved_by".to_string(),
                match v.as_str() {
                    Some("paper") => "the paper's steps".into(),
                    Some("repair") => "the paper's steps + mrpp's repair".into(),
                    Some("lacam") => "the paper's steps + LaCAM completion".into(),
                    _ => v.clone(),
                },
            ),
            _ => (k.clone(), v.clone()),
        };
        out.insert(key, value);
    }
    out
}

/// Writes the plan file and a made program, each atomically.
fn write_outputs<P: Problem>(
    loaded: &Loaded<P>,
    req: &SolveRequest,
    info: RunInfo,
    outcome: &Outcome<P>,
    notes: Map<String, Value>,
) -> Result<(), Fail> {
    let program = notes
        .get("program")
        .and_then(Value::as_str)
        .map(str::to_string);
    if let Some(out) = &req.out {
        let mut text = (loaded.write)(&loaded.problem, info, outcome, notes, req.format)?;
        if outcome.is_ok() && mrpp_core::stop_requested() && req.format == Format::Json {
            // A plan found before Ctrl-C (an anytime planner's best so far) is valid but says so.
            let mut env = mrpp_core::envelope::Envelope::<Value>::parse(&text, out)?;
            env.status = "interrupted".into();
            text = env.to_json();
        }
        write_atomic(out, &text)?;
        if outcome.is_ok() {
            say!("plan written to {}", out.display());
        } else {
            say!("run record (no plan) written to {}", out.display());
        }
    }
    match (&req.save_program, program) {
        (Some(path), Some(p)) => {
            write_atomic(path, format!("{p}\n"))?;
            say!("program written to {}", path.display());
        }
        (Some(path), None) => say!("no program made the plan: {} not written", path.display()),
        (None, _) => {}
    }
    Ok(())
}

/// A plan file that passed the validator and whose claimed metrics hold.
pub(crate) struct Checked {
    pub(crate) agents: usize,
    /// The validator's metrics.
    pub(crate) metrics: Map<String, Value>,
    /// Extra words for the summary (planner, seed, ...).
    pub(crate) about: String,
}

/// Reads a plan file, validates it and compares its claimed metrics with the validator's.
fn check_with<P: Problem + 'static>(
    def: &Def<P>,
    inputs: &Inputs,
    plan_path: &Path,
) -> Result<Checked, Fail> {
    let read = (def.read_plan)(inputs, plan_path)?;
    let m = read
        .problem
        .validate(&read.plan)
        .map_err(|v| Fail(format!("{}: invalid plan: {v}", plan_path.display())))?;
    let actual = metrics_object(&m);
    let disputed = mrpp_core::envelope::disputed(&read.claims, &Value::Object(actual.clone()));
    if let Some((k, claim, real)) = disputed.first() {
        return Err(Fail(format!(
            "{}: plan claims {k} {claim} but its paths give {real}",
            plan_path.display()
        )));
    }
    Ok(Checked {
        agents: read.problem.num_agents(),
        metrics: actual,
        about: read.about,
    })
}

/// The generic `validate`: exit 0 when the plan is valid and its claims hold, 1 naming the first
/// violation.
fn validate_with<P: Problem + 'static>(
    def: &Def<P>,
    inputs: &Inputs,
    plan_path: &Path,
) -> Result<u8, Fail> {
    let c = check_with(def, inputs, plan_path)?;
    detail!(
        "checked: every agent's path against the {} rules; the file's claimed metrics agree with \
         the validator's",
        def.name
    );
    // Every digit, for scripts (the summary line rounds).
    detail!("metrics: {}", Value::Object(c.metrics.clone()));
    say!(
        "valid: {} agents | {}{}",
        c.agents,
        pairs(&c.metrics),
        if c.about.is_empty() {
            String::new()
        } else {
            format!(" | {}", c.about)
        }
    );
    Ok(0)
}

/// `mrpp planners [--family F]`: every planner with its description and parameters.
pub(crate) fn list_planners(family: Option<&str>) -> Result<u8, Fail> {
    if let Some(f) = family.filter(|f| !FAMILIES.iter().any(|x| x.name() == *f)) {
        let names: Vec<&str> = FAMILIES.iter().map(|x| x.name()).collect();
        return Err(Fail(format!(
            "unknown family `{f}` (known: {})",
            names.join(", ")
        )));
    }
    for fam in FAMILIES
        .iter()
        .filter(|x| family.is_none_or(|f| x.name() == f))
    {
        for (name, about, params) in fam.planners() {
            out!("{name:<12} [{}] {about}", fam.name());
            for p in params {
                let kv = format!("{}={}", p.name, p.default);
                out!("    -p {kv:<24} {}", p.doc);
            }
        }
    }
    Ok(0)
}
