//! The HBMO navigation paper's experiments (§5, Figs. 5–12) as a sweep: HBMO, DE, PSO and ORCA
//! on seeded worlds, `runs` runs each (the paper: k = 5), with the paper's metrics.
//!
//! Panels (robots of radius 6, all at one speed; the sweeps' worlds from [`random_world`], chosen
//! by [`SweepWorlds`]: `fresh`, the default, draws one world per value with a seed derived from
//! the user's seed and the panel's key; `fixed` draws one world of 10 robots and 10 obstacles
//! from the seed and gives every value a prefix of it, so the obstacle sweep keeps the old
//! obstacles and adds new ones, as the paper does: "old obstacles were retained and new obstacles
//! were added"):
//! - `fig12`: the bundled 6-robot / 4-obstacle world (`six-robots-four-obstacles.json`): steps to
//!   arrival, ATPT, ATPD, AUTD per method, with Mann–Whitney p-values of HBMO against each other
//!   method (so do the sweeps' tables, per world) (the paper: HBMO 35, DE 37, PSO 38 steps, one run shown);
//! - `robots`: 2, 4, 6, 8, 10 robots among 4 obstacles at speed 16 (Figs. 6, 9–11: AUTD per step,
//!   ATPT, ATPD, AUTD against the robot count);
//! - `obstacles`: 2, 4, 6, 8, 10 obstacles with 6 robots at speed 16 (Fig. 7b: ATPD against the
//!   obstacle count);
//! - `velocity`: speeds 4, 8, 12, 16, 20 with 6 robots among 5 obstacles (Fig. 5: AUTD per step
//!   against the speed).
//!
//! Metrics (§5): ATPT (total path traversed), ATPD (Σ_i traversed_i − ideal_i), and the
//! uncovered target distance `UTD(t) = Σ_i ‖G_i − C_i(t)‖` (§5.2). The paper's AUTD is a *curve*:
//! `AUTD(t) = (1/k) Σ_runs UTD_run(t)`, plotted against the step (Figs. 5, 6, 11; drawn here as
//! `fig5-6-autd.svg`). The tables give two per-run numbers averaged over the arrived runs: `AUTD`,
//! the run's UTD averaged over its steps `0..=T` (`(1/(T+1)) Σ_t UTD(t)`; a slow run adds many
//! small late values and so looks better), and `UTD total`, the area under the run's curve
//! `Σ_{t=0..=T} UTD(t)` (length × steps; it grows with every step a robot is still short of its
//! goal, and equals the mean over any fixed horizon ≥ T times that horizon, since UTD stays 0
//! after arrival).
//!
//! Where the paper is silent: its worlds are figures only, so ours are generated; a run that does
//! not arrive (deadlock or step limit) is reported and left out of the means, never counted as
//! arrived; every planner runs with its registry defaults (joint mode, the waypoint guide and the
//! `near` obstacle term; `--param guide=goal` gives the paper's literal target,
//! `--param preset=paper` every paper-literal choice) plus the experiment's `params`
//! (see [`HbmoConfig::params`]).

use std::path::{Path, PathBuf};
use std::time::Duration;

use serde::{Deserialize, Serialize};

use crate::harness::{Manifest, RunRecord, Sweep};
use crate::report::{Panel, Series, csv_text, line_panels, line_panels_with};
use crate::stats::mann_whitney;
use mrpp_continuous::generator::random_world;
use mrpp_continuous::render::render_svg;
use mrpp_continuous::{NavProblem, PLANNERS, Trajectories, World};
use mrpp_core::error::{Error, Result};
use mrpp_core::seeds::derive_seed;
use mrpp_core::{Ctx, Deadline, Unsolved, solve};

/// The paper's steps to arrival on its 6-robot / 4-obstacle world (Fig. 12): HBMO, DE, PSO.
pub const PAPER_STEPS: [(&str, f64); 3] = [("hbmo", 35.0), ("de", 37.0), ("pso", 38.0)];

/// How the sweeps' worlds are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SweepWorlds {
    /// One generated world per sweep value, each from its own seed (mrpp before issue 32).
    #[default]
    Fresh,
    /// One generated world (10 robots, 10 obstacles) for every sweep; a value takes its first
    /// robots and first obstacles, so each obstacle count keeps the previous count's obstacles
    /// (the paper, §5).
    Fixed,
}

impl SweepWorlds {
    /// The CLI's name of this choice.
    pub fn name(self) -> &'static str {
        match self {
            SweepWorlds::Fresh => "fresh",
            SweepWorlds::Fixed => "fixed",
        }
    }
}

/// What to run.
#[derive(Debug, Clone)]
pub struct HbmoConfig {
    pub seed: u64,
    /// Runs per (world, planner); the paper: 5.
    pub runs: usize,
    /// Planners, by registry name.
    pub planners: Vec<String>,
    /// Extra `-p key=value` parameters, in order (a later value wins). `key=value` goes to every
    /// chosen planner that declares `key` (a key that none declares is an error);
    /// `planner:key=value` goes to that planner only (e.g. `hbmo:flights=72`).
    pub params: Vec<(String, String)>,
    /// Wall-clock limit per run.
    pub time_limit: Duration,
    /// How the sweeps' worlds are drawn (`fig12` is always the bundled world).
    pub sweep_worlds: SweepWorlds,
}

impl Default for HbmoConfig {
    fn default() -> Self {
        HbmoConfig {
            seed: 0,
            runs: 5,
            planners: ["hbmo", "de", "pso", "orca"].map(String::from).to_vec(),
            params: Vec::new(),
            time_limit: Duration::from_secs(60),
            sweep_worlds: SweepWorlds::Fresh,
        }
    }
}

impl HbmoConfig {
    /// The parameters `planner` gets (see [`HbmoConfig::params`]).
    ///
    /// # Errors
    /// [`Error::Param`] for a `planner:` prefix that names no continuous planner, or a key that
    /// no chosen planner declares.
    pub fn params_for(&self, planner: &str) -> Result<Vec<(String, String)>> {
        let mut out = Vec::new();
        for (k, v) in &self.params {
            if let Some((who, key)) = k.split_once(':') {
                let entry = mrpp_core::registry::find(PLANNERS, who).ok_or_else(|| {
                    Error::Param(format!(
                        "-p {k}={v}: `{who}` is not a continuous planner (hbmo, de, pso, orca)"
                    ))
                })?;
                if !entry.params.iter().any(|p| p.name == key) {
                    return Err(Error::Param(format!(
                        "-p {k}={v}: planner `{who}` has no parameter `{key}`"
                    )));
                }
                if who == planner {
                    out.push((key.to_string(), v.clone()));
                }
                continue;
            }
            let declares = |name: &str| {
                mrpp_core::registry::find(PLANNERS, name)
                    .is_some_and(|e| e.params.iter().any(|p| p.name == k))
            };
            if !self.planners.iter().any(|q| declares(q)) {
                return Err(Error::Param(format!(
                    "-p {k}={v}: none of the planners {} has a parameter `{k}`",
                    self.planners.join(", ")
                )));
            }
            if declares(planner) {
                out.push((k.clone(), v.clone()));
            }
        }
        Ok(out)
    }
}

/// One world of a panel.
#[derive(Debug, Clone)]
pub struct PanelWorld {
    pub panel: &'static str,
    /// The panel's variable (robots, obstacles or speed; 0 for `fig12`).
    pub x: f64,
    pub problem: NavProblem,
}

/// One run's results.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NavRow {
    pub panel: String,
    pub x: f64,
    pub robots: usize,
    pub obstacles: usize,
    pub planner: String,
    pub run: usize,
    pub seed: u64,
    pub status: String,
    pub steps: Option<usize>,
    pub atpt: Option<f64>,
    pub atpd: Option<f64>,
    /// UTD averaged over the run's steps `0..=T` (see the module doc).
    pub autd: Option<f64>,
    /// `Σ_{t=0..=T} UTD(t)`, the area under the run's UTD curve (length × steps; see the module
    /// doc).
    #[serde(default)]
    pub utd_total: Option<f64>,
    pub runtime_ms: f64,
    /// UTD per step of an arrived run (the AUTD curves).
    pub utd: Vec<f64>,
    /// The trajectories of run 0 on `fig12` (for the final-configuration pictures).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub picture: Vec<Vec<[f64; 2]>>,
}

/// The experiment as a sweep: jobs (world, planner, run).
pub struct HbmoNavigation {
    pub cfg: HbmoConfig,
    /// Each planner's parameters ([`HbmoConfig::params_for`]), in `cfg.planners`' order.
    params: Vec<Vec<(String, String)>>,
    worlds: Vec<PanelWorld>,
    jobs: Vec<(usize, usize, usize)>,
}

/// The first `robots` robots and first `obstacles` obstacles of `base` (both at most its own).
pub fn prefix_world(base: &World, robots: usize, obstacles: usize) -> World {
    let mut w = base.clone();
    w.robots.truncate(robots);
    w.obstacles.truncate(obstacles);
    w
}

fn with_speed(mut w: World, speed: f64) -> World {
    for r in &mut w.robots {
        r.speed = speed;
    }
    w
}

impl HbmoNavigation {
    /// The panels' worlds (the bundled one read from `data`, the folder of
    /// `six-robots-four-obstacles.json`) and the jobs.
    pub fn new(cfg: HbmoConfig, data: &Path) -> Result<Self> {
        if cfg.runs == 0 || cfg.runs > 10_000 {
            return Err(Error::Param(format!(
                "runs must be 1 to 10000, got {}",
                cfg.runs
            )));
        }
        let mut params = Vec::with_capacity(cfg.planners.len());
        for (k, p) in cfg.planners.iter().enumerate() {
            if cfg.planners[..k].contains(p) {
                return Err(Error::Param(format!("planner `{p}` is named twice")));
            }
            let entry = mrpp_core::registry::find(PLANNERS, p).ok_or_else(|| {
                Error::Param(format!(
                    "`{p}` is not a continuous planner (hbmo, de, pso, orca)"
                ))
            })?;
            let given = cfg.params_for(p)?;
            entry.instantiate(&given)?;
            params.push(given);
        }
        let fig12: PathBuf = data.join("six-robots-four-obstacles.json");
        let mut worlds = vec![PanelWorld {
            panel: "fig12",
            x: 0.0,
            problem: NavProblem::new(World::load(&fig12)?),
        }];
        let fixed = match cfg.sweep_worlds {
            SweepWorlds::Fresh => None,
            SweepWorlds::Fixed => Some(
                random_world(10, 10, derive_seed(cfg.seed, "world/fixed")).ok_or_else(|| {
                    Error::Internal("no fixed world with 10 robots and 10 obstacles".into())
                })?,
            ),
        };
        let world_of =
            |panel: &'static str, x: f64, robots: usize, obstacles: usize, speed: f64| {
                let w = match &fixed {
                    Some(base) => prefix_world(base, robots, obstacles),
                    None => {
                        let seed = derive_seed(cfg.seed, &format!("world/{panel}/{x}"));
                        random_world(robots, obstacles, seed).ok_or_else(|| {
                            Error::Internal(format!(
                                "no {panel} world with {robots} robots and {obstacles} obstacles"
                            ))
                        })?
                    }
                };
                Ok::<_, Error>(PanelWorld {
                    panel,
                    x,
                    problem: NavProblem::new(with_speed(w, speed)),
                })
            };
        for n in [2, 4, 6, 8, 10] {
            worlds.push(world_of("robots", n as f64, n, 4, 16.0)?);
        }
        for m in [2, 4, 6, 8, 10] {
            worlds.push(world_of("obstacles", m as f64, 6, m, 16.0)?);
        }
        for v in [4.0, 8.0, 12.0, 16.0, 20.0] {
            worlds.push(world_of("velocity", v, 6, 5, v)?);
        }
        let (np, nr) = (cfg.planners.len(), cfg.runs);
        let jobs = (0..worlds.len())
            .flat_map(|w| (0..np).flat_map(move |p| (0..nr).map(move |r| (w, p, r))))
            .collect();
        Ok(HbmoNavigation {
            cfg,
            params,
            worlds,
            jobs,
        })
    }

    fn label(&self, w: usize) -> String {
        let pw = &self.worlds[w];
        format!("{}/{}", pw.panel, pw.x)
    }
}

impl Sweep for HbmoNavigation {
    type Job = (usize, usize, usize);
    type Row = NavRow;

    fn name(&self) -> &str {
        "hbmo"
    }
    fn jobs(&self) -> &[(usize, usize, usize)] {
        &self.jobs
    }
    fn key(&self, &(w, p, r): &(usize, usize, usize)) -> String {
        format!("{}/{}/{r}", self.label(w), self.cfg.planners[p])
    }
    fn run(&self, job: &(usize, usize, usize)) -> Result<NavRow> {
        let (w, p, r) = *job;
        let pw = &self.worlds[w];
        let name = &self.cfg.planners[p];
        let entry = mrpp_core::registry::find(PLANNERS, name).expect("checked in new");
        let planner = entry.instantiate(&self.params[p])?;
        let seed = derive_seed(self.cfg.seed, &self.key(job));
        let started = std::time::Instant::now();
        let out = solve(
            planner.as_ref(),
            &pw.problem,
            &Ctx::new(seed, Deadline::after(self.cfg.time_limit)),
        );
        let runtime_ms = started.elapsed().as_secs_f64() * 1e3;
        let world = pw.problem.world();
        let mut row = NavRow {
            panel: pw.panel.into(),
            x: pw.x,
            robots: world.robots.len(),
            obstacles: world.obstacles.len(),
            planner: name.clone(),
            run: r,
            seed,
            status: String::new(),
            steps: None,
            atpt: None,
            atpd: None,
            autd: None,
            utd_total: None,
            runtime_ms,
            utd: Vec::new(),
            picture: Vec::new(),
        };
        match out {
            Ok(s) => {
                row.status = "arrived".into();
                row.steps = Some(s.metrics.steps);
                row.atpt = Some(s.metrics.total_path);
                row.atpd = Some(s.metrics.total_deviation);
                row.autd = Some(s.metrics.mean_utd);
                row.utd = pw.problem.utd_series(&s.plan);
                row.utd_total = Some(row.utd.iter().sum());
                if pw.panel == "fig12" && r == 0 {
                    row.picture = s.plan.positions;
                }
            }
            Err(Unsolved::Invalid(why)) => return Err(Error::Internal(why)),
            Err(why @ (Unsolved::TimeLimit | Unsolved::MemoryLimit | Unsolved::Interrupted)) => {
                row.status = why.status().into();
            }
            Err(Unsolved::GaveUp(why)) => {
                row.status = if why.starts_with("deadlock") {
                    "deadlock"
                } else {
                    "step_limit"
                }
                .into()
            }
        }
        Ok(row)
    }
    fn records(&self, r: &NavRow) -> Vec<RunRecord> {
        vec![RunRecord {
            job: 0,
            key: String::new(),
            family: mrpp_continuous::FAMILY.into(),
            instance: format!("{}/{}", r.panel, r.x),
            planner: r.planner.clone(),
            params: self
                .cfg
                .planners
                .iter()
                .position(|q| *q == r.planner)
                .map(|k| self.params[k].as_slice())
                .unwrap_or_default()
                .iter()
                .map(|(k, v)| format!("{k}={v}"))
                .collect::<Vec<_>>()
                .join(" "),
            run: r.run,
            seed: r.seed,
            status: if r.status == "arrived" {
                "solved".into()
            } else {
                r.status.clone()
            },
            sum_of_costs: None,
            makespan: r.steps.map(|s| s as u64),
            sum_of_moves: None,
            runtime_ms: r.runtime_ms,
            note: String::new(),
            ..Default::default()
        }]
    }
    fn pages(&self, rows: &[&NavRow], m: &Manifest) -> Result<Vec<(String, String)>> {
        let mut files = vec![
            ("results.csv".to_string(), results_csv(rows)?),
            ("hbmo.md".to_string(), page(self, rows, m)),
            ("fig5-6-autd.svg".to_string(), autd_figure(rows)?),
            (
                "fig7-11-metrics.svg".to_string(),
                metrics_figure(&self.cfg.planners, rows)?,
            ),
        ];
        let fig12 = &self.worlds[0].problem;
        for r in rows.iter().filter(|r| !r.picture.is_empty()) {
            let plan = Trajectories {
                positions: r.picture.clone(),
            };
            files.push((
                format!("fig12-{}.svg", r.planner),
                render_svg(fig12.world(), Some(&plan)),
            ));
        }
        Ok(files)
    }
    fn summary(&self, rows: &[&NavRow]) -> String {
        fig12_table(&self.cfg.planners, rows)
    }
    fn config(&self) -> String {
        format!("{:?}", self.cfg)
    }
}

fn results_csv(rows: &[&NavRow]) -> Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let e = |e: csv::Error| Error::Internal(e.to_string());
    w.write_record([
        "panel",
        "x",
        "robots",
        "obstacles",
        "planner",
        "run",
        "seed",
        "status",
        "steps",
        "atpt",
        "atpd",
        "autd",
        "utd_total",
        "runtime_ms",
    ])
    .map_err(e)?;
    let opt = |v: Option<f64>| v.map(|x| format!("{x:.4}")).unwrap_or_default();
    for r in rows {
        w.write_record([
            r.panel.clone(),
            r.x.to_string(),
            r.robots.to_string(),
            r.obstacles.to_string(),
            r.planner.clone(),
            r.run.to_string(),
            r.seed.to_string(),
            r.status.clone(),
            r.steps.map(|s| s.to_string()).unwrap_or_default(),
            opt(r.atpt),
            opt(r.atpd),
            opt(r.autd),
            opt(r.utd_total),
            format!("{:.1}", r.runtime_ms),
        ])
        .map_err(e)?;
    }
    csv_text(w)
}

/// Mean and standard deviation.
fn mean_sd(v: &[f64]) -> (f64, f64) {
    let n = v.len().max(1) as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0).max(1.0);
    (m, var.sqrt())
}

fn arrived<'a>(rows: &'a [&NavRow], panel: &str, x: f64, planner: &str) -> Vec<&'a NavRow> {
    rows.iter()
        .copied()
        .filter(|r| r.panel == panel && r.x == x && r.planner == planner && r.status == "arrived")
        .collect()
}

/// The two-sided Mann–Whitney p-value of `a` against `b` to three places, or "—" when either has
/// no arrived run (there is nothing to compare).
fn p_value(a: &[f64], b: &[f64]) -> String {
    if a.is_empty() || b.is_empty() {
        "—".to_string()
    } else {
        format!("{:.3}", mann_whitney(a, b).1)
    }
}

/// Fig. 12: per method on the bundled world, with HBMO-vs-method p-values.
fn fig12_table(planners: &[String], rows: &[&NavRow]) -> String {
    let mut s = String::from(
        "| method | runs arrived | steps (mean ± sd) | paper steps | ATPT | ATPD | AUTD (per-step mean) | UTD total (per run) | p (steps, HBMO vs) | p (ATPT, HBMO vs) |\n|---|---|---|---|---|---|---|---|---|---|\n",
    );
    let runs = |p: &str| {
        rows.iter()
            .filter(|r| r.panel == "fig12" && r.planner == p)
            .count()
    };
    let get = |p: &str, f: &dyn Fn(&NavRow) -> Option<f64>| -> Vec<f64> {
        arrived(rows, "fig12", 0.0, p)
            .iter()
            .filter_map(|r| f(r))
            .collect()
    };
    let steps = |r: &NavRow| r.steps.map(|s| s as f64);
    for p in planners {
        let st = get(p, &steps);
        let (sm, ssd) = mean_sd(&st);
        let fmt = |v: Vec<f64>| {
            if v.is_empty() {
                "—".to_string()
            } else {
                format!("{:.1}", mean_sd(&v).0)
            }
        };
        let steps_text = if st.is_empty() {
            "—".to_string()
        } else {
            format!("{sm:.1} ± {ssd:.1}")
        };
        let paper = PAPER_STEPS
            .iter()
            .find(|(n, _)| n == p)
            .map_or("—".to_string(), |(_, v)| format!("{v}"));
        let pv = |f: &dyn Fn(&NavRow) -> Option<f64>| {
            if p == "hbmo" || !planners.iter().any(|q| q == "hbmo") {
                "—".to_string()
            } else {
                p_value(&get("hbmo", f), &get(p, f))
            }
        };
        s.push_str(&format!(
            "| {p} | {}/{} | {steps_text} | {paper} | {} | {} | {} | {} | {} | {} |\n",
            st.len(),
            runs(p),
            fmt(get(p, &|r| r.atpt)),
            fmt(get(p, &|r| r.atpd)),
            fmt(get(p, &|r| r.autd)),
            fmt(get(p, &|r| r.utd_total)),
            pv(&steps),
            pv(&|r| r.atpt),
        ));
    }
    s
}

/// A table of one panel: per x value and method, arrived runs and mean metrics.
fn panel_table(planners: &[String], rows: &[&NavRow], panel: &str, x_name: &str) -> String {
    let mut xs: Vec<f64> = rows
        .iter()
        .filter(|r| r.panel == panel)
        .map(|r| r.x)
        .collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    let mut s = format!(
        "| {x_name} | method | arrived | steps | ATPT | ATPD | AUTD (per-step mean) | UTD total (per run) | p (steps, HBMO vs) | p (ATPT, HBMO vs) |\n|---|---|---|---|---|---|---|---|---|---|\n"
    );
    for x in xs {
        for p in planners {
            let a = arrived(rows, panel, x, p);
            let all = rows
                .iter()
                .filter(|r| r.panel == panel && r.x == x && &r.planner == p)
                .count();
            let m = |f: &dyn Fn(&NavRow) -> Option<f64>| {
                let v: Vec<f64> = a.iter().filter_map(|r| f(r)).collect();
                if v.is_empty() {
                    "—".to_string()
                } else {
                    format!("{:.1}", mean_sd(&v).0)
                }
            };
            let values = |q: &str, f: &dyn Fn(&NavRow) -> Option<f64>| -> Vec<f64> {
                arrived(rows, panel, x, q)
                    .iter()
                    .filter_map(|r| f(r))
                    .collect()
            };
            let pv = |f: &dyn Fn(&NavRow) -> Option<f64>| {
                if p == "hbmo" || !planners.iter().any(|q| q == "hbmo") {
                    "—".to_string()
                } else {
                    p_value(&values("hbmo", f), &values(p, f))
                }
            };
            let steps = |r: &NavRow| r.steps.map(|s| s as f64);
            s.push_str(&format!(
                "| {x} | {p} | {}/{all} | {} | {} | {} | {} | {} | {} | {} |\n",
                a.len(),
                m(&steps),
                m(&|r| r.atpt),
                m(&|r| r.atpd),
                m(&|r| r.autd),
                m(&|r| r.utd_total),
                pv(&steps),
                pv(&|r| r.atpt)
            ));
        }
    }
    s
}

fn page(t: &HbmoNavigation, rows: &[&NavRow], m: &Manifest) -> String {
    let p = &t.cfg.planners;
    format!(
        "# HBMO navigation paper, §5 / Figs. 5–12: HBMO, DE, PSO (and ORCA)\n\n`mrpp {}` — mrpp {}, {} runs per world and method, wall time {:.1} s, {} threads, sweep worlds `{}`. Means over arrived runs; a run that did not arrive (deadlock, step limit) is counted in `arrived` and left out of the means. ATPT = total path traversed, ATPD = total deviation from the ideal paths; with UTD(t) = Σ_i ‖G_i − C_i(t)‖ (§5.2), AUTD (per-step mean) = UTD averaged over a run's steps 0..=T and UTD total (per run) = Σ_t UTD(t) over the run (the tables average both over runs; the paper's AUTD is the curve of UTD(t) averaged over runs, fig5-6-autd.svg). p = two-sided Mann–Whitney U (normal approximation).\n\n## Fig. 12: 6 robots, 4 obstacles (the bundled world)\n\n{}\nPictures: fig12-<method>.svg (run 0).\n\n## Figs. 6, 9–11: robot count (4 obstacles, speed 16)\n\n{}\n## Fig. 7b: obstacle count (6 robots, speed 16)\n\n{}\n## Fig. 5: speed (6 robots, 5 obstacles)\n\n{}\nAUTD per step: fig5-6-autd.svg; ATPT/ATPD/steps against robots and obstacles: fig7-11-metrics.svg.\n",
        m.sweep_command().join(" "),
        m.mrpp_version,
        t.cfg.runs,
        m.wall_seconds,
        m.threads,
        t.cfg.sweep_worlds.name(),
        fig12_table(p, rows),
        panel_table(p, rows, "robots", "robots"),
        panel_table(p, rows, "obstacles", "obstacles"),
        panel_table(p, rows, "velocity", "speed"),
    )
}

/// The mean UTD curve over the arrived runs of one (panel, x, planner), a run that has arrived
/// holding its last value.
fn mean_curve(rows: &[&NavRow], panel: &str, x: f64, planner: &str) -> Vec<(f64, f64)> {
    let a = arrived(rows, panel, x, planner);
    let len = a.iter().map(|r| r.utd.len()).max().unwrap_or(0);
    (0..len)
        .map(|t| {
            let v: f64 = a
                .iter()
                .map(|r| r.utd.get(t).or(r.utd.last()).copied().unwrap_or(0.0))
                .sum();
            (t as f64, v / a.len().max(1) as f64)
        })
        .collect()
}

/// Figs. 5 and 6: HBMO's AUTD per step with speed and with robot count as the variable.
fn autd_figure(rows: &[&NavRow]) -> Result<String> {
    let curves = |panel: &str, unit: &str, xs: &[f64]| Panel {
        title: format!("AUTD vs step, {unit} as variable (HBMO)"),
        series: xs
            .iter()
            .map(|&x| Series {
                name: format!("{unit} {x}"),
                points: mean_curve(rows, panel, x, "hbmo"),
                ..Series::default()
            })
            .collect(),
    };
    let panels = [
        curves("velocity", "speed", &[4.0, 8.0, 12.0, 16.0, 20.0]),
        curves("robots", "robots", &[2.0, 4.0, 6.0, 8.0, 10.0]),
    ];
    line_panels("HBMO paper Figs. 5-6", "step", "AUTD", &panels).map_err(Error::Internal)
}

/// Figs. 7b and 9–11: ATPD vs obstacles, ATPT and ATPD vs robots, per method.
fn metrics_figure(planners: &[String], rows: &[&NavRow]) -> Result<String> {
    let series = |panel: &str, f: &dyn Fn(&NavRow) -> Option<f64>| -> Vec<Series> {
        planners
            .iter()
            .map(|p| {
                let mut xs: Vec<f64> = rows
                    .iter()
                    .filter(|r| r.panel == panel)
                    .map(|r| r.x)
                    .collect();
                xs.sort_by(f64::total_cmp);
                xs.dedup();
                let points = xs
                    .iter()
                    .map(|&x| {
                        (
                            x,
                            mean_sd(
                                &arrived(rows, panel, x, p)
                                    .iter()
                                    .filter_map(|r| f(r))
                                    .collect::<Vec<_>>(),
                            )
                            .0,
                        )
                    })
                    .collect();
                Series {
                    name: p.clone(),
                    points,
                    ..Series::default()
                }
            })
            .collect()
    };
    let panels = [
        Panel {
            title: "ATPT vs robots (Fig. 9a)".into(),
            series: series("robots", &|r| r.atpt),
        },
        Panel {
            title: "ATPD vs robots (Fig. 10)".into(),
            series: series("robots", &|r| r.atpd),
        },
        Panel {
            title: "steps vs robots".into(),
            series: series("robots", &|r| r.steps.map(|s| s as f64)),
        },
        Panel {
            title: "ATPD vs obstacles (Fig. 7b)".into(),
            series: series("obstacles", &|r| r.atpd),
        },
    ];
    line_panels_with(
        "HBMO paper Figs. 7, 9-11",
        &[
            ("robots", "ATPT (total path traversed)"),
            ("robots", "ATPD (deviation from the ideal paths)"),
            ("robots", "steps"),
            ("obstacles", "ATPD (deviation from the ideal paths)"),
        ],
        &panels,
    )
    .map_err(Error::Internal)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn data() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/continuous")
    }

    fn cfg(params: &[(&str, &str)]) -> HbmoConfig {
        HbmoConfig {
            params: params
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect(),
            ..HbmoConfig::default()
        }
    }

    #[test]
    fn params_go_to_the_planners_that_declare_them() {
        let c = cfg(&[
            ("guide", "goal"),
            ("preset", "paper"),
            ("hbmo:flights", "72"),
            ("de:population", "30"),
        ]);
        let kv = |v: &[(&str, &str)]| -> Vec<(String, String)> {
            v.iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect()
        };
        assert_eq!(
            c.params_for("hbmo").unwrap(),
            kv(&[("guide", "goal"), ("preset", "paper"), ("flights", "72")])
        );
        assert_eq!(
            c.params_for("de").unwrap(),
            kv(&[("guide", "goal"), ("preset", "paper"), ("population", "30")])
        );
        // ORCA declares `guide` but no preset.
        assert_eq!(c.params_for("orca").unwrap(), kv(&[("guide", "goal")]));
        assert!(HbmoNavigation::new(c, &data()).is_ok());
        for bad in [
            ("nope", "1"),
            ("hbmo:nope", "1"),
            ("astar:flights", "1"),
            ("brood_drones", "false"),
        ] {
            let mut c = cfg(&[bad]);
            if bad.0 == "brood_drones" {
                // Declared by hbmo only: refused when hbmo is not among the planners.
                c.planners = vec!["de".into(), "orca".into()];
            }
            let e = HbmoNavigation::new(c, &data()).err().expect("refused");
            assert!(e.to_string().contains(bad.0), "{e}");
        }
    }

    #[test]
    fn fixed_sweep_worlds_keep_the_old_obstacles_and_add_new_ones() {
        let worlds = |mode, seed| {
            let c = HbmoConfig {
                sweep_worlds: mode,
                seed,
                ..HbmoConfig::default()
            };
            HbmoNavigation::new(c, &data()).unwrap().worlds
        };
        let of = |ws: &[PanelWorld], panel: &str| -> Vec<World> {
            ws.iter()
                .filter(|w| w.panel == panel)
                .map(|w| w.problem.world().clone())
                .collect()
        };
        let fixed = worlds(SweepWorlds::Fixed, 4);
        let obstacles = of(&fixed, "obstacles");
        assert_eq!(obstacles.len(), 5);
        for pair in obstacles.windows(2) {
            let (a, b) = (&pair[0], &pair[1]);
            assert_eq!(b.obstacles.len(), a.obstacles.len() + 2);
            assert_eq!(a.obstacles[..], b.obstacles[..a.obstacles.len()]);
            assert_eq!(a.robots, b.robots);
        }
        // Robots are added the same way, and every sweep shares the one world's obstacles.
        let robots = of(&fixed, "robots");
        for pair in robots.windows(2) {
            assert_eq!(pair[0].robots[..], pair[1].robots[..pair[0].robots.len()]);
            assert_eq!(pair[0].obstacles, pair[1].obstacles);
        }
        assert_eq!(robots[0].obstacles[..], obstacles[1].obstacles[..]);
        // Deterministic from the seed; another seed, another world.
        assert_eq!(of(&worlds(SweepWorlds::Fixed, 4), "obstacles"), obstacles);
        assert_ne!(of(&worlds(SweepWorlds::Fixed, 5), "obstacles"), obstacles);
        // The fresh mode draws unrelated worlds: the obstacles of 2 are not those of 4's first 2.
        let fresh = of(&worlds(SweepWorlds::Fresh, 4), "obstacles");
        assert_ne!(fresh[0].obstacles[..], fresh[1].obstacles[..2]);
    }
}
