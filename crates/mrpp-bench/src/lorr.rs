//! League of Robot Runners problems run lifelong, as a sweep (issue 28, item 7): every problem x
//! lifelong planner x scheduler x guidance x run (planners `lifelong-pibt` by default, or
//! `lifelong-lns`), and optionally a peer program (the League's
//! start kit, built by hand) once per problem, all measured in tasks finished over the same
//! steps, and every run checked by mrpp's lifelong validator (the kit's rules replayed).
//!
//! The peer is a command template run with `sh -c` (placeholders `{problem}` the problem JSON,
//! `{steps}`, `{step_ms}` the planning time per step in milliseconds, `{preprocess_ms}` and `{out}`
//! the output JSON it must write; e.g. the kit's `./build/lifelong -i {problem} -o {out}
//! --simulationTime {steps} --planTimeLimit {step_ms} --preprocessTimeLimit {preprocess_ms}`). Its
//! output is read as the League's output JSON and replayed by the same validator; a command that
//! fails to run is reported as `peer_failed` with its exit status and stderr, never as a result.
//!
//! Where the issue is silent: jobs run in parallel on the harness's worker threads like every
//! sweep (each run is one thread; `mrpp experiment lorr --jobs 1` runs them one at a time), the
//! run's overall limit is twice its steps' budgets plus its
//! preprocessing time plus a minute, and a peer gets the same.

use std::path::{Path, PathBuf};
use std::time::Duration;

use serde::{Deserialize, Serialize};

use crate::harness::{Manifest, PeerRun, RunRecord, Sweep, run_peer_command, shell_quote};
use crate::report::{Panel, Series, csv_text, line_panels};
use crate::sweep::PeerSpec;
use mrpp_core::error::{Error, Result};
use mrpp_core::seeds::derive_seed;
use mrpp_core::{Ctx, Deadline, Problem, Unsolved, solve};
use mrpp_exec::DelayConfig;
use mrpp_lifelong::PLANNERS;
use mrpp_lifelong::execution::ExecutionModel;
use mrpp_lifelong::executor::ExecutorKind;
use mrpp_lifelong::lorr_output::from_json;
use mrpp_lifelong::problem::replay;
use mrpp_lifelong::runner::PIBT_ENTRY;
use mrpp_lifelong::{ActionModel, LifelongProblem, Trace};

/// What to run.
#[derive(Debug, Clone)]
pub struct LorrConfig {
    pub seed: u64,
    /// League of Robot Runners problem JSON files (any start-kit layout).
    pub problems: Vec<PathBuf>,
    /// Horizon in steps (the kit's `--simulationTime`).
    pub steps: u32,
    /// Planning time per step (the kit's `--planTimeLimit`).
    pub step_time: Duration,
    /// Time before step 0 (the kit's `--preprocessTimeLimit`).
    pub preprocess_time: Duration,
    pub model: ActionModel,
    /// Lifelong planners to run, by registry name.
    pub planners: Vec<String>,
    /// The planners' `scheduler` values to run.
    pub schedulers: Vec<String>,
    /// The planners' `guidance` values to run.
    pub guidance: Vec<String>,
    /// Runs (seeds) per configuration.
    pub runs: usize,
    pub peer: Option<PeerSpec>,
    /// Run in ticks under the League's 2026 execution model (`steps` then counts ticks and
    /// `step_time` is each planner call's time); `None`: one action per step.
    pub ticks: Option<TicksConfig>,
}

/// The 2026 execution model's settings of a sweep in ticks: each problem's own `agentCounter`,
/// `agentSize` and `delayConfig`, with these.
#[derive(Debug, Clone)]
pub struct TicksConfig {
    pub executor: ExecutorKind,
    /// Ticks between planner calls.
    pub plan_every: u32,
    /// Delays for mrpp's runs instead of each problem's `delayConfig` (a peer reads the file).
    pub delays: Option<DelayConfig>,
    /// Delay probabilities to sweep (empty: each problem's own): each problem runs once per
    /// value, its delays (`delays`, else its `delayConfig`) with `pDelay` replaced; a peer reads
    /// a copy of the problem file whose `delayConfig` says the same.
    pub delay_probabilities: Vec<f64>,
    /// Actions of slack to sweep (`mrpp_lifelong::k_robust`; empty: 0 only): every planner
    /// configuration runs once per value, named `PLANNER+K-robust` for K > 0 (the peer once).
    pub k_robust: Vec<u32>,
}

/// One run of the sweep.
#[derive(Debug, Clone)]
pub enum LorrJob {
    /// A planner on problem `problem` with scheduler and guidance by index, run `run`.
    Mrpp {
        problem: usize,
        planner: usize,
        scheduler: usize,
        guidance: usize,
        run: usize,
        /// Index into [`TicksConfig::k_robust`] (0 when it is empty).
        robust: usize,
    },
    /// The peer on problem `problem`.
    Peer { problem: usize },
}

/// A run's result.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LorrRow {
    /// The problem's name (with `@p=P` in a sweep over delay probabilities).
    pub problem: String,
    /// The delay probability of a sweep over them (`None`: the problem's own).
    #[serde(default)]
    pub p_delay: Option<f64>,
    pub robots: usize,
    pub free_cells: usize,
    /// The planner's or the peer's name.
    pub program: String,
    pub scheduler: String,
    pub guidance: String,
    pub run: usize,
    pub seed: u64,
    /// `valid`, or for a peer `invalid` (refused by the validator) or `peer_failed`.
    pub status: String,
    pub tasks_finished: Option<usize>,
    pub errands: Option<usize>,
    pub steps: u32,
    pub late_steps: usize,
    /// Planner time per step from the run's own record (`plannerTimes`), milliseconds.
    pub planner_ms_mean: f64,
    pub planner_ms_p99: f64,
    pub planner_ms_max: f64,
    pub wall_s: f64,
    /// Tasks finished after each step (index 0: before step 1).
    pub finished: Vec<u32>,
    /// Why a peer failed, or the validator's refusal.
    pub note: String,
    /// In ticks, mrpp's runs: robot-ticks the per-tick resolution made a robot wait rather
    /// than collide (`errors` of the trace; the kit records only the last tick's).
    #[serde(default)]
    pub resolver_waits: Option<usize>,
}

/// The sweep.
pub struct LorrSweep {
    cfg: LorrConfig,
    problems: Vec<(String, LifelongProblem)>,
    /// Per entry of `problems`: its file's index in the configuration and the swept delay
    /// probability, if any.
    sources: Vec<(usize, Option<f64>)>,
    jobs: Vec<LorrJob>,
}

/// The placeholders a peer's command may use.
const PLACEHOLDERS: [&str; 5] = ["problem", "steps", "step_ms", "preprocess_ms", "out"];

impl LorrSweep {
    /// Loads every problem and checks every option before any run.
    ///
    /// # Errors
    /// A problem that does not read (file, line and rule), an unknown scheduler or guidance, no
    /// problem, zero runs, or a peer command without `{problem}` and `{out}` or with an unknown
    /// placeholder.
    pub fn new(cfg: LorrConfig) -> Result<Self> {
        if cfg.problems.is_empty() {
            return Err(Error::Param("no problem to run".into()));
        }
        if cfg.runs == 0 {
            return Err(Error::Param("--runs must be at least 1".into()));
        }
        if cfg.planners.is_empty() {
            return Err(Error::Param("no planner to run".into()));
        }
        for name in &cfg.planners {
            let entry = planner_entry(name)?;
            for s in &cfg.schedulers {
                for g in &cfg.guidance {
                    entry.instantiate(&[
                        ("scheduler".into(), s.clone()),
                        ("guidance".into(), g.clone()),
                    ])?;
                }
            }
        }
        if let Some(peer) = &cfg.peer {
            check_placeholders(&peer.command)?;
        }
        let mut problems = Vec::new();
        let mut sources = Vec::new();
        let mut names = std::collections::HashSet::new();
        for (index, path) in cfg.problems.iter().enumerate() {
            let mut p = LifelongProblem::load(path, cfg.model, cfg.steps, cfg.step_time)?
                .with_preprocess_time(cfg.preprocess_time);
            let name = path.file_stem().map_or_else(
                || path.display().to_string(),
                |s| s.to_string_lossy().into(),
            );
            if !names.insert(name.clone()) {
                return Err(Error::Param(format!(
                    "two problems are named {name}: give files with different names"
                )));
            }
            let Some(t) = &cfg.ticks else {
                problems.push((name, p));
                sources.push((index, None));
                continue;
            };
            let mut m = ExecutionModel::of_problem(p.files())?;
            m.executor = t.executor;
            m.plan_every = t.plan_every;
            if let Some(d) = &t.delays {
                m.delays = d.clone();
            }
            if t.delay_probabilities.is_empty() {
                p = p.with_execution(m);
                problems.push((name, p));
                sources.push((index, None));
                continue;
            }
            if t.delays.is_none() && p.files().json.get("delayConfig").is_none() {
                return Err(Error::Param(format!(
                    "{}: no delayConfig to sweep the delay probability of; give --delays (its durations are kept, its p replaced)",
                    path.display()
                )));
            }
            for &prob in &t.delay_probabilities {
                if !(0.0..=1.0).contains(&prob) {
                    return Err(Error::Param(format!(
                        "delay probability {prob}: expected a number in [0, 1]"
                    )));
                }
                let mut m = m.clone();
                m.delays.p_delay = prob;
                problems.push((format!("{name}@p={prob}"), p.clone().with_execution(m)));
                sources.push((index, Some(prob)));
            }
        }
        let robust_values = cfg.ticks.as_ref().map_or(1, |t| t.k_robust.len().max(1));
        let mut jobs = Vec::new();
        for problem in 0..problems.len() {
            if cfg.peer.is_some() {
                jobs.push(LorrJob::Peer { problem });
            }
            for planner in 0..cfg.planners.len() {
                for scheduler in 0..cfg.schedulers.len() {
                    for guidance in 0..cfg.guidance.len() {
                        for robust in 0..robust_values {
                            for run in 0..cfg.runs {
                                jobs.push(LorrJob::Mrpp {
                                    problem,
                                    planner,
                                    scheduler,
                                    guidance,
                                    run,
                                    robust,
                                });
                            }
                        }
                    }
                }
            }
        }
        Ok(LorrSweep {
            cfg,
            problems,
            sources,
            jobs,
        })
    }

    fn row(&self, problem: usize, program: &str) -> LorrRow {
        let (name, p) = &self.problems[problem];
        LorrRow {
            problem: name.clone(),
            p_delay: self.sources[problem].1,
            robots: p.num_agents(),
            free_cells: p.map().graph().num_vertices(),
            program: program.into(),
            scheduler: String::new(),
            guidance: String::new(),
            run: 0,
            seed: 0,
            status: String::new(),
            tasks_finished: None,
            errands: None,
            steps: 0,
            late_steps: 0,
            planner_ms_mean: 0.0,
            planner_ms_p99: 0.0,
            planner_ms_max: 0.0,
            wall_s: 0.0,
            finished: Vec::new(),
            note: String::new(),
            resolver_waits: None,
        }
    }

    /// The `index`th value of the k-robust sweep (0 without one).
    fn k_robust(&self, index: usize) -> u32 {
        self.cfg
            .ticks
            .as_ref()
            .and_then(|t| t.k_robust.get(index).copied())
            .unwrap_or(0)
    }

    /// The overall limit of one run (module doc).
    fn run_limit(&self) -> Duration {
        let calls = match &self.cfg.ticks {
            None => self.cfg.steps,
            Some(t) => self.cfg.steps / t.plan_every.max(1) + 2,
        };
        self.cfg.step_time * calls * 2 + self.cfg.preprocess_time + Duration::from_secs(60)
    }

    /// Fills `row` from a trace the validator accepts, or says why not.
    fn measure(&self, problem: usize, trace: &Trace, row: &mut LorrRow) -> Result<()> {
        let p = &self.problems[problem].1;
        let m = p
            .validate(trace)
            .map_err(|v| Error::Internal(v.to_string()))?;
        let mut finished = vec![0u32];
        replay(p, trace, |sim| finished.push(sim.finished as u32))
            .map_err(|v| Error::Internal(v.to_string()))?;
        let mut times: Vec<f64> = trace.planner_times.iter().map(|t| t * 1e3).collect();
        times.sort_by(f64::total_cmp);
        row.status = "valid".into();
        row.tasks_finished = Some(m.tasks_finished);
        row.errands = Some(m.errands);
        row.steps = m.steps;
        row.late_steps = m.late_steps;
        if !times.is_empty() {
            row.planner_ms_mean = times.iter().sum::<f64>() / times.len() as f64;
            row.planner_ms_p99 = times[((times.len() - 1) as f64 * 0.99) as usize];
            row.planner_ms_max = times[times.len() - 1];
        }
        row.finished = finished;
        row.resolver_waits = trace.ticks.is_some().then_some(trace.errors.len());
        Ok(())
    }

    /// The problem file a peer reads: the configuration's, or in a sweep over delay
    /// probabilities a copy in `dir` whose `delayConfig` is this entry's delays and whose files
    /// are named relative to `dir` (the kit reads them relative to the problem file).
    fn peer_problem(&self, problem: usize, dir: &Path) -> std::result::Result<PathBuf, String> {
        let (index, prob) = self.sources[problem];
        let path = &self.cfg.problems[index];
        let path = std::fs::canonicalize(path).unwrap_or_else(|_| path.clone());
        if prob.is_none() {
            return Ok(path);
        }
        let p = &self.problems[problem].1;
        let m = p.execution().expect("a sweep over delays runs in ticks");
        let mut json = p.files().json.clone();
        let base = path.parent().unwrap_or(Path::new("/"));
        // `dir` is absolute: climb to the root, then down to the original file.
        let up = "../".repeat(dir.components().count().saturating_sub(1));
        for key in ["mapFile", "agentFile", "taskFile"] {
            if let Some(rel) = json.get(key).and_then(|v| v.as_str()) {
                let file = base.join(rel);
                let file = file.strip_prefix("/").unwrap_or(&file).to_string_lossy();
                json[key] = serde_json::Value::String(format!("{up}{file}"));
            }
        }
        json["delayConfig"] = mrpp_lifelong::execution::delay_config_json(&m.delays, m.delay_seed);
        let copy = dir.join(path.file_name().unwrap_or_else(|| "problem.json".as_ref()));
        std::fs::write(&copy, json.to_string())
            .map_err(|e| format!("cannot write {}: {e}", copy.display()))?;
        Ok(copy)
    }

    fn run_peer(&self, problem: usize, peer: &PeerSpec) -> LorrRow {
        let mut row = self.row(problem, &peer.name);
        row.scheduler = "its own".into();
        row.guidance = "its own".into();
        let dir =
            std::env::temp_dir().join(format!("mrpp-lorr-peer-{}-{problem}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        if let Err(e) = std::fs::create_dir_all(&dir) {
            row.status = "peer_failed".into();
            row.note = format!("cannot make {}: {e}", dir.display());
            return row;
        }
        let out = dir.join("out.json");
        let path = match self.peer_problem(problem, &dir) {
            Ok(path) => path,
            Err(e) => {
                row.status = "peer_failed".into();
                row.note = e;
                return row;
            }
        };
        let mut command = peer.command.clone();
        for (k, v) in [
            ("problem", shell_quote(&path.to_string_lossy())),
            ("steps", self.cfg.steps.to_string()),
            ("step_ms", self.cfg.step_time.as_millis().to_string()),
            (
                "preprocess_ms",
                self.cfg.preprocess_time.as_millis().to_string(),
            ),
            ("out", shell_quote(&out.to_string_lossy())),
        ] {
            command = command.replace(&format!("{{{k}}}"), &v);
        }
        let ran = run_peer_command(&command, &out, &dir.join("stderr.txt"), self.run_limit());
        let _ = std::fs::remove_dir_all(&dir);
        let (text, wall_ms) = match ran {
            PeerRun::Failed { note, wall_ms } => {
                row.status = "peer_failed".into();
                row.note = note;
                row.wall_s = wall_ms / 1e3;
                return row;
            }
            PeerRun::Killed { wall_ms } => {
                row.status = "peer_failed".into();
                row.note = format!("killed after {:.0} s", wall_ms / 1e3);
                row.wall_s = wall_ms / 1e3;
                return row;
            }
            PeerRun::Done { text, wall_ms, .. } => (text, wall_ms),
        };
        row.wall_s = wall_ms / 1e3;
        let p = &self.problems[problem].1;
        let verdict = from_json(p, &text, &out)
            .map_err(|e| e.to_string())
            .and_then(|(trace, claims)| {
                self.measure(problem, &trace, &mut row)
                    .map_err(|e| e.to_string())?;
                // The kit's output keeps only the last tick's waits.
                row.resolver_waits = None;
                if Some(claims.tasks_finished) != row.tasks_finished.map(|t| t as u64) {
                    return Err(format!(
                        "it claims {} tasks finished, the replay counts {:?}",
                        claims.tasks_finished, row.tasks_finished
                    ));
                }
                Ok(())
            });
        if let Err(why) = verdict {
            row.status = "invalid".into();
            row.note = why;
            row.tasks_finished = None;
            row.errands = None;
        }
        row
    }
}

/// The lifelong planner named `name`.
fn planner_entry(name: &str) -> Result<&'static mrpp_core::PlannerEntry<LifelongProblem>> {
    PLANNERS.iter().find(|e| e.name == name).ok_or_else(|| {
        let known: Vec<&str> = PLANNERS.iter().map(|e| e.name).collect();
        Error::Param(format!(
            "unknown lifelong planner {name} (known: {})",
            known.join(", ")
        ))
    })
}

fn check_placeholders(command: &str) -> Result<()> {
    for needed in ["problem", "out"] {
        if !command.contains(&format!("{{{needed}}}")) {
            return Err(Error::Param(format!(
                "the peer command must use {{{needed}}}: {command}"
            )));
        }
    }
    let mut rest = command;
    while let Some(i) = rest.find('{') {
        let Some(j) = rest[i..].find('}') else { break };
        let name = &rest[i + 1..i + j];
        if !PLACEHOLDERS.contains(&name) {
            return Err(Error::Param(format!(
                "unknown placeholder {{{name}}} in the peer command (known: {})",
                PLACEHOLDERS.map(|p| format!("{{{p}}}")).join(", ")
            )));
        }
        rest = &rest[i + j + 1..];
    }
    Ok(())
}

impl Sweep for LorrSweep {
    type Job = LorrJob;
    type Row = LorrRow;

    fn name(&self) -> &str {
        "lorr"
    }
    fn jobs(&self) -> &[LorrJob] {
        &self.jobs
    }
    fn key(&self, job: &LorrJob) -> String {
        match *job {
            LorrJob::Mrpp {
                problem,
                planner,
                scheduler,
                guidance,
                run,
                robust,
            } => {
                // lifelong-pibt's keys (and so its seeds) are those of the sweeps before
                // other planners could be run.
                let name = &self.cfg.planners[planner];
                let planner = if name == PIBT_ENTRY.name {
                    String::new()
                } else {
                    format!("{name}/")
                };
                // k = 0 keeps the keys (and seeds) of sweeps before k-robust runs.
                let robust = match self.k_robust(robust) {
                    0 => String::new(),
                    k => format!("/k{k}"),
                };
                format!(
                    "{}/{planner}{}/{}/{run}{robust}",
                    self.problems[problem].0,
                    self.cfg.schedulers[scheduler],
                    self.cfg.guidance[guidance]
                )
            }
            LorrJob::Peer { problem } => format!(
                "{}/peer/{}",
                self.problems[problem].0,
                self.cfg.peer.as_ref().map_or("", |p| p.name.as_str())
            ),
        }
    }
    fn run(&self, job: &LorrJob) -> Result<LorrRow> {
        let (problem, planner, scheduler, guidance, run, robust) = match *job {
            LorrJob::Peer { problem } => {
                let peer = self.cfg.peer.as_ref().expect("a peer job has a peer");
                return Ok(self.run_peer(problem, peer));
            }
            LorrJob::Mrpp {
                problem,
                planner,
                scheduler,
                guidance,
                run,
                robust,
            } => (problem, planner, scheduler, guidance, run, robust),
        };
        let entry = planner_entry(&self.cfg.planners[planner])?;
        let k = self.k_robust(robust);
        let mut row = if k == 0 {
            self.row(problem, entry.name)
        } else {
            self.row(problem, &format!("{}+{k}-robust", entry.name))
        };
        row.scheduler = self.cfg.schedulers[scheduler].clone();
        row.guidance = self.cfg.guidance[guidance].clone();
        row.run = run;
        row.seed = derive_seed(self.cfg.seed, &self.key(job));
        let planner = entry.instantiate(&[
            ("scheduler".into(), row.scheduler.clone()),
            ("guidance".into(), row.guidance.clone()),
        ])?;
        let with_k;
        let p = if k == 0 {
            &self.problems[problem].1
        } else {
            let p = &self.problems[problem].1;
            let mut m = p.execution().cloned().expect("k-robust runs are in ticks");
            m.k_robust = k;
            with_k = p.clone().with_execution(m);
            &with_k
        };
        let started = std::time::Instant::now();
        let solved = solve(
            planner.as_ref(),
            p,
            &Ctx::new(row.seed, Deadline::after(self.run_limit())),
        )
        .map_err(|e| match e {
            Unsolved::Invalid(why) => Error::Internal(format!("{}: {why}", self.key(job))),
            other => Error::Internal(format!("{}: {}", self.key(job), other.status())),
        })?;
        row.wall_s = started.elapsed().as_secs_f64();
        self.measure(problem, &solved.plan, &mut row)?;
        Ok(row)
    }
    fn records(&self, r: &LorrRow) -> Vec<RunRecord> {
        vec![RunRecord {
            job: 0,
            key: String::new(),
            family: mrpp_lifelong::FAMILY.into(),
            instance: r.problem.clone(),
            planner: r.program.clone(),
            params: format!("scheduler={};guidance={}", r.scheduler, r.guidance),
            run: r.run,
            seed: r.seed,
            status: if r.status == "valid" {
                "solved".into()
            } else {
                r.status.clone()
            },
            sum_of_costs: None,
            makespan: Some(u64::from(r.steps)),
            sum_of_moves: None,
            runtime_ms: r.wall_s * 1e3,
            note: r.note.clone(),
            ..Default::default()
        }]
    }
    fn pages(&self, rows: &[&LorrRow], m: &Manifest) -> Result<Vec<(String, String)>> {
        let mut pages = vec![
            ("results.csv".into(), results_csv(rows)?),
            ("lorr.md".into(), page(self, rows, m)),
            ("throughput.svg".into(), figure(self, rows)?),
        ];
        if self.sources.iter().any(|s| s.1.is_some()) {
            pages.push(("delays.svg".into(), delay_figure(self, rows)?));
        }
        Ok(pages)
    }
    fn summary(&self, rows: &[&LorrRow]) -> String {
        table(rows)
    }
    fn config(&self) -> String {
        format!("{:?}", self.cfg)
    }
}

fn results_csv(rows: &[&LorrRow]) -> Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let e = |e: csv::Error| Error::Internal(e.to_string());
    w.write_record([
        "problem",
        "robots",
        "free_cells",
        "program",
        "scheduler",
        "guidance",
        "run",
        "seed",
        "status",
        "tasks_finished",
        "errands",
        "steps",
        "late_steps",
        "planner_ms_mean",
        "planner_ms_p99",
        "planner_ms_max",
        "wall_s",
        "note",
        "resolver_waits",
    ])
    .map_err(e)?;
    let opt = |v: Option<usize>| v.map(|x| x.to_string()).unwrap_or_default();
    for r in rows {
        w.write_record([
            r.problem.clone(),
            r.robots.to_string(),
            r.free_cells.to_string(),
            r.program.clone(),
            r.scheduler.clone(),
            r.guidance.clone(),
            r.run.to_string(),
            r.seed.to_string(),
            r.status.clone(),
            opt(r.tasks_finished),
            opt(r.errands),
            r.steps.to_string(),
            r.late_steps.to_string(),
            format!("{:.3}", r.planner_ms_mean),
            format!("{:.3}", r.planner_ms_p99),
            format!("{:.3}", r.planner_ms_max),
            format!("{:.2}", r.wall_s),
            r.note.clone(),
            opt(r.resolver_waits),
        ])
        .map_err(e)?;
    }
    csv_text(w)
}

/// A configuration's label: the program, and for mrpp its scheduler and guidance.
fn label(r: &LorrRow) -> String {
    if r.program == PIBT_ENTRY.name {
        format!("{} {} {}", r.program, r.scheduler, r.guidance)
    } else {
        r.program.clone()
    }
}

/// Per problem and configuration: tasks finished (mean and range over runs), late steps, planner
/// ms per step (mean, largest 99th percentile).
fn table(rows: &[&LorrRow]) -> String {
    let mut out = String::from(
        "| problem | robots | robots / free cells | program | runs | tasks finished (mean, min–max) | late steps | planner ms/step (mean / p99) |\n|---|---|---|---|---|---|---|---|\n",
    );
    let mut keys: Vec<(String, String)> = Vec::new();
    for r in rows {
        let k = (r.problem.clone(), label(r));
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    for (problem, config) in keys {
        let group: Vec<&&LorrRow> = rows
            .iter()
            .filter(|r| r.problem == problem && label(r) == config)
            .collect();
        let first = group[0];
        let done: Vec<usize> = group.iter().filter_map(|r| r.tasks_finished).collect();
        let tasks = if done.is_empty() {
            format!("— ({})", first.status)
        } else {
            format!(
                "{:.1} ({}–{})",
                done.iter().sum::<usize>() as f64 / done.len() as f64,
                done.iter().min().expect("non-empty"),
                done.iter().max().expect("non-empty")
            )
        };
        let late: usize = group.iter().map(|r| r.late_steps).sum();
        let mean = group.iter().map(|r| r.planner_ms_mean).sum::<f64>() / group.len() as f64;
        let p99 = group.iter().map(|r| r.planner_ms_p99).fold(0.0, f64::max);
        out.push_str(&format!(
            "| {problem} | {} | {:.1}% | {config} | {} | {tasks} | {late} | {mean:.1} / {p99:.0} |\n",
            first.robots,
            100.0 * first.robots as f64 / first.free_cells.max(1) as f64,
            group.len(),
        ));
    }
    out
}

fn page(sweep: &LorrSweep, rows: &[&LorrRow], m: &Manifest) -> String {
    let failed: Vec<String> = rows
        .iter()
        .filter(|r| r.status != "valid")
        .map(|r| {
            format!(
                "- {} on {}: {} ({})",
                r.program, r.problem, r.status, r.note
            )
        })
        .collect();
    format!(
        "# League of Robot Runners problems, lifelong\n\n\
         `mrpp {}` | command: `mrpp {}` | seed {} | {} jobs on {} threads, {:.0} s\n\n\
         {}, {} s preprocessing, {}. Every run below was replayed by mrpp's \
         lifelong validator (the start kit's rules); tasks finished are its count. Planner times \
         are each run's own record (machine-dependent).\n\n{}\n{}\n\
         Tasks finished over the steps: `throughput.svg`{}; every run: `results.csv`.\n",
        m.mrpp_version,
        m.command.join(" "),
        m.seed,
        m.jobs,
        m.threads,
        m.wall_seconds,
        match &sweep.cfg.ticks {
            None => format!(
                "{} steps, {} s per step",
                sweep.cfg.steps,
                sweep.cfg.step_time.as_secs_f64()
            ),
            Some(t) => format!(
                "{} ticks under the League's 2026 execution model (each problem's agentCounter, agentSize and {}; executor {}; a plan every {} ticks, {} s each)",
                sweep.cfg.steps,
                t.delays
                    .as_ref()
                    .map_or("delayConfig".to_string(), |d| format!(
                        "delays {}",
                        d.spec()
                    )),
                t.executor.name(),
                t.plan_every,
                sweep.cfg.step_time.as_secs_f64()
            ),
        },
        sweep.cfg.preprocess_time.as_secs_f64(),
        sweep.cfg.model.name(),
        table(rows),
        if failed.is_empty() {
            String::new()
        } else {
            format!("Runs without a result:\n{}\n", failed.join("\n"))
        },
        if sweep.sources.iter().any(|s| s.1.is_some()) {
            "; over the delay probability: `delays.svg`"
        } else {
            ""
        }
    )
}

/// One panel per problem: tasks finished after each step, a line per configuration (the first
/// run of each; at most about 150 points a line).
fn figure(sweep: &LorrSweep, rows: &[&LorrRow]) -> Result<String> {
    let panels: Vec<Panel> = sweep
        .problems
        .iter()
        .map(|(name, _)| Panel {
            title: name.clone(),
            series: rows
                .iter()
                .filter(|r| &r.problem == name && r.run == 0 && !r.finished.is_empty())
                .map(|r| {
                    let last = r.finished.len() - 1;
                    let stride = last.div_ceil(150).max(1);
                    Series {
                        name: label(r),
                        points: (0..=last)
                            .filter(|t| t % stride == 0 || *t == last)
                            .map(|t| (t as f64, f64::from(r.finished[t])))
                            .collect(),
                        ..Series::default()
                    }
                })
                .collect(),
        })
        .collect();
    line_panels(
        "tasks finished over the steps (first run of each configuration)",
        "step",
        "tasks finished",
        &panels,
    )
    .map_err(Error::Internal)
}

/// One panel per problem file of a sweep over delay probabilities: tasks finished (mean over
/// runs) over the delay probability, a line per configuration.
fn delay_figure(sweep: &LorrSweep, rows: &[&LorrRow]) -> Result<String> {
    let mut files: Vec<usize> = sweep.sources.iter().map(|s| s.0).collect();
    files.dedup();
    let panels: Vec<Panel> = files
        .into_iter()
        .map(|index| {
            let names: Vec<&str> = sweep
                .sources
                .iter()
                .zip(&sweep.problems)
                .filter(|(s, _)| s.0 == index)
                .map(|(_, (n, _))| n.as_str())
                .collect();
            let mine: Vec<&&LorrRow> = rows
                .iter()
                .filter(|r| names.contains(&r.problem.as_str()) && r.tasks_finished.is_some())
                .collect();
            let mut labels: Vec<String> = mine.iter().map(|r| label(r)).collect();
            labels.sort();
            labels.dedup();
            let series = labels
                .into_iter()
                .map(|l| {
                    let mut points: Vec<(f64, f64)> = Vec::new();
                    for name in &names {
                        let done: Vec<f64> = mine
                            .iter()
                            .filter(|r| r.problem == *name && label(r) == l)
                            .filter_map(|r| r.tasks_finished.map(|t| t as f64))
                            .collect();
                        let p = mine
                            .iter()
                            .find(|r| r.problem == *name)
                            .and_then(|r| r.p_delay);
                        if let (Some(p), false) = (p, done.is_empty()) {
                            points.push((p, done.iter().sum::<f64>() / done.len() as f64));
                        }
                    }
                    Series {
                        name: l,
                        points,
                        ..Series::default()
                    }
                })
                .collect();
            Panel {
                title: sweep.cfg.problems[index]
                    .file_stem()
                    .map_or_else(String::new, |s| s.to_string_lossy().into()),
                series,
            }
        })
        .collect();
    line_panels(
        "tasks finished over the delay probability (mean over runs)",
        "delay probability per robot per tick",
        "tasks finished",
        &panels,
    )
    .map_err(Error::Internal)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peer_placeholders_are_checked() {
        assert!(check_placeholders("kit -i {problem} -o {out} -s {steps} -t {step_ms}").is_ok());
        assert!(check_placeholders("kit -i {problem}").is_err());
        let e = check_placeholders("kit -i {problem} -o {out} {seed}").unwrap_err();
        assert!(e.to_string().contains("{seed}"), "{e}");
    }

    #[test]
    fn a_sweep_over_delay_probabilities_gives_each_value_its_problem_and_peer_file() {
        let problem = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../data/robot-runners/lorr2026-maze/maze-example_40.json");
        let cfg = |probabilities: Vec<f64>| LorrConfig {
            seed: 0,
            problems: vec![problem.clone()],
            steps: 30,
            step_time: Duration::from_millis(100),
            preprocess_time: Duration::from_secs(1),
            model: ActionModel::MapfT,
            planners: vec![PIBT_ENTRY.name.into()],
            schedulers: vec!["greedy".into()],
            guidance: vec!["auto".into()],
            runs: 1,
            peer: None,
            ticks: Some(TicksConfig {
                executor: ExecutorKind::Tpg,
                plan_every: 10,
                delays: None,
                delay_probabilities: probabilities,
                k_robust: Vec::new(),
            }),
        };
        let sweep = LorrSweep::new(cfg(vec![0.0, 0.05])).unwrap();
        let names: Vec<&str> = sweep.problems.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["maze-example_40@p=0", "maze-example_40@p=0.05"]);
        let own = ExecutionModel::of_problem(sweep.problems[0].1.files()).unwrap();
        let swept = sweep.problems[1].1.execution().unwrap();
        assert_eq!(swept.delays.p_delay, 0.05);
        assert_eq!(swept.delays.min_delay, own.delays.min_delay);
        assert_eq!(swept.delays.max_delay, own.delays.max_delay);
        assert_eq!(sweep.jobs.len(), 2);
        // The peer's copy: the same problem, read from elsewhere, with the swept delays.
        let dir = std::env::temp_dir().join(format!("mrpp-lorr-sweep-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let copy = sweep.peer_problem(1, &dir).unwrap();
        assert_eq!(copy.parent(), Some(dir.as_path()));
        let read = LifelongProblem::load(&copy, ActionModel::MapfT, 30, Duration::from_millis(100))
            .unwrap();
        let model = ExecutionModel::of_problem(read.files()).unwrap();
        assert_eq!(model.delays, swept.delays);
        assert_eq!(model.delay_seed, own.delay_seed);
        assert_eq!(read.num_agents(), sweep.problems[1].1.num_agents());
        assert_eq!(
            read.map().graph().num_vertices(),
            sweep.problems[1].1.map().graph().num_vertices()
        );
        // Without a sweep the peer reads the file itself.
        let own_only = LorrSweep::new(cfg(Vec::new())).unwrap();
        assert_eq!(own_only.problems[0].0, "maze-example_40");
        assert_eq!(
            own_only.peer_problem(0, &dir).unwrap(),
            std::fs::canonicalize(&problem).unwrap()
        );
        std::fs::remove_dir_all(&dir).unwrap();
        let e = LorrSweep::new(cfg(vec![1.5])).err().unwrap();
        assert!(e.to_string().contains("[0, 1]"), "{e}");
        // A k-robust sweep: one run per value, named after it, k = 0 keeping its old key (and
        // seed), each run valid and filtered.
        let mut c = cfg(vec![0.05]);
        c.ticks.as_mut().unwrap().k_robust = vec![0, 2];
        let sweep = LorrSweep::new(c).unwrap();
        assert_eq!(sweep.jobs.len(), 2);
        let keys: Vec<String> = sweep.jobs.iter().map(|j| sweep.key(j)).collect();
        assert_eq!(
            keys,
            [
                "maze-example_40@p=0.05/greedy/auto/0",
                "maze-example_40@p=0.05/greedy/auto/0/k2"
            ]
        );
        let rows: Vec<LorrRow> = sweep.jobs.iter().map(|j| sweep.run(j).unwrap()).collect();
        assert_eq!(rows[0].program, PIBT_ENTRY.name);
        assert_eq!(rows[1].program, format!("{}+2-robust", PIBT_ENTRY.name));
        for r in &rows {
            assert_eq!(r.status, "valid");
            assert!(r.resolver_waits.is_some());
        }
    }

    #[test]
    fn a_path_with_a_quote_is_quoted_for_the_shell() {
        assert_eq!(shell_quote("a'b"), "'a'\\''b'");
    }
}
