//! Problem instances: one start and one goal vertex per agent on a
//! [`Graph`](crate::mapf::graph::Graph). Two agents may share neither a start nor a goal. File
//! formats that describe instances (MovingAI `.scen`, tree JSON, ...) live in the family crates.

use rustc_hash::FxHashMap;

use crate::mapf::graph::VertexId;

/// Starts and goals of the agents, as vertex ids.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Instance {
    pub starts: Vec<VertexId>,
    pub goals: Vec<VertexId>,
}

impl Instance {
    /// Checks lengths and uniqueness; used by every constructor and by generated instances.
    pub fn new(starts: Vec<VertexId>, goals: Vec<VertexId>) -> std::result::Result<Self, String> {
        let inst = Instance { starts, goals };
        inst.check()?;
        Ok(inst)
    }

    /// Equal numbers of starts and goals, no two agents on one start, none sharing a goal.
    ///
    /// # Errors
    /// The first rule broken, naming the agents (0-based).
    pub fn check(&self) -> std::result::Result<(), String> {
        if self.starts.len() != self.goals.len() {
            return Err(format!(
                "{} starts but {} goals",
                self.starts.len(),
                self.goals.len()
            ));
        }
        for (what, list) in [("start", &self.starts), ("goal", &self.goals)] {
            let mut seen = FxHashMap::default();
            for (i, &v) in list.iter().enumerate() {
                if let Some(j) = seen.insert(v, i) {
                    return Err(format!("agents {j} and {i} share a {what}"));
                }
            }
        }
        Ok(())
    }

    pub fn num_agents(&self) -> usize {
        self.starts.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_and_uniqueness_are_checked() {
        assert!(Instance::new(vec![0, 1], vec![1, 0]).is_ok());
        assert!(
            Instance::new(vec![0], vec![1, 0])
                .unwrap_err()
                .contains("1 starts")
        );
        assert!(
            Instance::new(vec![0, 0], vec![1, 2])
                .unwrap_err()
                .contains("share a start")
        );
        assert!(
            Instance::new(vec![0, 1], vec![2, 2])
                .unwrap_err()
                .contains("share a goal")
        );
    }
}
