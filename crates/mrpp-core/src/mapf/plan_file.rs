//! MAPF plans in the plan envelope ([`crate::envelope`]), shared by the grid and tree families:
//! each family only says how a vertex becomes a path element (a cell, a node id) and back.

use std::collections::BTreeMap;
use std::path::Path;

use rustc_hash::FxHashMap;
use serde::Serialize;
use serde::de::DeserializeOwned;
use serde_json::Value;

use crate::contract::{Solved, Unsolved};
use crate::envelope::{AgentPath, Envelope, FORMAT, World};
use crate::error::{Error, Result};
use crate::mapf::MapfProblem;
use crate::mapf::graph::VertexId;
use crate::mapf::instance::Instance;
use crate::mapf::plan::{GoalSemantics, Plan, Rules};

/// What a plan file records about the run besides the plan.
#[derive(Debug, Clone, Default)]
pub struct RunInfo {
    pub family: String,
    pub world: World,
    pub planner: String,
    pub params: BTreeMap<String, String>,
    pub seed: u64,
    pub runtime_ms: f64,
}

/// The envelope of one run on `problem`: starts and goals always, the validated plan and its
/// metrics when solved, the reason (`status`) when not. Paths are written as validated.
pub fn mapf_envelope<E>(
    problem: &MapfProblem,
    info: RunInfo,
    outcome: &std::result::Result<Solved<MapfProblem>, Unsolved>,
    elem: impl Fn(VertexId) -> E,
) -> Envelope<E> {
    let inst = problem.instance();
    let solved = outcome.as_ref().ok();
    let agents = (0..inst.num_agents())
        .map(|i| AgentPath {
            start: elem(inst.starts[i]),
            goal: elem(inst.goals[i]),
            path: solved
                .and_then(|s| s.plan.paths.get(i))
                .map(|p| p.iter().map(|&v| elem(v)).collect())
                .unwrap_or_default(),
        })
        .collect();
    let metrics = solved
        .and_then(|s| serde_json::to_value(s.metrics).ok())
        .and_then(|v| v.as_object().cloned())
        .unwrap_or_default();
    Envelope {
        format: FORMAT.into(),
        family: info.family,
        world: info.world,
        planner: info.planner,
        params: info.params,
        seed: info.seed,
        solved: solved.is_some(),
        status: match outcome {
            Ok(_) => "solved".into(),
            Err(why) => why.status().into(),
        },
        rules: serde_json::to_value(problem.rules()).unwrap_or(Value::Null),
        metrics,
        runtime_ms: info.runtime_ms,
        agents,
        extra: Default::default(),
    }
}

/// The rules a plan file records: its `rules` object, else the keys of older files
/// (`goal_semantics`, `allow_following`), else `default` for what is missing.
pub fn mapf_rules<E>(env: &Envelope<E>, default: Rules, path: &Path) -> Result<Rules> {
    if !env.rules.is_null() {
        return serde_json::from_value(env.rules.clone())
            .map_err(|e| Error::invalid(path, format!("bad \"rules\": {e}")));
    }
    let mut rules = default;
    if let Some(v) = env.extra.get("goal_semantics") {
        rules.semantics = serde_json::from_value::<GoalSemantics>(v.clone())
            .map_err(|e| Error::invalid(path, format!("bad \"goal_semantics\": {e}")))?;
    }
    if let Some(v) = env.extra.get("allow_following") {
        rules.allow_following = v
            .as_bool()
            .ok_or_else(|| Error::invalid(path, "\"allow_following\" must be true or false"))?;
    }
    Ok(rules)
}

/// The instance and plan a solved envelope holds, with every element mapped by `vertex` (an
/// `Err(why)` names what is wrong with the element, e.g. "off the map"; `label` shows an element
/// in messages). Errors are
/// [`Error::Invalid`] naming `path`: the file says `solved: false`; an element is not a vertex
/// (naming agent, start/goal or step); two agents share a start or a goal. Everything else
/// (jumps, conflicts, goals not reached) is the validator's job.
pub fn mapf_plan<E: Serialize + DeserializeOwned>(
    env: &Envelope<E>,
    vertex: impl Fn(&E) -> std::result::Result<VertexId, String>,
    label: impl Fn(&E) -> String,
    path: &Path,
) -> Result<(Instance, Plan)> {
    env.require_solved(path)?;
    plan_or_starts(env, vertex, label, path)
}

/// As [`mapf_plan`], but a file that says `solved: false` is read too: each agent then stands
/// on its start (a one-state path), so that its starts and goals can be drawn. For pictures
/// only: a validator must use [`mapf_plan`].
///
/// # Errors
/// As [`mapf_plan`], except for `solved: false`.
pub fn mapf_plan_to_draw<E: Serialize + DeserializeOwned>(
    env: &Envelope<E>,
    vertex: impl Fn(&E) -> std::result::Result<VertexId, String>,
    label: impl Fn(&E) -> String,
    path: &Path,
) -> Result<(Instance, Plan)> {
    plan_or_starts(env, vertex, label, path)
}

fn plan_or_starts<E: Serialize + DeserializeOwned>(
    env: &Envelope<E>,
    vertex: impl Fn(&E) -> std::result::Result<VertexId, String>,
    label: impl Fn(&E) -> String,
    path: &Path,
) -> Result<(Instance, Plan)> {
    let at = |e: &E, what: &dyn Fn() -> String| {
        vertex(e).map_err(|why| Error::invalid(path, format!("{}: {why}", what())))
    };
    let (mut starts, mut goals, mut paths) = (Vec::new(), Vec::new(), Vec::new());
    let mut start_of: FxHashMap<VertexId, usize> = FxHashMap::default();
    let mut goal_of: FxHashMap<VertexId, usize> = FxHashMap::default();
    for (i, a) in env.agents.iter().enumerate() {
        let s = at(&a.start, &|| format!("agent {i} start"))?;
        let g = at(&a.goal, &|| format!("agent {i} goal"))?;
        if let Some(j) = start_of.insert(s, i) {
            let msg = format!("agents {j} and {i} share the start {}", label(&a.start));
            return Err(Error::invalid(path, msg));
        }
        if let Some(j) = goal_of.insert(g, i) {
            let msg = format!("agents {j} and {i} share the goal {}", label(&a.goal));
            return Err(Error::invalid(path, msg));
        }
        let p = if env.solved {
            a.path
                .iter()
                .enumerate()
                .map(|(t, e)| at(e, &|| format!("agent {i} path at t={t}")))
                .collect::<Result<Vec<_>>>()?
        } else {
            vec![s]
        };
        starts.push(s);
        goals.push(g);
        paths.push(p);
    }
    let inst = Instance::new(starts, goals).map_err(|msg| Error::invalid(path, msg))?;
    Ok((inst, Plan::new(paths)))
}
