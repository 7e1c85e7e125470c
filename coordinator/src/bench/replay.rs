//! Replayed task outcomes, for measuring the coordinator alone
//! (`fixplan bench-coordinator`): a simulated worker whose
//! [`Runner`] is a [`Replay`] answers a task it has seen before (same
//! part, same task) with the outcome computed the first time, at once,
//! instead of doing it again. Shared by the simulated workers of one
//! process. Never used by `fixplan worker`.

use bytes::Bytes;
use fixplan_worker::finish::{FinishInputs, Finisher};
use fixplan_worker::protocol::{Answer, Assign, Digest, Outcome, Task};
use fixplan_worker::task::{self, CachedPart, Runner};
use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

/// What names a task's outcome: the part, the range, `good_enough` (bits),
/// what finishing it needs (a part listed twice is finished under each
/// of its places), and for the finishing of a cut part the time its
/// shards took (it is in the part's message, and a shard enumerated twice
/// in the warm-up may be replayed with the other time; the merged
/// fixtures are the same in every run of one catalogue).
type OutcomeKey = (Digest, u64, u64, Option<u64>, Option<Bytes>, Option<u64>);

fn key(assign: &Assign) -> OutcomeKey {
    let (range, good_enough, context, merged) = match &assign.task {
        Task::Enumerate { range, good_enough } => (range.clone(), *good_enough, None, None),
        Task::EnumerateAndFinish { range, context } => {
            (range.clone(), None, Some(context.clone()), None)
        }
        Task::Finish { merged, context } => {
            (0..0, None, Some(context.clone()), Some(merged.micros))
        }
    };
    (
        assign.digest,
        range.start,
        range.end,
        good_enough.map(f64::to_bits),
        context,
        merged,
    )
}

/// The key of `assign`'s enumeration alone (no finish context), for a part
/// listed many times: enumerated once, finished under each place.
fn enumeration_key(assign: &Assign) -> OutcomeKey {
    let mut shard = key(assign);
    shard.4 = None;
    shard
}

/// `outcome` as the outcome of task `id`.
fn renamed(outcome: &mut Outcome, id: u64) {
    match outcome {
        Outcome::Done(d) => d.shard_id = id,
        Outcome::Failed(f) => f.shard_id = id,
    }
}

/// Task outcomes computed once, replayed after.
#[derive(Default)]
pub struct Replay {
    results: Mutex<HashMap<OutcomeKey, Outcome>>,
    /// The outcomes of enumerations by [`enumeration_key`].
    enumerations: Mutex<HashMap<OutcomeKey, Outcome>>,
    hits: AtomicU64,
    misses: AtomicU64,
}

impl std::fmt::Debug for Replay {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (hits, misses) = self.counts();
        formatter
            .debug_struct("Replay")
            .field("hits", &hits)
            .field("misses", &misses)
            .finish_non_exhaustive()
    }
}

impl Runner for Replay {
    /// The recorded outcome; else a recorded enumeration finished again
    /// for this task's context; else the task done ([`task::run`]) and
    /// recorded.
    fn run(&self, assign: &Assign, part: &CachedPart, finisher: Option<&dyn Finisher>) -> Outcome {
        if let Some(o) = self.get(assign) {
            return o;
        }
        let o = self
            .refinished(assign, part, finisher)
            .unwrap_or_else(|| task::run(assign, part, finisher));
        self.put(assign, o)
    }
}

impl Replay {
    /// The recorded outcome of `assign`, renamed to `assign`'s task id.
    fn get(&self, assign: &Assign) -> Option<Outcome> {
        let results = self.results.lock().unwrap_or_else(|e| e.into_inner());
        let Some(o) = results.get(&key(assign)) else {
            self.misses.fetch_add(1, Ordering::Relaxed);
            return None;
        };
        let mut o = o.clone();
        drop(results);
        renamed(&mut o, assign.shard_id);
        self.hits.fetch_add(1, Ordering::Relaxed);
        Some(o)
    }

    /// Records the outcome of `assign` (a failure too: the same input fails
    /// the same way), unless it was sent without its input, and returns
    /// the outcome to send: the one recorded first under its key. Two
    /// copies of a part may be enumerated at once in the warm-up; both
    /// then report the first one's timing, as the measured run will, so a
    /// cut part's merged timing (in its finishing's key) is the same in
    /// both runs.
    fn put(&self, assign: &Assign, outcome: Outcome) -> Outcome {
        if assign.input.is_none() && !matches!(outcome, Outcome::Done(_)) {
            return outcome;
        }
        if !matches!(assign.task, Task::Finish { .. }) {
            // A finishing has no enumeration to finish again elsewhere.
            let mut enumerations = self.enumerations.lock().unwrap_or_else(|e| e.into_inner());
            enumerations
                .entry(enumeration_key(assign))
                .or_insert_with(|| outcome.clone());
        }
        let mut results = self.results.lock().unwrap_or_else(|e| e.into_inner());
        let mut first = results.entry(key(assign)).or_insert(outcome).clone();
        drop(results);
        renamed(&mut first, assign.shard_id);
        first
    }

    /// A whole part enumerated before under another finish context,
    /// finished for `assign`.
    fn refinished(
        &self,
        assign: &Assign,
        part: &CachedPart,
        finisher: Option<&dyn Finisher>,
    ) -> Option<Outcome> {
        let Task::EnumerateAndFinish { context, .. } = &assign.task else {
            return None;
        };
        let enumerations = self.enumerations.lock().unwrap_or_else(|e| e.into_inner());
        let Outcome::Done(mut done) = enumerations.get(&enumeration_key(assign))?.clone() else {
            return None;
        };
        drop(enumerations);
        let (Answer::Enumerated { result, .. } | Answer::EnumeratedAndFinished { result, .. }) =
            done.answer
        else {
            return None;
        };
        let prepared = part.get();
        let (input, prep) = prepared.as_ref().as_ref().ok()?;
        let inputs = FinishInputs {
            input,
            prep,
            result: &result,
            micros: done.micros,
            context,
        };
        let finished = task::finished(Some(finisher?), &inputs);
        done.shard_id = assign.shard_id;
        done.answer = Answer::EnumeratedAndFinished { result, finished };
        Some(Outcome::Done(done))
    }

    /// Tasks answered from the cache, and tasks computed, so far.
    pub fn counts(&self) -> (u64, u64) {
        (
            self.hits.load(Ordering::Relaxed),
            self.misses.load(Ordering::Relaxed),
        )
    }
}
