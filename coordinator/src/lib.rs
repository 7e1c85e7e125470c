//! The fixplan command line and the coordinator of distributed runs.
//!
//! A part's path through the code, from catalogue file to MCAP message:
//! `fixplan-catalog` reads it; `run` makes it a job and hands it to a
//! backend (threads here, or `cluster` workers), which solves it through
//! `job` (shards, grid steps, merge); `run` turns the result into the
//! part's messages (`output`, with the scene of `view`) and writes them
//! in catalogue order. `study` runs many kits through the same path,
//! `bench` measures it, and `cli` is the command line over all of it.
//! Imports flow one way: `cli` -> `bench`, `study` -> `run` -> `cluster`,
//! `view` -> `output` -> `job` (`scripts/import_cycles.py` checks it).
//!
//! The modules are the crate's own: what other crates use is the short
//! list re-exported below, for the two binaries (`fixplan` and the tests
//! crate's copy, [`main`]) and the workspace's integration tests, which
//! drive runs, clusters and studies as a library and read the files back.

// The re-exported items' docs point into the crate's private modules (the
// channels, checks and conversions they rely on): written for whoever
// works on the crate, and resolved by `cargo doc --document-private-items`.
#![allow(rustdoc::private_intra_doc_links)]

mod bench;
mod cli;
mod cluster;
mod drawing;
mod interrupt;
mod job;
mod output;
mod run;
mod study;
mod view;

/// The command line: what both binaries run.
pub use cli::main;

/// Catalogue runs: options, where the parts are solved, the default
/// catalogue, the results file of an interrupted run, and the slices of a
/// run split across machines.
pub use run::{
    backend::Backend,
    default_catalog,
    resume::partial_path,
    run_catalog, run_parts,
    slice::{merge_files, Slice},
    RunOptions,
};

/// How a part's search walks grid steps (`--grid-steps`, `--good-enough`).
pub use job::SearchOptions;

/// Distributed runs driven directly (the cluster tests).
pub use cluster::{
    run_distributed, scheduler::Stats, ClusterOptions, Distributed, PartInput, TransportChoice,
    VerifyPolicy,
};

/// The certificates of mutual TLS (`fixplan certs`).
#[cfg(feature = "tls")]
pub use cluster::certs::{Authority, Issued, Validity, COORDINATOR_CN, ROUTER_CN, WORKER_CN};

/// The results file: reading it back, its channels and message types,
/// and the schemas the viewers check them against.
pub use output::{
    fields::{KitField, ParamsField, StatusName},
    messages::{
        PartMsg, StepField, METADATA_RUN, NS_PER_PART, TOPIC_FIXTURES, TOPIC_PART, TOPIC_RUN,
        TOPIC_SCENE,
    },
    reader::Contents,
    schemas::{viewer_refusals, FOXGLOVE_SCENE_UPDATE},
    PartMessages, PartRecord, ResultsFile,
};

/// `fixplan show`, `export` and `render` as functions.
pub use view::{
    render::render,
    show::{export_json, show},
};

/// Kit studies and their file.
pub use study::{median, nearest_rank, read_mcap, study_kits, StudyKitMsg};

/// The throughput ceiling benchmark (`fixplan bench ceiling`) and the
/// replay of a recorded run.
pub use bench::{
    ceiling::{run_once, CeilingArgs},
    replay::Replay,
};
