//! The text result format of LaCAM/PIBT, so existing MAPF visualizers (and scripts written for
//! those planners) read our plans, and so `mrpp validate` reads theirs.
//!
//! ```text
//! agents=2
//! map_file=room.map
//! solver=pibt
//! solved=1
//! soc=5
//! makespan=3
//! comp_time=12
//! starts=(1,0),(3,0),
//! goals=(2,0),(0,2),
//! solution=
//! 0:(1,0),(3,0),
//! 1:(2,0),(3,1),
//! ...
//! ```
//!
//! Cells are `(x,y)` with x the column and y the row. Each `solution` line is the configuration of
//! all agents at one time step, from 0 to the makespan; an agent whose path has ended is repeated
//! on its last cell. Keys the reader does not know (`soc_lb`, `makespan_lb`, `seed`, ...) are
//! skipped, as LaCAM's variants add their own; `soc`, `makespan` and `sum_of_loss` are claims
//! that `mrpp validate` holds against the paths ([`LacamClaims`]). A file of step lines alone (pypibt's output and
//! the visualizer's demos, with or without `solution=`) is read as solved, its starts step 0 and
//! its goals the last step.

use std::fmt::Write as _;
use std::path::Path;

use rustc_hash::FxHashMap;

use crate::map::GridMap;
use mrpp_core::error::{Error, Result};
use mrpp_core::mapf::graph::VertexId;
use mrpp_core::mapf::instance::Instance;
use mrpp_core::mapf::plan::{Metrics, Plan, position};
use mrpp_core::mapf::search::distance::lower_bounds;

/// Writes the LaCAM text result with lacam3's keys (Okumura, "Engineering LaCAM*", AAMAS 2024,
/// public code Kei18/lacam3): `agents`, `map_file`, `solver`, `solved`, `soc`, `soc_lb`,
/// `makespan`, `makespan_lb`, `sum_of_loss`, `sum_of_loss_lb`, `comp_time`, `seed`, `starts`,
/// `goals`, `solution`. `outcome` is `None` when nothing was solved: the text then says
/// `solved=0`, the costs are 0 (as LaCAM does) and the `solution=` section is empty.
///
/// The lower bounds are `mrpp info`'s: the sum and the maximum of the agents' start–goal distances
/// (`sum_of_loss_lb` = `soc_lb`; 0 when an agent cannot reach its goal). `sum_of_loss` counts,
/// per agent and step, every step except staying on its goal (what LaCAM* minimises).
/// `comp_time` is written in whole milliseconds (rounded; negative or non-finite becomes 0),
/// because LaCAM writes an integer and some readers parse it as one. The solution runs from step 0
/// to `metrics.makespan`, extended if some path still moves later (possible only for plans under
/// `visit` semantics), so no information of the plan is cut off.
pub fn write_lacam(
    map: &GridMap,
    map_file: &str,
    solver: &str,
    inst: &Instance,
    outcome: Option<(&Plan, Metrics)>,
    comp_time_ms: f64,
    seed: u64,
) -> String {
    let n = inst.num_agents();
    let comp_time = if comp_time_ms.is_finite() && comp_time_ms > 0.0 {
        comp_time_ms.round() as u64
    } else {
        0
    };
    let (soc, makespan) = outcome.map_or((0, 0), |(_, m)| (m.sum_of_costs, m.makespan));
    let (soc_lb, makespan_lb) =
        lower_bounds(map.graph(), &inst.starts, &inst.goals).unwrap_or((0, 0));
    let loss = outcome.map_or(0, |(plan, _)| plan.sum_of_loss(&inst.goals));
    let mut s = String::new();
    let _ = writeln!(s, "agents={n}");
    let _ = writeln!(s, "map_file={}", one_line(map_file));
    let _ = writeln!(s, "solver={}", one_line(solver));
    let _ = writeln!(s, "solved={}", u8::from(outcome.is_some()));
    let _ = writeln!(s, "soc={soc}");
    let _ = writeln!(s, "soc_lb={soc_lb}");
    let _ = writeln!(s, "makespan={makespan}");
    let _ = writeln!(s, "makespan_lb={makespan_lb}");
    let _ = writeln!(s, "sum_of_loss={loss}");
    let _ = writeln!(s, "sum_of_loss_lb={soc_lb}");
    let _ = writeln!(s, "comp_time={comp_time}");
    let _ = writeln!(s, "seed={seed}");
    let cells = |s: &mut String, vs: &mut dyn Iterator<Item = VertexId>| {
        for v in vs {
            let (x, y) = map.cell(v);
            let _ = write!(s, "({x},{y}),");
        }
        s.push('\n');
    };
    s.push_str("starts=");
    cells(&mut s, &mut inst.starts.iter().copied());
    s.push_str("goals=");
    cells(&mut s, &mut inst.goals.iter().copied());
    s.push_str("solution=\n");
    if let Some((plan, m)) = outcome {
        let last_move = plan
            .paths
            .iter()
            .map(|p| {
                // Last step at which this path changes cell.
                p.windows(2)
                    .rposition(|w| w[0] != w[1])
                    .map_or(0, |i| i + 1)
            })
            .max()
            .unwrap_or(0);
        let horizon = (m.makespan as usize).max(last_move);
        // An empty path makes the plan invalid anyway; writing no steps beats panicking here.
        if plan.paths.iter().all(|p| !p.is_empty()) {
            for t in 0..=horizon {
                let _ = write!(s, "{t}:");
                cells(&mut s, &mut plan.paths.iter().map(|p| position(p, t)));
            }
        }
    }
    s
}

/// Names and solver names go on one `key=value` line; a line break in them would end the line.
fn one_line(s: &str) -> String {
    s.replace(['\n', '\r'], " ")
}

/// Reads a LaCAM text result on `map` into the instance and the plan it holds.
///
/// Every path has one vertex per `solution` line (trailing waits are kept; [`Plan::trim`] drops
/// them). Errors are [`Error::Parse`] naming the line: a missing or malformed key, a wall or
/// off-map cell (naming the cell), a tuple count that differs from `agents=`, steps out of order,
/// two agents sharing a start or goal. A result with `solved=0` is [`Error::Invalid`]: it holds
/// no plan. Whether the plan itself is valid is the validator's question.
pub fn parse_lacam(text: &str, path: &Path, map: &GridMap) -> Result<(Instance, Plan)> {
    parse_lacam_with_claims(text, path, map).map(|(inst, plan, _)| (inst, plan))
}

/// What a LaCAM result claims about its plan: `soc`, `makespan` and `sum_of_loss` with their
/// lines, when the file has them. [`LacamClaims::check`] holds them against the paths, as the
/// plan envelope's `metrics` are.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct LacamClaims {
    pub soc: Option<(u64, usize)>,
    pub makespan: Option<(u64, usize)>,
    pub sum_of_loss: Option<(u64, usize)>,
}

impl LacamClaims {
    /// Compares the claims with the validator's `sum_of_costs` and `makespan` of `plan` and with
    /// its sum of loss (computed as [`write_lacam`] writes it).
    ///
    /// # Errors
    /// The first claim that disagrees, naming the file, its line, the claim and the true value.
    pub fn check(
        &self,
        path: &Path,
        plan: &Plan,
        goals: &[VertexId],
        sum_of_costs: u64,
        makespan: u64,
    ) -> Result<()> {
        let loss = || plan.sum_of_loss(goals);
        for (key, claim, actual) in [
            ("soc", self.soc, sum_of_costs),
            ("makespan", self.makespan, makespan),
            ("sum_of_loss", self.sum_of_loss, u64::MAX),
        ] {
            let Some((value, line)) = claim else { continue };
            let actual = if key == "sum_of_loss" { loss() } else { actual };
            if value != actual {
                return Err(Error::parse(
                    path,
                    line,
                    format!("the result claims {key}={value} but its paths give {actual}"),
                ));
            }
        }
        Ok(())
    }
}

/// [`parse_lacam`] with the file's [`LacamClaims`].
///
/// # Errors
/// As [`parse_lacam`], and a claim that is not a count.
pub fn parse_lacam_with_claims(
    text: &str,
    path: &Path,
    map: &GridMap,
) -> Result<(Instance, Plan, LacamClaims)> {
    let mut claims = LacamClaims::default();
    let mut agents: Option<(usize, usize)> = None;
    let mut solved: Option<(bool, usize)> = None;
    let mut starts: Option<(Vec<VertexId>, usize)> = None;
    let mut goals: Option<(Vec<VertexId>, usize)> = None;
    // Each step's configuration and its line.
    let mut steps: Vec<(Vec<VertexId>, usize)> = Vec::new();
    let mut in_solution = false;
    let mut last_line = 0;
    for (i, raw) in text.lines().enumerate() {
        let no = i + 1;
        last_line = no;
        let line = raw.trim();
        if line.is_empty() {
            continue;
        }
        // A step line before any `solution=`: a solution-only file (pypibt's output, the
        // visualizer's demos).
        let step_line = line.split_once(':').is_some_and(|(t, _)| {
            !t.trim().is_empty() && t.trim().chars().all(|c| c.is_ascii_digit())
        }) && !line.contains('=');
        if step_line && !in_solution && steps.is_empty() {
            in_solution = true;
        }
        if in_solution {
            let (t, rest) = line.split_once(':').ok_or_else(|| {
                Error::parse(path, no, format!("expected `t:(x,y),...`, found `{line}`"))
            })?;
            let t: usize = t
                .trim()
                .parse()
                .map_err(|_| Error::parse(path, no, format!("bad time step `{}`", t.trim())))?;
            if t != steps.len() {
                return Err(Error::parse(
                    path,
                    no,
                    format!("time step {t} where step {} was expected", steps.len()),
                ));
            }
            let cfg = cells(rest, path, no, map)?;
            if let Some((n, _)) = agents
                && cfg.len() != n
            {
                return Err(Error::parse(
                    path,
                    no,
                    format!("step {t} has {} cells but agents={n}", cfg.len()),
                ));
            }
            steps.push((cfg, no));
            continue;
        }
        let (key, value) = line.split_once('=').ok_or_else(|| {
            Error::parse(path, no, format!("expected `key=value`, found `{line}`"))
        })?;
        let value = value.trim();
        match key.trim() {
            "agents" => {
                let n = value.parse::<usize>().map_err(|_| {
                    Error::parse(path, no, format!("agents=`{value}` is not a count"))
                })?;
                agents = Some((n, no));
            }
            "solved" => {
                let b = match value {
                    "1" | "true" => true,
                    "0" | "false" => false,
                    _ => {
                        return Err(Error::parse(
                            path,
                            no,
                            format!("solved=`{value}` is not 0 or 1"),
                        ));
                    }
                };
                solved = Some((b, no));
            }
            "starts" => starts = Some((cells(value, path, no, map)?, no)),
            "goals" => goals = Some((cells(value, path, no, map)?, no)),
            "solution" => {
                if !value.is_empty() {
                    return Err(Error::parse(
                        path,
                        no,
                        "`solution=` must end its line; steps follow on their own lines",
                    ));
                }
                in_solution = true;
            }
            key @ ("soc" | "makespan" | "sum_of_loss") => {
                let v = value.parse::<u64>().map_err(|_| {
                    Error::parse(path, no, format!("{key}=`{value}` is not a count"))
                })?;
                let slot = match key {
                    "soc" => &mut claims.soc,
                    "makespan" => &mut claims.makespan,
                    _ => &mut claims.sum_of_loss,
                };
                *slot = Some((v, no));
            }
            _ => {} // comp_time, soc_lb, seed, ...: informative only.
        }
    }
    let missing = |key: &str| Error::parse(path, last_line.max(1), format!("no `{key}=` line"));
    // Without any header key, the steps say it all: the agents are step 0's, solved, from step
    // 0's cells to the last step's. With a header, every key is required.
    let bare = agents.is_none() && solved.is_none() && starts.is_none() && goals.is_none();
    if bare && let Some((cfg, line)) = steps.first() {
        agents = Some((cfg.len(), *line));
        solved = Some((true, *line));
        starts = steps.first().cloned();
        goals = steps.last().cloned();
    }
    let (n, agents_line) = agents.ok_or_else(|| missing("agents"))?;
    let (solved, _) = solved.ok_or_else(|| missing("solved"))?;
    if !solved {
        return Err(Error::invalid(
            path,
            "the result says solved=0: it holds no plan (nothing to check or draw)",
        ));
    }
    let (starts, starts_line) = starts.ok_or_else(|| missing("starts"))?;
    let (goals, goals_line) = goals.ok_or_else(|| missing("goals"))?;
    for (list, line, what) in [
        (&starts, starts_line, "starts"),
        (&goals, goals_line, "goals"),
    ] {
        if list.len() != n {
            return Err(Error::parse(
                path,
                line,
                format!(
                    "{what} has {} cells but agents={n} (line {agents_line})",
                    list.len()
                ),
            ));
        }
        let mut seen: FxHashMap<VertexId, usize> = FxHashMap::default();
        for (i, &v) in list.iter().enumerate() {
            if let Some(j) = seen.insert(v, i) {
                let (x, y) = map.cell(v);
                return Err(Error::parse(
                    path,
                    line,
                    format!("agents {j} and {i} share the cell ({x},{y}) in {what}"),
                ));
            }
        }
    }
    if !in_solution {
        return Err(missing("solution"));
    }
    if steps.is_empty() {
        return Err(Error::parse(
            path,
            last_line.max(1),
            "solved=1 but the solution has no steps",
        ));
    }
    // `agents=` may come after the steps in hand-made files, so the counts are checked again here.
    if let Some((cfg, line)) = steps.iter().find(|(cfg, _)| cfg.len() != n) {
        return Err(Error::parse(
            path,
            *line,
            format!("this step has {} cells but agents={n}", cfg.len()),
        ));
    }
    let paths = (0..n)
        .map(|i| steps.iter().map(|(cfg, _)| cfg[i]).collect())
        .collect();
    let inst = Instance::new(starts, goals).map_err(|msg| Error::invalid(path, msg))?;
    Ok((inst, Plan::new(paths), claims))
}

/// Parses `(x,y),(x,y),` (spaces tolerated, final comma optional) into vertices of `map`.
fn cells(text: &str, path: &Path, line: usize, map: &GridMap) -> Result<Vec<VertexId>> {
    let mut out = Vec::new();
    let mut rest = text.trim();
    while !rest.is_empty() {
        let bad = || {
            Error::parse(
                path,
                line,
                format!(
                    "expected `(x,y),` at `{}`",
                    rest.chars().take(20).collect::<String>()
                ),
            )
        };
        let inner_end = rest.find(')').ok_or_else(bad)?;
        let inner = rest.strip_prefix('(').ok_or_else(bad)?;
        let inner = &inner[..inner_end - 1];
        let (x, y) = inner.split_once(',').ok_or_else(bad)?;
        let x: i64 = x.trim().parse().map_err(|_| bad())?;
        let y: i64 = y.trim().parse().map_err(|_| bad())?;
        let v = map.vertex_at(x, y).ok_or_else(|| {
            Error::parse(
                path,
                line,
                format!(
                    "agent {}: {}",
                    out.len(),
                    map.cell_problem(x, y).unwrap_or_default()
                ),
            )
        })?;
        out.push(v);
        rest = rest[inner_end + 1..].trim_start();
        rest = rest.strip_prefix(',').unwrap_or(rest).trim_start();
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrpp_core::{MapfProblem, Problem as _, Rules};

    /// ```text
    /// ...
    /// .@.
    /// ...
    /// ```
    fn map() -> GridMap {
        GridMap::parse(
            "type octile\nheight 3\nwidth 3\nmap\n...\n.@.\n...\n",
            Path::new("m.map"),
        )
        .unwrap()
        .0
    }

    fn v(m: &GridMap, x: i64, y: i64) -> VertexId {
        m.vertex_at(x, y).unwrap()
    }

    /// Agent 0 goes (0,0) -> (2,0) along the top; agent 1 waits one step, then (2,2) -> (2,1).
    fn tiny() -> (GridMap, Instance, Plan, Metrics) {
        let m = map();
        let inst = Instance::new(
            vec![v(&m, 0, 0), v(&m, 2, 2)],
            vec![v(&m, 2, 0), v(&m, 2, 1)],
        )
        .unwrap();
        let plan = Plan::new(vec![
            vec![v(&m, 0, 0), v(&m, 1, 0), v(&m, 2, 0)],
            vec![v(&m, 2, 2), v(&m, 2, 2), v(&m, 2, 1)],
        ]);
        let metrics = MapfProblem::on(m.graph(), &inst, Rules::default())
            .validate(&plan)
            .unwrap();
        (m, inst, plan, metrics)
    }

    #[test]
    fn a_solution_only_file_is_read_as_solved_from_its_first_to_its_last_step() {
        let (m, inst, plan, _) = tiny();
        for text in [
            "0:(0,0),(2,2),\n1:(1,0),(2,2),\n2:(2,0),(2,1),\n",
            "solution=\n0:(0,0),(2,2)\n1:(1,0),(2,2)\n2:(2,0),(2,1)\n",
        ] {
            let (i, p) = parse_lacam(text, Path::new("r.txt"), &m).unwrap();
            assert_eq!((i, p), (inst.clone(), plan.clone()), "{text}");
        }
        // Still one-line errors when the steps are broken.
        let err = parse_lacam("0:(0,0),(2,2),\n2:(2,0),(2,1),\n", Path::new("r.txt"), &m)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("r.txt:2") && err.contains("step 2 where step 1"),
            "{err}"
        );
    }

    #[test]
    fn exact_text_of_a_tiny_plan() {
        let (m, inst, plan, metrics) = tiny();
        let text = write_lacam(&m, "m.map", "pibt", &inst, Some((&plan, metrics)), 3.6, 9);
        assert_eq!(
            text,
            "agents=2\nmap_file=m.map\nsolver=pibt\nsolved=1\nsoc=4\nsoc_lb=3\nmakespan=2\n\
             makespan_lb=2\nsum_of_loss=4\nsum_of_loss_lb=3\ncomp_time=4\nseed=9\n\
             starts=(0,0),(2,2),\ngoals=(2,0),(2,1),\nsolution=\n\
             0:(0,0),(2,2),\n1:(1,0),(2,2),\n2:(2,0),(2,1),\n"
        );
    }

    /// Each claim of a written result holds; changing any one of them by 1 is caught, naming the
    /// line, the claim and the true value.
    #[test]
    fn claims_are_held_against_the_paths() {
        let (m, inst, plan, metrics) = tiny();
        let text = write_lacam(&m, "m.map", "pibt", &inst, Some((&plan, metrics)), 3.6, 9);
        let check = |text: &str| {
            let (inst, plan, claims) =
                parse_lacam_with_claims(text, Path::new("r.txt"), &m).unwrap();
            claims.check(
                Path::new("r.txt"),
                &plan,
                &inst.goals,
                metrics.sum_of_costs,
                metrics.makespan,
            )
        };
        check(&text).unwrap();
        for (key, line, right, wrong) in [
            ("soc", 5, 4, 5),
            ("makespan", 7, 2, 3),
            ("sum_of_loss", 9, 4, 3),
        ] {
            let bad = text.replace(&format!("\n{key}={right}\n"), &format!("\n{key}={wrong}\n"));
            assert_ne!(bad, text);
            let err = check(&bad).unwrap_err().to_string();
            assert_eq!(
                err,
                format!("r.txt:{line}: the result claims {key}={wrong} but its paths give {right}")
            );
        }
        let err =
            parse_lacam_with_claims(&text.replace("soc=4", "soc=four"), Path::new("r.txt"), &m)
                .unwrap_err()
                .to_string();
        assert!(err.contains("r.txt:5: soc=`four` is not a count"), "{err}");
    }

    #[test]
    fn round_trip_gives_the_same_plan_after_trimming() {
        let (m, inst, _, _) = tiny();
        // Agent 0 arrives at t=2, agent 1 at t=4 (after two waits) and agent 0's path ends early.
        let plan = Plan::new(vec![
            vec![v(&m, 0, 0), v(&m, 1, 0), v(&m, 2, 0), v(&m, 2, 0)],
            vec![
                v(&m, 2, 2),
                v(&m, 1, 2),
                v(&m, 1, 2),
                v(&m, 2, 2),
                v(&m, 2, 1),
            ],
        ]);
        let metrics = MapfProblem::on(m.graph(), &inst, Rules::default())
            .validate(&plan)
            .unwrap();
        let text = write_lacam(&m, "m.map", "x", &inst, Some((&plan, metrics)), 0.0, 0);
        let (inst2, mut plan2) = parse_lacam(&text, Path::new("r.txt"), &m).unwrap();
        assert_eq!(inst2, inst);
        assert!(
            plan2.paths.iter().all(|p| p.len() == 5),
            "one cell per step"
        );
        assert_eq!(
            MapfProblem::on(m.graph(), &inst2, Rules::default()).validate(&plan2),
            Ok(metrics)
        );
        let mut want = plan.clone();
        want.trim();
        plan2.trim();
        assert_eq!(plan2, want);
    }

    #[test]
    fn unsolved_result_holds_no_plan() {
        let (m, inst, _, _) = tiny();
        let text = write_lacam(&m, "m.map", "x", &inst, None, f64::NAN, 0);
        assert!(
            text.contains(
                "solved=0\nsoc=0\nsoc_lb=3\nmakespan=0\nmakespan_lb=2\nsum_of_loss=0\n\
                 sum_of_loss_lb=3\ncomp_time=0\nseed=0\n"
            ),
            "{text}"
        );
        assert!(text.ends_with("solution=\n"), "{text}");
        let err = parse_lacam(&text, Path::new("r.txt"), &m).unwrap_err();
        assert!(matches!(err, Error::Invalid { .. }), "{err}");
        assert!(err.to_string().contains("no plan"));
    }

    #[test]
    fn reads_lacam_own_output_with_extra_keys_and_crlf() {
        let m = map();
        let text = "agents=2\r\nmap_file=m.map\r\nsolver=planner\r\nsolved=1\r\nsoc=4\r\n\
                    soc_lb=4\r\nmakespan=2\r\nmakespan_lb=2\r\ncomp_time=0\r\nseed=0\r\n\
                    starts=(0,0),(2,2),\r\ngoals=(2,0),(2,1)\r\nsolution=\r\n\
                    0:(0,0),(2,2),\r\n1:( 1 , 0 ),(2,2),\r\n2:(2,0),(2,1),\r\n";
        let (inst, plan) = parse_lacam(text, Path::new("r.txt"), &m).unwrap();
        let metrics = MapfProblem::on(m.graph(), &inst, Rules::default())
            .validate(&plan)
            .unwrap();
        assert_eq!((metrics.sum_of_costs, metrics.makespan), (4, 2));
    }

    fn err_of(text: &str) -> String {
        parse_lacam(text, Path::new("r.txt"), &map())
            .unwrap_err()
            .to_string()
    }

    const HEAD: &str = "agents=2\nsolved=1\nstarts=(0,0),(2,2),\ngoals=(2,0),(2,1),\nsolution=\n";

    #[test]
    fn errors_name_the_line_and_cell() {
        let e = err_of(&format!("{HEAD}0:(0,0),(2,2),\n1:(1,1),(2,2),\n"));
        assert!(e.starts_with("r.txt:7:"), "{e}");
        assert!(e.contains("agent 0: cell (1,1) is a wall"), "{e}");

        let e = err_of(&format!("{HEAD}0:(0,0),(2,2),\n1:(0,0),(3,2),\n"));
        assert!(e.starts_with("r.txt:7:"), "{e}");
        assert!(e.contains("agent 1: cell (3,2) is off the 3x3 map"), "{e}");

        let e = err_of(&format!("{HEAD}0:(0,0),(2,2),\n2:(0,0),(2,2),\n"));
        assert!(
            e.starts_with("r.txt:7:") && e.contains("step 1 was expected"),
            "{e}"
        );

        let e = err_of(&format!("{HEAD}0:(0,0),\n"));
        assert!(
            e.starts_with("r.txt:6:") && e.contains("1 cells but agents=2"),
            "{e}"
        );

        let e = err_of(&format!("{HEAD}0:(0,0)(2,2\n"));
        assert!(
            e.starts_with("r.txt:6:") && e.contains("expected `(x,y),`"),
            "{e}"
        );

        let e = err_of(
            "agents=2\nsolved=1\nstarts=(0,0),(0,0),\ngoals=(2,0),(2,1),\nsolution=\n0:(0,0),(0,0),\n",
        );
        assert!(
            e.starts_with("r.txt:3:") && e.contains("share the cell (0,0)"),
            "{e}"
        );

        let e = err_of("agents=2\nsolved=1\nstarts=(0,0),(2,2),\nsolution=\n0:(0,0),(2,2),\n");
        assert!(e.contains("no `goals=` line"), "{e}");

        let e = err_of("agents=2\nsolved=1\nstarts=(0,0),\ngoals=(2,0),(2,1),\nsolution=\n");
        assert!(
            e.starts_with("r.txt:3:") && e.contains("starts has 1 cells"),
            "{e}"
        );

        let e = err_of(HEAD);
        assert!(e.contains("no steps"), "{e}");

        let e = err_of("agents=two\n");
        assert!(e.starts_with("r.txt:1:"), "{e}");
    }
}
