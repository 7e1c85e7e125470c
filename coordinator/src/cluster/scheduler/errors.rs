//! Why the scheduler says no: to a whole message ([`Refusal`], answered
//! with a refusal frame), to one outcome of a report ([`NotTaken`], a
//! note in the reply), and why a part has no result ([`PartFailure`], the
//! part's message in the results file). The texts reach workers, logs and
//! results files: they read as they always did.

use crate::cluster::verify::CheckError;
use fixplan_core::PrepareError;
use fixplan_worker::protocol::{BudgetStop, TaskError};
use thiserror::Error;

/// Why a whole message is refused. A worker prints it and exits, so it
/// says what the worker would have to change.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum Refusal {
    /// A worker caught sending a bad result gets nothing more this run.
    #[error("refused: worker {0} sent results that failed verification")]
    Banned(String),
    /// Only a coordinator sends welcomes and replies.
    #[error("refused: unexpected message")]
    Unexpected,
    /// `--transport iceoryx2` on either side, but shared memory does not
    /// reach another host.
    #[error("refused: iceoryx2 transport forced, but the worker is not on the coordinator's host")]
    IoxOnAnotherHost,
}

/// Why one outcome of a report was not taken (the worker reads
/// `shard N not taken: ...` and carries on, unless it was rejected).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum NotTaken {
    /// A shard id this run never handed out.
    #[error("unknown shard")]
    UnknownShard,
    /// A result for a shard done already (its lease ran out and another
    /// worker was first): the first result wins.
    #[error("duplicate: this shard is already done")]
    Duplicate,
    /// A failure reported for a shard done already.
    #[error("duplicate")]
    DuplicateFailure,
    /// The result failed its checks, and its worker is banned.
    #[error("rejected: {0}")]
    Rejected(#[from] CheckError),
}

/// Why a part has no merged result. Its text is the embedded run's
/// message for the part, without the part's name.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum PartFailure {
    /// The part cannot be prepared: bad outline, kit or parameters.
    #[error(transparent)]
    Prepare(#[from] PrepareError),
    /// A worker's enumeration failed (`internal error in the enumeration:
    /// ...`): its error as it came over the wire.
    #[error(transparent)]
    Worker(#[from] TaskError),
    /// Workers died (or their lease ran out) holding its shards twice: it
    /// is not handed out again.
    #[error("killed or timed out {workers} workers while being solved ({alone} of them holding nothing else); not handed out again")]
    Killed {
        /// Workers lost or timed out holding one of its shards.
        workers: u32,
        /// Of those, workers that held nothing but that shard.
        alone: u32,
    },
    /// Beyond `--part-setups` or `--part-seconds`
    /// ([`super::budget`]); the run words it as the embedded run does.
    #[error("over its work budget: {0}")]
    OverBudget(BudgetStop),
}

impl PartFailure {
    /// The part's status: `invalid` when the input cannot be prepared (the
    /// embedded run's verdict), `failed` when the solving failed.
    pub fn status(&self) -> fixplan_core::Status {
        match self {
            PartFailure::Prepare(_) => fixplan_core::Status::Invalid,
            PartFailure::Worker(_) | PartFailure::Killed { .. } => fixplan_core::Status::Failed,
            PartFailure::OverBudget(_) => fixplan_core::Status::OverBudget,
        }
    }
}
