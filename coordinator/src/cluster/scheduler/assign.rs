//! Handing out work: the next batch of shards for a worker that has just
//! reported (and so holds none any more), sized so that the workers run
//! out of work together.

use super::state::{requeue, Settings, ShardStatus, ShardWork, State, ROLE};
use super::tasks;
use fixplan_worker::protocol::{Assign, Next};
use std::time::Instant;
use tracing::info;

/// What `worker`, still working on `holding`, is to do next: work, wait,
/// rejoin, or stop.
pub(super) fn next_work(
    st: &mut State,
    settings: &Settings,
    worker: &str,
    holding: &[u64],
) -> Next {
    let Some(w) = st.workers.get_mut(worker) else {
        return Next::Rejoin;
    };
    // Anything else still leased to it went out in a reply it never got.
    let holding: std::collections::HashSet<u64> = holding.iter().copied().collect();
    let lost: Vec<u64> = w.leased.extract_if(|id| !holding.contains(id)).collect();
    if st.open_parts == 0 {
        w.got_done = true;
        return Next::Done;
    }
    requeue(st, lost.into_iter());
    if !st.started {
        if st.workers.len() < settings.min_workers {
            return Next::Idle { retry_ms: 10 };
        }
        st.started = true;
        info!(
            role = ROLE,
            "{} workers: starting ({} shards)",
            st.workers.len(),
            st.shards.len()
        );
    }
    let limit = batch_limit(st, settings, worker);
    let Some(batch) = lease_batch(st, settings, worker, limit) else {
        return Next::Rejoin;
    };
    if batch.is_empty() {
        // Short: the other shards may be done any moment, and then this
        // worker learns at once that the run is over.
        return Next::Idle { retry_ms: 5 };
    }
    st.stats.assigned += batch.len() as u64;
    Next::Work(batch)
}

/// Guided self-scheduling, per worker thread: a worker's batch is about
/// the cost left divided among twice the threads, times its own threads,
/// at most `batch_cost` a thread; so batches shrink towards the end and
/// the workers finish together. One request feeds all of a worker's
/// threads (its batch runs on its whole pool), so a batch sized for one
/// thread would leave a 64-thread worker mostly idle, and cost the
/// coordinator a round trip per thread's worth of work.
fn batch_limit(st: &State, settings: &Settings, worker: &str) -> (u64, usize) {
    let threads: u64 = st.workers.values().map(|w| w.threads).sum();
    let mine = st.workers.get(worker).map_or(1, |w| w.threads).max(1);
    let cost = (st.queued_cost.saturating_mul(mine) / (2 * threads.max(1)))
        .clamp(1, settings.batch_cost.max(1).saturating_mul(mine));
    (cost, crate::job::shards::max_batch_shards(mine))
}

/// Leases shards from the front of the queue to `worker` until they cost
/// `limit.0` or number `limit.1`, skipping those no longer needed; `None`
/// if it is not known.
fn lease_batch(
    st: &mut State,
    settings: &Settings,
    worker: &str,
    limit: (u64, usize),
) -> Option<Vec<Assign>> {
    let mut batch = Vec::new();
    let mut cost = 0;
    // Suspects' shards this worker may not take now, back in front after.
    let mut deferred = Vec::new();
    let holds_nothing = st.workers.get(worker)?.leased.is_empty();
    // Parts whose `--part-seconds` ran out before all their shards went.
    let mut out_of_time = Vec::new();
    let now = Instant::now();
    while cost < limit.0 && batch.len() < limit.1 {
        let Some(id) = st.queue.pop_front() else {
            break;
        };
        let sh = &mut st.shards[id as usize];
        if sh.status != ShardStatus::Queued {
            continue;
        }
        let part = &st.parts[sh.part];
        // A suspect's shard goes alone, to a worker holding nothing.
        let suspect = part.suspect() && !part.closed;
        if suspect && !(holds_nothing && batch.is_empty()) {
            deferred.push(id);
            continue;
        }
        let needed = !part.closed && !sh.past(part.stop);
        let Some(task) = needed.then(|| tasks::task(part, sh, settings)).flatten() else {
            // Past a `--good-enough` hit, or of a part delivered: not
            // needed any more.
            sh.status = ShardStatus::Done;
            st.queued_cost = st.queued_cost.saturating_sub(sh.cost);
            continue;
        };
        let budget = match super::budget::task_budget(&mut st.parts[sh.part], settings, now) {
            Ok(budget) => budget,
            Err(stop) if matches!(sh.work, ShardWork::Combinations(_)) => {
                out_of_time.push((sh.part, stop));
                continue;
            }
            // A cut part's finishing: its enumeration is over.
            Err(_) => Default::default(),
        };
        let part = &st.parts[sh.part];
        sh.status = ShardStatus::Leased {
            worker: worker.to_string(),
            until: now + settings.lease,
        };
        st.queued_cost = st.queued_cost.saturating_sub(sh.cost);
        cost += sh.cost;
        let w = st.workers.get_mut(worker)?;
        w.leased.insert(id);
        // The part's input goes with its first shard to each worker.
        let input = w.parts_sent.insert(sh.part).then(|| part.input.clone());
        batch.push(Assign {
            shard_id: id,
            digest: part.digest,
            input,
            task,
            budget,
        });
        if suspect {
            break;
        }
    }
    for id in deferred.into_iter().rev() {
        st.queue.push_front(id);
    }
    for (p, stop) in out_of_time {
        super::budget::fail(st, p, stop);
    }
    Some(batch)
}
