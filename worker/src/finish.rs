//! Workers that finish parts. A part enumerated whole can be turned into
//! what the results file holds right where it was solved
//! ([`crate::protocol::Task::EnumerateAndFinish`]), and a part cut into
//! shards on the worker handed its merged result
//! ([`crate::protocol::Task::Finish`]), so the coordinator only checks a
//! sample and copies bytes: building the report, the messages and
//! compressing them was most of the coordinator's work per part, and what
//! capped the workers one coordinator serves.
//!
//! What a finished part is belongs to the coordinator (its messages, the
//! results file); this crate only carries it: the coordinator's binary
//! gives its worker loop a [`Finisher`], and the bytes travel opaque in the
//! tasks' `context` and in [`crate::protocol::Answer`].

use crate::part_input::PartInput;
use crate::protocol::FinishError;
use fixplan_core::{PartialResult, PreparedPart};

/// Everything a part is finished from: the same for the worker that
/// finishes it and for the coordinator that checks the worker's bytes.
#[derive(Debug, Clone, Copy)]
pub struct FinishInputs<'a> {
    /// The part, kit, parameters and unit, as the coordinator sent them.
    pub input: &'a PartInput,
    /// The part prepared from `input`.
    pub prep: &'a PreparedPart,
    /// Its enumeration: of its one shard (whatever range that shard was
    /// labelled with), or its shards merged.
    pub result: &'a PartialResult,
    /// The time the enumeration took, for the part's timing.
    pub micros: u64,
    /// What the coordinator sent besides (its place and entry in the
    /// catalogue), opaque to the worker.
    pub context: &'a [u8],
}

/// Turns a part's enumeration into the coordinator's bytes.
pub trait Finisher: Send + Sync {
    /// The finished part. An error goes back to the coordinator, which
    /// then finishes the part itself.
    fn finish(&self, inputs: &FinishInputs) -> Result<Vec<u8>, FinishError>;

    /// Whether a worker's finished part (`theirs`) holds what
    /// [`Finisher::finish`] makes of the same inputs here: how the
    /// coordinator checks a finished part whose result it re-derived. The
    /// error says what differs.
    fn check(&self, inputs: &FinishInputs, theirs: &[u8]) -> Result<(), FinishError>;
}

impl std::fmt::Debug for dyn Finisher {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        formatter.write_str("Finisher")
    }
}
