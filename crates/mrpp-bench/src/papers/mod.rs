//! Paper tables and figures, each a function returning rows (the CLI writes files and draws).

pub mod gp_trees;
pub mod hstar_instances;
pub mod hstar_table2;
