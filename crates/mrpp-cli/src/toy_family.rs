//! A toy family that exists only in tests, to show (and keep true) that a new family is its own
//! module plus one line in [`crate::family::FAMILIES`]: agents on a line of cells, one problem
//! type, one validator, one planner, its own world file (`--line-world`, JSON
//! `{"length": L, "agents": [[start, goal], ...]}`) and the plan envelope with integer cells.
//!
//! It also holds the test-only "broken" planners of the grid and tree families, which return a
//! colliding plan, so that `mrpp solve` is seen to refuse an invalid plan with exit 1.

use std::path::Path;
use std::time::Duration;

use serde::Serialize;

use mrpp_core::envelope::{AgentPath, Envelope, FORMAT, World};
use mrpp_core::{Ctx, MapfProblem, Plan, Planner, PlannerEntry, Problem, Unsolved};

use crate::family::{Def, Format, Inputs, Loaded, ReadPlan};
use crate::output::{Fail, file_name};

/// Agents on cells `0..length` of a line; a step moves an agent by one cell or keeps it.
pub(crate) struct Line {
    length: i64,
    starts: Vec<i64>,
    goals: Vec<i64>,
}

#[derive(Clone, Copy, Serialize)]
pub(crate) struct LineMetrics {
    makespan: u64,
}

impl Problem for Line {
    type Plan = Vec<Vec<i64>>;
    type Metrics = LineMetrics;
    type Violation = String;
    fn num_agents(&self) -> usize {
        self.starts.len()
    }
    fn validate(&self, plan: &Vec<Vec<i64>>) -> Result<LineMetrics, String> {
        if plan.len() != self.starts.len() {
            return Err("wrong agent count".into());
        }
        let horizon = plan.iter().map(Vec::len).max().unwrap_or(0);
        let at = |i: usize, t: usize| plan[i][t.min(plan[i].len() - 1)];
        for (i, p) in plan.iter().enumerate() {
            if p.first() != Some(&self.starts[i]) || p.last() != Some(&self.goals[i]) {
                return Err(format!("agent {i} does not go from its start to its goal"));
            }
            if p.iter().any(|c| !(0..self.length).contains(c))
                || p.windows(2).any(|w| (w[0] - w[1]).abs() > 1)
            {
                return Err(format!("agent {i} leaves the line or jumps"));
            }
        }
        for t in 0..horizon {
            for i in 0..plan.len() {
                for j in i + 1..plan.len() {
                    let swap = t > 0 && at(i, t) == at(j, t - 1) && at(j, t) == at(i, t - 1);
                    if at(i, t) == at(j, t) || swap {
                        return Err(format!("agents {i} and {j} collide at t={t}"));
                    }
                }
            }
        }
        Ok(LineMetrics {
            makespan: horizon.saturating_sub(1) as u64,
        })
    }
}

/// Moves every agent one cell toward its goal when that cell is free, in id order.
struct Walk;

impl Planner<Line> for Walk {
    fn name(&self) -> &str {
        "line-walk"
    }
    fn plan(&self, p: &Line, ctx: &Ctx) -> Result<Vec<Vec<i64>>, Unsolved> {
        let mut paths: Vec<Vec<i64>> = p.starts.iter().map(|&s| vec![s]).collect();
        for _ in 0..(p.length * p.starts.len() as i64) {
            if ctx.deadline.expired() {
                return Err(Unsolved::TimeLimit);
            }
            let mut now: Vec<i64> = paths.iter().map(|q| *q.last().unwrap()).collect();
            for i in 0..now.len() {
                let next = now[i] + (p.goals[i] - now[i]).signum();
                if !now.contains(&next) {
                    now[i] = next;
                }
            }
            paths.iter_mut().zip(&now).for_each(|(q, &c)| q.push(c));
            if now == p.goals {
                return Ok(paths);
            }
        }
        Err(Unsolved::GaveUp("agents block each other".into()))
    }
}

static LINE_PLANNERS: &[PlannerEntry<Line>] = &[PlannerEntry {
    name: "line-walk",
    about: "test family: agents walk toward their goals on a line",
    params: &[],
    build: |_| Ok(Box::new(Walk)),
}];

#[derive(serde::Deserialize)]
struct LineFile {
    length: i64,
    agents: Vec<[i64; 2]>,
}

fn load_line(inputs: &Inputs) -> Result<(Line, String), Fail> {
    let path = inputs
        .line_world
        .as_deref()
        .ok_or_else(|| Fail("line problems need --line-world".into()))?;
    let text = mrpp_core::error::read_file(path)?;
    let f: LineFile =
        serde_json::from_str(&text).map_err(|e| Fail(format!("{}: {e}", path.display())))?;
    let line = Line {
        length: f.length,
        starts: f.agents.iter().map(|a| a[0]).collect(),
        goals: f.agents.iter().map(|a| a[1]).collect(),
    };
    Ok((line, file_name(path)))
}

/// The toy family: the one line the family table needs points here.
pub(crate) static TOY: Def<Line> = Def {
    name: "line",
    planners: LINE_PLANNERS,
    claims: |i| i.line_world.is_some(),
    load: |inputs| {
        let (problem, file) = load_line(inputs)?;
        Ok(Loaded {
            summary: format!("world {file} | agents {}", problem.num_agents()),
            problem,
            write: Box::new(move |p: &Line, info, outcome, _, _: Format| {
                let plan = outcome.as_ref().ok();
                let env = Envelope {
                    format: FORMAT.into(),
                    family: "line".into(),
                    world: World {
                        kind: "line".into(),
                        file: file.clone(),
                    },
                    planner: info.planner,
                    params: info.params,
                    seed: info.seed,
                    solved: plan.is_some(),
                    status: String::new(),
                    rules: serde_json::Value::Null,
                    metrics: plan
                        .map(|s| crate::output::metrics_object(&s.metrics))
                        .unwrap_or_default(),
                    runtime_ms: info.runtime_ms,
                    agents: (0..p.num_agents())
                        .map(|i| AgentPath {
                            start: p.starts[i],
                            goal: p.goals[i],
                            path: plan.map(|s| s.plan[i].clone()).unwrap_or_default(),
                        })
                        .collect(),
                    extra: Default::default(),
                };
                Ok(env.to_json())
            }),
        })
    },
    read_plan: |inputs, path| {
        let (problem, _) = load_line(inputs)?;
        let env: Envelope<i64> = Envelope::parse(&mrpp_core::error::read_file(path)?, path)?;
        Ok(ReadPlan {
            problem,
            plan: env.agents.iter().map(|a| a.path.clone()).collect(),
            claims: env.metrics,
            about: String::new(),
        })
    },
    info: None,
    render: None,
    scene: None,
    lacam: false,
};

/// A planner that sends every agent straight to its goal, ignoring the others: on any instance
/// where two paths cross, its plan collides. Registered in test-only copies of the grid and tree
/// families below.
struct Broken;

impl Planner<MapfProblem> for Broken {
    fn name(&self) -> &str {
        "broken"
    }
    fn plan(&self, p: &MapfProblem, _: &Ctx) -> Result<Plan, Unsolved> {
        let inst = p.instance();
        let paths = (0..inst.num_agents())
            .map(|i| {
                let d = mrpp_core::mapf::search::distance::bfs_distances(p.graph(), inst.goals[i]);
                mrpp_core::mapf::search::distance::descend(p.graph(), &d, inst.starts[i])
            })
            .collect();
        Ok(Plan::new(paths))
    }
}

static BROKEN_GRID_PLANNERS: &[PlannerEntry<MapfProblem>] = &[PlannerEntry {
    name: "broken-grid",
    about: "test only: independent shortest paths, collisions and all",
    params: &[],
    build: |_| Ok(Box::new(Broken)),
}];

static BROKEN_TREE_PLANNERS: &[PlannerEntry<MapfProblem>] = &[PlannerEntry {
    name: "broken-trees",
    about: "test only: independent shortest paths, collisions and all",
    params: &[],
    build: |_| Ok(Box::new(Broken)),
}];

/// The grid family with only the broken planner.
pub(crate) static BROKEN_GRID: Def<MapfProblem> = Def {
    planners: BROKEN_GRID_PLANNERS,
    ..crate::grid_family::def()
};

/// The tree family with only the broken planner.
pub(crate) static BROKEN_TREES: Def<MapfProblem> = Def {
    planners: BROKEN_TREE_PLANNERS,
    ..crate::tree_family::def()
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::family::{SolveRequest, list_planners};
    use crate::verbs;

    fn tmp(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("mrpp-toy-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    fn request(inputs: Inputs, planner: &str, out: Option<std::path::PathBuf>) -> SolveRequest {
        SolveRequest {
            inputs,
            planner: planner.into(),
            params: Vec::new(),
            seed: 0,
            time_limit: 10.0,
            out,
            format: Format::Json,
            save_program: None,
            command: "solve",
        }
    }

    #[test]
    fn a_toy_family_gets_solve_validate_and_planners_from_the_table() {
        let world = tmp("w.json");
        std::fs::write(&world, r#"{"length": 6, "agents": [[0, 3], [1, 5]]}"#).unwrap();
        let inputs = Inputs {
            line_world: Some(world),
            ..Inputs::default()
        };
        let out = tmp("plan.json");
        let _ = std::fs::remove_file(&out);
        let code = verbs::solve(&request(inputs.clone(), "line-walk", Some(out.clone())));
        assert!(matches!(code, Ok(0)));
        let text = std::fs::read_to_string(&out).unwrap();
        assert!(
            text.contains("\"family\": \"line\"") && text.contains("\"makespan\": 4"),
            "{text}"
        );
        assert!(matches!(verbs::validate(&inputs, &out), Ok(0)));
        let forged = text.replace("\"makespan\": 4", "\"makespan\": 2");
        std::fs::write(&out, forged).unwrap();
        let Err(Fail(e)) = verbs::validate(&inputs, &out) else {
            panic!("forged claim accepted")
        };
        assert!(e.contains("claims makespan 2"), "{e}");
        assert!(matches!(list_planners(Some("line")), Ok(0)));
        let _ = Duration::ZERO;
    }

    #[test]
    fn an_invalid_plan_is_an_error_for_grid_and_tree_problems() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data");
        let grid = Inputs {
            map: Some(root.join("movingai/random-32-32-20.map")),
            scen: Some(root.join("movingai/random-32-32-20-random-1.scen")),
            ..Inputs::default()
        };
        let trees = Inputs {
            instance: Some(root.join("trees/example.json")),
            ..Inputs::default()
        };
        for (inputs, planner) in [(grid, "broken-grid"), (trees, "broken-trees")] {
            let out = tmp(&format!("{planner}.json"));
            let _ = std::fs::remove_file(&out);
            let Err(Fail(e)) = verbs::solve(&request(inputs, planner, Some(out.clone()))) else {
                panic!("{planner}: a colliding plan was accepted")
            };
            assert!(
                e.contains("invalid plan") && e.contains("conflict"),
                "{planner}: {e}"
            );
            assert!(!out.exists(), "{planner}: a plan file was written");
        }
    }
}
