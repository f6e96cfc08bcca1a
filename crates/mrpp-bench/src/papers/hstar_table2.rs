//! The H* paper's Table II: Max / Sum of path lengths of Enol2023, WHCA*, NSGA-III and H* on the
//! instances of Table I, averaged over R runs (the paper uses 10).
//!
//! Every (instance, method, run) is an independent job with its own seed derived from the user's
//! seed and the job's key, so the rows do not depend on how many threads ran them. Max / Sum are the
//! makespan and the sum of costs of a valid plan (waits count); a run whose planner does not return a
//! valid plan is "not solved" and leaves no numbers. Runtime is wall time and does depend on the
//! machine and its load.

use std::path::Path;
use std::time::{Duration, Instant};

use rayon::prelude::*;

use crate::papers::hstar_instances::{PaperInstance, Scenario2Map, table1_instances};
use mrpp_core::error::{Error, Result, read_file};
use mrpp_core::mapf::instance::Instance;
use mrpp_core::registry::find;
use mrpp_core::seeds::derive_seed;
use mrpp_core::{Ctx, Deadline, MapfProblem, Planner, Solved, solve};
use mrpp_grid::map::GridMap;

/// One column of Table II.
#[derive(Debug, Clone)]
pub struct Method {
    /// The paper's column name: `Enol2023`, `WHCA`, `NSGA-III`, `H*`.
    pub column: String,
    /// Registry name of the planner.
    pub planner: &'static str,
    /// Its `-p key=value` parameters (defaults for the rest).
    pub params: Vec<(String, String)>,
}

impl Method {
    /// The planner, built from the grid registry.
    pub fn build(&self) -> Result<Box<dyn Planner<MapfProblem>>> {
        find(mrpp_grid::PLANNERS, self.planner)
            .ok_or_else(|| Error::Param(format!("unknown planner `{}`", self.planner)))?
            .instantiate(&self.params)
    }
}

/// The paper's four methods, in its column order, with our planner names.
pub fn table2_methods() -> Vec<Method> {
    let m = |column: &str, planner: &'static str| Method {
        column: column.into(),
        planner,
        params: Vec::new(),
    };
    vec![
        m("Enol2023", mrpp_grid::coevolution::NAME),
        m("WHCA", mrpp_grid::cooperative::WHCA),
        m("NSGA-III", mrpp_grid::nsga3::NAME),
        m("H*", mrpp_grid::hstar::NAME),
    ]
}

/// What to run.
#[derive(Debug, Clone)]
pub struct Table2Config {
    pub runs: usize,
    pub seed: u64,
    pub scenario2_map: Scenario2Map,
    pub methods: Vec<Method>,
    /// Wall-clock limit of one run.
    pub time_limit: Duration,
}

impl Default for Table2Config {
    fn default() -> Self {
        Table2Config {
            runs: 10,
            seed: 0,
            scenario2_map: Scenario2Map::OpenRooms,
            methods: table2_methods(),
            time_limit: Duration::from_secs(30),
        }
    }
}

/// One run: a CSV row of `results.csv` (plus the plan, when solved).
#[derive(Debug, Clone)]
pub struct RunRow {
    pub scenario: u8,
    pub robots: usize,
    /// Table II's row label (`6`, `3 × 4`, ...).
    pub label: String,
    /// The paper's column name.
    pub column: String,
    pub planner: String,
    pub run: usize,
    pub seed: u64,
    pub solved: bool,
    /// Makespan of the plan.
    pub max: Option<u64>,
    /// Sum of costs of the plan.
    pub sum: Option<u64>,
    pub runtime_ms: f64,
    /// Why it was not solved.
    pub note: String,
    /// The validated plan with its metrics, when solved.
    pub plan: Option<Solved<MapfProblem>>,
}

/// A loaded Table I instance.
pub struct LoadedInstance {
    pub info: PaperInstance,
    pub map: GridMap,
    pub inst: Instance,
    /// The instance as the planners see it (`stay` rules).
    pub problem: MapfProblem,
}

/// Loads the Table I instances under `root`.
pub fn load_table1(root: &Path, sc2: Scenario2Map) -> Result<Vec<LoadedInstance>> {
    table1_instances(root, sc2)
        .into_iter()
        .map(|info| {
            let map = GridMap::load(&info.map)?;
            let inst = mrpp_grid::scen::load_agents(&info.robots_file, &map, None)?;
            if inst.num_agents() != info.robots {
                return Err(Error::invalid(
                    &info.robots_file,
                    format!(
                        "expected {} robots, found {}",
                        info.robots,
                        inst.num_agents()
                    ),
                ));
            }
            let problem = mrpp_grid::problem_on(&map, inst.clone());
            Ok(LoadedInstance {
                info,
                map,
                inst,
                problem,
            })
        })
        .collect()
}

/// Number of jobs [`run_table2`] will run.
pub fn job_count(instances: &[LoadedInstance], cfg: &Table2Config) -> usize {
    instances.len() * cfg.methods.len() * cfg.runs
}

/// Runs every job in parallel (rayon's pool); `on_done` is called once per finished job, from any
/// thread. Rows come back in a fixed order: instance, method, run.
pub fn run_table2(
    instances: &[LoadedInstance],
    cfg: &Table2Config,
    on_done: &(dyn Fn(&RunRow) + Sync),
) -> Result<Vec<RunRow>> {
    if cfg.runs == 0 {
        return Err(Error::Param("--runs must be at least 1".into()));
    }
    let planners = cfg
        .methods
        .iter()
        .map(Method::build)
        .collect::<Result<Vec<_>>>()?;
    let jobs: Vec<(usize, usize, usize)> = (0..instances.len())
        .flat_map(|i| {
            (0..cfg.methods.len()).flat_map(move |m| (0..cfg.runs).map(move |r| (i, m, r)))
        })
        .collect();
    let rows = jobs
        .par_iter()
        .map(|&(i, m, run)| {
            let li = &instances[i];
            let planner = planners[m].as_ref();
            let key = format!(
                "sc{}/{}/{}/{run}",
                li.info.scenario,
                li.info.robots,
                planner.name()
            );
            let seed = derive_seed(cfg.seed, &key);
            let opts = Ctx::new(seed, Deadline::after(cfg.time_limit));
            let started = Instant::now();
            let outcome = solve(planner, &li.problem, &opts);
            let runtime_ms = started.elapsed().as_secs_f64() * 1e3;
            let (metrics, plan, note) = match outcome {
                Ok(s) => (Some(s.metrics), Some(s), String::new()),
                Err(why) => (None, None, why.to_string()),
            };
            let row = RunRow {
                scenario: li.info.scenario,
                robots: li.info.robots,
                label: li.info.label.clone(),
                column: cfg.methods[m].column.clone(),
                planner: planner.name().to_string(),
                run,
                seed,
                solved: metrics.is_some(),
                max: metrics.map(|m| m.makespan),
                sum: metrics.map(|m| m.sum_of_costs),
                runtime_ms,
                note,
                plan,
            };
            on_done(&row);
            row
        })
        .collect();
    Ok(rows)
}

/// One cell of the paper's Table II (`None` = blank: paths with collisions).
#[derive(Debug, Clone, PartialEq)]
pub struct PaperCell {
    pub scenario: u8,
    pub robots: usize,
    pub column: String,
    pub max_sum: Option<(f64, f64)>,
}

/// Reads `table2-paper.csv` (`scenario,robots,method,max,sum`; `#` comments).
pub fn load_paper_table2(path: &Path) -> Result<Vec<PaperCell>> {
    let text = read_file(path)?;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') || line.starts_with("scenario,") {
            continue;
        }
        let f: Vec<&str> = line.split(',').collect();
        let bad = |what: &str| Error::parse(path, i + 1, format!("{what} in `{line}`"));
        if f.len() != 5 {
            return Err(bad("expected 5 fields"));
        }
        let num = |s: &str| s.trim().parse::<f64>().map_err(|_| bad("bad number"));
        let max_sum = if f[3].trim().is_empty() {
            None
        } else {
            Some((num(f[3])?, num(f[4])?))
        };
        out.push(PaperCell {
            scenario: f[0].trim().parse().map_err(|_| bad("bad scenario"))?,
            robots: f[1].trim().parse().map_err(|_| bad("bad robot count"))?,
            column: f[2].trim().to_string(),
            max_sum,
        });
    }
    Ok(out)
}

/// Averages of one (instance, method) over its solved runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellSummary {
    pub solved: usize,
    pub runs: usize,
    pub mean_max: Option<f64>,
    pub mean_sum: Option<f64>,
}

/// Summarises the runs of one instance and method.
pub fn summarize(rows: &[RunRow], scenario: u8, robots: usize, column: &str) -> CellSummary {
    let runs: Vec<&RunRow> = rows
        .iter()
        .filter(|r| r.scenario == scenario && r.robots == robots && r.column == column)
        .collect();
    let solved: Vec<&&RunRow> = runs.iter().filter(|r| r.solved).collect();
    let mean = |f: &dyn Fn(&RunRow) -> Option<u64>| {
        (!solved.is_empty())
            .then(|| solved.iter().filter_map(|r| f(r)).sum::<u64>() as f64 / solved.len() as f64)
    };
    CellSummary {
        solved: solved.len(),
        runs: runs.len(),
        mean_max: mean(&|r| r.max),
        mean_sum: mean(&|r| r.sum),
    }
}

/// Table II's layout in Markdown: for each row and method, ours (`Max / Sum`, averaged over the
/// solved runs; empty when no run was solved; `k/R` when only some were) beside the paper's.
pub fn render_table2_markdown(
    instances: &[LoadedInstance],
    rows: &[RunRow],
    methods: &[Method],
    paper: &[PaperCell],
) -> String {
    let mut s = String::new();
    s.push_str("| SC | robots |");
    for m in methods {
        s.push_str(&format!(" {} ours | {} paper |", m.column, m.column));
    }
    s.push('\n');
    s.push_str("|---|---|");
    for _ in methods {
        s.push_str("---|---|");
    }
    s.push('\n');
    for li in instances {
        let (sc, n) = (li.info.scenario, li.info.robots);
        s.push_str(&format!("| {sc} | {} |", li.info.label));
        for m in methods {
            let c = summarize(rows, sc, n, &m.column);
            let ours = match (c.mean_max, c.mean_sum) {
                (Some(mx), Some(sm)) if c.solved == c.runs => format!("{mx:.1} / {sm:.1}"),
                (Some(mx), Some(sm)) => format!("{mx:.1} / {sm:.1} ({}/{})", c.solved, c.runs),
                _ => String::new(),
            };
            let theirs = paper
                .iter()
                .find(|p| p.scenario == sc && p.robots == n && p.column == m.column)
                .and_then(|p| p.max_sum)
                .map(|(mx, sm)| format!("{mx:.1} / {sm:.1}"))
                .unwrap_or_default();
            s.push_str(&format!(" {ours} | {theirs} |"));
        }
        s.push('\n');
    }
    s
}
