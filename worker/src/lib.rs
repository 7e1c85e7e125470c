//! Runs shards (combination ranges) of prepared parts. The embedded run and,
//! later, the distributed workers go through this one entry point so that
//! both produce the same bytes.

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
