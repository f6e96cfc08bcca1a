//! Planners for MAPF on 4-connected grids (they work on any [`crate::Graph`] with coordinates):
//! H* (the paper's hybrid greedy planner) and the cooperative A* family (CA*, HCA*, WHCA*).

pub mod coevolution;
pub mod cooperative;
pub mod corridors;
pub mod hstar;
pub mod nsga3;

use crate::error::{Error, Result};
use crate::solve::Planner;

/// What the command line (or an experiment) asks for; unknown names give a clear error.
#[derive(Debug, Clone, Default)]
pub struct PlannerSpec {
    /// `hstar`, `ca`, `hca`, `whca`.
    pub name: String,
    /// WHCA* window (default 8).
    pub window: Option<u32>,
    /// H* variant: `repaired` (default) or `paper`; coevolution: `intended` (default) or
    /// `inverted` (the authors' inverted collision count).
    pub variant: Option<String>,
}

/// Names accepted by [`build_planner`].
pub const PLANNER_NAMES: &[&str] = &["hstar", "ca", "hca", "whca", "coevolution", "nsga3"];

/// Builds the planner a spec names; options that do not apply to it are refused, not ignored.
pub fn build_planner(spec: &PlannerSpec) -> Result<Box<dyn Planner>> {
    let refuse = |opt: &str| {
        Err(Error::Param(format!(
            "--{opt} does not apply to planner `{}`",
            spec.name
        )))
    };
    match spec.name.as_str() {
        "hstar" => {
            if spec.window.is_some() {
                return refuse("window");
            }
            let variant = match spec.variant.as_deref() {
                None | Some("repaired") => hstar::Variant::Repaired,
                Some("paper") => hstar::Variant::Paper,
                Some(other) => {
                    return Err(Error::Param(format!(
                        "unknown H* variant `{other}` (known: repaired, paper)"
                    )));
                }
            };
            Ok(Box::new(hstar::HStar {
                variant,
                ..hstar::HStar::default()
            }))
        }
        "ca" | "hca" | "whca" => {
            if spec.variant.is_some() {
                return refuse("variant");
            }
            match (spec.name.as_str(), spec.window) {
                ("ca", None) => Ok(Box::new(cooperative::Cooperative::ca())),
                ("hca", None) => Ok(Box::new(cooperative::Cooperative::hca())),
                ("whca", None) => Ok(Box::new(cooperative::Cooperative::whca(
                    cooperative::DEFAULT_WINDOW,
                ))),
                ("whca", Some(w)) if (1..=10_000).contains(&w) => {
                    Ok(Box::new(cooperative::Cooperative::whca(w)))
                }
                ("whca", Some(w)) => Err(Error::Param(format!(
                    "--window must be between 1 and 10000, got {w}"
                ))),
                _ => refuse("window"),
            }
        }
        "coevolution" => {
            if spec.window.is_some() {
                return refuse("window");
            }
            let inverted_fitness = match spec.variant.as_deref() {
                None | Some("intended") => false,
                Some("inverted") => true,
                Some(other) => {
                    return Err(Error::Param(format!(
                        "unknown coevolution variant `{other}` (known: intended, inverted)"
                    )));
                }
            };
            Ok(Box::new(coevolution::Coevolution {
                inverted_fitness,
                ..coevolution::Coevolution::default()
            }))
        }
        "nsga3" => {
            if spec.window.is_some() {
                return refuse("window");
            }
            if spec.variant.is_some() {
                return refuse("variant");
            }
            Ok(Box::new(nsga3::Nsga3Planner::default()))
        }
        other => Err(Error::Param(format!(
            "unknown planner `{other}` (known: {})",
            PLANNER_NAMES.join(", ")
        ))),
    }
}
