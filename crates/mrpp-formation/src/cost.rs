//! Edge cost vectors `c_e = (c_e(1), …, c_e(R))`: the time `r` robots need to cross corridor `e`
//! together (the GA paper's §2.1: "a cost function that considers the corridor's length and width
//! and the number of robots that cross it"). The paper gives no formula; these are ours, each a
//! named, documented model. Robots move at unit speed, so a lone robot needs `c_e(1) = ℓ_e`.
//!
//! A corridor of width `w_e` (twice its clearance) holds `cap_e = max(1, ⌊w_e / (2ρ + gap)⌋)`
//! robots side by side (ρ = robot radius). Beyond that, the group crosses in `k = ⌈r / cap_e⌉`
//! waves:
//! - [`CostModel::Lanes`] (default, κ = 0.5): `c_e(r) = ℓ_e (1 + κ (k − 1))` — every extra wave
//!   slows the group by a share κ of the corridor's length (the group has to reform into a column
//!   and back). This is what makes narrow corridors worth a split.
//! - [`CostModel::Waves`]: `c_e(r) = ℓ_e + (k − 1)(2ρ + gap)` — waves follow each other at one
//!   robot's spacing (the physical lower bound; splits rarely pay).
//! - [`CostModel::Hard`]: `c_e(r) = ℓ_e` when `r ≤ cap_e`, else `∞` (for tests: capacity is a
//!   wall).
//!
//! Every model is non-decreasing in `r` with `c_e(1) = ℓ_e`, which the exact planner's bounds rely on.

use serde::{Deserialize, Serialize};

use crate::roadmap::RoadEdge;

/// A cost model and its parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "model", rename_all = "lowercase")]
pub enum CostModel {
    /// `ℓ (1 + κ (k − 1))` for `k` waves.
    Lanes {
        #[serde(default = "half")]
        kappa: f64,
    },
    /// `ℓ + (k − 1)(2ρ + gap)`.
    Waves,
    /// `ℓ` within capacity, infinite beyond.
    Hard,
}

fn half() -> f64 {
    0.5
}

impl Default for CostModel {
    fn default() -> Self {
        CostModel::Lanes { kappa: 0.5 }
    }
}

/// The space between robots side by side or one behind the other: half a radius.
pub fn gap(radius: f64) -> f64 {
    radius / 2.0
}

/// How many robots of radius `radius` fit side by side in `edge` (at least 1).
pub fn capacity(edge: &RoadEdge, radius: f64) -> usize {
    ((edge.width() / (2.0 * radius + gap(radius))).floor() as usize).max(1)
}

impl CostModel {
    /// `c_e(r)` for `r ≥ 1` robots crossing `edge` together (0 for `r = 0`).
    pub fn cost(&self, edge: &RoadEdge, r: usize, radius: f64) -> f64 {
        if r == 0 {
            return 0.0;
        }
        let cap = capacity(edge, radius);
        let waves = r.div_ceil(cap) as f64;
        match *self {
            CostModel::Lanes { kappa } => edge.length * (1.0 + kappa * (waves - 1.0)),
            CostModel::Waves => edge.length + (waves - 1.0) * (2.0 * radius + gap(radius)),
            CostModel::Hard if r <= cap => edge.length,
            CostModel::Hard => f64::INFINITY,
        }
    }

    /// A name for outputs: `lanes(κ=0.5)`, `waves`, `hard`.
    pub fn label(&self) -> String {
        match self {
            CostModel::Lanes { kappa } => format!("lanes(kappa={kappa})"),
            CostModel::Waves => "waves".into(),
            CostModel::Hard => "hard".into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn models_start_at_the_length_and_never_decrease() {
        let e = RoadEdge {
            u: 0,
            v: 1,
            length: 10.0,
            clearance: 1.0,
            polyline: vec![],
        };
        // Width 2, radius 0.4: 2 / (0.8 + 0.2) = 2 side by side.
        assert_eq!(capacity(&e, 0.4), 2);
        for m in [CostModel::default(), CostModel::Waves, CostModel::Hard] {
            assert_eq!(m.cost(&e, 1, 0.4), 10.0);
            for r in 1..8 {
                assert!(m.cost(&e, r + 1, 0.4) >= m.cost(&e, r, 0.4));
            }
        }
        assert_eq!(CostModel::default().cost(&e, 3, 0.4), 15.0);
        assert_eq!(CostModel::Waves.cost(&e, 3, 0.4), 11.0);
        assert!(CostModel::Hard.cost(&e, 3, 0.4).is_infinite());
        let m: CostModel = serde_json::from_str(r#"{"model": "lanes"}"#).unwrap();
        assert_eq!(m, CostModel::default());
    }
}
