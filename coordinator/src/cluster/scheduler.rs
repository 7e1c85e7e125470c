//! The coordinator's bookkeeping: the shard queue, leases, workers, and the
//! partial results of each part. Transport-free: every request arrives as
//! bytes through [`Scheduler::handle`] (zenoh queryables and the iceoryx2 server
//! call it alike) and the answer goes back as bytes.

use super::verify::{self, VerifyPolicy};
use fixplan_core::{merge, Fixture, PartialResult, PreparedPart};
use fixplan_worker::part_input::{short_hex, PartInput};
use fixplan_worker::protocol::{
    decode, encode, encode_refused, refusal_for, Assign, DataPath, Digest, Frame, Join, Msg, Next,
    Outcome, ShardDone, ShardFailed, TransportChoice, Welcome,
};
use std::collections::{HashMap, HashSet, VecDeque};
use std::ops::Range;
use std::sync::mpsc::Sender;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use tracing::{info, warn};

/// A finished part: merged result, or the message of why it failed.
pub type PartDone = (usize, Result<Finished, String>);

/// A part's merged result, with the part prepared if the coordinator had
/// to prepare it (to cut it into shards or to re-derive its fixtures).
#[derive(Debug)]
pub struct Finished {
    pub prep: Option<Arc<PreparedPart>>,
    pub input: Arc<PartInput>,
    pub merged: PartialResult,
    /// `--good-enough`: the combination where the part stopped.
    pub stopped_at: Option<u64>,
}

/// Shard range meaning "every combination of the part": a part that
/// stays whole is sent without the coordinator preparing it (it does not
/// know the exact count); the worker's enumeration stops at the count.
pub const WHOLE: Range<u64> = 0..u64::MAX;

pub(crate) struct PartSlot {
    /// `None` until needed: small parts go out whole and are prepared here
    /// only when a result of theirs is re-derived.
    pub prep: Option<Arc<PreparedPart>>,
    pub source: Arc<PartInput>,
    pub input: Arc<Vec<u8>>,
    pub digest: Digest,
    /// Ids of its shards (contiguous, in combination order).
    pub shard_ids: Range<u64>,
    /// The first `--good-enough` hit reported so far: the part ends with
    /// the shards up to it, the rest are dropped.
    pub stop: Option<u64>,
    pub partials: Vec<Held>,
    pub top: Vec<Fixture>,
    pub closed: bool,
}

impl PartSlot {
    fn top_k(&self) -> usize {
        self.source.params.top_k
    }

    /// The part prepared, here and once, if it was sent out unprepared.
    fn prepared(&mut self) -> Result<Arc<PreparedPart>, fixplan_core::PrepareError> {
        if let Some(p) = &self.prep {
            return Ok(p.clone());
        }
        let p = Arc::new(self.source.prepare()?);
        self.prep = Some(p.clone());
        Ok(p)
    }
}

#[derive(Debug, Clone, PartialEq)]
enum ShardStatus {
    Queued,
    Leased { worker: String, until: Instant },
    Done,
}

struct ShardSlot {
    part: usize,
    range: Range<u64>,
    /// [`crate::job::shards::cost`] of the shard, for batching.
    cost: u64,
    status: ShardStatus,
    /// The worker whose result was taken.
    by: Option<Arc<str>>,
}

/// A shard result held until its part is complete.
pub(crate) struct Held {
    shard: u64,
    hit: Option<u64>,
    result: PartialResult,
}

struct WorkerSlot {
    name: Arc<str>,
    parts_sent: HashSet<usize>,
    leased: HashSet<u64>,
    got_done: bool,
    shards: u64,
    threads: u64,
    /// Fixtures of this worker re-derived so far (until there are
    /// [`verify::FULL_CHECKS`], all its results are checked in full).
    rederived: u64,
}

/// Run-wide figures (for the benchmark and the final log line).
#[derive(Debug, Clone, Default)]
pub struct Stats {
    pub shards: u64,
    pub results: u64,
    pub duplicates: u64,
    pub rejected: u64,
    pub requeued: u64,
    pub workers_joined: u64,
    pub workers_lost: u64,
    pub fixtures_rederived: u64,
    /// Bytes of results and assignments (frames, as sent).
    pub result_bytes: u64,
    pub assign_bytes: u64,
    /// Results checked in full (every fixture entering the top-k re-derived).
    pub results_rederived: u64,
    /// Requests (reports) answered, and shards handed out.
    pub requests: u64,
    pub assigned: u64,
    /// CPU time of the coordinator's threads handling requests (thread
    /// CPU clock: time the thread was preempted does not count).
    pub handle_micros: u64,
    /// Worker time enumerating, as reported.
    pub worker_micros: u64,
}

pub struct Settings {
    pub run_id: String,
    pub host_id: String,
    pub transport: TransportChoice,
    /// The iceoryx2 data path, when the coordinator serves one.
    pub iox: Option<DataPath>,
    /// Workers it serves at most (more on this host use zenoh).
    pub iox_clients: usize,
    pub lease: Duration,
    pub min_workers: usize,
    pub verify: VerifyPolicy,
    /// `--good-enough` threshold of every part.
    pub good_enough: Option<f64>,
    /// Cost of work ([`crate::job::shards::cost`]) handed out in one assignment at
    /// most: small shards travel together up to it.
    pub batch_cost: u64,
}

pub(crate) struct State {
    parts: Vec<PartSlot>,
    shards: Vec<ShardSlot>,
    queue: VecDeque<u64>,
    workers: HashMap<String, WorkerSlot>,
    started: bool,
    open_parts: usize,
    banned: HashSet<String>,
    /// Cost of the shards in the queue (batches shrink as it runs out, so
    /// the last ones end together).
    queued_cost: u64,
    /// Parts finished while answering the current request.
    done: Vec<PartDone>,
    pub stats: Stats,
}

pub struct Scheduler {
    pub settings: Settings,
    st: Mutex<State>,
    /// Finished parts go to the consumer in one message per request (a
    /// wake-up per part cost the coordinator more than merging them).
    tx: Mutex<Sender<Vec<PartDone>>>,
}

const ROLE: &str = "coordinator";

impl Scheduler {
    /// `parts`: `(index, prepared part, wire input, shard ranges)` of the
    /// parts to distribute.
    pub(crate) fn new(
        settings: Settings,
        parts: Vec<(usize, PartSlot, Vec<Range<u64>>, usize)>,
        tx: Sender<Vec<PartDone>>,
    ) -> (Scheduler, Vec<usize>) {
        let mut st = State {
            parts: Vec::new(),
            shards: Vec::new(),
            queue: VecDeque::new(),
            workers: HashMap::new(),
            started: false,
            open_parts: 0,
            banned: HashSet::new(),
            queued_cost: 0,
            done: Vec::new(),
            stats: Stats::default(),
        };
        let mut index = Vec::new();
        for (i, mut slot, ranges, segments) in parts {
            let p = st.parts.len();
            let first = st.shards.len() as u64;
            slot.shard_ids = first..first + ranges.len() as u64;
            for r in ranges {
                let combinations = if r == WHOLE {
                    fixplan_core::combinations::combination_count(segments)
                } else {
                    r.end - r.start
                };
                let cost = crate::job::shards::cost(combinations, segments);
                st.queue.push_back(st.shards.len() as u64);
                st.queued_cost += cost;
                st.shards.push(ShardSlot {
                    part: p,
                    range: r,
                    cost,
                    status: ShardStatus::Queued,
                    by: None,
                });
            }
            st.parts.push(slot);
            index.push(i);
            st.open_parts += 1;
        }
        st.stats.shards = st.shards.len() as u64;
        (
            Scheduler {
                settings,
                st: Mutex::new(st),
                tx: Mutex::new(tx),
            },
            index,
        )
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, State> {
        self.st.lock().unwrap_or_else(|e| e.into_inner())
    }

    pub fn stats(&self) -> Stats {
        self.lock().stats.clone()
    }

    pub fn finished(&self) -> bool {
        self.lock().open_parts == 0
    }

    /// Whether every worker still known has been told the run is over.
    pub fn all_told(&self) -> bool {
        self.lock().workers.values().all(|w| w.got_done)
    }

    /// Answers one request. Never panics on input: unreadable frames are
    /// logged and answered with a refusal.
    pub fn handle(&self, bytes: &[u8], part_index: &[usize]) -> Vec<u8> {
        let t0 = super::cpu_time::thread_micros();
        let reply = match decode(bytes) {
            Err(e) => {
                warn!(role = ROLE, "dropped a message: {e}");
                encode_refused(&refusal_for(&e))
            }
            Ok(Frame::Refused(r)) => {
                warn!(role = ROLE, "dropped an unexpected refusal: {r}");
                encode_refused("refused: unexpected message")
            }
            Ok(Frame::Msg(m)) => {
                let has_results =
                    matches!(&m, Msg::Report { outcomes, .. } if !outcomes.is_empty());
                match self.on_msg(m, part_index) {
                    Ok(reply) => self.encode_reply(&reply, has_results, bytes.len()),
                    Err(reason) => encode_refused(&reason),
                }
            }
        };
        let done = {
            let mut st = self.lock();
            st.stats.handle_micros += super::cpu_time::thread_micros().saturating_sub(t0);
            std::mem::take(&mut st.done)
        };
        if !done.is_empty() {
            let _ = self.tx.lock().unwrap_or_else(|e| e.into_inner()).send(done);
        }
        reply
    }

    /// Encodes a reply, counting the bytes of results in and work out.
    fn encode_reply(&self, reply: &Msg, has_results: bool, request_len: usize) -> Vec<u8> {
        let out = match encode(reply) {
            Ok(b) => b,
            Err(e) => encode_refused(&format!("refused: {e}")),
        };
        let mut st = self.lock();
        st.stats.requests += 1;
        if has_results {
            st.stats.result_bytes += request_len as u64;
        }
        if let Msg::Reply {
            next: Next::Work(_),
            ..
        } = reply
        {
            st.stats.assign_bytes += out.len() as u64;
        }
        out
    }

    /// The reply, or the reason of a refusal.
    fn on_msg(&self, m: Msg, part_index: &[usize]) -> Result<Msg, String> {
        let banned = |w: &str| self.lock().banned.contains(w);
        let refusal =
            |w: &str| format!("refused: worker {w} sent results that failed verification");
        match m {
            Msg::Join(j) if banned(&j.worker) => Err(refusal(&j.worker)),
            Msg::Report { worker, .. } if banned(&worker) => Err(refusal(&worker)),
            Msg::Join(j) => self.join(j),
            Msg::Report { worker, outcomes } => {
                let mut notes = Vec::new();
                for o in outcomes {
                    // One bad result and nothing else of this worker counts
                    // (its other shards are back in the queue already).
                    if banned(&worker) {
                        break;
                    }
                    let (id, taken) = match o {
                        Outcome::Done(r) => (r.shard_id, self.result(*r, &worker, part_index)),
                        Outcome::Failed(f) => (f.shard_id, self.failed(f, &worker, part_index)),
                    };
                    if let Err(note) = taken {
                        notes.push(format!("shard {id} not taken: {note}"));
                    }
                }
                if banned(&worker) {
                    return Err(refusal(&worker));
                }
                Ok(Msg::Reply {
                    notes,
                    next: self.next_work(&worker),
                })
            }
            other => {
                warn!(
                    role = ROLE,
                    "dropped a message that only a coordinator sends: {}",
                    kind(&other)
                );
                Err("refused: unexpected message".into())
            }
        }
    }

    fn join(&self, j: Join) -> Result<Msg, String> {
        let s = &self.settings;
        let same_host = j.host_id == s.host_id;
        let forced = |t| s.transport == t || j.transport == t;
        let data = if forced(TransportChoice::Zenoh) {
            DataPath::Zenoh
        } else if forced(TransportChoice::Iceoryx2) {
            match (&s.iox, same_host) {
                (Some(d), true) => d.clone(),
                _ => {
                    warn!(
                        role = ROLE,
                        "refused worker {}: iceoryx2 forced but it is on another host", j.worker
                    );
                    return Err("refused: iceoryx2 transport forced, but the worker is not on the coordinator's host".into());
                }
            }
        } else {
            match (&s.iox, same_host) {
                (Some(d), true) => d.clone(),
                _ => DataPath::Zenoh,
            }
        };
        let mut st = self.lock();
        if st.open_parts == 0 {
            return Ok(Msg::Reply {
                notes: Vec::new(),
                next: Next::Done,
            });
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
            j.worker,
            j.pid,
            j.threads,
            j.software
        );
        let old = st.workers.insert(
            j.worker.clone(),
            WorkerSlot {
                name: j.worker.as_str().into(),
                parts_sent: HashSet::new(),
                leased: HashSet::new(),
                got_done: false,
                shards: 0,
                threads: u64::from(j.threads.max(1)),
                rederived: 0,
            },
        );
        if let Some(old) = old {
            requeue(&mut st, old.leased.into_iter());
        }
        Ok(Msg::Welcome(Welcome {
            run_id: s.run_id.clone(),
            data,
            lease_ms: s.lease.as_millis() as u64,
        }))
    }

    /// The next assignment of a worker that has just reported (and so
    /// holds no shard any more).
    fn next_work(&self, worker: &str) -> Next {
        let mut st = self.lock();
        let st = &mut *st;
        let Some(w) = st.workers.get_mut(worker) else {
            return Next::Rejoin;
        };
        // Anything still leased to it went out in a reply it never got.
        let lost: Vec<u64> = w.leased.drain().collect();
        if st.open_parts == 0 {
            w.got_done = true;
            return Next::Done;
        }
        requeue(st, lost.into_iter());
        if !st.started {
            if st.workers.len() < self.settings.min_workers {
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
        // Guided self-scheduling: a batch of about the cost left divided
        // among twice the threads, at most `batch_cost`, so batches shrink
        // towards the end and the workers finish together.
        let threads: u64 = st.workers.values().map(|w| w.threads).sum();
        let limit =
            (st.queued_cost / (2 * threads.max(1))).clamp(1, self.settings.batch_cost.max(1));
        let mut batch = Vec::new();
        let mut cost = 0;
        while cost < limit && batch.len() < crate::job::shards::MAX_BATCH_SHARDS {
            let Some(id) = st.queue.pop_front() else {
                break;
            };
            let sh = &mut st.shards[id as usize];
            if sh.status != ShardStatus::Queued {
                continue;
            }
            let part = &st.parts[sh.part];
            if part.closed || part.stop.is_some_and(|s| sh.range.start > s) {
                // Past a `--good-enough` hit: not needed any more.
                sh.status = ShardStatus::Done;
                st.queued_cost = st.queued_cost.saturating_sub(sh.cost);
                continue;
            }
            sh.status = ShardStatus::Leased {
                worker: worker.to_string(),
                until: Instant::now() + self.settings.lease,
            };
            st.queued_cost = st.queued_cost.saturating_sub(sh.cost);
            cost += sh.cost;
            let Some(w) = st.workers.get_mut(worker) else {
                return Next::Rejoin;
            };
            w.leased.insert(id);
            let part = &st.parts[sh.part];
            let input = if w.parts_sent.insert(sh.part) {
                Some(part.input.as_ref().clone())
            } else {
                None
            };
            batch.push(Assign {
                shard_id: id,
                digest: part.digest,
                range: sh.range.clone(),
                input,
                good_enough: self.settings.good_enough,
            });
        }
        if batch.is_empty() {
            // Short: the other shards may be done any moment, and then this
            // worker learns at once that the run is over.
            return Next::Idle { retry_ms: 5 };
        }
        st.stats.assigned += batch.len() as u64;
        Next::Work(batch)
    }

    /// Takes one shard result: `Err(note)` when it is not merged.
    fn result(&self, r: ShardDone, worker: &str, part_index: &[usize]) -> Result<(), String> {
        let mut st = self.lock();
        let st = &mut *st;
        st.stats.results += 1;
        let Some(sh) = st.shards.get(r.shard_id as usize) else {
            warn!(
                role = ROLE,
                "dropped a result for unknown shard {} from worker {}", r.shard_id, worker
            );
            return Err("unknown shard".into());
        };
        if sh.status == ShardStatus::Done {
            st.stats.duplicates += 1;
            return Err("duplicate: this shard is already done".into());
        }
        let (p, shard_range) = (sh.part, sh.range.clone());
        // A shard stopped by `--good-enough` answers for its prefix.
        let range = match r.hit {
            Some(h) if shard_range.contains(&h) => shard_range.start..h + 1,
            _ => shard_range.clone(),
        };
        let deep = self.settings.verify.deep(
            r.shard_id,
            st.workers.get(worker).map_or(0, |w| w.rederived),
        );
        let part = &mut st.parts[p];
        let check = if r.digest != part.digest {
            Err(format!(
                "result for part {}, shard is of part {}",
                short_hex(&r.digest),
                short_hex(&part.digest)
            ))
        } else if let Err(e) =
            verify::check_stop(self.settings.good_enough, &shard_range, r.hit, &r.result)
        {
            Err(e)
        } else if deep {
            match part.prepared() {
                Ok(prep) => verify::check(&prep, &range, &r.result, &part.top, true),
                Err(e) => Err(format!("the coordinator cannot prepare the part: {e}")),
            }
        } else {
            match &part.prep {
                Some(prep) => verify::check(prep, &range, &r.result, &part.top, false),
                None => verify::check_shape(part.top_k(), &range, &r.result).map(|()| 0),
            }
        };
        if let Some(w) = st.workers.get_mut(worker) {
            w.leased.remove(&r.shard_id);
        }
        let checked = match check {
            Ok(n) => n,
            Err(e) => {
                st.stats.rejected += 1;
                warn!(
                    role = ROLE,
                    "rejected shard {} (part #{}, combinations {range:?}) from worker {}: {e}; it goes back to the queue",
                    r.shard_id,
                    part_index.get(p).copied().unwrap_or(p),
                    worker
                );
                // A worker that sends a bad result gets no more work.
                if let Some(w) = st.workers.remove(worker) {
                    requeue(st, w.leased.into_iter());
                }
                st.banned.insert(worker.to_string());
                requeue(st, std::iter::once(r.shard_id));
                redo_work_of(st, worker);
                return Err(format!("rejected: {e}"));
            }
        };
        st.stats.fixtures_rederived += checked as u64;
        st.stats.results_rederived += u64::from(deep);
        st.stats.worker_micros += r.micros;
        st.shards[r.shard_id as usize].status = ShardStatus::Done;
        if let Some(w) = st.workers.get_mut(worker) {
            w.shards += 1;
            w.rederived += checked as u64;
            st.shards[r.shard_id as usize].by = Some(w.name.clone());
        }
        let part = &mut st.parts[p];
        let top_k = part.top_k();
        let mut result = r.result;
        if shard_range == WHOLE && r.hit.is_none() {
            // As the embedded run cuts it: `0..count`.
            result.range = 0..result.counts.combinations;
        }
        if let Some(h) = r.hit {
            part.stop = Some(part.stop.map_or(h, |s| s.min(h)));
        }
        let (stop, ids) = (part.stop, part.shard_ids.clone());
        let counts = |id: u64| stop.is_none_or(|s| st.shards[id as usize].range.start <= s);
        let open = ids
            .clone()
            .any(|id| counts(id) && st.shards[id as usize].status != ShardStatus::Done);
        let part = &mut st.parts[p];
        if open {
            // The running top-k only serves the checks of the shards to come.
            let lists = vec![std::mem::take(&mut part.top), result.fixtures.clone()];
            part.top = fixplan_core::ranking::merge_ranked(lists, top_k);
        }
        part.partials.push(Held {
            shard: r.shard_id,
            hit: r.hit,
            result,
        });
        if !open && !part.closed {
            part.closed = true;
            // Shards past the stop: results that came in are left out,
            // the others are never handed out (or are duplicates later).
            let kept = std::mem::take(&mut part.partials)
                .into_iter()
                .map(|h| h.result)
                .filter(|r| stop.is_none_or(|s| r.range.start <= s))
                .collect();
            let done = Finished {
                prep: part.prep.clone(),
                input: part.source.clone(),
                merged: merge(top_k, kept),
                stopped_at: stop,
            };
            st.open_parts -= 1;
            for id in ids {
                st.shards[id as usize].status = ShardStatus::Done;
            }
            let idx = part_index.get(p).copied().unwrap_or(p);
            st.done.push((idx, Ok(done)));
        }
        Ok(())
    }

    fn failed(&self, f: ShardFailed, worker: &str, part_index: &[usize]) -> Result<(), String> {
        let mut st = self.lock();
        let st = &mut *st;
        let Some(sh) = st.shards.get(f.shard_id as usize) else {
            return Err("unknown shard".into());
        };
        if sh.status == ShardStatus::Done {
            return Err("duplicate".into());
        }
        let p = sh.part;
        if let Some(w) = st.workers.get_mut(worker) {
            w.leased.remove(&f.shard_id);
        }
        let idx = part_index.get(p).copied().unwrap_or(p);
        // A part sent whole was not prepared here: if it cannot be, that is
        // the input's fault and the coordinator's own message stands (the
        // embedded run's); otherwise the worker's enumeration failed.
        let message = match st.parts[p].prepared() {
            Err(e) => e.to_string(),
            Ok(_) => {
                warn!(
                    role = ROLE,
                    "part #{idx}: worker {} failed shard {}: {}", worker, f.shard_id, f.message
                );
                f.message
            }
        };
        for sh in st.shards.iter_mut().filter(|s| s.part == p) {
            sh.status = ShardStatus::Done;
        }
        let part = &mut st.parts[p];
        if !part.closed {
            part.closed = true;
            st.open_parts -= 1;
            st.done.push((idx, Err(message)));
        }
        Ok(())
    }

    /// A worker's liveliness token vanished: its shards go back to the queue.
    pub fn worker_lost(&self, worker: &str) {
        let mut st = self.lock();
        if let Some(w) = st.workers.remove(worker) {
            st.stats.workers_lost += 1;
            let n = requeue(&mut st, w.leased.into_iter());
            if st.open_parts > 0 {
                info!(
                    role = ROLE,
                    "worker {worker} left after {} shards; {n} shards back in the queue", w.shards
                );
            }
        }
    }

    /// Shards whose lease ran out go back to the queue (their worker may
    /// still answer: the first result wins).
    pub fn expire_leases(&self) {
        let mut st = self.lock();
        let now = Instant::now();
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
        for (id, worker) in expired {
            warn!(
                role = ROLE,
                "shard {id}: lease of worker {worker} ran out; back in the queue"
            );
            if let Some(w) = st.workers.get_mut(&worker) {
                w.leased.remove(&id);
            }
            requeue(&mut st, std::iter::once(id));
        }
    }
}

/// A worker failed a check: what it did for parts still open is done
/// again (its results there were taken, most of them unchecked under
/// [`VerifyPolicy::Sample`]). Parts already delivered keep theirs: a
/// worker is checked in full until it has earned some trust, which is
/// where a build or platform that computes differently shows up.
fn redo_work_of(st: &mut State, worker: &str) {
    let mine = |sh: &ShardSlot| sh.by.as_deref() == Some(worker);
    let parts: HashSet<usize> = st
        .shards
        .iter()
        .filter(|sh| mine(sh) && !st.parts[sh.part].closed)
        .map(|sh| sh.part)
        .collect();
    for p in parts {
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
        part.top = fixplan_core::ranking::merge_ranked(lists, part.top_k());
        let stop = part.stop;
        for id in part.shard_ids.clone() {
            let sh = &st.shards[id as usize];
            // Done but not held: this worker's, or skipped past a stop
            // that may have been its.
            if sh.status == ShardStatus::Done
                && !held.contains(&id)
                && stop.is_none_or(|s| sh.range.start <= s)
            {
                back_in_queue(st, id);
            }
        }
    }
}

/// Puts one shard back at the front of the queue, whatever became of it.
fn back_in_queue(st: &mut State, id: u64) {
    let sh = &mut st.shards[id as usize];
    sh.status = ShardStatus::Queued;
    sh.by = None;
    st.queued_cost += sh.cost;
    st.queue.push_front(id);
    st.stats.requeued += 1;
}

/// Puts shards that are not done back at the front of the queue.
fn requeue(st: &mut State, ids: impl Iterator<Item = u64>) -> usize {
    let mut n = 0;
    for id in ids {
        if let Some(sh) = st.shards.get_mut(id as usize) {
            if sh.status != ShardStatus::Done && sh.status != ShardStatus::Queued {
                back_in_queue(st, id);
                n += 1;
            }
        }
    }
    n
}

fn kind(m: &Msg) -> &'static str {
    match m {
        Msg::Join(_) => "join",
        Msg::Welcome(_) => "welcome",
        Msg::Report { .. } => "report",
        Msg::Reply { .. } => "reply",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fixplan_catalog::kit::{builtin_kit, METRIC_25};
    use fixplan_core::{Params, Part};
    use std::sync::mpsc::channel;

    fn core(parts: usize, shard: u64, verify: VerifyPolicy) -> (Scheduler, Vec<usize>) {
        let (c, index, rx) = core_rx(parts, shard, verify);
        // Keep the channel open for parts that do close.
        std::mem::forget(rx);
        (c, index)
    }

    fn core_rx(
        parts: usize,
        shard: u64,
        verify: VerifyPolicy,
    ) -> (
        Scheduler,
        Vec<usize>,
        std::sync::mpsc::Receiver<Vec<PartDone>>,
    ) {
        let (kit, units) = builtin_kit(METRIC_25).expect("built-in kit");
        let slots = (0..parts)
            .map(|i| {
                let w = 100.0 + 10.0 * i as f64;
                let part = Part {
                    outline: vec![[0.0, 0.0], [w, 0.0], [w, 60.0], [0.0, 60.0]],
                    access: vec![],
                };
                let source = PartInput {
                    part,
                    kit: kit.clone(),
                    params: Params::default(),
                    units,
                };
                let prep = source.prepare().expect("prepare");
                let ranges = crate::job::shards::ranges(prep.combination_count(), shard);
                let segments = prep.segments.len();
                let slot = PartSlot {
                    prep: Some(Arc::new(prep)),
                    source: Arc::new(source),
                    input: Arc::new(vec![i as u8]),
                    digest: [i as u8; 32],
                    shard_ids: 0..0,
                    stop: None,
                    partials: Vec::new(),
                    top: Vec::new(),
                    closed: false,
                };
                (i, slot, ranges, segments)
            })
            .collect();
        let settings = Settings {
            run_id: "run".into(),
            host_id: "host".into(),
            transport: TransportChoice::Zenoh,
            iox: None,
            iox_clients: 1,
            lease: Duration::from_secs(300),
            min_workers: 1,
            verify,
            good_enough: None,
            batch_cost: 1,
        };
        let (tx, rx) = channel();
        let (c, index) = Scheduler::new(settings, slots, tx);
        (c, index, rx)
    }

    /// The honest outcome of each shard of `batch` (part 0).
    fn honest(c: &Scheduler, batch: &[Assign]) -> Vec<Outcome> {
        let prep = c.lock().parts[0].prep.clone().expect("prepared");
        batch
            .iter()
            .map(|a| {
                Outcome::Done(Box::new(ShardDone {
                    shard_id: a.shard_id,
                    digest: a.digest,
                    micros: 1,
                    result: prep.enumerate_range(a.range.clone()),
                    hit: None,
                }))
            })
            .collect()
    }

    fn report(c: &Scheduler, index: &[usize], worker: &str, outcomes: Vec<Outcome>) -> Frame {
        let msg = Msg::Report {
            worker: worker.into(),
            outcomes,
        };
        decode(&c.handle(&encode(&msg).expect("encode"), index)).expect("decode")
    }

    #[test]
    fn a_banned_worker_s_work_on_open_parts_is_done_again() {
        let (mut c, index, rx) = core_rx(1, 4, VerifyPolicy::All);
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
        }) = report(&c, &index, "a", honest(&c, &first))
        else {
            panic!("no second batch")
        };
        assert!(first_ids
            .iter()
            .all(|&id| c.lock().shards[id as usize].status == ShardStatus::Done));
        // ...then lies about one fixture of it.
        let mut lies = honest(&c, &second);
        let forged = lies.iter_mut().find_map(|o| match o {
            Outcome::Done(d) if !d.result.fixtures.is_empty() => Some(d),
            _ => None,
        });
        forged.expect("a shard with fixtures").result.fixtures[0].score *= 0.5;
        assert!(matches!(report(&c, &index, "a", lies), Frame::Refused(_)));
        // Its first, accepted results are back in the queue.
        for &id in &first_ids {
            assert_eq!(c.lock().shards[id as usize].status, ShardStatus::Queued);
        }
        // `b` does everything; the part comes out as one enumeration.
        let mut outcomes = Vec::new();
        loop {
            match report(&c, &index, "b", outcomes) {
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
        let prep = c.lock().parts[0].prep.clone().expect("prepared");
        assert_eq!(f.merged, prep.enumerate_all());
    }

    fn join(c: &Scheduler, name: &str) {
        let j = Join {
            worker: name.into(),
            host_id: "other".into(),
            pid: 1,
            threads: 1,
            transport: TransportChoice::Zenoh,
            software: "test".into(),
        };
        assert!(matches!(c.join(j), Ok(Msg::Welcome(_))));
    }

    fn ids(n: &Next) -> Vec<u64> {
        match n {
            Next::Work(b) => b.iter().map(|a| a.shard_id).collect(),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn shards_of_a_lost_reply_go_back_to_the_queue() {
        let (c, _) = core(2, 8, VerifyPolicy::All);
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
    fn nothing_else_of_a_report_counts_after_a_bad_result() {
        let (mut c, index) = core(1, 4, VerifyPolicy::All);
        c.settings.batch_cost = u64::MAX;
        join(&c, "liar");
        let Next::Work(batch) = c.next_work("liar") else {
            panic!("no work")
        };
        let prep = c.lock().parts[0].prep.clone().expect("prepared");
        let mut outcomes: Vec<(bool, Outcome)> = batch
            .iter()
            .map(|a| {
                let mut result = prep.enumerate_range(a.range.clone());
                let bad = !result.fixtures.is_empty();
                if let Some(f) = result.fixtures.first_mut() {
                    f.score *= 0.5;
                }
                let done = ShardDone {
                    shard_id: a.shard_id,
                    digest: a.digest,
                    micros: 1,
                    result,
                    hit: None,
                };
                (bad, Outcome::Done(Box::new(done)))
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
        let ids: Vec<u64> = honest
            .iter()
            .map(|o| match o {
                Outcome::Done(d) => d.shard_id,
                Outcome::Failed(f) => f.shard_id,
            })
            .collect();
        honest.insert(0, bad.1);
        let report = encode(&Msg::Report {
            worker: "liar".into(),
            outcomes: honest,
        })
        .expect("encode");
        let reply = decode(&c.handle(&report, &index)).expect("decode");
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
        let (mut c, _) = core(3, 4, VerifyPolicy::All);
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
}
