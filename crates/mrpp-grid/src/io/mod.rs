//! Grid plan files: the plan envelope with `[x, y]` cells, the MAPF Tracker result CSV, the
//! LaCAM/PIBT text result that MAPF visualizers read, and an SVG picture of a plan.

pub mod lacam;
pub mod plan_json;
pub mod render;
pub mod tracker;
