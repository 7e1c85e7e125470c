//! The coordinator's moving parts around [`Scheduler`]: the zenoh session with
//! its queryables (`P/join`, `P/work`), the liveliness subscriber
//! (`P/alive/*`) and token (`P/coordinator`), the lease timer, the iceoryx2
//! server thread, and the local workers. Stopping it tells the workers the
//! run is over, then removes the run's shared memory.

use super::local::{LocalSpec, LocalWorkers};
use super::options::ClusterError;
use super::scheduler::Scheduler;
use fixplan_worker::iox;
use fixplan_worker::protocol::DataPath;
use fixplan_worker::zenoh_link::{open, Keys, ZenohOptions};
use std::any::Any;
use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};
use tracing::warn;
use zenoh::sample::SampleKind;
use zenoh::Wait;

/// A zenoh declaration, alive as long as it is kept.
type Declared = Box<dyn Any + Send>;

/// A running coordinator: the scheduler served over zenoh (and iceoryx2),
/// until [`Runtime::shutdown`] or drop.
pub struct Runtime {
    /// What the transports serve; its figures outlive the run.
    pub scheduler: Arc<Scheduler>,
    ctl: Arc<iox::ServeControl>,
    threads: Vec<JoinHandle<()>>,
    session: zenoh::Session,
    iox_prefix: Option<String>,
    /// `--workers N`: the processes it started, stopped with the run.
    pub local: Option<LocalWorkers>,
    _keep: Vec<Declared>,
}

const ROLE: &str = "coordinator";

/// The endpoint a local worker connects to for a listen endpoint.
pub fn connect_for(listen: &str) -> String {
    listen
        .replace("0.0.0.0", "127.0.0.1")
        .replace("[::]", "[::1]")
}

impl Runtime {
    /// Serves `scheduler`: the iceoryx2 server first (a worker may be told
    /// about it as soon as zenoh is up), then the zenoh queryables, the
    /// liveliness of the workers and of the coordinator, the lease timer.
    pub fn start(
        scheduler: Arc<Scheduler>,
        zopts: &ZenohOptions,
        key_prefix: &str,
    ) -> Result<Runtime, ClusterError> {
        let keys = Keys::new(key_prefix);
        let ctl = Arc::new(iox::ServeControl::default());
        let mut threads = Vec::new();
        let mut iox_prefix = None;
        if let Some(DataPath::Iceoryx2 { prefix, service }) = scheduler.settings.iox.clone() {
            threads.push(serve_iox(&scheduler, &ctl, &prefix, service)?);
            iox_prefix = Some(prefix);
        }
        let session = open(zopts)?;
        let mut keep = serve_zenoh(&session, &keys, &scheduler)?;
        keep.push(watch_workers(&session, &keys, &scheduler, &ctl)?);
        let token = session
            .liveliness()
            .declare_token(keys.coordinator())
            .wait()
            .map_err(ClusterError::Zenoh)?;
        keep.push(Box::new(token));
        threads.push(lease_timer(scheduler.clone(), ctl.clone()));
        Ok(Runtime {
            scheduler,
            ctl,
            threads,
            session,
            iox_prefix,
            local: None,
            _keep: keep,
        })
    }

    /// Starts `n` local worker processes as `spec` says.
    pub fn spawn_local(&mut self, spec: &LocalSpec, count: usize) -> Result<(), ClusterError> {
        if count > 0 {
            self.local = Some(LocalWorkers::spawn(spec, count).map_err(ClusterError::Spawn)?);
        }
        Ok(())
    }

    /// Tells the workers the run is over (within `grace`), then stops.
    pub fn shutdown(&mut self, grace: Duration) {
        if self.ctl.stop.load(Ordering::SeqCst) {
            return;
        }
        self.ctl.closing.store(true, Ordering::SeqCst);
        let until = Instant::now() + grace;
        while !self.scheduler.all_told() && Instant::now() < until {
            std::thread::sleep(Duration::from_millis(2));
        }
        if let Some(l) = &mut self.local {
            l.stop(
                until
                    .saturating_duration_since(Instant::now())
                    .max(Duration::from_millis(500)),
            );
        }
        self.ctl.stop.store(true, Ordering::SeqCst);
        for t in &self.threads {
            t.thread().unpark();
        }
        for t in self.threads.drain(..) {
            let _ = t.join();
        }
        self._keep.clear();
        let _ = self.session.close().wait();
        if let Some(p) = &self.iox_prefix {
            iox::remove_prefix(p);
        }
    }
}

impl Drop for Runtime {
    fn drop(&mut self) {
        self.shutdown(Duration::from_millis(500));
    }
}

/// The iceoryx2 server thread, once it is up.
fn serve_iox(
    scheduler: &Arc<Scheduler>,
    ctl: &Arc<iox::ServeControl>,
    prefix: &str,
    service: String,
) -> Result<JoinHandle<()>, ClusterError> {
    let (ready_tx, ready_rx) = std::sync::mpsc::channel();
    let (c, ct) = (scheduler.clone(), ctl.clone());
    let p2 = prefix.to_string();
    let thread = std::thread::spawn(move || {
        let ready_tx2 = ready_tx.clone();
        let r = iox::serve(
            &p2,
            &service,
            c.settings.iox_clients,
            move || drop(ready_tx2.send(Ok(()))),
            &ct,
            |b| c.handle(b),
        );
        if let Err(e) = r {
            warn!(role = ROLE, "iceoryx2 server stopped: {e}");
            let _ = ready_tx.send(Err(e));
        }
    });
    match ready_rx.recv_timeout(Duration::from_secs(10)) {
        Ok(Ok(())) => Ok(thread),
        Ok(Err(e)) => Err(ClusterError::Iceoryx2(e)),
        Err(_) => Err(ClusterError::Iceoryx2Timeout),
    }
}

/// The queryables workers join and report on. Callbacks, not polling
/// threads: a query is answered on zenoh's own thread as soon as it
/// arrives, and nothing has to notice the stop flag at the end of the run
/// (undeclaring is enough).
fn serve_zenoh(
    session: &zenoh::Session,
    keys: &Keys,
    scheduler: &Arc<Scheduler>,
) -> Result<Vec<Declared>, ClusterError> {
    let mut keep: Vec<Declared> = Vec::new();
    for key in [keys.join(), keys.work()] {
        let c = scheduler.clone();
        let q = session
            .declare_queryable(&key)
            .callback(move |query| {
                let bytes = query
                    .payload()
                    .map(|p| p.to_bytes().into_owned())
                    .unwrap_or_default();
                let reply = c.handle(&bytes);
                if let Err(e) = query.reply(query.key_expr().clone(), reply).wait() {
                    warn!(role = ROLE, "cannot reply on {}: {e}", query.key_expr());
                }
            })
            .wait()
            .map_err(ClusterError::Zenoh)?;
        keep.push(Box::new(q));
    }
    Ok(keep)
}

/// The workers' liveliness: a worker whose token vanishes is lost (its
/// shards go back to the queue, its shared memory is cleaned up).
fn watch_workers(
    session: &zenoh::Session,
    keys: &Keys,
    scheduler: &Arc<Scheduler>,
    ctl: &Arc<iox::ServeControl>,
) -> Result<Declared, ClusterError> {
    let c = scheduler.clone();
    let ct = ctl.clone();
    let alive_prefix = format!("{}/alive/", keys.prefix);
    let sub = session
        .liveliness()
        .declare_subscriber(keys.alive_all())
        .history(true)
        .callback(move |sample| {
            if sample.kind() == SampleKind::Delete {
                let k = sample.key_expr().as_str();
                c.worker_lost(k.strip_prefix(&alive_prefix).unwrap_or(k));
                ct.cleanup.store(true, Ordering::SeqCst);
            }
        })
        .wait()
        .map_err(ClusterError::Zenoh)?;
    Ok(Box::new(sub))
}

/// The thread that puts shards whose lease ran out back in the queue.
fn lease_timer(scheduler: Arc<Scheduler>, ctl: Arc<iox::ServeControl>) -> JoinHandle<()> {
    std::thread::spawn(move || {
        while !ctl.stop.load(Ordering::SeqCst) {
            scheduler.expire_leases();
            // Woken early by `shutdown` (unpark), so stopping costs no wait.
            std::thread::park_timeout(Duration::from_millis(100));
        }
    })
}
