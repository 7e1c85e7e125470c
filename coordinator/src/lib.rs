//! The fixplan command line and, later, the coordinator of distributed runs.

pub mod solve_cmd;
