//! iceoryx2: shard requests and results between processes of one host,
//! through shared memory.
//!
//! One request-response service `SERVICE` (`[u8]` -> `[u8]`, the same
//! frames as over zenoh) with the coordinator as its only server, plus
//! event services for wake-ups: `SERVICE/req` (workers notify, the
//! coordinator listens) and one `SERVICE/resp/<client id>` per worker
//! (its own listener, the coordinator notifies it when its reply is
//! out). One shared response event woke every worker for every reply: its
//! cost grew with the workers (64 sends per reply at 64 workers). A
//! request is encoded straight into a loaned shared-memory slice; replies
//! are decoded in place.
//!
//! Each run gets its own iceoryx2 global prefix (`fxp<pid>x<nonce>_`), so
//! runs and tests never meet; [`remove_stale`] deletes the resources of
//! runs whose coordinator died. Nodes use `SignalHandlingMode::Disabled`:
//! nobody calls `Node::wait`, and SIGTERM/SIGINT keep their default action,
//! so `systemctl stop`, Kubernetes and `kill` stop a worker at once; the
//! coordinator's liveliness and lease handling re-queue its shard.

use crate::protocol::{decode, Frame};
use crate::zenoh_link::LinkError;
use iceoryx2::port::client::Client;
use iceoryx2::port::listener::Listener;
use iceoryx2::port::notifier::Notifier;
use iceoryx2::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

type Ipc = ipc::Service;
/// Worker processes of one host served by shared memory, unless the
/// coordinator starts more itself. iceoryx2 sizes the server's response
/// bookkeeping by this and sweeps all of it when a client leaves, and the
/// sweep costs the coordinator about 45 ms at 256 clients, 3 ms at 16
/// (perf). Workers beyond it fall back to zenoh.
pub const DEFAULT_CLIENTS: usize = 4;
const SLICE_HINT: usize = 4096;
/// Start of every prefix this crate creates.
pub const PREFIX_HEAD: &str = "fxp";

fn err<E: std::fmt::Debug>(step: &'static str) -> impl FnOnce(E) -> LinkError {
    move |e| LinkError::Iceoryx2 {
        step,
        detail: format!("{e:?}"),
    }
}

/// Silences iceoryx2's own logging below errors (it warns about a missing
/// config file otherwise).
pub fn quiet_logs() {
    set_log_level(LogLevel::Error);
}

/// A prefix unique to this process and moment.
pub fn new_prefix() -> String {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.subsec_nanos())
        .unwrap_or(0);
    format!("{PREFIX_HEAD}{}x{:08x}_", std::process::id(), nanos)
}

/// iceoryx2's configuration with the run's global `prefix`: every node of
/// a run (coordinator and workers) must use the same one to meet.
pub fn config(prefix: &str) -> Result<Config, LinkError> {
    let mut c = Config::default();
    c.global.prefix = FileName::new(prefix.as_bytes()).map_err(err("prefix"))?;
    Ok(c)
}

fn node(prefix: &str) -> Result<Node<Ipc>, LinkError> {
    NodeBuilder::new()
        .config(&config(prefix)?)
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<Ipc>()
        .map_err(err("node"))
}

fn name(text: &str) -> Result<ServiceName, LinkError> {
    ServiceName::new(text).map_err(err("service name"))
}

/// The event service that wakes the client `client` of `service` when its
/// reply is out.
fn response_event(service: &str, client: u128) -> Result<ServiceName, LinkError> {
    name(&format!("{service}/resp/{client:032x}"))
}

/// The coordinator's notifiers of its clients' response events, opened at
/// a client's first reply.
struct Wakers<'n> {
    node: &'n Node<Ipc>,
    service: &'n str,
    notifiers: std::collections::HashMap<u128, Notifier<Ipc>>,
}

impl Wakers<'_> {
    /// Wakes `client`. A client whose event cannot be opened (gone) is
    /// not woken: a live one finds its reply at its next poll anyway.
    fn wake(&mut self, client: u128) {
        if !self.notifiers.contains_key(&client) {
            let opened = response_event(self.service, client).and_then(|n| {
                let ev = self
                    .node
                    .service_builder(&n)
                    .event()
                    .open()
                    .map_err(err("open response event"))?;
                ev.notifier_builder().create().map_err(err("notifier"))
            });
            match opened {
                Ok(n) => {
                    self.notifiers.insert(client, n);
                }
                Err(e) => {
                    tracing::debug!(
                        role = "coordinator",
                        "iceoryx2: cannot wake client {client:032x}: {e}"
                    );
                    return;
                }
            }
        }
        if let Some(n) = self.notifiers.get(&client) {
            let _ = n.notify();
        }
    }
}

/// The worker's end.
pub struct IoxClient {
    client: Client<Ipc, [u8], (), [u8], ()>,
    notifier: Notifier<Ipc>,
    listener: Listener<Ipc>,
    // Dropped last: the ports above belong to it.
    _node: Node<Ipc>,
}

impl IoxClient {
    /// Opens the coordinator's services (retrying briefly: an open that
    /// races a dead-node cleanup can fail once).
    pub fn open(prefix: &str, service: &str) -> Result<IoxClient, LinkError> {
        let mut last = None;
        for _ in 0..20 {
            match Self::try_open(prefix, service) {
                Ok(c) => return Ok(c),
                Err(e) => last = Some(e),
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        Err(last.unwrap_or(LinkError::NoReply))
    }

    fn try_open(prefix: &str, service: &str) -> Result<IoxClient, LinkError> {
        let node = node(prefix)?;
        let rr = node
            .service_builder(&name(service)?)
            .request_response::<[u8], [u8]>()
            .open()
            .map_err(err("open request-response service"))?;
        let client = rr
            .client_builder()
            .initial_max_slice_len(SLICE_HINT)
            .allocation_strategy(AllocationStrategy::PowerOfTwo)
            .create()
            .map_err(err("client"))?;
        let req = node
            .service_builder(&name(&format!("{service}/req"))?)
            .event()
            .open()
            .map_err(err("open request event"))?;
        let notifier = req.notifier_builder().create().map_err(err("notifier"))?;
        let resp = node
            .service_builder(&response_event(service, client.id().value())?)
            .event()
            .max_notifiers(1)
            .max_listeners(1)
            .max_nodes(2)
            .create()
            .map_err(err("create response event"))?;
        let listener = resp.listener_builder().create().map_err(err("listener"))?;
        Ok(IoxClient {
            client,
            notifier,
            listener,
            _node: node,
        })
    }

    /// One request, one reply.
    pub fn request(&self, bytes: &[u8], timeout: Duration) -> Result<Frame, LinkError> {
        let req = self
            .client
            .loan_slice_uninit(bytes.len())
            .map_err(err("loan"))?;
        let pending = req.write_from_slice(bytes).send().map_err(err("send"))?;
        self.notifier.notify().map_err(err("notify"))?;
        let deadline = Instant::now() + timeout;
        loop {
            if let Some(resp) = pending.receive().map_err(err("receive"))? {
                return Ok(decode(resp.payload())?);
            }
            let now = Instant::now();
            if now >= deadline || !pending.is_connected() {
                return Err(LinkError::NoReply);
            }
            let wait = (deadline - now).min(Duration::from_millis(20));
            self.listener
                .timed_wait(|_| {}, wait)
                .map_err(err("wait"))?;
        }
    }
}

/// How the coordinator steers its iceoryx2 server thread.
#[derive(Debug, Default)]
pub struct ServeControl {
    /// Return as soon as seen.
    pub stop: AtomicBool,
    /// The run is ending: wait for requests in 1 ms steps instead of 100,
    /// so that `stop` is seen at once (nothing else can wake the thread).
    pub closing: AtomicBool,
    /// A worker vanished: sweep dead nodes.
    pub cleanup: AtomicBool,
}

/// The coordinator's end: serves requests of up to `max_clients` workers
/// until `ctl.stop`, answering each with `handle(request bytes)`.
pub fn serve(
    prefix: &str,
    service: &str,
    max_clients: usize,
    ready: impl FnOnce(),
    ctl: &ServeControl,
    mut handle: impl FnMut(&[u8]) -> Vec<u8>,
) -> Result<(), LinkError> {
    let max_clients = max_clients.max(1);
    let node = node(prefix)?;
    let rr = node
        .service_builder(&name(service)?)
        .request_response::<[u8], [u8]>()
        .max_clients(max_clients)
        .max_servers(1)
        .max_nodes(max_clients + 2)
        .max_active_requests_per_client(2)
        .max_response_buffer_size(2)
        .create()
        .map_err(err("create request-response service"))?;
    let server = rr
        .server_builder()
        .initial_max_slice_len(SLICE_HINT)
        .allocation_strategy(AllocationStrategy::PowerOfTwo)
        .create()
        .map_err(err("server"))?;
    let req = node
        .service_builder(&name(&format!("{service}/req"))?)
        .event()
        .max_notifiers(max_clients)
        .max_listeners(1)
        .max_nodes(max_clients + 2)
        .create()
        .map_err(err("create request event"))?;
    let listener = req.listener_builder().create().map_err(err("listener"))?;
    let mut wakers = Wakers {
        node: &node,
        service,
        notifiers: Default::default(),
    };
    let mut answered = Vec::new();
    ready();
    while !ctl.stop.load(Ordering::SeqCst) {
        if ctl.cleanup.swap(false, Ordering::SeqCst) {
            // Reopened at the next reply: a gone worker's event is let go.
            wakers.notifiers.clear();
            node.try_cleanup_dead_nodes();
        }
        // Idle wake-ups cost ~40 us each (perf), so wait long while the run
        // goes on: requests wake the thread anyway, and the last reports of
        // a run (answered `Done`) come after `closing` is set.
        let wait = if ctl.closing.load(Ordering::SeqCst) {
            Duration::from_millis(1)
        } else {
            Duration::from_millis(100)
        };
        listener.timed_wait(|_| {}, wait).map_err(err("wait"))?;
        while let Some(active) = server.receive().map_err(err("receive"))? {
            let reply = handle(active.payload());
            answered.push(active.origin().value());
            match active.loan_slice_uninit(reply.len()) {
                Ok(r) => {
                    if let Err(e) = r.write_from_slice(&reply).send() {
                        tracing::warn!(
                            role = "coordinator",
                            "iceoryx2: cannot send a reply: {e:?}"
                        );
                    }
                }
                Err(e) => {
                    tracing::warn!(role = "coordinator", "iceoryx2: cannot loan a reply: {e:?}");
                }
            }
        }
        answered.sort_unstable();
        answered.dedup();
        for client in answered.drain(..) {
            wakers.wake(client);
        }
    }
    Ok(())
}

/// Paths of the files iceoryx2 keeps for the prefixes of this crate:
/// `/dev/shm/fxp*` and `<iceoryx2 root>/**/fxp*`.
fn our_files() -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    let root = Config::default().global.root_path().to_string();
    let mut dirs = vec![
        std::path::PathBuf::from("/dev/shm"),
        std::path::PathBuf::from(root),
    ];
    while let Some(d) = dirs.pop() {
        let Ok(rd) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in rd.flatten() {
            let p = e.path();
            if e.file_type().map(|t| t.is_dir()).unwrap_or(false) && !d.starts_with("/dev/shm") {
                dirs.push(p);
            } else if e.file_name().to_string_lossy().starts_with(PREFIX_HEAD) {
                out.push(p);
            }
        }
    }
    out
}

/// The prefix a file belongs to, and its creator's pid.
fn prefix_of(file_name: &str) -> Option<(String, u32)> {
    let rest = file_name.strip_prefix(PREFIX_HEAD)?;
    let x = rest.find('x')?;
    let pid: u32 = rest[..x].parse().ok()?;
    let us = rest.find('_')?;
    Some((file_name[..PREFIX_HEAD.len() + us + 1].to_string(), pid))
}

/// Removes the iceoryx2 resources of one prefix: dead nodes through
/// iceoryx2's own cleanup, then any file left with that prefix.
pub fn remove_prefix(prefix: &str) {
    if let Ok(cfg) = config(prefix) {
        let _ = Node::<Ipc>::list(&cfg, |state| {
            if let NodeState::Dead(view) = state {
                let _ = view.try_remove_stale_resources();
            }
            CallbackProgression::Continue
        });
    }
    for p in our_files() {
        let n = p
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        if n.starts_with(prefix) {
            let _ = std::fs::remove_file(&p);
        }
    }
}

/// Removes the resources of runs whose coordinator process is gone.
/// Returns the prefixes cleaned.
pub fn remove_stale() -> Vec<String> {
    let mut stale = std::collections::BTreeSet::new();
    for p in our_files() {
        let n = p
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        if let Some((prefix, pid)) = prefix_of(&n) {
            if !std::path::Path::new(&format!("/proc/{pid}")).exists() {
                stale.insert(prefix);
            }
        }
    }
    for p in &stale {
        remove_prefix(p);
    }
    stale.into_iter().collect()
}

/// Whether any file of `prefix` is left (for tests).
pub fn files_left(prefix: &str) -> Vec<std::path::PathBuf> {
    our_files()
        .into_iter()
        .filter(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with(prefix))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    #[test]
    fn prefix_parse() {
        assert_eq!(
            super::prefix_of("fxp123xdeadbeef_iox2_abc"),
            Some(("fxp123xdeadbeef_".into(), 123))
        );
        assert_eq!(super::prefix_of("iox2_abc"), None);
    }
}
