//! The scheduler driven by hand: bans, lost replies, batch sizes.

use super::state::{ShardStatus, ShardWork};
use super::*;
use crate::cluster::verify::VerifyPolicy;
use bytes::Bytes;
use fixplan_catalog::kit::{builtin_kit, METRIC_25};
use fixplan_core::{Params, Part};
use fixplan_worker::finish::FinishInputs;
use fixplan_worker::part_input::PartInput;
use fixplan_worker::protocol::{
    Answer, Assign, BudgetStop, FinishError, Task, TaskFailed, TransportChoice,
};
use std::ops::Range;
use std::sync::mpsc::{channel, Receiver};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A run's settings for a test: zenoh, one worker needed.
fn settings(verify: VerifyPolicy, batch_cost: u64) -> Settings {
    Settings {
        run_id: "run".into(),
        host_id: "host".into(),
        transport: TransportChoice::Zenoh,
        iox: None,
        iox_clients: 1,
        lease: Duration::from_secs(300),
        min_workers: 1,
        verify,
        good_enough: None,
        part_setups: None,
        part_fixtures: None,
        part_seconds: None,
        batch_cost,
        finisher: None,
    }
}

fn core(parts: usize, shard: u64, verify: VerifyPolicy) -> Scheduler {
    let (c, rx) = core_rx(parts, shard, verify);
    // Keep the channel open for parts that do close.
    std::mem::forget(rx);
    c
}

fn core_rx(parts: usize, shard: u64, verify: VerifyPolicy) -> (Scheduler, Receiver<Vec<Delivery>>) {
    let (kit, units) = builtin_kit(METRIC_25).expect("built-in kit");
    let planned = (0..parts)
        .map(|i| {
            let w = 100.0 + 10.0 * i as f64;
            let part = Part::polygon(&[[0.0, 0.0], [w, 0.0], [w, 60.0], [0.0, 60.0]]);
            let source = PartInput {
                part,
                kit: kit.clone(),
                params: Params::default(),
                units,
            };
            let prep = source.prepare().expect("prepare");
            PlannedPart {
                index: i,
                ranges: crate::job::shards::ranges(prep.combination_count(), shard),
                segments: prep.segments().len(),
                prep: Some(Arc::new(prep)),
                source: Arc::new(source),
                input: vec![i as u8],
                finish: None,
            }
        })
        .collect();
    let settings = settings(verify, 1);
    let (tx, rx) = channel();
    (Scheduler::new(settings, planned, tx), rx)
}

/// The honest outcome of each shard of `batch` (part 0).
fn honest(scheduler: &Scheduler, batch: &[Assign]) -> Vec<Outcome> {
    let prep = scheduler.lock().parts[0].prep.clone().expect("prepared");
    batch
        .iter()
        .map(|a| done(a, prep.enumerate_range(range_of(a)), None))
        .collect()
}

/// The combinations task `a` enumerates.
fn range_of(assign: &Assign) -> Range<u64> {
    match &assign.task {
        Task::Enumerate { range, .. } | Task::EnumerateAndFinish { range, .. } => range.clone(),
        Task::Finish { .. } => panic!("a finishing enumerates nothing"),
    }
}

/// `a` done in 1 us, with `result` and `finished` bytes, answered as its
/// kind of task is.
fn done(
    assign: &Assign,
    result: fixplan_core::PartialResult,
    finished: Option<Vec<u8>>,
) -> Outcome {
    let finished = finished.map(Bytes::from).ok_or(FinishError::NoFinisher);
    let answer = match &assign.task {
        Task::Enumerate { .. } => Answer::Enumerated { result, hit: None },
        Task::EnumerateAndFinish { .. } => Answer::EnumeratedAndFinished { result, finished },
        Task::Finish { .. } => Answer::Finished(finished),
    };
    Outcome::Done(Box::new(TaskDone {
        shard_id: assign.shard_id,
        digest: assign.digest,
        micros: 1,
        answer,
    }))
}

/// `o` with its finished part replaced by `bytes`.
fn forge(outcome: &mut Outcome, bytes: &[u8]) {
    let Outcome::Done(d) = outcome else {
        panic!("failed")
    };
    match &mut d.answer {
        Answer::EnumeratedAndFinished { finished, .. } | Answer::Finished(finished) => {
            *finished = Ok(Bytes::copy_from_slice(bytes))
        }
        Answer::Enumerated { .. } => panic!("nothing finished"),
    }
}

fn report(scheduler: &Scheduler, worker: &str, outcomes: Vec<Outcome>) -> Frame {
    report_holding(scheduler, worker, outcomes, vec![])
}

fn report_holding(
    scheduler: &Scheduler,
    worker: &str,
    outcomes: Vec<Outcome>,
    holding: Vec<u64>,
) -> Frame {
    let msg = Msg::Report {
        worker: worker.into(),
        outcomes,
        holding,
    };
    decode(&scheduler.handle(&encode(&msg).expect("encode"))).expect("decode")
}

#[test]
fn a_banned_worker_s_work_on_open_parts_is_done_again() {
    let (mut c, rx) = core_rx(1, 4, VerifyPolicy::All);
    // The slot hands its prepared part over when the part closes.
    let prep = c.lock().parts[0].prep.clone().expect("prepared");
    let total = c.lock().queued_cost;
    c.settings.batch_cost = total / 4;
    join(&c, "a");
    join(&c, "b");
    let Next::Work(first) = c.next_work("a") else {
        panic!("no work")
    };
    let first_ids: Vec<u64> = first.iter().map(|a| a.shard_id).collect();
    // `a` hands in honest results and gets more work...
    let Frame::Msg(Msg::Reply {
        next: Next::Work(second),
        ..
    }) = report(&c, "a", honest(&c, &first))
    else {
        panic!("no second batch")
    };
    assert!(first_ids
        .iter()
        .all(|&id| c.lock().shards[id as usize].status == ShardStatus::Done));
    // ...then lies about one fixture of it.
    let mut lies = honest(&c, &second);
    let forged = lies.iter_mut().find_map(|o| match o {
        Outcome::Done(d) => match &mut d.answer {
            Answer::Enumerated { result, .. } if !result.fixtures.is_empty() => Some(result),
            _ => None,
        },
        Outcome::Failed(_) => None,
    });
    forged.expect("a shard with fixtures").fixtures[0].score *= 0.5;
    assert!(matches!(report(&c, "a", lies), Frame::Refused(_)));
    // Its first, accepted results are back in the queue.
    for &id in &first_ids {
        assert_eq!(c.lock().shards[id as usize].status, ShardStatus::Queued);
    }
    // `b` does everything; the part comes out as one enumeration.
    let mut outcomes = Vec::new();
    loop {
        match report(&c, "b", outcomes) {
            Frame::Msg(Msg::Reply {
                next: Next::Work(b),
                ..
            }) => outcomes = honest(&c, &b),
            Frame::Msg(Msg::Reply {
                next: Next::Done, ..
            }) => break,
            f => panic!("{f:?}"),
        }
    }
    let done = rx.try_recv().expect("the part");
    let Ok(f) = &done[0].1 else { panic!("failed") };
    assert_eq!(f.merged, prep.enumerate_all());
}

fn join(scheduler: &Scheduler, name: &str) {
    join_threads(scheduler, name, 1);
}

fn join_threads(scheduler: &Scheduler, name: &str, threads: u32) {
    let j = Join {
        worker: name.into(),
        host_id: "other".into(),
        pid: 1,
        threads,
        transport: TransportChoice::Zenoh,
        software: "test".into(),
    };
    assert!(matches!(scheduler.join(j), Ok(Msg::Welcome(_))));
}

fn ids(next: &Next) -> Vec<u64> {
    match next {
        Next::Work(b) => b.iter().map(|a| a.shard_id).collect(),
        other => panic!("{other:?}"),
    }
}

#[test]
fn shards_of_a_lost_reply_go_back_to_the_queue() {
    let c = core(2, 8, VerifyPolicy::All);
    join(&c, "w");
    let first = ids(&c.next_work("w"));
    assert!(!first.is_empty());
    // The reply was lost: the worker reports again with no outcome.
    let again = ids(&c.next_work("w"));
    assert_eq!(again, first, "the same shards, handed out again");
    assert_eq!(c.stats().requeued, first.len() as u64);
    // An unknown worker is told to join.
    assert_eq!(c.next_work("stranger"), Next::Rejoin);
}

#[test]
fn shards_a_worker_still_holds_stay_with_it() {
    let mut c = core(2, 1, VerifyPolicy::All);
    c.settings.batch_cost = u64::MAX;
    join(&c, "w");
    let first = ids(&c.next_work("w"));
    assert!(first.len() >= 4, "{first:?}");
    // It reports while it still works on two of them; the others went
    // out in a reply it lost.
    let held = first[..2].to_vec();
    let Frame::Msg(Msg::Reply { next, .. }) = report_holding(&c, "w", vec![], held.clone()) else {
        panic!("no reply")
    };
    let again = ids(&next);
    assert_eq!(c.stats().requeued, (first.len() - 2) as u64);
    assert!(held.iter().all(|id| !again.contains(id)), "{again:?}");
    assert!(first[2..].iter().all(|id| again.contains(id)), "{again:?}");
    for id in &held {
        let st = c.lock();
        assert!(
            matches!(&st.shards[*id as usize].status, ShardStatus::Leased { worker, .. } if worker == "w")
        );
        assert!(st.workers["w"].leased.contains(id));
    }
}

#[test]
fn nothing_else_of_a_report_counts_after_a_bad_result() {
    let mut c = core(1, 4, VerifyPolicy::All);
    c.settings.batch_cost = u64::MAX;
    join(&c, "liar");
    let Next::Work(batch) = c.next_work("liar") else {
        panic!("no work")
    };
    let prep = c.lock().parts[0].prep.clone().expect("prepared");
    let mut outcomes: Vec<(bool, Outcome)> = batch
        .iter()
        .map(|a| {
            let mut result = prep.enumerate_range(range_of(a));
            let bad = !result.fixtures.is_empty();
            if let Some(f) = result.fixtures.first_mut() {
                f.score *= 0.5;
            }
            (bad, done(a, result, None))
        })
        .collect();
    // One corrupted result first, honest ones after it.
    let first_bad = outcomes
        .iter()
        .position(|o| o.0)
        .expect("a shard with fixtures");
    let bad = outcomes.remove(first_bad);
    let mut honest: Vec<Outcome> = outcomes.into_iter().filter(|o| !o.0).map(|o| o.1).collect();
    assert!(!honest.is_empty(), "need honest shards too");
    let ids: Vec<u64> = honest.iter().map(Outcome::shard_id).collect();
    honest.insert(0, bad.1);
    let report = encode(&Msg::Report {
        worker: "liar".into(),
        outcomes: honest,
        holding: vec![],
    })
    .expect("encode");
    let reply = decode(&c.handle(&report)).expect("decode");
    assert!(
        matches!(reply, Frame::Refused(ref r) if r.contains("liar")),
        "{reply:?}"
    );
    let st = c.lock();
    assert_eq!(st.stats.rejected, 1);
    for id in ids {
        assert_ne!(
            st.shards[id as usize].status,
            ShardStatus::Done,
            "shard {id}"
        );
    }
}

#[test]
fn batches_shrink_as_the_queue_runs_out() {
    let mut c = core(3, 4, VerifyPolicy::All);
    let total = c.lock().queued_cost;
    c.settings.batch_cost = total / 4;
    join(&c, "w");
    let mut sizes = Vec::new();
    loop {
        let n = c.next_work("w");
        let Next::Work(b) = &n else { break };
        let cost: u64 = b
            .iter()
            .map(|a| c.lock().shards[a.shard_id as usize].cost)
            .sum();
        sizes.push(cost);
        // Drop the lease so the next call does not re-queue the batch.
        c.lock().workers.get_mut("w").unwrap().leased.clear();
        for a in b {
            c.lock().shards[a.shard_id as usize].status = ShardStatus::Done;
        }
    }
    assert!(sizes.len() >= 4, "{sizes:?}");
    let max_shard = c.lock().shards.iter().map(|s| s.cost).max().unwrap();
    assert!(sizes[0] <= total / 4 + max_shard, "{sizes:?}");
    assert!(sizes.last() < sizes.first(), "{sizes:?}");
    assert_eq!(sizes.iter().sum::<u64>(), total);
}

#[test]
fn a_worker_s_batch_grows_with_its_threads() {
    let mut c = core(3, 1, VerifyPolicy::All);
    let costs: Vec<u64> = c.lock().shards.iter().map(|s| s.cost).collect();
    let max_shard = *costs.iter().max().unwrap();
    // The queue is long enough that these batches are cut by the cost a
    // thread, not by guided self-scheduling.
    assert!(costs.iter().sum::<u64>() >= 40 * max_shard, "{costs:?}");
    c.settings.batch_cost = max_shard;
    join_threads(&c, "one", 1);
    join_threads(&c, "eight", 8);
    let cost = |n: &Next| match n {
        Next::Work(b) => b
            .iter()
            .map(|a| c.lock().shards[a.shard_id as usize].cost)
            .sum::<u64>(),
        _ => 0,
    };
    let one = cost(&c.next_work("one"));
    let eight = cost(&c.next_work("eight"));
    assert!(one <= 2 * max_shard, "{one} {max_shard}");
    assert!(eight >= 8 * max_shard, "{eight} {max_shard}");
    assert!(eight <= 9 * max_shard, "{eight} {max_shard}");
}

/// `n` parts planned whole and unprepared, each with a finish context.
fn whole_parts(count: usize, verify: VerifyPolicy) -> (Scheduler, Receiver<Vec<Delivery>>) {
    let (kit, units) = builtin_kit(METRIC_25).expect("built-in kit");
    let planned = (0..count)
        .map(|i| {
            let w = 100.0 + 10.0 * i as f64;
            let source = PartInput {
                part: Part::polygon(&[[0.0, 0.0], [w, 0.0], [w, 60.0], [0.0, 60.0]]),
                kit: kit.clone(),
                params: Params::default(),
                units,
            };
            PlannedPart {
                index: i,
                ranges: vec![WHOLE],
                segments: 4,
                prep: None,
                input: source.encode().expect("encode"),
                source: Arc::new(source),
                finish: Some(vec![b'c', i as u8]),
            }
        })
        .collect();
    let settings = settings(verify, u64::MAX);
    let (tx, rx) = channel();
    (Scheduler::new(settings, planned, tx), rx)
}

/// Honest results of whole parts, each with `finished` bytes naming its
/// part (`f`, part index: what [`Tag`] makes of its context).
fn finished_outcomes(scheduler: &Scheduler, batch: &[Assign]) -> Vec<Outcome> {
    batch
        .iter()
        .map(|a| {
            let input = PartInput::decode(a.input.as_deref().expect("input")).expect("decode");
            let mut result = input.prepare().expect("prepare").enumerate_all();
            result.range = 0..u64::MAX;
            let Task::EnumerateAndFinish { range, context } = &a.task else {
                panic!("a whole part is enumerated and finished")
            };
            assert_eq!(*range, WHOLE);
            let p = scheduler.lock().shards[a.shard_id as usize].part;
            assert_eq!(context[..], [b'c', p as u8], "the part's own context");
            done(a, result, Some(vec![b'f', p as u8]))
        })
        .collect()
}

fn finished_of(rx: &Receiver<Vec<Delivery>>) -> Vec<(usize, Option<Vec<u8>>)> {
    let mut out: Vec<_> = rx
        .try_iter()
        .flatten()
        .map(|(i, r)| (i, r.expect("merged").finished.map(|b| b.to_vec())))
        .collect();
    out.sort();
    out
}

/// A finisher that tags a part's context: `c, p` becomes `f, p`.
struct Tag;

impl fixplan_worker::finish::Finisher for Tag {
    fn finish(&self, inputs: &FinishInputs) -> Result<Vec<u8>, FinishError> {
        Ok(vec![b'f', inputs.context[1]])
    }

    fn check(&self, inputs: &FinishInputs, theirs: &[u8]) -> Result<(), FinishError> {
        let ours = [b'f', inputs.context[1]];
        (ours == theirs)
            .then_some(())
            .ok_or_else(|| FinishError::Records(format!("{theirs:?}, not {ours:?}")))
    }
}

/// Runs every shard with [`finished_outcomes`] as worker `w`.
fn finish_all(scheduler: &Scheduler) {
    work_until_done(scheduler, "w", Vec::new(), finished_outcomes);
}

/// Worker `w` reports `outcomes`, then answers every assignment with
/// `answer` until the run is over.
fn work_until_done(
    scheduler: &Scheduler,
    worker: &str,
    mut outcomes: Vec<Outcome>,
    answer: fn(&Scheduler, &[Assign]) -> Vec<Outcome>,
) {
    loop {
        match report(scheduler, worker, outcomes) {
            Frame::Msg(Msg::Reply {
                next: Next::Work(b),
                ..
            }) => outcomes = answer(scheduler, &b),
            Frame::Msg(Msg::Reply {
                next: Next::Done, ..
            }) => break,
            f => panic!("{f:?}"),
        }
    }
}

#[test]
fn whole_parts_come_back_finished_unless_re_derived() {
    // Re-derived: the coordinator finishes the part from the checked result.
    let (c, rx) = whole_parts(3, VerifyPolicy::All);
    join(&c, "w");
    finish_all(&c);
    assert_eq!(finished_of(&rx), vec![(0, None), (1, None), (2, None)]);
    // Trusted (past its full checks, not sampled): the worker's bytes.
    let (c, rx) = whole_parts(3, VerifyPolicy::Sample { one_in: u64::MAX });
    join(&c, "w");
    if let Some(w) = c.lock().workers.get_mut("w") {
        w.rederived = crate::cluster::verify::FULL_CHECKS;
    }
    finish_all(&c);
    let got = finished_of(&rx);
    assert_eq!(
        got,
        (0..3u8)
            .map(|p| (p as usize, Some(vec![b'f', p])))
            .collect::<Vec<_>>()
    );
}

#[test]
fn re_derived_parts_keep_their_finished_bytes_only_if_they_match() {
    let with_tag = || {
        let (mut c, rx) = whole_parts(3, VerifyPolicy::All);
        c.settings.finisher = Some(Arc::new(Tag));
        join(&c, "w");
        (c, rx)
    };
    // Honest: checked against the coordinator's own, kept.
    let (c, rx) = with_tag();
    finish_all(&c);
    let got = finished_of(&rx);
    assert_eq!(
        got,
        (0..3u8)
            .map(|p| (p as usize, Some(vec![b'f', p])))
            .collect::<Vec<_>>()
    );
    // Forged finished bytes on an honest result: refused, worker banned.
    let (c, rx) = with_tag();
    let Next::Work(batch) = c.next_work("w") else {
        panic!("no work")
    };
    let mut forged = finished_outcomes(&c, &batch);
    forge(&mut forged[0], b"forged");
    assert!(matches!(report(&c, "w", forged), Frame::Refused(_)));
    assert_eq!(c.stats().rejected, 1);
    assert!(finished_of(&rx)
        .iter()
        .all(|(_, f)| f.as_deref() != Some(b"forged")));
}

/// `n` rectangles cut in shards of 3 from an estimate of `estimate`
/// combinations (open last shard), unprepared, each with a finish
/// context, finished by workers with [`Tag`].
fn cut_parts_from(
    count: usize,
    verify: VerifyPolicy,
    estimate: u64,
) -> (Scheduler, Receiver<Vec<Delivery>>) {
    let (c, rx) = whole_parts(count, verify);
    let st = c.lock();
    let planned: Vec<PlannedPart> = st
        .parts
        .iter()
        .enumerate()
        .map(|(i, p)| PlannedPart {
            index: i,
            ranges: crate::job::shards::open_ranges(estimate, 3),
            segments: 4,
            prep: None,
            input: p.input.to_vec(),
            source: p.source.clone(),
            finish: p.finish.as_ref().map(|f| f.to_vec()),
        })
        .collect();
    drop(st);
    let mut settings = settings(verify, u64::MAX);
    settings.finisher = Some(Arc::new(Tag));
    let (tx, rx2) = channel();
    drop(rx);
    (Scheduler::new(settings, planned, tx), rx2)
}

/// Honest outcomes of `batch`: shards enumerated, cut parts finished as
/// [`Tag`] finishes them (checking what the task carries on the way).
/// [`cut_parts_from`] the right estimate.
fn cut_parts(count: usize, verify: VerifyPolicy) -> (Scheduler, Receiver<Vec<Delivery>>) {
    cut_parts_from(count, verify, fixplan_core::combination_count(4))
}

fn honest_cut(scheduler: &Scheduler, batch: &[Assign]) -> Vec<Outcome> {
    batch
        .iter()
        .map(|a| {
            let p = scheduler.lock().shards[a.shard_id as usize].part;
            let prep = scheduler.lock().parts[p].source.prepare().expect("prepare");
            match &a.task {
                Task::Finish { merged, context } => {
                    assert_eq!(context[..], [b'c', p as u8]);
                    let mut whole = prep.enumerate_all();
                    whole.range = 0..whole.counts.combinations;
                    assert_eq!(merged.result, whole, "merged as the embedded run");
                    done(a, whole, Some(vec![b'f', p as u8]))
                }
                Task::Enumerate { range, .. } => done(a, prep.enumerate_range(range.clone()), None),
                Task::EnumerateAndFinish { .. } => panic!("a shard is not finished"),
            }
        })
        .collect()
}

#[test]
fn cut_parts_are_finished_by_a_worker_from_their_merged_result() {
    for verify in [VerifyPolicy::All, VerifyPolicy::Sample { one_in: u64::MAX }] {
        let (c, rx) = cut_parts(3, verify);
        assert!(c
            .lock()
            .parts
            .iter()
            .all(|p| p.shard_ids.end - p.shard_ids.start > 2));
        join(&c, "w");
        work_until_done(&c, "w", Vec::new(), honest_cut);
        let parts: Vec<_> = rx.try_iter().flatten().collect();
        assert_eq!(parts.len(), 3);
        for (i, r) in parts {
            let m = r.expect("merged");
            let mut whole = m.input.prepare().expect("prepare").enumerate_all();
            whole.range = 0..whole.counts.combinations;
            assert_eq!(m.merged, whole, "part {i}");
            assert_eq!(
                m.finished.as_deref(),
                Some(&[b'f', i as u8][..]),
                "part {i}"
            );
        }
        // One finishing task per part, handed out once.
        let st = c.lock();
        let tasks = st
            .shards
            .iter()
            .filter(|s| matches!(s.work, ShardWork::Finishing(_)))
            .count();
        assert_eq!(tasks, 3);
        assert_eq!(st.stats.finishings, 3);
        assert_eq!(st.stats.requeued, 0);
    }
}

/// An estimate too high leaves shards past the part's combinations, one
/// too low an open last shard with the rest: the merged part is the
/// embedded run's either way.
#[test]
fn cut_parts_merge_the_same_whatever_their_estimate() {
    let count = fixplan_core::combination_count(4);
    for estimate in [4, count / 2, count * 3] {
        let (c, rx) = cut_parts_from(2, VerifyPolicy::All, estimate);
        join(&c, "w");
        work_until_done(&c, "w", Vec::new(), honest_cut);
        let parts: Vec<_> = rx.try_iter().flatten().collect();
        assert_eq!(parts.len(), 2, "estimate {estimate}");
        for (i, r) in parts {
            let m = r.expect("merged");
            let mut whole = m.input.prepare().expect("prepare").enumerate_all();
            whole.range = 0..whole.counts.combinations;
            assert_eq!(m.merged, whole, "part {i}, estimate {estimate}");
        }
    }
}

#[test]
fn forged_finishing_of_a_cut_part_is_refused() {
    let (c, rx) = cut_parts(1, VerifyPolicy::All);
    join(&c, "liar");
    let mut outcomes = Vec::new();
    let task = loop {
        let Frame::Msg(Msg::Reply {
            next: Next::Work(b),
            ..
        }) = report(&c, "liar", outcomes)
        else {
            panic!("no work")
        };
        if let Some(t) = b.iter().find(|a| matches!(a.task, Task::Finish { .. })) {
            break t.clone();
        }
        outcomes = honest_cut(&c, &b);
    };
    let mut forged = honest_cut(&c, std::slice::from_ref(&task));
    forge(&mut forged[0], b"forged");
    assert!(matches!(report(&c, "liar", forged), Frame::Refused(_)));
    assert_eq!(c.stats().rejected, 1);
    // Its shards are done again, by an honest worker, and finished by it.
    join(&c, "w");
    work_until_done(&c, "w", Vec::new(), honest_cut);
    let parts: Vec<_> = rx.try_iter().flatten().collect();
    assert_eq!(parts.len(), 1);
    let m = parts[0].1.as_ref().expect("merged");
    assert_eq!(m.finished.as_deref(), Some(&[b'f', 0][..]));
}

#[test]
fn a_cut_part_waiting_to_be_finished_is_merged_again_if_a_worker_of_it_is_banned() {
    let (c, rx) = cut_parts(2, VerifyPolicy::Sample { one_in: u64::MAX });
    join(&c, "a");
    join(&c, "b");
    // Trusted: `a`'s results are taken unchecked.
    if let Some(w) = c.lock().workers.get_mut("a") {
        w.rederived = crate::cluster::verify::FULL_CHECKS;
    }
    let part0: Vec<u64> = c.lock().parts[0].shard_ids.clone().collect();
    // `a` does every shard of part 0 (honest), so part 0 waits to be
    // finished, and `b` takes the finishing task.
    let batch: Vec<Assign> = {
        let mut st = c.lock();
        st.queue.retain(|id| !part0.contains(id));
        drop(st);
        let mut b = Vec::new();
        for &id in &part0 {
            let mut st = c.lock();
            let sh = &mut st.shards[id as usize];
            sh.status = ShardStatus::Leased {
                worker: "a".into(),
                until: Instant::now() + Duration::from_secs(60),
            };
            let ShardWork::Combinations(range) = &sh.work else {
                panic!("a shard")
            };
            let range = range.clone();
            let digest = st.parts[0].digest;
            st.workers.get_mut("a").expect("a").leased.insert(id);
            b.push(Assign {
                shard_id: id,
                digest,
                input: None,
                task: Task::Enumerate {
                    range,
                    good_enough: None,
                },
                budget: Default::default(),
            });
        }
        b
    };
    for o in honest_cut(&c, &batch) {
        let Outcome::Done(d) = o else {
            panic!("failed")
        };
        c.result(*d, "a").expect("taken");
    }
    let task = c.lock().parts[0]
        .finishing
        .expect("part 0 waits to be finished");
    let Next::Work(for_b) = c.next_work("b") else {
        panic!("no work for b")
    };
    assert_eq!(for_b[0].shard_id, task, "finishing goes first");
    // `a` then sends a result for another part than it was given.
    let Next::Work(for_a) = c.next_work("a") else {
        panic!("no work for a")
    };
    let mut bad = honest_cut(&c, &for_a);
    if let Some(Outcome::Done(d)) = bad.first_mut() {
        d.digest = [9; 32];
    }
    assert!(matches!(report(&c, "a", bad), Frame::Refused(_)));
    // Part 0 held `a`'s results: its finishing is called off, and `b`'s
    // finishing of it comes too late.
    assert_eq!(c.lock().parts[0].finishing, None);
    let late = honest_cut(&c, &for_b[..1]);
    let Frame::Msg(Msg::Reply { notes, next }) = report(&c, "b", late) else {
        panic!("refused")
    };
    assert!(notes.iter().any(|n| n.contains("not taken")), "{notes:?}");
    assert!(rx.try_iter().flatten().all(|(i, _)| i != 0));
    let outcomes = match next {
        Next::Work(b) => honest_cut(&c, &b),
        _ => Vec::new(),
    };
    work_until_done(&c, "b", outcomes, honest_cut);
    let parts: Vec<_> = rx.try_iter().flatten().collect();
    assert_eq!(parts.len(), 2, "each part once");
    for (i, r) in parts {
        let m = r.expect("merged");
        assert_eq!(m.finished.as_deref(), Some(&[b'f', i as u8][..]));
        for &id in &part0 {
            assert_eq!(
                c.lock().shards[id as usize].by.as_deref(),
                Some("b"),
                "part 0 redone by b"
            );
        }
    }
}

/// The honest outcome of each task of `batch`, whatever its part.
fn honest_any(scheduler: &Scheduler, batch: &[Assign]) -> Vec<Outcome> {
    batch
        .iter()
        .map(|a| {
            let prep = {
                let st = scheduler.lock();
                let part = st.shards[a.shard_id as usize].part;
                st.parts[part].prep.clone().expect("prepared")
            };
            done(a, prep.enumerate_range(range_of(a)), None)
        })
        .collect()
}

/// Workers lost holding a batch: every part in it is suspected once and
/// its shards go out alone; the part whose lone shard is with the next
/// worker lost is failed and never handed out again; the others are
/// merged as usual.
#[test]
fn a_part_whose_shards_were_with_two_lost_workers_is_failed() {
    let (mut c, rx) = core_rx(3, 8, VerifyPolicy::All);
    c.settings.batch_cost = u64::MAX;
    join(&c, "w1");
    let first = ids(&c.next_work("w1"));
    let part_of = |id: u64| c.lock().shards[id as usize].part;
    let parts: std::collections::BTreeSet<usize> = first.iter().map(|&id| part_of(id)).collect();
    assert!(parts.len() >= 2, "{first:?}");
    c.worker_lost("w1");
    join(&c, "w2");
    let lone = ids(&c.next_work("w2"));
    assert_eq!(lone.len(), 1, "a suspect's shard goes alone: {lone:?}");
    let killer = part_of(lone[0]);
    c.worker_lost("w2");
    join(&c, "w3");
    let mut next = c.next_work("w3");
    loop {
        match next {
            Next::Work(batch) => {
                assert!(batch.iter().all(|a| part_of(a.shard_id) != killer));
                // A suspect holds its worker alone.
                let suspects = batch
                    .iter()
                    .filter(|a| parts.contains(&part_of(a.shard_id)))
                    .count();
                assert!(suspects == 0 || batch.len() == 1, "{}", batch.len());
                let outcomes = honest_any(&c, &batch);
                let Frame::Msg(Msg::Reply { next: n, .. }) = report(&c, "w3", outcomes) else {
                    panic!("no reply")
                };
                next = n;
            }
            Next::Idle { .. } => next = c.next_work("w3"),
            Next::Done => break,
            other => panic!("{other:?}"),
        }
    }
    let delivered: Vec<Delivery> = rx.try_iter().flatten().collect();
    assert_eq!(delivered.len(), 3);
    for (i, d) in delivered {
        match d {
            Err(PartFailure::Killed { workers, alone }) => {
                assert_eq!((i, workers, alone), (killer, 2, 1));
                assert_eq!(
                    PartFailure::Killed { workers, alone }.status(),
                    fixplan_core::Status::Failed
                );
            }
            Ok(_) => assert_ne!(i, killer),
            Err(e) => panic!("part #{i}: {e}"),
        }
    }
}

/// Leases `held` to `worker` as a reply would have.
fn lease_to(c: &Scheduler, worker: &str, held: &[u64]) {
    let mut st = c.lock();
    st.queue.retain(|id| !held.contains(id));
    for &id in held {
        st.shards[id as usize].status = ShardStatus::Leased {
            worker: worker.into(),
            until: Instant::now() + Duration::from_secs(3600),
        };
    }
    let w = st.workers.get_mut(worker).expect("joined");
    w.leased.extend(held.iter().copied());
}

/// Two workers lost at once, each holding a batch with shards of the same
/// two parts (handed out before either loss was seen): neither death is a
/// part's own, so neither part is failed, only suspected; the next worker
/// lost holding one part's shard alone fails that part, and one lost
/// holding shards of the failed part and of the other does not fail it.
#[test]
fn deaths_only_in_batches_fail_no_part() {
    let (c, _rx) = core_rx(2, 2, VerifyPolicy::All);
    for w in ["w1", "w2", "w3", "w4"] {
        join(&c, w);
    }
    let (a, b) = {
        let st = c.lock();
        (st.parts[0].shard_ids.clone(), st.parts[1].shard_ids.clone())
    };
    assert!(a.end - a.start >= 4 && b.end - b.start >= 3, "{a:?} {b:?}");
    lease_to(&c, "w1", &[a.start, b.start]);
    lease_to(&c, "w2", &[a.start + 1, b.start + 1]);
    c.worker_lost("w1");
    c.worker_lost("w2");
    assert!(c.lock().done.is_empty(), "no part failed");
    {
        let st = c.lock();
        for p in &st.parts[..2] {
            assert_eq!((p.deaths.workers, p.deaths.alone), (2, 0));
            assert!(p.suspect() && !p.closed);
        }
    }
    lease_to(&c, "w3", &[a.start + 2]);
    c.worker_lost("w3");
    let failed = |c: &Scheduler| {
        let st = c.lock();
        let done: Vec<_> = st
            .done
            .iter()
            .map(|(i, d)| (*i, d.as_ref().err().cloned()))
            .collect();
        done
    };
    match failed(&c).as_slice() {
        [(0, Some(PartFailure::Killed { workers, alone }))] => {
            assert_eq!((*workers, *alone), (3, 1))
        }
        other => panic!("{other:?}"),
    }
    // A worker that dies holding the failed part's shard too did not die
    // holding the other alone.
    lease_to(&c, "w4", &[a.start + 3, b.start + 2]);
    c.worker_lost("w4");
    assert_eq!(failed(&c).len(), 1, "part 1 not failed");
    let st = c.lock();
    assert_eq!(
        (st.parts[1].deaths.workers, st.parts[1].deaths.alone),
        (3, 0)
    );
    assert!(!st.parts[1].closed);
}

/// Every task carries the run's budget; a worker's over-budget answer for
/// one shard makes its part `over_budget` (no shard of it goes out
/// again) and the other parts are merged as ever; a part whose
/// `--part-seconds` ran out before all its shards went is over too.
#[test]
fn over_budget_answers_and_spent_time_end_their_part() {
    let (mut c, rx) = core_rx(2, 3, VerifyPolicy::All);
    c.settings.part_setups = Some(1_000);
    c.settings.batch_cost = 1;
    join(&c, "w");
    let Next::Work(batch) = c.next_work("w") else {
        panic!("no work")
    };
    assert!(batch.iter().all(|a| a.budget.setups == Some(1_000)));
    let over = batch[0].shard_id;
    let over_part = c.lock().shards[over as usize].part;
    let failed = Outcome::Failed(TaskFailed {
        shard_id: over,
        error: fixplan_worker::protocol::TaskError::OverBudget(BudgetStop::Setups(1_000)),
    });
    let mut next = match report(&c, "w", vec![failed]) {
        Frame::Msg(Msg::Reply { next, .. }) => next,
        other => panic!("{other:?}"),
    };
    loop {
        match next {
            Next::Work(batch) => {
                let part_of = |id: u64| c.lock().shards[id as usize].part;
                assert!(batch.iter().all(|a| part_of(a.shard_id) != over_part));
                let Frame::Msg(Msg::Reply { next: n, .. }) =
                    report(&c, "w", honest_any(&c, &batch))
                else {
                    panic!("no reply")
                };
                next = n;
            }
            Next::Idle { .. } => next = c.next_work("w"),
            Next::Done => break,
            other => panic!("{other:?}"),
        }
    }
    let delivered: Vec<Delivery> = rx.try_iter().flatten().collect();
    assert_eq!(delivered.len(), 2);
    for (i, d) in delivered {
        match d {
            Err(e @ PartFailure::OverBudget(BudgetStop::Setups(1_000))) => {
                assert_eq!(i, over_part);
                assert_eq!(e.status(), fixplan_core::Status::OverBudget);
            }
            Ok(_) => assert_ne!(i, over_part),
            Err(e) => panic!("part #{i}: {e}"),
        }
    }
    // Time: the clock starts with a part's first task, and a part whose
    // time is up when its next shard would go out is over.
    let (mut c, rx) = core_rx(1, 3, VerifyPolicy::All);
    c.settings.part_seconds = Some(0.001);
    c.settings.batch_cost = 1;
    join(&c, "w");
    let first = match c.next_work("w") {
        Next::Work(batch) => batch,
        other => panic!("{other:?}"),
    };
    assert!(first.iter().all(|a| a.budget.millis == Some(1)));
    std::thread::sleep(Duration::from_millis(5));
    let outcomes = honest_any(&c, &first);
    let Frame::Msg(Msg::Reply { next, .. }) = report(&c, "w", outcomes) else {
        panic!("no reply")
    };
    let next = match next {
        Next::Idle { .. } => c.next_work("w"),
        other => other,
    };
    assert_eq!(next, Next::Done, "no shard of a part out of time goes out");
    let delivered: Vec<Delivery> = rx.try_iter().flatten().collect();
    assert!(matches!(
        delivered.as_slice(),
        [(0, Err(PartFailure::OverBudget(BudgetStop::Deadline)))]
    ));
}

/// Part 0 of a one-part scheduler with `--good-enough` (any fixture is
/// good enough) in shards of 3, every shard in one batch: each shard
/// answered honestly, except that `over` shards answer `stop`. What the
/// part becomes, and the first combination with a fixture.
fn good_enough_with_overs(
    over: impl Fn(&Range<u64>, u64) -> bool,
    stop: BudgetStop,
) -> (Result<Option<u64>, PartFailure>, u64) {
    let (mut c, rx) = core_rx(1, 3, VerifyPolicy::All);
    let good = 1e9;
    c.settings.good_enough = Some(good);
    c.settings.part_setups = Some(1_000_000);
    c.settings.batch_cost = u64::MAX;
    join(&c, "w");
    let prep = c.lock().parts[0].prep.clone().expect("prepared");
    let hit = fixplan_worker::run_shard_until(&prep, 0..prep.combination_count(), Some(good))
        .1
        .expect("a fixture");
    let Next::Work(batch) = c.next_work("w") else {
        panic!("no work")
    };
    assert!(
        batch.iter().any(|a| range_of(a).start > hit),
        "shards past the hit at {hit}"
    );
    // Answers past the stop first: their verdict waits for the stop.
    let mut outcomes: Vec<(u64, Outcome)> = batch
        .iter()
        .map(|a| {
            let range = range_of(a);
            let outcome = if over(&range, hit) {
                Outcome::Failed(TaskFailed {
                    shard_id: a.shard_id,
                    error: fixplan_worker::protocol::TaskError::OverBudget(stop),
                })
            } else {
                let (result, h) = fixplan_worker::run_shard_until(&prep, range.clone(), Some(good));
                match done(a, result, None) {
                    Outcome::Done(mut d) => {
                        d.answer = match d.answer {
                            Answer::Enumerated { result, .. } => {
                                Answer::Enumerated { result, hit: h }
                            }
                            other => other,
                        };
                        Outcome::Done(d)
                    }
                    failed => failed,
                }
            };
            (u64::MAX - range.start, outcome)
        })
        .collect();
    outcomes.sort_by_key(|o| o.0);
    report(&c, "w", outcomes.into_iter().map(|o| o.1).collect());
    let delivered: Vec<Delivery> = rx.try_iter().flatten().collect();
    let [(0, part)] = <[Delivery; 1]>::try_from(delivered).expect("one part delivered") else {
        panic!("part 0")
    };
    (part.map(|m| m.stopped_at), hit)
}

/// With `--good-enough`, a shard past the part's stop that stopped on
/// its budget does not count (the embedded run never enumerates it); one
/// up to the stop makes the part over budget, for the budget it stopped
/// on, setups or fixtures.
#[test]
fn a_budget_stop_counts_only_up_to_the_good_enough_stop() {
    let past = |r: &Range<u64>, hit: u64| r.start > hit;
    let (part, hit) = good_enough_with_overs(past, BudgetStop::Setups(10));
    assert!(matches!(part, Ok(Some(h)) if h == hit), "{part:?}");
    let (part, _) = good_enough_with_overs(past, BudgetStop::Fixtures(5));
    assert!(matches!(part, Ok(Some(_))), "{part:?}");
    let first = |r: &Range<u64>, _: u64| r.start == 0;
    for stop in [BudgetStop::Setups(10), BudgetStop::Fixtures(5)] {
        let (part, hit) = good_enough_with_overs(first, stop);
        assert!(hit >= 3, "the first shard is before the stop: {hit}");
        assert!(
            matches!(part, Err(PartFailure::OverBudget(s)) if s == stop),
            "{part:?}"
        );
    }
}
