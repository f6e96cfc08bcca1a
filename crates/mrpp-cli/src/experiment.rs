//! `mrpp experiment ...`: runs a paper's table, shows progress, writes CSV, Markdown and SVG.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use clap::{Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};

use mrpp_bench::papers::hstar_instances::Scenario2Map;
use mrpp_bench::papers::hstar_table2::{
    LoadedInstance, RunRow, Table2Config, job_count, load_paper_table2, load_table1,
    render_table2_markdown, run_table2, summarize, table2_methods,
};
use mrpp_core::mapf::plan_file::RunInfo;
use mrpp_core::mapf::search::distance::lower_bounds;
use mrpp_grid::io::plan_json::grid_envelope;

use crate::output::{Fail, write_atomic};
use crate::plots::{Panel, Series, line_panels};

#[derive(Clone, Copy, ValueEnum)]
pub enum Sc2Map {
    /// `scenery_4rooms_B.txt`: four open rooms (the paper's description; default).
    Open,
    /// `scenery_4rooms.txt`: each room holds the Scenario-1 obstacles.
    Obstacles,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum Fitness {
    Intended,
    Inverted,
}

#[derive(Subcommand)]
pub enum Experiment {
    /// Table II of the H* paper: Enol2023, WHCA*, NSGA-III and H* on Table I's instances.
    HstarTable2(HstarTable2Args),
    /// Table 3 of the GP paper: a program evolved per tree problem vs Push-Swap-Wait.
    GpTable3(crate::gp_experiment::GpTable3Args),
    /// Table 4 of the GP paper: programs trained on |X| problems, tested on new ones, vs PSW.
    GpTable4(crate::gp_experiment::GpTable4Args),
    /// Table 5 of the GP paper: % solved by GP and PSW with 0.25–1.5 × leaves robots.
    GpTable5(crate::gp_experiment::GpTable5Args),
}

#[derive(clap::Args)]
pub struct HstarTable2Args {
    /// Runs per (instance, method); the paper uses 10.
    #[arg(long, default_value_t = 10)]
    runs: usize,
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Output directory (results.csv, table2.md, fig5.svg, plans/).
    #[arg(long, default_value = "out/hstar-table2")]
    out: PathBuf,
    /// Also write every solved plan as plans/<scenario>-<robots>-<planner>-<run>.json.
    #[arg(long)]
    save_plans: bool,
    /// Directory holding scenario1/ .. scenario3/ and table2-paper.csv.
    #[arg(long, default_value = "data/hstar-paper")]
    data: PathBuf,
    #[arg(long, value_enum, default_value_t = Sc2Map::Open)]
    sc2_map: Sc2Map,
    /// Wall-clock limit of one run, in seconds.
    #[arg(long, default_value_t = 30.0)]
    time_limit: f64,
    /// Only these planners (comma-separated: coevolution, whca, nsga3, hstar).
    #[arg(long, value_delimiter = ',')]
    planners: Option<Vec<String>>,
    /// Enol2023's collision count: intended, or inverted as in the authors' code.
    #[arg(long, value_enum, default_value_t = Fitness::Intended)]
    coevolution_fitness: Fitness,
}

pub fn run(cmd: Experiment) -> Result<u8, Fail> {
    match cmd {
        Experiment::HstarTable2(args) => hstar_table2(&args),
        Experiment::GpTable3(args) => crate::gp_experiment::table3(&args),
        Experiment::GpTable4(args) => crate::gp_experiment::table4(&args),
        Experiment::GpTable5(args) => crate::gp_experiment::table5(&args),
    }
}

fn hstar_table2(args: &HstarTable2Args) -> Result<u8, Fail> {
    let HstarTable2Args {
        runs,
        seed,
        ref out,
        save_plans,
        ref data,
        sc2_map,
        time_limit,
        ref planners,
        coevolution_fitness,
    } = *args;
    if !(1..=1000).contains(&runs) {
        return Err(Fail(format!(
            "--runs must be between 1 and 1000, got {runs}"
        )));
    }
    if !(time_limit.is_finite() && time_limit > 0.0 && time_limit <= 1e6) {
        return Err(Fail(format!(
            "--time-limit must be a positive number of seconds, got {time_limit}"
        )));
    }
    if !data.join("scenario1").is_dir() {
        return Err(Fail(format!(
            "{}: no scenario1/ here; pass --data with the directory of the H* paper's files (the repository's data/hstar-paper)",
            data.display()
        )));
    }
    let mut methods = table2_methods();
    if let Some(keep) = &planners {
        for k in keep {
            if !methods.iter().any(|m| m.planner == k) {
                return Err(Fail(format!(
                    "--planners: unknown planner `{k}` (known: coevolution, whca, nsga3, hstar)"
                )));
            }
        }
        methods.retain(|m| keep.iter().any(|k| k == m.planner));
    }
    if let Fitness::Inverted = coevolution_fitness {
        for m in methods
            .iter_mut()
            .filter(|m| m.planner == mrpp_grid::coevolution::NAME)
        {
            m.params.push(("variant".into(), "inverted".into()));
        }
    }
    let scenario2_map = match sc2_map {
        Sc2Map::Open => Scenario2Map::OpenRooms,
        Sc2Map::Obstacles => Scenario2Map::ObstacleRooms,
    };
    let cfg = Table2Config {
        runs,
        seed,
        scenario2_map,
        methods,
        time_limit: Duration::from_secs_f64(time_limit),
    };
    let paper = load_paper_table2(&data.join("table2-paper.csv"))?;
    let instances = load_table1(data, scenario2_map)?;
    std::fs::create_dir_all(out)
        .map_err(|e| Fail(format!("{}: cannot create: {e}", out.display())))?;

    let jobs = job_count(&instances, &cfg);
    println!(
        "mrpp {} | experiment hstar-table2 | seed {seed} | runs {runs} | {} instances x {} methods = {jobs} jobs | threads {}",
        env!("CARGO_PKG_VERSION"),
        instances.len(),
        cfg.methods.len(),
        rayon_threads()
    );
    let bar = ProgressBar::new(jobs as u64);
    bar.set_style(
        ProgressStyle::with_template(
            "{bar:40} {pos}/{len} runs  {elapsed_precise} (eta {eta})  {msg}",
        )
        .expect("static template"),
    );
    let started = Instant::now();
    let rows = run_table2(&instances, &cfg, &|row: &RunRow| {
        bar.set_message(format!("SC{} {} {}", row.scenario, row.label, row.planner));
        bar.inc(1);
    })?;
    bar.finish_and_clear();
    let wall = started.elapsed().as_secs_f64();

    write_atomic(&out.join("results.csv"), &results_csv(&rows)?)?;
    let command = format!(
        "mrpp experiment hstar-table2 --runs {runs} --seed {seed} --sc2-map {} --time-limit {time_limit} --coevolution-fitness {}{}",
        match sc2_map {
            Sc2Map::Open => "open",
            Sc2Map::Obstacles => "obstacles",
        },
        match coevolution_fitness {
            Fitness::Intended => "intended",
            Fitness::Inverted => "inverted",
        },
        planners
            .as_ref()
            .map(|p| format!(" --planners {}", p.join(",")))
            .unwrap_or_default()
    );
    let md = table2_page(&instances, &rows, &cfg, &paper, &command, wall);
    write_atomic(&out.join("table2.md"), &md)?;
    write_atomic(
        &out.join("fig5.svg"),
        &fig5(&instances, &rows, &cfg, &paper)?,
    )?;
    if save_plans {
        let dir = out.join("plans");
        std::fs::create_dir_all(&dir)
            .map_err(|e| Fail(format!("{}: cannot create: {e}", dir.display())))?;
        for row in rows.iter().filter(|r| r.solved) {
            let li = instances
                .iter()
                .find(|li| li.info.scenario == row.scenario && li.info.robots == row.robots)
                .expect("row of a loaded instance");
            let solved = row.plan.clone().expect("solved rows carry their plan");
            let map_file = li
                .info
                .map
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let info = RunInfo {
                planner: row.planner.clone(),
                seed: row.seed,
                runtime_ms: row.runtime_ms,
                ..RunInfo::default()
            };
            let file = grid_envelope(&li.map, &map_file, &li.problem, info, &Ok(solved));
            let name = format!(
                "{}-{}-{}-{}.json",
                row.scenario, row.robots, row.planner, row.run
            );
            write_atomic(&dir.join(name), &file.to_json())?;
        }
    }
    let solved = rows.iter().filter(|r| r.solved).count();
    println!(
        "{solved}/{} runs solved in {wall:.1} s; wrote {}/results.csv, table2.md, fig5.svg{}",
        rows.len(),
        out.display(),
        if save_plans { ", plans/" } else { "" }
    );
    Ok(0)
}

pub(crate) fn rayon_threads() -> usize {
    std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1)
        .min(
            std::env::var("RAYON_NUM_THREADS")
                .ok()
                .and_then(|v| v.parse().ok())
                .unwrap_or(usize::MAX),
        )
}

fn results_csv(rows: &[RunRow]) -> Result<String, Fail> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "scenario",
        "robots",
        "planner",
        "run",
        "seed",
        "solved",
        "max",
        "sum",
        "runtime_ms",
    ])?;
    for r in rows {
        w.write_record([
            r.scenario.to_string(),
            r.robots.to_string(),
            r.planner.clone(),
            r.run.to_string(),
            r.seed.to_string(),
            r.solved.to_string(),
            r.max.map(|v| v.to_string()).unwrap_or_default(),
            r.sum.map(|v| v.to_string()).unwrap_or_default(),
            format!("{:.3}", r.runtime_ms),
        ])?;
    }
    String::from_utf8(w.into_inner().map_err(|e| Fail(e.to_string()))?)
        .map_err(|e| Fail(e.to_string()))
}

fn table2_page(
    instances: &[LoadedInstance],
    rows: &[RunRow],
    cfg: &Table2Config,
    paper: &[mrpp_bench::papers::hstar_table2::PaperCell],
    command: &str,
    wall: f64,
) -> String {
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
         in conflict); mean runtime of our runs:\n\n",
    );
    s.push_str("| SC | robots | LB Max / Sum | Enol2023 stage 1 |");
    for m in &cfg.methods {
        s.push_str(&format!(" {} ms |", m.column));
    }
    s.push_str("\n|---|---|---|---|");
    for _ in &cfg.methods {
        s.push_str("---|");
    }
    s.push('\n');
    for li in instances {
        let lb = lower_bounds(li.map.graph(), &li.inst.starts, &li.inst.goals)
            .map(|(sum, max)| format!("{max} / {sum}"))
            .unwrap_or_else(|i| format!("agent {i} cannot reach its goal"));
        s.push_str(&format!(
            "| {} | {} | {lb} | {} |",
            li.info.scenario,
            li.info.label,
            stage1(li)
        ));
        for m in &cfg.methods {
            let times: Vec<f64> = rows
                .iter()
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

/// Enol2023's stage 1 alone: the A* routes with private obstacles, as Max / Sum (arrival steps) and
/// how many robot pairs still conflict.
fn stage1(li: &LoadedInstance) -> String {
    use mrpp_grid::coevolution::{Coevolution, astar_with_private_obstacles, route_conflict};
    let g = li.map.graph();
    let Ok(stage) = astar_with_private_obstacles(
        g,
        &li.inst,
        &Coevolution::default(),
        mrpp_core::contract::Deadline::none(),
    ) else {
        return String::new();
    };
    let lengths: Vec<usize> = stage
        .routes
        .iter()
        .zip(&li.inst.goals)
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

fn fig5(
    instances: &[LoadedInstance],
    rows: &[RunRow],
    cfg: &Table2Config,
    paper: &[mrpp_bench::papers::hstar_table2::PaperCell],
) -> Result<String, Fail> {
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
    .map_err(Fail)
}
