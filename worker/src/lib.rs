//! Runs shards (combination ranges) of prepared parts. The embedded run and
//! the distributed workers go through this one entry point ([`run_shard`])
//! so that both produce the same bytes.
//!
//! The distributed side:
//! - [`protocol`]: versioned messages and their framing;
//! - [`part_input`]: a part's inputs on the wire, and its digest;
//! - [`zenoh_link`]: zenoh configuration, key expressions, request/reply;
//! - [`iox`]: iceoryx2 request/reply through shared memory on one host;
//! - [`agent`]: the `fixplan worker` loop;
//! - [`host`]: host ids and unique names; [`log`]: log lines.

pub mod agent;
pub mod host;
pub mod iox;
pub mod log;
pub mod part_input;
pub mod protocol;
pub mod zenoh_link;

use fixplan_core::{PartialResult, PreparedPart};
use std::ops::Range;

/// One unit of work: a range of one part's segment combinations.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Shard {
    pub part: String,
    pub range: Range<u64>,
}

/// Enumerates a shard on the current rayon pool.
pub fn run_shard(prep: &PreparedPart, range: Range<u64>) -> PartialResult {
    prep.enumerate_range(range)
}

/// Enumerates a shard, or with `good_enough` the shortest prefix of it that
/// admits a fixture scoring that or better (the hit index with it): the
/// prefixes of a part's shards merge into the embedded run's
/// [`PreparedPart::enumerate_until`] result.
pub fn run_shard_until(
    prep: &PreparedPart,
    range: Range<u64>,
    good_enough: Option<f64>,
) -> (PartialResult, Option<u64>) {
    match good_enough {
        Some(g) => prep.enumerate_until(range, g),
        None => (prep.enumerate_range(range), None),
    }
}
