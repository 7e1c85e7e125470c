//! `fixplan worker`: join a coordinator, pull shards, enumerate them, send
//! the results back; leave at the end of the run (or wait for the next one
//! with `stay`).

use crate::finish::Finisher;
use crate::host::{host_id, unique_name};
use crate::in_flight::InFlight;
use crate::iox::IoxClient;
use crate::part_input::{PartInput, WireInputError};
use crate::protocol::{
    encode_as, Assign, DataPath, Digest, Frame, Join, Msg, Next, Outcome, ShardDone, ShardFailed,
    TransportChoice, PROTOCOL_VERSION,
};
use crate::replay::Replay;
use crate::zenoh_link::{open, request, Keys, LinkError, ZenohOptions};
use fixplan_core::{PartialResult, PreparedPart};
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::Arc;
use std::time::{Duration, Instant};
use thiserror::Error;
use tracing::{info, warn};
use zenoh::Wait;

/// Misbehaviours for tests of the coordinator's checks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Fault {
    /// Halve the score of the best fixture of every result.
    CorruptScore,
    /// Finish parts (whole or cut) with a made-up timing: honest results,
    /// finished parts that are not what they make.
    ForgeFinished,
    /// Take this much longer over every shard (a slow machine: the run
    /// lasts as long whatever the size of its assignments, which tests
    /// that upset a worker mid-run rely on).
    SlowMs(u64),
}

/// A `--fault` value that names no [`Fault`].
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum FaultError {
    /// None of `corrupt-score`, `forge-finished`, `slow:MS`.
    #[error("unknown fault {0:?} (corrupt-score, forge-finished, slow:MS)")]
    Unknown(String),
    /// `slow:` without a number of milliseconds.
    #[error("{text}: {source}")]
    SlowMs {
        /// The value given.
        text: String,
        /// Why it is not a number.
        source: std::num::ParseIntError,
    },
}

impl std::str::FromStr for Fault {
    type Err = FaultError;
    fn from_str(s: &str) -> Result<Self, FaultError> {
        if s == "corrupt-score" {
            return Ok(Fault::CorruptScore);
        }
        if s == "forge-finished" {
            return Ok(Fault::ForgeFinished);
        }
        if let Some(ms) = s.strip_prefix("slow:") {
            return ms
                .parse()
                .map(Fault::SlowMs)
                .map_err(|source| FaultError::SlowMs {
                    text: s.to_string(),
                    source,
                });
        }
        Err(FaultError::Unknown(s.to_string()))
    }
}

/// What `fixplan worker` was told on its command line.
#[derive(Debug, Clone)]
pub struct WorkerOptions {
    /// How to reach the coordinator.
    pub zenoh: ZenohOptions,
    /// The run's key prefix: the coordinator's `--key-prefix`.
    pub key_prefix: String,
    /// Enumeration threads (default: all cores).
    pub threads: Option<usize>,
    /// The transport to ask for (iceoryx2 only helps on the coordinator's
    /// host).
    pub transport: TransportChoice,
    /// Wait for the next run instead of exiting when a run is over.
    pub stay: bool,
    /// Name in logs and liveliness (default: host-pid-nonce).
    pub name: Option<String>,
    /// Protocol version to claim (tests of the version check).
    pub protocol_version: u16,
    /// Misbehave on purpose (tests of the coordinator's checks).
    pub fault: Option<Fault>,
    /// Answer shards seen before from this cache, at once, and record the
    /// others (`fixplan bench-coordinator`: the coordinator measured alone).
    pub replay: Option<Arc<Replay>>,
    /// Finishes whole parts here ([`crate::finish`]): the `fixplan`
    /// binary's, so the coordinator only copies their bytes. Without one,
    /// the coordinator finishes every part itself.
    pub finisher: Option<Arc<dyn Finisher>>,
}

impl std::fmt::Debug for dyn Finisher {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Finisher")
    }
}

impl Default for WorkerOptions {
    fn default() -> Self {
        WorkerOptions {
            zenoh: ZenohOptions::default(),
            key_prefix: "fixplan".into(),
            threads: None,
            transport: TransportChoice::Auto,
            stay: false,
            name: None,
            protocol_version: PROTOCOL_VERSION,
            fault: None,
            replay: None,
            finisher: None,
        }
    }
}

/// Why a worker stopped before its run was over.
#[derive(Debug, Error)]
pub enum WorkerError {
    /// No zenoh session, or an iceoryx2 link that was asked for failed.
    #[error(transparent)]
    Link(#[from] LinkError),
    /// The coordinator will not have this worker (another protocol version,
    /// rejected results): retrying would not help, so `fixplan worker`
    /// exits with code 3.
    #[error("the coordinator refused this worker: {0}")]
    Refused(String),
    /// The enumeration threads could not be started.
    #[error("cannot start the thread pool: {0}")]
    Pool(rayon::ThreadPoolBuildError),
}

/// What a worker did, for its exit line.
#[derive(Debug, Clone, Default)]
pub struct WorkerSummary {
    /// Shards assigned to this worker (done or failed).
    pub shards: u64,
    /// Part inputs it prepared (once per part and run, thanks to the cache).
    pub parts_prepared: u64,
    /// Time its threads spent on shards, microseconds.
    pub busy_micros: u64,
    /// Its threads times the time it held shards, microseconds: beside
    /// [`WorkerSummary::busy_micros`], how long its threads had nothing
    /// while it held work (a simulated worker, which answers at once,
    /// counts neither).
    pub offered_micros: u64,
}

impl WorkerSummary {
    /// Percent of the time its assignments took that its threads were
    /// busy (100 if it had none).
    pub fn busy_percent(&self) -> u64 {
        (self.busy_micros.min(self.offered_micros) * 100)
            .checked_div(self.offered_micros)
            .unwrap_or(100)
    }
}

/// A part's input and the part prepared, or why there is none, shared by
/// the shards of the part.
type Prepared = Arc<Result<(PartInput, PreparedPart), WireInputError>>;

/// A part as its shards find it on a worker: the input its first shard
/// brought, prepared once, by whichever of its shards runs first, on the
/// pool (preparing on the agent's thread made it a serial stage before
/// every shard: about 30-50 us a part, a limit for many threads on small
/// parts).
struct PartSlot {
    digest: Digest,
    input: Option<bytes::Bytes>,
    prepared: std::sync::OnceLock<Prepared>,
}

impl PartSlot {
    /// The part prepared (the first call prepares it; concurrent ones
    /// wait for it).
    fn get(&self) -> Prepared {
        self.prepared
            .get_or_init(|| {
                Arc::new(PartInput::prepare_wire_kept(
                    &self.digest,
                    self.input.as_deref(),
                ))
            })
            .clone()
    }
}

enum DataLink {
    Zenoh,
    Iox(Box<IoxClient>),
}

struct Agent {
    opts: WorkerOptions,
    name: String,
    /// `worker NAME`: the `role` of every log line.
    role: String,
    keys: Keys,
    session: zenoh::Session,
    pool: rayon::ThreadPool,
    cache: HashMap<Digest, Arc<PartSlot>>,
    summary: WorkerSummary,
}

/// What becomes of one assignment ([`shard_outcome`] or
/// [`cut_part_outcome`]), with the worker's fault and finisher.
type OutcomeOf = fn(
    Option<Fault>,
    Option<&dyn Finisher>,
    Assign,
    &Result<(PartInput, PreparedPart), WireInputError>,
) -> Outcome;

/// One shard of an assignment, enumerated (on the calling rayon pool),
/// and finished when it is a whole part the coordinator asked to have
/// finished.
fn shard_outcome(
    fault: Option<Fault>,
    finisher: Option<&dyn Finisher>,
    a: Assign,
    prepared: &Result<(PartInput, PreparedPart), WireInputError>,
) -> Outcome {
    let failed = |message: String| {
        Outcome::Failed(ShardFailed {
            shard_id: a.shard_id,
            message,
        })
    };
    if let Some(Fault::SlowMs(ms)) = fault {
        std::thread::sleep(Duration::from_millis(ms));
    }
    let (input, prep) = match prepared {
        Ok((input, prep)) => (input, prep),
        Err(e) => return failed(e.to_string()),
    };
    let t0 = Instant::now();
    let out = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        crate::run_shard_until(prep, a.range.clone(), a.good_enough)
    }));
    match out {
        Ok((mut result, hit)) => {
            if fault == Some(Fault::CorruptScore) {
                if let Some(f) = result.fixtures.first_mut() {
                    f.score *= 0.5;
                }
            }
            let micros = t0.elapsed().as_micros() as u64;
            // The forger finishes with another timing than it reports.
            let forged = micros + u64::from(fault == Some(Fault::ForgeFinished)) * 1_000_000;
            let finished = match (finisher, &a.finish) {
                (Some(f), Some(context)) if hit.is_none() => {
                    finished(f, input, prep, &result, forged, context)
                }
                _ => None,
            };
            Outcome::Done(Box::new(ShardDone {
                shard_id: a.shard_id,
                digest: a.digest,
                micros,
                result,
                hit,
                finished,
            }))
        }
        Err(p) => failed(format!(
            "internal error in the enumeration: {}",
            crate::panic_text(p)
        )),
    }
}

/// A cut part finished from its merged result: the finished bytes and an
/// empty result (the coordinator holds the merged one), or no bytes if
/// this worker has no finisher or could not finish it (the coordinator
/// then does).
fn cut_part_outcome(
    fault: Option<Fault>,
    finisher: Option<&dyn Finisher>,
    a: Assign,
    prepared: &Result<(PartInput, PreparedPart), WireInputError>,
) -> Outcome {
    let (input, prep) = match prepared {
        Ok((input, prep)) => (input, prep),
        Err(e) => {
            return Outcome::Failed(ShardFailed {
                shard_id: a.shard_id,
                message: e.to_string(),
            })
        }
    };
    let t0 = Instant::now();
    let finished = match (finisher, &a.finish, &a.finish_from) {
        (Some(f), Some(context), Some(from)) => {
            // The forger finishes with another timing than it was sent.
            let forged = from.micros + u64::from(fault == Some(Fault::ForgeFinished)) * 1_000_000;
            finished(f, input, prep, &from.result, forged, context)
        }
        _ => None,
    };
    Outcome::Done(Box::new(ShardDone {
        shard_id: a.shard_id,
        digest: a.digest,
        micros: t0.elapsed().as_micros() as u64,
        result: PartialResult {
            range: 0..0,
            counts: Default::default(),
            fixtures: Vec::new(),
        },
        hit: None,
        finished,
    }))
}

/// A whole part finished by `f`, or `None` (logged) if it could not be:
/// the coordinator then finishes it from the result.
fn finished(
    f: &dyn Finisher,
    input: &PartInput,
    prep: &PreparedPart,
    result: &PartialResult,
    micros: u64,
    context: &[u8],
) -> Option<Vec<u8>> {
    let out = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        f.finish(input, prep, result, micros, context)
    }));
    match out {
        Ok(Ok(bytes)) => Some(bytes),
        Ok(Err(e)) => {
            warn!("could not finish a part here ({e}): the coordinator will");
            None
        }
        Err(p) => {
            warn!(
                "finishing a part panicked ({}): the coordinator will finish it",
                crate::panic_text(p)
            );
            None
        }
    }
}

/// A worker told to wait while shards of its own still run waits this
/// many times longer for one of them before it asks again.
const HOLDING_IDLE_FACTOR: u32 = 10;

const REQUEST_TIMEOUT: Duration = Duration::from_secs(10);
/// A coordinator silent for this long is presumed gone: join again.
const SILENCE: Duration = Duration::from_secs(15);

impl Agent {
    fn send(&self, link: &DataLink, msg: &Msg) -> Result<Frame, LinkError> {
        let bytes = encode_as(self.opts.protocol_version, msg)?;
        match link {
            DataLink::Zenoh => request(&self.session, &self.keys.work(), bytes, REQUEST_TIMEOUT),
            DataLink::Iox(c) => c.request(&bytes, REQUEST_TIMEOUT),
        }
    }

    fn join(&self) -> Result<Frame, LinkError> {
        let j = Join {
            worker: self.name.clone(),
            host_id: host_id(),
            pid: std::process::id(),
            threads: self.pool.current_num_threads() as u32,
            transport: self.opts.transport,
            software: env!("CARGO_PKG_VERSION").into(),
        };
        let bytes = encode_as(self.opts.protocol_version, &Msg::Join(j))?;
        request(
            &self.session,
            &self.keys.join(),
            bytes,
            Duration::from_secs(3),
        )
    }

    /// The slot of `a`'s part: the cached one, or a new one holding the
    /// input `a` brought.
    fn slot(&mut self, a: &Assign) -> Arc<PartSlot> {
        // A batch may hold several shards of one part: the first carries
        // the input, the cache serves the rest.
        if let Some(p) = self.cache.get(&a.digest) {
            return p.clone();
        }
        let slot = Arc::new(PartSlot {
            digest: a.digest,
            input: a.input.clone(),
            prepared: std::sync::OnceLock::new(),
        });
        self.summary.parts_prepared += 1;
        // Only cache what the coordinator sent: a missing input is retried.
        if a.input.is_some() {
            self.cache.insert(a.digest, slot.clone());
        }
        slot
    }

    /// `a`'s part prepared, here and now.
    fn prepared(&mut self, a: &Assign) -> Prepared {
        self.slot(a).get()
    }

    /// A simulated worker's assignment: what the replay cache knows at
    /// once, the rest computed side by side on the pool (each shard
    /// inside its own `catch_unwind`, so one panicking part fails alone)
    /// and recorded.
    fn replayed_batch(&mut self, replay: &Replay, batch: Vec<Assign>) -> Vec<Outcome> {
        // Finishing a cut part enumerates nothing: it is done apart.
        let (to_finish, shards): (Vec<Assign>, Vec<Assign>) =
            batch.into_iter().partition(|a| a.finish_from.is_some());
        let mut out = self.replayed(replay, to_finish, Self::finished_cut);
        out.extend(self.replayed(replay, shards, Self::enumerated));
        out
    }

    /// Cut parts finished from their merged results
    /// ([`Assign::finish_from`]), side by side on the pool.
    fn finished_cut(&mut self, batch: Vec<Assign>) -> Vec<Outcome> {
        self.on_pool(batch, cut_part_outcome)
    }

    /// [`Agent::replayed_batch`] of one kind: the assignments it knows at
    /// once, the others done by `compute` ([`Agent::enumerated`] for
    /// shards, [`Agent::finished_cut`] for finishings) and recorded.
    fn replayed(
        &mut self,
        replay: &Replay,
        batch: Vec<Assign>,
        compute: fn(&mut Self, Vec<Assign>) -> Vec<Outcome>,
    ) -> Vec<Outcome> {
        let mut out: Vec<Option<Outcome>> = batch.iter().map(|a| replay.get(a)).collect();
        let (mut todo, mut at) = (Vec::new(), Vec::new());
        for (i, mut a) in batch.into_iter().enumerate() {
            if out[i].is_none() {
                a.input = a.input.take().or_else(|| replay.input_for(&a));
                if let Some(o) = self.refinished(replay, &a) {
                    out[i] = Some(replay.put(&a, o));
                    continue;
                }
                todo.push(a);
                at.push(i);
            }
        }
        if !todo.is_empty() {
            let asked = todo.clone();
            for ((a, o), i) in asked.iter().zip(compute(self, todo)).zip(at) {
                out[i] = Some(replay.put(a, o));
            }
        }
        out.into_iter().flatten().collect()
    }

    /// A shard enumerated before under another finish context, finished
    /// for `a` (a part listed many times is enumerated once).
    fn refinished(&mut self, replay: &Replay, a: &Assign) -> Option<Outcome> {
        if a.finish_from.is_some() {
            // A finishing enumerates nothing to finish again.
            return None;
        }
        let (finisher, context) = (self.opts.finisher.clone()?, a.finish.as_ref()?);
        let Outcome::Done(mut done) = replay.enumerated(a)? else {
            return None;
        };
        let prepared = self.prepared(a);
        let (input, prep) = prepared.as_ref().as_ref().ok()?;
        done.finished = finished(
            finisher.as_ref(),
            input,
            prep,
            &done.result,
            done.micros,
            context,
        );
        Some(Outcome::Done(done))
    }

    /// Enumerates the shards of `batch` side by side on the pool.
    fn enumerated(&mut self, batch: Vec<Assign>) -> Vec<Outcome> {
        self.on_pool(batch, shard_outcome)
    }

    /// The `outcome` of each assignment of `batch` with its part prepared,
    /// side by side on the pool.
    fn on_pool(&mut self, batch: Vec<Assign>, outcome: OutcomeOf) -> Vec<Outcome> {
        if batch.is_empty() {
            return Vec::new();
        }
        let jobs: Vec<_> = batch
            .into_iter()
            .map(|a| {
                let prep = self.prepared(&a);
                (a, prep)
            })
            .collect();
        let fault = self.opts.fault;
        let finisher = self.opts.finisher.as_deref();
        self.pool.install(|| {
            jobs.into_par_iter()
                .map(|(a, prep)| outcome(fault, finisher, a, &prep))
                .collect::<Vec<_>>()
        })
    }

    /// Works for one coordinator until it says Done (true) or goes silent
    /// or asks for a new join (false). Shards run on the pool while the
    /// worker reports and asks for more ([`InFlight`]).
    fn serve_run(&mut self, link: DataLink) -> Result<bool, WorkerError> {
        let mut flight = InFlight::new(self.pool.current_num_threads());
        let out = self.serve_run_with(&link, &mut flight);
        self.summary.busy_micros += flight.busy_micros;
        self.summary.offered_micros += flight.offered_micros;
        out
    }

    fn serve_run_with(
        &mut self,
        link: &DataLink,
        flight: &mut InFlight,
    ) -> Result<bool, WorkerError> {
        let mut last_heard = Instant::now();
        // Kept until a reply comes: sent again as it is if none does.
        let mut report = Msg::Report {
            worker: self.name.clone(),
            outcomes: Vec::new(),
            holding: Vec::new(),
        };
        loop {
            let reply = self.send(link, &report);
            let (notes, next) = match reply {
                Ok(Frame::Msg(Msg::Reply { notes, next })) => (notes, next),
                Ok(Frame::Msg(m)) => {
                    warn!(role = self.role, "unexpected reply to a report: {m:?}");
                    std::thread::sleep(Duration::from_millis(200));
                    continue;
                }
                Ok(Frame::Refused(r)) => return Err(WorkerError::Refused(r)),
                Err(e) => {
                    // The report is sent again (the coordinator takes the
                    // first copy of a result and notes the others).
                    if last_heard.elapsed() > SILENCE {
                        warn!(
                            role = self.role,
                            "the coordinator is silent ({e}); joining again"
                        );
                        return Ok(false);
                    }
                    std::thread::sleep(Duration::from_millis(200));
                    continue;
                }
            };
            last_heard = Instant::now();
            for n in notes {
                warn!(role = self.role, "{n}");
            }
            let idle = match next {
                Next::Work(batch) => {
                    self.summary.shards += batch.len() as u64;
                    self.start(batch, flight);
                    None
                }
                Next::Idle { retry_ms } => {
                    let wait = Duration::from_millis(retry_ms.clamp(1, 2000));
                    if flight.is_empty() {
                        std::thread::sleep(wait);
                        Some(wait)
                    } else {
                        // Its own shards' results are worth a report
                        // sooner than more polling at the end of a run
                        // (each poll costs the coordinator a request).
                        Some(wait * HOLDING_IDLE_FACTOR)
                    }
                }
                // What still runs is dropped: the run is over, or the
                // coordinator no longer counts on this worker.
                Next::Done => return Ok(true),
                Next::Rejoin => return Ok(false),
            };
            // Ask again once every shard held has a thread.
            let outcomes = flight.take(self.pool.current_num_threads(), idle);
            report = Msg::Report {
                worker: self.name.clone(),
                outcomes,
                holding: flight.holding(),
            };
        }
    }

    /// Puts an assignment on the pool, shard by shard (replayed ones are
    /// known at once).
    fn start(&mut self, batch: Vec<Assign>, flight: &mut InFlight) {
        if let Some(replay) = self.opts.replay.clone() {
            let outcomes = self.replayed_batch(&replay, batch);
            flight.add_ready(outcomes);
            return;
        }
        for a in batch {
            let slot = self.slot(&a);
            // Finishing a cut part enumerates nothing.
            let outcome: OutcomeOf = if a.finish_from.is_some() {
                cut_part_outcome
            } else {
                shard_outcome
            };
            let (fault, finisher) = (self.opts.fault, self.opts.finisher.clone());
            flight.spawn(&self.pool, a.shard_id, move || {
                outcome(fault, finisher.as_deref(), a, &slot.get())
            });
        }
    }

    fn run(&mut self) -> Result<(), WorkerError> {
        let mut waiting_since = Instant::now();
        let mut said_waiting = false;
        let mut finished_run: Option<String> = None;
        // Whether this worker took part in a run that it lost (without
        // `stay`, it ends once the coordinator is gone for good).
        let mut was_in_run = false;
        loop {
            let welcome = match self.join() {
                Ok(Frame::Msg(Msg::Welcome(w))) => w,
                Ok(Frame::Msg(Msg::Reply {
                    next: Next::Done, ..
                })) => {
                    if !self.opts.stay && finished_run.is_none() {
                        info!(role = self.role, "the run is already over");
                        return Ok(());
                    }
                    std::thread::sleep(Duration::from_millis(500));
                    continue;
                }
                Ok(Frame::Refused(r)) => return Err(WorkerError::Refused(r)),
                Ok(Frame::Msg(m)) => {
                    warn!(role = self.role, "unexpected reply to join: {m:?}");
                    std::thread::sleep(Duration::from_millis(500));
                    continue;
                }
                Err(LinkError::Decode(e)) => {
                    return Err(WorkerError::Refused(format!(
                        "cannot read the coordinator's reply: {e}"
                    )));
                }
                Err(e) => {
                    if was_in_run && !self.opts.stay && waiting_since.elapsed() > GONE_AFTER {
                        // Its run ended while it was rejoining (the
                        // coordinator told the others), or the coordinator
                        // died: a worker without `stay` does not wait forever.
                        info!(role = self.role, "the coordinator is gone ({e}); stopping");
                        return Ok(());
                    }
                    if !said_waiting && waiting_since.elapsed() > Duration::from_secs(2) {
                        info!(
                            role = self.role,
                            "waiting for a coordinator on {} ({e})",
                            self.keys.join()
                        );
                        said_waiting = true;
                    }
                    std::thread::sleep(Duration::from_millis(300));
                    continue;
                }
            };
            if finished_run.as_deref() == Some(welcome.run_id.as_str()) {
                std::thread::sleep(Duration::from_millis(500));
                continue;
            }
            let link = match &welcome.data {
                DataPath::Zenoh => DataLink::Zenoh,
                DataPath::Iceoryx2 { prefix, service } => {
                    match IoxClient::open(prefix, service) {
                        Ok(c) => DataLink::Iox(Box::new(c)),
                        // The coordinator's shared memory is full (more
                        // workers on this host than it serves): zenoh
                        // reaches the same coordinator, unless iceoryx2
                        // was asked for.
                        Err(e) if self.opts.transport != TransportChoice::Iceoryx2 => {
                            warn!(
                                role = self.role,
                                "iceoryx2 unavailable ({e}); shards over zenoh"
                            );
                            DataLink::Zenoh
                        }
                        Err(e) => return Err(e.into()),
                    }
                }
            };
            info!(
                role = self.role,
                "joined run {} ({} threads, shards over {})",
                welcome.run_id,
                self.pool.current_num_threads(),
                match link {
                    DataLink::Zenoh => "zenoh",
                    DataLink::Iox(_) => "iceoryx2",
                }
            );
            was_in_run = true;
            if self.serve_run(link)? {
                info!(
                    role = self.role,
                    "run {} is over: {} shards done, its threads busy {}% of the time its assignments took",
                    welcome.run_id,
                    self.summary.shards,
                    self.summary.busy_percent()
                );
                if !self.opts.stay {
                    return Ok(());
                }
                finished_run = Some(welcome.run_id.clone());
                self.cache.clear();
            }
            waiting_since = Instant::now();
            said_waiting = false;
        }
    }
}

/// How long a worker without `stay` that lost its run keeps looking for
/// the coordinator: the zenoh link lease, so a coordinator that is only
/// slow to answer is not given up on.
const GONE_AFTER: Duration = Duration::from_secs(10);

/// Runs a worker until its run is over (or forever with `stay`).
pub fn run_worker(opts: WorkerOptions) -> Result<WorkerSummary, WorkerError> {
    crate::iox::quiet_logs();
    let name = opts.name.clone().unwrap_or_else(|| unique_name("w"));
    let keys = Keys::new(&opts.key_prefix);
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = opts.threads {
        pool = pool.num_threads(n);
    }
    let pool = pool.build().map_err(WorkerError::Pool)?;
    let session = open(&opts.zenoh)?;
    let _token = session
        .liveliness()
        .declare_token(keys.alive(&name))
        .wait()
        .map_err(LinkError::Zenoh)?;
    let mut agent = Agent {
        opts,
        role: format!("worker {name}"),
        name,
        keys,
        session,
        pool,
        cache: HashMap::new(),
        summary: WorkerSummary::default(),
    };
    let r = agent.run();
    let _ = agent.session.close().wait();
    r.map(|_| agent.summary)
}

#[cfg(test)]
mod tests {
    use super::{PartSlot, WorkerSummary};
    use crate::part_input::{digest, sample_input};
    use std::sync::{Arc, OnceLock};

    #[test]
    fn shards_running_at_once_prepare_their_part_once() {
        let bytes = sample_input().encode().unwrap();
        let slot = Arc::new(PartSlot {
            digest: digest(&bytes),
            input: Some(bytes.into()),
            prepared: OnceLock::new(),
        });
        let got: Vec<_> = std::thread::scope(|s| {
            let handles: Vec<_> = (0..4).map(|_| s.spawn(|| slot.get())).collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        assert!(got[0].is_ok());
        assert!(got.iter().all(|p| Arc::ptr_eq(p, &got[0])));
        // A part whose input never came fails its shards by name.
        let missing = PartSlot {
            digest: [0; 32],
            input: None,
            prepared: OnceLock::new(),
        };
        assert!(missing.get().is_err());
    }

    #[test]
    fn busy_percent_is_a_share_of_the_offered_time() {
        let s = |busy, offered| WorkerSummary {
            busy_micros: busy,
            offered_micros: offered,
            ..WorkerSummary::default()
        };
        assert_eq!(s(0, 0).busy_percent(), 100);
        assert_eq!(s(750, 1000).busy_percent(), 75);
        // Clock skew between threads never reads as more than all.
        assert_eq!(s(1010, 1000).busy_percent(), 100);
        assert_eq!(s(0, 1000).busy_percent(), 0);
    }
}
