//! A list of parts over the workers: planned into shards, served by the
//! [`Scheduler`] through the [`Runtime`], merged results handed back.

use super::local;
use super::options::{ClusterError, ClusterOptions};
use super::runtime::{self, Runtime};
use super::scheduler::{
    Delivery, MergedShards, PartFailure, PlannedPart, Scheduler, Settings, Stats, WHOLE,
};
use crate::job::shards;
use bytes::Bytes;
use fixplan_core::{PartialResult, PreparedPart};
use fixplan_worker::finish::Finisher;
use fixplan_worker::iox;
use fixplan_worker::part_input::PartInput;
use fixplan_worker::protocol::{DataPath, TransportChoice};
use fixplan_worker::zenoh_link::ZenohOptions;
use rayon::prelude::*;
use std::collections::VecDeque;
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError};
use std::sync::Arc;
use std::time::Duration;
use tracing::info;

/// A part the workers finished: its merged result, byte for byte the
/// embedded run's, with the part prepared (a report's plate placement
/// needs it) and, with `--good-enough`, where it stopped.
pub struct MergedPart {
    /// The part as the enumeration saw it.
    pub prep: PreparedPart,
    /// The merged result of its shards.
    pub merged: PartialResult,
    /// `--good-enough`: the combination where the part stopped.
    pub stopped_at: Option<u64>,
}

/// A part as the workers returned it.
pub enum Returned {
    /// Its merged result, for the coordinator to finish.
    Merged(Box<MergedPart>),
    /// Finished by its worker ([`fixplan_worker::finish`]): the bytes of
    /// the caller's finisher, to be copied.
    Finished(Bytes),
}

impl MergedPart {
    /// Takes the coordinator's prepared part if it has one, else prepares
    /// it here (parts go out unprepared and are prepared only when asked
    /// for).
    fn prepared(shards: MergedShards) -> Result<MergedPart, PartFailure> {
        let prep = match shards.prep {
            Some(p) => Arc::try_unwrap(p).unwrap_or_else(|p| (*p).clone()),
            None => shards.input.prepare()?,
        };
        Ok(MergedPart {
            prep,
            merged: shards.merged,
            stopped_at: shards.stopped_at,
        })
    }
}

/// Merged per-part results as the workers deliver them (in any order: the
/// caller puts them back in its own order).
pub struct Distributed {
    rx: Receiver<Vec<Delivery>>,
    /// Delivered by the scheduler, not yet handed out.
    ready: VecDeque<Delivery>,
    delivered: usize,
    total: usize,
    runtime: Option<Runtime>,
    final_stats: Stats,
}

impl Distributed {
    /// Run figures so far.
    pub fn stats(&self) -> Stats {
        self.runtime
            .as_ref()
            .map(|r| r.scheduler.stats())
            .unwrap_or_else(|| self.final_stats.clone())
    }

    /// Ends the run: tells the workers, stops local ones, frees shared memory.
    pub fn finish(&mut self) -> Stats {
        if let Some(mut r) = self.runtime.take() {
            r.shutdown(Duration::from_secs(3));
            self.final_stats = r.scheduler.stats();
        }
        self.final_stats.clone()
    }

    /// The next part's merged result, without preparing the part on the
    /// coordinator (what a caller needs that only counts or ranks).
    pub fn next_merged(&mut self) -> Option<(usize, Result<PartialResult, PartFailure>)> {
        self.next_delivery().map(|(i, r)| (i, r.map(|m| m.merged)))
    }

    /// The next part, prepared here if the run did not need to.
    pub fn next_part(&mut self) -> Option<(usize, Result<MergedPart, PartFailure>)> {
        let (i, r) = self.next_delivery()?;
        Some((i, r.and_then(MergedPart::prepared)))
    }

    /// Every part finished by now (at least one: waits for it), prepared
    /// here in parallel if the run did not need to and its worker did not
    /// finish it: preparing a part is most of the coordinator's own work
    /// on it, so on a host with several cores the coordinator
    /// keeps up with more workers. `None` once all parts are out (the run
    /// is ended then).
    pub fn next_parts(&mut self) -> Option<Vec<(usize, Result<Returned, PartFailure>)>> {
        let first = self.next_delivery()?;
        let more = self.ready.len().min(self.total - self.delivered);
        self.delivered += more;
        let batch: Vec<Delivery> = std::iter::once(first)
            .chain(self.ready.drain(..more))
            .collect();
        // Finished parts are handed over as they are; only the others are
        // worth rayon's threads.
        let mut out = Vec::with_capacity(batch.len());
        let mut to_prepare = Vec::new();
        for (i, r) in batch {
            match r {
                Ok(MergedShards {
                    finished: Some(bytes),
                    ..
                }) => out.push((i, Ok(Returned::Finished(bytes)))),
                other => to_prepare.push((i, other)),
            }
        }
        out.extend(map_batch(to_prepare, |(i, r)| {
            let r = r.and_then(MergedPart::prepared);
            (i, r.map(|m| Returned::Merged(Box::new(m))))
        }));
        Some(out)
    }

    /// The next finished part; `None` once all are (the run is ended then).
    fn next_delivery(&mut self) -> Option<Delivery> {
        if self.delivered >= self.total {
            self.finish();
            return None;
        }
        loop {
            if let Some(done) = self.ready.pop_front() {
                self.delivered += 1;
                return Some(done);
            }
            match self.rx.recv_timeout(Duration::from_secs(30)) {
                Ok(done) => self.ready.extend(done),
                Err(RecvTimeoutError::Timeout) => {
                    info!(
                        role = "coordinator",
                        "waiting for workers: {} of {} parts done", self.delivered, self.total
                    );
                }
                Err(RecvTimeoutError::Disconnected) => return None,
            }
        }
    }
}

/// Parts that came back together are worked on in parallel from this
/// many: for fewer, waking rayon's threads (which spin a while before they
/// sleep, on the coordinator's CPU) costs more than it saves.
const PARALLEL_FROM: usize = 8;

/// `items` mapped by `f`, on rayon's threads when there are enough of them.
pub(crate) fn map_batch<T: Send, U: Send>(
    items: Vec<T>,
    map: impl Fn(T) -> U + Sync + Send,
) -> Vec<U> {
    if items.len() < PARALLEL_FROM {
        items.into_iter().map(map).collect()
    } else {
        items.into_par_iter().map(map).collect()
    }
}

/// Distributes `parts` over workers. Returns at once; [`Distributed`]
/// yields `(index, Ok(part))` or `(index, Err(error))` as parts finish,
/// each equal byte for byte to the embedded run's.
/// Errors read as the embedded path's without the part name: the
/// `prepare` error, or `internal error in the enumeration: ...`.
pub fn run_distributed(
    parts: Vec<PartInput>,
    opts: ClusterOptions,
) -> Result<Distributed, ClusterError> {
    run_distributed_finishing(parts.into_iter().map(|p| (p, None)).collect(), opts, None)
}

/// [`run_distributed`] where the parts come with what a worker needs to
/// finish them ([`fixplan_worker::finish`]; `None`: the coordinator
/// finishes the part): a whole part's worker finishes it, a cut part is
/// finished by a worker from its merged result. Such parts come back as
/// [`Returned::Finished`] from [`Distributed::next_parts`], unless no
/// worker could finish them. `finisher` is the workers' own: a
/// finished part whose result is re-derived is finished again with it and
/// compared (without one, such a part comes back merged).
pub fn run_distributed_finishing(
    parts: Vec<(PartInput, Option<Vec<u8>>)>,
    opts: ClusterOptions,
    finisher: Option<Arc<dyn Finisher>>,
) -> Result<Distributed, ClusterError> {
    iox::quiet_logs();
    let total = parts.len();
    let (tx, rx) = channel::<Vec<Delivery>>();
    let threads = opts
        .worker_threads
        .unwrap_or_else(|| (crate::job::threads::cores() / opts.local_workers.max(1)).max(1));
    let slots = opts.expected_threads.unwrap_or(if opts.local_workers > 0 {
        threads * opts.local_workers
    } else {
        crate::job::threads::cores()
    });
    let (planned, batch_cost) = plan(parts, &opts, slots)?;
    let mut dist = Distributed {
        rx,
        ready: VecDeque::new(),
        delivered: 0,
        total,
        runtime: None,
        final_stats: Stats::default(),
    };
    if planned.is_empty() {
        return Ok(dist);
    }
    let mut settings = settings(&opts, batch_cost);
    settings.finisher = finisher;
    let scheduler = Scheduler::new(settings, planned, tx);
    let zopts = zenoh_options(&opts);
    let mut rt = Runtime::start(Arc::new(scheduler), &zopts, &opts.key_prefix)?;
    start_local_workers(&mut rt, &opts, &zopts, threads)?;
    dist.runtime = Some(rt);
    Ok(dist)
}

/// Cuts the parts into shards for `slots` worker threads, and the cost of
/// one assignment at most. Plans from estimates, without preparing any
/// part here (preparing the parts to cut, for their exact combination
/// counts, would make the coordinator's CPU the limit of a big cluster):
/// a part that would be one shard anyway goes out whole,
/// a bigger one is cut over its estimated combinations, its last shard
/// left open so that it takes whatever the estimate missed (access
/// regions can split segments). A shard past the part's real count
/// enumerates nothing.
fn plan(
    parts: Vec<(PartInput, Option<Vec<u8>>)>,
    opts: &ClusterOptions,
    slots: usize,
) -> Result<(Vec<PlannedPart>, u64), ClusterError> {
    let est: Vec<(u64, usize)> = parts.iter().map(|p| shards::estimate(&p.0)).collect();
    let target = shards::target_cost(&est, slots);
    let encoded: Vec<_> = parts.par_iter().map(|(p, _)| p.encode()).collect();
    let mut planned = Vec::with_capacity(parts.len());
    for (i, ((source, finish), input)) in parts.into_iter().zip(encoded).enumerate() {
        let input = input.map_err(|e| ClusterError::Input(i, e))?;
        let (count, segments) = est[i];
        let whole = opts.shard_size.is_none() && shards::cost(count, segments) <= target;
        let ranges = if whole {
            vec![WHOLE]
        } else {
            let size = opts
                .shard_size
                .unwrap_or_else(|| shards::shard_size(target, count, segments));
            shards::open_ranges(count, size)
        };
        planned.push(PlannedPart {
            index: i,
            prep: None,
            source: Arc::new(source),
            input,
            ranges,
            segments,
            finish,
        });
    }
    Ok((planned, shards::batch_cost(&est, slots)))
}

/// How the scheduler serves this run's workers.
fn settings(opts: &ClusterOptions, batch_cost: u64) -> Settings {
    Settings {
        run_id: fixplan_worker::host::unique_name("run"),
        host_id: fixplan_worker::host::host_id(),
        transport: opts.transport,
        iox: iox_data_path(opts),
        iox_clients: opts
            .iox_clients
            .unwrap_or(opts.local_workers)
            .max(iox::DEFAULT_CLIENTS),
        lease: opts.lease,
        min_workers: opts.min_workers,
        verify: opts.verify,
        good_enough: opts.good_enough,
        part_setups: opts.part_setups,
        part_fixtures: opts.part_fixtures,
        part_seconds: opts.part_seconds,
        batch_cost,
        finisher: None,
    }
}

/// The iceoryx2 data path of the run, unless it is zenoh only; what dead
/// runs left in shared memory is removed first.
fn iox_data_path(opts: &ClusterOptions) -> Option<DataPath> {
    if opts.transport == TransportChoice::Zenoh {
        return None;
    }
    let stale = iox::remove_stale();
    if !stale.is_empty() {
        info!(
            role = "coordinator",
            "removed the iceoryx2 resources of {} dead runs",
            stale.len()
        );
    }
    Some(DataPath::Iceoryx2 {
        prefix: iox::new_prefix(),
        service: format!(
            "fixplan/{}",
            fixplan_worker::host::sanitize(&opts.key_prefix)
        ),
    })
}

/// The zenoh options of the run: with no endpoint at all, a private unix
/// socket (local workers connect to it).
fn zenoh_options(opts: &ClusterOptions) -> ZenohOptions {
    let mut zopts = opts.zenoh.clone();
    if zopts.listen.is_empty() && zopts.connect.is_empty() && zopts.config_file.is_none() {
        let sock = std::env::temp_dir().join(format!(
            "{}.sock",
            fixplan_worker::host::unique_name("fixplan")
        ));
        zopts.listen = vec![format!("unixsock-stream/{}", sock.display())];
        crate::interrupt::remove_on_signal(sock);
    }
    zopts
}

/// Starts `--workers N` worker processes with `threads` threads each,
/// connected to the run's first endpoint.
fn start_local_workers(
    rt: &mut Runtime,
    opts: &ClusterOptions,
    zopts: &ZenohOptions,
    threads: usize,
) -> Result<(), ClusterError> {
    if opts.local_workers == 0 {
        return Ok(());
    }
    let exe = match &opts.worker_exe {
        Some(e) => e.clone(),
        None => std::env::current_exe().map_err(ClusterError::Spawn)?,
    };
    let connect = zopts
        .listen
        .first()
        .or(zopts.connect.first())
        .map(|e| runtime::connect_for(e))
        .ok_or(ClusterError::NoEndpoint)?;
    let spec = local::LocalSpec {
        exe: &exe,
        connect: &connect,
        key_prefix: &opts.key_prefix,
        transport: &opts.transport.to_string(),
        threads,
        quiet: opts.quiet,
        tls: zopts.tls.as_ref(),
    };
    rt.spawn_local(&spec, opts.local_workers)
}
