//! Discrete graph MAPF, shared by the grid and tree families: a graph (CSR, optional cell
//! coordinates), an instance (one start and one goal vertex per agent), the [`Rules`] (goal
//! semantics `stay`/`visit`, following allowed or not), plans, the validator and its metrics, and
//! the shared single-agent searches.
//!
//! [`MapfProblem`] is the [`Problem`](crate::contract::Problem) both families plan on; the rules
//! are owned by the problem, so one validator judges grid plans (`stay`) and tree plans (`visit`).

pub mod graph;
pub mod instance;
pub mod plan;
pub mod plan_file;
pub mod search;

use std::sync::Arc;

use crate::contract::Problem;
use graph::Graph;
use instance::Instance;
use plan::{Metrics, Plan, Rules, Violation};

/// A MAPF problem: a graph, the agents' starts and goals on it, and the rules plans obey.
#[derive(Debug, Clone)]
pub struct MapfProblem {
    graph: Arc<Graph>,
    instance: Instance,
    rules: Rules,
}

impl MapfProblem {
    /// A problem on `graph`.
    ///
    /// # Errors
    /// A message when a start or goal is not a vertex of `graph`.
    pub fn new(graph: Arc<Graph>, instance: Instance, rules: Rules) -> Result<Self, String> {
        let n = graph.num_vertices();
        for (i, (&s, &g)) in instance.starts.iter().zip(&instance.goals).enumerate() {
            if s as usize >= n || g as usize >= n {
                return Err(format!(
                    "agent {i}: start or goal is not one of the graph's {n} vertices"
                ));
            }
        }
        Ok(MapfProblem {
            graph,
            instance,
            rules,
        })
    }
    /// A problem on a copy of `graph` and `instance` (for tests and one-off uses; planners and
    /// experiments share the graph through [`MapfProblem::new`]).
    ///
    /// # Panics
    /// When a start or goal is not a vertex of `graph`.
    pub fn on(graph: &Graph, instance: &Instance, rules: Rules) -> Self {
        MapfProblem::new(Arc::new(graph.clone()), instance.clone(), rules)
            .expect("starts and goals are vertices of the graph")
    }
    pub fn graph(&self) -> &Graph {
        &self.graph
    }
    /// The shared graph (cheap to clone).
    pub fn graph_arc(&self) -> &Arc<Graph> {
        &self.graph
    }
    pub fn instance(&self) -> &Instance {
        &self.instance
    }
    pub fn rules(&self) -> Rules {
        self.rules
    }
}

/// A broken rule with its description in the graph's terms (cells on grids, `#id` otherwise).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MapfViolation {
    pub violation: Violation,
    pub text: String,
}

impl std::fmt::Display for MapfViolation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.text)
    }
}

impl Problem for MapfProblem {
    type Plan = Plan;
    type Metrics = Metrics;
    type Violation = MapfViolation;

    fn num_agents(&self) -> usize {
        self.instance.num_agents()
    }

    /// Distinct starts, distinct goals (vertices of the graph by construction).
    fn instance_rules(&self) -> Result<(), String> {
        self.instance.check()
    }

    /// Each agent alone on the graph: the sum and the largest of the start-goal distances
    /// bound the sum of costs and the makespan (none when a goal cannot be reached).
    fn lower_bounds(&self) -> Vec<(&'static str, f64)> {
        let i = &self.instance;
        match search::distance::lower_bounds(&self.graph, &i.starts, &i.goals) {
            Ok((sum, max)) => vec![("sum_of_costs", sum as f64), ("makespan", max as f64)],
            Err(_) => Vec::new(),
        }
    }

    fn validate(&self, plan: &Plan) -> Result<Metrics, MapfViolation> {
        plan::judge(&self.graph, &self.instance, self.rules, plan).map_err(|violation| {
            MapfViolation {
                text: violation.describe(&self.graph),
                violation,
            }
        })
    }

    /// Drops trailing repeats of each path's final vertex.
    fn canonical(&self, mut plan: Plan) -> Plan {
        plan.trim();
        plan
    }
}
