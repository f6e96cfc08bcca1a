//! Plan files: mrpp's JSON plan, the LaCAM/PIBT text result, an SVG picture of a plan, and the
//! JSON plan of a tree problem.

pub mod lacam;
pub mod plan_json;
pub mod render;
pub mod tree_plan_json;
