//! The verbs every family shares, each written once: the family comes from the planner name
//! (`solve`) or from the inputs (`validate`, `info`, `render`).

use std::path::Path;

use crate::family::{Inputs, SolveRequest, family_of_inputs, family_of_planner};
use crate::output::Fail;

/// `mrpp solve`: plans, exit 0 solved (a valid plan), 3 not solved, 1 bad input or an invalid
/// plan (a bug).
pub(crate) fn solve(req: &SolveRequest) -> Result<u8, Fail> {
    family_of_planner(&req.planner)?.solve(req)
}

/// `mrpp validate`: exit 0 when the plan is valid, 1 naming the first violation.
pub(crate) fn validate(inputs: &Inputs, plan: &Path) -> Result<u8, Fail> {
    family_of_inputs(inputs)?.validate(inputs, plan)
}

/// `mrpp info`: what the family can say about an instance (sizes, lower bounds).
pub(crate) fn info(inputs: &Inputs) -> Result<u8, Fail> {
    family_of_inputs(inputs)?.info(inputs)
}

/// `mrpp render`: a picture of a plan.
pub(crate) fn render(inputs: &Inputs, plan: &Path, out: &Path) -> Result<u8, Fail> {
    family_of_inputs(inputs)?.render(inputs, plan, out)
}
