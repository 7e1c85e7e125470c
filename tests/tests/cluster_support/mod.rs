//! Shared by the cluster_*.rs tests: worker processes that are killed on
//! drop, unique endpoints and key prefixes, a small catalogue, and the
//! embedded reference.
#![allow(dead_code)]
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use fixplan_coordinator::Backend;
use fixplan_coordinator::RunOptions;
use fixplan_coordinator::{ClusterOptions, Distributed, PartInput, TransportChoice};
use fixplan_core::PartialResult;
use fixplan_worker::zenoh_link::ZenohOptions;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

pub const EXE: &str = env!("CARGO_BIN_EXE_fixplan-it");

/// A worker process, killed (SIGKILL) and reaped on drop.
pub struct Proc {
    pub child: Option<Child>,
}

impl Proc {
    pub fn pid(&self) -> u32 {
        self.child.as_ref().map_or(0, |c| c.id())
    }
    pub fn sigkill(&mut self) {
        if let Some(c) = &mut self.child {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
    /// Sends a signal by name (`STOP`, `CONT`, ...) with kill(1).
    pub fn signal(&self, name: &str) {
        let ok = Command::new("kill")
            .args([format!("-{name}"), self.pid().to_string()])
            .status()
            .is_ok_and(|s| s.success());
        assert!(ok, "kill -{name} {}", self.pid());
    }
    /// Waits for the exit (up to `t`), returning the code and stderr.
    pub fn wait_output(&mut self, t: Duration) -> (Option<i32>, String) {
        let Some(mut c) = self.child.take() else {
            return (None, String::new());
        };
        let until = std::time::Instant::now() + t;
        let code = loop {
            if let Ok(Some(s)) = c.try_wait() {
                break s.code();
            }
            if std::time::Instant::now() > until {
                let _ = c.kill();
                let _ = c.wait();
                break None;
            }
            std::thread::sleep(Duration::from_millis(20));
        };
        let mut err = String::new();
        if let Some(mut e) = c.stderr.take() {
            let _ = e.read_to_string(&mut err);
        }
        (code, err)
    }
}

impl Drop for Proc {
    fn drop(&mut self) {
        self.sigkill();
    }
}

/// A free TCP port on loopback (free when asked: tests that use one hold
/// [`serial`]).
pub fn free_port() -> u16 {
    let l = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    l.local_addr().unwrap().port()
}

static N: AtomicUsize = AtomicUsize::new(0);

/// A unique name for this test process and call.
pub fn unique(tag: &str) -> String {
    format!(
        "{tag}-{}-{}",
        std::process::id(),
        N.fetch_add(1, Ordering::SeqCst)
    )
}

/// A coordinator setup on a private unix socket and key prefix.
pub struct Net {
    pub endpoint: String,
    pub prefix: String,
}

impl Net {
    pub fn new(tag: &str) -> Net {
        let sock = std::env::temp_dir().join(format!("fixplan-{}.sock", unique(tag)));
        Net {
            endpoint: format!("unixsock-stream/{}", sock.display()),
            prefix: format!("fxtest/{}", unique(tag)),
        }
    }

    pub fn options(&self, transport: TransportChoice) -> ClusterOptions {
        ClusterOptions {
            zenoh: ZenohOptions {
                listen: vec![self.endpoint.clone()],
                ..ZenohOptions::default()
            },
            key_prefix: self.prefix.clone(),
            transport,
            expected_threads: Some(2),
            ..ClusterOptions::default()
        }
    }

    /// Starts `fixplan worker` with these extra arguments.
    pub fn worker(&self, extra: &[&str]) -> Proc {
        self.worker_via(&self.endpoint, extra, Stdio::inherit())
    }

    /// Same, with its standard error captured.
    pub fn worker_captured(&self, extra: &[&str]) -> Proc {
        self.worker_via(&self.endpoint, extra, Stdio::piped())
    }

    pub fn worker_via(&self, endpoint: &str, extra: &[&str], stderr: Stdio) -> Proc {
        let child = Command::new(EXE)
            .args([
                "worker",
                "--connect",
                endpoint,
                "--key-prefix",
                &self.prefix,
                "--threads",
                "1",
            ])
            .args(extra)
            .stdin(Stdio::null())
            .stderr(stderr)
            .spawn()
            .expect("start fixplan worker");
        Proc { child: Some(child) }
    }
}

pub use fixplan_tests::catalog;

/// The valid parts of [`catalog`] as cluster inputs, with `top_k`.
pub fn inputs(top_k: usize) -> Vec<PartInput> {
    let (cat, spec) = catalog();
    let mut params = spec.params.clone();
    params.top_k = top_k;
    cat.parts
        .iter()
        .filter_map(|cp| cp.part.as_ref().ok())
        .map(|p| PartInput {
            part: p.clone(),
            kit: spec.kit.clone(),
            params: params.clone(),
            units: cat.units,
        })
        .collect()
}

/// The embedded result of each input: `Ok(bytes of the merged partial)` or
/// the prepare error.
pub fn embedded(inputs: &[PartInput]) -> Vec<Result<Vec<u8>, String>> {
    inputs
        .iter()
        .map(|i| {
            i.prepare()
                .map(|p| bytes(&p.enumerate_all()))
                .map_err(|e| e.to_string())
        })
        .collect()
}

pub fn bytes(p: &PartialResult) -> Vec<u8> {
    postcard::to_allocvec(p).unwrap()
}

/// Options of a quiet run of the in-memory catalogue into `out`, on one
/// embedded thread or on `cluster`.
pub fn run_opts(out: &Path, top_k: usize, cluster: Option<ClusterOptions>) -> RunOptions {
    RunOptions {
        catalog: PathBuf::from("mem"),
        kit: "case-kit".into(),
        top_k: Some(top_k),
        full_counts: false,
        output: out.to_path_buf(),
        resume: false,
        shard_size: None,
        quiet: true,
        search: Default::default(),
        backend: match cluster {
            Some(c) => Backend::Cluster(c),
            None => Backend::Embedded { threads: Some(1) },
        },
        arcs: None,
    }
}

/// Every part's merged result (bytes) or error, in input order, whatever
/// order the workers finished them in.
pub fn in_order(d: &mut Distributed) -> Vec<Result<Vec<u8>, String>> {
    let mut got = Vec::new();
    while let Some((i, r)) = d.next_merged() {
        got.push((i, r.map(|m| bytes(&m)).map_err(|e| e.to_string())));
    }
    got.sort_by_key(|(i, _)| *i);
    for (n, (i, _)) in got.iter().enumerate() {
        assert_eq!(n, *i, "every part exactly once");
    }
    got.into_iter().map(|(_, r)| r).collect()
}

/// iceoryx2 files left by runs of this test process.
pub fn shm_left() -> Vec<PathBuf> {
    fixplan_worker::iox::files_left(&format!(
        "{}{}x",
        fixplan_worker::iox::PREFIX_HEAD,
        std::process::id()
    ))
}

static SERIAL: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// One cluster test at a time per test binary: the machine has few cores,
/// and the shared-memory check must not see another test's live run.
pub fn serial() -> std::sync::MutexGuard<'static, ()> {
    SERIAL.lock().unwrap_or_else(|e| e.into_inner())
}
