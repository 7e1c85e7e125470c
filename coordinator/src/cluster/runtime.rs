//! The coordinator's moving parts around [`Scheduler`]: the zenoh session with
//! its queryables (`P/join`, `P/work`), the liveliness subscriber
//! (`P/alive/*`) and token (`P/coordinator`), the lease timer, the iceoryx2
//! server thread, and the local workers. Stopping it tells the workers the
//! run is over, then removes the run's shared memory.

use super::local::{LocalSpec, LocalWorkers};
use super::scheduler::Scheduler;
use fixplan_worker::iox;
use fixplan_worker::protocol::DataPath;
use fixplan_worker::zenoh_link::{open, Keys, ZenohOptions};
use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};
use tracing::warn;
use zenoh::sample::SampleKind;
use zenoh::Wait;

use super::options::ClusterError;

pub struct Runtime {
    pub core: Arc<Scheduler>,
    ctl: Arc<iox::ServeControl>,
    threads: Vec<JoinHandle<()>>,
    session: zenoh::Session,
    iox_prefix: Option<String>,
    pub local: Option<LocalWorkers>,
    _keep: Vec<Box<dyn std::any::Any + Send>>,
}

const ROLE: &str = "coordinator";

/// The endpoint a local worker connects to for a listen endpoint.
pub fn connect_for(listen: &str) -> String {
    listen
        .replace("0.0.0.0", "127.0.0.1")
        .replace("[::]", "[::1]")
}

impl Runtime {
    pub fn start(
        core: Arc<Scheduler>,
        part_index: Arc<Vec<usize>>,
        zopts: &ZenohOptions,
        key_prefix: &str,
    ) -> Result<Runtime, ClusterError> {
        let keys = Keys::new(key_prefix);
        let ctl = Arc::new(iox::ServeControl::default());
        let mut threads = Vec::new();
        let mut iox_prefix = None;
        // iceoryx2 first: a worker may be told about it as soon as zenoh is up.
        if let Some(DataPath::Iceoryx2 { prefix, service }) = core.settings.iox.clone() {
            let (ready_tx, ready_rx) = std::sync::mpsc::channel::<Result<(), String>>();
            let (c, ct, pi) = (core.clone(), ctl.clone(), part_index.clone());
            let p2 = prefix.clone();
            threads.push(std::thread::spawn(move || {
                let ready_tx2 = ready_tx.clone();
                let r = iox::serve(
                    &p2,
                    &service,
                    c.settings.iox_clients,
                    move || drop(ready_tx2.send(Ok(()))),
                    &ct,
                    |b| c.handle(b, &pi),
                );
                if let Err(e) = r {
                    let _ = ready_tx.send(Err(e.to_string()));
                    warn!(role = ROLE, "iceoryx2 server stopped: {e}");
                }
            }));
            match ready_rx.recv_timeout(Duration::from_secs(10)) {
                Ok(Ok(())) => {}
                Ok(Err(e)) => return Err(ClusterError::Iceoryx2(e)),
                Err(_) => return Err(ClusterError::Iceoryx2("the server did not start".into())),
            }
            iox_prefix = Some(prefix);
        }
        let session = open(zopts)?;
        let zerr = |e: zenoh::Error| ClusterError::Zenoh(e.to_string());
        let mut keep: Vec<Box<dyn std::any::Any + Send>> = Vec::new();
        // Callbacks, not polling threads: a query is answered on zenoh's
        // own thread as soon as it arrives, and nothing has to notice the
        // stop flag at the end of the run (undeclaring is enough).
        for key in [keys.join(), keys.work()] {
            let (c, pi) = (core.clone(), part_index.clone());
            let q = session
                .declare_queryable(&key)
                .callback(move |query| {
                    let bytes = query
                        .payload()
                        .map(|p| p.to_bytes().into_owned())
                        .unwrap_or_default();
                    let reply = c.handle(&bytes, &pi);
                    if let Err(e) = query.reply(query.key_expr().clone(), reply).wait() {
                        warn!(role = ROLE, "cannot reply on {}: {e}", query.key_expr());
                    }
                })
                .wait()
                .map_err(zerr)?;
            keep.push(Box::new(q));
        }
        let c = core.clone();
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
            .map_err(zerr)?;
        keep.push(Box::new(sub));
        let token = session
            .liveliness()
            .declare_token(keys.coordinator())
            .wait()
            .map_err(zerr)?;
        keep.push(Box::new(token));
        let (c, ct) = (core.clone(), ctl.clone());
        threads.push(std::thread::spawn(move || {
            while !ct.stop.load(Ordering::SeqCst) {
                c.expire_leases();
                // Woken early by `shutdown` (unpark), so stopping costs no wait.
                std::thread::park_timeout(Duration::from_millis(100));
            }
        }));
        Ok(Runtime {
            core,
            ctl,
            threads,
            session,
            iox_prefix,
            local: None,
            _keep: keep,
        })
    }

    pub fn spawn_local(&mut self, spec: &LocalSpec, n: usize) -> Result<(), ClusterError> {
        if n > 0 {
            self.local =
                Some(LocalWorkers::spawn(spec, n).map_err(|e| ClusterError::Spawn(e.to_string()))?);
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
        while !self.core.all_told() && Instant::now() < until {
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
