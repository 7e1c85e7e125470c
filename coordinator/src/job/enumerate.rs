//! A prepared part enumerated in this process: cut into shards, each shard
//! through the worker's own entry point (the one the cluster uses) on the
//! rayon pool, the pieces merged, within the part's work budget.

use super::shards;
use fixplan_core::{merge, report, BudgetHalt, PreparedPart, SolveResult, WorkBudget};
use rayon::prelude::*;

/// Enumerates a prepared part shard by shard and merges the pieces: the
/// same bytes whatever the shard size or thread count. The shards share
/// `budget`; when it is exceeded the result is incomplete and the budget
/// that stopped it comes with it (the part is then `over_budget`).
pub fn solve_prepared(
    prep: &PreparedPart,
    shard_size: Option<u64>,
    budget: &WorkBudget,
) -> (SolveResult, usize, Option<BudgetHalt>) {
    let count = prep.combination_count();
    let size = shard_size
        .unwrap_or_else(|| shards::embedded_shard_size(count, rayon::current_num_threads()));
    let mut ranges = shards::ranges(count, size);
    if ranges.is_empty() {
        // No combination: one empty shard still reports the part's counts.
        ranges.push(0..0);
    }
    let n = ranges.len();
    let pieces: Vec<_> = ranges
        .into_par_iter()
        .map(|r| fixplan_worker::run_shard_within(prep, r, budget))
        .collect();
    let halted = pieces.iter().find_map(|p| p.1);
    let merged = merge(prep.top_k(), pieces.into_iter().map(|p| p.0).collect());
    let halt = budget.verdict(halted, merged.counts.setups, merged.fixtures.len());
    (report(prep, &merged), n, halt)
}
