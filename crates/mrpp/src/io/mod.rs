//! Plan files: mrpp's JSON plan, the LaCAM/PIBT text result, and an SVG picture of a plan.

pub mod lacam;
pub mod plan_json;
pub mod render;
