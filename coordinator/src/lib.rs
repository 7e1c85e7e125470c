//! The fixplan command line and the coordinator of distributed runs.
//!
//! - [`run`]: `fixplan run`, whole catalogues into an MCAP results file;
//! - [`part_job`]: one part through the shard/merge path of the workers;
//! - [`mcap_out`], [`results`], [`messages`]: writing and reading results;
//! - [`scene`], [`draw`], [`render`]: Foxglove scenes and SVG pictures;
//! - [`show`]: tables and JSON lines from a results file;
//! - [`bench_cmd`]: `fixplan bench`, where the enumeration spends its time;
//! - [`cluster`]: the coordinator and workers of distributed runs.

pub mod bench_cmd;
pub mod cli;
pub mod cluster;
pub mod draw;
pub mod mcap_out;
pub mod messages;
pub mod part_job;
pub mod progress;
pub mod refine;
pub mod render;
pub mod results;
pub mod run;
pub mod scene;
pub mod show;
pub mod solve_cmd;
pub mod study;
pub mod study_cli;
pub mod sweep;
