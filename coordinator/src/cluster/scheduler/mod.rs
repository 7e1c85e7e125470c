//! The coordinator's bookkeeping: the shard queue, leases, workers, and the
//! partial results of each part. Transport-free: every request arrives as
//! bytes through [`Scheduler::handle`] (zenoh queryables and the iceoryx2
//! server call it alike) and the answer goes back as bytes.
//!
//! This file reads a request and dispatches it; `state` holds what the
//! scheduler knows, `tasks` makes a worker's tasks, `assign` hands them
//! out, `results` takes and merges their outcomes, `workers` follows joins, losses, leases and bans, and
//! `errors` says why a request or a result is turned down.

mod assign;
mod budget;
mod errors;
mod results;
mod state;
mod tasks;
#[cfg(test)]
mod tests;
mod workers;

pub use errors::PartFailure;
pub(crate) use state::{Delivery, MergedShards, PlannedPart};
pub use state::{Settings, Stats, WHOLE};

use errors::{NotTaken, Refusal};
use fixplan_worker::protocol::{
    decode, encode, encode_refused, refusal_for, Frame, Join, Msg, Next, Outcome, TaskDone,
    TaskFailed,
};
use state::{State, ROLE};
use std::sync::mpsc::Sender;
use std::sync::{Mutex, MutexGuard};
use std::time::Instant;
use tracing::warn;

/// The shard queue, leases, workers and results of one run, answering
/// the workers' requests. Shared by the transports' threads: one lock
/// around all its state, held for one step of a request at a time.
pub struct Scheduler {
    /// How it serves the workers (read by the transports too).
    pub settings: Settings,
    st: Mutex<State>,
    /// Finished parts go to the consumer in one message per request (a
    /// wake-up per part cost the coordinator more than merging them).
    tx: Mutex<Sender<Vec<Delivery>>>,
}

impl Scheduler {
    /// A scheduler with every shard of `parts` in the queue; finished
    /// parts go to `tx`.
    pub(crate) fn new(
        settings: Settings,
        parts: Vec<PlannedPart>,
        tx: Sender<Vec<Delivery>>,
    ) -> Scheduler {
        let st = State::new(parts, settings.good_enough.is_some());
        Scheduler {
            settings,
            st: Mutex::new(st),
            tx: Mutex::new(tx),
        }
    }

    /// The state. A thread that panicked holding the lock does not stop
    /// the others: the run goes on with the state as that thread left it.
    fn lock(&self) -> MutexGuard<'_, State> {
        self.st.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The run's figures so far.
    pub fn stats(&self) -> Stats {
        self.lock().stats.clone()
    }

    /// Whether every worker still known has been told the run is over.
    pub fn all_told(&self) -> bool {
        self.lock().workers.values().all(|w| w.got_done)
    }

    /// Answers one request. Never panics on input: unreadable frames are
    /// logged and answered with a refusal.
    pub fn handle(&self, bytes: &[u8]) -> Vec<u8> {
        let t0 = super::cpu_time::thread_micros();
        let reply = match decode(bytes) {
            Err(e) => {
                warn!(role = ROLE, "dropped a message: {e}");
                encode_refused(&refusal_for(&e))
            }
            Ok(Frame::Refused(r)) => {
                warn!(role = ROLE, "dropped an unexpected refusal: {r}");
                encode_refused(&Refusal::Unexpected.to_string())
            }
            Ok(Frame::Msg(m)) => {
                let has_results =
                    matches!(&m, Msg::Report { outcomes, .. } if !outcomes.is_empty());
                match self.on_msg(m) {
                    Ok(reply) => self.encode_reply(&reply, has_results, bytes.len()),
                    Err(refusal) => encode_refused(&refusal.to_string()),
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

    /// The reply to a message, or why it is refused.
    fn on_msg(&self, msg: Msg) -> Result<Msg, Refusal> {
        let banned = |w: &str| self.lock().banned.contains(w);
        match msg {
            Msg::Join(j) if banned(&j.worker) => Err(Refusal::Banned(j.worker)),
            Msg::Report { worker, .. } if banned(&worker) => Err(Refusal::Banned(worker)),
            Msg::Join(j) => self.join(j),
            Msg::Report {
                worker,
                outcomes,
                holding,
            } => self.report(&worker, outcomes, &holding),
            other => {
                warn!(
                    role = ROLE,
                    "dropped a message that only a coordinator sends: {}",
                    kind(&other)
                );
                Err(Refusal::Unexpected)
            }
        }
    }

    /// Takes a report's outcomes one by one, then answers with a note for
    /// each outcome not taken and the worker's next work.
    fn report(
        &self,
        worker: &str,
        outcomes: Vec<Outcome>,
        holding: &[u64],
    ) -> Result<Msg, Refusal> {
        let banned = |w: &str| self.lock().banned.contains(w);
        let mut notes = Vec::new();
        for o in outcomes {
            // One bad result and nothing else of this worker counts
            // (its other shards are back in the queue already).
            if banned(worker) {
                break;
            }
            let (id, taken) = match o {
                Outcome::Done(r) => (r.shard_id, self.result(*r, worker)),
                Outcome::Failed(f) => (f.shard_id, self.failed(f, worker)),
            };
            if let Err(note) = taken {
                notes.push(format!("shard {id} not taken: {note}"));
            }
        }
        if banned(worker) {
            return Err(Refusal::Banned(worker.to_string()));
        }
        Ok(Msg::Reply {
            notes,
            next: self.next_work_holding(worker, holding),
        })
    }

    fn join(&self, joining: Join) -> Result<Msg, Refusal> {
        let data = workers::data_path(&self.settings, &joining)?;
        Ok(workers::join(
            &mut self.lock(),
            &self.settings,
            joining,
            data,
        ))
    }

    /// The next assignment of a worker that has just reported and holds
    /// no shard any more.
    #[cfg(test)]
    fn next_work(&self, worker: &str) -> Next {
        self.next_work_holding(worker, &[])
    }

    /// The next assignment of a worker that has just reported and still
    /// works on the shards `holding`.
    fn next_work_holding(&self, worker: &str, holding: &[u64]) -> Next {
        assign::next_work(&mut self.lock(), &self.settings, worker, holding)
    }

    fn result(&self, done: TaskDone, worker: &str) -> Result<(), NotTaken> {
        results::take_result(&mut self.lock(), &self.settings, done, worker)
    }

    fn failed(&self, failure: TaskFailed, worker: &str) -> Result<(), NotTaken> {
        results::take_failure(&mut self.lock(), &self.settings, failure, worker)
    }

    /// A worker's liveliness token vanished: its shards go back to the queue.
    pub fn worker_lost(&self, worker: &str) {
        workers::lost(&mut self.lock(), worker);
    }

    /// Shards whose lease ran out go back to the queue (their worker may
    /// still answer: the first result wins).
    pub fn expire_leases(&self) {
        workers::expire_leases(&mut self.lock(), Instant::now());
    }
}

/// A message's kind, for the log.
fn kind(msg: &Msg) -> &'static str {
    match msg {
        Msg::Join(_) => "join",
        Msg::Welcome(_) => "welcome",
        Msg::Report { .. } => "report",
        Msg::Reply { .. } => "reply",
    }
}
