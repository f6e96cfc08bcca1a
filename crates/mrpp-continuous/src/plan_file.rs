//! Continuous plans in the plan envelope (`mrpp-plan/1`): path elements are `[x, y]` positions,
//! one per step (Δt = 1), every robot the same number of them; the uncovered target distance per
//! step (`"utd"`, the paper's AUTD curve for one run) rides along as an extra key. A checker
//! needs the world file beside the plan.

use std::path::Path;

use serde_json::json;

use crate::geometry::Point;
use crate::problem::{NavProblem, Trajectories};
use mrpp_core::envelope::{AgentPath, Envelope, FORMAT, World as WorldRef};
use mrpp_core::error::{Error, Result};
use mrpp_core::mapf::plan_file::RunInfo;
use mrpp_core::{Solved, Unsolved};

/// The envelope of one run on the world file `world_file` (its name).
pub fn continuous_envelope(
    world_file: &str,
    p: &NavProblem,
    info: RunInfo,
    outcome: &std::result::Result<Solved<NavProblem>, Unsolved>,
) -> Envelope<Point> {
    let solved = outcome.as_ref().ok();
    let mut extra = serde_json::Map::new();
    if let Some(s) = solved {
        extra.insert("utd".into(), json!(p.utd_series(&s.plan)));
    }
    Envelope {
        format: FORMAT.into(),
        family: crate::FAMILY.into(),
        world: WorldRef {
            kind: "continuous-world".into(),
            file: world_file.into(),
        },
        planner: info.planner,
        params: info.params,
        seed: info.seed,
        solved: solved.is_some(),
        status: outcome
            .as_ref()
            .map_or_else(|e| e.status().into(), |_| "solved".into()),
        rules: json!({"dt": 1.0, "epsilon": p.world().epsilon, "collision": "swept discs"}),
        metrics: solved
            .and_then(|s| serde_json::to_value(s.metrics).ok())
            .and_then(|v| v.as_object().cloned())
            .unwrap_or_default(),
        runtime_ms: info.runtime_ms,
        agents: p
            .world()
            .robots
            .iter()
            .enumerate()
            .map(|(i, r)| AgentPath {
                start: r.start,
                goal: r.goal,
                path: solved
                    .map(|s| s.plan.positions[i].clone())
                    .unwrap_or_default(),
            })
            .collect(),
        extra,
    }
}

/// Reads a continuous plan: its trajectories and envelope. Errors name `path`: malformed JSON
/// (with its line), `solved: false`, another robot count.
pub fn read_continuous_plan(
    p: &NavProblem,
    text: &str,
    path: &Path,
) -> Result<(Trajectories, Envelope<Point>)> {
    let env: Envelope<Point> = Envelope::parse(text, path)?;
    env.require_solved(path)?;
    if env.agents.len() != p.world().robots.len() {
        return Err(Error::invalid(
            path,
            format!(
                "{} agents in the plan, {} robots in the world",
                env.agents.len(),
                p.world().robots.len()
            ),
        ));
    }
    let plan = Trajectories {
        positions: env.agents.iter().map(|a| a.path.clone()).collect(),
    };
    Ok((plan, env))
}
