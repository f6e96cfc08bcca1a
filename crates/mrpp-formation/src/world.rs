//! The formation file (a JSON configuration: map, robots, Q_ini, Q_goal, radius, cost model) and
//! formation plans in the plan envelope.
//!
//! ```json
//! {"map": "../polygon-maps/gaps.txt", "robots": 3, "start": [2.0, 2.0], "goal": [30.0, 30.0],
//!  "radius": 0.3, "cost": {"model": "lanes", "kappa": 0.5}}
//! ```
//! `map` is relative to the formation file; points are in working units (the map's `[SCALE]`
//! applied); `radius` defaults to 0.3 and `cost` to `lanes` with κ = 0.5.
//!
//! A plan file is the envelope with roadmap vertex ids as path elements; it also holds the roadmap
//! it was planned on (`"roadmap": {"points", "edges": [[u, v, length, clearance], …]}`) and the
//! problem (`robots`, `start`, `goal`, `radius`, `cost`), so the independent checker can judge it
//! from the file alone.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use serde::{Deserialize, Serialize};
use serde_json::{Value, json};

use mrpp_core::envelope::{AgentPath, Envelope, FORMAT, World};
use mrpp_core::error::{Error, Result, read_file};
use mrpp_core::mapf::plan_file::RunInfo;
use mrpp_core::{Solved, Unsolved};

use crate::cost::CostModel;
use crate::polymap::{Point, PolygonMap};
use crate::problem::{FormationPlan, FormationProblem};
use crate::roadmap::{RoadmapOptions, build_roadmap};

/// The formation file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FormationFile {
    pub map: PathBuf,
    pub robots: usize,
    pub start: Point,
    pub goal: Point,
    #[serde(default = "default_radius")]
    pub radius: f64,
    #[serde(default)]
    pub cost: CostModel,
}

fn default_radius() -> f64 {
    0.3
}

impl FormationFile {
    /// Parses the text of a formation file (`path` names it in errors); `map` is left as written.
    ///
    /// # Errors
    /// Malformed JSON or an unknown key (with its line), `robots` outside 1..=64, a radius that is
    /// not a positive number.
    pub fn parse(text: &str, path: &Path) -> Result<Self> {
        let file: FormationFile = serde_json::from_str(text.trim_start_matches('\u{feff}'))
            .map_err(|e| Error::parse(path, e.line().max(1), e.to_string()))?;
        if file.robots == 0 || file.robots > 64 {
            return Err(Error::invalid(
                path,
                format!("robots must be between 1 and 64, got {}", file.robots),
            ));
        }
        if !(file.radius.is_finite() && file.radius > 0.0) {
            return Err(Error::invalid(
                path,
                format!("radius must be positive, got {}", file.radius),
            ));
        }
        Ok(file)
    }

    /// The polygon map the formation file at `path` names, resolved against the file's folder
    /// as [`Formation::load`] resolves it (so that outputs can refuse to overwrite it).
    ///
    /// # Errors
    /// As [`FormationFile::parse`], and an unreadable file.
    pub fn map_of(path: &Path) -> Result<PathBuf> {
        let file = FormationFile::parse(&read_file(path)?, path)?;
        Ok(map_beside(path, &file.map))
    }
}

/// A map named `map` in the formation file at `path`: relative to the file's folder.
fn map_beside(path: &Path, map: &Path) -> PathBuf {
    path.parent().unwrap_or(Path::new("")).join(map)
}

/// A loaded formation: the map, the problem on its roadmap, and the roadmap build time.
#[derive(Debug, Clone)]
pub struct Formation {
    pub file: FormationFile,
    pub map: PolygonMap,
    pub problem: FormationProblem,
    pub build_ms: f64,
}

impl Formation {
    /// Reads a formation file and its map, builds the roadmap and links Q_ini and Q_goal.
    ///
    /// # Errors
    /// Naming the file: malformed JSON (with its line), absurd numbers, a map error (file:line), a
    /// point outside the free space or seeing no roadmap vertex.
    pub fn load(path: &Path) -> Result<Self> {
        let mut file = FormationFile::parse(&read_file(path)?, path)?;
        file.map = map_beside(path, &file.map);
        let map = PolygonMap::load(&file.map)?;
        Self::on(file, map, path)
    }

    /// The formation of `file` on `map` (`path` names the file in errors).
    pub fn on(file: FormationFile, map: PolygonMap, path: &Path) -> Result<Self> {
        let started = Instant::now();
        let opts = RoadmapOptions {
            radius: file.radius,
            ..RoadmapOptions::default()
        };
        let mut roadmap = build_roadmap(&map, &opts);
        let mut link = |p: Point, what: &str| -> Result<u32> {
            if !map.is_free(p) || map.clearance(p) < file.radius {
                return Err(Error::invalid(
                    path,
                    format!(
                        "{what} ({}, {}) is not in free space with the robot's clearance",
                        p[0], p[1]
                    ),
                ));
            }
            roadmap.link(&map, p, file.radius).ok_or_else(|| {
                Error::invalid(
                    path,
                    format!("{what} ({}, {}) sees no roadmap vertex", p[0], p[1]),
                )
            })
        };
        let start = link(file.start, "start")?;
        let goal = link(file.goal, "goal")?;
        let build_ms = started.elapsed().as_secs_f64() * 1e3;
        let problem = FormationProblem::new(
            Arc::new(roadmap),
            file.robots,
            start,
            goal,
            file.cost,
            file.radius,
        )
        .map_err(|m| Error::invalid(path, m))?;
        Ok(Formation {
            file,
            map,
            problem,
            build_ms,
        })
    }
}

/// The envelope of one run on a formation.
pub fn formation_envelope(
    formation_file: &str,
    f: &Formation,
    mut info: RunInfo,
    outcome: &std::result::Result<Solved<FormationProblem>, Unsolved>,
) -> Envelope<u32> {
    let p = &f.problem;
    info.family = crate::FAMILY.into();
    let solved = outcome.as_ref().ok();
    let r = p.roadmap();
    let mut extra = serde_json::Map::new();
    extra.insert("robots".into(), p.robots().into());
    extra.insert("radius".into(), p.radius().into());
    extra.insert(
        "cost".into(),
        serde_json::to_value(p.cost_model()).unwrap_or(Value::Null),
    );
    extra.insert(
        "roadmap".into(),
        json!({
            "points": r.points,
            "edges": r.edges.iter().map(|e| json!([e.u, e.v, e.length, e.clearance])).collect::<Vec<_>>(),
        }),
    );
    Envelope {
        format: FORMAT.into(),
        family: info.family,
        world: World {
            kind: "formation".into(),
            file: formation_file.into(),
        },
        planner: info.planner,
        params: info.params,
        seed: info.seed,
        solved: solved.is_some(),
        status: outcome
            .as_ref()
            .map_or_else(|e| e.status().into(), |_| "solved".into()),
        rules: json!({"waiting": "first robot at a shared vertex waits", "opposite_directions": false}),
        metrics: solved
            .and_then(|s| serde_json::to_value(s.metrics).ok())
            .and_then(|v| v.as_object().cloned())
            .unwrap_or_default(),
        runtime_ms: info.runtime_ms,
        agents: (0..p.robots())
            .map(|i| AgentPath {
                start: p.start(),
                goal: p.goal(),
                path: solved.map(|s| s.plan.paths[i].clone()).unwrap_or_default(),
            })
            .collect(),
        extra,
    }
}

/// Reads a formation plan made for `f`: its plan and envelope. Errors name `path`: malformed
/// JSON (with its line), `solved: false`, another robot count, a vertex not on the roadmap.
pub fn read_formation_plan(
    f: &Formation,
    text: &str,
    path: &Path,
) -> Result<(FormationPlan, Envelope<u32>)> {
    let env: Envelope<u32> = Envelope::parse(text, path)?;
    env.require_solved(path)?;
    let n = f.problem.roadmap().num_vertices() as u32;
    if let Some((i, v)) = env
        .agents
        .iter()
        .enumerate()
        .find_map(|(i, a)| a.path.iter().find(|&&v| v >= n).map(|&v| (i, v)))
    {
        return Err(Error::invalid(
            path,
            format!("robot {i}'s path names vertex {v}, not one of the roadmap's {n}"),
        ));
    }
    let plan = FormationPlan {
        paths: env.agents.iter().map(|a| a.path.clone()).collect(),
    };
    Ok((plan, env))
}

/// A random start/goal pair for `map`: uniform points in free space with clearance at least
/// `2 · radius`, at least half the border's diagonal apart (at most 10 000 draws; `None` when none
/// was found).
pub fn random_pair(
    map: &PolygonMap,
    radius: f64,
    rng: &mut impl rand::Rng,
) -> Option<(Point, Point)> {
    use rand::RngExt;
    let (lo, hi) = map.bounds();
    let diag = crate::roadmap::dist(lo, hi);
    let mut free: Vec<Point> = Vec::new();
    for _ in 0..10_000 {
        let p = [
            lo[0] + rng.random::<f64>() * (hi[0] - lo[0]),
            lo[1] + rng.random::<f64>() * (hi[1] - lo[1]),
        ];
        if !map.is_free(p) || map.clearance(p) < 2.0 * radius {
            continue;
        }
        if let Some(&a) = free
            .iter()
            .find(|&&a| crate::roadmap::dist(a, p) >= diag / 2.0)
        {
            return Some((a, p));
        }
        free.push(p);
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::{Exact, brute_force};
    use crate::planners::Sequential;
    use mrpp_core::{Ctx, solve};

    fn load(name: &str) -> Formation {
        Formation::load(
            &Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../../data/formation")
                .join(name),
        )
        .unwrap()
    }

    fn planners() -> Vec<Box<dyn mrpp_core::Planner<FormationProblem>>> {
        vec![
            Box::new(Sequential),
            Box::new(crate::ga::Ga::default()),
            Box::new(Exact {
                candidate_limit: 200_000,
            }),
        ]
    }

    /// Issue 27 B: under every cost model, every plan a planner calls solved has finite
    /// metrics, in the problem's metrics and in the plan file (no null); planners that solve
    /// nothing give up honestly.
    #[test]
    fn solved_plans_have_finite_metrics_under_every_cost_model() {
        for cost in [
            CostModel::Lanes { kappa: 0.5 },
            CostModel::Waves,
            CostModel::Hard,
        ] {
            let mut solved = 0;
            for name in ["gaps-3.json", "potholes-3.json", "var_density2-3.json"] {
                for robots in [2, 3] {
                    let mut f = load(name);
                    let p = &f.problem;
                    f.problem = FormationProblem::new(
                        p.roadmap_arc().clone(),
                        robots,
                        p.start(),
                        p.goal(),
                        cost,
                        p.radius(),
                    )
                    .unwrap();
                    f.file.cost = cost;
                    f.file.robots = robots;
                    for planner in planners() {
                        let outcome = solve(planner.as_ref(), &f.problem, &Ctx::default());
                        let what = format!(
                            "{name}, {robots} robots, {}, {}",
                            cost.label(),
                            planner.name()
                        );
                        let s = match &outcome {
                            Ok(s) => s,
                            Err(e) => {
                                assert!(matches!(e, Unsolved::GaveUp(_)), "{what}: {e:?}");
                                continue;
                            }
                        };
                        solved += 1;
                        assert!(
                            s.metrics.c_max.is_finite() && s.metrics.sum_of_costs.is_finite(),
                            "{what}: {:?}",
                            s.metrics
                        );
                        let env = formation_envelope(name, &f, RunInfo::default(), &outcome);
                        for key in ["c_max", "sum_of_costs", "distinct_paths"] {
                            let v = env.metrics.get(key).and_then(Value::as_f64);
                            assert!(v.is_some_and(f64::is_finite), "{what}: {key} is {v:?}");
                        }
                    }
                }
            }
            assert!(solved >= 9, "{}: only {solved} solved", cost.label());
        }
    }

    /// Issue 27 B: a `hard` formation in which every corridor is too narrow for the robots
    /// (`mrpp gen formation -m data/polygon-maps/gaps.txt --robots 12 -s 0 --radius 2 --cost
    /// hard`): no plan has a finite cost. Every planner used to call its plan solved with
    /// `c_max: null`, and the validator accepted it; now each gives up naming the corridor over
    /// capacity, and the validator refuses such a plan.
    #[test]
    fn every_corridor_over_capacity_is_not_solved() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data");
        let map_path = dir.join("polygon-maps/gaps.txt");
        let file = FormationFile {
            map: map_path.clone(),
            robots: 12,
            start: [27.672422534731886, 27.011901108315516],
            goal: [26.722942625358925, 4.373909437673447],
            radius: 2.0,
            cost: CostModel::Hard,
        };
        let f = Formation::on(
            file,
            PolygonMap::load(&map_path).unwrap(),
            Path::new("over.json"),
        )
        .unwrap();
        let p = &f.problem;
        for planner in planners() {
            match solve(planner.as_ref(), p, &Ctx::default()) {
                Err(Unsolved::GaveUp(why)) => assert!(
                    why.contains("corridor") && why.contains("over capacity"),
                    "{}: {why}",
                    planner.name()
                ),
                Err(e) => panic!("{}: {e:?}", planner.name()),
                Ok(s) => panic!("{}: solved with {:?}", planner.name(), s.metrics),
            }
        }
        // The plan the planners used to return: the whole formation on one path.
        let paths = crate::planners::sequential_paths(p, &|_| 1.0);
        assert_eq!(paths.len(), 12);
        let e = mrpp_core::Problem::validate(p, &FormationPlan { paths }).unwrap_err();
        assert!(
            matches!(
                e,
                crate::FormationViolation::OverCapacity {
                    robots: 12,
                    capacity: 1,
                    ..
                }
            ),
            "{e}"
        );
    }

    #[test]
    fn bundled_formations_plan_and_exact_is_best() {
        for name in ["gaps-3.json", "potholes-3.json", "var_density2-3.json"] {
            let f = load(name);
            let p = &f.problem;
            let ctx = Ctx::default();
            let seq = solve(&Sequential, p, &ctx).unwrap();
            let ga = solve(&crate::ga::Ga::default(), p, &ctx).unwrap();
            let ex = solve(
                &Exact {
                    candidate_limit: 200_000,
                },
                p,
                &ctx,
            )
            .unwrap();
            eprintln!(
                "{name}: roadmap {} vertices {} edges ({:.1} ms) | sequential {:.3} | ga {:.3} | exact {:.3}",
                p.roadmap().num_vertices(),
                p.roadmap().edges.len(),
                f.build_ms,
                seq.metrics.c_max,
                ga.metrics.c_max,
                ex.metrics.c_max
            );
            assert!(ex.metrics.c_max <= ga.metrics.c_max + 1e-9);
            assert!(ga.metrics.c_max <= seq.metrics.c_max + 1e-9);
            if p.robots() <= 3
                && let Some((_, best)) = brute_force(p, 2_000)
            {
                assert!(
                    (best - ex.metrics.c_max).abs() < 1e-9,
                    "{name}: brute {best} vs exact {}",
                    ex.metrics.c_max
                );
            }
        }
    }
}
