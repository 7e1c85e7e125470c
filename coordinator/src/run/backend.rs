//! What a run solves and where: the jobs (a catalogue part with the kit
//! and parameters it is solved with) and the backend that solves them.

use crate::cluster::ClusterOptions;
use crate::job::solve_part::Preparation;
use crate::job::JobContext;
use bytes::Bytes;
use fixplan_catalog::CatalogPart;

/// Where the enumeration runs.
// One per run: the size of the cluster variant does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone)]
pub enum Backend {
    /// Threads of this process (default: all cores).
    Embedded {
        /// Threads of the pool.
        threads: Option<usize>,
    },
    /// The workers of a cluster (`--workers N`, `fixplan coordinator`).
    Cluster(ClusterOptions),
}

impl Backend {
    /// Threads of the embedded pool, or the worker threads a cluster
    /// expects (a coordinator's setting, else its local workers'); what
    /// the run's first log line reports.
    pub fn threads(&self) -> usize {
        match self {
            Backend::Embedded { threads } => threads.unwrap_or_else(crate::job::threads::cores),
            Backend::Cluster(c) => c
                .expected_threads
                .unwrap_or(c.worker_threads.unwrap_or(1) * c.local_workers.max(1)),
        }
    }
}

/// What a worker needs to finish job `i` itself ([`fixplan_worker::finish`]);
/// `None`: the caller finishes it.
pub type RemoteContext<'a> = dyn Fn(usize) -> Option<Vec<u8>> + Sync + 'a;

/// Jobs finished by the workers of a cluster: what each needs, the
/// workers' finisher (the coordinator checks finished parts with it), and
/// what the caller keeps of a job its worker finished.
pub struct RemoteFinish<'a, T> {
    /// What the worker of job `i` is sent to finish it.
    pub context: &'a RemoteContext<'a>,
    /// The workers' finisher.
    pub finisher: std::sync::Arc<dyn fixplan_worker::finish::Finisher>,
    /// What the caller keeps of job `i` finished by its worker: made from
    /// the finisher's bytes, to be copied.
    pub keep: &'a (dyn Fn(usize, Bytes) -> T + Sync),
}

/// One part to solve: the catalogue entry, the run inputs it is solved
/// with, and how to prepare it.
pub struct PartJob<'a> {
    /// The catalogue entry.
    pub part: &'a CatalogPart,
    /// Kit, parameters, unit, shard size and search of this job.
    pub ctx: &'a JobContext<'a>,
    /// Prepare here, or derive from a part prepared for another kit.
    pub preparation: Preparation<'a>,
}
