//! Replayed shard results, for measuring the coordinator alone
//! (`fixplan bench-coordinator`): a worker given a [`Replay`] answers a
//! shard it has seen before (same part digest, range and `good_enough`)
//! with the result computed the first time, at once, instead of
//! enumerating it again. Shared by the simulated workers of one process.
//! Never used by `fixplan worker`.

use crate::protocol::{Assign, Digest, Outcome};
use bytes::Bytes;
use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

/// What names a shard's result: the part, the range, `good_enough` (bits),
/// what finishing it needs (a part listed twice is finished under each
/// of its places), and for the finishing of a cut part the time its
/// shards took (it is in the part's message, and a shard enumerated twice
/// in the warm-up may be replayed with the other time; the merged
/// fixtures are the same in every run of one catalogue).
type Key = (Digest, u64, u64, Option<u64>, Option<Bytes>, Option<u64>);

fn key(a: &Assign) -> Key {
    (
        a.digest,
        a.range.start,
        a.range.end,
        a.good_enough.map(f64::to_bits),
        a.finish.clone(),
        a.finish_from.as_ref().map(|f| f.micros),
    )
}

/// `o` as the outcome of shard `id`.
fn renamed(o: &mut Outcome, id: u64) {
    match o {
        Outcome::Done(d) => d.shard_id = id,
        Outcome::Failed(f) => f.shard_id = id,
    }
}

/// Shard results computed once, replayed after.
#[derive(Default)]
pub struct Replay {
    results: Mutex<HashMap<Key, Outcome>>,
    /// The same outcomes by shard alone (no finish context): a part listed
    /// many times is enumerated once and only finished under each place.
    shards: Mutex<HashMap<Key, Outcome>>,
    /// Parts' wire inputs by digest: a replayed shard skips preparing its
    /// part, so a later shard of it that is not in the cache (sent without
    /// input: the coordinator believes this worker has it) takes it here.
    inputs: Mutex<HashMap<Digest, Bytes>>,
    hits: AtomicU64,
    misses: AtomicU64,
}

impl std::fmt::Debug for Replay {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (hits, misses) = self.counts();
        f.debug_struct("Replay")
            .field("hits", &hits)
            .field("misses", &misses)
            .finish_non_exhaustive()
    }
}

impl Replay {
    /// The recorded outcome of `a`'s shard, renamed to `a`'s shard id.
    pub fn get(&self, a: &Assign) -> Option<Outcome> {
        if let Some(input) = &a.input {
            let mut inputs = self.inputs.lock().unwrap_or_else(|e| e.into_inner());
            inputs.entry(a.digest).or_insert_with(|| input.clone());
        }
        let results = self.results.lock().unwrap_or_else(|e| e.into_inner());
        let Some(o) = results.get(&key(a)) else {
            self.misses.fetch_add(1, Ordering::Relaxed);
            return None;
        };
        let mut o = o.clone();
        drop(results);
        renamed(&mut o, a.shard_id);
        self.hits.fetch_add(1, Ordering::Relaxed);
        Some(o)
    }

    /// The wire input of `a`'s part, if `a` came without it and it is known.
    pub fn input_for(&self, a: &Assign) -> Option<Bytes> {
        if a.input.is_some() {
            return None;
        }
        let inputs = self.inputs.lock().unwrap_or_else(|e| e.into_inner());
        inputs.get(&a.digest).cloned()
    }

    /// Records the outcome of `a`'s shard (a failure too: the same input
    /// fails the same way), unless it was sent without its input, and
    /// returns the outcome to send: the one recorded first under its key.
    /// Two copies of a part may be enumerated at once in the warm-up; both
    /// then report the first one's timing, as the measured run will, so a
    /// cut part's merged timing (in its finishing's key) is the same in
    /// both runs.
    pub fn put(&self, a: &Assign, o: Outcome) -> Outcome {
        if a.input.is_none() && !matches!(o, Outcome::Done(_)) {
            return o;
        }
        if a.finish_from.is_none() {
            // A finishing has no enumeration to finish again elsewhere.
            let mut shard = key(a);
            shard.4 = None;
            let mut shards = self.shards.lock().unwrap_or_else(|e| e.into_inner());
            shards.entry(shard).or_insert_with(|| o.clone());
        }
        let mut results = self.results.lock().unwrap_or_else(|e| e.into_inner());
        let mut first = results.entry(key(a)).or_insert(o).clone();
        drop(results);
        renamed(&mut first, a.shard_id);
        first
    }

    /// The enumeration of `a`'s shard recorded under another finish
    /// context (renamed to `a`'s shard id), to be finished again.
    pub fn enumerated(&self, a: &Assign) -> Option<Outcome> {
        let mut shard = key(a);
        shard.4 = None;
        let shards = self.shards.lock().unwrap_or_else(|e| e.into_inner());
        let mut o = shards.get(&shard)?.clone();
        drop(shards);
        renamed(&mut o, a.shard_id);
        Some(o)
    }

    /// Shards answered from the cache, and shards computed, so far.
    pub fn counts(&self) -> (u64, u64) {
        (
            self.hits.load(Ordering::Relaxed),
            self.misses.load(Ordering::Relaxed),
        )
    }
}
