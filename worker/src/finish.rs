//! Workers that finish parts. A part enumerated as one shard can be
//! turned into what the results file holds right where it was solved, and
//! a part cut into shards on the worker handed its merged result
//! ([`crate::protocol::Assign::finish_from`]), so the coordinator only
//! checks a sample and copies bytes: building the
//! report, the messages and compressing them was most of the coordinator's
//! work per part, and what capped the workers one coordinator serves.
//!
//! What a finished part is belongs to the coordinator (its messages, the
//! results file); this crate only carries it: the coordinator's binary
//! gives its worker loop a [`Finisher`], and the bytes travel opaque in
//! [`crate::protocol::Assign::finish`] and
//! [`crate::protocol::ShardDone::finished`].

use crate::part_input::PartInput;
use fixplan_core::{PartialResult, PreparedPart};

/// Turns a part's enumeration into the coordinator's bytes.
pub trait Finisher: Send + Sync {
    /// The finished part, from its input, prepared part, its result (of
    /// its one shard, whatever range that shard was labelled with, or its
    /// shards merged), the enumeration's time, and the
    /// coordinator's `context` ([`crate::protocol::Assign::finish`]). An
    /// error is logged by the coordinator, which then finishes the part
    /// itself.
    fn finish(
        &self,
        input: &PartInput,
        prep: &PreparedPart,
        result: &PartialResult,
        micros: u64,
        context: &[u8],
    ) -> Result<Vec<u8>, String>;

    /// Whether a worker's finished part (`theirs`) holds what finishing
    /// the same inputs here makes ([`Finisher::finish`]'s arguments): how
    /// the coordinator checks a finished part whose result it re-derived.
    /// The error says what differs.
    fn check(
        &self,
        input: &PartInput,
        prep: &PreparedPart,
        result: &PartialResult,
        micros: u64,
        context: &[u8],
        theirs: &[u8],
    ) -> Result<(), String>;
}
