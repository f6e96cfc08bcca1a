//! Tree plans in the plan envelope ([`mrpp_core::envelope`]): path elements are node ids, the
//! world is the tree instance file (`tree-instance`), the rules are `visit` with following as the
//! run had it. A GP plan also records its program (`"program"`, the one-line S-expression), so
//! the file alone says which program made it.
//!
//! Files written before the envelope (`instance_file`, `goal_semantics`, `allow_following`,
//! `time_steps`) read as they are; a missing rule means `visit` with following allowed. Node ids
//! are unsigned, so a negative id is a serde error with its line; ids beyond the tree are caught
//! by [`read_tree_plan`], naming robot, step and node.

use std::path::Path;

use serde_json::Value;

use mrpp_core::envelope::{Envelope, World};
use mrpp_core::error::{Error, Result};
use mrpp_core::mapf::plan_file::{
    RunInfo, mapf_envelope, mapf_plan, mapf_plan_to_draw, mapf_rules,
};
use mrpp_core::{GoalSemantics, MapfProblem, Plan, Rules, Solved, Unsolved};

use crate::instance::TreeInstance;

/// The kind of world file tree plans name.
pub const WORLD_KIND: &str = "tree-instance";

/// The envelope of one run on a tree problem; `notes` are the planner's
/// ([`mrpp_core::Planner::notes`], e.g. the GP program that made the plan).
pub fn tree_envelope(
    instance_file: &str,
    problem: &MapfProblem,
    mut info: RunInfo,
    outcome: &std::result::Result<Solved<MapfProblem>, Unsolved>,
    notes: serde_json::Map<String, Value>,
) -> Envelope<u64> {
    info.family = crate::FAMILY.into();
    info.world = World {
        kind: WORLD_KIND.into(),
        file: instance_file.into(),
    };
    let mut env = mapf_envelope(problem, info, outcome, u64::from);
    env.extra.extend(notes);
    env
}

/// Reads a tree plan file made for `tree`: the problem (the tree's robots under the file's
/// rules, `visit` with following allowed when not recorded; `no_following` forbids following
/// whatever the file says), its plan and the envelope. Errors name `path`: malformed JSON (with
/// its line), `solved: false`, a goal semantics other than `visit`, another robot count, a robot
/// with another start or goal, a node off the tree (naming robot, step and node).
pub fn read_tree_plan(
    tree: &TreeInstance,
    text: &str,
    path: &Path,
    no_following: bool,
) -> Result<(MapfProblem, Plan, Envelope<u64>)> {
    read(tree, text, path, no_following, false)
}

/// As [`read_tree_plan`], but a file that says `solved: false` is read too, each robot standing
/// on its start, so that its starts and goals can be drawn. For pictures only.
///
/// # Errors
/// As [`read_tree_plan`], except for `solved: false`.
pub fn read_tree_plan_to_draw(
    tree: &TreeInstance,
    text: &str,
    path: &Path,
    no_following: bool,
) -> Result<(MapfProblem, Plan, Envelope<u64>)> {
    read(tree, text, path, no_following, true)
}

fn read(
    tree: &TreeInstance,
    text: &str,
    path: &Path,
    no_following: bool,
    to_draw: bool,
) -> Result<(MapfProblem, Plan, Envelope<u64>)> {
    mrpp_core::envelope::check_family(text, crate::FAMILY, path)?;
    let env: Envelope<u64> =
        Envelope::parse(text, path).map_err(|e| retag(e, "not a tree plan"))?;
    let mut rules = mapf_rules(&env, Rules::visit(true), path)?;
    if rules.semantics != GoalSemantics::Visit {
        return Err(Error::invalid(
            path,
            "the plan's goal semantics is \"stay\", but tree plans use \"visit\"",
        ));
    }
    rules.allow_following &= !no_following;
    let inst = &tree.instance;
    if env.agents.len() != inst.num_agents() {
        let msg = format!(
            "the plan has {} robots but the instance has {}",
            env.agents.len(),
            inst.num_agents()
        );
        return Err(Error::invalid(path, msg));
    }
    for (i, a) in env.agents.iter().enumerate() {
        for (what, claim, real) in [
            ("start", a.start, inst.starts[i]),
            ("goal", a.goal, inst.goals[i]),
        ] {
            if claim != u64::from(real) {
                let msg = format!("robot {i} has {what} {claim} but the instance says {real}");
                return Err(Error::invalid(path, msg));
            }
        }
    }
    let nodes = tree.num_nodes() as u64;
    let node = |&v: &u64| {
        if v < nodes {
            Ok(v as u32)
        } else {
            Err(format!(
                "node {v} is not on the tree (nodes are 0..{})",
                nodes.saturating_sub(1)
            ))
        }
    };
    let label = |v: &u64| v.to_string();
    let (_, plan) = if to_draw {
        mapf_plan_to_draw(&env, node, label, path)?
    } else {
        mapf_plan(&env, node, label, path)?
    };
    let problem = MapfProblem::new(std::sync::Arc::new(tree.graph.clone()), inst.clone(), rules)
        .expect("a TreeInstance names only its own nodes");
    Ok((problem, plan, env))
}

/// A parse error of a tree plan, with `what` in front of serde's message (its position is in the
/// line number already).
fn retag(e: Error, what: &str) -> Error {
    match e {
        Error::Parse { path, line, msg } => {
            let msg = match msg.rfind(" at line ") {
                Some(i) => msg[..i].to_string(),
                None => msg,
            };
            Error::Parse {
                path,
                line,
                msg: format!("{what}: {msg}"),
            }
        }
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrpp_core::{Instance, Problem as _, accept};
    use std::time::Duration;

    /// The T-tree: 0 - 1 - 2, 1 - 3; robot 0 goes 2 → 3, robot 1 goes 3 → 0.
    fn sample() -> (TreeInstance, MapfProblem, Solved<MapfProblem>) {
        let inst = Instance::new(vec![2, 3], vec![3, 0]).unwrap();
        let tree = TreeInstance::new(4, vec![(0, 1), (1, 2), (1, 3)], inst).unwrap();
        let problem = crate::tree_problem(&tree, true);
        let plan = Plan::new(vec![vec![2, 2, 1, 3], vec![3, 1, 0]]);
        let s = accept(&problem, plan, "hand", Duration::ZERO).unwrap();
        (tree, problem, s)
    }

    #[test]
    fn round_trip_keeps_plan_rules_and_program() {
        let (tree, problem, s) = sample();
        let info = RunInfo {
            planner: "gp".into(),
            seed: 7,
            ..RunInfo::default()
        };
        let prog = "(if-robot-is-solved stay move-toward-objective)".to_string();
        let text = tree_envelope(
            "t \"q\".json",
            &problem,
            info,
            &Ok(s.clone()),
            serde_json::Map::from_iter([("program".to_string(), Value::from(prog.clone()))]),
        )
        .to_json();
        assert!(text.contains("\"goal\": \"visit\""), "{text}");
        assert!(text.contains("\"makespan\": 3"), "{text}");
        let (p2, plan, env) = read_tree_plan(&tree, &text, Path::new("p.json"), false).unwrap();
        assert_eq!(plan, s.plan);
        assert_eq!(env.extra["program"], prog.as_str());
        assert_eq!(env.world.file, "t \"q\".json");
        assert_eq!(p2.validate(&plan).unwrap(), s.metrics);
        let (strict, _, _) = read_tree_plan(&tree, &text, Path::new("p.json"), true).unwrap();
        assert!(!strict.rules().allow_following);
    }

    #[test]
    fn legacy_and_unsolved_files() {
        let (tree, problem, _) = sample();
        let legacy = r#"{"instance_file": "i.json", "solved": true, "goal_semantics": "visit", "allow_following": false,
            "metrics": {"time_steps": 3}, "agents": [{"start": 2, "goal": 3, "path": [2, 2, 1, 3]}, {"start": 3, "goal": 0, "path": [3, 1, 0]}]}"#;
        let (p, plan, _) = read_tree_plan(&tree, legacy, Path::new("l.json"), false).unwrap();
        assert!(!p.rules().allow_following);
        // Robot 1 enters node 1 as robot 0 leaves it: fine with following, not without.
        let e = p.validate(&plan).unwrap_err().to_string();
        assert!(e.contains("following conflict"), "{e}");
        let text = tree_envelope(
            "i.json",
            &problem,
            RunInfo::default(),
            &Err(Unsolved::TimeLimit),
            serde_json::Map::new(),
        )
        .to_json();
        assert!(!text.contains("program"), "{text}");
        let e = read_tree_plan(&tree, &text, Path::new("u.json"), false)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("u.json: ") && e.contains("no plan"), "{e}");
    }

    #[test]
    fn bad_files_name_the_file_line_and_content() {
        let (tree, _, _) = sample();
        for (text, prefix) in [
            ("{\"solved\": tru", "b.json:1:"),
            (
                "{\n\"solved\": true,\n\"agents\": [\n{\"start\": -1, \"goal\": 0}\n]}",
                "b.json:4:",
            ),
            ("{\n\"agents\": []\n}", "b.json:3:"),
            ("[1, 2]", "b.json:1:"),
        ] {
            let e = read_tree_plan(&tree, text, Path::new("b.json"), false)
                .unwrap_err()
                .to_string();
            assert!(
                e.starts_with(prefix) && e.contains("not a tree plan"),
                "{e}"
            );
            assert!(!e.contains(" at line "), "{e}");
        }
        let err = |text: &str| {
            read_tree_plan(&tree, text, Path::new("c.json"), false)
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
            e.contains("agent 0 path at t=2: node 9 is not on the tree"),
            "{e}"
        );
        let e = err(&two(r#"{"start": 1, "goal": 3, "path": [1]}"#));
        assert!(
            e.contains("robot 0 has start 1 but the instance says 2"),
            "{e}"
        );
        assert!(
            err(r#"{"solved": true, "agents": []}"#).contains("0 robots but the instance has 2")
        );
        let e = err(r#"{"solved": true, "goal_semantics": "stay", "agents": []}"#);
        assert!(e.contains("tree plans use \"visit\""), "{e}");
    }
}
