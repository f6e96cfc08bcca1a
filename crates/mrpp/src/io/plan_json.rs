//! mrpp's JSON plan: what `mrpp solve` writes and `mrpp validate` reads back.
//!
//! ```json
//! {"map_file": "room.map", "planner": "pibt", "seed": 0, "solved": true, "goal_semantics": "stay",
//!  "metrics": {"sum_of_costs": 5, "makespan": 3, "sum_of_moves": 4, "runtime_ms": 0.4},
//!  "agents": [{"start": [1, 0], "goal": [2, 0], "path": [[1, 0], [0, 0], [2, 0]]}]}
//! ```
//!
//! Cells are `[x, y]` (x = column, y = row, from 0 at the top-left); the index in `path` is the
//! time step and `path[0]` is the start. A path may end early: the agent then stays on its last
//! cell. An unsolved run keeps starts and goals (so the file still describes the instance) with
//! empty paths and `null` metrics.
//!
//! Cells are stored as signed integers so that a file naming a cell off the map (e.g. `[-1, 3]`)
//! parses and then fails with a message naming the agent, step and cell, instead of a bare serde
//! type error.

use std::fmt::Write as _;
use std::path::Path;

use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::graph::VertexId;
use crate::grid::GridMap;
use crate::instance::Instance;
use crate::plan::{GoalSemantics, Metrics, Plan};

/// A grid cell `[x, y]`.
pub type Cell = [i64; 2];

/// The whole JSON plan file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlanFile {
    /// The map the plan was made on, as the planner was given it (informative only).
    #[serde(default)]
    pub map_file: String,
    #[serde(default)]
    pub planner: String,
    #[serde(default)]
    pub seed: u64,
    pub solved: bool,
    /// Missing in hand-written files means `stay`, MAPF's default.
    #[serde(default)]
    pub goal_semantics: GoalSemantics,
    /// Missing in hand-written files means "not reported".
    #[serde(default)]
    pub metrics: PlanMetrics,
    pub agents: Vec<AgentEntry>,
}

/// Quality of the plan as the planner reported it; the counts are `null` when nothing was solved.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct PlanMetrics {
    pub sum_of_costs: Option<u64>,
    pub makespan: Option<u64>,
    pub sum_of_moves: Option<u64>,
    #[serde(default)]
    pub runtime_ms: f64,
}

/// One agent: its task and its path (empty when unsolved).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct AgentEntry {
    pub start: Cell,
    pub goal: Cell,
    #[serde(default)]
    pub path: Vec<Cell>,
}

impl PlanFile {
    /// Describes one planner run. `outcome` is `None` when the planner found no plan: the file
    /// then says `solved: false`, keeps starts and goals, and has empty paths and null metrics.
    /// Paths are written as given (no trimming), so the file shows exactly what the planner made.
    /// A non-finite `runtime_ms` is written as 0 because JSON has no NaN/inf.
    pub fn new(
        map: &GridMap,
        map_file: &str,
        planner: &str,
        seed: u64,
        inst: &Instance,
        outcome: Option<(&Plan, Metrics)>,
        runtime_ms: f64,
    ) -> PlanFile {
        let cell = |v: VertexId| -> Cell {
            let (x, y) = map.cell(v);
            [x as i64, y as i64]
        };
        let agents = (0..inst.num_agents())
            .map(|i| AgentEntry {
                start: cell(inst.starts[i]),
                goal: cell(inst.goals[i]),
                path: outcome
                    .and_then(|(plan, _)| plan.paths.get(i))
                    .map(|p| p.iter().map(|&v| cell(v)).collect())
                    .unwrap_or_default(),
            })
            .collect();
        let runtime_ms = if runtime_ms.is_finite() {
            runtime_ms
        } else {
            0.0
        };
        let metrics = match outcome {
            Some((_, m)) => PlanMetrics {
                sum_of_costs: Some(m.sum_of_costs),
                makespan: Some(m.makespan),
                sum_of_moves: Some(m.sum_of_moves),
                runtime_ms,
            },
            None => PlanMetrics {
                runtime_ms,
                ..PlanMetrics::default()
            },
        };
        PlanFile {
            map_file: map_file.to_string(),
            planner: planner.to_string(),
            seed,
            solved: outcome.is_some(),
            goal_semantics: GoalSemantics::Stay,
            metrics,
            agents,
        }
    }

    /// JSON text with one agent per line and paths wrapped every [`CELLS_PER_LINE`] cells, so a
    /// person can read the file and diffs stay local. Strings and numbers go through serde_json,
    /// so the text is always valid JSON that [`PlanFile::parse`] reads back to the same value.
    pub fn to_json(&self) -> String {
        let mut s = String::new();
        s.push_str("{\n");
        let _ = writeln!(s, "  \"map_file\": {},", js(&self.map_file));
        let _ = writeln!(s, "  \"planner\": {},", js(&self.planner));
        let _ = writeln!(s, "  \"seed\": {},", self.seed);
        let _ = writeln!(s, "  \"solved\": {},", self.solved);
        let _ = writeln!(s, "  \"goal_semantics\": {},", js(&self.goal_semantics));
        let m = &self.metrics;
        let _ = writeln!(
            s,
            "  \"metrics\": {{\"sum_of_costs\": {}, \"makespan\": {}, \"sum_of_moves\": {}, \"runtime_ms\": {}}},",
            js(&m.sum_of_costs),
            js(&m.makespan),
            js(&m.sum_of_moves),
            js(&m.runtime_ms)
        );
        if self.agents.is_empty() {
            s.push_str("  \"agents\": []\n}\n");
            return s;
        }
        s.push_str("  \"agents\": [\n");
        for (i, a) in self.agents.iter().enumerate() {
            let _ = write!(
                s,
                "    {{\"start\": {}, \"goal\": {}, \"path\": [",
                cell_json(a.start),
                cell_json(a.goal)
            );
            for (t, &c) in a.path.iter().enumerate() {
                if t > 0 {
                    s.push(',');
                    if t % CELLS_PER_LINE == 0 {
                        s.push_str("\n      ");
                    } else {
                        s.push(' ');
                    }
                }
                s.push_str(&cell_json(c));
            }
            s.push_str("]}");
            s.push_str(if i + 1 < self.agents.len() {
                ",\n"
            } else {
                "\n"
            });
        }
        s.push_str("  ]\n}\n");
        s
    }

    /// Reads a JSON plan. Malformed JSON or a wrong shape becomes [`Error::Parse`] with serde's
    /// (1-based) line number; cells are only checked against a map by
    /// [`PlanFile::to_instance_and_plan`].
    pub fn parse(text: &str, path: &Path) -> Result<PlanFile> {
        serde_json::from_str(text).map_err(|e| Error::parse(path, e.line().max(1), e.to_string()))
    }

    /// Turns the file's cells into the instance and plan the validator judges.
    ///
    /// Errors are [`Error::Invalid`] (the file is well-formed JSON but its content does not fit
    /// `map`), each naming what is wrong:
    /// - the file says `solved: false` (it holds no plan);
    /// - a start, goal or path cell is off the map or a wall (naming agent, step and cell);
    /// - two agents share a start or a goal.
    ///
    /// Everything else (path starts elsewhere, jumps, conflicts, goal not reached, empty paths)
    /// is the validator's job, so it is reported in the validator's own terms.
    pub fn to_instance_and_plan(&self, map: &GridMap, path: &Path) -> Result<(Instance, Plan)> {
        if !self.solved {
            return Err(Error::invalid(
                path,
                "the file says solved=false: it holds no plan to validate",
            ));
        }
        let vertex = |c: Cell, what: &dyn Fn() -> String| -> Result<VertexId> {
            map.vertex_at(c[0], c[1]).ok_or_else(|| {
                Error::invalid(
                    path,
                    format!(
                        "{}: {}",
                        what(),
                        map.cell_problem(c[0], c[1]).unwrap_or_default()
                    ),
                )
            })
        };
        let mut starts = Vec::with_capacity(self.agents.len());
        let mut goals = Vec::with_capacity(self.agents.len());
        let mut paths = Vec::with_capacity(self.agents.len());
        let mut start_of: FxHashMap<VertexId, usize> = FxHashMap::default();
        let mut goal_of: FxHashMap<VertexId, usize> = FxHashMap::default();
        for (i, a) in self.agents.iter().enumerate() {
            let s = vertex(a.start, &|| format!("agent {i} start"))?;
            let g = vertex(a.goal, &|| format!("agent {i} goal"))?;
            if let Some(j) = start_of.insert(s, i) {
                return Err(Error::invalid(
                    path,
                    format!(
                        "agents {j} and {i} share the start ({},{})",
                        a.start[0], a.start[1]
                    ),
                ));
            }
            if let Some(j) = goal_of.insert(g, i) {
                return Err(Error::invalid(
                    path,
                    format!(
                        "agents {j} and {i} share the goal ({},{})",
                        a.goal[0], a.goal[1]
                    ),
                ));
            }
            let p = a
                .path
                .iter()
                .enumerate()
                .map(|(t, &c)| vertex(c, &|| format!("agent {i} path at t={t}")))
                .collect::<Result<Vec<_>>>()?;
            starts.push(s);
            goals.push(g);
            paths.push(p);
        }
        let inst = Instance::new(starts, goals).map_err(|msg| Error::invalid(path, msg))?;
        Ok((inst, Plan::new(paths)))
    }
}

/// How many cells of a path `to_json` puts on one line.
pub const CELLS_PER_LINE: usize = 16;

fn cell_json(c: Cell) -> String {
    format!("[{}, {}]", c[0], c[1])
}

/// One value formatted the way serde_json writes it (string escapes, `null`, float digits).
fn js<T: Serialize + ?Sized>(v: &T) -> String {
    serde_json::to_string(v).expect("plain values always serialize")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 4x3 map, one wall at (1,1):
    /// ```text
    /// ....
    /// .@..
    /// ....
    /// ```
    fn map() -> GridMap {
        GridMap::parse(
            "type octile\nheight 3\nwidth 4\nmap\n....\n.@..\n....\n",
            Path::new("m.map"),
        )
        .unwrap()
        .0
    }

    fn v(m: &GridMap, x: i64, y: i64) -> VertexId {
        m.vertex_at(x, y).unwrap()
    }

    fn sample() -> (GridMap, Instance, Plan, Metrics) {
        let m = map();
        let inst = Instance::new(
            vec![v(&m, 0, 0), v(&m, 3, 0)],
            vec![v(&m, 2, 0), v(&m, 0, 2)],
        )
        .unwrap();
        let plan = Plan::new(vec![
            vec![v(&m, 0, 0), v(&m, 1, 0), v(&m, 2, 0)],
            vec![
                v(&m, 3, 0),
                v(&m, 3, 1),
                v(&m, 3, 2),
                v(&m, 2, 2),
                v(&m, 1, 2),
                v(&m, 0, 2),
            ],
        ]);
        let metrics = plan.validate(m.graph(), &inst, Default::default()).unwrap();
        (m, inst, plan, metrics)
    }

    #[test]
    fn json_round_trip_gives_same_instance_and_plan() {
        let (m, inst, plan, metrics) = sample();
        let f = PlanFile::new(
            &m,
            "m.map",
            "test \"q\"",
            7,
            &inst,
            Some((&plan, metrics)),
            1.5,
        );
        let text = f.to_json();
        let back = PlanFile::parse(&text, Path::new("p.json")).unwrap();
        assert_eq!(back, f);
        // The hand-formatted text is the same JSON value serde would write.
        let a: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(a, serde_json::to_value(&f).unwrap());
        assert!(text.contains("\"goal_semantics\": \"stay\""), "{text}");
        assert!(text.contains("\"sum_of_costs\": 7"), "{text}");
        let (inst2, plan2) = back.to_instance_and_plan(&m, Path::new("p.json")).unwrap();
        assert_eq!(inst2, inst);
        assert_eq!(plan2, plan);
        assert_eq!(
            back.agents[1].path[..2],
            [[3, 0], [3, 1]],
            "x is the column, y the row"
        );
    }

    #[test]
    fn long_paths_wrap_and_still_parse() {
        let m = GridMap::parse("..\n", Path::new("a.map")).unwrap().0;
        let (a, b) = (v(&m, 0, 0), v(&m, 1, 0));
        let inst = Instance::new(vec![a], vec![b]).unwrap();
        let mut p = vec![a; 40];
        p.push(b);
        let plan = Plan::new(vec![p]);
        let metrics = plan.validate(m.graph(), &inst, Default::default()).unwrap();
        let f = PlanFile::new(&m, "a.map", "x", 0, &inst, Some((&plan, metrics)), 0.0);
        let text = f.to_json();
        assert!(text.lines().count() > 10, "{text}");
        assert!(text.lines().all(|l| l.len() < 200), "{text}");
        assert_eq!(PlanFile::parse(&text, Path::new("p")).unwrap(), f);
    }

    #[test]
    fn unsolved_file_has_null_metrics_and_holds_no_plan() {
        let (m, inst, _, _) = sample();
        let f = PlanFile::new(&m, "m.map", "none", 0, &inst, None, f64::NAN);
        let text = f.to_json();
        assert!(text.contains("\"solved\": false"));
        assert!(text.contains("\"sum_of_costs\": null"), "{text}");
        assert!(text.contains("\"runtime_ms\": 0.0"), "{text}");
        let back = PlanFile::parse(&text, Path::new("p.json")).unwrap();
        assert!(back.agents.iter().all(|a| a.path.is_empty()));
        assert_eq!(back.agents[1].goal, [0, 2]);
        let err = back
            .to_instance_and_plan(&m, Path::new("p.json"))
            .unwrap_err()
            .to_string();
        assert!(err.contains("no plan"), "{err}");
    }

    #[test]
    fn serde_errors_carry_the_line() {
        let text = "{\n  \"solved\": true,\n  \"agents\": [\n    {\"start\": [0, 0], \"goal\": 3}\n  ]\n}\n";
        match PlanFile::parse(text, Path::new("bad.json")).unwrap_err() {
            Error::Parse { line, path, .. } => {
                assert_eq!(line, 4);
                assert_eq!(path, Path::new("bad.json"));
            }
            e => panic!("unexpected {e}"),
        }
        assert!(matches!(
            PlanFile::parse("{\"solved\": tru", Path::new("x")),
            Err(Error::Parse { line: 1, .. })
        ));
    }

    #[test]
    fn minimal_hand_written_file_is_accepted() {
        let m = map();
        let text = r#"{"solved": true, "agents": [{"start": [0,0], "goal": [0,1], "path": [[0,0],[0,1]]}]}"#;
        let f = PlanFile::parse(text, Path::new("h.json")).unwrap();
        assert_eq!(f.goal_semantics, GoalSemantics::Stay);
        assert_eq!(f.metrics.sum_of_costs, None);
        let (inst, plan) = f.to_instance_and_plan(&m, Path::new("h.json")).unwrap();
        let metrics = plan.validate(m.graph(), &inst, Default::default()).unwrap();
        assert_eq!(metrics.sum_of_costs, 1);
    }

    fn convert_err(text: &str) -> String {
        let m = map();
        PlanFile::parse(text, Path::new("e.json"))
            .unwrap()
            .to_instance_and_plan(&m, Path::new("e.json"))
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn bad_cells_name_agent_step_and_cell() {
        let wall = convert_err(
            r#"{"solved": true, "agents": [
                {"start": [0,0], "goal": [0,2], "path": [[0,0]]},
                {"start": [3,0], "goal": [2,1], "path": [[3,0],[2,0],[1,0],[1,1],[1,2]]}]}"#,
        );
        assert!(wall.starts_with("e.json: "), "{wall}");
        assert!(wall.contains("agent 1 path at t=3"), "{wall}");
        assert!(wall.contains("(1,1) is a wall"), "{wall}");

        let off = convert_err(
            r#"{"solved": true, "agents": [{"start": [0,0], "goal": [-1,2], "path": []}]}"#,
        );
        assert!(off.contains("agent 0 goal"), "{off}");
        assert!(off.contains("(-1,2) is off the 4x3 map"), "{off}");

        let start_wall = convert_err(
            r#"{"solved": true, "agents": [{"start": [1,1], "goal": [0,0], "path": []}]}"#,
        );
        assert!(start_wall.contains("agent 0 start"), "{start_wall}");
    }

    #[test]
    fn shared_start_or_goal_is_rejected() {
        let s = convert_err(
            r#"{"solved": true, "agents": [
                {"start": [0,0], "goal": [0,2], "path": [[0,0]]},
                {"start": [0,0], "goal": [3,2], "path": [[0,0]]}]}"#,
        );
        assert!(s.contains("agents 0 and 1 share the start (0,0)"), "{s}");
        let g = convert_err(
            r#"{"solved": true, "agents": [
                {"start": [0,0], "goal": [3,2], "path": [[0,0]]},
                {"start": [0,2], "goal": [3,2], "path": [[0,2]]}]}"#,
        );
        assert!(g.contains("agents 0 and 1 share the goal (3,2)"), "{g}");
    }
}
