//! The shards a worker has running on its pool while it asks for more.
//!
//! A worker that ran each assignment to its end before asking again would
//! leave its threads waiting for the assignment's slowest shard, every
//! time (docs/performance.md measures that idle share). So the agent hands each shard to the pool on its own and asks again as soon
//! as no more shards wait for a thread than it has threads, telling the
//! coordinator which shards it still holds (protocol 7,
//! [`crate::protocol::Msg::Report`]).

use crate::protocol::{Outcome, TaskError, TaskFailed};
use std::collections::HashSet;
use std::sync::mpsc::{channel, Receiver, Sender};
use std::time::{Duration, Instant};

/// An outcome and the time its thread spent on it, microseconds.
type Timed = (Outcome, u64);

/// Shards on the pool, the outcomes back from it, and how busy it was.
pub struct InFlight {
    tx: Sender<Timed>,
    rx: Receiver<Timed>,
    running: HashSet<u64>,
    ready: Vec<Outcome>,
    /// Threads of the pool, for the time it was offered.
    threads: u64,
    /// Since when the pool has had shards (none running: `None`).
    since: Option<Instant>,
    /// Time its threads spent on shards, microseconds.
    pub busy_micros: u64,
    /// Its threads times the time it had shards, microseconds.
    pub offered_micros: u64,
}

/// Microseconds since `t`.
fn micros_since(start: Instant) -> u64 {
    u64::try_from(start.elapsed().as_micros()).unwrap_or(u64::MAX)
}

impl InFlight {
    /// Nothing running yet, on a pool of `threads` threads.
    pub fn new(threads: usize) -> InFlight {
        let (tx, rx) = channel();
        InFlight {
            tx,
            rx,
            running: HashSet::new(),
            ready: Vec::new(),
            threads: threads.max(1) as u64,
            since: None,
            busy_micros: 0,
            offered_micros: 0,
        }
    }

    /// Runs `job` (shard `id`) on `pool`. A panic outside the job's own
    /// guards fails that shard alone, as in a whole assignment.
    pub fn spawn(
        &mut self,
        pool: &rayon::ThreadPool,
        id: u64,
        job: impl FnOnce() -> Outcome + Send + 'static,
    ) {
        self.since.get_or_insert_with(Instant::now);
        self.running.insert(id);
        let tx = self.tx.clone();
        pool.spawn(move || {
            let t = Instant::now();
            let out =
                std::panic::catch_unwind(std::panic::AssertUnwindSafe(job)).unwrap_or_else(|p| {
                    Outcome::Failed(TaskFailed {
                        shard_id: id,
                        error: TaskError::Crashed(crate::panic_text(p)),
                    })
                });
            let micros = micros_since(t);
            // A worker that left the run drops what is still running.
            let _ = tx.send((out, micros));
        });
    }

    /// Outcomes known at once (replayed), for the next report.
    pub fn add_ready(&mut self, outcomes: Vec<Outcome>) {
        self.ready.extend(outcomes);
    }

    /// The shards still running, for the next report.
    pub fn holding(&self) -> Vec<u64> {
        let mut v: Vec<u64> = self.running.iter().copied().collect();
        v.sort_unstable();
        v
    }

    /// Whether nothing runs and nothing waits to be reported.
    pub fn is_empty(&self) -> bool {
        self.running.is_empty() && self.ready.is_empty()
    }

    /// What to report next: waits until at most `low` shards run, then
    /// (with `idle`: the coordinator had no work) for one outcome at
    /// most that long, and takes every outcome that is in.
    pub fn take(&mut self, low: usize, idle: Option<Duration>) -> Vec<Outcome> {
        while self.running.len() > low {
            match self.rx.recv() {
                Ok(t) => self.record(t),
                Err(_) => break,
            }
        }
        if let Some(d) = idle {
            if self.ready.is_empty() && !self.running.is_empty() {
                if let Ok(t) = self.rx.recv_timeout(d) {
                    self.record(t);
                }
            }
        }
        while let Ok(t) = self.rx.try_recv() {
            self.record(t);
        }
        std::mem::take(&mut self.ready)
    }

    fn record(&mut self, (out, micros): Timed) {
        self.busy_micros += micros;
        if self.running.remove(&out.shard_id()) && self.running.is_empty() {
            if let Some(t) = self.since.take() {
                self.offered_micros += self.threads * micros_since(t);
            }
        }
        self.ready.push(out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pool(threads: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
    }

    fn failed(id: u64) -> Outcome {
        Outcome::Failed(TaskFailed {
            shard_id: id,
            error: TaskError::MissingInput,
        })
    }

    #[test]
    fn asks_again_once_no_more_run_than_the_low_mark() {
        let pool = pool(2);
        let mut f = InFlight::new(2);
        let (go_tx, go_rx) = channel::<()>();
        let go = std::sync::Arc::new(std::sync::Mutex::new(go_rx));
        // Shard 0 waits for a go; the others end at once.
        let g = go.clone();
        f.spawn(&pool, 0, move || {
            let _ = g.lock().unwrap().recv();
            failed(0)
        });
        for id in 1..5 {
            f.spawn(&pool, id, move || failed(id));
        }
        let first = f.take(1, None);
        let mut ids: Vec<u64> = first.iter().map(Outcome::shard_id).collect();
        ids.sort_unstable();
        assert_eq!(ids, [1, 2, 3, 4]);
        assert_eq!(f.holding(), [0]);
        assert!(!f.is_empty());
        // Nothing more within the idle wait while shard 0 holds.
        assert!(f.take(1, Some(Duration::from_millis(20))).is_empty());
        go_tx.send(()).unwrap();
        let last = f.take(0, None);
        assert_eq!(last.iter().map(Outcome::shard_id).collect::<Vec<_>>(), [0]);
        assert!(f.is_empty());
        assert!(
            f.offered_micros >= f.busy_micros / 2,
            "{}",
            f.offered_micros
        );
    }

    #[test]
    fn a_panicking_job_fails_its_shard_alone() {
        let pool = pool(1);
        let mut f = InFlight::new(1);
        f.spawn(&pool, 7, || panic!("boom"));
        f.spawn(&pool, 8, || failed(8));
        let mut out = f.take(0, None);
        out.sort_by_key(Outcome::shard_id);
        match &out[..] {
            [Outcome::Failed(a), Outcome::Failed(b)] => {
                assert_eq!((a.shard_id, b.shard_id), (7, 8));
                assert_eq!(a.error, TaskError::Crashed("boom".into()));
            }
            other => panic!("{other:?}"),
        }
    }
}
