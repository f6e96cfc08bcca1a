//! The papers' tables and figures as sweeps on the harness: each declares its jobs and its pages
//! (Markdown beside the paper's numbers, CSV, SVG figures).
//!
//! - [`hstar_table2`]: the H* paper's Table II (Enol2023, WHCA*, NSGA-III, H*), on
//!   [`hstar_instances`] (Table I);
//! - [`gp_trees`]: the GP paper's Tables 3–5 (GP vs Push-Swap-Wait), pages in [`gp_pages`];
//! - [`ga_formation`]: the GA formation paper's Fig. 4 (sequential and GA against the optimum).
//! - [`hbmo_navigation`]: the HBMO paper's Figs. 5–12 (HBMO, DE, PSO and ORCA, step by step).

pub mod ga_formation;
pub mod gp_pages;
pub mod gp_trees;
pub mod hbmo_navigation;
pub mod hstar_instances;
pub mod hstar_table2;
