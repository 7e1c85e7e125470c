//! What a worker reports for one shard: a result, checked (see
//! [`crate::cluster::verify`]) and held until its part is complete, then
//! merged into the part's result; or a failure, which fails the part.

use super::errors::{NotTaken, PartError};
use super::state::{
    MergedShards, PartSlot, Settings, ShardResult, ShardStatus, State, ROLE, WHOLE,
};
use super::workers;
use crate::cluster::verify::{self, CheckError};
use fixplan_core::merge;
use fixplan_worker::protocol::{ShardDone, ShardFailed};
use std::ops::Range;
use tracing::warn;

/// Takes one shard result, or says why not (a rejected one bans its
/// worker).
pub(super) fn take_result(
    st: &mut State,
    s: &Settings,
    r: ShardDone,
    worker: &str,
) -> Result<(), NotTaken> {
    st.stats.results += 1;
    let (p, shard_range) = shard_of(st, &r, worker)?;
    // A shard stopped by `--good-enough` answers for its prefix.
    let range = match r.hit {
        Some(h) if shard_range.contains(&h) => shard_range.start..h + 1,
        _ => shard_range.clone(),
    };
    let deep = s.verify.deep(
        r.shard_id,
        st.workers.get(worker).map_or(0, |w| w.rederived),
    );
    let check = check(&mut st.parts[p], s, &r, &shard_range, &range, deep);
    if let Some(w) = st.workers.get_mut(worker) {
        w.leased.remove(&r.shard_id);
    }
    let checked = match check {
        Ok(n) => n,
        Err(e) => {
            reject(st, &r, p, &range, worker, &e);
            return Err(NotTaken::Rejected(e));
        }
    };
    accept(st, &r, worker, checked, deep);
    let mut r = r;
    if deep && s.finisher.is_none() {
        // The result was re-derived, its finished part cannot be checked:
        // the caller finishes the part from the result.
        r.finished = None;
    }
    hold(st, p, r, &shard_range);
    Ok(())
}

/// The part and combinations of the shard `r` answers, if that shard is
/// still to be done.
fn shard_of(st: &mut State, r: &ShardDone, worker: &str) -> Result<(usize, Range<u64>), NotTaken> {
    let Some(sh) = st.shards.get(r.shard_id as usize) else {
        warn!(
            role = ROLE,
            "dropped a result for unknown shard {} from worker {}", r.shard_id, worker
        );
        return Err(NotTaken::UnknownShard);
    };
    if sh.status == ShardStatus::Done {
        st.stats.duplicates += 1;
        return Err(NotTaken::Duplicate);
    }
    Ok((sh.part, sh.range.clone()))
}

/// The checks of a result against its part as it stands (`deep`: its
/// fixtures re-derived too): how many fixtures were re-derived.
fn check(
    part: &mut PartSlot,
    s: &Settings,
    r: &ShardDone,
    shard_range: &Range<u64>,
    range: &Range<u64>,
    deep: bool,
) -> Result<usize, CheckError> {
    if r.digest != part.digest {
        return Err(CheckError::OtherPart {
            got: r.digest,
            want: part.digest,
        });
    }
    verify::check_stop(s.good_enough, shard_range, r.hit, &r.result)?;
    if deep {
        let prep = part.prepared().map_err(CheckError::CannotPrepare)?;
        let n = verify::check(&prep, range, &r.result, &part.top, true)?;
        if let (Some(theirs), Some(f), Some(context)) = (&r.finished, &s.finisher, &part.finish) {
            verify::check_finished(
                f.as_ref(),
                &part.source,
                &prep,
                &r.result,
                r.micros,
                context,
                theirs,
            )?;
        }
        return Ok(n);
    }
    match &part.prep {
        Some(prep) => verify::check(prep, range, &r.result, &part.top, false),
        None => verify::check_shape(part.top_k(), range, &r.result).map(|()| 0),
    }
}

/// A result failed its checks: its shard goes back to the queue, and its
/// worker is banned.
fn reject(
    st: &mut State,
    r: &ShardDone,
    p: usize,
    range: &Range<u64>,
    worker: &str,
    e: &CheckError,
) {
    st.stats.rejected += 1;
    let part_index = &st.part_index;
    warn!(role = ROLE,
        "rejected shard {} (part #{}, combinations {range:?}) from worker {}: {e}; it goes back to the queue",
        r.shard_id,
        part_index.get(p).copied().unwrap_or(p),
        worker
    );
    // A worker that sends a bad result gets no more work.
    workers::ban(st, worker, r.shard_id);
}

/// Counts a result that passed its checks, and marks its shard done by
/// `worker` (whose work is redone if it is caught later).
fn accept(st: &mut State, r: &ShardDone, worker: &str, checked: usize, deep: bool) {
    st.stats.fixtures_rederived += checked as u64;
    st.stats.results_rederived += u64::from(deep);
    st.stats.worker_micros += r.micros;
    st.shards[r.shard_id as usize].status = ShardStatus::Done;
    if let Some(w) = st.workers.get_mut(worker) {
        w.shards += 1;
        w.rederived += checked as u64;
        st.shards[r.shard_id as usize].by = Some(w.name.clone());
    }
}

/// Holds a result taken for part `p`, and closes the part once no shard up
/// to its stop is left.
fn hold(st: &mut State, p: usize, r: ShardDone, shard_range: &Range<u64>) {
    let part = &mut st.parts[p];
    let mut result = r.result;
    if *shard_range == WHOLE && r.hit.is_none() {
        // As the embedded run cuts it: `0..count`.
        result.range = 0..result.counts.combinations;
    }
    if let Some(h) = r.hit {
        part.stop = Some(part.stop.map_or(h, |s| s.min(h)));
    }
    let open = still_open(st, p);
    let part = &mut st.parts[p];
    if open {
        // The running top-k only serves the checks of the shards to come.
        let lists = vec![std::mem::take(&mut part.top), result.fixtures.clone()];
        part.top = fixplan_core::ranking::merge_ranked(lists, part.top_k());
    }
    part.partials.push(ShardResult {
        shard: r.shard_id,
        hit: r.hit,
        result,
        finished: r.finished,
    });
    if !open && !part.closed {
        close(st, p);
    }
}

/// Whether a shard of part `p` up to its stop is not done yet.
fn still_open(st: &State, p: usize) -> bool {
    let part = &st.parts[p];
    let counts = |id: u64| {
        part.stop
            .is_none_or(|s| st.shards[id as usize].range.start <= s)
    };
    part.shard_ids
        .clone()
        .any(|id| counts(id) && st.shards[id as usize].status != ShardStatus::Done)
}

/// Merges the results of part `p` and hands the part to the consumer.
fn close(st: &mut State, p: usize) {
    let part = &mut st.parts[p];
    part.closed = true;
    let stop = part.stop;
    // Shards past the stop: results that came in are left out, the others
    // are never handed out (or are duplicates later).
    let mut partials = std::mem::take(&mut part.partials);
    // Finished by its worker: a whole part's one shard, not stopped (moved
    // out: a chunk is kilobytes, copied once already off the wire).
    let finished = match partials.as_mut_slice() {
        [one] if stop.is_none() && part.shard_ids.end - part.shard_ids.start == 1 => {
            one.finished.take()
        }
        _ => None,
    };
    let kept = partials
        .into_iter()
        .map(|h| h.result)
        .filter(|r| stop.is_none_or(|s| r.range.start <= s))
        .collect();
    let done = MergedShards {
        // The part is closed: its slot needs the prepared part no more, and
        // handing over the only reference spares a copy of it.
        prep: part.prep.take(),
        input: part.source.clone(),
        merged: merge(part.top_k(), kept),
        stopped_at: stop,
        finished,
    };
    st.open_parts -= 1;
    for id in part.shard_ids.clone() {
        st.shards[id as usize].status = ShardStatus::Done;
    }
    let idx = st.part_index.get(p).copied().unwrap_or(p);
    st.done.push((idx, Ok(done)));
}

/// A worker could not enumerate a shard: the part fails, with the
/// coordinator's own message if the part cannot be prepared (the embedded
/// run's), else the worker's.
pub(super) fn take_failure(st: &mut State, f: ShardFailed, worker: &str) -> Result<(), NotTaken> {
    let Some(sh) = st.shards.get(f.shard_id as usize) else {
        return Err(NotTaken::UnknownShard);
    };
    if sh.status == ShardStatus::Done {
        return Err(NotTaken::DuplicateFailure);
    }
    let p = sh.part;
    if let Some(w) = st.workers.get_mut(worker) {
        w.leased.remove(&f.shard_id);
    }
    let idx = st.part_index.get(p).copied().unwrap_or(p);
    // A part sent whole was not prepared here: if it cannot be, that is
    // the input's fault and the coordinator's own message stands (the
    // embedded run's); otherwise the worker's enumeration failed.
    let error = match st.parts[p].prepared() {
        Err(e) => PartError::Prepare(e),
        Ok(_) => {
            warn!(
                role = ROLE,
                "part #{idx}: worker {} failed shard {}: {}", worker, f.shard_id, f.message
            );
            PartError::Worker(f.message)
        }
    };
    for sh in st.shards.iter_mut().filter(|s| s.part == p) {
        sh.status = ShardStatus::Done;
    }
    let part = &mut st.parts[p];
    if !part.closed {
        part.closed = true;
        st.open_parts -= 1;
        st.done.push((idx, Err(error)));
    }
    Ok(())
}
