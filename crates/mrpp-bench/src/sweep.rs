//! Sweeps described as data: grid maps x scenarios x agent counts x planners (with parameters)
//! x runs, each job one validated run of one planner, its row a [`RunRecord`].
//!
//! The config is TOML (or the same fields given as flags):
//!
//! ```toml
//! name = "random-32"      # names the sweep in its manifest
//! seed = 0                # every job's seed derives from it and the job's key
//! runs = 2                # runs per (instance, agent count, planner)
//! time_limit = 10.0       # seconds per run
//! # peer_timeout = 300.0  # seconds before a peer is killed (default: 2 x time_limit + 10)
//!
//! [[instances]]
//! map = "../../data/movingai/random-32-32-20.map"    # relative to this file
//! scen = "../../data/movingai/random-32-32-20-random-1.scen"
//! agents = [10, 20, 50]   # the first N agents of the scenario; empty = all
//!
//! [[instances]]           # one instance per scenario k = 1..=25 ({k} in `scen`)
//! map = "../../data/movingai/den520d.map"
//! scen = "../../data/movingai/den520d-random-{k}.scen"
//! scens = "1..=25"
//! agents = "50..=1000 step 50"   # a range (and/or numbers: "50..=300 step 50, 333")
//!
//! [[planners]]
//! name = "whca"
//! params = { window = "8" }
//!
//! [[peers]]               # an external solver, run as a shell command per job
//! name = "lacam0"
//! command = "/path/to/lacam0/build/main -m {map} -i {scen} -N {agents} -s {seed} -t {time_limit} -o {out}"
//! ```
//!
//! A *peer* is any solver that writes the LaCAM text result (`solved=`, `starts=`, `goals=`,
//! `solution=`): the placeholders `{map}`, `{scen}`, `{agents}`, `{seed}` (the job's seed modulo
//! 2^31), `{time_limit}` (seconds) and `{out}` (a fresh file) are filled in (paths shell-quoted)
//! and the command runs under `sh -c` in its own process group, which is killed after
//! `peer_timeout` seconds (default: twice the time limit plus 10 s; recorded as `time_limit`).
//! Its result is read, checked to be for the same agents, and validated like mrpp's own plans;
//! its runtime is the file's `comp_time` (ms) when present, else the command's wall time. A peer's missing or
//! unreadable result is `gave_up`; a result the validator rejects is `invalid` (a peer's bug is
//! recorded, not fatal).
//!
//! Every solved run's record also has the time to its first plan (LaCAM\*'s own count, lacam3's
//! `comp_time_initial_solution`, else the runtime), its sum of loss, the lower bounds of the sum
//! of costs and loss (the agents' shortest-path distances summed) and of the makespan (their
//! largest; `mrpp solve` prints the same), the two ratios to the bound, and its peak memory: the heap bytes an mrpp planner
//! had live at most above those live when it started (counted by the binary's allocator, so
//! recorded only with `--jobs 1`: with more jobs at once the count would hold theirs too), or a peer's peak resident set (the largest `VmHWM` of its processes, sampled every 5 ms on Linux, which also
//! counts its code and libraries, so the two are not the same measure). The bounds take one
//! shortest-path search per agent, once per instance, before the first run's clock starts.
//!
//! Job key: `<map>/<scen>/a<agents>/<planner>[;k=v...]/<run>` (file stems). Pages: `records.csv`
//! (the records), `summary.md` (overall per solver: success, and medians of runtime, first plan,
//! the two ratios and peak memory over the instances every solver solved; per instance and planner: runs solved, mean sum of costs, mean
//! makespan and mean runtime over the solved runs; per map, agent count and solver: success rate
//! and median runtime), `success.svg` (success rate against agents, one panel per map) and
//! `runtime.svg` (median runtime of the solved runs against agents).

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Duration;

use serde::{Deserialize, Serialize};

use crate::harness::{
    Manifest, PeerRun, RunRecord, Sweep, params_text, run_peer_command, shell_quote,
};
use crate::stats::median;
use mrpp_core::error::{Error, Result, read_file};
use mrpp_core::registry::find;
use mrpp_core::seeds::derive_seed;
use mrpp_core::{Ctx, Deadline, MapfProblem, Params, Planner, Problem, Unsolved, accept, solve};

/// A sweep as data (TOML or flags).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepConfig {
    #[serde(default = "default_name")]
    pub name: String,
    #[serde(default)]
    pub seed: u64,
    #[serde(default = "one")]
    pub runs: usize,
    /// Seconds per run.
    #[serde(default = "ten")]
    pub time_limit: f64,
    /// Seconds after which a peer's process group is killed (recorded as `time_limit`); `None`
    /// = twice `time_limit` plus 10 s. At least `time_limit`. Raise it for a peer that takes long
    /// to write a large plan after its search: lacam0 with 10,000 agents on
    /// warehouse-20-40-10-2-1 found its plan in 41 s and wrote its 224 MB result 170 s later.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub peer_timeout: Option<f64>,
    pub instances: Vec<InstanceSpec>,
    #[serde(default)]
    pub planners: Vec<PlannerSpec>,
    /// External solvers run as commands (module doc).
    #[serde(default)]
    pub peers: Vec<PeerSpec>,
}

/// An external solver: a name and a command template (module doc).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PeerSpec {
    pub name: String,
    pub command: String,
}

impl std::str::FromStr for PeerSpec {
    type Err = String;
    /// `name=command template`.
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s.split_once('=') {
            Some((name, command)) if !name.trim().is_empty() && !command.trim().is_empty() => {
                Ok(PeerSpec {
                    name: name.trim().to_string(),
                    command: command.to_string(),
                })
            }
            _ => Err(format!(
                "expected a peer `name=command template`, e.g. `lacam0=/path/main -m {{map}} -i {{scen}} -N {{agents}} -s {{seed}} -t {{time_limit}} -o {{out}}`, got `{s}`"
            )),
        }
    }
}

/// The placeholders a peer's command may use.
const PLACEHOLDERS: [&str; 6] = ["map", "scen", "agents", "seed", "time_limit", "out"];

impl PeerSpec {
    /// Checks the template's placeholders.
    fn check(&self) -> Result<()> {
        let mut rest = self.command.as_str();
        while let Some(open) = rest.find('{') {
            let close = rest[open..].find('}').ok_or_else(|| {
                Error::Param(format!(
                    "peer `{}`: an unclosed `{{` in its command",
                    self.name
                ))
            })?;
            let name = &rest[open + 1..open + close];
            if !PLACEHOLDERS.contains(&name) {
                return Err(Error::Param(format!(
                    "peer `{}`: unknown placeholder `{{{name}}}` (known: {})",
                    self.name,
                    PLACEHOLDERS.map(|p| format!("{{{p}}}")).join(", ")
                )));
            }
            rest = &rest[open + close + 1..];
        }
        if !self.command.contains("{out}") {
            return Err(Error::Param(format!(
                "peer `{}`: its command must write its result to `{{out}}`",
                self.name
            )));
        }
        Ok(())
    }
}

/// `s` quoted for `sh`.
fn default_name() -> String {
    "bench".into()
}
fn one() -> usize {
    1
}
fn ten() -> f64 {
    10.0
}

/// A grid map and scenario, at some agent counts.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InstanceSpec {
    pub map: PathBuf,
    pub scen: PathBuf,
    /// The first N agents of the scenario, for each N; empty = all of them. In TOML a list of
    /// numbers or a string of numbers and ranges (`"50..=1000 step 50, 1024"`).
    #[serde(default, deserialize_with = "agent_counts")]
    pub agents: Vec<usize>,
    /// Scenario numbers (`"1..=25"`, same syntax as `agents`): the instance stands for one per
    /// number `k`, with `{k}` in `scen` replaced by it ([`SweepConfig::load`] expands them).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scens: Option<String>,
}

/// Agent counts: a list of numbers, or a string of numbers and ranges ([`parse_counts`]).
fn agent_counts<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> std::result::Result<Vec<usize>, D::Error> {
    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Counts {
        List(Vec<usize>),
        Text(String),
    }
    match Counts::deserialize(d)? {
        Counts::List(v) => Ok(v),
        Counts::Text(t) => parse_counts(&t).map_err(serde::de::Error::custom),
    }
}

/// Numbers and ranges, comma-separated: `7`, `A..=B` (every number from A to B) and
/// `A..=B step S` (A, A+S, ... up to B), e.g. `"50..=300 step 50, 333"`.
///
/// # Errors
/// A message naming the part that is not a number or range (or a range that is empty, or a
/// zero step).
pub fn parse_counts(text: &str) -> std::result::Result<Vec<usize>, String> {
    let number = |s: &str| {
        s.trim()
            .parse::<usize>()
            .map_err(|_| format!("`{}` is not a whole number (in `{text}`)", s.trim()))
    };
    let mut out = Vec::new();
    for part in text.split(',') {
        let part = part.trim();
        let Some((from, rest)) = part.split_once("..=") else {
            out.push(number(part)?);
            continue;
        };
        let (to, step) = match rest.split_once("step") {
            Some((to, step)) => (number(to)?, number(step)?),
            None => (number(rest)?, 1),
        };
        let from = number(from)?;
        if step == 0 || from > to || (to - from) / step > 1_000_000 {
            return Err(format!(
                "`{part}`: a range is `A..=B` or `A..=B step S` with A <= B and S >= 1 (in `{text}`)"
            ));
        }
        out.extend((from..=to).step_by(step));
    }
    Ok(out)
}

/// A registered planner with parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlannerSpec {
    pub name: String,
    /// Parameter values: strings, numbers or booleans (`window = 8` or `window = "8"`).
    #[serde(default, deserialize_with = "scalars")]
    pub params: BTreeMap<String, String>,
}

/// A table of scalars as text.
fn scalars<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> std::result::Result<BTreeMap<String, String>, D::Error> {
    let raw = BTreeMap::<String, toml::Value>::deserialize(d)?;
    raw.into_iter()
        .map(|(k, v)| match v {
            toml::Value::String(s) => Ok((k, s)),
            toml::Value::Integer(i) => Ok((k, i.to_string())),
            toml::Value::Float(f) => Ok((k, f.to_string())),
            toml::Value::Boolean(b) => Ok((k, b.to_string())),
            other => Err(serde::de::Error::custom(format!(
                "parameter `{k}` must be a string, number or boolean, not {other}"
            ))),
        })
        .collect()
}

impl SweepConfig {
    /// A configuration as a manifest recorded it ([`Sweep::config`] of a [`GridSweep`]: TOML with
    /// the paths as resolved), so a merge rebuilds exactly the sweep its parts ran.
    pub fn from_recorded(text: &str) -> Result<Self> {
        toml::from_str(text).map_err(|e| {
            Error::Internal(format!(
                "a recorded sweep configuration does not read back: {e}"
            ))
        })
    }

    /// Reads a TOML sweep; relative paths in it are taken from the file's folder.
    pub fn load(path: &Path) -> Result<Self> {
        let text = read_file(path)?;
        if text.trim_start().starts_with('{') {
            return Err(Error::parse(
                path,
                1,
                "this is JSON; a bench config is TOML (see bench/configs/example.toml)",
            ));
        }
        let mut cfg: SweepConfig = toml::from_str(&text).map_err(|e| {
            let line = e
                .span()
                .map(|s| text[..s.start].lines().count().max(1))
                .unwrap_or(1);
            Error::parse(path, line, e.message().to_string())
        })?;
        let dir = path.parent().unwrap_or(Path::new(""));
        for i in &mut cfg.instances {
            i.map = dir.join(&i.map);
            i.scen = dir.join(&i.scen);
        }
        cfg.expand_scens().map_err(|e| Error::parse(path, 1, e))?;
        Ok(cfg)
    }

    /// Replaces every instance with `scens` by one instance per scenario number (`{k}` in its
    /// `scen` replaced by the number).
    ///
    /// # Errors
    /// `scens` does not parse, or `scen` has no `{k}`.
    pub fn expand_scens(&mut self) -> std::result::Result<(), String> {
        let mut out = Vec::with_capacity(self.instances.len());
        for spec in std::mem::take(&mut self.instances) {
            let Some(scens) = &spec.scens else {
                out.push(spec);
                continue;
            };
            let pattern = spec.scen.to_string_lossy().into_owned();
            if !pattern.contains("{k}") {
                return Err(format!(
                    "instance with scens = \"{scens}\": its scen `{pattern}` needs `{{k}}` where the number goes"
                ));
            }
            for k in parse_counts(scens)? {
                out.push(InstanceSpec {
                    scen: PathBuf::from(pattern.replace("{k}", &k.to_string())),
                    scens: None,
                    ..spec.clone()
                });
            }
        }
        self.instances = out;
        Ok(())
    }

    /// The number of jobs (instances x agent counts x solvers x runs), counted without reading
    /// any map or scenario; `None` when an instance has no agent counts (all of its scenario's
    /// agents: the count needs the file).
    pub fn job_count(&self) -> Option<usize> {
        let solvers = self.planners.len() + self.peers.len();
        let mut instances = 0;
        for spec in &self.instances {
            if spec.agents.is_empty() {
                return None;
            }
            instances += spec.agents.len();
        }
        Some(instances * solvers * self.runs)
    }
}

/// One loaded instance of the sweep.
struct Loaded {
    /// `<map stem>/<scen stem>/a<agents>`.
    name: String,
    /// The map's file stem (figures have one panel per map).
    map_name: String,
    map: mrpp_grid::GridMap,
    map_path: PathBuf,
    scen_path: PathBuf,
    problem: MapfProblem,
    /// (sum, max) of the agents' shortest-path distances, computed by the first job that needs
    /// them ([`Loaded::bounds`]).
    bounds: std::sync::OnceLock<Option<(u64, u64)>>,
}

impl Loaded {
    /// The lower bounds of the sum of costs (and of loss) and of the makespan
    /// ([`mrpp_core::mapf::search::distance::lower_bounds`]: the sum and the largest of the
    /// agents' start-goal distances); `None` when a goal cannot be reached.
    fn bounds(&self) -> Option<(u64, u64)> {
        *self.bounds.get_or_init(|| {
            let inst = self.problem.instance();
            mrpp_core::mapf::search::distance::lower_bounds(
                self.problem.graph(),
                &inst.starts,
                &inst.goals,
            )
            .ok()
        })
    }

    /// The quality columns of a solved run's record: sum of loss, the lower bounds and the
    /// ratios (module doc).
    fn quality(
        &self,
        plan: &mrpp_core::mapf::plan::Plan,
        m: &mrpp_core::Metrics,
        rec: &mut RunRecord,
    ) {
        let loss = plan.sum_of_loss(&self.problem.instance().goals);
        rec.sum_of_loss = Some(loss);
        let Some((lb, makespan_lb)) = self.bounds() else {
            return;
        };
        // A bound of 0 (every agent starts on its goal) leaves the ratios empty.
        let ratio = |x: u64| (lb > 0).then(|| x as f64 / lb as f64);
        rec.lower_bound = Some(lb);
        rec.makespan_lower_bound = Some(makespan_lb);
        rec.sum_of_costs_ratio = ratio(m.sum_of_costs);
        rec.sum_of_loss_ratio = ratio(loss);
    }
}

/// Who solves a job: a registered planner or a peer.
enum Solver {
    Own(Built),
    Peer(PeerSpec),
}

impl Solver {
    fn label(&self) -> &str {
        match self {
            Solver::Own(b) => &b.label,
            Solver::Peer(p) => &p.name,
        }
    }
}

/// One planner of the sweep, built.
struct Built {
    label: String,
    params: String,
    planner: Box<dyn Planner<MapfProblem>>,
}

/// A [`SweepConfig`] ready to run.
pub struct GridSweep {
    pub cfg: SweepConfig,
    instances: Vec<Loaded>,
    planners: Vec<Solver>,
    jobs: Vec<(usize, usize, usize)>,
    /// Consecutive `peer_failed` runs per solver (peers only).
    peer_failures: Vec<std::sync::atomic::AtomicUsize>,
}

/// Consecutive failed runs of one peer command after which a sweep stops.
pub const MAX_PEER_FAILURES: usize = 3;

fn stem(p: &Path) -> String {
    p.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

impl GridSweep {
    /// Loads every instance and builds every planner (from the grid registry).
    ///
    /// # Errors
    /// A file error naming file and line; an unknown planner or parameter; absurd numbers.
    pub fn new(cfg: SweepConfig) -> Result<Self> {
        check(&cfg)?;
        let mut instances = Vec::new();
        for spec in &cfg.instances {
            let counts: Vec<Option<usize>> = if spec.agents.is_empty() {
                vec![None]
            } else {
                spec.agents.iter().map(|&n| Some(n)).collect()
            };
            for n in counts {
                let (map, problem) = mrpp_grid::load_problem(&spec.map, &spec.scen, n)?;
                let name = format!(
                    "{}/{}/a{}",
                    stem(&spec.map),
                    stem(&spec.scen),
                    problem.instance().num_agents()
                );
                instances.push(Loaded {
                    name,
                    map_name: stem(&spec.map),
                    map,
                    map_path: spec.map.clone(),
                    scen_path: spec.scen.clone(),
                    problem,
                    bounds: std::sync::OnceLock::new(),
                });
            }
        }
        let mut seen_names = std::collections::BTreeSet::new();
        for inst in &instances {
            if !seen_names.insert(inst.name.clone()) {
                return Err(Error::Param(format!(
                    "instance `{}` is listed twice (map and scenario file names and the agent count name an instance)",
                    inst.name
                )));
            }
        }
        let mut planners = cfg
            .planners
            .iter()
            .map(|p| build(p).map(Solver::Own))
            .collect::<Result<Vec<_>>>()?;
        for peer in &cfg.peers {
            peer.check()?;
            if planners.iter().any(|s| s.label() == peer.name) {
                return Err(Error::Param(format!(
                    "`{}` names two solvers of the sweep",
                    peer.name
                )));
            }
            planners.push(Solver::Peer(peer.clone()));
        }
        let (i, p, r) = (instances.len(), planners.len(), cfg.runs);
        let jobs = (0..i)
            .flat_map(|i| (0..p).flat_map(move |p| (0..r).map(move |r| (i, p, r))))
            .collect();
        Ok(GridSweep {
            cfg,
            instances,
            peer_failures: planners.iter().map(|_| Default::default()).collect(),
            planners,
            jobs,
        })
    }
}

fn check(cfg: &SweepConfig) -> Result<()> {
    if !(1..=10_000).contains(&cfg.runs) {
        return Err(Error::Param(format!(
            "runs must be between 1 and 10000, got {}",
            cfg.runs
        )));
    }
    if !(cfg.time_limit.is_finite() && cfg.time_limit > 0.0 && cfg.time_limit <= 1e7) {
        return Err(Error::Param(format!(
            "time_limit must be a positive number of seconds, got {}",
            cfg.time_limit
        )));
    }
    if let Some(t) = cfg.peer_timeout
        && !(t.is_finite() && t >= cfg.time_limit && t <= 1e7)
    {
        return Err(Error::Param(format!(
            "peer_timeout must be a number of seconds at least time_limit ({}), got {t}",
            cfg.time_limit
        )));
    }
    if cfg.instances.is_empty() || (cfg.planners.is_empty() && cfg.peers.is_empty()) {
        return Err(Error::Param(
            "a sweep needs at least one instance and one planner or peer".into(),
        ));
    }
    Ok(())
}

fn build(spec: &PlannerSpec) -> Result<Built> {
    let entry = find(mrpp_grid::PLANNERS, &spec.name).ok_or_else(|| {
        let known: Vec<&str> = mrpp_grid::PLANNERS.iter().map(|e| e.name).collect();
        Error::Param(format!(
            "`{}` is not a grid planner (known: {})",
            spec.name,
            known.join(", ")
        ))
    })?;
    let given: Vec<(String, String)> = spec.params.clone().into_iter().collect();
    let params = Params::resolve(entry.name, entry.params, &given)?;
    let planner = (entry.build)(&params)?;
    let label = if given.is_empty() {
        spec.name.clone()
    } else {
        let g: Vec<(&str, &str)> = given
            .iter()
            .map(|(k, v)| (k.as_str(), v.as_str()))
            .collect();
        format!("{};{}", spec.name, params_text(g))
    };
    Ok(Built {
        label,
        params: params_text(params.iter()),
        planner,
    })
}

impl Sweep for GridSweep {
    type Job = (usize, usize, usize);
    type Row = RunRecord;

    fn name(&self) -> &str {
        &self.cfg.name
    }

    fn jobs(&self) -> &[(usize, usize, usize)] {
        &self.jobs
    }

    fn key(&self, &(i, p, r): &(usize, usize, usize)) -> String {
        format!(
            "{}/{}/{r}",
            self.instances[i].name,
            self.planners[p].label()
        )
    }

    fn run(&self, job: &(usize, usize, usize)) -> Result<RunRecord> {
        let (i, p, run) = *job;
        let seed = derive_seed(self.cfg.seed, &self.key(job));
        let b = match &self.planners[p] {
            Solver::Own(b) => b,
            Solver::Peer(peer) => return self.run_peer_counted(p, peer, i, run, seed, job),
        };
        // A planner of its own per job, so that its notes (the first plan's time) are this
        // run's even when jobs run in parallel.
        let planner = build(&self.cfg.planners[p])?.planner;
        let inst = &self.instances[i];
        inst.bounds(); // before the clock starts
        let ctx = Ctx::new(
            seed,
            Deadline::after(Duration::from_secs_f64(self.cfg.time_limit)),
        );
        let live = mrpp_core::memory::live_bytes();
        mrpp_core::memory::reset_peak();
        let started = std::time::Instant::now();
        let outcome = solve(planner.as_ref(), &inst.problem, &ctx);
        let runtime_ms = started.elapsed().as_secs_f64() * 1e3;
        let peak = mrpp_core::memory::peak_bytes().saturating_sub(live);
        // The counter is process-wide: with other jobs running beside this one it would hold
        // their bytes too, so the peak is only recorded when jobs run one at a time.
        let alone = crate::harness::threads() == 1;
        let m = match &outcome {
            Err(Unsolved::Invalid(why)) => return Err(Error::Internal(why.clone())),
            Err(_) => None,
            Ok(s) => Some(s.metrics),
        };
        let mut rec = RunRecord {
            job: 0,
            key: String::new(),
            family: mrpp_grid::FAMILY.into(),
            instance: inst.name.clone(),
            planner: planner.name().to_string(),
            params: b.params.clone(),
            run,
            seed,
            status: outcome
                .as_ref()
                .map_or_else(|e| e.status().into(), |_| "solved".into()),
            sum_of_costs: m.map(|m| m.sum_of_costs),
            makespan: m.map(|m| m.makespan),
            sum_of_moves: m.map(|m| m.sum_of_moves),
            runtime_ms,
            peak_memory_mb: (alone && peak > 0).then(|| peak as f64 / 1e6),
            ..Default::default()
        };
        if let Ok(solved) = &outcome {
            rec.first_solution_ms = Some(
                planner
                    .notes()
                    .get("first_solution_ms")
                    .and_then(serde_json::Value::as_f64)
                    .unwrap_or(runtime_ms),
            );
            inst.quality(&solved.plan, &solved.metrics, &mut rec);
        }
        Ok(rec)
    }

    fn records(&self, row: &RunRecord) -> Vec<RunRecord> {
        vec![row.clone()]
    }

    fn pages(&self, rows: &[&RunRecord], m: &Manifest) -> Result<Vec<(String, String)>> {
        let (success, runtime) = self.figures(rows)?;
        Ok(vec![
            ("summary.md".into(), self.summary_page(rows, m)),
            ("success.svg".into(), success),
            ("runtime.svg".into(), runtime),
            ("solved_over_time.svg".into(), self.solved_over_time(rows)?),
        ])
    }

    fn summary(&self, rows: &[&RunRecord]) -> String {
        self.table(rows)
    }

    /// The sweep as TOML (paths as resolved).
    fn config(&self) -> String {
        toml::to_string(&self.cfg).unwrap_or_else(|e| format!("unprintable config: {e}"))
    }
}

impl GridSweep {
    /// Per instance and planner: runs solved, mean sum of costs, makespan and runtime.
    fn table(&self, rows: &[&RunRecord]) -> String {
        let mut s = String::from(
            "| instance | planner | solved | sum of costs | makespan | runtime ms |\n|---|---|---|---|---|---|\n",
        );
        for inst in &self.instances {
            for b in &self.planners {
                let mine: Vec<&&RunRecord> = rows
                    .iter()
                    .filter(|r| r.instance == inst.name && self.is_of(r, b))
                    .collect();
                let ok: Vec<&&&RunRecord> = mine.iter().filter(|r| r.status == "solved").collect();
                let mean = |f: &dyn Fn(&RunRecord) -> f64| {
                    if ok.is_empty() {
                        String::from("-")
                    } else {
                        format!(
                            "{:.1}",
                            ok.iter().map(|r| f(r)).sum::<f64>() / ok.len() as f64
                        )
                    }
                };
                let _ = writeln!(
                    s,
                    "| {} | {} | {}/{} | {} | {} | {} |",
                    inst.name,
                    b.label(),
                    ok.len(),
                    mine.len(),
                    mean(&|r| r.sum_of_costs.unwrap_or(0) as f64),
                    mean(&|r| r.makespan.unwrap_or(0) as f64),
                    mean(&|r| r.runtime_ms)
                );
            }
        }
        s
    }

    fn summary_page(&self, rows: &[&RunRecord], m: &Manifest) -> String {
        format!(
            "# Sweep `{}`\n\n`mrpp {}` — mrpp {}, seed {}, {} runs per cell, {} s per run, wall time {:.1} s, {} threads.\n\n## Overall\n\n![runs solved within a time](solved_over_time.svg)\n\n{}\n## Per instance\n\n{}\n## Success rate and median runtime by agents\n\n![success rate](success.svg)\n![runtime](runtime.svg)\n\n{}",
            self.cfg.name,
            m.sweep_command().join(" "),
            m.mrpp_version,
            self.cfg.seed,
            self.cfg.runs,
            self.cfg.time_limit,
            m.wall_seconds,
            m.threads,
            self.overall_table(rows),
            self.table(rows),
            self.by_agents_table(rows)
        )
    }

    /// Per solver: runs solved of its runs, and the median runtime of its solved runs, over all
    /// of them and over the instances every solver solved in every run (the fair comparison of
    /// speed: each solver's median over the same instances).
    fn overall_table(&self, rows: &[&RunRecord]) -> String {
        let solved_by_all = |inst: &str| {
            self.planners.iter().all(|b| {
                let mine: Vec<&&RunRecord> = rows
                    .iter()
                    .filter(|r| r.instance == inst && self.is_of(r, b))
                    .collect();
                !mine.is_empty() && mine.iter().all(|r| r.status == "solved")
            })
        };
        let common: Vec<&str> = self
            .instances
            .iter()
            .map(|i| i.name.as_str())
            .filter(|i| solved_by_all(i))
            .collect();
        let mut s = format!(
            "| solver | solved | success % | median runtime ms, its solved runs | median over the {} instances every solver solved: runtime ms | first plan ms | sum of costs / lower bound | sum of loss / lower bound | peak memory MB (mrpp: heap; peers: resident set) |\n|---|---|---|---|---|---|---|---|---|\n",
            common.len()
        );
        for b in &self.planners {
            let mine: Vec<&&RunRecord> = rows.iter().filter(|r| self.is_of(r, b)).collect();
            let ok: Vec<f64> = mine
                .iter()
                .filter(|r| r.status == "solved")
                .map(|r| r.runtime_ms)
                .collect();
            let shared: Vec<&&&RunRecord> = mine
                .iter()
                .filter(|r| r.status == "solved" && common.contains(&r.instance.as_str()))
                .collect();
            let med = |f: &dyn Fn(&RunRecord) -> Option<f64>, digits: usize| {
                median(shared.iter().filter_map(|r| f(r)).collect())
                    .map_or("-".into(), |m| format!("{m:.digits$}"))
            };
            let _ = writeln!(
                s,
                "| {} | {}/{} | {:.1} | {} | {} | {} | {} | {} | {} |",
                b.label(),
                ok.len(),
                mine.len(),
                if mine.is_empty() {
                    0.0
                } else {
                    100.0 * ok.len() as f64 / mine.len() as f64
                },
                median(ok).map_or("-".into(), |m| format!("{m:.1}")),
                med(&|r| Some(r.runtime_ms), 1),
                med(&|r| r.first_solution_ms, 1),
                med(&|r| r.sum_of_costs_ratio, 3),
                med(&|r| r.sum_of_loss_ratio, 3),
                med(&|r| r.peak_memory_mb, 1),
            );
        }
        s
    }

    /// `solved_over_time.svg`: per solver, the share of its runs solved within a time, against
    /// that time on a log scale (the form of the LaCAM\* paper's figure, Okumura, IJCAI 2023).
    fn solved_over_time(&self, rows: &[&RunRecord]) -> Result<String> {
        use crate::report::{Panel, Series, line_panels};
        let limit_ms = self.cfg.time_limit * 1000.0;
        let series = self
            .planners
            .iter()
            .map(|b| {
                let mine: Vec<&&RunRecord> = rows.iter().filter(|r| self.is_of(r, b)).collect();
                let mut times: Vec<f64> = mine
                    .iter()
                    .filter(|r| r.status == "solved")
                    .map(|r| r.runtime_ms.max(1.0))
                    .collect();
                times.sort_by(f64::total_cmp);
                let share = |k: usize| 100.0 * k as f64 / mine.len().max(1) as f64;
                let mut points = vec![(0.0, 0.0)];
                for (k, t) in times.iter().enumerate() {
                    points.push((t.log10(), share(k)));
                    points.push((t.log10(), share(k + 1)));
                }
                points.push((limit_ms.max(1.0).log10(), share(times.len())));
                Series {
                    name: b.label().to_string(),
                    points,
                    ..Series::default()
                }
            })
            .collect();
        let panel = Panel {
            title: format!(
                "{} runs per solver",
                rows.len() / self.planners.len().max(1)
            ),
            series,
        };
        line_panels(
            "Runs solved within a time",
            "runtime, log10 ms (0 = 1 ms, 3 = 1 s)",
            "solved %",
            &[panel],
        )
        .map_err(Error::Internal)
    }

    /// Whether record `r` is a run of solver `b`.
    fn is_of(&self, r: &RunRecord, b: &Solver) -> bool {
        match b {
            Solver::Own(b) => r.params == b.params && r.planner == b.planner.name(),
            Solver::Peer(p) => r.params == "peer" && r.planner == p.name,
        }
    }

    /// Per map, agent count and solver: (success rate in %, median runtime of the solved runs
    /// in ms), over all scenarios and runs of that cell.
    fn by_agents(&self, rows: &[&RunRecord]) -> Vec<(String, usize, usize, f64, Option<f64>)> {
        let mut cells: Vec<(String, usize)> = Vec::new();
        for inst in &self.instances {
            let key = (inst.map_name.clone(), inst.problem.num_agents());
            if !cells.contains(&key) {
                cells.push(key);
            }
        }
        let mut out = Vec::new();
        for (map, agents) in cells {
            for (s, b) in self.planners.iter().enumerate() {
                let mine: Vec<&&RunRecord> = rows
                    .iter()
                    .filter(|r| {
                        self.is_of(r, b)
                            && self.instances.iter().any(|i| {
                                i.name == r.instance
                                    && i.map_name == map
                                    && i.problem.num_agents() == agents
                            })
                    })
                    .collect();
                if mine.is_empty() {
                    continue;
                }
                let times: Vec<f64> = mine
                    .iter()
                    .filter(|r| r.status == "solved")
                    .map(|r| r.runtime_ms)
                    .collect();
                let rate = 100.0 * times.len() as f64 / mine.len() as f64;
                out.push((map.clone(), agents, s, rate, median(times)));
            }
        }
        out
    }

    fn by_agents_table(&self, rows: &[&RunRecord]) -> String {
        let mut s = String::from(
            "| map | agents | solver | success % | median runtime ms (solved) |\n|---|---|---|---|---|\n",
        );
        for (map, agents, solver, rate, median) in self.by_agents(rows) {
            let _ = writeln!(
                s,
                "| {map} | {agents} | {} | {rate:.0} | {} |",
                self.planners[solver].label(),
                median.map_or("-".into(), |m| format!("{m:.1}"))
            );
        }
        s
    }

    /// `success.svg` and `runtime.svg`: one panel per map, one line per solver.
    fn figures(&self, rows: &[&RunRecord]) -> Result<(String, String)> {
        use crate::report::{Panel, Series, line_panels};
        let cells = self.by_agents(rows);
        let mut maps: Vec<&str> = Vec::new();
        for (m, ..) in &cells {
            if !maps.contains(&m.as_str()) {
                maps.push(m);
            }
        }
        let panels = |runtime: bool| -> Vec<Panel> {
            maps.iter()
                .map(|&map| Panel {
                    title: map.to_string(),
                    series: self
                        .planners
                        .iter()
                        .enumerate()
                        .map(|(k, b)| Series {
                            name: b.label().to_string(),
                            points: cells
                                .iter()
                                .filter(|c| c.0 == map && c.2 == k)
                                .filter_map(|c| {
                                    if runtime {
                                        c.4.map(|m| (c.1 as f64, m))
                                    } else {
                                        Some((c.1 as f64, c.3))
                                    }
                                })
                                .collect(),
                            ..Series::default()
                        })
                        .collect(),
                })
                .collect()
        };
        let draw = |title: &str, y: &str, runtime: bool| {
            line_panels(title, "agents", y, &panels(runtime)).map_err(Error::Internal)
        };
        Ok((
            draw("Success rate", "solved %", false)?,
            draw("Median runtime of solved runs", "ms", true)?,
        ))
    }

    /// [`Self::run_peer`], counting the peer's consecutive `peer_failed` runs: after
    /// [`MAX_PEER_FAILURES`] in a row the sweep stops with an error naming the peer, its last
    /// failure and its command, instead of recording a broken command as a planner that solved
    /// nothing.
    fn run_peer_counted(
        &self,
        p: usize,
        peer: &PeerSpec,
        i: usize,
        run: usize,
        seed: u64,
        job: &(usize, usize, usize),
    ) -> Result<RunRecord> {
        use std::sync::atomic::Ordering;
        let rec = self.run_peer(peer, i, run, seed, job);
        let failures = &self.peer_failures[p];
        if rec.status != "peer_failed" {
            failures.store(0, Ordering::Relaxed);
            return Ok(rec);
        }
        let n = failures.fetch_add(1, Ordering::Relaxed) + 1;
        if n >= MAX_PEER_FAILURES {
            return Err(Error::Param(format!(
                "peer `{}` failed {n} runs in a row (last: {}); check its command: {}",
                peer.name, rec.note, peer.command
            )));
        }
        Ok(rec)
    }

    /// A `peer_failed` record of peer `peer` on instance `i`.
    fn peer_failed(
        &self,
        peer: &PeerSpec,
        i: usize,
        run: usize,
        seed: u64,
        note: String,
        runtime_ms: f64,
    ) -> RunRecord {
        RunRecord {
            job: 0,
            key: String::new(),
            family: mrpp_grid::FAMILY.into(),
            instance: self.instances[i].name.clone(),
            planner: peer.name.clone(),
            params: "peer".into(),
            run,
            seed,
            status: "peer_failed".into(),
            sum_of_costs: None,
            makespan: None,
            sum_of_moves: None,
            runtime_ms,
            note,
            ..Default::default()
        }
    }

    /// Runs peer `peer` on instance `i` (module doc).
    fn run_peer(
        &self,
        peer: &PeerSpec,
        i: usize,
        run: usize,
        seed: u64,
        job: &(usize, usize, usize),
    ) -> RunRecord {
        let inst = &self.instances[i];
        let n = inst.problem.num_agents();
        let failed =
            |note: String, runtime_ms: f64| self.peer_failed(peer, i, run, seed, note, runtime_ms);
        let record = |status: &str, m: Option<mrpp_core::Metrics>, runtime_ms: f64| RunRecord {
            job: 0,
            key: String::new(),
            family: mrpp_grid::FAMILY.into(),
            instance: inst.name.clone(),
            planner: peer.name.clone(),
            params: "peer".into(),
            run,
            seed,
            status: status.into(),
            sum_of_costs: m.map(|m| m.sum_of_costs),
            makespan: m.map(|m| m.makespan),
            sum_of_moves: m.map(|m| m.sum_of_moves),
            runtime_ms,
            ..Default::default()
        };
        // One folder per job (its key is unique in the sweep), emptied first.
        let dir = std::env::temp_dir().join(format!(
            "mrpp-peer-{}-{:016x}",
            std::process::id(),
            derive_seed(0, &self.key(job))
        ));
        let _ = std::fs::remove_dir_all(&dir);
        if let Err(e) = std::fs::create_dir_all(&dir) {
            return failed(format!("cannot make {}: {e}", dir.display()), 0.0);
        }
        let out = dir.join("result.txt");
        let stderr_path = dir.join("stderr.txt");
        let mut command = peer.command.clone();
        for (k, v) in [
            ("map", shell_quote(&inst.map_path.to_string_lossy())),
            ("scen", shell_quote(&inst.scen_path.to_string_lossy())),
            ("agents", n.to_string()),
            ("seed", (seed % (1 << 31)).to_string()),
            ("time_limit", self.cfg.time_limit.to_string()),
            ("out", shell_quote(&out.to_string_lossy())),
        ] {
            command = command.replace(&format!("{{{k}}}"), &v);
        }
        let limit = Duration::from_secs_f64(
            self.cfg
                .peer_timeout
                .unwrap_or(self.cfg.time_limit * 2.0 + 10.0),
        );
        let ran = run_peer_command(&command, &out, &stderr_path, limit);
        let _ = std::fs::remove_dir_all(&dir);
        let (text, wall_ms, peak_rss_kb) = match ran {
            PeerRun::Failed { note, wall_ms } => return failed(note, wall_ms),
            PeerRun::Killed { wall_ms } => return record("time_limit", None, wall_ms),
            PeerRun::Done {
                text,
                wall_ms,
                peak_rss_kb,
            } => (text, wall_ms, peak_rss_kb),
        };
        // A peer's own count of milliseconds under `key`, when it is a sane number.
        let ms = |key: &str| {
            text.lines()
                .find_map(|l| l.strip_prefix(key)?.strip_prefix('='))
                .and_then(|v| v.trim().parse::<f64>().ok())
                .filter(|&ms| ms.is_finite() && (0.0..1e12).contains(&ms))
        };
        let runtime_ms = ms("comp_time").unwrap_or(wall_ms);
        let record = |status: &str, m: Option<mrpp_core::Metrics>, runtime_ms: f64| RunRecord {
            peak_memory_mb: peak_rss_kb.map(|kb| kb as f64 * 1024.0 / 1e6),
            ..record(status, m, runtime_ms)
        };
        if text
            .lines()
            .any(|l| matches!(l.trim(), "solved=0" | "solved=false"))
        {
            let status = if runtime_ms >= self.cfg.time_limit * 1e3 {
                "time_limit"
            } else {
                "gave_up"
            };
            return record(status, None, runtime_ms);
        }
        let Ok((theirs, plan, claims)) =
            mrpp_grid::io::lacam::parse_lacam_with_claims(&text, &out, &inst.map)
        else {
            return record("invalid", None, runtime_ms);
        };
        let ours = inst.problem.instance();
        if theirs.starts != ours.starts || theirs.goals != ours.goals {
            return record("invalid", None, runtime_ms);
        }
        match accept(
            &inst.problem,
            plan,
            &peer.name,
            Duration::from_secs_f64(runtime_ms / 1e3),
        ) {
            // A peer's claimed soc / makespan / sum_of_loss must hold too (lacam0 and lacam3
            // count them as mrpp does).
            Ok(s)
                if claims
                    .check(
                        &out,
                        &s.plan,
                        &ours.goals,
                        s.metrics.sum_of_costs,
                        s.metrics.makespan,
                    )
                    .is_ok() =>
            {
                let mut rec = record("solved", Some(s.metrics), runtime_ms);
                rec.first_solution_ms =
                    Some(ms("comp_time_initial_solution").unwrap_or(runtime_ms));
                inst.quality(&s.plan, &s.metrics, &mut rec);
                rec
            }
            _ => record("invalid", None, runtime_ms),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_and_ranges() {
        assert_eq!(
            parse_counts("50..=200 step 50, 333").unwrap(),
            [50, 100, 150, 200, 333]
        );
        assert_eq!(parse_counts("1..=3").unwrap(), [1, 2, 3]);
        assert_eq!(parse_counts(" 7 ").unwrap(), [7]);
        assert_eq!(parse_counts("50..=1000 step 50").unwrap().len(), 20);
        for bad in ["", "x", "5..=1", "1..=5 step 0", "1..=x", "1..=10 step"] {
            assert!(parse_counts(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn scens_expand_and_jobs_count_without_files() {
        let dir = std::env::temp_dir().join(format!("mrpp-sweep-scens-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("c.toml");
        std::fs::write(
            &path,
            "runs = 2\n[[instances]]\nmap = \"m.map\"\nscen = \"m-random-{k}.scen\"\nscens = \"1..=3\"\nagents = \"10..=30 step 10\"\n[[planners]]\nname = \"lacam\"\n",
        )
        .unwrap();
        let cfg = SweepConfig::load(&path).unwrap();
        assert_eq!(cfg.instances.len(), 3);
        assert_eq!(cfg.instances[2].scen, dir.join("m-random-3.scen"));
        assert_eq!(cfg.instances[0].agents, [10, 20, 30]);
        assert_eq!(cfg.job_count(), Some(3 * 3 * 2));
        // Without `{k}` the scenario numbers have nowhere to go.
        std::fs::write(
            &path,
            "[[instances]]\nmap = \"m.map\"\nscen = \"m.scen\"\nscens = \"1..=3\"\n",
        )
        .unwrap();
        let err = SweepConfig::load(&path).unwrap_err().to_string();
        assert!(err.contains("{k}"), "{err}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
