//! The one way parts get solved: a list of jobs, a backend (threads of this
//! process, or the workers of a cluster), and each part's result handed
//! over in job order, whatever order the parts finish in. `fixplan run`,
//! `fixplan coordinator` and `fixplan study` all go through
//! [`solve_in_order`].

use super::backend::{Backend, PartJob, RemoteFinish};
use super::cluster_jobs::Sink;
use super::journal::Watch;
use super::ordered::Reorder;
use crate::job::{solve_guarded, Solved};
use anyhow::{Context, Result};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{mpsc, Condvar, Mutex};

/// Solves `jobs` on `backend`. `finish(i, solved)` turns job `i`'s result
/// into what the caller keeps (messages, a study row); it runs on the
/// solving threads. `deliver(i, kept)` receives them strictly in job
/// order, on the calling thread; an error from it stops the run and is
/// returned.
pub fn solve_in_order<T: Send>(
    jobs: &[PartJob],
    backend: &Backend,
    finish: impl Fn(usize, Solved) -> T + Sync,
    deliver: impl FnMut(usize, T) -> Result<()>,
) -> Result<()> {
    solve_in_order_finishing(jobs, backend, None, None, finish, deliver)
}

/// [`solve_in_order`] where the cluster's workers may finish jobs
/// themselves: `remote` says what a worker needs to finish job `i`, and
/// such jobs are kept by `remote.keep` instead of `finish` (not always: a
/// job whose result was re-derived here comes solved). On the embedded
/// backend, `watch` is told of every job's solve and may answer a job
/// without solving it or have it solved alone (the run's journal).
pub fn solve_in_order_finishing<T: Send>(
    jobs: &[PartJob],
    backend: &Backend,
    remote: Option<&RemoteFinish<T>>,
    watch: Option<&dyn Watch>,
    finish: impl Fn(usize, Solved) -> T + Sync,
    mut deliver: impl FnMut(usize, T) -> Result<()>,
) -> Result<()> {
    let (tx, rx) = mpsc::channel::<(usize, T)>();
    let abort = AtomicBool::new(false);
    // Parts delivered so far, for the embedded drivers' window.
    let gate = (Mutex::new(0usize), Condvar::new());
    let (cluster, drivers) = match backend {
        Backend::Cluster(c) => (Some(super::cluster_jobs::start(jobs, c, remote)?), None),
        Backend::Embedded { threads } => {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads.unwrap_or_else(crate::job::threads::cores))
                .build()
                .context("cannot start the thread pool")?;
            let drivers = Drivers {
                jobs,
                pool,
                next: AtomicUsize::new(0),
                abort: &abort,
                gate: &gate,
                watch,
            };
            (None, Some(drivers))
        }
    };
    let finish = &finish;
    let mut failure = None;
    let unasked = std::thread::scope(|s| {
        let cluster = cluster.map(|c| {
            let tx = tx.clone();
            s.spawn(move || {
                let send = |i, kept| tx.send((i, kept)).is_ok();
                let sink = Sink {
                    solved: finish,
                    finished: remote.map(|r| r.keep),
                    send: &send,
                };
                c.deliver(jobs, &sink)
            })
        });
        if let Some(d) = &drivers {
            for _ in 0..d.pool.current_num_threads().max(1) {
                let tx = tx.clone();
                s.spawn(move || d.run(&tx, finish));
            }
        }
        drop(tx);
        // However this loop ends (even by a panic), the drivers must not be
        // left waiting at the gate, or the scope would never close.
        let _release = Release(&abort, &gate.1);
        let mut order = Reorder::new(0);
        'recv: for (i, out) in rx.iter() {
            for (i, out) in order.push(i, out) {
                if let Err(e) = deliver(i, out) {
                    failure = Some(e);
                    break 'recv;
                }
                *gate.0.lock().unwrap_or_else(|e| e.into_inner()) = i + 1;
                gate.1.notify_all();
            }
        }
        cluster.map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
    });
    match (failure, unasked) {
        (Some(e), _) => Err(e),
        (None, Some(Err(e))) => Err(e.into()),
        (None, _) => Ok(()),
    }
}

/// Sets the abort flag and wakes the drivers when dropped.
struct Release<'a>(&'a AtomicBool, &'a Condvar);

impl Drop for Release<'_> {
    fn drop(&mut self) {
        self.0.store(true, Ordering::SeqCst);
        self.1.notify_all();
    }
}

/// The embedded backend: threads that each take the next job, solve it on
/// the shared pool (its shards in parallel) and send it on.
struct Drivers<'a, 'j> {
    jobs: &'a [PartJob<'j>],
    pool: rayon::ThreadPool,
    next: AtomicUsize,
    abort: &'a AtomicBool,
    gate: &'a (Mutex<usize>, Condvar),
    watch: Option<&'a dyn Watch>,
}

impl Drivers<'_, '_> {
    /// Parts in flight at once: enough to keep the pool busy on small
    /// parts, few enough that finished parts waiting for a slow one stay
    /// bounded.
    fn window(&self) -> usize {
        2 * self.pool.current_num_threads().max(1) + 2
    }

    /// Whether job `job` must wait, `delivered` jobs being delivered: it
    /// is beyond the window, or a job before it must be solved alone and
    /// is not delivered yet, or it must be solved alone and jobs before it
    /// are not delivered yet.
    fn must_wait(&self, job: usize, delivered: usize) -> bool {
        if job >= delivered + self.window() {
            return true;
        }
        let Some(w) = self.watch else {
            return false;
        };
        (delivered..job).any(|j| w.alone(j)) || (w.alone(job) && delivered < job)
    }

    /// Waits until job `i` may start (within the window of the delivered
    /// ones, alone if it must be); false if the run is aborting.
    fn wait_for_room(&self, job: usize) -> bool {
        let mut delivered = self.gate.0.lock().unwrap_or_else(|e| e.into_inner());
        while self.must_wait(job, *delivered) && !self.abort.load(Ordering::SeqCst) {
            delivered = self
                .gate
                .1
                .wait(delivered)
                .unwrap_or_else(|e| e.into_inner());
        }
        !self.abort.load(Ordering::SeqCst)
    }

    fn run<T: Send>(
        &self,
        tx: &mpsc::Sender<(usize, T)>,
        finish: &(impl Fn(usize, Solved) -> T + Sync),
    ) {
        loop {
            let i = self.next.fetch_add(1, Ordering::SeqCst);
            // A signal stops the run: no more work ([`crate::interrupt`]).
            if i >= self.jobs.len() || crate::interrupt::stopping() || !self.wait_for_room(i) {
                break;
            }
            let job = &self.jobs[i];
            let answered = self.watch.and_then(|w| w.verdict(i));
            let out = match answered {
                Some(solved) => finish(i, solved),
                None => {
                    if let Some(w) = self.watch {
                        w.started(i);
                    }
                    let out = self.pool.install(|| {
                        let solved = solve_guarded(job.ctx, job.part, job.preparation);
                        finish(i, solved)
                    });
                    if let Some(w) = self.watch {
                        w.finished(i);
                    }
                    out
                }
            };
            if tx.send((i, out)).is_err() {
                break;
            }
        }
    }
}
