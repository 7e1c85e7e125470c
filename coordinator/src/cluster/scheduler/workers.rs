//! The workers: who joins and over which data path, who is lost, whose
//! leases run out, and what becomes of the work of a worker caught
//! sending a bad result.

use super::errors::{PartFailure, Refusal};
use super::state::{
    back_in_queue, fail_part, requeue, strike, Gone, Settings, ShardSlot, ShardStatus, ShardWork,
    State, WorkerSlot, ROLE,
};
use fixplan_worker::protocol::{DataPath, Join, Msg, Next, TransportChoice, Welcome};
use std::collections::HashSet;
use std::time::Instant;
use tracing::{info, warn};

/// Where a joining worker is to send its requests: iceoryx2 shared memory
/// if it is on this host and the coordinator serves it, else zenoh; a
/// refusal if iceoryx2 is forced but cannot reach it.
pub(super) fn data_path(settings: &Settings, joining: &Join) -> Result<DataPath, Refusal> {
    let same_host = joining.host_id == settings.host_id;
    let forced = |t| settings.transport == t || joining.transport == t;
    if forced(TransportChoice::Zenoh) {
        return Ok(DataPath::Zenoh);
    }
    match (&settings.iox, same_host) {
        (Some(d), true) => Ok(d.clone()),
        _ if forced(TransportChoice::Iceoryx2) => {
            warn!(
                role = ROLE,
                "refused worker {}: iceoryx2 forced but it is on another host", joining.worker
            );
            Err(Refusal::IoxOnAnotherHost)
        }
        _ => Ok(DataPath::Zenoh),
    }
}

/// Welcomes a worker, or tells it the run is over. A worker that joins
/// again under its name (restarted) had its shards: they go back to the
/// queue.
pub(super) fn join(st: &mut State, settings: &Settings, joining: Join, data: DataPath) -> Msg {
    if st.open_parts == 0 {
        return Msg::Reply {
            notes: Vec::new(),
            next: Next::Done,
        };
    }
    st.stats.workers_joined += 1;
    let how = if data == DataPath::Zenoh {
        "zenoh"
    } else {
        "iceoryx2"
    };
    info!(
        role = ROLE,
        "worker {} joined (pid {}, {} threads, fixplan {}, shards over {how})",
        joining.worker,
        joining.pid,
        joining.threads,
        joining.software
    );
    let old = st.workers.insert(
        joining.worker.clone(),
        WorkerSlot {
            name: joining.worker.as_str().into(),
            parts_sent: HashSet::new(),
            leased: HashSet::new(),
            got_done: false,
            shards: 0,
            threads: u64::from(joining.threads.max(1)),
            rederived: 0,
        },
    );
    if let Some(old) = old {
        // Restarted: it died holding them.
        let held: Vec<u64> = old.leased.into_iter().collect();
        gone_holding(st, &joining.worker, (&held, &held), Gone::Died);
    }
    Msg::Welcome(Welcome {
        run_id: settings.run_id.clone(),
        data,
        lease_ms: settings.lease.as_millis() as u64,
    })
}

/// A worker's liveliness token vanished: its shards go back to the queue.
pub(super) fn lost(st: &mut State, worker: &str) {
    if let Some(w) = st.workers.remove(worker) {
        st.stats.workers_lost += 1;
        let held: Vec<u64> = w.leased.into_iter().collect();
        let n = gone_holding(st, worker, (&held, &held), Gone::Died);
        if st.open_parts > 0 {
            info!(
                role = ROLE,
                "worker {worker} left after {} shards; {n} shards back in the queue", w.shards
            );
        }
    }
}

/// Shards whose lease ran out by `now` go back to the queue (their worker
/// may still answer: the first result wins).
pub(super) fn expire_leases(st: &mut State, now: Instant) {
    let expired: Vec<(u64, String)> = st
        .shards
        .iter()
        .enumerate()
        .filter_map(|(i, s)| match &s.status {
            ShardStatus::Leased { worker, until } if *until <= now => {
                Some((i as u64, worker.clone()))
            }
            _ => None,
        })
        .collect();
    let mut by_worker: std::collections::BTreeMap<String, Vec<u64>> = Default::default();
    for (id, worker) in expired {
        warn!(
            role = ROLE,
            "shard {id}: lease of worker {worker} ran out; back in the queue"
        );
        by_worker.entry(worker).or_default().push(id);
    }
    for (worker, held) in by_worker {
        // All it held, the expired ones included.
        let holding: Vec<u64> = st
            .workers
            .get(&worker)
            .map(|w| w.leased.iter().copied().collect())
            .unwrap_or_else(|| held.clone());
        if let Some(w) = st.workers.get_mut(&worker) {
            w.leased.retain(|id| !held.contains(id));
        }
        gone_holding(st, &worker, (&held, &holding), Gone::TimedOut);
    }
}

/// A worker is gone (lost, restarted) or timed out with the shards
/// `shards.0` (of all it held, `shards.1`): they go back to the queue, and
/// the parts among them count it ([`strike`]); a part at its second,
/// one of them its own (a worker holding nothing else: its shards go out
/// alone after the first), is failed and handed out no more. Returns the
/// shards put back.
fn gone_holding(st: &mut State, worker: &str, shards: (&[u64], &[u64]), how: Gone) -> usize {
    let condemned = strike(st, worker, shards, how);
    let n = requeue(st, shards.0.iter().copied());
    for p in condemned {
        let d = st.parts[p].deaths.clone();
        let idx = st.part_index.get(p).copied().unwrap_or(p);
        warn!(
            role = ROLE,
            "part #{idx}: {} workers were lost or timed out holding its shards ({} of them holding nothing else); failed, not handed out again",
            d.workers,
            d.alone
        );
        fail_part(
            st,
            p,
            PartFailure::Killed {
                workers: d.workers,
                alone: d.alone,
            },
        );
    }
    n
}

/// A worker sent a bad result for shard `id`: it gets no more work, what
/// it holds and that shard go back to the queue, and what it did for
/// parts still open is done again.
pub(super) fn ban(st: &mut State, worker: &str, id: u64) {
    if let Some(w) = st.workers.remove(worker) {
        requeue(st, w.leased.into_iter());
    }
    st.banned.insert(worker.to_string());
    requeue(st, std::iter::once(id));
    redo_work_of(st, worker);
}

/// A worker failed a check: what it did for parts still open is done
/// again (its results there were taken, most of them unchecked under
/// [`crate::cluster::VerifyPolicy::Sample`]). Parts already delivered keep
/// theirs: a worker is checked in full until it has earned some trust,
/// which is where a build or platform that computes differently shows up.
fn redo_work_of(st: &mut State, worker: &str) {
    let mine = |sh: &ShardSlot| sh.by.as_deref() == Some(worker);
    let parts: HashSet<usize> = st
        .shards
        .iter()
        .filter(|sh| mine(sh) && !st.parts[sh.part].closed)
        .map(|sh| sh.part)
        .collect();
    for p in parts {
        cancel_finishing(st, p);
        let part = &mut st.parts[p];
        part.partials
            .retain(|h| st.shards[h.shard as usize].by.as_deref() != Some(worker));
        let held: HashSet<u64> = part.partials.iter().map(|h| h.shard).collect();
        part.stop = part.partials.iter().filter_map(|h| h.hit).min();
        let lists = part
            .partials
            .iter()
            .map(|h| h.result.fixtures.clone())
            .collect();
        part.top = fixplan_core::merge_ranked(lists, part.top_k());
        let stop = part.stop;
        for id in part.shard_ids.clone() {
            let sh = &st.shards[id as usize];
            // Done but not held: this worker's, or skipped past a stop
            // that may have been its.
            if sh.status == ShardStatus::Done && !held.contains(&id) && !sh.past(stop) {
                back_in_queue(st, id);
            }
        }
    }
}

/// A cut part waiting to be finished is to be merged again: the merged
/// result its finishing task holds is dropped, and a result of that task
/// still to come is a duplicate.
fn cancel_finishing(st: &mut State, slot: usize) {
    let Some(id) = st.parts[slot].finishing.take() else {
        return;
    };
    let task = &mut st.shards[id as usize];
    if task.status == ShardStatus::Queued {
        st.queued_cost = st.queued_cost.saturating_sub(task.cost);
    }
    task.status = ShardStatus::Done;
    task.work = ShardWork::Finishing(None);
}
