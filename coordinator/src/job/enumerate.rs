//! A prepared part enumerated in this process: cut into shards, each shard
//! through the worker's own entry point (the one the cluster uses) on the
//! rayon pool, the pieces merged.

use super::shards;
use fixplan_core::{merge, report, PreparedPart, SolveResult};
use rayon::prelude::*;

/// Enumerates a prepared part shard by shard and merges the pieces: the
/// same bytes whatever the shard size or thread count.
pub fn solve_prepared(prep: &PreparedPart, shard_size: Option<u64>) -> (SolveResult, usize) {
    let count = prep.combination_count();
    let size = shard_size
        .unwrap_or_else(|| shards::embedded_shard_size(count, rayon::current_num_threads()));
    let mut ranges = shards::ranges(count, size);
    if ranges.is_empty() {
        // No combination: one empty shard still reports the part's counts.
        ranges.push(0..0);
    }
    let n = ranges.len();
    let parts: Vec<_> = ranges
        .into_par_iter()
        .map(|r| fixplan_worker::run_shard(prep, r))
        .collect();
    let merged = merge(prep.top_k(), parts);
    (report(prep, &merged), n)
}
