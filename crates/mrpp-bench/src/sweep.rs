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
//!
//! [[instances]]
//! map = "../../data/movingai/random-32-32-20.map"    # relative to this file
//! scen = "../../data/movingai/random-32-32-20-random-1.scen"
//! agents = [10, 20, 50]   # the first N agents of the scenario; empty = all
//!
//! [[planners]]
//! name = "whca"
//! params = { window = "8" }
//! ```
//!
//! Job key: `<map>/<scen>/a<agents>/<planner>[;k=v...]/<run>` (file stems). Pages: `results.csv`
//! (the records) and `summary.md` (per instance and planner: runs solved, mean sum of costs,
//! mean makespan and mean runtime over the solved runs).

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Duration;

use serde::{Deserialize, Serialize};

use crate::harness::{Manifest, RunRecord, Sweep, params_text};
use mrpp_core::error::{Error, Result, read_file};
use mrpp_core::registry::find;
use mrpp_core::seeds::derive_seed;
use mrpp_core::{Ctx, Deadline, MapfProblem, Params, Planner, Unsolved, solve};

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
    pub instances: Vec<InstanceSpec>,
    pub planners: Vec<PlannerSpec>,
}

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
    /// The first N agents of the scenario, for each N; empty = all of them.
    #[serde(default)]
    pub agents: Vec<usize>,
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
        Ok(cfg)
    }
}

/// One loaded instance of the sweep.
struct Loaded {
    /// `<map stem>/<scen stem>/a<agents>`.
    name: String,
    problem: MapfProblem,
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
    planners: Vec<Built>,
    jobs: Vec<(usize, usize, usize)>,
}

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
                let (_, problem) = mrpp_grid::load_problem(&spec.map, &spec.scen, n)?;
                let name = format!(
                    "{}/{}/a{}",
                    stem(&spec.map),
                    stem(&spec.scen),
                    problem.instance().num_agents()
                );
                instances.push(Loaded { name, problem });
            }
        }
        let planners = cfg.planners.iter().map(build).collect::<Result<Vec<_>>>()?;
        let (i, p, r) = (instances.len(), planners.len(), cfg.runs);
        let jobs = (0..i)
            .flat_map(|i| (0..p).flat_map(move |p| (0..r).map(move |r| (i, p, r))))
            .collect();
        Ok(GridSweep {
            cfg,
            instances,
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
    if cfg.instances.is_empty() || cfg.planners.is_empty() {
        return Err(Error::Param(
            "a sweep needs at least one instance and one planner".into(),
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
        format!("{}/{}/{r}", self.instances[i].name, self.planners[p].label)
    }

    fn run(&self, job: &(usize, usize, usize)) -> Result<RunRecord> {
        let (i, p, run) = *job;
        let seed = derive_seed(self.cfg.seed, &self.key(job));
        let b = &self.planners[p];
        let ctx = Ctx::new(
            seed,
            Deadline::after(Duration::from_secs_f64(self.cfg.time_limit)),
        );
        let started = std::time::Instant::now();
        let outcome = solve(b.planner.as_ref(), &self.instances[i].problem, &ctx);
        let runtime_ms = started.elapsed().as_secs_f64() * 1e3;
        let m = match &outcome {
            Err(Unsolved::Invalid(why)) => return Err(Error::Internal(why.clone())),
            Err(_) => None,
            Ok(s) => Some(s.metrics),
        };
        Ok(RunRecord {
            job: 0,
            key: String::new(),
            family: mrpp_grid::FAMILY.into(),
            instance: self.instances[i].name.clone(),
            planner: b.planner.name().to_string(),
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
        })
    }

    fn records(&self, row: &RunRecord) -> Vec<RunRecord> {
        vec![row.clone()]
    }

    fn pages(&self, rows: &[&RunRecord], m: &Manifest) -> Result<Vec<(String, String)>> {
        Ok(vec![("summary.md".into(), self.summary_page(rows, m))])
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
                    .filter(|r| {
                        r.instance == inst.name
                            && r.params == b.params
                            && r.planner == b.planner.name()
                    })
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
                    b.label,
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
            "# Sweep `{}`\n\n`mrpp {}` — mrpp {}, seed {}, {} runs per cell, {} s per run, wall time {:.1} s, {} threads.\n\n{}",
            self.cfg.name,
            m.sweep_command().join(" "),
            m.mrpp_version,
            self.cfg.seed,
            self.cfg.runs,
            self.cfg.time_limit,
            m.wall_seconds,
            m.threads,
            self.table(rows)
        )
    }
}
