//! What a worker reports for one shard: a result, checked (see
//! [`crate::cluster::verify`]) and held until its part is complete, then
//! merged into the part's result; or a failure, which fails the part.

use super::errors::{NotTaken, PartFailure};
use super::state::{
    fail_part, queue_finishing, MergedShards, PartSlot, Settings, ShardResult, ShardStatus,
    ShardWork, State, ROLE, WHOLE,
};
use super::{tasks, workers};
use crate::cluster::verify::{self, CheckError};
use bytes::Bytes;
use fixplan_core::{merge, PartialResult};
use fixplan_worker::finish::FinishInputs;
use fixplan_worker::protocol::{Answer, Digest, MergedCut, TaskDone, TaskError, TaskFailed};
use std::ops::Range;
use tracing::warn;

/// A task's outcome as the scheduler checks it: whose, for which part,
/// how long it took.
struct OutcomeHead {
    shard_id: u64,
    digest: Digest,
    micros: u64,
}

/// A shard's enumeration as a worker reported it.
struct ShardReport {
    result: PartialResult,
    hit: Option<u64>,
    /// The part finished by the worker, if it was asked to and could.
    finished: Option<Bytes>,
}

/// An outcome read against the task it answers.
enum Taken {
    /// A shard's enumeration, and the shard's combinations.
    Enumeration(ShardReport, Range<u64>),
    /// A cut part's finishing: the finished part, if the worker could.
    Finishing(Option<Bytes>),
}

/// `answer` read as the answer to `work`; `None` if it answers another
/// kind of task.
fn read(work: &ShardWork, answer: Answer) -> Option<Taken> {
    match (work, answer) {
        (ShardWork::Combinations(range), Answer::Enumerated { result, hit }) => {
            Some(Taken::Enumeration(
                ShardReport {
                    result,
                    hit,
                    finished: None,
                },
                range.clone(),
            ))
        }
        (ShardWork::Combinations(range), Answer::EnumeratedAndFinished { result, finished }) => {
            Some(Taken::Enumeration(
                ShardReport {
                    result,
                    hit: None,
                    finished: finished.ok(),
                },
                range.clone(),
            ))
        }
        (ShardWork::Finishing(_), Answer::Finished(finished)) => {
            Some(Taken::Finishing(finished.ok()))
        }
        _ => None,
    }
}

/// Takes one task's outcome, or says why not (a rejected one bans its
/// worker).
pub(super) fn take_result(
    st: &mut State,
    settings: &Settings,
    done: TaskDone,
    worker: &str,
) -> Result<(), NotTaken> {
    st.stats.results += 1;
    let p = task_of(st, done.shard_id, worker)?;
    let head = OutcomeHead {
        shard_id: done.shard_id,
        digest: done.digest,
        micros: done.micros,
    };
    let sh = &st.shards[done.shard_id as usize];
    let taken = if tasks::expects(&st.parts[p], sh, &done.answer) {
        read(&sh.work, done.answer)
    } else {
        None
    };
    match taken {
        Some(Taken::Enumeration(enumeration, range)) => {
            take_enumeration(st, settings, &head, enumeration, worker, (p, range))
        }
        Some(Taken::Finishing(finished)) => {
            take_finishing(st, settings, &head, finished, worker, p)
        }
        None => {
            if let Some(w) = st.workers.get_mut(worker) {
                w.leased.remove(&head.shard_id);
            }
            let e = CheckError::WrongAnswer;
            reject(st, &head, p, &"its task", worker, &e);
            Err(NotTaken::Rejected(e))
        }
    }
}

/// Takes a shard's enumeration (of part `p`, combinations
/// `shard_range`), checked.
fn take_enumeration(
    st: &mut State,
    settings: &Settings,
    head: &OutcomeHead,
    mut enumeration: ShardReport,
    worker: &str,
    (p, shard_range): (usize, Range<u64>),
) -> Result<(), NotTaken> {
    // A shard stopped by `--good-enough` answers for its prefix.
    let range = match enumeration.hit {
        Some(h) if shard_range.contains(&h) => shard_range.start..h + 1,
        _ => shard_range.clone(),
    };
    let deep = settings.verify.deep(
        head.shard_id,
        st.workers.get(worker).map_or(0, |w| w.rederived),
    );
    let check = check(
        &mut st.parts[p],
        settings,
        head,
        &enumeration,
        (&shard_range, &range),
        deep,
    );
    if let Some(w) = st.workers.get_mut(worker) {
        w.leased.remove(&head.shard_id);
    }
    let checked = match check {
        Ok(n) => n,
        Err(e) => {
            reject(
                st,
                head,
                p,
                &format_args!("combinations {range:?}"),
                worker,
                &e,
            );
            return Err(NotTaken::Rejected(e));
        }
    };
    accept(st, head, worker, checked, deep);
    if deep && settings.finisher.is_none() {
        // The result was re-derived, its finished part cannot be checked:
        // the caller finishes the part from the result.
        enumeration.finished = None;
    }
    hold(st, settings, p, head, enumeration, &shard_range);
    Ok(())
}

/// Takes a worker's finishing of cut part `p` (checked, for the
/// verification sample, by finishing the part here too), and delivers
/// the part with it (without it, if the worker could not finish it: the
/// caller then does).
fn take_finishing(
    st: &mut State,
    settings: &Settings,
    head: &OutcomeHead,
    finished: Option<Bytes>,
    worker: &str,
    slot: usize,
) -> Result<(), NotTaken> {
    let id = head.shard_id;
    let deep = settings
        .verify
        .deep(id, st.workers.get(worker).map_or(0, |w| w.rederived));
    let merged = match &st.shards[id as usize].work {
        ShardWork::Finishing(merged) => merged.as_deref(),
        ShardWork::Combinations(_) => None,
    };
    let check = check_finishing(
        &mut st.parts[slot],
        settings,
        head,
        finished.as_ref(),
        merged,
        deep,
    );
    if let Some(w) = st.workers.get_mut(worker) {
        w.leased.remove(&id);
    }
    if let Err(e) = check {
        reject(st, head, slot, &"its finishing", worker, &e);
        return Err(NotTaken::Rejected(e));
    }
    accept(st, head, worker, 0, deep);
    if let ShardWork::Finishing(merged) = &mut st.shards[id as usize].work {
        if let Some(merged) = merged.take() {
            deliver(st, slot, merged.result, None, finished);
        }
    }
    Ok(())
}

/// The checks of a worker's finishing of a cut part: its part, and with
/// `deep` the finished bytes against the coordinator's own finishing.
fn check_finishing(
    part: &mut PartSlot,
    settings: &Settings,
    head: &OutcomeHead,
    finished: Option<&Bytes>,
    merged: Option<&MergedCut>,
    deep: bool,
) -> Result<(), CheckError> {
    if head.digest != part.digest {
        return Err(CheckError::OtherPart {
            got: head.digest,
            want: part.digest,
        });
    }
    let (Some(theirs), true) = (finished, deep) else {
        return Ok(());
    };
    let prep = part.prepared().map_err(CheckError::CannotPrepare)?;
    if let (Some(f), Some(context), Some(merged)) = (&settings.finisher, &part.finish, merged) {
        let inputs = FinishInputs {
            input: &part.source,
            prep: &prep,
            result: &merged.result,
            micros: merged.micros,
            context,
        };
        verify::check_finished(f.as_ref(), &inputs, theirs)?;
    }
    Ok(())
}

/// The part of the task `id` answers, if that task is still to be done.
fn task_of(st: &mut State, id: u64, worker: &str) -> Result<usize, NotTaken> {
    let Some(sh) = st.shards.get(id as usize) else {
        warn!(
            role = ROLE,
            "dropped a result for unknown shard {} from worker {}", id, worker
        );
        return Err(NotTaken::UnknownShard);
    };
    if sh.status == ShardStatus::Done {
        st.stats.duplicates += 1;
        return Err(NotTaken::Duplicate);
    }
    Ok(sh.part)
}

/// The checks of a result against its part as it stands (`deep`: its
/// fixtures re-derived too): how many fixtures were re-derived.
fn check(
    part: &mut PartSlot,
    settings: &Settings,
    head: &OutcomeHead,
    enumeration: &ShardReport,
    (shard_range, range): (&Range<u64>, &Range<u64>),
    deep: bool,
) -> Result<usize, CheckError> {
    if head.digest != part.digest {
        return Err(CheckError::OtherPart {
            got: head.digest,
            want: part.digest,
        });
    }
    verify::check_stop(
        settings.good_enough,
        shard_range,
        enumeration.hit,
        &enumeration.result,
    )?;
    if deep {
        let prep = part.prepared().map_err(CheckError::CannotPrepare)?;
        let n = verify::check(&prep, range, &enumeration.result, &part.top, true)?;
        if let (Some(theirs), Some(f), Some(context)) =
            (&enumeration.finished, &settings.finisher, &part.finish)
        {
            let inputs = FinishInputs {
                input: &part.source,
                prep: &prep,
                result: &enumeration.result,
                micros: head.micros,
                context,
            };
            verify::check_finished(f.as_ref(), &inputs, theirs)?;
        }
        return Ok(n);
    }
    match &part.prep {
        Some(prep) => verify::check(prep, range, &enumeration.result, &part.top, false),
        None => verify::check_shape(part.top_k(), range, &enumeration.result).map(|()| 0),
    }
}

/// A result failed its checks: its shard goes back to the queue, and its
/// worker is banned.
fn reject(
    st: &mut State,
    task: &OutcomeHead,
    slot: usize,
    what: &dyn std::fmt::Display,
    worker: &str,
    error: &CheckError,
) {
    st.stats.rejected += 1;
    let part_index = &st.part_index;
    warn!(
        role = ROLE,
        "rejected shard {} (part #{}, {what}) from worker {}: {error}; it goes back to the queue",
        task.shard_id,
        part_index.get(slot).copied().unwrap_or(slot),
        worker
    );
    // A worker that sends a bad result gets no more work.
    workers::ban(st, worker, task.shard_id);
}

/// Counts a result that passed its checks, and marks its shard done by
/// `worker` (whose work is redone if it is caught later).
fn accept(st: &mut State, task: &OutcomeHead, worker: &str, checked: usize, deep: bool) {
    st.stats.fixtures_rederived += checked as u64;
    st.stats.results_rederived += u64::from(deep);
    st.stats.worker_micros += task.micros;
    st.shards[task.shard_id as usize].status = ShardStatus::Done;
    if let Some(w) = st.workers.get_mut(worker) {
        w.shards += 1;
        w.rederived += checked as u64;
        st.shards[task.shard_id as usize].by = Some(w.name.clone());
    }
}

/// Holds a result taken for part `p`, and closes the part once no shard up
/// to its stop is left.
fn hold(
    st: &mut State,
    settings: &Settings,
    slot: usize,
    head: &OutcomeHead,
    enumeration: ShardReport,
    shard_range: &Range<u64>,
) {
    let part = &mut st.parts[slot];
    let mut result = enumeration.result;
    if *shard_range == WHOLE && enumeration.hit.is_none() {
        // As the embedded run cuts it: `0..count`.
        result.range = 0..result.counts.combinations;
    }
    if let Some(h) = enumeration.hit {
        part.stop = Some(part.stop.map_or(h, |settings| settings.min(h)));
    }
    let open = still_open(st, slot);
    let part = &mut st.parts[slot];
    if open {
        // The running top-k only serves the checks of the shards to come.
        let lists = vec![std::mem::take(&mut part.top), result.fixtures.clone()];
        part.top = fixplan_core::merge_ranked(lists, part.top_k());
    }
    part.partials.push(ShardResult {
        shard: head.shard_id,
        hit: enumeration.hit,
        micros: head.micros,
        result,
        finished: enumeration.finished,
    });
    if super::budget::held_over(st, settings, slot) {
        return;
    }
    if !open && !st.parts[slot].closed {
        close(st, settings, slot);
    }
}

/// Whether a shard of part `p` up to its stop is not done yet.
fn still_open(st: &State, slot: usize) -> bool {
    let part = &st.parts[slot];
    let counts = |id: u64| !st.shards[id as usize].past(part.stop);
    part.shard_ids
        .clone()
        .any(|id| counts(id) && st.shards[id as usize].status != ShardStatus::Done)
}

/// Merges the results of part `p` and hands the part to the consumer, or
/// for a cut part that workers finish, queues its finishing.
fn close(st: &mut State, settings: &Settings, slot: usize) {
    let part = &mut st.parts[slot];
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
        .filter(|r| stop.is_none_or(|settings| r.range.start <= settings))
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
    let finish = part.finish.is_some();
    if let Some(over) = super::budget::over_at_close(&st.parts[slot], settings, &merged) {
        super::budget::fail(st, slot, over);
        return;
    }
    if !whole && stop.is_none() && settings.finisher.is_some() && finish {
        queue_finishing(
            st,
            slot,
            MergedCut {
                result: merged,
                micros,
            },
        );
        return;
    }
    deliver(st, slot, merged, stop, finished);
}

/// Hands part `p` to the consumer: its merged result, the combination
/// where it stopped, and its finished bytes if a worker finished it.
fn deliver(
    st: &mut State,
    slot: usize,
    merged: PartialResult,
    stopped_at: Option<u64>,
    finished: Option<Bytes>,
) {
    let part = &mut st.parts[slot];
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
    let idx = st.part_index.get(slot).copied().unwrap_or(slot);
    st.done.push((idx, Ok(done)));
}

/// A worker could not enumerate a shard: the part fails, with the
/// coordinator's own message if the part cannot be prepared (the embedded
/// run's), else the worker's.
pub(super) fn take_failure(
    st: &mut State,
    settings: &Settings,
    failure: TaskFailed,
    worker: &str,
) -> Result<(), NotTaken> {
    let Some(sh) = st.shards.get(failure.shard_id as usize) else {
        return Err(NotTaken::UnknownShard);
    };
    if sh.status == ShardStatus::Done {
        return Err(NotTaken::DuplicateFailure);
    }
    let p = sh.part;
    if let Some(w) = st.workers.get_mut(worker) {
        w.leased.remove(&failure.shard_id);
    }
    if let ShardWork::Finishing(merged) = &mut st.shards[failure.shard_id as usize].work {
        // A worker that cannot finish a cut part: the caller finishes it.
        warn!(
            role = ROLE,
            "worker {worker} could not finish a cut part: {}", failure.error
        );
        let merged = merged.take();
        st.shards[failure.shard_id as usize].status = ShardStatus::Done;
        if let Some(merged) = merged {
            deliver(st, p, merged.result, None, None);
        }
        return Ok(());
    }
    if let TaskError::OverBudget(stop) = failure.error {
        let deferred = super::budget::shard_over(st, settings, (p, failure.shard_id), stop);
        if deferred && !still_open(st, p) && !st.parts[p].closed {
            close(st, settings, p);
        }
        return Ok(());
    }
    let idx = st.part_index.get(p).copied().unwrap_or(p);
    // A part sent whole was not prepared here: if it cannot be, that is
    // the input's fault and the coordinator's own message stands (the
    // embedded run's); otherwise the worker's enumeration failed.
    let error = match st.parts[p].prepared() {
        Err(e) => PartFailure::Prepare(e),
        Ok(_) => {
            warn!(
                role = ROLE,
                "part #{idx}: worker {} failed shard {}: {}",
                worker,
                failure.shard_id,
                failure.error
            );
            PartFailure::Worker(failure.error)
        }
    };
    fail_part(st, p, error);
    Ok(())
}
