//! How a cluster run is set up, and why it can fail to start.

use super::verify::VerifyPolicy;
use fixplan_worker::protocol::TransportChoice;
use fixplan_worker::zenoh_link::ZenohOptions;
use std::path::PathBuf;
use std::time::Duration;
use thiserror::Error;

#[derive(Debug, Error)]
pub enum ClusterError {
    #[error("zenoh: {0}")]
    Zenoh(String),
    #[error("iceoryx2: {0}")]
    Iceoryx2(String),
    #[error("cannot start a local worker: {0}")]
    Spawn(String),
    #[error("{0}")]
    Link(#[from] fixplan_worker::zenoh_link::LinkError),
    #[error("part {0}: {1}")]
    Input(usize, String),
}

/// How to run the coordinator.
#[derive(Debug, Clone)]
pub struct ClusterOptions {
    /// Listen/connect endpoints, mode and config file. With no endpoint at
    /// all and local workers, a private unix socket is used.
    pub zenoh: ZenohOptions,
    /// Key-expression prefix of the run (several runs can share a network).
    pub key_prefix: String,
    pub transport: TransportChoice,
    /// Workers to wait for before handing out the first shard.
    pub min_workers: usize,
    /// Combinations per shard (default: from the cost estimate).
    pub shard_size: Option<u64>,
    /// How long a shard may stay with one worker.
    pub lease: Duration,
    /// Worker processes to start on this host.
    pub local_workers: usize,
    /// Threads of each local worker (default: cores / local workers).
    pub worker_threads: Option<usize>,
    /// The `fixplan` executable for local workers (default: this one).
    pub worker_exe: Option<PathBuf>,
    /// Worker threads expected in all, for the shard sizes (default: the
    /// local workers' threads, or this host's cores).
    pub expected_threads: Option<usize>,
    /// Less logging (local workers too).
    pub quiet: bool,
    /// How much of each result is re-derived before it is merged.
    pub verify: VerifyPolicy,
    /// `--good-enough`: every part stops at its first combination that
    /// admits a fixture scoring this or better (the embedded run's rule).
    pub good_enough: Option<f64>,
}

impl Default for ClusterOptions {
    fn default() -> Self {
        ClusterOptions {
            zenoh: ZenohOptions::default(),
            key_prefix: "fixplan".into(),
            transport: TransportChoice::Auto,
            min_workers: 1,
            shard_size: None,
            lease: Duration::from_secs(300),
            local_workers: 0,
            worker_threads: None,
            worker_exe: None,
            expected_threads: None,
            quiet: false,
            verify: VerifyPolicy::default(),
            good_enough: None,
        }
    }
}
