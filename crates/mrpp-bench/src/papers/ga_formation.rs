//! The GA formation paper's experiment (§3, Fig. 4) as a sweep: configurations (map, Q_ini,
//! Q_goal, R) over the three public CTU maps and the four seeded stand-ins, each solved by the
//! sequential planner, the GA and the exact planner; the share of configurations where sequential
//! and GA reach the optimum (the paper: 92% and 97% of about 2000), the mean excess over it, the
//! generation at which the GA found its best, time per GA generation and roadmap build time.
//!
//! Choices where the paper is silent: Q_ini/Q_goal pairs are drawn uniformly in free space with
//! clearance ≥ 2 radius and at least half the map's diagonal apart ([`random_pair`]), from a seed
//! derived from the user's seed and the pair's key (`<map>/<pair>`), the same pair for every R;
//! radius 0.3; the default cost model (lanes, κ = 0.5); the GA with the paper's parameters and a
//! seed derived from the job's key. A configuration whose optimum cannot be proven within the
//! exact planner's time limit is reported and left out of the percentages.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::harness::{Manifest, RunRecord, Sweep};
use crate::report::{Panel, Series, csv_text, line_panels_with};
use mrpp_core::Solved;
use mrpp_core::error::{Error, Result};
use mrpp_core::mapf::plan_file::RunInfo;
use mrpp_core::seeds::derive_seed;
use mrpp_core::{Ctx, Deadline, Planner, Unsolved, accept, solve};
use mrpp_formation::exact::Exact;
use mrpp_formation::ga::Ga;
use mrpp_formation::planners::Sequential;
use mrpp_formation::polymap::{Point, PolygonMap};
use mrpp_formation::world::{Formation, FormationFile, formation_envelope, random_pair};
use mrpp_formation::{CostModel, FormationPlan, FormationProblem};

/// The paper's shares of optimal solutions: sequential, GA.
pub const PAPER_OPTIMAL: (f64, f64) = (92.0, 97.0);

/// The maps, in order: the three public ones, then the stand-ins.
pub const MAPS: [&str; 7] = [
    "gaps",
    "potholes",
    "var_density2",
    "gen-dense",
    "gen-staggered-brick-wall",
    "gen-var-density",
    "gen-var-density3",
];

/// What to run.
#[derive(Debug, Clone)]
pub struct FormationConfig {
    pub seed: u64,
    /// Q_ini/Q_goal pairs per map.
    pub pairs: usize,
    /// Formation sizes.
    pub robots: Vec<usize>,
    pub radius: f64,
    pub cost: CostModel,
    pub ga: Ga,
    /// Wall-clock limit of the exact planner per configuration.
    pub exact_limit: Duration,
    /// Also write every plan as `plans/<map>-<pair>-r<R>-<planner>.json` (the plan envelope,
    /// roadmap included, so `tools/check/formation.py` can judge it alone).
    pub save_plans: bool,
}

impl Default for FormationConfig {
    fn default() -> Self {
        FormationConfig {
            seed: 0,
            pairs: 10,
            robots: vec![1, 2, 3],
            radius: 0.3,
            cost: CostModel::default(),
            ga: Ga::default(),
            exact_limit: Duration::from_secs(30),
            save_plans: false,
        }
    }
}

/// One configuration's results.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FormationRow {
    pub map: String,
    pub pair: usize,
    pub robots: usize,
    pub start: Point,
    pub goal: Point,
    pub ga_seed: u64,
    pub roadmap_ms: f64,
    pub sequential: f64,
    pub ga: f64,
    /// The proven optimum, `None` when the exact planner did not finish.
    pub optimum: Option<f64>,
    pub ga_generation_of_best: usize,
    pub ga_ms_per_generation: f64,
    pub exact_ms: f64,
    /// The GA's plan (for the Fig. 5-style picture).
    pub ga_plan: Vec<Vec<u32>>,
    /// With `save_plans`: (planner, plan envelope JSON) of every plan.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub plan_files: Vec<(String, String)>,
}

/// The experiment as a sweep: jobs (map, pair, R).
pub struct GaFormation {
    pub cfg: FormationConfig,
    maps: Vec<(String, PolygonMap, PathBuf)>,
    pairs: Vec<Vec<(Point, Point)>>,
    jobs: Vec<(usize, usize, usize)>,
}

impl GaFormation {
    /// Loads the seven maps from `dir` (laid out like the bundled `data/polygon-maps/`) and draws
    /// the start/goal pairs.
    pub fn new(cfg: FormationConfig, dir: &Path) -> Result<Self> {
        if cfg.robots.is_empty() || cfg.robots.iter().any(|&r| r == 0 || r > 64) {
            return Err(Error::Param(format!(
                "robot counts must be 1 to 64, got {:?}",
                cfg.robots
            )));
        }
        let mut maps = Vec::new();
        let mut pairs = Vec::new();
        for name in MAPS {
            let path = dir.join(format!("{name}.txt"));
            let map = PolygonMap::load(&path)?;
            let mut list = Vec::new();
            for k in 0..cfg.pairs {
                let mut rng =
                    ChaCha8Rng::seed_from_u64(derive_seed(cfg.seed, &format!("{name}/{k}")));
                let pair = random_pair(&map, cfg.radius, &mut rng)
                    .ok_or_else(|| Error::invalid(&path, "no free start/goal pair found"))?;
                list.push(pair);
            }
            pairs.push(list);
            maps.push((name.to_string(), map, path));
        }
        let (np, nr) = (cfg.pairs, cfg.robots.len());
        let jobs = (0..maps.len())
            .flat_map(|m| (0..np).flat_map(move |k| (0..nr).map(move |r| (m, k, r))))
            .collect();
        Ok(GaFormation {
            cfg,
            maps,
            pairs,
            jobs,
        })
    }

    fn formation(&self, m: usize, k: usize, robots: usize) -> Result<Formation> {
        let (_, map, path) = &self.maps[m];
        let (start, goal) = self.pairs[m][k];
        let file = FormationFile {
            map: path.clone(),
            robots,
            start,
            goal,
            radius: self.cfg.radius,
            cost: self.cfg.cost,
        };
        Formation::on(file, map.clone(), path)
    }
}

/// A planner's validated plan (none when it gave up or ran out of time), with the run's wall
/// time; an invalid plan is a bug.
fn run_one(
    planner: &dyn Planner<FormationProblem>,
    f: &Formation,
    ctx: &Ctx,
) -> Result<(Option<Solved<FormationProblem>>, f64)> {
    let started = Instant::now();
    let out = solve(planner, &f.problem, ctx);
    let ms = started.elapsed().as_secs_f64() * 1e3;
    match out {
        Ok(s) => Ok((Some(s), ms)),
        Err(Unsolved::Invalid(why)) => Err(Error::Internal(why)),
        Err(_) => Ok((None, ms)),
    }
}

/// The plan envelope of one solved run, as written by `mrpp solve`.
fn plan_file(
    f: &Formation,
    map: &str,
    planner: &str,
    seed: u64,
    s: &Solved<FormationProblem>,
) -> String {
    let info = RunInfo {
        planner: planner.into(),
        seed,
        runtime_ms: s.runtime.as_secs_f64() * 1e3,
        ..RunInfo::default()
    };
    formation_envelope(&format!("{map}.txt"), f, info, &Ok(s.clone())).to_json()
}

impl Sweep for GaFormation {
    type Job = (usize, usize, usize);
    type Row = FormationRow;

    fn name(&self) -> &str {
        "ga-formation"
    }
    fn jobs(&self) -> &[(usize, usize, usize)] {
        &self.jobs
    }
    fn key(&self, &(m, k, r): &(usize, usize, usize)) -> String {
        format!("{}/{k}/r{}", self.maps[m].0, self.cfg.robots[r])
    }
    fn run(&self, job: &(usize, usize, usize)) -> Result<FormationRow> {
        let (m, k, r) = *job;
        let robots = self.cfg.robots[r];
        let f = self.formation(m, k, robots)?;
        let none = Ctx::default();
        let (seq, _) = run_one(&Sequential, &f, &none)?;
        let ga_seed = derive_seed(self.cfg.seed, &self.key(job));
        let started = Instant::now();
        let ga_run = self
            .cfg
            .ga
            .run(&f.problem, &Ctx::new(ga_seed, Deadline::none()));
        let ga_ms = started.elapsed().as_secs_f64() * 1e3;
        let ga_run = ga_run
            .ok_or_else(|| Error::Internal(format!("{}: Q_goal unreachable", self.key(job))))?;
        // The GA's plan passes the validator like every plan (its run is driven directly for its
        // generation count); under `--cost hard` it may find none within the corridors'
        // capacities (an infinite c_max, like a planner that gave up).
        let ga = if ga_run.c_max.is_finite() {
            Some(
                accept(&f.problem, ga_run.plan.clone(), "ga", Duration::ZERO)
                    .map_err(|e| Error::Internal(e.to_string()))?,
            )
        } else {
            None
        };
        let exact = Exact {
            candidate_limit: 500_000,
        };
        let (opt, exact_ms) = run_one(
            &exact,
            &f,
            &Ctx::new(0, Deadline::after(self.cfg.exact_limit)),
        )?;
        let (start, goal) = self.pairs[m][k];
        let map = &self.maps[m].0;
        let mut plan_files = Vec::new();
        if self.cfg.save_plans {
            let runs = [
                ("sequential", 0, seq.as_ref()),
                ("ga", ga_seed, ga.as_ref()),
                ("exact", 0, opt.as_ref()),
            ];
            for (name, seed, s) in runs {
                if let Some(s) = s {
                    plan_files.push((name.to_string(), plan_file(&f, map, name, seed, s)));
                }
            }
        }
        Ok(FormationRow {
            map: self.maps[m].0.clone(),
            pair: k,
            robots,
            start,
            goal,
            ga_seed,
            roadmap_ms: f.build_ms,
            sequential: seq.as_ref().map_or(f64::INFINITY, |s| s.metrics.c_max),
            ga: ga.as_ref().map_or(f64::INFINITY, |g| g.metrics.c_max),
            optimum: opt.as_ref().map(|o| o.metrics.c_max),
            ga_generation_of_best: ga_run.generation_of_best,
            ga_ms_per_generation: ga_ms / ga_run.generations.max(1) as f64,
            exact_ms,
            ga_plan: ga.as_ref().map_or_else(Vec::new, |g| g.plan.paths.clone()),
            plan_files,
        })
    }
    fn records(&self, r: &FormationRow) -> Vec<RunRecord> {
        let rec = |planner: &str, c: Option<f64>, seed: u64| RunRecord {
            job: 0,
            key: String::new(),
            family: mrpp_formation::FAMILY.into(),
            instance: format!("{}/{}/r{}", r.map, r.pair, r.robots),
            planner: planner.into(),
            params: String::new(),
            run: 0,
            seed,
            status: if c.is_some() { "solved" } else { "time_limit" }.into(),
            sum_of_costs: None,
            makespan: None,
            sum_of_moves: None,
            runtime_ms: 0.0,
            note: String::new(),
            ..Default::default()
        };
        vec![
            rec("sequential", Some(r.sequential), 0),
            rec("ga", Some(r.ga), r.ga_seed),
            rec("exact", r.optimum, 0),
        ]
    }
    fn pages(&self, rows: &[&FormationRow], m: &Manifest) -> Result<Vec<(String, String)>> {
        let mut files = vec![
            ("results.csv".to_string(), results_csv(rows)?),
            ("ga-formation.md".to_string(), page(self, rows, m)),
            ("fig4.svg".to_string(), fig4(rows)?),
        ];
        if let Some(svg) = fig5(self, rows)? {
            files.push(("fig5.svg".to_string(), svg));
        }
        for r in rows {
            for (planner, text) in &r.plan_files {
                let name = format!("plans/{}-{}-r{}-{planner}.json", r.map, r.pair, r.robots);
                files.push((name, text.clone()));
            }
        }
        Ok(files)
    }
    fn summary(&self, rows: &[&FormationRow]) -> String {
        summary_table(rows)
    }
    fn config(&self) -> String {
        format!("{:?}", self.cfg)
    }
}

fn results_csv(rows: &[&FormationRow]) -> Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let e = |e: csv::Error| Error::Internal(e.to_string());
    w.write_record([
        "map",
        "pair",
        "robots",
        "start_x",
        "start_y",
        "goal_x",
        "goal_y",
        "sequential",
        "ga",
        "optimum",
        "ga_generation_of_best",
        "ga_ms_per_generation",
        "roadmap_ms",
        "exact_ms",
    ])
    .map_err(e)?;
    for r in rows {
        w.write_record([
            r.map.clone(),
            r.pair.to_string(),
            r.robots.to_string(),
            format!("{:.4}", r.start[0]),
            format!("{:.4}", r.start[1]),
            format!("{:.4}", r.goal[0]),
            format!("{:.4}", r.goal[1]),
            format!("{:.6}", r.sequential),
            format!("{:.6}", r.ga),
            r.optimum.map(|o| format!("{o:.6}")).unwrap_or_default(),
            r.ga_generation_of_best.to_string(),
            format!("{:.3}", r.ga_ms_per_generation),
            format!("{:.3}", r.roadmap_ms),
            format!("{:.3}", r.exact_ms),
        ])
        .map_err(e)?;
    }
    csv_text(w)
}

/// Whether `c` is the optimum `o` (relative 1e-9).
fn optimal(c: f64, o: f64) -> bool {
    (c - o).abs() <= 1e-9 * o.abs().max(1.0)
}

/// The Markdown table: per R and overall, % optimal and mean % above the optimum.
fn summary_table(rows: &[&FormationRow]) -> String {
    let mut s = String::from(
        "| R | configurations | sequential optimal | GA optimal | sequential mean % above | GA mean % above | GA generation of best (mean) | GA ms / generation | roadmap ms |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    let mut groups: Vec<Option<usize>> = rows.iter().map(|r| Some(r.robots)).collect();
    groups.sort();
    groups.dedup();
    groups.push(None);
    for g in groups {
        let mine: Vec<&&FormationRow> = rows
            .iter()
            .filter(|r| g.is_none_or(|k| r.robots == k))
            .collect();
        let proven: Vec<(&&&FormationRow, f64)> = mine
            .iter()
            .filter_map(|r| r.optimum.map(|o| (r, o)))
            .collect();
        let n = proven.len().max(1) as f64;
        let pct = |f: &dyn Fn(&FormationRow) -> f64| {
            100.0 * proven.iter().filter(|(r, o)| optimal(f(r), *o)).count() as f64 / n
        };
        let above = |f: &dyn Fn(&FormationRow) -> f64| {
            proven
                .iter()
                .map(|(r, o)| 100.0 * (f(r) - o) / o.max(1e-12))
                .sum::<f64>()
                / n
        };
        let mean = |f: &dyn Fn(&FormationRow) -> f64| {
            mine.iter().map(|r| f(r)).sum::<f64>() / mine.len().max(1) as f64
        };
        s.push_str(&format!(
            "| {} | {}{} | {:.1}% | {:.1}% | {:.2} | {:.2} | {:.1} | {:.3} | {:.1} |\n",
            g.map_or("all".to_string(), |k| k.to_string()),
            proven.len(),
            if proven.len() < mine.len() {
                format!(" (+{} unproven)", mine.len() - proven.len())
            } else {
                String::new()
            },
            pct(&|r| r.sequential),
            pct(&|r| r.ga),
            above(&|r| r.sequential),
            above(&|r| r.ga),
            mean(&|r| r.ga_generation_of_best as f64),
            mean(&|r| r.ga_ms_per_generation),
            mean(&|r| r.roadmap_ms),
        ));
    }
    s.push_str(&format!(
        "| paper | ≈2000 (R ≤ 3) | {}% | {}% | | | ≈20 (\"optimal within 20 generations on average\") | ≈200 (Python) | |\n",
        PAPER_OPTIMAL.0, PAPER_OPTIMAL.1
    ));
    s
}

fn page(t: &GaFormation, rows: &[&FormationRow], m: &Manifest) -> String {
    format!(
        "# GA formation paper, §3 / Fig. 4: sequential and GA against the optimum\n\n`mrpp {}` — mrpp {}, {} pairs per map on {} maps, R in {:?}, cost model {}, GA initial population {}, wall time {:.1} s, {} threads.\n\n{}\nOptimum = the exact planner's proven optimum (branch and bound); a configuration it could not prove within {:?} is counted as unproven and left out of the percentages. Fig. 4: fig4.svg; a Fig. 5-style picture: fig5.svg.\n",
        m.sweep_command().join(" "),
        m.mrpp_version,
        t.cfg.pairs,
        MAPS.len(),
        t.cfg.robots,
        t.cfg.cost.label(),
        if t.cfg.ga.random_start {
            "random"
        } else {
            "sequential"
        },
        m.wall_seconds,
        m.threads,
        summary_table(rows),
        t.cfg.exact_limit
    )
}

/// Fig. 4: cost per configuration (sorted by optimum), optimum vs sequential and vs GA, and the
/// % difference of each.
fn fig4(rows: &[&FormationRow]) -> Result<String> {
    let mut proven: Vec<(&&FormationRow, f64)> = rows
        .iter()
        .filter_map(|r| r.optimum.map(|o| (r, o)))
        .collect();
    proven.sort_by(|a, b| a.1.total_cmp(&b.1));
    let pts = |f: &dyn Fn(&FormationRow, f64) -> f64| -> Vec<(f64, f64)> {
        proven
            .iter()
            .enumerate()
            .map(|(i, (r, o))| (i as f64, f(r, *o)))
            .collect()
    };
    let series = |name: &str, p: Vec<(f64, f64)>| Series {
        name: name.into(),
        points: p,
        ..Series::default()
    };
    let panels = [
        Panel {
            title: "(a) optimum vs sequential".into(),
            series: vec![
                series("optimum", pts(&|_, o| o)),
                series("sequential", pts(&|r, _| r.sequential)),
            ],
        },
        Panel {
            title: "(b) optimum vs GA".into(),
            series: vec![
                series("optimum", pts(&|_, o| o)),
                series("GA", pts(&|r, _| r.ga)),
            ],
        },
        Panel {
            title: "(c) % above the optimum".into(),
            series: vec![
                series(
                    "sequential",
                    pts(&|r, o| 100.0 * (r.sequential - o) / o.max(1e-12)),
                ),
                series("GA", pts(&|r, o| 100.0 * (r.ga - o) / o.max(1e-12))),
            ],
        },
    ];
    line_panels_with(
        "Fig. 4: cost per configuration (sorted by optimum)",
        &[
            ("configuration", "c_max (cost of the plan)"),
            ("configuration", "c_max (cost of the plan)"),
            ("configuration", "% above the optimum"),
        ],
        &panels,
    )
    .map_err(Error::Internal)
}

/// Fig. 5-style picture: the first configuration where the sequential planner misses the optimum
/// (else the first one), with the GA's plan.
fn fig5(t: &GaFormation, rows: &[&FormationRow]) -> Result<Option<String>> {
    let pick = rows
        .iter()
        .find(|r| r.optimum.is_some_and(|o| !optimal(r.sequential, o)))
        .or_else(|| rows.first());
    let Some(r) = pick else { return Ok(None) };
    let m = t
        .maps
        .iter()
        .position(|x| x.0 == r.map)
        .ok_or_else(|| Error::Internal("map of a row".into()))?;
    let f = t.formation(m, r.pair, r.robots)?;
    // The GA's plan of this row passed the validator when the row was made.
    let plan = FormationPlan {
        paths: r.ga_plan.clone(),
    };
    Ok(Some(mrpp_formation::render::render_svg(
        &f.map,
        &f.problem,
        Some(&plan),
    )))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::harness::{Shard, run_shard};

    #[test]
    fn rows_do_not_depend_on_the_thread_count() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/polygon-maps");
        let cfg = FormationConfig {
            pairs: 1,
            robots: vec![2, 3],
            ..FormationConfig::default()
        };
        let sweep = GaFormation::new(cfg, &dir).unwrap();
        let go = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| {
                    let (rows, _) =
                        run_shard(&sweep, Shard::ALL, Vec::new(), &|_| {}, &|_, _| Ok(())).unwrap();
                    rows.into_iter()
                        .map(|(_, r)| FormationRow {
                            roadmap_ms: 0.0,
                            ga_ms_per_generation: 0.0,
                            exact_ms: 0.0,
                            ..r
                        })
                        .collect::<Vec<_>>()
                })
        };
        let (one, two) = (go(1), go(2));
        assert_eq!(one, two);
        assert_eq!(one.len(), 14);
        assert!(one.iter().all(|r| {
            r.optimum
                .is_some_and(|o| o <= r.ga + 1e-9 && r.ga <= r.sequential + 1e-9)
        }));
    }
}
