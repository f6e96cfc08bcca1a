//! Grid plans in the plan envelope ([`mrpp_core::envelope`]): path elements are `[x, y]` cells
//! (x = column, y = row, from 0 at the top-left), the world is the map file (`grid-map`).
//!
//! Files written before the envelope (`map_file`, `goal_semantics`, `runtime_ms` inside
//! `metrics`) read as they are. Cells are stored as signed integers so that a file naming a cell
//! off the map (e.g. `[-1, 3]`) parses and then fails with a message naming the agent, step and
//! cell, instead of a bare serde type error.

use std::path::Path;

use mrpp_core::envelope::{Envelope, World};
use mrpp_core::error::Result;
use mrpp_core::mapf::plan_file::{
    RunInfo, mapf_envelope, mapf_plan, mapf_plan_to_draw, mapf_rules,
};
use mrpp_core::{MapfProblem, Plan, Rules, Solved, Unsolved};

use crate::map::GridMap;

/// A grid cell `[x, y]`.
pub type Cell = [i64; 2];

/// The kind of world file grid plans name.
pub const WORLD_KIND: &str = "grid-map";

/// The envelope of one run on a grid problem; `map_file` names the map as it was given.
pub fn grid_envelope(
    map: &GridMap,
    map_file: &str,
    problem: &MapfProblem,
    mut info: RunInfo,
    outcome: &std::result::Result<Solved<MapfProblem>, Unsolved>,
) -> Envelope<Cell> {
    info.family = crate::FAMILY.into();
    info.world = World {
        kind: WORLD_KIND.into(),
        file: map_file.into(),
    };
    mapf_envelope(problem, info, outcome, |v| {
        let (x, y) = map.cell(v);
        [i64::from(x), i64::from(y)]
    })
}

/// Reads a grid plan file against `map`: the problem it describes (its starts and goals, its
/// rules; `stay` when not recorded), its plan, and the envelope (for its claims). Errors name
/// `path`: malformed JSON (with its line), `solved: false`, a cell off the map or on a wall
/// (naming agent, step and cell), shared starts or goals.
pub fn read_grid_plan(
    map: &GridMap,
    text: &str,
    path: &Path,
) -> Result<(MapfProblem, Plan, Envelope<Cell>)> {
    read(map, text, path, true)
}

/// As [`read_grid_plan`], but a file that says `solved: false` is read as its agents standing
/// on their starts (for pictures of an unsolved instance; `mapf_plan_to_draw`).
///
/// # Errors
/// As [`read_grid_plan`], except for `solved: false`.
pub fn read_grid_plan_to_draw(
    map: &GridMap,
    text: &str,
    path: &Path,
) -> Result<(MapfProblem, Plan, Envelope<Cell>)> {
    read(map, text, path, false)
}

fn read(
    map: &GridMap,
    text: &str,
    path: &Path,
    solved_only: bool,
) -> Result<(MapfProblem, Plan, Envelope<Cell>)> {
    mrpp_core::envelope::check_family(text, crate::FAMILY, path)?;
    let env: Envelope<Cell> = Envelope::parse(text, path)?;
    if env.agents.is_empty() {
        return Err(mrpp_core::Error::invalid(path, "the plan has no agents"));
    }
    let rules = mapf_rules(&env, Rules::default(), path)?;
    let vertex = |c: &Cell| {
        map.vertex_at(c[0], c[1])
            .ok_or_else(|| map.cell_problem(c[0], c[1]).unwrap_or_default())
    };
    let label = |c: &Cell| format!("({},{})", c[0], c[1]);
    let (inst, plan) = if solved_only {
        mapf_plan(&env, vertex, label, path)?
    } else {
        mapf_plan_to_draw(&env, vertex, label, path)?
    };
    let problem = MapfProblem::new(map.graph_arc().clone(), inst, rules)
        .expect("cells were mapped to the map's vertices");
    Ok((problem, plan, env))
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrpp_core::{Ctx, Instance, Problem as _, VertexId, accept};
    use std::time::Duration;

    fn map() -> GridMap {
        GridMap::parse("....\n.#..\n....", Path::new("m.txt"))
            .unwrap()
            .0
    }

    fn v(m: &GridMap, x: i64, y: i64) -> VertexId {
        m.vertex_at(x, y).unwrap()
    }

    fn solved(m: &GridMap) -> (MapfProblem, Solved<MapfProblem>) {
        let inst =
            Instance::new(vec![v(m, 0, 0), v(m, 3, 2)], vec![v(m, 3, 0), v(m, 0, 2)]).unwrap();
        let problem = crate::problem_on(m, inst);
        let row0: Vec<VertexId> = (0..4).map(|x| v(m, x, 0)).collect();
        let row2: Vec<VertexId> = (0..4).rev().map(|x| v(m, x, 2)).collect();
        let s = accept(
            &problem,
            Plan::new(vec![row0, row2]),
            "hand",
            Duration::ZERO,
        )
        .unwrap();
        (problem, s)
    }

    #[test]
    fn round_trip_gives_same_problem_and_plan() {
        let m = map();
        let (problem, s) = solved(&m);
        let info = RunInfo {
            planner: "hand".into(),
            seed: 4,
            ..RunInfo::default()
        };
        let text = grid_envelope(&m, "m.txt", &problem, info, &Ok(s.clone())).to_json();
        assert!(text.contains("\"family\": \"grid\""), "{text}");
        assert!(text.contains("\"sum_of_costs\": 6"), "{text}");
        let (p2, plan2, env) = read_grid_plan(&m, &text, Path::new("p.json")).unwrap();
        assert_eq!(p2.instance(), problem.instance());
        assert_eq!(plan2, s.plan);
        assert_eq!(env.seed, 4);
        assert!(
            env.disputed_metrics(&serde_json::to_value(s.metrics).unwrap())
                .is_empty()
        );
        assert_eq!(p2.validate(&plan2).unwrap(), s.metrics);
    }

    #[test]
    fn unsolved_file_keeps_the_task_and_holds_no_plan() {
        let m = map();
        let (problem, _) = solved(&m);
        let text = grid_envelope(
            &m,
            "m.txt",
            &problem,
            RunInfo::default(),
            &Err(Unsolved::TimeLimit),
        )
        .to_json();
        assert!(
            text.contains("\"solved\": false") && text.contains("\"status\": \"time_limit\""),
            "{text}"
        );
        let err = read_grid_plan(&m, &text, Path::new("u.json"))
            .unwrap_err()
            .to_string();
        assert!(err.contains("no plan"), "{err}");
    }

    #[test]
    fn legacy_file_and_bad_cells() {
        let m = map();
        let legacy = r#"{"map_file": "m.txt", "planner": "x", "seed": 0, "solved": true, "goal_semantics": "stay",
            "metrics": {"sum_of_costs": 1, "makespan": 1, "sum_of_moves": 1, "runtime_ms": 0.1},
            "agents": [{"start": [0, 0], "goal": [1, 0], "path": [[0, 0], [1, 0]]}]}"#;
        let (p, plan, _) = read_grid_plan(&m, legacy, Path::new("l.json")).unwrap();
        assert_eq!(p.validate(&plan).unwrap().sum_of_costs, 1);
        let wall = legacy.replace("[[0, 0], [1, 0]]", "[[0, 0], [1, 1]]");
        let e = read_grid_plan(&m, &wall, Path::new("w.json"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("w.json: agent 0 path at t=1") && e.contains("wall"),
            "{e}"
        );
        let shared = r#"{"solved": true, "agents": [{"start": [0, 0], "goal": [1, 0]}, {"start": [0, 0], "goal": [2, 0]}]}"#;
        let e = read_grid_plan(&m, shared, Path::new("s.json"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("agents 0 and 1 share the start (0,0)"), "{e}");
        let _ = Ctx::default();
    }
}
