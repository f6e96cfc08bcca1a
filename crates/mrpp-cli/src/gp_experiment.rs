//! `mrpp experiment gp-table3|gp-table4|gp-table5`: the GP paper's experiments (see
//! `docs/reproduction/gp-trees.md`). Each writes `results.csv`, a Markdown table beside the
//! paper's numbers and, where the paper has one, its figures as SVG.

use std::fmt::Write as _;
use std::ops::RangeInclusive;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};

use mrpp_bench::papers::gp_trees::{
    Comparison, GpExperimentConfig, PAPER_TABLE3, PAPER_TABLE3_TOTALS, PAPER_TABLE4, PAPER_TABLE5,
    ProblemRow, TestRow, TrainedProgram, mean_by_x, run_table3, run_table4, run_table5, swap_ratio,
};

use crate::output::{Fail, write_atomic};
use crate::plots::{Panel, Series, line_panels};

/// What the three experiments share.
#[derive(Args)]
pub struct GpCommon {
    /// Problems: Table 3 — problems (default 100, paper 1000); Table 4 — test problems per trial
    /// (default 50, paper 100); Table 5 — problems per leaf multiplier (default 40, paper 200).
    #[arg(long)]
    problems: Option<usize>,
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// GP parameters; `--paper-settings` also sets the paper's problem counts (days of CPU time
    /// on 2 cores).
    #[command(flatten)]
    gp: crate::tree_family::GpParamArgs,
    /// Wall-clock bound of one evolution in seconds (ψ* so far is kept; makes results depend on
    /// the machine, so it is off by default).
    #[arg(long)]
    evolve_time_limit: Option<f64>,
    /// Wall-clock bound, in seconds, of one PSW run or one run of a program on a test problem.
    #[arg(long, default_value_t = 60.0)]
    run_time_limit: f64,
    /// Depth budgets of the generated trees, `MIN-MAX` (default 3-4, trees of the paper's scale;
    /// with --paper-settings the paper's 4-10, and 4-9 for Table 4's test problems).
    #[arg(long, value_parser = parse_depths)]
    depths: Option<RangeInclusive<u32>>,
    /// Output directory (default out/gp-tableN).
    #[arg(long)]
    out: Option<PathBuf>,
}

fn parse_depths(s: &str) -> Result<RangeInclusive<u32>, String> {
    let bad = || format!("expected MIN-MAX with 1 <= MIN <= MAX <= 12, got `{s}`");
    let (a, b) = s.split_once('-').ok_or_else(bad)?;
    let (a, b): (u32, u32) = (
        a.trim().parse().map_err(|_| bad())?,
        b.trim().parse().map_err(|_| bad())?,
    );
    if (1..=b).contains(&a) && b <= 12 {
        Ok(a..=b)
    } else {
        Err(bad())
    }
}

#[derive(Args)]
pub struct GpTable3Args {
    #[command(flatten)]
    common: GpCommon,
}

#[derive(Args)]
pub struct GpTable4Args {
    #[command(flatten)]
    common: GpCommon,
    /// Training-set sizes |X|.
    #[arg(long, value_delimiter = ',', default_value = "5,10,20")]
    train_sizes: Vec<usize>,
    /// Trials per |X| (default 2, paper 10).
    #[arg(long)]
    trials: Option<usize>,
}

#[derive(Args)]
pub struct GpTable5Args {
    #[command(flatten)]
    common: GpCommon,
    /// Leaf multipliers l_m: ⌊l_m · #leaves⌋ robots.
    #[arg(long, value_delimiter = ',', default_value = "0.25,0.5,1.0,1.5")]
    multipliers: Vec<f64>,
}

fn positive_seconds(what: &str, s: f64) -> Result<Duration, Fail> {
    if s.is_finite() && s > 0.0 && s <= 1e7 {
        Ok(Duration::from_secs_f64(s))
    } else {
        Err(Fail(format!(
            "--{what} must be a positive number of seconds, got {s}"
        )))
    }
}

impl GpCommon {
    /// The configuration and the problem count (`default` / `paper` when not given).
    fn config(&self, default: usize, paper: usize) -> Result<(GpExperimentConfig, usize), Fail> {
        let base = if self.gp.paper_settings {
            GpExperimentConfig::paper()
        } else {
            GpExperimentConfig::scaled_down()
        };
        let params = self.gp.params_over(base.params.clone(), true)?;
        let problems = self.problems.unwrap_or(if self.gp.paper_settings {
            paper
        } else {
            default
        });
        if !(1..=100_000).contains(&problems) {
            return Err(Fail(format!(
                "--problems must be between 1 and 100000, got {problems}"
            )));
        }
        let cfg = GpExperimentConfig {
            train_depths: self.depths.clone().unwrap_or(base.train_depths.clone()),
            test_depths: self.depths.clone().unwrap_or(base.test_depths.clone()),
            seed: self.seed,
            params,
            run_time_limit: positive_seconds("run-time-limit", self.run_time_limit)?,
            evolve_time_limit: self
                .evolve_time_limit
                .map(|s| positive_seconds("evolve-time-limit", s))
                .transpose()?,
            ..base
        };
        Ok((cfg, problems))
    }

    fn out(&self, name: &str) -> Result<PathBuf, Fail> {
        let out = self
            .out
            .clone()
            .unwrap_or_else(|| PathBuf::from(format!("out/{name}")));
        std::fs::create_dir_all(&out)
            .map_err(|e| Fail(format!("{}: cannot create: {e}", out.display())))?;
        Ok(out)
    }

    /// The command line that reproduces the run (written into the Markdown page).
    fn command(
        &self,
        name: &str,
        cfg: &GpExperimentConfig,
        problems: usize,
        extra: &str,
    ) -> String {
        let p = &cfg.params;
        let mut c = format!(
            "mrpp experiment {name} --seed {} --problems {problems} --population {} --generations {} --runs {}",
            cfg.seed, p.population, p.generations, p.runs
        );
        if self.gp.paper_settings {
            c.push_str(" --paper-settings");
        }
        if let Some(k) = self.gp.evolution_cap {
            let _ = write!(c, " --evolution-cap {k}");
        }
        let g = &self.gp;
        for (flag, v) in [
            ("p-reproduction", g.p_reproduction),
            ("p-crossover", g.p_crossover),
            ("p-mutation", g.p_mutation),
        ] {
            if let Some(v) = v {
                let _ = write!(c, " --{flag} {v}");
            }
        }
        for (flag, v) in [
            ("min-depth", g.min_depth),
            ("max-depth", g.max_depth),
            ("init-depth", g.init_depth),
        ] {
            if let Some(v) = v {
                let _ = write!(c, " --{flag} {v}");
            }
        }
        if let Some(s) = self.evolve_time_limit {
            let _ = write!(c, " --evolve-time-limit {s}");
        }
        if self.depths.is_some() || !self.gp.paper_settings {
            let d = &cfg.train_depths;
            let _ = write!(c, " --depths {}-{}", d.start(), d.end());
        }
        c + extra
    }
}

fn header(name: &str, cfg: &GpExperimentConfig, jobs: usize) {
    let p = &cfg.params;
    println!(
        "mrpp {} | experiment {name} | seed {} | |P| {} x {} generations x {} runs | {jobs} jobs | threads {}",
        env!("CARGO_PKG_VERSION"),
        cfg.seed,
        p.population,
        p.generations,
        p.runs,
        crate::experiment::rayon_threads()
    );
}

/// Progress on stderr: an indicatif bar on a terminal; otherwise (a log file, CI) one plain
/// line per finished job, so long batch runs still show where they are.
struct Progress {
    bar: ProgressBar,
    plain: bool,
    len: usize,
    unit: &'static str,
    done: std::sync::atomic::AtomicUsize,
    started: Instant,
}

impl Progress {
    fn new(len: usize, unit: &'static str) -> Self {
        let bar = ProgressBar::new(len as u64);
        bar.set_style(
            ProgressStyle::with_template(&format!(
                "{{bar:40}} {{pos}}/{{len}} {unit}  {{elapsed_precise}} (eta {{eta}})  {{msg}}"
            ))
            .expect("static template"),
        );
        Progress {
            bar,
            plain: !std::io::IsTerminal::is_terminal(&std::io::stderr()),
            len,
            unit,
            done: std::sync::atomic::AtomicUsize::new(0),
            started: Instant::now(),
        }
    }

    fn tick(&self, msg: String) {
        let k = self.done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        if self.plain {
            eprintln!(
                "[{:.0} s] {k}/{} {}: {msg}",
                self.started.elapsed().as_secs_f64(),
                self.len,
                self.unit
            );
        } else {
            self.bar.set_message(msg);
            self.bar.inc(1);
        }
    }

    fn finish(&self) {
        self.bar.finish();
    }
}

/// Writes every output file (each atomically, after all were computed), prints the Markdown
/// table and what was written.
fn write_all(out: &Path, files: &[(&str, String)], md: &str) -> Result<u8, Fail> {
    for (name, text) in files {
        write_atomic(&out.join(name), text)?;
    }
    print!("{md}");
    let names: Vec<&str> = files.iter().map(|f| f.0).collect();
    println!("wrote {}/{}", out.display(), names.join(", "));
    Ok(0)
}

/// Steps for a progress line: the number, or `-` when not solved.
fn show(v: Option<u64>) -> String {
    v.map_or_else(|| "-".into(), |s| s.to_string())
}

fn opt(v: Option<u64>) -> String {
    v.map(|s| s.to_string()).unwrap_or_default()
}

fn csv_text(w: csv::Writer<Vec<u8>>) -> Result<String, Fail> {
    String::from_utf8(w.into_inner().map_err(|e| Fail(e.to_string()))?)
        .map_err(|e| Fail(e.to_string()))
}

fn problems_csv(rows: &[ProblemRow]) -> Result<String, Fail> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "multiplier",
        "problem",
        "depth",
        "nodes",
        "leaves",
        "robots",
        "lower_bound",
        "psw_steps",
        "psw_swaps",
        "gp_steps",
        "gp_generations",
        "gp_evaluations",
        "gp_seconds",
        "program",
    ])?;
    for r in rows {
        w.write_record([
            r.multiplier.map(|m| m.to_string()).unwrap_or_default(),
            r.index.to_string(),
            r.depth.to_string(),
            r.nodes.to_string(),
            r.leaves.to_string(),
            r.robots.to_string(),
            r.lower_bound.to_string(),
            opt(r.psw_steps),
            r.psw_swaps.to_string(),
            opt(r.gp_steps),
            r.gp_generations.to_string(),
            r.gp_evaluations.to_string(),
            format!("{:.3}", r.gp_seconds),
            r.program.clone().unwrap_or_default(),
        ])?;
    }
    csv_text(w)
}

/// Time steps against x (robots, or the swap ratio): mean ± standard deviation of each method.
fn steps_panel(title: String, gp: Vec<(f64, f64)>, psw: Vec<(f64, f64)>) -> Panel {
    let series = |name: &str, pts: Vec<(f64, f64)>| {
        let m = mean_by_x(pts);
        Series {
            name: name.into(),
            points: m.iter().map(|&(x, y, _)| (x, y)).collect(),
            spread: m.iter().map(|&(_, _, sd)| sd).collect(),
            ..Series::default()
        }
    };
    Panel {
        title,
        series: vec![series("GP", gp), series("PSW", psw)],
    }
}

fn pct(part: usize, whole: usize) -> f64 {
    Comparison::pct(part, whole)
}

pub fn table3(args: &GpTable3Args) -> Result<u8, Fail> {
    let c = &args.common;
    let (cfg, problems) = c.config(100, 1000)?;
    let out = c.out("gp-table3")?;
    let mut files: Vec<(&str, String)> = Vec::new();
    header("gp-table3", &cfg, problems);
    let bar = Progress::new(problems, "problems");
    let started = Instant::now();
    let rows = run_table3(&cfg, problems, &|r: &ProblemRow| {
        bar.tick(format!(
            "problem {}: {} nodes, {} robots, PSW {} / GP {} steps",
            r.index,
            r.nodes,
            r.robots,
            show(r.psw_steps),
            show(r.gp_steps)
        ));
    })?;
    bar.finish();
    let wall = started.elapsed().as_secs_f64();
    files.push(("results.csv", problems_csv(&rows)?));

    let cmp = Comparison::of(rows.iter().map(|r| (r.gp_steps, r.psw_steps)));
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# GP paper, Table 3: GP evolved per problem vs PSW\n\n`{}` — mrpp {}, {problems} problems \
         (#leaves − 1 robots, depth budgets {}–{}, b = 4), wall time {wall:.1} s.\n",
        c.command("gp-table3", &cfg, problems, ""),
        env!("CARGO_PKG_VERSION"),
        cfg.train_depths.start(),
        cfg.train_depths.end()
    );
    md.push_str("| | GP Better | GP = PSW | PSW Better | PSW total steps | GP total steps | GP / PSW |\n|---|---|---|---|---|---|---|\n");
    let _ = writeln!(
        md,
        "| mrpp | {:.1}% | {:.1}% | {:.1}% | {} | {} | {:.1}% |",
        pct(cmp.gp_better, cmp.problems),
        pct(cmp.equal, cmp.problems),
        pct(cmp.psw_better, cmp.problems),
        cmp.psw_total,
        cmp.gp_total,
        100.0 * cmp.gp_total as f64 / cmp.psw_total.max(1) as f64
    );
    let _ = writeln!(
        md,
        "| paper (1000 problems) | {}% | {}% | {}% | {} | {} | {:.1}% |",
        PAPER_TABLE3.0,
        PAPER_TABLE3.1,
        PAPER_TABLE3.2,
        PAPER_TABLE3_TOTALS.0,
        PAPER_TABLE3_TOTALS.1,
        100.0 * PAPER_TABLE3_TOTALS.1 as f64 / PAPER_TABLE3_TOTALS.0 as f64
    );
    let _ = writeln!(
        md,
        "\nSolved: GP {} / {problems}, PSW {} / {problems}; totals over the {} problems both solved. \
         Sum of lower bounds (longest start–goal distance per problem): {}. Figures: fig4.svg \
         (time steps vs robots), fig5.svg (time steps vs PSW swaps per robot).",
        cmp.gp_solved,
        cmp.psw_solved,
        cmp.both,
        rows.iter().map(|r| r.lower_bound).sum::<u64>()
    );
    files.push(("table3.md", md.clone()));
    let solved: Vec<&ProblemRow> = rows
        .iter()
        .filter(|r| r.gp_steps.is_some() && r.psw_steps.is_some())
        .collect();
    let pts = |f: &dyn Fn(&ProblemRow) -> f64, s: &dyn Fn(&ProblemRow) -> Option<u64>| {
        solved
            .iter()
            .map(|r| (f(r), s(r).unwrap_or_default() as f64))
            .collect::<Vec<_>>()
    };
    let by_robots = |r: &ProblemRow| r.robots as f64;
    let by_swaps = |r: &ProblemRow| swap_ratio(r.psw_swaps, r.robots);
    let gp = |r: &ProblemRow| r.gp_steps;
    let psw = |r: &ProblemRow| r.psw_steps;
    let fig4 = line_panels(
        "Fig. 4: GP vs PSW, trained/tested on individual problems",
        "robots",
        "time steps (mean ± sd)",
        &[steps_panel(
            "time steps".into(),
            pts(&by_robots, &gp),
            pts(&by_robots, &psw),
        )],
    )
    .map_err(Fail)?;
    let fig5 = line_panels(
        "Fig. 5: GP vs PSW, trained/tested on individual problems",
        "PSW swaps / robots",
        "time steps (mean ± sd)",
        &[steps_panel(
            "time steps".into(),
            pts(&by_swaps, &gp),
            pts(&by_swaps, &psw),
        )],
    )
    .map_err(Fail)?;
    files.push(("fig4.svg", fig4));
    files.push(("fig5.svg", fig5));
    write_all(&out, &files, &md)
}

pub fn table4(args: &GpTable4Args) -> Result<u8, Fail> {
    let c = &args.common;
    let (cfg, tests) = c.config(50, 100)?;
    let trials = args
        .trials
        .unwrap_or(if c.gp.paper_settings { 10 } else { 2 });
    if !(1..=1000).contains(&trials) {
        return Err(Fail(format!(
            "--trials must be between 1 and 1000, got {trials}"
        )));
    }
    if args.train_sizes.is_empty() || args.train_sizes.iter().any(|&x| !(1..=1000).contains(&x)) {
        return Err(Fail(format!(
            "--train-sizes must be between 1 and 1000, got {:?}",
            args.train_sizes
        )));
    }
    let out = c.out("gp-table4")?;
    let mut files: Vec<(&str, String)> = Vec::new();
    let jobs = args.train_sizes.len() * trials;
    header("gp-table4", &cfg, jobs);
    let bar = Progress::new(jobs, "trainings");
    let started = Instant::now();
    let (programs, rows) = run_table4(
        &cfg,
        &args.train_sizes,
        trials,
        tests,
        &|p: &TrainedProgram| {
            bar.tick(format!(
                "|X| = {} trial {} (solved its training set: {})",
                p.train_size, p.trial, p.solved_training_set
            ));
        },
    )?;
    bar.finish();
    let wall = started.elapsed().as_secs_f64();

    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "train_size",
        "trial",
        "problem",
        "depth",
        "nodes",
        "robots",
        "lower_bound",
        "psw_steps",
        "psw_swaps",
        "gp_steps",
    ])?;
    for r in &rows {
        w.write_record([
            r.train_size.to_string(),
            r.trial.to_string(),
            r.index.to_string(),
            r.depth.to_string(),
            r.nodes.to_string(),
            r.robots.to_string(),
            r.lower_bound.to_string(),
            opt(r.psw_steps),
            r.psw_swaps.to_string(),
            opt(r.gp_steps),
        ])?;
    }
    files.push(("results.csv", csv_text(w)?));
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "train_size",
        "trial",
        "solved_training_set",
        "generations",
        "evaluations",
        "seconds",
        "program",
    ])?;
    for p in &programs {
        w.write_record([
            p.train_size.to_string(),
            p.trial.to_string(),
            p.solved_training_set.to_string(),
            p.generations.to_string(),
            p.evaluations.to_string(),
            format!("{:.3}", p.seconds),
            p.program.clone(),
        ])?;
    }
    files.push(("programs.csv", csv_text(w)?));

    let sizes = args
        .train_sizes
        .iter()
        .map(|x| x.to_string())
        .collect::<Vec<_>>()
        .join(",");
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# GP paper, Table 4: general GP vs PSW\n\n`{}` — mrpp {}, {trials} trials per |X|, {tests} \
         new test problems per trial (depth budgets {}–{}; training {}–{}), wall time {wall:.1} s.\n",
        c.command(
            "gp-table4",
            &cfg,
            tests,
            &format!(" --train-sizes {sizes} --trials {trials}")
        ),
        env!("CARGO_PKG_VERSION"),
        cfg.test_depths.start(),
        cfg.test_depths.end(),
        cfg.train_depths.start(),
        cfg.train_depths.end()
    );
    md.push_str("Percentages are over the test problems GP solved, as in the paper.\n\n| X | # GP Solved | % GP Better | % GP = PSW | % PSW Better | paper: # GP Solved (of 1000) | % GP Better | % GP = PSW | % PSW Better |\n|---|---|---|---|---|---|---|---|---|\n");
    for &x in &args.train_sizes {
        let mine: Vec<&TestRow> = rows.iter().filter(|r| r.train_size == x).collect();
        let solved: Vec<&&TestRow> = mine.iter().filter(|r| r.gp_steps.is_some()).collect();
        let cmp = Comparison::of(solved.iter().map(|r| (r.gp_steps, r.psw_steps)));
        let paper = PAPER_TABLE4
            .iter()
            .find(|p| p.0 == x)
            .map(|p| format!("{} | {} | {} | {}", p.1, p.2, p.3, p.4))
            .unwrap_or_else(|| "| | |".into());
        let _ = writeln!(
            md,
            "| {x} | {} / {} | {:.2} | {:.2} | {:.2} | {paper} |",
            solved.len(),
            mine.len(),
            pct(cmp.gp_better, cmp.problems),
            pct(cmp.equal, cmp.problems),
            pct(cmp.psw_better, cmp.problems),
        );
    }
    let trained = programs.iter().filter(|p| p.solved_training_set).count();
    let _ = writeln!(
        md,
        "\n{trained} of {} evolutions found a program solving their whole training set (the others \
         are tested with their lowest-fitness program); programs in programs.csv. Figures: fig6.svg \
         (time steps vs robots), fig7.svg (time steps vs PSW swaps per robot), over test problems \
         GP solved.",
        programs.len()
    );
    files.push(("table4.md", md.clone()));
    let panels = |x_of: &dyn Fn(&TestRow) -> f64| -> Vec<Panel> {
        args.train_sizes
            .iter()
            .map(|&x| {
                let solved: Vec<&TestRow> = rows
                    .iter()
                    .filter(|r| r.train_size == x && r.gp_steps.is_some() && r.psw_steps.is_some())
                    .collect();
                steps_panel(
                    format!("|X| = {x}"),
                    solved
                        .iter()
                        .map(|r| (x_of(r), r.gp_steps.unwrap_or_default() as f64))
                        .collect(),
                    solved
                        .iter()
                        .map(|r| (x_of(r), r.psw_steps.unwrap_or_default() as f64))
                        .collect(),
                )
            })
            .collect()
    };
    let fig6 = line_panels(
        "Fig. 6: GP vs PSW, trained first, tested on new problems",
        "robots",
        "time steps (mean ± sd)",
        &panels(&|r| r.robots as f64),
    )
    .map_err(Fail)?;
    let fig7 = line_panels(
        "Fig. 7: GP vs PSW, trained first, tested on new problems",
        "PSW swaps / robots",
        "time steps (mean ± sd)",
        &panels(&|r| swap_ratio(r.psw_swaps, r.robots)),
    )
    .map_err(Fail)?;
    files.push(("fig6.svg", fig6));
    files.push(("fig7.svg", fig7));
    write_all(&out, &files, &md)
}

pub fn table5(args: &GpTable5Args) -> Result<u8, Fail> {
    let c = &args.common;
    let (cfg, problems) = c.config(40, 200)?;
    if args.multipliers.is_empty() {
        return Err(Fail("--multipliers needs at least one value".into()));
    }
    let out = c.out("gp-table5")?;
    let mut files: Vec<(&str, String)> = Vec::new();
    let jobs = problems * args.multipliers.len();
    header("gp-table5", &cfg, jobs);
    let bar = Progress::new(jobs, "problems");
    let started = Instant::now();
    let rows = run_table5(&cfg, &args.multipliers, problems, &|r: &ProblemRow| {
        bar.tick(format!(
            "x{} problem {}: {} robots, PSW {} / GP {} steps",
            r.multiplier.unwrap_or(0.0),
            r.index,
            r.robots,
            show(r.psw_steps),
            show(r.gp_steps)
        ));
    })?;
    bar.finish();
    let wall = started.elapsed().as_secs_f64();
    files.push(("results.csv", problems_csv(&rows)?));
    let ms = args
        .multipliers
        .iter()
        .map(|m| m.to_string())
        .collect::<Vec<_>>()
        .join(",");
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# GP paper, Table 5: GP vs PSW where PSW is not complete\n\n`{}` — mrpp {}, {problems} \
         problems per multiplier (⌊l_m · #leaves⌋ robots, at most |N| − 2), wall time {wall:.1} s.\n",
        c.command("gp-table5", &cfg, problems, &format!(" --multipliers {ms}")),
        env!("CARGO_PKG_VERSION")
    );
    md.push_str("| Leaf Multiplier | % GP Solved | % PSW Solved | paper: % GP Solved | % PSW Solved |\n|---|---|---|---|---|\n");
    let mut gp_pts = Vec::new();
    let mut psw_pts = Vec::new();
    for &m in &args.multipliers {
        let cmp = Comparison::of(
            rows.iter()
                .filter(|r| r.multiplier == Some(m))
                .map(|r| (r.gp_steps, r.psw_steps)),
        );
        let (g, p) = (
            pct(cmp.gp_solved, cmp.problems),
            pct(cmp.psw_solved, cmp.problems),
        );
        gp_pts.push((m, g));
        psw_pts.push((m, p));
        let paper = PAPER_TABLE5
            .iter()
            .find(|t| t.0 == m)
            .map(|t| format!("{} | {}", t.1, t.2))
            .unwrap_or_else(|| " | ".into());
        let _ = writeln!(md, "| {m} | {g:.1} | {p:.1} | {paper} |");
    }
    files.push(("table5.md", md.clone()));
    let paper_series = |name: &str, f: fn(&(f64, f64, f64)) -> f64| Series {
        name: format!("{name} (paper)"),
        points: PAPER_TABLE5.iter().map(|t| (t.0, f(t))).collect(),
        paper: true,
        ..Series::default()
    };
    let svg = line_panels(
        "Table 5: problems solved; lines: mrpp, circles: paper",
        "robots / leaves",
        "% solved",
        &[Panel {
            title: "% solved".into(),
            series: vec![
                Series {
                    name: "GP".into(),
                    points: gp_pts,
                    ..Series::default()
                },
                Series {
                    name: "PSW".into(),
                    points: psw_pts,
                    ..Series::default()
                },
                paper_series("GP", |t| t.1),
                paper_series("PSW", |t| t.2),
            ],
        }],
    )
    .map_err(Fail)?;
    files.push(("table5.svg", svg));
    write_all(&out, &files, &md)
}
