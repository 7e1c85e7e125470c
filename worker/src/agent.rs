//! `fixplan worker`: join a coordinator, pull shards, enumerate them, send
//! the results back; leave at the end of the run (or wait for the next one
//! with `stay`).

use crate::finish::Finisher;
use crate::host::{host_id, unique_name};
use crate::in_flight::InFlight;
use crate::iox::IoxClient;
use crate::protocol::{
    encode_as, Assign, DataPath, Digest, Frame, Join, Msg, Next, TransportChoice, PROTOCOL_VERSION,
};
use crate::task::{CachedPart, Plain, Runner};
use crate::zenoh_link::{open, request, Keys, LinkError, ZenohOptions};
use std::collections::HashMap;
use std::sync::Arc;
use std::time::{Duration, Instant};
use thiserror::Error;
use tracing::{info, warn};
use zenoh::Wait;

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
    /// How tasks are run: [`Plain`], or the binary's own around it
    /// (faults for tests of the coordinator's checks, replayed results
    /// for `fixplan bench-coordinator`).
    pub runner: Arc<dyn Runner>,
    /// Finishes parts here ([`crate::finish`]): the `fixplan`
    /// binary's, so the coordinator only copies their bytes. Without one,
    /// the coordinator finishes every part itself.
    pub finisher: Option<Arc<dyn Finisher>>,
    /// The process that started this worker (`fixplan run --workers`):
    /// once it is gone (this worker reparented), the worker stops, even
    /// before it joined a run. A coordinator killed by SIGKILL cannot
    /// stop its workers, and one killed before they joined left them
    /// waiting for it for ever.
    pub parent: Option<u32>,
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
            runner: Arc::new(Plain),
            finisher: None,
            parent: None,
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
    cache: HashMap<Digest, Arc<CachedPart>>,
    summary: WorkerSummary,
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

    /// The part of task `a`: the cached one, or a new one holding the
    /// input `a` brought.
    fn part(&mut self, assign: &Assign) -> Arc<CachedPart> {
        // A batch may hold several tasks of one part: the first carries
        // the input, the cache serves the rest.
        if let Some(p) = self.cache.get(&assign.digest) {
            return p.clone();
        }
        let part = Arc::new(CachedPart::new(assign.digest, assign.input.clone()));
        self.summary.parts_prepared += 1;
        // Only cache what the coordinator sent: assign missing input is retried.
        if assign.input.is_some() {
            self.cache.insert(assign.digest, part.clone());
        }
        part
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

    /// Puts an assignment on the pool, task by task.
    fn start(&mut self, batch: Vec<Assign>, flight: &mut InFlight) {
        for a in batch {
            let part = self.part(&a);
            let (runner, finisher) = (self.opts.runner.clone(), self.opts.finisher.clone());
            flight.spawn(&self.pool, a.shard_id, move || {
                runner.run(&a, &part, finisher.as_deref())
            });
        }
    }

    /// Whether the process that started this worker has died: the
    /// kernel then hands the worker to another parent.
    fn orphaned(&self) -> bool {
        self.opts
            .parent
            .is_some_and(|parent| std::os::unix::process::parent_id() != parent)
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
                    if self.orphaned() {
                        info!(
                            role = self.role,
                            "the process that started this worker is gone ({e}); stopping"
                        );
                        return Ok(());
                    }
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
    use super::WorkerSummary;

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
