//! The formation problem, its plans and its validator (the GA paper's §2.1).
//!
//! R identical robots start together at `Q_ini` and must all reach `Q_goal`; a plan is one roadmap
//! path per robot (a vertex sequence). The paper's rules, as the validator applies them:
//! - every path starts at `Q_ini`, ends at `Q_goal`, follows roadmap edges and visits no vertex
//!   twice (a path with a loop is never better and makes the waiting rule ambiguous);
//! - **no two robots cross one edge in opposite directions** (the paper's collision:
//!   `(p_i(m), p_i(m+1)) = (p_j(l+1), p_j(l))`);
//! - **the first robot at a shared vertex waits for the others** that have the vertex on their
//!   path, so the robots that use an edge leave its tail together and cross it as one group of
//!   `n_e` robots, taking `c_e(n_e)` ([`crate::cost`]);
//! - the waiting must be possible: the shared vertices may not be visited in orders that make
//!   robots wait for each other in a circle (the union of the paths, as a directed graph, has no
//!   cycle);
//! - **every group's crossing takes a finite time**: a corridor whose cost `c_e(n_e)` is not
//!   finite (the `hard` model with more robots than the corridor holds side by side, [`crate::cost`])
//!   cannot be crossed, so a plan that sends such a group is refused, naming the first such
//!   corridor along robot 0's path, then robot 1's, and so on
//!   ([`FormationViolation::OverCapacity`]); and the plan's `c_max` and sum of costs must be
//!   finite numbers ([`FormationViolation::CostNotFinite`]). A plan the validator accepts therefore
//!   never has an infinite, NaN or missing metric.
//!
//! Timing: `T(Q_ini) = 0`; for every other vertex `v` on some path,
//! `T(v) = max over robots i through v of T(pred_i(v)) + c_e(n_e)` for the edge `e` from the
//! predecessor. Robot `i`'s cost `c_i` is its arrival time at `Q_goal` (waits at earlier merges
//! included), and the plan's cost is the worst, `c_max = T(Q_goal)` — the paper's
//! "the cost of the whole solution is that of the worst path".

use std::sync::Arc;

use rustc_hash::FxHashMap;
use serde::Serialize;

use crate::cost::CostModel;
use crate::roadmap::Roadmap;
use mrpp_core::Problem;

/// A formation problem on a roadmap.
#[derive(Debug, Clone)]
pub struct FormationProblem {
    roadmap: Arc<Roadmap>,
    robots: usize,
    start: u32,
    goal: u32,
    cost: CostModel,
    radius: f64,
    /// `table[e][r]` = `c_e(r)` for `r` in `0..=robots`.
    table: Vec<Vec<f64>>,
}

/// One roadmap path per robot.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct FormationPlan {
    pub paths: Vec<Vec<u32>>,
}

/// What the validator measures on a valid plan.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FormationMetrics {
    /// The worst robot's arrival time at `Q_goal`: the plan's cost.
    pub c_max: f64,
    /// The sum of the robots' arrival times.
    pub sum_of_costs: f64,
    /// How many different paths the formation uses (1 = it never splits).
    pub distinct_paths: usize,
}

/// The first rule a plan breaks.
#[derive(Debug, Clone, PartialEq)]
pub enum FormationViolation {
    RobotCount {
        plan: usize,
        problem: usize,
    },
    WrongEnds {
        robot: usize,
    },
    NotAnEdge {
        robot: usize,
        step: usize,
        from: u32,
        to: u32,
    },
    Revisit {
        robot: usize,
        vertex: u32,
    },
    OppositeDirections {
        a: usize,
        b: usize,
        from: u32,
        to: u32,
    },
    CircularWait {
        vertex: u32,
    },
    /// `robots` robots cross the corridor between roadmap vertices `from` and `to` (in that
    /// direction) together, but its cost for that many is not finite: it holds `capacity` robots
    /// side by side and the cost model forbids more (`hard`).
    OverCapacity {
        from: u32,
        to: u32,
        robots: usize,
        capacity: usize,
    },
    /// The plan's `c_max` or sum of costs (`what`) is not a finite number although every
    /// corridor's cost is (a sum that overflows).
    CostNotFinite {
        what: &'static str,
    },
}

impl std::fmt::Display for FormationViolation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Self::RobotCount { plan, problem } => {
                write!(
                    f,
                    "the plan has {plan} paths but the formation has {problem} robots"
                )
            }
            Self::WrongEnds { robot } => {
                write!(f, "robot {robot}'s path does not go from Q_ini to Q_goal")
            }
            Self::NotAnEdge {
                robot,
                step,
                from,
                to,
            } => write!(
                f,
                "robot {robot} jumps from vertex {from} to {to} at step {step} (no roadmap edge)"
            ),
            Self::Revisit { robot, vertex } => {
                write!(f, "robot {robot} visits vertex {vertex} twice")
            }
            Self::OppositeDirections { a, b, from, to } => write!(
                f,
                "robots {a} and {b} cross the edge {from}-{to} in opposite directions"
            ),
            Self::CircularWait { vertex } => write!(
                f,
                "the robots would wait for each other in a circle (through vertex {vertex})"
            ),
            Self::OverCapacity {
                from,
                to,
                robots,
                capacity,
            } => write!(
                f,
                "corridor {from}-{to} is over capacity: {robots} robots cross it together but it \
                 holds {capacity} side by side, so the crossing never ends (infinite cost)"
            ),
            Self::CostNotFinite { what } => {
                write!(f, "the plan's {what} is not a finite number")
            }
        }
    }
}

/// Per-robot arrival times and the plan's cost.
#[derive(Debug, Clone, PartialEq)]
pub struct Evaluation {
    pub per_robot: Vec<f64>,
    pub c_max: f64,
}

impl FormationProblem {
    /// A problem for `robots` robots of radius `radius` (working units) from vertex `start` to
    /// `goal`.
    ///
    /// # Errors
    /// A message when `robots` is 0, a vertex is not on the roadmap, the radius is not a positive
    /// number, or the `lanes` model's κ is not a finite number ≥ 0 (a negative κ would make a
    /// group cheaper than one robot, breaking the models' promise of costs that never fall).
    pub fn new(
        roadmap: Arc<Roadmap>,
        robots: usize,
        start: u32,
        goal: u32,
        cost: CostModel,
        radius: f64,
    ) -> Result<Self, String> {
        let n = roadmap.num_vertices() as u32;
        if robots == 0 {
            return Err("a formation needs at least one robot".into());
        }
        if start >= n || goal >= n {
            return Err(format!(
                "Q_ini {start} or Q_goal {goal} is not one of the roadmap's {n} vertices"
            ));
        }
        if !(radius.is_finite() && radius > 0.0) {
            return Err(format!(
                "the radius must be a positive number, got {radius}"
            ));
        }
        if let CostModel::Lanes { kappa } = cost
            && !(kappa.is_finite() && kappa >= 0.0)
        {
            return Err(format!(
                "the lanes cost model's kappa must be a number >= 0, got {kappa}"
            ));
        }
        let table = roadmap
            .edges
            .iter()
            .map(|e| (0..=robots).map(|r| cost.cost(e, r, radius)).collect())
            .collect();
        Ok(FormationProblem {
            roadmap,
            robots,
            start,
            goal,
            cost,
            radius,
            table,
        })
    }

    pub fn roadmap(&self) -> &Roadmap {
        &self.roadmap
    }
    pub fn roadmap_arc(&self) -> &Arc<Roadmap> {
        &self.roadmap
    }
    pub fn robots(&self) -> usize {
        self.robots
    }
    pub fn start(&self) -> u32 {
        self.start
    }
    pub fn goal(&self) -> u32 {
        self.goal
    }
    pub fn cost_model(&self) -> CostModel {
        self.cost
    }
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// `c_e(r)` (`r ≤ robots`).
    #[inline]
    pub fn edge_cost(&self, e: u32, r: usize) -> f64 {
        self.table[e as usize][r.min(self.robots)]
    }

    /// The timing of `paths` (any number of them, e.g. part of a plan) under the paper's rules,
    /// or the first rule they break (a corridor over capacity included: an `Ok` evaluation has
    /// finite times, unless a sum overflows).
    pub fn evaluate(&self, paths: &[Vec<u32>]) -> Result<Evaluation, FormationViolation> {
        let edges = self.path_edges(paths)?;
        let usage = self.usage(&edges)?;
        let times = self.event_times(paths, &edges, &usage)?;
        self.check_capacity(paths, &edges, &usage)?;
        let per_robot: Vec<f64> = paths
            .iter()
            .zip(&edges)
            .map(|(p, es)| match es.last() {
                None => 0.0,
                Some(&(e, _)) => {
                    let pred = p[p.len() - 2];
                    let n = usage[&e].0 + usage[&e].1;
                    times[&pred] + self.edge_cost(e, n)
                }
            })
            .collect();
        let c_max = per_robot.iter().copied().fold(0.0, f64::max);
        Ok(Evaluation { per_robot, c_max })
    }

    /// When each robot of `paths` leaves each vertex of its path and reaches the next one, under
    /// the timing of [`FormationProblem::evaluate`]: per robot, per edge of its path,
    /// `(departure, arrival)`. A robot arriving at a vertex waits there until its departure (the
    /// group's event time). Used to animate plans.
    ///
    /// # Errors
    /// The first rule the paths break.
    pub fn schedule(&self, paths: &[Vec<u32>]) -> Result<Vec<Vec<(f64, f64)>>, FormationViolation> {
        let edges = self.path_edges(paths)?;
        let usage = self.usage(&edges)?;
        let times = self.event_times(paths, &edges, &usage)?;
        self.check_capacity(paths, &edges, &usage)?;
        Ok(paths
            .iter()
            .zip(&edges)
            .map(|(p, es)| {
                p.windows(2)
                    .zip(es)
                    .map(|(w, &(e, _))| {
                        let n = usage[&e].0 + usage[&e].1;
                        let depart = times[&w[0]];
                        (depart, depart + self.edge_cost(e, n))
                    })
                    .collect()
            })
            .collect())
    }

    /// Directed use of each edge by `edges` (each path's `(edge id, forward)`): robots u→v,
    /// robots v→u, and the first robot of each; or the first two robots that cross an edge in
    /// opposite directions.
    #[allow(clippy::type_complexity)]
    fn usage(
        &self,
        edges: &[Vec<(u32, bool)>],
    ) -> Result<FxHashMap<u32, (usize, usize, usize, usize)>, FormationViolation> {
        let mut usage: FxHashMap<u32, (usize, usize, usize, usize)> = FxHashMap::default();
        for (i, es) in edges.iter().enumerate() {
            for &(e, forward) in es {
                let u = usage.entry(e).or_insert((0, 0, usize::MAX, usize::MAX));
                if forward {
                    u.0 += 1;
                    u.2 = u.2.min(i);
                } else {
                    u.1 += 1;
                    u.3 = u.3.min(i);
                }
                if u.0 > 0 && u.1 > 0 {
                    let edge = &self.roadmap.edges[e as usize];
                    let (a, b) = (u.2.min(u.3), u.2.max(u.3));
                    return Err(FormationViolation::OppositeDirections {
                        a,
                        b,
                        from: edge.u,
                        to: edge.v,
                    });
                }
            }
        }
        Ok(usage)
    }

    /// The first corridor, along robot 0's path, then robot 1's, ..., whose group cost
    /// `c_e(n_e)` is not finite ([`FormationViolation::OverCapacity`]).
    fn check_capacity(
        &self,
        paths: &[Vec<u32>],
        edges: &[Vec<(u32, bool)>],
        usage: &FxHashMap<u32, (usize, usize, usize, usize)>,
    ) -> Result<(), FormationViolation> {
        for (p, es) in paths.iter().zip(edges) {
            for (w, &(e, _)) in p.windows(2).zip(es) {
                let n = usage[&e].0 + usage[&e].1;
                if !self.edge_cost(e, n).is_finite() {
                    return Err(FormationViolation::OverCapacity {
                        from: w[0],
                        to: w[1],
                        robots: n,
                        capacity: crate::cost::capacity(
                            &self.roadmap.edges[e as usize],
                            self.radius,
                        ),
                    });
                }
            }
        }
        Ok(())
    }

    /// Each path's edges `(edge id, forward)`, after checking ends, edges and revisits.
    #[allow(clippy::type_complexity)]
    fn path_edges(&self, paths: &[Vec<u32>]) -> Result<Vec<Vec<(u32, bool)>>, FormationViolation> {
        let mut out = Vec::with_capacity(paths.len());
        for (i, p) in paths.iter().enumerate() {
            if p.first() != Some(&self.start) || p.last() != Some(&self.goal) {
                return Err(FormationViolation::WrongEnds { robot: i });
            }
            let mut seen: FxHashMap<u32, ()> = FxHashMap::default();
            for &v in p {
                if seen.insert(v, ()).is_some() {
                    return Err(FormationViolation::Revisit {
                        robot: i,
                        vertex: v,
                    });
                }
            }
            let mut es = Vec::with_capacity(p.len());
            for (step, w) in p.windows(2).enumerate() {
                let e =
                    self.roadmap
                        .edge_between(w[0], w[1])
                        .ok_or(FormationViolation::NotAnEdge {
                            robot: i,
                            step: step + 1,
                            from: w[0],
                            to: w[1],
                        })?;
                es.push((e, self.roadmap.edges[e as usize].u == w[0]));
            }
            out.push(es);
        }
        Ok(out)
    }

    /// `T(v)` for every vertex on a path (longest path in the union DAG), or a circular wait.
    fn event_times(
        &self,
        paths: &[Vec<u32>],
        edges: &[Vec<(u32, bool)>],
        usage: &FxHashMap<u32, (usize, usize, usize, usize)>,
    ) -> Result<FxHashMap<u32, f64>, FormationViolation> {
        // The union graph: distinct arcs a→b with their group cost.
        let mut arcs: FxHashMap<(u32, u32), f64> = FxHashMap::default();
        for (p, es) in paths.iter().zip(edges) {
            for (w, &(e, _)) in p.windows(2).zip(es) {
                let n = usage[&e].0 + usage[&e].1;
                arcs.insert((w[0], w[1]), self.edge_cost(e, n));
            }
        }
        let mut indeg: FxHashMap<u32, usize> = FxHashMap::default();
        let mut out: FxHashMap<u32, Vec<(u32, f64)>> = FxHashMap::default();
        for p in paths {
            for &v in p {
                indeg.entry(v).or_insert(0);
            }
        }
        let mut arc_list: Vec<(&(u32, u32), &f64)> = arcs.iter().collect();
        arc_list.sort_by_key(|(k, _)| **k);
        for (&(a, b), &c) in arc_list {
            *indeg.get_mut(&b).expect("vertex of a path") += 1;
            out.entry(a).or_default().push((b, c));
        }
        let mut times: FxHashMap<u32, f64> = indeg.keys().map(|&v| (v, 0.0)).collect();
        let mut ready: Vec<u32> = indeg
            .iter()
            .filter(|(_, d)| **d == 0)
            .map(|(v, _)| *v)
            .collect();
        let mut done = 0;
        while let Some(a) = ready.pop() {
            done += 1;
            let ta = times[&a];
            for &(b, c) in out.get(&a).map(Vec::as_slice).unwrap_or(&[]) {
                let tb = times.get_mut(&b).expect("vertex of a path");
                *tb = tb.max(ta + c);
                let d = indeg.get_mut(&b).expect("vertex of a path");
                *d -= 1;
                if *d == 0 {
                    ready.push(b);
                }
            }
        }
        if done < indeg.len() {
            let stuck = indeg
                .iter()
                .filter(|(_, d)| **d > 0)
                .map(|(v, _)| *v)
                .min()
                .unwrap_or(0);
            return Err(FormationViolation::CircularWait { vertex: stuck });
        }
        Ok(times)
    }

    /// The metrics of a full plan (any number of paths accepted here; `validate` checks the
    /// count): always finite numbers.
    ///
    /// # Errors
    /// The first rule the plan breaks, a corridor over capacity or a `c_max` / sum of costs that
    /// is not finite included.
    pub fn metrics(&self, plan: &FormationPlan) -> Result<FormationMetrics, FormationViolation> {
        let ev = self.evaluate(&plan.paths)?;
        let mut distinct = plan.paths.clone();
        distinct.sort();
        distinct.dedup();
        let sum_of_costs: f64 = ev.per_robot.iter().sum();
        if !ev.c_max.is_finite() {
            return Err(FormationViolation::CostNotFinite { what: "c_max" });
        }
        if !sum_of_costs.is_finite() {
            return Err(FormationViolation::CostNotFinite {
                what: "sum of costs",
            });
        }
        Ok(FormationMetrics {
            c_max: ev.c_max,
            sum_of_costs,
            distinct_paths: distinct.len(),
        })
    }

    /// Why no plan was found, for a planner whose best plan `paths` is not valid: its first
    /// violation (the corridor over capacity, typically).
    pub(crate) fn why_not(&self, paths: &[Vec<u32>]) -> String {
        match self.evaluate(paths) {
            Err(v) => v.to_string(),
            Ok(e) if !e.c_max.is_finite() => "its c_max is not a finite number".into(),
            Ok(_) => "it is valid".into(),
        }
    }
}

impl Problem for FormationProblem {
    type Plan = FormationPlan;
    type Metrics = FormationMetrics;
    type Violation = FormationViolation;

    fn num_agents(&self) -> usize {
        self.robots
    }

    fn validate(&self, plan: &FormationPlan) -> Result<FormationMetrics, FormationViolation> {
        if plan.paths.len() != self.robots {
            return Err(FormationViolation::RobotCount {
                plan: plan.paths.len(),
                problem: self.robots,
            });
        }
        self.metrics(plan)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// The hard-capacity test of the sequential planner's reconstruction: S=0, A=1, B=2, G=3;
    /// S–A, A–G length 1 capacity 1; S–B, B–G length 1.5 capacity 3.
    pub(crate) fn diamond(cost: CostModel) -> FormationProblem {
        let pts = vec![[0.0, 0.0], [1.0, 0.0], [0.75, 1.0], [2.0, 0.0]];
        let mut r =
            Roadmap::from_segments(pts, &[(0, 1, 0.5), (1, 3, 0.5), (0, 2, 1.5), (2, 3, 1.5)]);
        for (e, len) in [(0, 1.0), (1, 1.0), (2, 1.5), (3, 1.5)] {
            r.edges[e].length = len;
        }
        // radius 0.4: capacity ⌊w / 1.0⌋ = 1 for width 1, 3 for width 3.
        FormationProblem::new(Arc::new(r), 3, 0, 3, cost, 0.4).unwrap()
    }

    #[test]
    fn timing_waits_and_shares() {
        let p = diamond(CostModel::Hard);
        let plan = FormationPlan {
            paths: vec![vec![0, 1, 3], vec![0, 2, 3], vec![0, 2, 3]],
        };
        let m = p.validate(&plan).unwrap();
        assert_eq!(m.c_max, 3.0);
        assert_eq!(m.sum_of_costs, 2.0 + 3.0 + 3.0);
        assert_eq!(m.distinct_paths, 2);
        let all_a = FormationPlan {
            paths: vec![vec![0, 1, 3]; 3],
        };
        let lanes = diamond(CostModel::default());
        assert_eq!(lanes.validate(&all_a).unwrap().c_max, 4.0); // 2 · (1 + 0.5 · 2)
    }

    /// Issue 27 B: three robots on a corridor that holds one have an infinite cost under the
    /// hard model, and the validator refuses the plan naming the corridor (it used to accept it
    /// with c_max = ∞, written as null).
    #[test]
    fn a_corridor_over_capacity_is_refused_by_name() {
        let p = diamond(CostModel::Hard);
        let all_a = FormationPlan {
            paths: vec![vec![0, 1, 3]; 3],
        };
        let e = p.validate(&all_a).unwrap_err();
        assert_eq!(
            e,
            FormationViolation::OverCapacity {
                from: 0,
                to: 1,
                robots: 3,
                capacity: 1
            }
        );
        assert!(
            e.to_string().contains("corridor 0-1 is over capacity"),
            "{e}"
        );
        assert!(p.evaluate(&all_a.paths).is_err());
        assert!(p.schedule(&all_a.paths).is_err());
        // A 2 + 1 split (two on the wide corridor through B, one through A) fits; two through A
        // do not.
        let ok = FormationPlan {
            paths: vec![vec![0, 2, 3], vec![0, 2, 3], vec![0, 1, 3]],
        };
        assert!(p.validate(&ok).unwrap().c_max.is_finite());
        let two_on_a = FormationPlan {
            paths: vec![vec![0, 2, 3], vec![0, 1, 3], vec![0, 1, 3]],
        };
        assert!(matches!(
            p.validate(&two_on_a).unwrap_err(),
            FormationViolation::OverCapacity {
                from: 0,
                to: 1,
                robots: 2,
                ..
            }
        ));
    }

    #[test]
    fn negative_or_non_finite_kappa_and_bad_radius_are_refused() {
        let r = diamond(CostModel::Waves).roadmap_arc().clone();
        for kappa in [-0.5, f64::INFINITY, f64::NAN] {
            let e = FormationProblem::new(r.clone(), 3, 0, 3, CostModel::Lanes { kappa }, 0.4)
                .unwrap_err();
            assert!(e.contains("kappa"), "{e}");
        }
        assert!(
            FormationProblem::new(r.clone(), 3, 0, 3, CostModel::Lanes { kappa: 0.0 }, 0.4).is_ok()
        );
        for radius in [0.0, -1.0, f64::NAN] {
            assert!(FormationProblem::new(r.clone(), 3, 0, 3, CostModel::Waves, radius).is_err());
        }
    }

    #[test]
    fn every_rule_is_caught() {
        let p = diamond(CostModel::Hard);
        let bad = |paths: Vec<Vec<u32>>| p.validate(&FormationPlan { paths }).unwrap_err();
        assert!(matches!(
            bad(vec![vec![0, 1, 3]; 2]),
            FormationViolation::RobotCount { .. }
        ));
        assert!(matches!(
            bad(vec![vec![0, 1], vec![0, 1, 3], vec![0, 1, 3]]),
            FormationViolation::WrongEnds { robot: 0 }
        ));
        assert!(matches!(
            bad(vec![vec![0, 3], vec![0, 1, 3], vec![0, 1, 3]]),
            FormationViolation::NotAnEdge { robot: 0, .. }
        ));
        assert!(matches!(
            bad(vec![vec![0, 1, 0, 2, 3], vec![0, 1, 3], vec![0, 1, 3]]),
            FormationViolation::Revisit { .. }
        ));
        let e = bad(vec![vec![0, 1, 3], vec![0, 2, 3, 1, 0, 2, 3]]);
        assert!(matches!(e, FormationViolation::RobotCount { .. }));
        // Opposite directions on 1–3 (robot 1 goes 0-2-3-1? not simple ends) built on a square.
        let sq = Roadmap::from_segments(
            vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [2.0, 0.5]],
            &[
                (0, 1, 1.0),
                (1, 2, 1.0),
                (2, 3, 1.0),
                (3, 0, 1.0),
                (1, 4, 1.0),
                (2, 4, 1.0),
            ],
        );
        let q = FormationProblem::new(Arc::new(sq), 2, 0, 4, CostModel::Waves, 0.1).unwrap();
        let e = q
            .validate(&FormationPlan {
                paths: vec![vec![0, 1, 2, 4], vec![0, 3, 2, 1, 4]],
            })
            .unwrap_err();
        assert!(
            matches!(e, FormationViolation::OppositeDirections { a: 0, b: 1, .. }),
            "{e}"
        );
        let ok = q
            .validate(&FormationPlan {
                paths: vec![vec![0, 1, 4], vec![0, 3, 2, 4]],
            })
            .unwrap();
        assert_eq!(ok.distinct_paths, 2);
    }
}
