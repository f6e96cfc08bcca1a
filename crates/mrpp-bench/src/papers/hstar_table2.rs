//! The H* paper's Table II as a sweep: Max / Sum of path lengths of Enol2023, WHCA*, NSGA-III
//! and H* on the instances of Table I, averaged over R runs (the paper uses 10).
//!
//! Every (instance, method, run) is one job with its own seed derived from the user's seed and
//! the job's key, so the rows depend neither on the thread count nor on the sharding. Max / Sum
//! are the makespan and the sum of costs of a valid plan (waits count); a run whose planner
//! returns no plan is "not solved" and leaves no numbers; an invalid plan (a bug) stops the
//! sweep. Runtime is wall time and does depend on the machine and its load. The page
//! (`table2.md`) sets ours beside the paper's numbers (kept as CSV, `table2-paper.csv`), with
//! each instance's lower bounds and Enol2023's stage-1 routes; `fig5.svg` is the paper's Fig. 5.

use std::path::Path;
use std::time::Duration;

use serde::{Deserialize, Serialize};

use crate::harness::{Manifest, RunRecord, Sweep, params_text};
use crate::papers::hstar_instances::{PaperInstance, Scenario2Map, table1_instances};
use crate::report::{Panel, Series, csv_text, line_panels};
use mrpp_core::error::{Error, Result, read_file};
use mrpp_core::mapf::plan_file::RunInfo;
use mrpp_core::mapf::search::distance::lower_bounds;
use mrpp_core::registry::find;
use mrpp_core::seeds::derive_seed;
use mrpp_core::{Ctx, Deadline, MapfProblem, Params, Planner, Solved, Unsolved, solve};
use mrpp_grid::io::plan_json::grid_envelope;
use mrpp_grid::map::GridMap;

/// One column of Table II.
#[derive(Debug, Clone)]
pub struct Method {
    /// The column's name: the paper's (`Enol2023`, `WHCA`, `NSGA-III`, `H*`) or mrpp's
    /// (`H* paper steps`).
    pub column: String,
    /// The paper's column this one is compared with.
    pub paper_column: String,
    /// The method's name in `results.csv`, in plan file names and for `--planners`: the
    /// planner's registry name, or `hstar-paper` for H\* with `variant=paper`.
    pub key: &'static str,
    /// Registry name of the planner.
    pub planner: &'static str,
    /// Its `-p key=value` parameters (defaults for the rest).
    pub params: Vec<(String, String)>,
}

impl Method {
    /// The planner's resolved parameters (every key, defaults filled in).
    pub fn resolved(&self) -> Result<Params> {
        let entry = find(mrpp_grid::PLANNERS, self.planner)
            .ok_or_else(|| Error::Param(format!("unknown planner `{}`", self.planner)))?;
        Params::resolve(entry.name, entry.params, &self.params)
    }

    /// The planner, built from the grid registry.
    pub fn build(&self) -> Result<Box<dyn Planner<MapfProblem>>> {
        let entry = find(mrpp_grid::PLANNERS, self.planner)
            .ok_or_else(|| Error::Param(format!("unknown planner `{}`", self.planner)))?;
        (entry.build)(&self.resolved()?)
    }
}

/// The paper's four methods, in its column order, with our planner names, and after them H\*
/// as the paper publishes it (`-p variant=paper`: the paper's steps only, no repair or local
/// re-planning; key `hstar-paper`), compared with the paper's H\* column too.
pub fn table2_methods() -> Vec<Method> {
    let m = |column: &str, planner: &'static str| Method {
        column: column.into(),
        paper_column: column.into(),
        key: planner,
        planner,
        params: Vec::new(),
    };
    vec![
        m("Enol2023", mrpp_grid::coevolution::NAME),
        m("WHCA", mrpp_grid::cooperative::WHCA),
        m("NSGA-III", mrpp_grid::nsga3::NAME),
        m("H*", mrpp_grid::hstar::NAME),
        Method {
            column: "H* paper steps".into(),
            paper_column: "H*".into(),
            key: HSTAR_PAPER,
            planner: mrpp_grid::hstar::NAME,
            params: vec![("variant".into(), "paper".into())],
        },
    ]
}

/// The key of the column of H\* as published ([`table2_methods`]).
pub const HSTAR_PAPER: &str = "hstar-paper";

/// What to run.
#[derive(Debug, Clone)]
pub struct Table2Config {
    pub runs: usize,
    pub seed: u64,
    pub scenario2_map: Scenario2Map,
    pub methods: Vec<Method>,
    /// Wall-clock limit of one run.
    pub time_limit: Duration,
    /// Also write every solved plan as `plans/<scenario>-<robots>-<planner>-<run>.json`.
    pub save_plans: bool,
}

impl Default for Table2Config {
    fn default() -> Self {
        Table2Config {
            runs: 10,
            seed: 0,
            scenario2_map: Scenario2Map::OpenRooms,
            methods: table2_methods(),
            time_limit: Duration::from_secs(30),
            save_plans: false,
        }
    }
}

/// One run: a CSV row of `results.csv` (plus the plan file, when plans are saved).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
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
    /// `solved`, or why not (`time_limit`, `gave_up`).
    pub status: String,
    /// Makespan of the plan.
    pub max: Option<u64>,
    /// Sum of costs of the plan.
    pub sum: Option<u64>,
    /// Sum of moves of the plan.
    pub moves: Option<u64>,
    pub runtime_ms: f64,
    /// Why it was not solved.
    pub note: String,
    /// The plan envelope of a solved run, when plans are saved.
    pub plan_file: Option<String>,
}

/// A loaded Table I instance.
pub struct LoadedInstance {
    pub info: PaperInstance,
    pub map: GridMap,
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
            let problem = mrpp_grid::problem_on(&map, inst);
            Ok(LoadedInstance { info, map, problem })
        })
        .collect()
}

/// Table II as a sweep: jobs (instance, method, run) in that order.
pub struct Table2 {
    pub cfg: Table2Config,
    pub instances: Vec<LoadedInstance>,
    pub paper: Vec<PaperCell>,
    planners: Vec<Box<dyn Planner<MapfProblem>>>,
    jobs: Vec<(usize, usize, usize)>,
}

impl Table2 {
    /// Loads Table I's instances and the paper's numbers from `data` (laid out like the bundled
    /// `data/hstar-paper/`) and builds every method's planner.
    pub fn new(cfg: Table2Config, data: &Path) -> Result<Self> {
        if cfg.runs == 0 {
            return Err(Error::Param("--runs must be at least 1".into()));
        }
        let planners = cfg
            .methods
            .iter()
            .map(Method::build)
            .collect::<Result<_>>()?;
        let paper = load_paper_table2(&data.join("table2-paper.csv"))?;
        let instances = load_table1(data, cfg.scenario2_map)?;
        let (i, m, r) = (instances.len(), cfg.methods.len(), cfg.runs);
        let jobs = (0..i)
            .flat_map(|i| (0..m).flat_map(move |m| (0..r).map(move |r| (i, m, r))))
            .collect();
        Ok(Table2 {
            cfg,
            instances,
            paper,
            planners,
            jobs,
        })
    }

    /// The row of one finished run.
    fn row(
        &self,
        (i, m, run): (usize, usize, usize),
        seed: u64,
        outcome: &Result<Solved<MapfProblem>, Unsolved>,
        runtime_ms: f64,
    ) -> RunRow {
        let li = &self.instances[i];
        let metrics = outcome.as_ref().ok().map(|s| s.metrics);
        RunRow {
            scenario: li.info.scenario,
            robots: li.info.robots,
            label: li.info.label.clone(),
            column: self.cfg.methods[m].column.clone(),
            planner: self.cfg.methods[m].key.to_string(),
            run,
            seed,
            solved: metrics.is_some(),
            status: outcome
                .as_ref()
                .map_or_else(|e| e.status().to_string(), |_| "solved".into()),
            max: metrics.map(|m| m.makespan),
            sum: metrics.map(|m| m.sum_of_costs),
            moves: metrics.map(|m| m.sum_of_moves),
            runtime_ms,
            note: outcome
                .as_ref()
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default(),
            plan_file: None,
        }
    }
}

impl Sweep for Table2 {
    type Job = (usize, usize, usize);
    type Row = RunRow;

    fn name(&self) -> &str {
        "hstar-table2"
    }

    fn jobs(&self) -> &[(usize, usize, usize)] {
        &self.jobs
    }

    fn key(&self, &(i, m, run): &(usize, usize, usize)) -> String {
        let li = &self.instances[i];
        format!(
            "sc{}/{}/{}/{run}",
            li.info.scenario, li.info.robots, self.cfg.methods[m].key
        )
    }

    fn run(&self, job: &(usize, usize, usize)) -> Result<RunRow> {
        let seed = derive_seed(self.cfg.seed, &self.key(job));
        let li = &self.instances[job.0];
        let ctx = Ctx::new(seed, Deadline::after(self.cfg.time_limit));
        let started = std::time::Instant::now();
        let outcome = solve(self.planners[job.1].as_ref(), &li.problem, &ctx);
        let runtime_ms = started.elapsed().as_secs_f64() * 1e3;
        if let Err(Unsolved::Invalid(why)) = &outcome {
            return Err(Error::Internal(why.clone()));
        }
        let mut row = self.row(*job, seed, &outcome, runtime_ms);
        if let (true, Ok(s)) = (self.cfg.save_plans, &outcome) {
            let map_file = file_name(&li.info.map);
            let info = RunInfo {
                planner: self.planners[job.1].name().to_string(),
                seed,
                runtime_ms,
                ..RunInfo::default()
            };
            let env = grid_envelope(&li.map, &map_file, &li.problem, info, &Ok(s.clone()));
            row.plan_file = Some(env.to_json());
        }
        Ok(row)
    }

    fn records(&self, r: &RunRow) -> Vec<RunRecord> {
        let m = self.cfg.methods.iter().find(|m| m.column == r.column);
        let params = m
            .and_then(|m| m.resolved().ok())
            .map(|p| params_text(p.iter()))
            .unwrap_or_default();
        vec![RunRecord {
            job: 0,
            key: String::new(),
            family: mrpp_grid::FAMILY.into(),
            instance: format!("sc{}/{}", r.scenario, r.robots),
            planner: r.planner.clone(),
            params,
            run: r.run,
            seed: r.seed,
            status: r.status.clone(),
            sum_of_costs: r.sum,
            makespan: r.max,
            sum_of_moves: r.moves,
            runtime_ms: r.runtime_ms,
            note: String::new(),
            ..Default::default()
        }]
    }

    fn pages(&self, rows: &[&RunRow], manifest: &Manifest) -> Result<Vec<(String, String)>> {
        let command = format!("mrpp {}", manifest.sweep_command().join(" "));
        let mut files = vec![
            ("results.csv".to_string(), results_csv(rows)?),
            (
                "table2.md".to_string(),
                table2_page(self, rows, &command, manifest.wall_seconds),
            ),
            ("fig5.svg".to_string(), fig5(self, rows)?),
        ];
        for r in rows {
            if let Some(text) = &r.plan_file {
                let name = format!(
                    "plans/{}-{}-{}-{}.json",
                    r.scenario, r.robots, r.planner, r.run
                );
                files.push((name, text.clone()));
            }
        }
        Ok(files)
    }

    fn config(&self) -> String {
        format!("{:?}", self.cfg)
    }

    fn summary(&self, rows: &[&RunRow]) -> String {
        let solved = rows.iter().filter(|r| r.solved).count();
        let table = render_table2_markdown(&self.instances, rows, &self.cfg.methods, &self.paper);
        format!("{table}\n{solved}/{} runs solved", rows.len())
    }
}

fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

fn results_csv(rows: &[&RunRow]) -> Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let header = [
        "scenario",
        "robots",
        "planner",
        "run",
        "seed",
        "solved",
        "max",
        "sum",
        "runtime_ms",
    ];
    w.write_record(header)
        .map_err(|e| Error::Internal(e.to_string()))?;
    let opt = |v: Option<u64>| v.map(|v| v.to_string()).unwrap_or_default();
    for r in rows {
        w.write_record([
            r.scenario.to_string(),
            r.robots.to_string(),
            r.planner.clone(),
            r.run.to_string(),
            r.seed.to_string(),
            r.solved.to_string(),
            opt(r.max),
            opt(r.sum),
            format!("{:.3}", r.runtime_ms),
        ])
        .map_err(|e| Error::Internal(e.to_string()))?;
    }
    csv_text(w)
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
pub fn summarize(rows: &[&RunRow], scenario: u8, robots: usize, column: &str) -> CellSummary {
    let runs: Vec<&RunRow> = rows
        .iter()
        .copied()
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
    rows: &[&RunRow],
    methods: &[Method],
    paper: &[PaperCell],
) -> String {
    let mut s = String::new();
    s.push_str("| SC | robots |");
    for m in methods {
        s.push_str(&format!(" {} ours | {} paper |", m.column, m.paper_column));
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
                // H* as published says why it stopped (the other columns stay empty, as the
                // paper's do).
                _ if m.key == HSTAR_PAPER && c.runs > 0 => rows
                    .iter()
                    .find(|r| r.scenario == sc && r.robots == n && r.column == m.column)
                    .map(|r| format!("— {}", why(&r.note)))
                    .unwrap_or_default(),
                _ => String::new(),
            };
            let theirs = paper
                .iter()
                .find(|p| p.scenario == sc && p.robots == n && p.column == m.paper_column)
                .and_then(|p| p.max_sum)
                .map(|(mx, sm)| format!("{mx:.1} / {sm:.1}"))
                .unwrap_or_default();
            s.push_str(&format!(" {ours} | {theirs} |"));
        }
        s.push('\n');
    }
    s
}

/// The first clause of a planner's reason for not solving (before any parenthesis), without
/// the table's `|`.
fn why(note: &str) -> String {
    note.split(" (")
        .next()
        .unwrap_or(note)
        .replace('|', "/")
        .trim()
        .to_string()
}

/// `table2.md`: ours beside the paper's Table II, lower bounds, Enol2023's stage 1, runtimes.
fn table2_page(t: &Table2, rows: &[&RunRow], command: &str, wall: f64) -> String {
    let (instances, cfg, paper) = (&t.instances, &t.cfg, &t.paper);
    let mut s = String::new();
    s.push_str("# H* paper, Table II: Max / Sum of path lengths\n\n");
    s.push_str(&format!(
        "`{command}` — mrpp {}, {} runs per cell, wall time {wall:.1} s.\n\n",
        env!("CARGO_PKG_VERSION"),
        cfg.runs
    ));
    s.push_str(
        "Ours: mean makespan / mean sum of costs (waits count) over the runs that returned a valid plan; \
         `(k/R)` when only k of R runs did; empty when none did. Paper: its Table II (empty = paths with collisions).\n\n",
    );
    s.push_str(&render_table2_markdown(
        instances,
        rows,
        &cfg.methods,
        paper,
    ));
    s.push_str(
        "\nLower bounds (each robot's shortest distance, others ignored); Enol2023's stage-1 routes \
         (A* with private obstacles, before co-evolution: Max / Sum and the number of robot pairs still \
         in conflict), and the authors' initial A* routes (their squared Euclidean heuristic, each robot \
         alone: what the paper's Enol2023 cells match); \
         mean runtime of our runs:\n\n",
    );
    s.push_str("| SC | robots | LB Max / Sum | Enol2023 stage 1 | authors' initial A* |");
    for m in &cfg.methods {
        s.push_str(&format!(" {} ms |", m.column));
    }
    s.push_str("\n|---|---|---|---|---|");
    for _ in &cfg.methods {
        s.push_str("---|");
    }
    s.push('\n');
    for li in instances {
        let lb = lower_bounds(
            li.map.graph(),
            &li.problem.instance().starts,
            &li.problem.instance().goals,
        )
        .map(|(sum, max)| format!("{max} / {sum}"))
        .unwrap_or_else(|i| format!("agent {i} cannot reach its goal"));
        s.push_str(&format!(
            "| {} | {} | {lb} | {} | {} |",
            li.info.scenario,
            li.info.label,
            stage1(li, false),
            stage1(li, true)
        ));
        for m in &cfg.methods {
            let times: Vec<f64> = rows
                .iter()
                .copied()
                .filter(|r| {
                    r.scenario == li.info.scenario
                        && r.robots == li.info.robots
                        && r.column == m.column
                })
                .map(|r| r.runtime_ms)
                .collect();
            let mean = times.iter().sum::<f64>() / times.len().max(1) as f64;
            s.push_str(&format!(" {mean:.1} |"));
        }
        s.push('\n');
    }
    s
}

/// Enol2023's stage 1 alone: the A* routes with private obstacles, as Max / Sum (arrival steps)
/// and how many robot pairs still conflict; with `authors_initial`, the authors' first A* routes
/// instead (squared Euclidean heuristic, each robot alone, no round of private obstacles).
fn stage1(li: &LoadedInstance, authors_initial: bool) -> String {
    use mrpp_grid::coevolution::{Coevolution, astar_with_private_obstacles, route_conflict};
    let g = li.map.graph();
    let Ok(stage) = astar_with_private_obstacles(
        g,
        li.problem.instance(),
        &if authors_initial {
            Coevolution {
                heuristic: mrpp_grid::coevolution::AstarHeuristic::SquaredEuclidean,
                astar_rounds: 0,
                ..Coevolution::default()
            }
        } else {
            Coevolution::default()
        },
        Deadline::none(),
    ) else {
        return String::new();
    };
    let lengths: Vec<usize> = stage
        .routes
        .iter()
        .zip(&li.problem.instance().goals)
        .map(|(r, &goal)| {
            mrpp_core::mapf::plan::path_cost(r, goal, mrpp_core::GoalSemantics::Stay)
                .unwrap_or(r.len() - 1)
        })
        .collect();
    let n = stage.routes.len();
    let pairs = (0..n)
        .flat_map(|a| (a + 1..n).map(move |b| (a, b)))
        .filter(|&(a, b)| route_conflict(&stage.routes[a], &stage.routes[b]).is_some())
        .count();
    format!(
        "{} / {}, {pairs} pairs",
        lengths.iter().max().unwrap_or(&0),
        lengths.iter().sum::<usize>()
    )
}

/// `fig5.svg`: the average path length per robot against the robot count, ours and the paper's.
fn fig5(t: &Table2, rows: &[&RunRow]) -> Result<String> {
    let (instances, cfg, paper) = (&t.instances, &t.cfg, &t.paper);
    let mut panels = Vec::new();
    for sc in 1..=3u8 {
        let here: Vec<&LoadedInstance> = instances
            .iter()
            .filter(|li| li.info.scenario == sc)
            .collect();
        let mut series = Vec::new();
        for m in &cfg.methods {
            let points: Vec<(f64, f64)> = here
                .iter()
                .filter_map(|li| {
                    let c = summarize(rows, sc, li.info.robots, &m.column);
                    c.mean_sum
                        .map(|s| (li.info.robots as f64, s / li.info.robots as f64))
                })
                .collect();
            series.push(Series {
                name: m.column.clone(),
                points,
                paper: false,
                ..Series::default()
            });
            let paper_points: Vec<(f64, f64)> = here
                .iter()
                .filter_map(|li| {
                    paper
                        .iter()
                        .find(|p| {
                            p.scenario == sc && p.robots == li.info.robots && p.column == m.column
                        })
                        .and_then(|p| p.max_sum)
                        .map(|(_, sum)| (li.info.robots as f64, sum / li.info.robots as f64))
                })
                .collect();
            if !paper_points.is_empty() {
                series.push(Series {
                    name: format!("{} (paper)", m.column),
                    points: paper_points,
                    paper: true,
                    ..Series::default()
                });
            }
        }
        panels.push(Panel {
            title: format!("Scenario {sc}"),
            series,
        });
    }
    line_panels(
        "Average path length per robot (Sum / robots); lines: mrpp, circles: paper",
        "robots",
        "average path length",
        &panels,
    )
    .map_err(Error::Internal)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper's Enol2023 cells for Scenario 3 are exactly the Max / Sum of the authors' initial
    /// A* routes (squared Euclidean heuristic, each robot alone), which still conflict: the
    /// published figures are routes before any conflict resolution (issue 32 item 1).
    #[test]
    fn the_papers_enol2023_scenario_3_cells_are_the_authors_initial_astar_routes() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/hstar-paper");
        let instances = load_table1(&root, Scenario2Map::OpenRooms).unwrap();
        let paper = load_paper_table2(&root.join("table2-paper.csv")).unwrap();
        let mut checked = 0;
        for li in instances.iter().filter(|li| li.info.scenario == 3) {
            let cell = paper
                .iter()
                .find(|c| c.scenario == 3 && c.robots == li.info.robots && c.column == "Enol2023")
                .and_then(|c| c.max_sum)
                .unwrap();
            let ours = stage1(li, true);
            let want = format!("{} / {},", cell.0, cell.1);
            assert!(
                ours.starts_with(&want),
                "SC3 {}: {ours} vs {want}",
                li.info.robots
            );
            let pairs: usize = ours
                .split(", ")
                .nth(1)
                .and_then(|p| p.split(' ').next())
                .and_then(|p| p.parse().ok())
                .unwrap();
            assert!(pairs > 0, "SC3 {}: the routes conflict", li.info.robots);
            checked += 1;
        }
        assert_eq!(checked, 5);
    }
}
