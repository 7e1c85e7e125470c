//! How a part's combination range is cut into shards: one cost model and
//! one cutter for the embedded run and the cluster.
//!
//! The work of a combination grows with the part's segment count (each
//! locator setup tries every segment for the clamp), so a part costs about
//! `combinations x segments`. Shards are cut so that each costs about the
//! same, whatever the part: a small part is one shard, a big one many, and
//! the catalogue gives about [`SHARDS_PER_SLOT`] shards per worker thread
//! expected, so a slow shard at the end does not leave the others idle.

use std::ops::Range;

/// Shards per expected worker thread, over the whole catalogue.
pub const SHARDS_PER_SLOT: u64 = 8;
/// No shard smaller than this many combinations (the round trip would
/// dominate).
pub const MIN_COMBINATIONS: u64 = 16;

/// Estimated cost of a part (arbitrary units).
pub fn cost(combinations: u64, segments: usize) -> u64 {
    combinations.saturating_mul(segments.max(1) as u64)
}

/// The cost one shard should have: the catalogue's cost spread over
/// [`SHARDS_PER_SLOT`] shards per expected worker thread.
pub fn target_cost(parts: &[(u64, usize)], slots: usize) -> u64 {
    let total: u64 = parts.iter().map(|&(c, s)| cost(c, s)).sum();
    let target_shards = (slots.max(1) as u64) * SHARDS_PER_SLOT;
    total.div_ceil(target_shards).max(1)
}

/// Combinations per shard of one part for a target shard cost.
pub fn shard_size(target: u64, combinations: u64, segments: usize) -> u64 {
    (target / segments.max(1) as u64)
        .max(MIN_COMBINATIONS)
        .min(combinations.max(1))
}

/// A part's cost before it is prepared, from its outline and access
/// regions: every edge taken for one usable segment (trimming drops some,
/// access regions can split some), as `(combinations, segments)`.
pub fn estimate(input: &fixplan_worker::part_input::PartInput) -> (u64, usize) {
    let n = input.part.outline.len() + input.part.access.iter().map(Vec::len).sum::<usize>();
    (fixplan_core::combination_count(n), n)
}

/// Batches per expected worker thread: assignments group small shards up
/// to about `total cost / (slots x BATCHES_PER_SLOT)` for each of the
/// worker's threads, so that a catalogue of small parts needs a few round
/// trips per worker, not one per part. Each round trip costs the
/// coordinator CPU, and more batches per slot mean more round trips
/// (`fixplan bench-coordinator` measures it; docs/performance.md has the
/// figures); the tail stays balanced by guided self-scheduling, which
/// shrinks batches as the queue empties.
pub const BATCHES_PER_SLOT: u64 = 8;

/// Shards in one assignment at most, whatever their cost: keeps messages
/// (inputs out, results back) and what a lost worker takes with it
/// bounded on huge catalogues of small parts...
pub const MAX_BATCH_SHARDS: usize = 256;

/// ... unless the worker has so many threads that this many a thread is
/// more: each of its threads needs a few shards of every batch.
pub const MAX_BATCH_SHARDS_PER_THREAD: usize = 16;

/// Shards in one assignment at most for a worker of `threads` threads.
pub fn max_batch_shards(threads: u64) -> usize {
    let threads = usize::try_from(threads).unwrap_or(usize::MAX);
    MAX_BATCH_SHARDS.max(MAX_BATCH_SHARDS_PER_THREAD.saturating_mul(threads))
}

/// The most cost one assignment carries for each of the worker's threads
/// (it always carries one shard, however big).
pub fn batch_cost(parts: &[(u64, usize)], slots: usize) -> u64 {
    let total: u64 = parts.iter().map(|&(c, s)| cost(c, s)).sum();
    total
        .div_ceil((slots.max(1) as u64) * BATCHES_PER_SLOT)
        .max(1)
}

/// Combinations per shard in an embedded run when not given: a few shards
/// per thread for a big part, one for a small part (a shard's fixed cost
/// would dominate below 256 combinations).
pub fn embedded_shard_size(combinations: u64, threads: usize) -> u64 {
    let target_shards = (threads.max(1) * 4) as u64;
    combinations.div_ceil(target_shards).max(256)
}

/// The shards of `0..count`: `size` combinations each, the last shorter.
pub fn ranges(count: u64, size: u64) -> Vec<Range<u64>> {
    let size = size.max(1);
    (0..count.div_ceil(size))
        .map(|i| i * size..((i + 1) * size).min(count))
        .collect()
}

/// The shards of a part estimated at `count` combinations: `size` each,
/// the last one open (to `u64::MAX`) so that it takes whatever the
/// estimate missed; one open shard (a whole part) if the estimate fits in
/// one. A worker's enumeration stops at the part's real count.
pub fn open_ranges(count: u64, size: u64) -> Vec<Range<u64>> {
    let mut r = ranges(count, size);
    match r.last_mut() {
        Some(last) => last.end = u64::MAX,
        None => r.push(0..u64::MAX),
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn open_ranges_end_open() {
        assert_eq!(open_ranges(10, 3), [0..3, 3..6, 6..9, 9..u64::MAX]);
        let whole = 0..u64::MAX;
        assert_eq!(open_ranges(3, 3), vec![whole.clone()]);
        assert_eq!(open_ranges(0, 3), vec![whole]);
    }

    #[test]
    fn sizes_balance_cost() {
        let parts = [(10, 4), (100_000, 40)];
        let target = target_cost(&parts, 2);
        assert_eq!(shard_size(target, 10, 4), 10);
        let shards_big = 100_000u64.div_ceil(shard_size(target, 100_000, 40));
        assert!((8..=20).contains(&shards_big), "{shards_big}");
        assert_eq!(ranges(10, 4), vec![0..4, 4..8, 8..10]);
        assert!(ranges(0, 4).is_empty());
    }
}
