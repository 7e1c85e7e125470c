//! Runs shards (combination ranges) of prepared parts. The embedded run and
//! the distributed workers go through this one entry point ([`run_shard`])
//! so that both produce the same bytes.
//!
//! The distributed side:
//! - [`protocol`]: versioned messages and their framing;
//! - [`part_input`]: a part's inputs on the wire, and its digest;
//! - [`zenoh_link`]: zenoh configuration (TLS files), key expressions,
//!   request/reply;
//! - [`exposure`]: which listen endpoints let other hosts join, refused
//!   without TLS unless `--insecure`;
//! - [`iox`]: iceoryx2 request/reply through shared memory on one host;
//! - [`agent`]: the `fixplan worker` loop;
//! - [`task`]: what a worker is asked ([`protocol::Task`]), read and
//!   done in one place, and the [`task::Runner`] seam around it;
//! - [`finish`]: the [`finish::Finisher`] that turns a part's result into
//!   the coordinator's bytes;
//! - [`in_flight`]: the tasks a worker runs while it asks for more;
//! - [`host`]: host ids and unique names.
//!
//! Library code only emits `tracing` events; the `fixplan` binary (crate
//! `fixplan-coordinator`) installs the subscriber, and gives its workers
//! their finisher and, in tests and benchmarks, a [`task::Runner`] of its
//! own (faults, replayed results).

pub mod agent;
pub mod exposure;
pub mod finish;
pub mod host;
pub mod in_flight;
pub mod iox;
pub mod part_input;
pub mod protocol;
pub mod task;
pub mod zenoh_link;

use fixplan_core::{PartialResult, PreparedPart};
use std::ops::Range;

/// Enumerates a shard on the current rayon pool.
pub fn run_shard(prep: &PreparedPart, range: Range<u64>) -> PartialResult {
    prep.enumerate_range(range)
}

/// [`run_shard`] within a part's work budget (shared by its shards): the
/// shard's result, and the budget that stopped it if one did (its result
/// is then incomplete; the part is `over_budget`).
pub fn run_shard_within(
    prep: &PreparedPart,
    range: Range<u64>,
    budget: &fixplan_core::WorkBudget,
) -> (PartialResult, Option<fixplan_core::BudgetHalt>) {
    let options = fixplan_core::EnumerateOptions {
        budget: Some(budget),
        ..Default::default()
    };
    let done = prep.enumerate(range, options);
    (done.result, done.halted)
}

/// Enumerates a shard, or with `good_enough` the shortest prefix of it that
/// admits a fixture scoring that or better (the hit index with it): the
/// prefixes of a part's shards merge into the embedded run's
/// [`PreparedPart::enumerate`] result.
pub fn run_shard_until(
    prep: &PreparedPart,
    range: Range<u64>,
    good_enough: Option<f64>,
) -> (PartialResult, Option<u64>) {
    let options = fixplan_core::EnumerateOptions {
        good_enough,
        ..Default::default()
    };
    let done = prep.enumerate(range, options);
    (done.result, done.stopped_at)
}

/// The message of a caught panic, for the part's `invalid` result: a bug
/// in one part's enumeration must not end the run, but must be reported.
pub fn panic_text(payload: Box<dyn std::any::Any + Send>) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into())
}
