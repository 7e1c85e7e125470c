//! The coordinator's bookkeeping: the shard queue, leases, workers, and the
//! partial results of each part. Transport-free: every request arrives as
//! bytes through [`Core::handle`] (zenoh queryables and the iceoryx2 server
//! call it alike) and the answer goes back as bytes.

use super::verify;
use fixplan_core::{merge, Fixture, PartialResult, PreparedPart};
use fixplan_worker::part_input::short_hex;
use fixplan_worker::protocol::{
    decode, encode, encode_refused, refusal_for, Assign, DataPath, Digest, Frame, Join, Msg,
    ShardDone, ShardFailed, TransportChoice, Welcome,
};
use fixplan_worker::{info, warn};
use std::collections::{HashMap, HashSet, VecDeque};
use std::ops::Range;
use std::sync::mpsc::Sender;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// A finished part: merged result, or the message of why it failed.
pub type PartDone = (usize, Result<(Arc<PreparedPart>, PartialResult), String>);

pub(crate) struct PartSlot {
    pub prep: Arc<PreparedPart>,
    pub input: Arc<Vec<u8>>,
    pub digest: Digest,
    pub left: usize,
    pub partials: Vec<PartialResult>,
    pub top: Vec<Fixture>,
    pub closed: bool,
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
    status: ShardStatus,
}

struct WorkerSlot {
    parts_sent: HashSet<usize>,
    leased: HashSet<u64>,
    got_done: bool,
    shards: u64,
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
    /// Time spent in the coordinator handling requests.
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
    pub lease: Duration,
    pub min_workers: usize,
}

pub(crate) struct State {
    parts: Vec<PartSlot>,
    shards: Vec<ShardSlot>,
    queue: VecDeque<u64>,
    workers: HashMap<String, WorkerSlot>,
    started: bool,
    open_parts: usize,
    banned: HashSet<String>,
    pub stats: Stats,
}

pub struct Core {
    pub settings: Settings,
    st: Mutex<State>,
    tx: Mutex<Sender<PartDone>>,
}

const ROLE: &str = "coordinator";

impl Core {
    /// `parts`: `(index, prepared part, wire input, shard ranges)` of the
    /// parts to distribute.
    pub(crate) fn new(
        settings: Settings,
        parts: Vec<(usize, PartSlot, Vec<Range<u64>>)>,
        tx: Sender<PartDone>,
    ) -> (Core, Vec<usize>) {
        let mut st = State {
            parts: Vec::new(),
            shards: Vec::new(),
            queue: VecDeque::new(),
            workers: HashMap::new(),
            started: false,
            open_parts: 0,
            banned: HashSet::new(),
            stats: Stats::default(),
        };
        let mut index = Vec::new();
        for (i, mut slot, ranges) in parts {
            let p = st.parts.len();
            slot.left = ranges.len();
            for r in ranges {
                st.queue.push_back(st.shards.len() as u64);
                st.shards.push(ShardSlot {
                    part: p,
                    range: r,
                    status: ShardStatus::Queued,
                });
            }
            st.parts.push(slot);
            index.push(i);
            st.open_parts += 1;
        }
        st.stats.shards = st.shards.len() as u64;
        (
            Core {
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
        let t0 = Instant::now();
        let reply = match decode(bytes) {
            Err(e) => {
                warn!(ROLE, "dropped a message: {e}");
                encode_refused(&refusal_for(&e))
            }
            Ok(Frame::Refused(r)) => {
                warn!(ROLE, "dropped an unexpected refusal: {r}");
                encode_refused("refused: unexpected message")
            }
            Ok(Frame::Msg(m)) => {
                let is_result = matches!(m, Msg::Result(_));
                let reply = match self.on_msg(m, part_index) {
                    Ok(r) => r,
                    Err(reason) => return encode_refused(&reason),
                };
                let out = match encode(&reply) {
                    Ok(b) => b,
                    Err(e) => encode_refused(&format!("refused: {e}")),
                };
                let mut st = self.lock();
                if is_result {
                    st.stats.result_bytes += bytes.len() as u64;
                } else if matches!(reply, Msg::Assign(_)) {
                    st.stats.assign_bytes += out.len() as u64;
                }
                out
            }
        };
        self.lock().stats.handle_micros += t0.elapsed().as_micros() as u64;
        reply
    }

    /// The reply, or the reason of a refusal.
    fn on_msg(&self, m: Msg, part_index: &[usize]) -> Result<Msg, String> {
        let banned = |w: &str| self.lock().banned.contains(w);
        match m {
            Msg::Join(j) if banned(&j.worker) => Err(format!(
                "refused: worker {} sent results that failed verification",
                j.worker
            )),
            Msg::Pull { worker } if banned(&worker) => Err(format!(
                "refused: worker {worker} sent results that failed verification"
            )),
            Msg::Join(j) => self.join(j),
            Msg::Pull { worker } => Ok(self.pull(&worker)),
            Msg::Result(r) => Ok(self.result(*r, part_index)),
            Msg::Failed(f) => Ok(self.failed(f, part_index)),
            other => {
                warn!(
                    ROLE,
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
                        ROLE,
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
            return Ok(Msg::Done);
        }
        st.stats.workers_joined += 1;
        let how = if data == DataPath::Zenoh {
            "zenoh"
        } else {
            "iceoryx2"
        };
        info!(
            ROLE,
            "worker {} joined (pid {}, {} threads, fixplan {}, shards over {how})",
            j.worker,
            j.pid,
            j.threads,
            j.software
        );
        let old = st.workers.insert(
            j.worker.clone(),
            WorkerSlot {
                parts_sent: HashSet::new(),
                leased: HashSet::new(),
                got_done: false,
                shards: 0,
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

    fn pull(&self, worker: &str) -> Msg {
        let mut st = self.lock();
        let st = &mut *st;
        let Some(w) = st.workers.get_mut(worker) else {
            return Msg::Rejoin;
        };
        if st.open_parts == 0 {
            w.got_done = true;
            return Msg::Done;
        }
        if !st.started {
            if st.workers.len() < self.settings.min_workers {
                return Msg::Idle { retry_ms: 200 };
            }
            st.started = true;
            info!(
                ROLE,
                "{} workers: starting ({} shards)",
                st.workers.len(),
                st.shards.len()
            );
        }
        while let Some(id) = st.queue.pop_front() {
            let sh = &mut st.shards[id as usize];
            if sh.status != ShardStatus::Queued {
                continue;
            }
            sh.status = ShardStatus::Leased {
                worker: worker.to_string(),
                until: Instant::now() + self.settings.lease,
            };
            let Some(w) = st.workers.get_mut(worker) else {
                return Msg::Rejoin;
            };
            w.leased.insert(id);
            let part = &st.parts[sh.part];
            let input = if w.parts_sent.insert(sh.part) {
                Some(part.input.as_ref().clone())
            } else {
                None
            };
            return Msg::Assign(Assign {
                shard_id: id,
                digest: part.digest,
                range: sh.range.clone(),
                input,
            });
        }
        // Short: the other shards may be done any moment, and then this
        // worker learns at once that the run is over.
        Msg::Idle { retry_ms: 5 }
    }

    fn result(&self, r: ShardDone, part_index: &[usize]) -> Msg {
        let mut st = self.lock();
        let st = &mut *st;
        st.stats.results += 1;
        let Some(sh) = st.shards.get(r.shard_id as usize) else {
            warn!(
                ROLE,
                "dropped a result for unknown shard {} from worker {}", r.shard_id, r.worker
            );
            return Msg::Ack {
                accepted: false,
                note: "unknown shard".into(),
            };
        };
        if sh.status == ShardStatus::Done {
            st.stats.duplicates += 1;
            return Msg::Ack {
                accepted: false,
                note: "duplicate: this shard is already done".into(),
            };
        }
        let (p, range) = (sh.part, sh.range.clone());
        let part = &st.parts[p];
        let check = if r.digest != part.digest {
            Err(format!(
                "result for part {}, shard is of part {}",
                short_hex(&r.digest),
                short_hex(&part.digest)
            ))
        } else {
            verify::check(&part.prep, &range, &r.result, &part.top)
        };
        if let Some(w) = st.workers.get_mut(&r.worker) {
            w.leased.remove(&r.shard_id);
        }
        let checked = match check {
            Ok(n) => n,
            Err(e) => {
                st.stats.rejected += 1;
                warn!(
                    ROLE,
                    "rejected shard {} (part #{}, combinations {range:?}) from worker {}: {e}; it goes back to the queue",
                    r.shard_id,
                    part_index.get(p).copied().unwrap_or(p),
                    r.worker
                );
                // A worker that sends a bad result gets no more work.
                if let Some(w) = st.workers.remove(&r.worker) {
                    requeue(st, w.leased.into_iter());
                }
                st.banned.insert(r.worker.clone());
                requeue(st, std::iter::once(r.shard_id));
                return Msg::Ack {
                    accepted: false,
                    note: format!("rejected: {e}"),
                };
            }
        };
        st.stats.fixtures_rederived += checked as u64;
        st.stats.worker_micros += r.micros;
        st.shards[r.shard_id as usize].status = ShardStatus::Done;
        if let Some(w) = st.workers.get_mut(&r.worker) {
            w.shards += 1;
        }
        let part = &mut st.parts[p];
        let top_k = part.prep.top_k;
        let mut lists = vec![std::mem::take(&mut part.top), r.result.fixtures.clone()];
        part.top = fixplan_core::ranking::merge_ranked(std::mem::take(&mut lists), top_k);
        part.partials.push(r.result);
        part.left -= 1;
        if part.left == 0 && !part.closed {
            part.closed = true;
            let merged = merge(top_k, std::mem::take(&mut part.partials));
            let prep = part.prep.clone();
            st.open_parts -= 1;
            let idx = part_index.get(p).copied().unwrap_or(p);
            let _ = self
                .tx
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .send((idx, Ok((prep, merged))));
        }
        Msg::Ack {
            accepted: true,
            note: String::new(),
        }
    }

    fn failed(&self, f: ShardFailed, part_index: &[usize]) -> Msg {
        let mut st = self.lock();
        let st = &mut *st;
        let Some(sh) = st.shards.get(f.shard_id as usize) else {
            return Msg::Ack {
                accepted: false,
                note: "unknown shard".into(),
            };
        };
        if sh.status == ShardStatus::Done {
            return Msg::Ack {
                accepted: false,
                note: "duplicate".into(),
            };
        }
        let p = sh.part;
        if let Some(w) = st.workers.get_mut(&f.worker) {
            w.leased.remove(&f.shard_id);
        }
        let idx = part_index.get(p).copied().unwrap_or(p);
        warn!(
            ROLE,
            "part #{idx}: worker {} failed shard {}: {}", f.worker, f.shard_id, f.message
        );
        for sh in st.shards.iter_mut().filter(|s| s.part == p) {
            sh.status = ShardStatus::Done;
        }
        let part = &mut st.parts[p];
        if !part.closed {
            part.closed = true;
            st.open_parts -= 1;
            let _ = self
                .tx
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .send((idx, Err(f.message)));
        }
        Msg::Ack {
            accepted: true,
            note: String::new(),
        }
    }

    /// A worker's liveliness token vanished: its shards go back to the queue.
    pub fn worker_lost(&self, worker: &str) {
        let mut st = self.lock();
        if let Some(w) = st.workers.remove(worker) {
            st.stats.workers_lost += 1;
            let n = requeue(&mut st, w.leased.into_iter());
            if st.open_parts > 0 {
                info!(
                    ROLE,
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
                ROLE,
                "shard {id}: lease of worker {worker} ran out; back in the queue"
            );
            if let Some(w) = st.workers.get_mut(&worker) {
                w.leased.remove(&id);
            }
            requeue(&mut st, std::iter::once(id));
        }
    }
}

/// Puts shards that are not done back at the front of the queue.
fn requeue(st: &mut State, ids: impl Iterator<Item = u64>) -> usize {
    let mut n = 0;
    for id in ids {
        if let Some(sh) = st.shards.get_mut(id as usize) {
            if sh.status != ShardStatus::Done {
                sh.status = ShardStatus::Queued;
                st.queue.push_front(id);
                st.stats.requeued += 1;
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
        Msg::Pull { .. } => "pull",
        Msg::Assign(_) => "assign",
        Msg::Idle { .. } => "idle",
        Msg::Done => "done",
        Msg::Rejoin => "rejoin",
        Msg::Result(_) => "result",
        Msg::Failed(_) => "failed",
        Msg::Ack { .. } => "ack",
    }
}
