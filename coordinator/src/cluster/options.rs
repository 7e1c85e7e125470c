//! How a cluster run is set up, and why it can fail to start.

use super::verify::VerifyPolicy;
use fixplan_worker::part_input::InputError;
use fixplan_worker::protocol::TransportChoice;
use fixplan_worker::zenoh_link::{LinkError, ZenohOptions};
use std::path::PathBuf;
use std::time::Duration;
use thiserror::Error;

/// Why a cluster run could not start.
#[derive(Debug, Error)]
pub enum ClusterError {
    /// The coordinator's queryables, liveliness subscriber or token.
    #[error("zenoh: {0}")]
    Zenoh(#[source] zenoh::Error),
    /// The iceoryx2 server stopped before it was up.
    #[error("iceoryx2: {0}")]
    Iceoryx2(#[source] LinkError),
    /// The iceoryx2 server did not say it was up in time.
    #[error("iceoryx2: the server did not start")]
    Iceoryx2Timeout,
    /// `--workers N`: a worker process would not start.
    #[error("cannot start a local worker: {0}")]
    Spawn(#[source] std::io::Error),
    /// `--workers N` with no endpoint the workers could connect to.
    #[error("cannot start a local worker: no endpoint for the local workers")]
    NoEndpoint,
    /// The zenoh session would not open (configuration, endpoints).
    #[error("{0}")]
    Link(#[from] LinkError),
    /// A part that cannot be encoded for the workers: no worker could
    /// run it, so the run does not start.
    #[error("part {0}: {1}")]
    Input(usize, #[source] InputError),
}

/// How to run the coordinator.
#[derive(Debug, Clone)]
pub struct ClusterOptions {
    /// Listen/connect endpoints, mode and config file. With no endpoint at
    /// all and local workers, a private unix socket is used.
    pub zenoh: ZenohOptions,
    /// Key-expression prefix of the run (several runs can share a network).
    pub key_prefix: String,
    /// `auto` (iceoryx2 shared memory for workers on this host, zenoh for
    /// the others), or one of them forced.
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
    /// Workers the iceoryx2 server serves at once (default: the local
    /// workers, at least [`fixplan_worker::iox::DEFAULT_CLIENTS`]); more
    /// workers on this host fall back to zenoh.
    pub iox_clients: Option<usize>,
    /// Less logging (local workers too).
    pub quiet: bool,
    /// How much of each result is re-derived before it is merged.
    pub verify: VerifyPolicy,
    /// `--good-enough`: every part stops at its first combination that
    /// admits a fixture scoring this or better (the embedded run's rule).
    pub good_enough: Option<f64>,
    /// `--part-setups`: a part with more setups is `over_budget` (the
    /// embedded run's verdict, whatever the workers).
    pub part_setups: Option<u64>,
    /// `--part-fixtures`: a part keeping more fixtures is `over_budget`
    /// (the embedded run's verdict, whatever the workers).
    pub part_fixtures: Option<u64>,
    /// `--part-seconds`: a part still enumerating this long after its
    /// first task went out is `over_budget` (the coordinator's clock).
    pub part_seconds: Option<f64>,
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
            iox_clients: None,
            quiet: false,
            verify: VerifyPolicy::default(),
            good_enough: None,
            part_setups: None,
            part_fixtures: None,
            part_seconds: None,
        }
    }
}
