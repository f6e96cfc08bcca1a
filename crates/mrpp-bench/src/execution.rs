//! One-shot plans executed on robots that are late, as a sweep (issue 29, item 7): every grid
//! instance x planner x delay probability x executor x run, each a plan made once (validated by
//! `solve`) and executed tick by tick under seeded Bernoulli delays by `mrpp_exec::execute`
//! (the action dependency graph, `adg`, or the plan's timing, `naive`), every execution replayed
//! by `mrpp_exec::check`. Measured: runs with a collision, collisions, how the execution ended
//! (finished, deadlock), executed makespan and sum of costs over the plan's own, ticks lost to
//! delays, waits added.
//!
//! Where the issue is silent: the plan of each (instance, planner) is made once, with a seed
//! derived from its key, and shared by every delay and executor, so the columns differ only by
//! the execution; delays last `min`–`max` ticks uniformly; a run's delay seed derives from its
//! key. `lacam*` is LaCAM with `anytime=true` (LaCAM*) until the planning time limit.

use std::path::PathBuf;
use std::sync::OnceLock;
use std::time::Duration;

use serde::{Deserialize, Serialize};

use crate::harness::{Manifest, RunRecord, Sweep};
use crate::report::{Panel, Series, csv_text, line_panels};
use mrpp_core::error::{Error, Result};
use mrpp_core::mapf::plan::Plan;
use mrpp_core::seeds::derive_seed;
use mrpp_core::{Ctx, Deadline, MapfProblem, solve};
use mrpp_exec::execute::Ending;
use mrpp_exec::{DelayConfig, ExecConfig, ExecutorKind, check::check, execute};
use mrpp_mapf::GridMap;

/// A grid instance: map, scenario, agents.
#[derive(Debug, Clone)]
pub struct Instance {
    pub map: PathBuf,
    pub scen: PathBuf,
    pub agents: usize,
}

/// What to run.
#[derive(Debug, Clone)]
pub struct ExecutionConfig {
    pub seed: u64,
    pub instances: Vec<Instance>,
    /// Grid planners by registry name; `lacam*` = `lacam` with `anytime=true`.
    pub planners: Vec<String>,
    /// Bernoulli delay probabilities per robot per tick.
    pub delays: Vec<f64>,
    /// A delay's duration range in ticks.
    pub min_delay: u32,
    pub max_delay: u32,
    pub executors: Vec<ExecutorKind>,
    /// Robustness of the executed plans: each plan re-timed to be k-robust
    /// (`mrpp_exec::robust`; 0 = as planned).
    pub robust: Vec<u32>,
    /// Re-planning on drift (`mrpp_exec::replan`): a robot this many ticks behind its plan's
    /// timing makes the instance's planner plan again from where the robots are (0: never).
    pub replan: Vec<u64>,
    /// Ticks per move (`agentCounter`).
    pub ticks_per_move: u32,
    /// Side of a robot's square (`agentSize`), cells.
    pub agent_size: f64,
    /// Runs (delay seeds) per point.
    pub runs: usize,
    /// Planning time per plan.
    pub time_limit: Duration,
}

/// One execution.
#[derive(Debug, Clone, Copy)]
pub struct ExecJob {
    pub instance: usize,
    pub planner: usize,
    pub delay: usize,
    pub executor: usize,
    pub robust: usize,
    pub replan: usize,
    pub run: usize,
}

/// An execution's result.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ExecRow {
    pub instance: String,
    pub agents: usize,
    pub planner: String,
    pub p_delay: f64,
    pub executor: String,
    /// The plan was re-timed to be k-robust (0: as planned).
    pub k: u32,
    /// Re-planning drift threshold in ticks (0: no re-planning).
    #[serde(default)]
    pub replan_drift: u64,
    /// Plans that took over on drift.
    #[serde(default)]
    pub replans: usize,
    pub run: usize,
    pub seed: u64,
    /// `finished`, `deadlock`, `tick_limit`, or `unsolved` (the planner found no plan).
    pub status: String,
    pub collisions: usize,
    pub planned_makespan: u64,
    pub planned_sum_of_costs: u64,
    pub makespan_ratio: f64,
    pub sum_of_costs_ratio: f64,
    pub ticks_lost_to_delays: u64,
    pub waits_added: u64,
    pub wall_ms: f64,
}

/// A plan made once per (instance, planner), or why there is none.
type Made = std::result::Result<(GridMap, Plan), String>;

/// The sweep.
pub struct ExecutionSweep {
    cfg: ExecutionConfig,
    problems: Vec<(String, GridMap, MapfProblem)>,
    plans: Vec<OnceLock<Made>>,
    jobs: Vec<ExecJob>,
}

impl ExecutionSweep {
    /// Loads every instance and checks every option before any run.
    ///
    /// # Errors
    /// An instance that does not read (file, line and rule), an unknown planner, a delay
    /// probability outside [0, 1], `min` of 0 or above `max`, no executor, zero runs.
    pub fn new(cfg: ExecutionConfig) -> Result<Self> {
        if cfg.runs == 0 {
            return Err(Error::Param("--runs must be at least 1".into()));
        }
        if cfg.executors.is_empty()
            || cfg.planners.is_empty()
            || cfg.delays.is_empty()
            || cfg.robust.is_empty()
            || cfg.replan.is_empty()
        {
            return Err(Error::Param(
                "give at least one planner, delay probability, robustness, re-planning drift and executor".into(),
            ));
        }
        for &p in &cfg.delays {
            DelayConfig::parse(&format!(
                "bernoulli:p={p},min={},max={}",
                cfg.min_delay, cfg.max_delay
            ))
            .map_err(Error::Param)?;
        }
        for name in &cfg.planners {
            planner(name)?;
        }
        if let Some(k) = cfg.robust.iter().find(|&&k| k > 1000) {
            return Err(Error::Param(format!(
                "--robust {k}: expected 0 to 1000 steps"
            )));
        }
        let mut problems = Vec::new();
        for inst in &cfg.instances {
            let (map, problem) = mrpp_grid::load_problem(&inst.map, &inst.scen, Some(inst.agents))?;
            let stem = |p: &PathBuf| {
                p.file_stem()
                    .map_or_else(|| p.display().to_string(), |s| s.to_string_lossy().into())
            };
            problems.push((
                format!("{}/{}/a{}", stem(&inst.map), stem(&inst.scen), inst.agents),
                map,
                problem,
            ));
        }
        if problems.is_empty() {
            return Err(Error::Param("no instance to run".into()));
        }
        let mut jobs = Vec::new();
        for instance in 0..problems.len() {
            for planner in 0..cfg.planners.len() {
                for delay in 0..cfg.delays.len() {
                    for robust in 0..cfg.robust.len() {
                        for replan in 0..cfg.replan.len() {
                            for executor in 0..cfg.executors.len() {
                                for run in 0..cfg.runs {
                                    jobs.push(ExecJob {
                                        instance,
                                        planner,
                                        delay,
                                        executor,
                                        robust,
                                        replan,
                                        run,
                                    });
                                }
                            }
                        }
                    }
                }
            }
        }
        let plans = (0..problems.len() * cfg.planners.len())
            .map(|_| OnceLock::new())
            .collect();
        Ok(ExecutionSweep {
            cfg,
            problems,
            plans,
            jobs,
        })
    }

    /// The plan of (instance, planner), made on first use.
    fn plan(&self, instance: usize, planner_index: usize) -> Result<&Made> {
        let cell = &self.plans[instance * self.cfg.planners.len() + planner_index];
        if let Some(made) = cell.get() {
            return Ok(made);
        }
        let (name, map, problem) = &self.problems[instance];
        let spec = &self.cfg.planners[planner_index];
        let p = planner(spec)?;
        let ctx = Ctx::new(
            derive_seed(self.cfg.seed, &format!("{name}/{spec}")),
            Deadline::after(self.cfg.time_limit),
        );
        let made = match solve(p.as_ref(), problem, &ctx) {
            Ok(s) => Ok((map.clone(), s.plan)),
            Err(mrpp_core::Unsolved::Invalid(why)) => {
                return Err(Error::Internal(format!("{name}/{spec}: {why}")));
            }
            Err(other) => Err(other.status().to_string()),
        };
        Ok(cell.get_or_init(|| made))
    }
}

/// A plan's makespan and sum of costs in ticks on its own timing: each robot done at the tick
/// after its last move (as `mrpp_exec::execute` counts them).
fn planned_ticks(plan: &Plan, ticks_per_move: u32) -> (u64, u64) {
    let c = u64::from(ticks_per_move.max(1));
    let finish: Vec<u64> = plan
        .paths
        .iter()
        .map(|p| {
            p.windows(2)
                .rposition(|w| w[0] != w[1])
                .map_or(0, |t| (t as u64 + 1) * c)
        })
        .collect();
    (
        finish.iter().copied().max().unwrap_or(0),
        finish.iter().sum(),
    )
}

/// The planner a spec names (`lacam*` = LaCAM*).
fn planner(spec: &str) -> Result<Box<dyn mrpp_core::Planner<MapfProblem>>> {
    let (name, params): (&str, Vec<(String, String)>) = match spec {
        "lacam*" => ("lacam", vec![("anytime".into(), "true".into())]),
        other => (other, Vec::new()),
    };
    let entry = mrpp_grid::PLANNERS
        .iter()
        .find(|e| e.name == name)
        .ok_or_else(|| {
            let known: Vec<&str> = mrpp_grid::PLANNERS.iter().map(|e| e.name).collect();
            Error::Param(format!(
                "unknown grid planner {spec} (known: {}, lacam*)",
                known.join(", ")
            ))
        })?;
    entry.instantiate(&params)
}

impl Sweep for ExecutionSweep {
    type Job = ExecJob;
    type Row = ExecRow;

    fn name(&self) -> &str {
        "execution"
    }
    fn jobs(&self) -> &[ExecJob] {
        &self.jobs
    }
    fn key(&self, j: &ExecJob) -> String {
        // Without re-planning the key is the one of earlier versions (resumable outputs).
        let replan = match self.cfg.replan[j.replan] {
            0 => String::new(),
            d => format!("/r{d}"),
        };
        format!(
            "{}/{}/p{}/k{}{replan}/{}/{}",
            self.problems[j.instance].0,
            self.cfg.planners[j.planner],
            self.cfg.delays[j.delay],
            self.cfg.robust[j.robust],
            self.cfg.executors[j.executor].name(),
            j.run
        )
    }
    fn run(&self, j: &ExecJob) -> Result<ExecRow> {
        let (name, _, problem) = &self.problems[j.instance];
        let executor = self.cfg.executors[j.executor];
        let p = self.cfg.delays[j.delay];
        // Every executor of a run sees the same delays: the seed leaves the executor out.
        let seed = derive_seed(
            self.cfg.seed,
            &format!("{name}/{}/p{p}/{}", self.cfg.planners[j.planner], j.run),
        );
        let mut row = ExecRow {
            instance: name.clone(),
            agents: problem.instance().starts.len(),
            planner: self.cfg.planners[j.planner].clone(),
            p_delay: p,
            executor: executor.name().into(),
            k: self.cfg.robust[j.robust],
            replan_drift: self.cfg.replan[j.replan],
            replans: 0,
            run: j.run,
            seed,
            status: "unsolved".into(),
            collisions: 0,
            planned_makespan: 0,
            planned_sum_of_costs: 0,
            makespan_ratio: 0.0,
            sum_of_costs_ratio: 0.0,
            ticks_lost_to_delays: 0,
            waits_added: 0,
            wall_ms: 0.0,
        };
        let (map, plan) = match self.plan(j.instance, j.planner)? {
            Ok(made) => made,
            Err(_) => return Ok(row),
        };
        let (planned_makespan, planned_soc) = planned_ticks(plan, self.cfg.ticks_per_move);
        let robust;
        let plan = if row.k == 0 {
            plan
        } else {
            robust = mrpp_exec::robust::k_robust(plan, row.k);
            mrpp_core::Problem::validate(problem, &robust).map_err(|v| {
                Error::Internal(format!(
                    "{}: the re-timed plan is invalid: {v}",
                    self.key(j)
                ))
            })?;
            &robust
        };
        let cfg = ExecConfig {
            executor,
            ticks_per_move: self.cfg.ticks_per_move,
            delays: DelayConfig::parse(&format!(
                "bernoulli:p={p},min={},max={}",
                self.cfg.min_delay, self.cfg.max_delay
            ))
            .map_err(Error::Param)?,
            seed,
            agent_size: self.cfg.agent_size,
            max_ticks: 10_000_000,
        };
        let started = std::time::Instant::now();
        let (run, executed) = if row.replan_drift == 0 {
            (execute(map, plan, &cfg), None)
        } else {
            let p = planner(&self.cfg.planners[j.planner])?;
            let mut replanner =
                mrpp_exec::Replanner::new(problem, p.as_ref(), seed, self.cfg.time_limit);
            let mut replan = |at: &[mrpp_core::mapf::graph::VertexId]| replanner.plan(at);
            let replanning = mrpp_exec::Replanning {
                drift: row.replan_drift,
                planner: &mut replan,
            };
            let (run, executed) = mrpp_exec::execute_replanning(map, plan, &cfg, Some(replanning));
            if let Some(why) = replanner.invalid {
                return Err(Error::Internal(format!(
                    "{}: a re-plan was invalid: {why}",
                    self.key(j)
                )));
            }
            (run, Some(executed))
        };
        row.wall_ms = started.elapsed().as_secs_f64() * 1e3;
        row.replans = run.metrics.replans;
        // Under the ADG a re-planned executed plan is valid (`mrpp_exec::replan`); the naive
        // executor may have broken it. Without re-planning it is the plan, validated already.
        if let Some(executed) = executed.as_ref().filter(|_| executor == ExecutorKind::Adg) {
            mrpp_core::Problem::validate(problem, executed).map_err(|v| {
                Error::Internal(format!(
                    "{}: the executed plan is invalid: {v}",
                    self.key(j)
                ))
            })?;
        }
        let executed = executed.as_ref().unwrap_or(plan);
        check(map, executed, &run, cfg.ticks_per_move, cfg.agent_size).map_err(|e| {
            Error::Internal(format!(
                "{}: the execution does not replay: {e}",
                self.key(j)
            ))
        })?;
        row.status = match run.ending {
            Ending::Finished => "finished",
            Ending::Deadlock { .. } => "deadlock",
            Ending::TickLimit => "tick_limit",
        }
        .into();
        let m = run.metrics;
        row.collisions = m.collisions;
        // Over the plan as made, so that a re-timed plan's own extra length counts.
        let ratio = |a: u64, b: u64| if b == 0 { 1.0 } else { a as f64 / b as f64 };
        row.planned_makespan = planned_makespan;
        row.planned_sum_of_costs = planned_soc;
        row.makespan_ratio = ratio(m.makespan, planned_makespan);
        row.sum_of_costs_ratio = ratio(m.sum_of_costs, planned_soc);
        row.ticks_lost_to_delays = m.ticks_lost_to_delays;
        row.waits_added = m.waits_added;
        Ok(row)
    }
    fn records(&self, r: &ExecRow) -> Vec<RunRecord> {
        vec![RunRecord {
            job: 0,
            key: String::new(),
            family: "grid".into(),
            instance: r.instance.clone(),
            planner: r.planner.clone(),
            params: format!("executor={};p_delay={}", r.executor, r.p_delay),
            run: r.run,
            seed: r.seed,
            status: if r.status == "unsolved" {
                "gave_up".into()
            } else {
                "solved".into()
            },
            sum_of_costs: None,
            makespan: None,
            sum_of_moves: None,
            runtime_ms: r.wall_ms,
            note: format!("{}; {} collisions", r.status, r.collisions),
            ..Default::default()
        }]
    }
    fn pages(&self, rows: &[&ExecRow], m: &Manifest) -> Result<Vec<(String, String)>> {
        Ok(vec![
            ("results.csv".into(), results_csv(rows)?),
            ("execution.md".into(), page(self, rows, m)),
            ("execution.svg".into(), figure(rows)?),
        ])
    }
    fn summary(&self, rows: &[&ExecRow]) -> String {
        table(rows)
    }
    fn config(&self) -> String {
        format!("{:?}", self.cfg)
    }
}

fn results_csv(rows: &[&ExecRow]) -> Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let e = |e: csv::Error| Error::Internal(e.to_string());
    w.write_record([
        "instance",
        "agents",
        "planner",
        "p_delay",
        "executor",
        "k",
        "replan_drift",
        "replans",
        "run",
        "seed",
        "status",
        "collisions",
        "planned_makespan",
        "planned_sum_of_costs",
        "makespan_ratio",
        "sum_of_costs_ratio",
        "ticks_lost_to_delays",
        "waits_added",
        "wall_ms",
    ])
    .map_err(e)?;
    for r in rows {
        w.write_record([
            r.instance.clone(),
            r.agents.to_string(),
            r.planner.clone(),
            r.p_delay.to_string(),
            r.executor.clone(),
            r.k.to_string(),
            r.replan_drift.to_string(),
            r.replans.to_string(),
            r.run.to_string(),
            r.seed.to_string(),
            r.status.clone(),
            r.collisions.to_string(),
            r.planned_makespan.to_string(),
            r.planned_sum_of_costs.to_string(),
            format!("{:.4}", r.makespan_ratio),
            format!("{:.4}", r.sum_of_costs_ratio),
            r.ticks_lost_to_delays.to_string(),
            r.waits_added.to_string(),
            format!("{:.2}", r.wall_ms),
        ])
        .map_err(e)?;
    }
    csv_text(w)
}

/// Rows grouped by (instance, planner, executor, p), in first-seen order.
fn groups<'a>(rows: &[&'a ExecRow]) -> Vec<Vec<&'a ExecRow>> {
    let mut out: Vec<Vec<&ExecRow>> = Vec::new();
    for &r in rows {
        match out.iter_mut().find(|g| {
            let f = g[0];
            f.instance == r.instance
                && f.planner == r.planner
                && f.executor == r.executor
                && f.k == r.k
                && f.replan_drift == r.replan_drift
                && f.p_delay == r.p_delay
        }) {
            Some(g) => g.push(r),
            None => out.push(vec![r]),
        }
    }
    out
}

fn mean(xs: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = xs.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    if n == 0 { f64::NAN } else { s / n as f64 }
}

/// The mean of finished runs' ratios to 3 decimals, `-` when no run finished.
fn ratio(xs: impl Iterator<Item = f64>) -> String {
    let m = mean(xs);
    if m.is_nan() {
        "-".into()
    } else {
        format!("{m:.3}")
    }
}

/// Per (instance, planner, executor, p): runs, runs with a collision, deadlocks, mean
/// collisions, mean executed / planned makespan and sum of costs (finished runs).
fn table(rows: &[&ExecRow]) -> String {
    let mut out = String::from(
        "| instance | planner | k-robust | re-plan drift | executor | p | runs | collided | deadlocks | collisions (mean) | re-plans (mean) | makespan / planned | sum of costs / planned |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for g in groups(rows) {
        let f = g[0];
        if f.status == "unsolved" {
            out.push_str(&format!(
                "| {} | {} | {} | {} | {} | {} | {} (no plan) | | | | | | |\n",
                f.instance,
                f.planner,
                f.k,
                drift(f),
                f.executor,
                f.p_delay,
                g.len()
            ));
            continue;
        }
        let collided = g.iter().filter(|r| r.collisions > 0).count();
        let deadlocks = g.iter().filter(|r| r.status == "deadlock").count();
        let done: Vec<&&ExecRow> = g.iter().filter(|r| r.status == "finished").collect();
        out.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} ({:.0}%) | {} | {:.1} | {:.1} | {} | {} |\n",
            f.instance,
            f.planner,
            f.k,
            drift(f),
            f.executor,
            f.p_delay,
            g.len(),
            collided,
            100.0 * collided as f64 / g.len() as f64,
            deadlocks,
            mean(g.iter().map(|r| r.collisions as f64)),
            mean(g.iter().map(|r| r.replans as f64)),
            ratio(done.iter().map(|r| r.makespan_ratio)),
            ratio(done.iter().map(|r| r.sum_of_costs_ratio)),
        ));
    }
    out
}

fn page(sweep: &ExecutionSweep, rows: &[&ExecRow], m: &Manifest) -> String {
    let c = &sweep.cfg;
    format!(
        "# One-shot plans executed under delays\n\n\
         `mrpp {}` | command: `mrpp {}` | seed {} | {} jobs on {} threads, {:.0} s\n\n\
         Each plan is made once per instance and planner ({} s each) and executed by every \
         executor under the same Bernoulli delays per run (each robot, each tick, a delay of \
         {}–{} ticks starts with probability p); {} ticks per move, footprints of side {} cells. \
         Every execution was replayed by `mrpp_exec::check`. Ratios are over finished runs.\n\n{}\n\
         Lines over p: `execution.svg`; every run: `results.csv`.\n",
        m.mrpp_version,
        m.command.join(" "),
        m.seed,
        m.jobs,
        m.threads,
        m.wall_seconds,
        c.time_limit.as_secs_f64(),
        c.min_delay,
        c.max_delay,
        c.ticks_per_move,
        c.agent_size,
        table(rows),
    )
}

/// A re-planning drift threshold as the table shows it (`-` for none).
fn drift(r: &ExecRow) -> String {
    match r.replan_drift {
        0 => "-".into(),
        d => d.to_string(),
    }
}

/// A figure line's name: planner, robustness (when re-timed), re-planning (when on), executor.
fn name(r: &ExecRow) -> String {
    let mut n = r.planner.clone();
    if r.k > 0 {
        n += &format!(" {}-robust", r.k);
    }
    if r.replan_drift > 0 {
        n += &format!(" re-plan@{}", r.replan_drift);
    }
    format!("{n} {}", r.executor)
}

/// Three panels over the delay probability: runs with a collision (%), executed makespan over
/// planned, executed sum of costs over planned; a line per (planner, robustness, executor),
/// instances pooled. Ratios are over the plan as made (before re-timing), so a k-robust plan's
/// own extra length counts.
fn figure(rows: &[&ExecRow]) -> Result<String> {
    let mut names: Vec<String> = Vec::new();
    for r in rows {
        let n = name(r);
        if r.status != "unsolved" && !names.contains(&n) {
            names.push(n);
        }
    }
    let mut ps: Vec<f64> = rows.iter().map(|r| r.p_delay).collect();
    ps.sort_by(f64::total_cmp);
    ps.dedup();
    let series = |value: &dyn Fn(&[&ExecRow]) -> f64| -> Vec<Series> {
        names
            .iter()
            .map(|n| Series {
                name: n.clone(),
                points: ps
                    .iter()
                    .filter_map(|&p| {
                        let g: Vec<&ExecRow> = rows
                            .iter()
                            .copied()
                            .filter(|r| r.p_delay == p && r.status != "unsolved" && name(r) == *n)
                            .collect();
                        let v = value(&g);
                        (!g.is_empty() && v.is_finite()).then_some((p, v))
                    })
                    .collect(),
                ..Series::default()
            })
            .collect()
    };
    let finished = |g: &[&ExecRow], f: fn(&ExecRow) -> f64| {
        mean(g.iter().filter(|r| r.status == "finished").map(|r| f(r)))
    };
    let panels = [
        Panel {
            title: "runs with a collision (%)".into(),
            series: series(&|g| {
                100.0 * g.iter().filter(|r| r.collisions > 0).count() as f64 / g.len().max(1) as f64
            }),
        },
        Panel {
            title: "executed makespan / planned".into(),
            series: series(&|g| finished(g, |r| r.makespan_ratio)),
        },
        Panel {
            title: "executed sum of costs / planned".into(),
            series: series(&|g| finished(g, |r| r.sum_of_costs_ratio)),
        },
    ];
    line_panels(
        "one-shot plans executed under delays",
        "delay probability per robot per tick",
        "",
        &panels,
    )
    .map_err(Error::Internal)
}
