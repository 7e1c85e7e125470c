//! A list of parts over the workers: planned into shards, served by the
//! [`Scheduler`] through the [`Runtime`], merged results handed back.

use super::local;
use super::options::{ClusterError, ClusterOptions};
use super::runtime::{self, Runtime};
use super::scheduler::{Finished, PartDone, PartSlot, Scheduler, Settings, Stats, WHOLE};
use crate::job::shards;
use fixplan_core::{PartialResult, PreparedPart};
use fixplan_worker::iox;
use fixplan_worker::part_input::{digest, PartInput};
use fixplan_worker::protocol::TransportChoice;
use rayon::prelude::*;
use std::collections::VecDeque;
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError};
use std::sync::Arc;
use std::time::Duration;
use tracing::info;

/// A part's merged result with its prepared form (for the report: plate
/// placement needs it) and, with `--good-enough`, where it stopped.
pub struct Solved {
    pub prep: PreparedPart,
    pub merged: PartialResult,
    pub stopped_at: Option<u64>,
}

/// Merged per-part results as the workers deliver them (in any order: the
/// caller puts them back in its own order).
pub struct Distributed {
    rx: Receiver<Vec<PartDone>>,
    /// Delivered by the scheduler, not yet handed out.
    ready: VecDeque<PartDone>,
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
            .map(|r| r.core.stats())
            .unwrap_or_else(|| self.final_stats.clone())
    }

    /// Ends the run: tells the workers, stops local ones, frees shared memory.
    pub fn finish(&mut self) -> Stats {
        if let Some(mut r) = self.runtime.take() {
            r.shutdown(Duration::from_secs(3));
            self.final_stats = r.core.stats();
        }
        self.final_stats.clone()
    }

    /// The next part's merged result, without preparing the part on the
    /// coordinator (what a caller needs that only counts or ranks).
    pub fn next_merged(&mut self) -> Option<(usize, Result<PartialResult, String>)> {
        self.next_finished().map(|(i, r)| (i, r.map(|f| f.merged)))
    }

    /// The next part, prepared here if the run did not need to.
    pub fn next_part(&mut self) -> Option<(usize, Result<Solved, String>)> {
        let (i, r) = self.next_finished()?;
        let r = r.and_then(|f| {
            let prep = match f.prep {
                Some(p) => Arc::try_unwrap(p).unwrap_or_else(|p| (*p).clone()),
                None => f.input.prepare().map_err(|e| e.to_string())?,
            };
            Ok(Solved {
                prep,
                merged: f.merged,
                stopped_at: f.stopped_at,
            })
        });
        Some((i, r))
    }

    fn next_finished(&mut self) -> Option<(usize, Result<Finished, String>)> {
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

/// Distributes `parts` over workers. Returns at once; [`Distributed`]
/// yields `(index, Ok(part))` or `(index, Err(message))` as parts finish,
/// each equal byte for byte to the embedded run's.
/// Error messages are those of the embedded path without the part name:
/// the `prepare` error, or `internal error in the enumeration: ...`.
pub fn run_distributed(
    parts: Vec<PartInput>,
    opts: ClusterOptions,
) -> Result<Distributed, ClusterError> {
    iox::quiet_logs();
    let total = parts.len();
    let (tx, rx) = channel::<Vec<PartDone>>();
    let threads = opts
        .worker_threads
        .unwrap_or_else(|| (fixplan_worker::host::cores() / opts.local_workers.max(1)).max(1));
    let slots = opts.expected_threads.unwrap_or(if opts.local_workers > 0 {
        threads * opts.local_workers
    } else {
        fixplan_worker::host::cores()
    });
    // Plan from estimates: a part that would be one shard anyway goes out
    // whole and unprepared (preparing every part here cost the coordinator
    // more than all else it does); only parts to be cut are prepared, for
    // their exact combination count.
    let est: Vec<(u64, usize)> = parts.iter().map(shards::estimate).collect();
    let target = shards::target_cost(&est, slots);
    let batch_cost = shards::batch_cost(&est, slots);
    let whole: Vec<bool> = est
        .iter()
        .map(|&(c, n)| opts.shard_size.is_none() && shards::cost(c, n) <= target)
        .collect();
    let encoded: Vec<_> = parts
        .par_iter()
        .zip(whole.par_iter())
        .map(|(p, &whole)| {
            let prep = (!whole).then(|| p.prepare().map_err(|e| e.to_string()));
            (prep, p.encode().map_err(|e| e.to_string()))
        })
        .collect();
    let mut slots_in = Vec::new();
    for (i, (source, (prep, bytes))) in parts.into_iter().zip(encoded).enumerate() {
        let bytes = bytes.map_err(|e| ClusterError::Input(i, e))?;
        let source = Arc::new(source);
        let (prep, ranges, segments) = match prep {
            None => (None, vec![WHOLE], est[i].1),
            Some(Err(e)) => {
                let _ = tx.send(vec![(i, Err(e))]);
                continue;
            }
            Some(Ok(prep)) => {
                let (count, n) = (prep.combination_count(), prep.segments.len());
                if count == 0 {
                    let r = fixplan_worker::run_shard(&prep, 0..0);
                    let merged = fixplan_core::merge(prep.top_k, vec![r]);
                    let done = Finished {
                        prep: Some(Arc::new(prep)),
                        input: source,
                        merged,
                        stopped_at: None,
                    };
                    let _ = tx.send(vec![(i, Ok(done))]);
                    continue;
                }
                let size = opts
                    .shard_size
                    .unwrap_or_else(|| shards::shard_size(target, count, n))
                    .max(1);
                (Some(Arc::new(prep)), shards::ranges(count, size), n)
            }
        };
        let slot = PartSlot {
            digest: digest(&bytes),
            prep,
            source,
            input: Arc::new(bytes),
            shard_ids: 0..0,
            stop: None,
            partials: Vec::new(),
            top: Vec::new(),
            closed: false,
        };
        slots_in.push((i, slot, ranges, segments));
    }
    if slots_in.is_empty() {
        return Ok(Distributed {
            rx,
            ready: VecDeque::new(),
            delivered: 0,
            total,
            runtime: None,
            final_stats: Stats::default(),
        });
    }
    let iox = if opts.transport == TransportChoice::Zenoh {
        None
    } else {
        let stale = iox::remove_stale();
        if !stale.is_empty() {
            info!(
                role = "coordinator",
                "removed the iceoryx2 resources of {} dead runs",
                stale.len()
            );
        }
        Some(fixplan_worker::protocol::DataPath::Iceoryx2 {
            prefix: iox::new_prefix(),
            service: format!(
                "fixplan/{}",
                fixplan_worker::host::sanitize(&opts.key_prefix)
            ),
        })
    };
    let settings = Settings {
        run_id: fixplan_worker::host::unique_name("run"),
        host_id: fixplan_worker::host::host_id(),
        transport: opts.transport,
        iox,
        iox_clients: opts.local_workers.max(iox::DEFAULT_CLIENTS),
        lease: opts.lease,
        min_workers: opts.min_workers,
        verify: opts.verify,
        good_enough: opts.good_enough,
        batch_cost,
    };
    let (core, index) = Scheduler::new(settings, slots_in, tx);
    let core = Arc::new(core);
    let mut zopts = opts.zenoh.clone();
    if zopts.listen.is_empty() && zopts.connect.is_empty() && zopts.config_file.is_none() {
        let sock = std::env::temp_dir().join(format!(
            "{}.sock",
            fixplan_worker::host::unique_name("fixplan")
        ));
        zopts.listen = vec![format!("unixsock-stream/{}", sock.display())];
    }
    let mut rt = Runtime::start(core, Arc::new(index), &zopts, &opts.key_prefix)?;
    if opts.local_workers > 0 {
        let exe = match &opts.worker_exe {
            Some(e) => e.clone(),
            None => std::env::current_exe().map_err(|e| ClusterError::Spawn(e.to_string()))?,
        };
        let connect = zopts
            .listen
            .first()
            .or(zopts.connect.first())
            .map(|e| runtime::connect_for(e))
            .ok_or_else(|| ClusterError::Spawn("no endpoint for the local workers".into()))?;
        let spec = local::LocalSpec {
            exe: &exe,
            connect: &connect,
            key_prefix: &opts.key_prefix,
            transport: &opts.transport.to_string(),
            threads,
            quiet: opts.quiet,
        };
        rt.spawn_local(&spec, opts.local_workers)?;
    }
    Ok(Distributed {
        rx,
        ready: VecDeque::new(),
        delivered: 0,
        total,
        runtime: Some(rt),
        final_stats: Stats::default(),
    })
}
