//! The fixplan command line and the coordinator of distributed runs.
//!
//! A part's path through the code, from catalogue file to MCAP message:
//! `fixplan-catalog` reads it; [`run`] makes it a job and hands it to a
//! backend (threads here, or [`cluster`] workers), which solves it through
//! [`job`] (shards, grid steps, merge); [`run`] turns the result into the
//! part's messages ([`output`], with the scene of [`view`]) and writes them
//! in catalogue order. [`study`] runs many kits through the same path,
//! [`mod@bench`] measures it, and [`cli`] is the command line over all of it.
//! Imports flow one way: `cli` -> `bench`, `study` -> `run` -> `cluster`,
//! `view` -> `output` -> `job` (`scripts/import_cycles.py` checks it).

pub mod bench;
pub mod cli;
pub mod cluster;
pub mod drawing;
pub mod job;
pub mod output;
pub mod run;
pub mod study;
pub mod view;
