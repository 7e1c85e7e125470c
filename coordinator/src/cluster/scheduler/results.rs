//! What a worker reports for one shard: a result, checked (see
//! [`crate::cluster::verify`]) and held until its part is complete, then
//! merged into the part's result; or a failure, which fails the part.

use super::errors::{NotTaken, PartError};
use super::state::{
    queue_finishing, MergedShards, PartSlot, Settings, ShardResult, ShardStatus, State, ROLE, WHOLE,
};
use super::workers;
use crate::cluster::verify::{self, CheckError};
use fixplan_core::{merge, PartialResult};
use fixplan_worker::protocol::{FinishFrom, ShardDone, ShardFailed};
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
    if st.shards[r.shard_id as usize].finish_from.is_some() {
        return take_finishing(st, s, r, worker, p);
    }
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
            reject(
                st,
                &r,
                p,
                &format_args!("combinations {range:?}"),
                worker,
                &e,
            );
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
    hold(st, s, p, r, &shard_range);
    Ok(())
}

/// Takes a worker's finishing of cut part `p` (checked, for the
/// verification sample, by finishing the part here too), and delivers
/// the part with it.
fn take_finishing(
    st: &mut State,
    s: &Settings,
    r: ShardDone,
    worker: &str,
    p: usize,
) -> Result<(), NotTaken> {
    let id = r.shard_id;
    let deep = s
        .verify
        .deep(id, st.workers.get(worker).map_or(0, |w| w.rederived));
    let from = st.shards[id as usize].finish_from.as_deref();
    let check = check_finishing(&mut st.parts[p], s, &r, from, deep);
    if let Some(w) = st.workers.get_mut(worker) {
        w.leased.remove(&id);
    }
    if let Err(e) = check {
        reject(st, &r, p, &"its finishing", worker, &e);
        return Err(NotTaken::Rejected(e));
    }
    accept(st, &r, worker, 0, deep);
    if let Some(from) = st.shards[id as usize].finish_from.take() {
        deliver(st, p, from.result, None, r.finished);
    }
    Ok(())
}

/// The checks of a worker's finishing of a cut part: its part, and with
/// `deep` the finished bytes against the coordinator's own finishing.
fn check_finishing(
    part: &mut PartSlot,
    s: &Settings,
    r: &ShardDone,
    from: Option<&FinishFrom>,
    deep: bool,
) -> Result<(), CheckError> {
    if r.digest != part.digest {
        return Err(CheckError::OtherPart {
            got: r.digest,
            want: part.digest,
        });
    }
    if !deep || r.finished.is_none() {
        return Ok(());
    }
    let prep = part.prepared().map_err(CheckError::CannotPrepare)?;
    if let (Some(theirs), Some(f), Some(context), Some(from)) =
        (&r.finished, &s.finisher, &part.finish, from)
    {
        verify::check_finished(
            f.as_ref(),
            &part.source,
            &prep,
            &from.result,
            from.micros,
            context,
            theirs,
        )?;
    }
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
    what: &dyn std::fmt::Display,
    worker: &str,
    e: &CheckError,
) {
    st.stats.rejected += 1;
    let part_index = &st.part_index;
    warn!(
        role = ROLE,
        "rejected shard {} (part #{}, {what}) from worker {}: {e}; it goes back to the queue",
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
fn hold(st: &mut State, s: &Settings, p: usize, r: ShardDone, shard_range: &Range<u64>) {
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
        part.top = fixplan_core::merge_ranked(lists, part.top_k());
    }
    part.partials.push(ShardResult {
        shard: r.shard_id,
        hit: r.hit,
        micros: r.micros,
        result,
        finished: r.finished,
    });
    if !open && !part.closed {
        close(st, s, p);
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

/// Merges the results of part `p` and hands the part to the consumer, or
/// for a cut part that workers finish, queues its finishing.
fn close(st: &mut State, s: &Settings, p: usize) {
    let part = &mut st.parts[p];
    let stop = part.stop;
    // Shards past the stop: results that came in are left out, the others
    // are never handed out (or are duplicates later).
    let mut partials = std::mem::take(&mut part.partials);
    let whole = part.shard_ids.end - part.shard_ids.start == 1;
    // Finished by its worker: a whole part's one shard, not stopped (moved
    // out: a chunk is kilobytes, copied once already off the wire).
    let finished = match partials.as_mut_slice() {
        [one] if stop.is_none() && whole => one.finished.take(),
        _ => None,
    };
    let micros = partials.iter().map(|h| h.micros).sum();
    let kept = partials
        .into_iter()
        .map(|h| h.result)
        .filter(|r| stop.is_none_or(|s| r.range.start <= s))
        .collect();
    let mut merged = merge(part.top_k(), kept);
    if merged.range.end == u64::MAX {
        // A part cut from an estimate ends with an open shard: numbered
        // as the embedded run numbers it, `0..count`.
        merged.range.end = merged
            .range
            .start
            .saturating_add(merged.counts.combinations);
    }
    if !whole && stop.is_none() && s.finisher.is_some() && part.finish.is_some() {
        queue_finishing(
            st,
            p,
            FinishFrom {
                result: merged,
                micros,
            },
        );
        return;
    }
    deliver(st, p, merged, stop, finished);
}

/// Hands part `p` to the consumer: its merged result, the combination
/// where it stopped, and its finished bytes if a worker finished it.
fn deliver(
    st: &mut State,
    p: usize,
    merged: PartialResult,
    stopped_at: Option<u64>,
    finished: Option<Vec<u8>>,
) {
    let part = &mut st.parts[p];
    part.closed = true;
    part.finishing = None;
    let done = MergedShards {
        // The part is closed: its slot needs the prepared part no more, and
        // handing over the only reference spares a copy of it.
        prep: part.prep.take(),
        input: part.source.clone(),
        merged,
        stopped_at,
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
    if let Some(from) = st.shards[f.shard_id as usize].finish_from.take() {
        // A worker that cannot finish a cut part: the caller finishes it.
        warn!(
            role = ROLE,
            "worker {worker} could not finish a cut part: {}", f.message
        );
        st.shards[f.shard_id as usize].status = ShardStatus::Done;
        deliver(st, p, from.result, None, None);
        return Ok(());
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
