//! What the scheduler knows: every part with its shard results so far,
//! every shard and where it is, the workers, the run's figures; and the
//! one way a shard goes back to the queue.

use super::errors::PartFailure;
use crate::cluster::verify::VerifyPolicy;
use bytes::Bytes;
use fixplan_core::{Fixture, PartialResult, PrepareError, PreparedPart};
use fixplan_worker::finish::Finisher;
use fixplan_worker::part_input::{digest, PartInput};
use fixplan_worker::protocol::{BudgetStop, DataPath, Digest, MergedCut, TransportChoice};
use std::collections::{HashMap, HashSet, VecDeque};
use std::ops::Range;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Who the scheduler's log lines are from.
pub(super) const ROLE: &str = "coordinator";

/// Shard range meaning "every combination of the part": a part that
/// stays whole is sent without the coordinator preparing it (it does not
/// know the exact count); the worker's enumeration stops at the count.
pub const WHOLE: Range<u64> = 0..u64::MAX;

/// A part as the run planned it: what the scheduler is handed.
pub(crate) struct PlannedPart {
    /// Its index in the caller's list: the part is delivered under it.
    pub index: usize,
    /// The part prepared by the caller, if it was. A run plans from
    /// estimates and prepares nothing: a part is prepared here only if a
    /// result of it is re-derived or its worker cannot finish it.
    pub prep: Option<Arc<PreparedPart>>,
    /// The part, kit and parameters, to prepare it from.
    pub source: Arc<PartInput>,
    /// `source` encoded, as it goes to the workers.
    pub input: Vec<u8>,
    /// Its shards' combinations ([`WHOLE`] for a part that stays whole).
    pub ranges: Vec<Range<u64>>,
    /// Its segment count (estimated for a whole part), for shard costs.
    pub segments: usize,
    /// What a worker needs to finish the part
    /// ([`fixplan_worker::finish`]), if the caller wants it finished there
    /// (ignored with `--good-enough`: a part that stops early is finished
    /// by the caller).
    pub finish: Option<Vec<u8>>,
}

/// A part's shard results merged, as the scheduler hands it over. The
/// part is prepared only if the coordinator had to (to re-derive its
/// fixtures): preparing it is the consumer's call.
#[derive(Debug)]
pub(crate) struct MergedShards {
    /// The part prepared here, if it was.
    pub prep: Option<Arc<PreparedPart>>,
    /// The part as it was sent, to prepare it from.
    pub input: Arc<PartInput>,
    /// The merged result, byte for byte the embedded run's.
    pub merged: PartialResult,
    /// `--good-enough`: the combination where the part stopped.
    pub stopped_at: Option<u64>,
    /// The part as the worker finished it ([`fixplan_worker::finish`]),
    /// unless the coordinator must finish it (a result it re-derived, or a
    /// worker that did not).
    pub finished: Option<Bytes>,
}

/// A finished part under its index in the caller's list.
pub(crate) type Delivery = (usize, Result<MergedShards, PartFailure>);

/// A part being worked on.
pub(super) struct PartSlot {
    /// `None` until needed: parts go out unprepared and are prepared here
    /// only when a result of theirs is re-derived.
    pub(super) prep: Option<Arc<PreparedPart>>,
    pub(super) source: Arc<PartInput>,
    pub(super) input: Bytes,
    /// What results must name to be taken for this part.
    pub(super) digest: Digest,
    /// Ids of its shards (contiguous, in combination order).
    pub(super) shard_ids: Range<u64>,
    /// The first `--good-enough` hit reported so far: the part ends with
    /// the shards up to it, the rest are dropped.
    pub(super) stop: Option<u64>,
    /// Results taken, merged when the part is complete.
    pub(super) partials: Vec<ShardResult>,
    /// The best fixtures so far, for the checks of the shards to come.
    pub(super) top: Vec<Fixture>,
    /// Delivered (merged or failed): later results are duplicates.
    pub(super) closed: bool,
    /// [`PlannedPart::finish`].
    pub(super) finish: Option<Bytes>,
    /// A cut part whose shards are all merged, waiting for a worker to
    /// finish it: the finishing task's id (the merged result is in that
    /// task's [`ShardWork::Finishing`]).
    pub(super) finishing: Option<u64>,
    /// Workers lost or timed out holding one of its shards ([`strike`]).
    pub(super) deaths: WorkerLosses,
    /// When its first task was handed out: `--part-seconds` runs from
    /// then ([`super::budget`]).
    pub(super) started: Option<Instant>,
    /// With `--good-enough`: the first combination of the earliest shard
    /// that stopped on `--part-setups` or `--part-fixtures`, and which,
    /// judged when the part closes.
    pub(super) over: Option<(u64, BudgetStop)>,
}

/// How often a part's shards were with a worker that was lost or whose
/// lease ran out.
#[derive(Debug, Clone, Default)]
pub(super) struct WorkerLosses {
    pub(super) workers: u32,
    /// Of those, workers that held nothing but shards of this part.
    pub(super) alone: u32,
    /// Their names: a worker counts once per part (its shards' leases
    /// may run out one request after another).
    pub(super) names: HashSet<String>,
    /// Its shards were with a worker whose lease ran out while it held
    /// other parts' too: not counted (a slow batch), but its shards now
    /// go out alone so that a next timeout tells.
    pub(super) suspected: bool,
}

/// WorkerLosses at which a part is failed and handed out no more (one of them
/// its own: [`WorkerLosses::condemned`]).
pub(super) const DEATHS_TO_FAIL: u32 = 2;

impl WorkerLosses {
    /// Whether the part is to be failed: [`DEATHS_TO_FAIL`] workers, one
    /// of them holding nothing but its shards. Workers that die at once
    /// with batches handed out before either loss was seen can share an
    /// innocent part: deaths in batches alone only make it a suspect,
    /// whose shards then go out alone, so that a next death is its own.
    pub(super) fn condemned(&self) -> bool {
        self.workers >= DEATHS_TO_FAIL && self.alone >= 1
    }
}

impl PartSlot {
    pub(super) fn top_k(&self) -> usize {
        self.source.params.top_k
    }

    /// The part prepared, here and once, if it was sent out unprepared.
    pub(super) fn prepared(&mut self) -> Result<Arc<PreparedPart>, PrepareError> {
        if let Some(p) = &self.prep {
            return Ok(p.clone());
        }
        let p = Arc::new(self.source.prepare()?);
        self.prep = Some(p.clone());
        Ok(p)
    }
}

/// Where a shard is.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum ShardStatus {
    Queued,
    /// Handed out; back in the queue if no result comes by `until`.
    Leased {
        worker: String,
        until: Instant,
    },
    Done,
}

/// What a task of the scheduler stands for: the scheduler's side of a
/// [`fixplan_worker::protocol::Task`] (made from it in `tasks`).
#[derive(Debug)]
pub(super) enum ShardWork {
    /// Combinations of the part to enumerate ([`WHOLE`] for a part that
    /// goes out whole).
    Combinations(Range<u64>),
    /// The finishing of a cut part from its merged result, held until the
    /// part is delivered or merged again (then `None`).
    Finishing(Option<Box<MergedCut>>),
}

/// A task: a shard of a part, or a cut part's finishing.
pub(super) struct ShardSlot {
    pub(super) part: usize,
    pub(super) work: ShardWork,
    /// [`crate::job::shards::cost`] of the shard, for batching.
    pub(super) cost: u64,
    pub(super) status: ShardStatus,
    /// The worker whose result was taken.
    pub(super) by: Option<Arc<str>>,
}

impl ShardSlot {
    /// Whether the shard starts past `stop` (a `--good-enough` hit): not
    /// needed any more. A finishing is never past a stop.
    pub(super) fn past(&self, stop: Option<u64>) -> bool {
        match &self.work {
            ShardWork::Combinations(range) => stop.is_some_and(|s| range.start > s),
            ShardWork::Finishing(_) => false,
        }
    }
}

/// A shard result taken, held until its part is complete.
pub(super) struct ShardResult {
    pub(super) shard: u64,
    pub(super) hit: Option<u64>,
    /// The worker's time on the shard.
    pub(super) micros: u64,
    pub(super) result: PartialResult,
    /// [`MergedShards::finished`], of a whole part's one shard.
    pub(super) finished: Option<Bytes>,
}

pub(super) struct WorkerSlot {
    pub(super) name: Arc<str>,
    /// Parts whose input it has: later shards of them go without it.
    pub(super) parts_sent: HashSet<usize>,
    pub(super) leased: HashSet<u64>,
    /// Told the run is over (the coordinator waits for that to stop).
    pub(super) got_done: bool,
    pub(super) shards: u64,
    /// Its enumeration threads, for the batch sizes.
    pub(super) threads: u64,
    /// Fixtures of this worker re-derived so far (until there are
    /// [`crate::cluster::verify::FULL_CHECKS`], all its results are checked
    /// in full).
    pub(super) rederived: u64,
}

/// Run-wide figures, for the benchmark and the final log line: what the
/// coordinator did and how much it cost.
#[derive(Debug, Clone, Default)]
pub struct Stats {
    /// Shards the parts were cut into.
    pub shards: u64,
    /// Cut parts handed to a worker to finish from their merged results
    /// (a part merged again after a ban is counted again).
    pub finishings: u64,
    /// Shard results received, taken or not.
    pub results: u64,
    /// Results for shards already done (a lease ran out, both answered).
    pub duplicates: u64,
    /// Results that failed their checks.
    pub rejected: u64,
    /// Shards put back in the queue (lost, expired, or to be redone).
    pub requeued: u64,
    /// Joins, rejoins included.
    pub workers_joined: u64,
    /// Workers whose liveliness token vanished.
    pub workers_lost: u64,
    /// Fixtures re-derived by the checks.
    pub fixtures_rederived: u64,
    /// Bytes of results (frames, as sent).
    pub result_bytes: u64,
    /// Bytes of assignments (frames, as sent).
    pub assign_bytes: u64,
    /// Results checked in full (every fixture entering the top-k re-derived).
    pub results_rederived: u64,
    /// Requests (reports) answered.
    pub requests: u64,
    /// Shards handed out.
    pub assigned: u64,
    /// CPU time of the coordinator's threads handling requests (thread
    /// CPU clock: time the thread was preempted does not count).
    pub handle_micros: u64,
    /// Worker time enumerating, as reported.
    pub worker_micros: u64,
}

/// How the scheduler serves the workers, fixed for the run.
pub struct Settings {
    /// Names the run in welcomes: a worker that rejoins a new run knows.
    pub run_id: String,
    /// This host's id: workers with the same one may use shared memory.
    pub host_id: String,
    /// `--transport`: forcing one side forces the data path.
    pub transport: TransportChoice,
    /// The iceoryx2 data path, when the coordinator serves one.
    pub iox: Option<DataPath>,
    /// Workers it serves at most (more on this host use zenoh).
    pub iox_clients: usize,
    /// How long a shard may stay with one worker.
    pub lease: Duration,
    /// Workers to wait for before handing out the first shard.
    pub min_workers: usize,
    /// How much of each result is re-derived before it is merged.
    pub verify: VerifyPolicy,
    /// `--good-enough` threshold of every part.
    pub good_enough: Option<f64>,
    /// `--part-setups` of every part ([`super::budget`]).
    pub part_setups: Option<u64>,
    /// `--part-fixtures` of every part ([`super::budget`]).
    pub part_fixtures: Option<u64>,
    /// `--part-seconds` of every part, by this process's clock.
    pub part_seconds: Option<f64>,
    /// Cost of work ([`crate::job::shards::cost`]) handed out in one
    /// assignment at most, for each thread of the worker it goes to:
    /// small shards travel together up to it.
    pub batch_cost: u64,
    /// What the workers finish whole parts with: the coordinator checks
    /// the finished parts whose results it re-derives with it. Without
    /// one, such parts are finished by the caller instead.
    pub finisher: Option<Arc<dyn Finisher>>,
}

/// Everything the scheduler changes, behind its one lock.
pub(super) struct State {
    pub(super) parts: Vec<PartSlot>,
    pub(super) shards: Vec<ShardSlot>,
    pub(super) queue: VecDeque<u64>,
    pub(super) workers: HashMap<String, WorkerSlot>,
    /// `min_workers` have joined once: work is handed out from then on.
    pub(super) started: bool,
    pub(super) open_parts: usize,
    /// Workers caught sending a bad result.
    pub(super) banned: HashSet<String>,
    /// Cost of the shards in the queue (batches shrink as it runs out, so
    /// the last ones end together).
    pub(super) queued_cost: u64,
    /// Parts finished while answering the current request.
    pub(super) done: Vec<Delivery>,
    /// Each part's index in the caller's list.
    pub(super) part_index: Vec<usize>,
    pub(super) stats: Stats,
}

impl State {
    /// Every shard of `parts` in the queue, in order; with `--good-enough`
    /// (`stops`), the parts' finish contexts dropped.
    pub(super) fn new(parts: Vec<PlannedPart>, stops: bool) -> State {
        // Sized once: growing these by doubling copied every slot again,
        // which showed in the coordinator's CPU on big catalogues.
        let shards: usize = parts.iter().map(|p| p.ranges.len()).sum();
        let mut st = State {
            parts: Vec::with_capacity(parts.len()),
            shards: Vec::with_capacity(shards),
            queue: VecDeque::with_capacity(shards),
            workers: HashMap::new(),
            started: false,
            open_parts: 0,
            banned: HashSet::new(),
            queued_cost: 0,
            done: Vec::new(),
            part_index: Vec::with_capacity(parts.len()),
            stats: Stats::default(),
        };
        for mut part in parts {
            if stops {
                part.finish = None;
            }
            st.add(part);
        }
        st.stats.shards = st.shards.len() as u64;
        st
    }

    fn add(&mut self, part: PlannedPart) {
        let p = self.parts.len();
        let first = self.shards.len() as u64;
        // The last shard of a part may be open ([`WHOLE`], or cut from an
        // estimate): it costs the estimate's rest.
        let estimate = fixplan_core::combination_count(part.segments);
        for r in part.ranges.iter().cloned() {
            let combinations = r.end.min(estimate).saturating_sub(r.start);
            let cost = crate::job::shards::cost(combinations, part.segments);
            self.queue.push_back(self.shards.len() as u64);
            self.queued_cost += cost;
            self.shards.push(ShardSlot {
                part: p,
                work: ShardWork::Combinations(r),
                cost,
                status: ShardStatus::Queued,
                by: None,
            });
        }
        self.parts.push(PartSlot {
            prep: part.prep,
            source: part.source,
            digest: digest(&part.input),
            input: Bytes::from(part.input),
            shard_ids: first..first + part.ranges.len() as u64,
            stop: None,
            partials: Vec::new(),
            top: Vec::new(),
            closed: false,
            finish: part.finish.map(Bytes::from),
            finishing: None,
            deaths: WorkerLosses::default(),
            started: None,
            over: None,
        });
        self.part_index.push(part.index);
        self.open_parts += 1;
    }
}

/// Queues the finishing of cut part `p` from its merged result, first in
/// line (the results file waits for the part, in catalogue order).
pub(super) fn queue_finishing(st: &mut State, slot: usize, merged: MergedCut) {
    let id = st.shards.len() as u64;
    let cost = st.parts[slot].source.part.outline.len().max(1) as u64;
    st.shards.push(ShardSlot {
        part: slot,
        work: ShardWork::Finishing(Some(Box::new(merged))),
        cost,
        status: ShardStatus::Queued,
        by: None,
    });
    st.queued_cost += cost;
    st.queue.push_front(id);
    st.parts[slot].finishing = Some(id);
    st.stats.finishings += 1;
}

impl PartSlot {
    /// A suspect: its shards were with a worker that was lost once; each
    /// goes out alone, to a worker that holds nothing else, so a second
    /// loss is its own.
    pub(super) fn suspect(&self) -> bool {
        self.deaths.workers > 0 || self.deaths.suspected
    }
}

/// The open parts of the shards `ids`.
fn open_parts_of(st: &State, ids: &[u64]) -> HashSet<usize> {
    ids.iter()
        .filter_map(|&id| st.shards.get(id as usize))
        .filter(|sh| sh.status != ShardStatus::Done)
        .map(|sh| sh.part)
        .filter(|&p| !st.parts[p].closed)
        .collect()
}

/// How a worker left its shards.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Gone {
    /// Lost or restarted: it died holding them.
    Died,
    /// Their lease ran out: it may only be slow with a big batch.
    TimedOut,
}

/// `worker` left shards `held` (of all it held, `holding`): every open
/// part among them counts it once (the coordinator cannot tell which
/// shard killed it), except a timeout of a worker that held more than
/// that one shard (a batch runs shard after shard, so a slow batch
/// outlives its leases without anything being wrong), which only makes
/// its parts suspects: their shards then go out alone, and a timeout of
/// a shard alone counts. Returns the parts now condemned
/// ([`WorkerLosses::condemned`]).
pub(super) fn strike(
    st: &mut State,
    worker: &str,
    (held, holding): (&[u64], &[u64]),
    how: Gone,
) -> Vec<usize> {
    let parts = open_parts_of(st, held);
    // Of all parts it held, failed ones included: a worker that died
    // holding the killer's shards too (the killer failed by a death seen
    // just before) did not die holding nothing else.
    let mut all = holding.iter().filter_map(|&id| st.shards.get(id as usize));
    let first = all.next().map(|sh| sh.part);
    let alone = parts.len() == 1 && all.all(|sh| Some(sh.part) == first);
    let counts = how == Gone::Died || holding.len() == 1;
    let mut condemned = Vec::new();
    for p in parts {
        let d = &mut st.parts[p].deaths;
        d.suspected = true;
        if !counts || !d.names.insert(worker.to_string()) {
            continue;
        }
        d.workers += 1;
        d.alone += u32::from(alone);
        if d.condemned() {
            condemned.push(p);
        }
    }
    condemned.sort_unstable();
    condemned
}

/// Part `p` has no result: none of its shards goes out again, and the
/// consumer gets `error` for it (once).
pub(super) fn fail_part(st: &mut State, p: usize, error: PartFailure) {
    for sh in st.shards.iter_mut().filter(|s| s.part == p) {
        sh.status = ShardStatus::Done;
    }
    let idx = st.part_index.get(p).copied().unwrap_or(p);
    let part = &mut st.parts[p];
    if !part.closed {
        part.closed = true;
        part.finishing = None;
        st.open_parts -= 1;
        st.done.push((idx, Err(error)));
    }
}

/// Puts one shard back at the front of the queue, whatever became of it.
pub(super) fn back_in_queue(st: &mut State, id: u64) {
    let sh = &mut st.shards[id as usize];
    sh.status = ShardStatus::Queued;
    sh.by = None;
    st.queued_cost += sh.cost;
    st.queue.push_front(id);
    st.stats.requeued += 1;
}

/// Puts shards that are not done back at the front of the queue.
pub(super) fn requeue(st: &mut State, ids: impl Iterator<Item = u64>) -> usize {
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
