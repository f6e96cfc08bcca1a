//! The GP paper's pages (Tables 3–5): `results.csv`, the Markdown table beside the paper's
//! numbers, and Fig. 4–7 / the Table 5 chart as SVG, all made from the sweeps' rows.

use std::fmt::Write as _;

use crate::harness::Manifest;
use crate::papers::gp_trees::{
    Comparison, Distribution, GpExperimentConfig, GpTable4, PAPER_TABLE3, PAPER_TABLE3_TOTALS,
    PAPER_TABLE4, PAPER_TABLE5, ProblemRow, Table4Row, TestRow, mean_by_x, swap_ratio,
};
use crate::report::{Panel, Series, csv_text, line_panels};
use mrpp_core::error::{Error, Result};

fn opt(v: Option<u64>) -> String {
    v.map(|s| s.to_string()).unwrap_or_default()
}

fn pct(part: usize, whole: usize) -> f64 {
    Comparison::pct(part, whole)
}

fn csv_err(e: csv::Error) -> Error {
    Error::Internal(e.to_string())
}

/// The line under a page's title: the command, the version, what ran, the wall time.
fn made_by(m: &Manifest, what: &str) -> String {
    format!(
        "`mrpp {}` — mrpp {}, {what}, wall time {:.1} s.\n",
        m.sweep_command().join(" "),
        m.mrpp_version,
        m.wall_seconds
    )
}

/// `results.csv` of Table 3 or Table 5.
fn problems_csv(rows: &[&ProblemRow]) -> Result<String> {
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
    ])
    .map_err(csv_err)?;
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
        ])
        .map_err(csv_err)?;
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

/// The Markdown table of Table 3 (also printed at the end of a run).
pub fn table3_summary(rows: &[&ProblemRow]) -> String {
    let cmp = Comparison::of(rows.iter().map(|r| (r.gp_steps, r.psw_steps)));
    let mut md = String::from(
        "| | GP Better | GP = PSW | PSW Better | PSW total steps | GP total steps | GP / PSW |\n|---|---|---|---|---|---|---|\n",
    );
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
    let (t, totals) = (PAPER_TABLE3, PAPER_TABLE3_TOTALS);
    let _ = writeln!(
        md,
        "| paper (1000 problems) | {}% | {}% | {}% | {} | {} | {:.1}% |",
        t.0,
        t.1,
        t.2,
        totals.0,
        totals.1,
        100.0 * totals.1 as f64 / totals.0 as f64
    );
    let _ = writeln!(
        md,
        "\nSolved: GP {} / {n}, PSW {} / {n}; totals over the {} problems both solved. \
         Sum of lower bounds (longest start–goal distance per problem): {}. Figures: fig4.svg \
         (time steps vs robots), fig5.svg (time steps vs PSW swaps per robot).",
        cmp.gp_solved,
        cmp.psw_solved,
        cmp.both,
        rows.iter().map(|r| r.lower_bound).sum::<u64>(),
        n = rows.len(),
    );
    md
}

/// Fig. 4 / Fig. 5 of the problems both methods solved: time steps against `x_of`.
fn fig45(
    rows: &[&ProblemRow],
    title: &str,
    x_desc: &str,
    x_of: &dyn Fn(&ProblemRow) -> f64,
) -> Result<String> {
    let solved: Vec<&&ProblemRow> = rows
        .iter()
        .filter(|r| r.gp_steps.is_some() && r.psw_steps.is_some())
        .collect();
    let pts = |s: &dyn Fn(&ProblemRow) -> Option<u64>| {
        solved
            .iter()
            .map(|r| (x_of(r), s(r).unwrap_or_default() as f64))
            .collect::<Vec<_>>()
    };
    let panel = steps_panel(
        "time steps".into(),
        pts(&|r| r.gp_steps),
        pts(&|r| r.psw_steps),
    );
    line_panels(title, x_desc, "time steps (mean ± sd)", &[panel]).map_err(Error::Internal)
}

/// Table 3's files: results.csv, table3.md, fig4.svg, fig5.svg.
pub fn table3(
    cfg: &GpExperimentConfig,
    rows: &[&ProblemRow],
    m: &Manifest,
) -> Result<Vec<(String, String)>> {
    let (d0, d1) = (cfg.train_depths.start(), cfg.train_depths.end());
    let what = match cfg.distribution {
        Distribution::Paper => format!(
            "{} problems (the paper's distribution: #leaves − 1 robots, depth budgets {d0}–{d1}, b = 4)",
            rows.len()
        ),
        Distribution::Authors => format!(
            "{} problems (the authors' distribution: node budgets {d0}–{d1}, 1–3 children a node, 2 to #leaves − 1 robots)",
            rows.len()
        ),
    };
    let md = format!(
        "# GP paper, Table 3: GP evolved per problem vs PSW\n\n{}\n{}",
        made_by(m, &what),
        table3_summary(rows)
    );
    let title = "GP vs PSW, trained/tested on individual problems";
    Ok(vec![
        ("results.csv".into(), problems_csv(rows)?),
        ("table3.md".into(), md),
        (
            "fig4.svg".into(),
            fig45(rows, &format!("Fig. 4: {title}"), "robots", &|r| {
                r.robots as f64
            })?,
        ),
        (
            "fig5.svg".into(),
            fig45(
                rows,
                &format!("Fig. 5: {title}"),
                "PSW swaps / robots",
                &|r| swap_ratio(r.psw_swaps, r.robots),
            )?,
        ),
    ])
}

/// The Markdown table of Table 5 (also printed at the end of a run).
pub fn table5_summary(multipliers: &[f64], rows: &[&ProblemRow]) -> String {
    let mut md = String::from(
        "| Leaf Multiplier | % GP Solved | % PSW Solved | paper: % GP Solved | % PSW Solved |\n|---|---|---|---|---|\n",
    );
    for (m, g, p) in table5_points(multipliers, rows) {
        let paper = PAPER_TABLE5
            .iter()
            .find(|t| t.0 == m)
            .map(|t| format!("{} | {}", t.1, t.2))
            .unwrap_or_else(|| " | ".into());
        let _ = writeln!(md, "| {m} | {g:.1} | {p:.1} | {paper} |");
    }
    md
}

/// `(multiplier, % GP solved, % PSW solved)`.
fn table5_points(multipliers: &[f64], rows: &[&ProblemRow]) -> Vec<(f64, f64, f64)> {
    multipliers
        .iter()
        .map(|&m| {
            let cmp = Comparison::of(
                rows.iter()
                    .filter(|r| r.multiplier == Some(m))
                    .map(|r| (r.gp_steps, r.psw_steps)),
            );
            (
                m,
                pct(cmp.gp_solved, cmp.problems),
                pct(cmp.psw_solved, cmp.problems),
            )
        })
        .collect()
}

/// Table 5's files: results.csv, table5.md, table5.svg.
pub fn table5(
    multipliers: &[f64],
    rows: &[&ProblemRow],
    m: &Manifest,
) -> Result<Vec<(String, String)>> {
    let per = rows.len() / multipliers.len().max(1);
    let what = format!("{per} problems per multiplier (⌊l_m · #leaves⌋ robots, at most |N| − 2)");
    let md = format!(
        "# GP paper, Table 5: GP vs PSW where PSW is not complete\n\n{}\n{}",
        made_by(m, &what),
        table5_summary(multipliers, rows)
    );
    let pts = table5_points(multipliers, rows);
    let ours = |name: &str, f: fn(&(f64, f64, f64)) -> f64| Series {
        name: name.into(),
        points: pts.iter().map(|t| (t.0, f(t))).collect(),
        ..Series::default()
    };
    let paper = |name: &str, f: fn(&(f64, f64, f64)) -> f64| Series {
        name: format!("{name} (paper)"),
        points: PAPER_TABLE5.iter().map(|t| (t.0, f(t))).collect(),
        paper: true,
        ..Series::default()
    };
    let panel = Panel {
        title: "% solved".into(),
        series: vec![
            ours("GP", |t| t.1),
            ours("PSW", |t| t.2),
            paper("GP", |t| t.1),
            paper("PSW", |t| t.2),
        ],
    };
    let svg = line_panels(
        "Table 5: problems solved; lines: mrpp, circles: paper",
        "robots / leaves",
        "% solved",
        &[panel],
    )
    .map_err(Error::Internal)?;
    Ok(vec![
        ("results.csv".into(), problems_csv(rows)?),
        ("table5.md".into(), md),
        ("table5.svg".into(), svg),
    ])
}

/// The Markdown table of Table 4 (also printed at the end of a run).
pub fn table4_summary(train_sizes: &[usize], rows: &[&Table4Row]) -> String {
    let tests: Vec<&TestRow> = rows.iter().flat_map(|r| &r.tests).collect();
    let mut md = String::from(
        "Percentages are over the test problems GP solved, as in the paper.\n\n| X | # GP Solved | % GP Better | % GP = PSW | % PSW Better | paper: # GP Solved (of 1000) | % GP Better | % GP = PSW | % PSW Better |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    for &x in train_sizes {
        let mine: Vec<&&TestRow> = tests.iter().filter(|r| r.train_size == x).collect();
        let solved: Vec<&&&TestRow> = mine.iter().filter(|r| r.gp_steps.is_some()).collect();
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
    let trained = rows
        .iter()
        .filter(|r| r.program.solved_training_set)
        .count();
    let _ = writeln!(
        md,
        "\n{trained} of {} evolutions found a program solving their whole training set (the others \
         are tested with their lowest-fitness program); programs in programs.csv. Figures: fig6.svg \
         (time steps vs robots), fig7.svg (time steps vs PSW swaps per robot), over test problems \
         GP solved.",
        rows.len()
    );
    md
}

/// `results.csv` (test problems) and `programs.csv` (trained programs) of Table 4.
fn table4_csvs(rows: &[&Table4Row]) -> Result<(String, String)> {
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
    ])
    .map_err(csv_err)?;
    for r in rows.iter().flat_map(|r| &r.tests) {
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
        ])
        .map_err(csv_err)?;
    }
    let results = csv_text(w)?;
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "train_size",
        "trial",
        "solved_training_set",
        "generations",
        "evaluations",
        "seconds",
        "program",
    ])
    .map_err(csv_err)?;
    for p in rows.iter().map(|r| &r.program) {
        w.write_record([
            p.train_size.to_string(),
            p.trial.to_string(),
            p.solved_training_set.to_string(),
            p.generations.to_string(),
            p.evaluations.to_string(),
            format!("{:.3}", p.seconds),
            p.program.clone(),
        ])
        .map_err(csv_err)?;
    }
    Ok((results, csv_text(w)?))
}

/// Fig. 6 / Fig. 7: one panel per |X|, time steps against `x_of` over test problems both solved.
fn fig67(
    t4: &GpTable4,
    rows: &[&Table4Row],
    title: &str,
    x_desc: &str,
    x_of: &dyn Fn(&TestRow) -> f64,
) -> Result<String> {
    let panels: Vec<Panel> = t4
        .train_sizes
        .iter()
        .map(|&x| {
            let solved: Vec<&TestRow> = rows
                .iter()
                .flat_map(|r| &r.tests)
                .filter(|r| r.train_size == x && r.gp_steps.is_some() && r.psw_steps.is_some())
                .collect();
            let pts = |s: &dyn Fn(&TestRow) -> Option<u64>| {
                solved
                    .iter()
                    .map(|r| (x_of(r), s(r).unwrap_or_default() as f64))
                    .collect()
            };
            steps_panel(
                format!("|X| = {x}"),
                pts(&|r| r.gp_steps),
                pts(&|r| r.psw_steps),
            )
        })
        .collect();
    line_panels(title, x_desc, "time steps (mean ± sd)", &panels).map_err(Error::Internal)
}

/// Table 4's files: results.csv, programs.csv, table4.md, fig6.svg, fig7.svg.
pub fn table4(t4: &GpTable4, rows: &[&Table4Row], m: &Manifest) -> Result<Vec<(String, String)>> {
    let cfg = &t4.cfg;
    let what = format!(
        "{} trials per |X|, {} new test problems per trial ({} distribution, budgets {}–{}; training {}–{})",
        t4.trials,
        t4.tests,
        cfg.distribution.name(),
        cfg.test_depths.start(),
        cfg.test_depths.end(),
        cfg.train_depths.start(),
        cfg.train_depths.end()
    );
    let md = format!(
        "# GP paper, Table 4: general GP vs PSW\n\n{}\n{}",
        made_by(m, &what),
        table4_summary(&t4.train_sizes, rows)
    );
    let (results, programs) = table4_csvs(rows)?;
    let title = "GP vs PSW, trained first, tested on new problems";
    Ok(vec![
        ("results.csv".into(), results),
        ("programs.csv".into(), programs),
        ("table4.md".into(), md),
        (
            "fig6.svg".into(),
            fig67(t4, rows, &format!("Fig. 6: {title}"), "robots", &|r| {
                r.robots as f64
            })?,
        ),
        (
            "fig7.svg".into(),
            fig67(
                t4,
                rows,
                &format!("Fig. 7: {title}"),
                "PSW swaps / robots",
                &|r| swap_ratio(r.psw_swaps, r.robots),
            )?,
        ),
    ])
}
