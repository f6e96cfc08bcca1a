//! The JSON plan of a single-lane tree problem: what `mrpp trees solve` / `trees run` write and
//! `mrpp trees validate` reads back. The grid plan's shape ([`super::plan_json`]) with node ids
//! instead of cells:
//!
//! ```json
//! {"instance_file": "i.json", "planner": "gp", "seed": 0, "program": "(if-robot-is-solved stay move-toward-objective)",
//!  "solved": true, "goal_semantics": "visit", "allow_following": true,
//!  "metrics": {"sum_of_costs": 5, "makespan": 3, "sum_of_moves": 4, "time_steps": 3, "runtime_ms": 0.4},
//!  "agents": [{"start": 3, "goal": 1, "path": [3, 2, 1]}]}
//! ```
//!
//! `time_steps` is the paper's τ (steps until every robot has visited its goal), which under
//! `visit` semantics equals the makespan; it is stored anyway because the paper's tables count it.
//! `program` is only present for GP plans (the S-expression on one line, so the file alone says
//! which program made it). `allow_following` records the rule the plan was made under, so that a
//! plan made without following is also validated without it. Missing keys in hand-written files
//! mean: `visit`, following allowed, metrics not reported. Other keys are ignored.
//!
//! Node ids are stored unsigned, so a negative id is a serde error with its line; ids beyond the
//! tree are caught by [`TreePlanFile::to_plan`], naming agent, step and node.

use std::fmt::Write as _;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::graph::VertexId;
use crate::instance::Instance;
use crate::plan::{GoalSemantics, Metrics, Plan};

/// The whole tree plan file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TreePlanFile {
    /// The instance file the plan was made for, as given to the planner (informative only).
    #[serde(default)]
    pub instance_file: String,
    #[serde(default)]
    pub planner: String,
    #[serde(default)]
    pub seed: u64,
    /// The GP program that made the plan (one-line S-expression); absent for other planners.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub program: Option<String>,
    pub solved: bool,
    /// Tree plans are judged with `visit` semantics, the default when the key is missing.
    #[serde(default = "visit")]
    pub goal_semantics: GoalSemantics,
    /// Whether the plan was made with following allowed (the default when the key is missing).
    #[serde(default = "yes")]
    pub allow_following: bool,
    #[serde(default)]
    pub metrics: TreePlanMetrics,
    pub agents: Vec<TreeAgentEntry>,
}

fn visit() -> GoalSemantics {
    GoalSemantics::Visit
}

fn yes() -> bool {
    true
}

/// Quality of the plan as the planner reported it; the counts are `null` when nothing was solved.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct TreePlanMetrics {
    pub sum_of_costs: Option<u64>,
    pub makespan: Option<u64>,
    pub sum_of_moves: Option<u64>,
    /// The paper's τ: the step at which every robot has visited its goal (= makespan).
    #[serde(default)]
    pub time_steps: Option<u64>,
    #[serde(default)]
    pub runtime_ms: f64,
}

/// One robot: its task and its path of node ids (empty when unsolved).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct TreeAgentEntry {
    pub start: u64,
    pub goal: u64,
    #[serde(default)]
    pub path: Vec<u64>,
}

/// How many node ids of a path `to_json` puts on one line.
pub const NODES_PER_LINE: usize = 24;

impl TreePlanFile {
    /// Describes one run on `inst`. `outcome` is `None` when no plan was found: the file then says
    /// `solved: false`, keeps starts and goals, and has empty paths and null metrics. The
    /// descriptive fields (`instance_file`, `planner`, `seed`, `program`, `allow_following`) are
    /// left at their defaults for the caller to fill in. A non-finite `runtime_ms` becomes 0
    /// (JSON has no NaN/inf).
    pub fn new(inst: &Instance, outcome: Option<(&Plan, Metrics)>, runtime_ms: f64) -> Self {
        let agents = (0..inst.num_agents())
            .map(|i| TreeAgentEntry {
                start: u64::from(inst.starts[i]),
                goal: u64::from(inst.goals[i]),
                path: outcome
                    .and_then(|(plan, _)| plan.paths.get(i))
                    .map(|p| p.iter().map(|&v| u64::from(v)).collect())
                    .unwrap_or_default(),
            })
            .collect();
        let runtime_ms = if runtime_ms.is_finite() {
            runtime_ms
        } else {
            0.0
        };
        let metrics = match outcome {
            Some((_, m)) => TreePlanMetrics {
                sum_of_costs: Some(m.sum_of_costs),
                makespan: Some(m.makespan),
                sum_of_moves: Some(m.sum_of_moves),
                time_steps: Some(m.makespan),
                runtime_ms,
            },
            None => TreePlanMetrics {
                runtime_ms,
                ..TreePlanMetrics::default()
            },
        };
        TreePlanFile {
            instance_file: String::new(),
            planner: String::new(),
            seed: 0,
            program: None,
            solved: outcome.is_some(),
            goal_semantics: GoalSemantics::Visit,
            allow_following: true,
            metrics,
            agents,
        }
    }

    /// JSON text with one agent per line and paths wrapped every [`NODES_PER_LINE`] ids, so that
    /// a person can read the file and diffs stay local. Strings and numbers go through serde_json,
    /// so [`TreePlanFile::parse`] reads the text back to the same value.
    pub fn to_json(&self) -> String {
        let mut s = String::from("{\n");
        let _ = writeln!(s, "  \"instance_file\": {},", js(&self.instance_file));
        let _ = writeln!(s, "  \"planner\": {},", js(&self.planner));
        let _ = writeln!(s, "  \"seed\": {},", self.seed);
        if let Some(p) = &self.program {
            let _ = writeln!(s, "  \"program\": {},", js(p));
        }
        let _ = writeln!(s, "  \"solved\": {},", self.solved);
        let _ = writeln!(s, "  \"goal_semantics\": {},", js(&self.goal_semantics));
        let _ = writeln!(s, "  \"allow_following\": {},", self.allow_following);
        let m = &self.metrics;
        let _ = writeln!(
            s,
            "  \"metrics\": {{\"sum_of_costs\": {}, \"makespan\": {}, \"sum_of_moves\": {}, \"time_steps\": {}, \"runtime_ms\": {}}},",
            js(&m.sum_of_costs),
            js(&m.makespan),
            js(&m.sum_of_moves),
            js(&m.time_steps),
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
                a.start, a.goal
            );
            for (t, v) in a.path.iter().enumerate() {
                if t > 0 {
                    s.push_str(if t % NODES_PER_LINE == 0 {
                        ",\n      "
                    } else {
                        ", "
                    });
                }
                let _ = write!(s, "{v}");
            }
            s.push_str(if i + 1 < self.agents.len() {
                "]},\n"
            } else {
                "]}\n"
            });
        }
        s.push_str("  ]\n}\n");
        s
    }

    /// Reads a tree plan. Malformed JSON or a wrong shape becomes [`Error::Parse`] naming `path`
    /// and serde's (1-based) line.
    pub fn parse(text: &str, path: &Path) -> Result<TreePlanFile> {
        serde_json::from_str(text).map_err(|e| {
            Error::parse(
                path,
                e.line().max(1),
                format!("not a tree plan: {}", without_position(&e)),
            )
        })
    }

    /// Reads a tree plan file.
    pub fn load(path: &Path) -> Result<TreePlanFile> {
        let text = crate::error::read_file(path)?;
        TreePlanFile::parse(&text, path)
    }

    /// The plan the validator judges, after checking what only the file can get wrong against
    /// the instance `inst` on a tree of `nodes` nodes ([`Error::Invalid`] naming `path`):
    /// - the file says `solved: false` (it holds no plan) or a goal semantics other than `visit`;
    /// - it has a different number of robots, or a robot with another start or goal;
    /// - a path names a node that is not on the tree (naming robot, step and node).
    ///
    /// Everything else (a path that starts elsewhere, jumps, conflicts, a goal never visited) is
    /// the validator's job, so it is reported in the validator's own terms.
    pub fn to_plan(&self, inst: &Instance, nodes: usize, path: &Path) -> Result<Plan> {
        let bad = |msg: String| Err(Error::invalid(path, msg));
        if !self.solved {
            return bad("the file says solved=false: it holds no plan to validate".into());
        }
        if self.goal_semantics != GoalSemantics::Visit {
            return bad(format!(
                "goal_semantics is {}, but tree plans use \"visit\"",
                js(&self.goal_semantics)
            ));
        }
        if self.agents.len() != inst.num_agents() {
            return bad(format!(
                "the plan has {} robots but the instance has {}",
                self.agents.len(),
                inst.num_agents()
            ));
        }
        let mut paths = Vec::with_capacity(self.agents.len());
        for (i, a) in self.agents.iter().enumerate() {
            for (what, claim, real) in [
                ("start", a.start, inst.starts[i]),
                ("goal", a.goal, inst.goals[i]),
            ] {
                if claim != u64::from(real) {
                    return bad(format!(
                        "robot {i} has {what} {claim} but the instance says {real}"
                    ));
                }
            }
            let mut p = Vec::with_capacity(a.path.len());
            for (t, &v) in a.path.iter().enumerate() {
                if v >= nodes as u64 {
                    return bad(format!(
                        "robot {i} at t={t} is on node {v}, which is not on the tree (nodes are 0..{})",
                        nodes.saturating_sub(1)
                    ));
                }
                p.push(v as VertexId);
            }
            paths.push(p);
        }
        Ok(Plan::new(paths))
    }
}

/// One value formatted the way serde_json writes it.
fn js<T: Serialize + ?Sized>(v: &T) -> String {
    serde_json::to_string(v).expect("plain values always serialize")
}

/// serde's message without its " at line L column C" suffix (the line is reported separately).
fn without_position(e: &serde_json::Error) -> String {
    let msg = e.to_string();
    match msg.rfind(" at line ") {
        Some(i) => msg[..i].to_string(),
        None => msg,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph::Graph;
    use crate::plan::ValidateOptions;

    /// The T-tree: 0 - 1 - 2, 1 - 3; robot 0 goes 2 → 3, robot 1 goes 3 → 0.
    fn sample() -> (Graph, Instance, Plan, Metrics) {
        let g = Graph::from_edges(4, &[(0, 1), (1, 2), (1, 3)]);
        let inst = Instance::new(vec![2, 3], vec![3, 0]).unwrap();
        let plan = Plan::new(vec![vec![2, 2, 1, 3], vec![3, 1, 0]]);
        let opts = ValidateOptions {
            semantics: GoalSemantics::Visit,
            allow_following: true,
        };
        let m = plan.validate(&g, &inst, opts).unwrap();
        (g, inst, plan, m)
    }

    #[test]
    fn round_trip_gives_same_file_and_plan() {
        let (_, inst, plan, m) = sample();
        let mut f = TreePlanFile::new(&inst, Some((&plan, m)), 1.5);
        f.instance_file = "t \"q\".json".into();
        f.planner = "gp".into();
        f.seed = 7;
        f.program = Some("(if-robot-is-solved stay move-toward-objective)".into());
        let text = f.to_json();
        let back = TreePlanFile::parse(&text, Path::new("p.json")).unwrap();
        assert_eq!(back, f);
        // The hand-formatted text is the JSON value serde would write.
        let a: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(a, serde_json::to_value(&f).unwrap());
        assert!(text.contains("\"goal_semantics\": \"visit\""), "{text}");
        assert!(text.contains("\"time_steps\": 3"), "{text}");
        assert_eq!(back.to_plan(&inst, 4, Path::new("p.json")).unwrap(), plan);
    }

    #[test]
    fn long_paths_wrap_and_unsolved_files_hold_no_plan() {
        let inst = Instance::new(vec![0], vec![1]).unwrap();
        let mut p = vec![0; 60];
        p.push(1);
        let plan = Plan::new(vec![p]);
        let m = Metrics {
            sum_of_costs: 60,
            makespan: 60,
            sum_of_moves: 1,
        };
        let f = TreePlanFile::new(&inst, Some((&plan, m)), 0.0);
        let text = f.to_json();
        assert!(text.lines().count() > 12 && text.lines().all(|l| l.len() < 200));
        assert_eq!(TreePlanFile::parse(&text, Path::new("p")).unwrap(), f);

        let none = TreePlanFile::new(&inst, None, f64::NAN);
        let text = none.to_json();
        assert!(text.contains("\"solved\": false") && text.contains("\"makespan\": null"));
        assert!(!text.contains("program"), "{text}");
        let back = TreePlanFile::parse(&text, Path::new("u.json")).unwrap();
        assert_eq!(back.agents[0].goal, 1);
        let e = back
            .to_plan(&inst, 2, Path::new("u.json"))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("u.json: ") && e.contains("no plan"), "{e}");
    }

    #[test]
    fn minimal_hand_written_file_defaults_to_visit_with_following() {
        let text = r#"{"solved": true, "agents": [{"start": 2, "goal": 3, "path": [2, 2, 2, 1, 3]},
            {"start": 3, "goal": 0, "path": [3, 1, 0]}]}"#;
        let f = TreePlanFile::parse(text, Path::new("h.json")).unwrap();
        assert_eq!(f.goal_semantics, GoalSemantics::Visit);
        assert!(f.allow_following && f.program.is_none());
        assert_eq!(f.metrics.time_steps, None);
        let (g, inst, _, _) = sample();
        let plan = f.to_plan(&inst, 4, Path::new("h.json")).unwrap();
        let m = crate::trees::validate_tree_plan(&g, &inst, &plan, true).unwrap();
        assert_eq!(m.makespan, 4);
    }

    #[test]
    fn bad_files_name_the_file_and_line() {
        let cases = [
            ("{\"solved\": tru", "b.json:1:"),
            (
                "{\n\"solved\": true,\n\"agents\": [\n{\"start\": -1, \"goal\": 0}\n]}",
                "b.json:4:",
            ),
            ("{\n\"agents\": []\n}", "b.json:3:"),
            ("[1, 2]", "b.json:1:"),
        ];
        for (text, prefix) in cases {
            let e = TreePlanFile::parse(text, Path::new("b.json"))
                .unwrap_err()
                .to_string();
            assert!(
                e.starts_with(prefix) && e.contains("not a tree plan"),
                "{e}"
            );
            assert!(!e.contains(" at line "), "{e}");
        }
        let e = TreePlanFile::load(Path::new("/nonexistent/x.json"))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("/nonexistent/x.json: "), "{e}");
    }

    #[test]
    fn content_that_does_not_fit_the_instance_is_named() {
        let (_, inst, _, _) = sample();
        let err = |text: &str| {
            TreePlanFile::parse(text, Path::new("c.json"))
                .unwrap()
                .to_plan(&inst, 4, Path::new("c.json"))
                .unwrap_err()
                .to_string()
        };
        let two = |a: &str| {
            format!(
                r#"{{"solved": true, "agents": [{a}, {{"start": 3, "goal": 0, "path": [3]}}]}}"#
            )
        };
        let e = err(&two(r#"{"start": 2, "goal": 3, "path": [2, 1, 9]}"#));
        assert!(
            e.contains("robot 0 at t=2 is on node 9, which is not on the tree"),
            "{e}"
        );
        let e = err(&two(r#"{"start": 1, "goal": 3, "path": [1]}"#));
        assert!(
            e.contains("robot 0 has start 1 but the instance says 2"),
            "{e}"
        );
        let e = err(r#"{"solved": true, "agents": []}"#);
        assert!(e.contains("0 robots but the instance has 2"), "{e}");
        let e = err(r#"{"solved": true, "goal_semantics": "stay", "agents": []}"#);
        assert!(e.contains("tree plans use \"visit\""), "{e}");
    }
}
