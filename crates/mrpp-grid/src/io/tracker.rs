//! The MAPF Tracker's result CSV (Shen et al., "Tracking Progress in Multi-Agent Path Finding",
//! 2023; <http://tracker.pathfinding.ai/>), written from a grid plan and read back into one.
//!
//! The layout, as the tracker's downloadable results hold it (checked against the two result
//! files PlanViz ships as examples, `example/random-32-32-20.csv` and
//! `example/random-32-32-20_random_1_300.csv`, MAPF-Competition/PlanViz commit `c03a1d6`, and
//! the columns its `script/tracker_transfer.py` reads):
//!
//! ```text
//! map_name,scen_type,type_id,agents,lower_cost,solution_cost,solution_plan
//! random-32-32-20,even,1,2,11,11,"drdr
//! uurruuu"
//! ```
//!
//! - one row per instance: the map's name (its file name without `.map`), the scenario's type
//!   (`random` or `even`) and number (the scenario file is `{map_name}-{scen_type}-{type_id}.scen`),
//!   the agent count (the scenario's first `agents` agents), a lower bound on the sum of costs and
//!   the plan's sum of costs;
//! - `solution_plan`: one string of moves per agent, agents in scenario order, separated by a
//!   newline (so the field is quoted); each string runs from the agent's start until it last
//!   arrives at its goal (no trailing waits), so its length is the agent's cost and the lengths
//!   sum to `solution_cost`;
//! - moves: `l` x - 1, `r` x + 1, `u` y + 1, `d` y - 1, `w` wait, with x the column and y the row
//!   of the MovingAI map (y grows down the file). So `u` moves *down* the map as drawn. This was
//!   measured, not assumed: replaying the 300-agent example from
//!   `random-32-32-20-random-1.scen` with `u` = y + 1 brings all 300 agents to their goals, with
//!   `u` = y - 1 only 8.
//!
//! The single-instance download (columns `agents,lower_cost,lower_date,solution_cost,
//! solution_date,path`) is read too: its plan column is `path`, and it names no map or scenario.
//!
//! mrpp writes `lower_cost` as `mrpp info`'s bound (the sum of the agents' start-goal distances);
//! the tracker's own lower bounds come from optimal solvers and may be higher. A scenario file
//! whose name is not `{map_name}-{type}-{id}.scen` is written with its file name (without
//! extension) as `scen_type` and `type_id` 0.

use std::fmt::Write as _;
use std::path::Path;

use mrpp_core::error::{Error, Result};
use mrpp_core::mapf::graph::VertexId;
use mrpp_core::mapf::instance::Instance;
use mrpp_core::mapf::plan::GoalSemantics;
use mrpp_core::mapf::plan::{Plan, path_cost};
use mrpp_core::mapf::search::distance::lower_bounds;

use crate::map::GridMap;

/// The columns mrpp writes, in order (the tracker's multi-instance download).
pub const HEADER: [&str; 7] = [
    "map_name",
    "scen_type",
    "type_id",
    "agents",
    "lower_cost",
    "solution_cost",
    "solution_plan",
];

/// One instance's result: a row of the CSV.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TrackerRow {
    /// The map's name (file name without `.map`); empty when the file does not say.
    pub map_name: String,
    /// The scenario's type (`random`, `even`); empty when the file does not say.
    pub scen_type: String,
    /// The scenario's number; 0 when the file does not say.
    pub type_id: u32,
    /// Agents: the scenario's first `agents`.
    pub agents: usize,
    /// A lower bound on the sum of costs, when given.
    pub lower_cost: Option<u64>,
    /// The plan's sum of costs (as claimed by the file when read).
    pub solution_cost: u64,
    /// Per agent, its moves (`l`, `r`, `u`, `d`, `w`; module doc).
    pub plan: Vec<String>,
    /// The file line the row starts on (1-based; 0 for rows not read from a file).
    pub line: usize,
}

impl TrackerRow {
    /// The row of `plan` for `inst` on `map`: moves up to each agent's last arrival at its goal,
    /// `solution_cost` their total, `lower_cost` the sum of start-goal distances (`None` when an
    /// agent cannot reach its goal). `scen_file` is the scenario's file name (module doc).
    ///
    /// # Errors
    /// A path that does not end on its agent's goal, or a step that is not a wait or a move to a
    /// 4-neighbour (naming agent and step): such a plan has no tracker form.
    pub fn of_plan(
        map: &GridMap,
        map_file: &str,
        scen_file: &str,
        inst: &Instance,
        plan: &Plan,
    ) -> std::result::Result<TrackerRow, String> {
        let map_name = stem(map_file, ".map");
        let (scen_type, type_id) = scen_kind(&map_name, scen_file);
        let mut moves = Vec::with_capacity(plan.paths.len());
        for (i, path) in plan.paths.iter().enumerate() {
            let goal = inst.goals[i];
            let cost = path_cost(path, goal, GoalSemantics::Stay)
                .ok_or_else(|| format!("agent {i} does not end on its goal"))?;
            moves.push(moves_of(map, &path[..=cost]).map_err(|k| {
                format!("agent {i}, step {k}: not a wait or a move to a neighbouring cell")
            })?);
        }
        let lower_cost = lower_bounds(map.graph(), &inst.starts, &inst.goals)
            .ok()
            .map(|(sum, _)| sum);
        Ok(TrackerRow {
            map_name,
            scen_type,
            type_id,
            agents: inst.num_agents(),
            lower_cost,
            solution_cost: moves.iter().map(|m| m.len() as u64).sum(),
            plan: moves,
            line: 0,
        })
    }

    /// The plan this row's moves give from `starts` (one path per agent, from its start; a path
    /// has one more vertex than moves). Whether it is valid is the validator's question.
    ///
    /// # Errors
    /// A start count other than `agents` or the plan's agent count, a letter outside `lrudw`, a
    /// move off the map or into a wall: naming `path`, the row's line, the agent and the step.
    pub fn to_plan(&self, map: &GridMap, starts: &[VertexId], path: &Path) -> Result<Plan> {
        let bad = |msg: String| Error::parse(path, self.line, msg);
        if self.plan.len() != self.agents || starts.len() != self.agents {
            return Err(bad(format!(
                "the row says agents={} but its plan has {} agents and the scenario gives {} starts",
                self.agents,
                self.plan.len(),
                starts.len()
            )));
        }
        let mut paths = Vec::with_capacity(self.agents);
        for (i, (moves, &start)) in self.plan.iter().zip(starts).enumerate() {
            let (x, y) = map.cell(start);
            let (mut x, mut y) = (i64::from(x), i64::from(y));
            let mut p = Vec::with_capacity(moves.len() + 1);
            p.push(start);
            for (k, c) in moves.chars().enumerate() {
                match c {
                    'l' => x -= 1,
                    'r' => x += 1,
                    'u' => y += 1,
                    'd' => y -= 1,
                    'w' => {}
                    other => {
                        return Err(bad(format!(
                            "agent {i}, step {}: `{other}` is not a move (l, r, u, d or w)",
                            k + 1
                        )));
                    }
                }
                let v = map.vertex_at(x, y).ok_or_else(|| {
                    bad(format!(
                        "agent {i}, step {}: `{c}` leads to ({x},{y}): {}",
                        k + 1,
                        map.cell_problem(x, y).unwrap_or_default()
                    ))
                })?;
                p.push(v);
            }
            paths.push(p);
        }
        Ok(Plan::new(paths))
    }
}

/// The moves of `path` (one letter per step), or the first step (1-based) that is neither a wait
/// nor a move to a 4-neighbour.
pub fn moves_of(map: &GridMap, path: &[VertexId]) -> std::result::Result<String, usize> {
    path.windows(2)
        .enumerate()
        .map(|(k, w)| {
            let (a, b) = (map.cell(w[0]), map.cell(w[1]));
            let (dx, dy) = (
                i64::from(b.0) - i64::from(a.0),
                i64::from(b.1) - i64::from(a.1),
            );
            match (dx, dy) {
                (0, 0) => Ok('w'),
                (-1, 0) => Ok('l'),
                (1, 0) => Ok('r'),
                (0, 1) => Ok('u'),
                (0, -1) => Ok('d'),
                _ => Err(k + 1),
            }
        })
        .collect()
}

/// `file` without its folder and `ext`.
fn stem(file: &str, ext: &str) -> String {
    let name = Path::new(file)
        .file_name()
        .map_or_else(|| file.to_string(), |n| n.to_string_lossy().into_owned());
    name.strip_suffix(ext).unwrap_or(&name).to_string()
}

/// `(scen_type, type_id)` of a scenario file named `{map_name}-{type}-{id}.scen` (module doc).
fn scen_kind(map_name: &str, scen_file: &str) -> (String, u32) {
    let s = stem(scen_file, ".scen");
    let parsed = s
        .strip_prefix(map_name)
        .and_then(|r| r.strip_prefix('-'))
        .and_then(|r| r.rsplit_once('-'))
        .and_then(|(t, id)| Some((t.to_string(), id.parse::<u32>().ok()?)))
        .filter(|(t, _)| !t.is_empty());
    parsed.unwrap_or((s, 0))
}

/// The CSV of `rows` with [`HEADER`] (fields quoted when they hold a comma, quote or newline;
/// lines end in `\n`).
pub fn write_tracker(rows: &[TrackerRow]) -> String {
    let mut s = HEADER.join(",");
    s.push('\n');
    for r in rows {
        let fields = [
            r.map_name.clone(),
            r.scen_type.clone(),
            r.type_id.to_string(),
            r.agents.to_string(),
            r.lower_cost.map_or(String::new(), |c| c.to_string()),
            r.solution_cost.to_string(),
            r.plan.join("\n"),
        ];
        let line: Vec<String> = fields.iter().map(|f| quoted(f)).collect();
        let _ = writeln!(s, "{}", line.join(","));
    }
    s
}

fn quoted(f: &str) -> String {
    if f.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", f.replace('"', "\"\""))
    } else {
        f.to_string()
    }
}

/// Whether `text` looks like a tracker result CSV: its first line is a header naming
/// `solution_cost` and a plan column (`solution_plan` or `path`).
pub fn is_tracker(text: &str) -> bool {
    let first = text
        .trim_start_matches('\u{feff}')
        .lines()
        .next()
        .unwrap_or("");
    let cols: Vec<String> = first
        .split(',')
        .map(|c| c.trim().trim_matches('"').to_ascii_lowercase())
        .collect();
    cols.iter().any(|c| c == "solution_cost")
        && cols.iter().any(|c| c == "solution_plan" || c == "path")
}

/// Reads a tracker result CSV (either layout; module doc) into its rows.
///
/// # Errors
/// [`Error::Parse`] naming the line: no header, a header without `agents`, `solution_cost` or a
/// plan column, a row with another field count, a count that is not a number, an unclosed
/// quote, a plan whose agent count differs from `agents`. A file with no rows is
/// [`Error::Invalid`].
pub fn parse_tracker(text: &str, path: &Path) -> Result<Vec<TrackerRow>> {
    let records = records(text.trim_start_matches('\u{feff}'), path)?;
    let Some((header, _)) = records.first() else {
        return Err(Error::invalid(path, "empty file: no tracker header"));
    };
    let col = |name: &str| {
        header
            .iter()
            .position(|h| h.trim().eq_ignore_ascii_case(name))
    };
    let need = |name: &str| {
        col(name).ok_or_else(|| {
            Error::parse(
                path,
                1,
                format!("the header has no `{name}` column: not a MAPF Tracker result CSV"),
            )
        })
    };
    let agents_col = need("agents")?;
    let cost_col = need("solution_cost")?;
    let plan_col = col("solution_plan")
        .or_else(|| col("path"))
        .ok_or_else(|| need("solution_plan").unwrap_err())?;
    let (map_col, type_col, id_col, lower_col) = (
        col("map_name"),
        col("scen_type"),
        col("type_id"),
        col("lower_cost"),
    );
    let mut rows = Vec::new();
    for (fields, line) in &records[1..] {
        if fields.len() == 1 && fields[0].trim().is_empty() {
            continue;
        }
        if fields.len() != header.len() {
            return Err(Error::parse(
                path,
                *line,
                format!(
                    "the row has {} fields, the header {}",
                    fields.len(),
                    header.len()
                ),
            ));
        }
        let text_at = |c: Option<usize>| c.map_or(String::new(), |c| fields[c].trim().to_string());
        let number = |c: usize, name: &str| -> Result<u64> {
            fields[c].trim().parse::<u64>().map_err(|_| {
                Error::parse(
                    path,
                    *line,
                    format!("`{name}` is `{}`, not a count", fields[c].trim()),
                )
            })
        };
        let agents = number(agents_col, "agents")? as usize;
        let plan: Vec<String> = fields[plan_col]
            .split('\n')
            .map(|s| s.trim_end_matches('\r').trim().to_string())
            .collect();
        // One agent with an empty plan is a field of one empty line.
        let plan = if agents == 0 && plan == [""] {
            Vec::new()
        } else {
            plan
        };
        if plan.len() != agents {
            return Err(Error::parse(
                path,
                *line,
                format!(
                    "the plan has {} agents (lines) but agents={agents}",
                    plan.len()
                ),
            ));
        }
        rows.push(TrackerRow {
            map_name: text_at(map_col),
            scen_type: text_at(type_col),
            type_id: match id_col {
                Some(c) if !fields[c].trim().is_empty() => number(c, "type_id")? as u32,
                _ => 0,
            },
            agents,
            lower_cost: match lower_col {
                Some(c) if !fields[c].trim().is_empty() => Some(number(c, "lower_cost")?),
                _ => None,
            },
            solution_cost: number(cost_col, "solution_cost")?,
            plan,
            line: *line,
        });
    }
    if rows.is_empty() {
        return Err(Error::invalid(path, "the tracker CSV has no result rows"));
    }
    Ok(rows)
}

/// The CSV's records (fields unquoted) with the line each starts on (RFC 4180: quoted fields may
/// hold commas, newlines and doubled quotes).
fn records(text: &str, path: &Path) -> Result<Vec<(Vec<String>, usize)>> {
    let mut out = Vec::new();
    let mut fields = Vec::new();
    let mut field = String::new();
    let mut line = 1;
    let mut start = 1;
    let mut quoted = false;
    let mut quote_line = 0;
    let mut chars = text.chars().peekable();
    let mut any = false;
    while let Some(c) = chars.next() {
        any = true;
        if quoted {
            match c {
                '"' if chars.peek() == Some(&'"') => {
                    chars.next();
                    field.push('"');
                }
                '"' => quoted = false,
                '\n' => {
                    line += 1;
                    field.push('\n');
                }
                _ => field.push(c),
            }
            continue;
        }
        match c {
            '"' if field.trim().is_empty() => {
                field.clear();
                quoted = true;
                quote_line = line;
            }
            ',' => fields.push(std::mem::take(&mut field)),
            '\r' if chars.peek() == Some(&'\n') => {}
            '\n' => {
                fields.push(std::mem::take(&mut field));
                out.push((std::mem::take(&mut fields), start));
                line += 1;
                start = line;
                any = false;
            }
            _ => field.push(c),
        }
    }
    if quoted {
        return Err(Error::parse(
            path,
            quote_line,
            "a quoted field is never closed",
        ));
    }
    if any {
        fields.push(field);
        out.push((fields, start));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrpp_core::Problem as _;

    fn map() -> GridMap {
        GridMap::parse("....\n.#..\n....", Path::new("m.txt"))
            .unwrap()
            .0
    }

    fn v(m: &GridMap, x: i64, y: i64) -> VertexId {
        m.vertex_at(x, y).unwrap()
    }

    /// Two agents swapping ends of the top and bottom rows, one arriving early.
    fn instance(m: &GridMap) -> (Instance, Plan) {
        let inst =
            Instance::new(vec![v(m, 0, 0), v(m, 3, 2)], vec![v(m, 3, 0), v(m, 2, 2)]).unwrap();
        let a: Vec<VertexId> = (0..4).map(|x| v(m, x, 0)).collect();
        let b = vec![v(m, 3, 2), v(m, 3, 2), v(m, 2, 2), v(m, 2, 2)];
        (inst, Plan::new(vec![a, b]))
    }

    #[test]
    fn writes_the_tracker_layout() {
        let m = map();
        let (inst, plan) = instance(&m);
        let row =
            TrackerRow::of_plan(&m, "dir/room.map", "room-even-3.scen", &inst, &plan).unwrap();
        assert_eq!(row.plan, vec!["rrr".to_string(), "wl".to_string()]);
        assert_eq!(row.solution_cost, 5);
        assert_eq!(row.lower_cost, Some(4));
        assert_eq!(
            write_tracker(&[row]),
            "map_name,scen_type,type_id,agents,lower_cost,solution_cost,solution_plan\n\
             room,even,3,2,4,5,\"rrr\nwl\"\n"
        );
    }

    #[test]
    fn y_grows_with_u() {
        let m = map();
        let p = vec![v(&m, 0, 0), v(&m, 0, 1), v(&m, 0, 2), v(&m, 0, 1)];
        assert_eq!(moves_of(&m, &p).unwrap(), "uud");
        assert_eq!(moves_of(&m, &[v(&m, 0, 0), v(&m, 2, 0)]), Err(1));
    }

    #[test]
    fn round_trip_gives_the_same_paths() {
        let m = map();
        let (inst, plan) = instance(&m);
        let text =
            write_tracker(&[TrackerRow::of_plan(&m, "m.map", "s.scen", &inst, &plan).unwrap()]);
        let rows = parse_tracker(&text, Path::new("r.csv")).unwrap();
        assert_eq!(rows.len(), 1);
        assert_eq!(rows[0].line, 2);
        assert_eq!((rows[0].scen_type.as_str(), rows[0].type_id), ("s", 0));
        let mut back = rows[0]
            .to_plan(&m, &inst.starts, Path::new("r.csv"))
            .unwrap();
        let mut want = plan.clone();
        back.trim();
        want.trim();
        assert_eq!(back, want);
        let problem = crate::problem_on(&m, inst);
        assert_eq!(problem.validate(&back).unwrap().sum_of_costs, 5);
    }

    #[test]
    fn reads_the_single_instance_layout_with_bom_and_crlf() {
        let text = "\u{feff}\"agents\",\"lower_cost\",\"lower_date\",\"solution_cost\",\"solution_date\",\"path\"\r\n\"2\",\"4\",\"2022-11-29\",\"5\",\"2022-11-29\",\"rrr\r\nwl\"\r\n";
        assert!(is_tracker(text));
        let rows = parse_tracker(text, Path::new("r.csv")).unwrap();
        assert_eq!(rows[0].plan, vec!["rrr".to_string(), "wl".to_string()]);
        assert_eq!((rows[0].agents, rows[0].solution_cost), (2, 5));
        assert_eq!(rows[0].lower_cost, Some(4));
    }

    #[test]
    fn malformed_files_name_the_line_and_rule() {
        let p = Path::new("r.csv");
        let head = "map_name,scen_type,type_id,agents,lower_cost,solution_cost,solution_plan\n";
        let err = |t: &str| parse_tracker(t, p).unwrap_err().to_string();
        assert!(
            err("a,b\n1,2\n").contains("no `agents` column"),
            "{}",
            err("a,b\n")
        );
        let e = err(&format!(
            "{head}m,even,1,2,4,5,\"rrr\nwl\"\nm,even,1,x,4,5,r\n"
        ));
        assert!(e.contains(":4") && e.contains("`agents` is `x`"), "{e}");
        let e = err(&format!("{head}m,even,1,3,4,5,\"rrr\nwl\"\n"));
        assert!(e.contains(":2") && e.contains("2 agents"), "{e}");
        let e = err(&format!("{head}m,even,1,2,4,5,\"rrr\nwl\n"));
        assert!(e.contains(":2") && e.contains("never closed"), "{e}");
        let e = err(&format!("{head}m,even,1,2,4\n"));
        assert!(e.contains("5 fields"), "{e}");
        let e = err(head);
        assert!(e.contains("no result rows"), "{e}");
        let m = map();
        let (inst, _) = instance(&m);
        let rows = parse_tracker(&format!("{head}m,even,1,2,4,5,\"rrd\nwx\"\n"), p).unwrap();
        let e = rows[0]
            .to_plan(&m, &inst.starts, p)
            .unwrap_err()
            .to_string();
        assert!(e.contains("agent 0, step 3") && e.contains("(2,-1)"), "{e}");
        let rows = parse_tracker(&format!("{head}m,even,1,2,4,5,\"rrr\nwx\"\n"), p).unwrap();
        let e = rows[0]
            .to_plan(&m, &inst.starts, p)
            .unwrap_err()
            .to_string();
        assert!(e.contains("agent 1, step 2") && e.contains("`x`"), "{e}");
    }
}
