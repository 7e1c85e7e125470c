//! Distributed runs: the coordinator's side of the cluster. Parts are cut
//! into shards ([`crate::job::shards`]), served to workers (`fixplan
//! worker`, crate `fixplan-worker`) over zenoh or iceoryx2 shared memory on
//! this host, checked and merged into the same bytes as the embedded run.
//! Uses `job` and the core and worker crates; knows nothing of catalogues
//! or results files.
//!
//! - [`distributed`]: parts in, merged results out ([`run_distributed`]:
//!   a [`MergedPart`] or a [`PartFailure`] for each);
//! - [`scheduler`]: queue, leases, workers, merging (transport-free);
//! - [`verify`]: the checks of a shard result and how many are re-derived;
//! - [`runtime`]: zenoh queryables, liveliness, iceoryx2 server, leases;
//! - [`local`]: worker processes on this host (`fixplan run --workers N`);
//! - [`options`]: how a cluster run is set up; [`cpu_time`]: CPU clocks;
//! - `certs` (feature `tls`): the certificates of mutual TLS
//!   (`fixplan certs`).

#[cfg(feature = "tls")]
pub(crate) mod certs;
pub(crate) mod cpu_time;
pub(crate) mod distributed;
pub(crate) mod local;
pub(crate) mod options;
pub(crate) mod runtime;
pub(crate) mod scheduler;
pub(crate) mod verify;

pub use distributed::{
    run_distributed, run_distributed_finishing, Distributed, MergedPart, Returned,
};
pub use fixplan_worker::part_input::PartInput;
pub use fixplan_worker::protocol::TransportChoice;
pub use options::{ClusterError, ClusterOptions};
pub use scheduler::PartFailure;
pub use verify::VerifyPolicy;
