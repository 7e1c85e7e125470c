//! Worker processes started by the coordinator on its own host
//! (`fixplan run --workers N`), stopped when the run ends, killed if they
//! outstay it, and sent SIGTERM when a signal stops the coordinator
//! ([`crate::interrupt`]): they would otherwise look for it for a
//! while, holding their shards' work.

use fixplan_worker::zenoh_link::TlsFiles;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// The worker processes of a run, killed on drop if still there.
pub struct LocalWorkers {
    children: Vec<Child>,
    /// SIGTERM to each of them if a signal ends the coordinator.
    _on_signal: Option<crate::interrupt::LastWords>,
}

/// What a local worker is started with.
pub struct LocalSpec<'a> {
    /// The `fixplan` executable (this one, unless told otherwise).
    pub exe: &'a Path,
    /// The coordinator's endpoint, as a worker connects to it.
    pub connect: &'a str,
    /// The run's key-expression prefix.
    pub key_prefix: &'a str,
    /// `--transport` of the workers, the coordinator's own.
    pub transport: &'a str,
    /// Enumeration threads of each worker.
    pub threads: usize,
    /// `--quiet`: the run's logging, for the workers too.
    pub quiet: bool,
    /// The coordinator's TLS files, for workers connecting over TLS.
    pub tls: Option<&'a TlsFiles>,
}

impl LocalWorkers {
    /// Starts `n` workers; they leave when the coordinator says the run
    /// is over.
    pub fn spawn(spec: &LocalSpec, count: usize) -> std::io::Result<LocalWorkers> {
        let mut w = LocalWorkers {
            children: Vec::new(),
            _on_signal: None,
        };
        for _ in 0..count {
            let mut c = Command::new(spec.exe);
            c.args([
                "worker",
                "--connect",
                spec.connect,
                "--key-prefix",
                spec.key_prefix,
                "--parent",
                &std::process::id().to_string(),
            ])
            .args([
                "--transport",
                spec.transport,
                "--threads",
                &spec.threads.to_string(),
            ])
            .stdin(Stdio::null());
            if spec.quiet {
                c.arg("--quiet");
            }
            if let Some(t) = spec.tls {
                c.arg("--tls-ca").arg(&t.ca);
                if let Some((cert, key)) = &t.identity {
                    c.arg("--tls-cert").arg(cert).arg("--tls-key").arg(key);
                }
            }
            w.children.push(c.spawn()?);
        }
        let pids: Vec<libc::pid_t> = w
            .children
            .iter()
            .filter_map(|c| c.id().try_into().ok())
            .collect();
        w._on_signal = Some(crate::interrupt::LastWords::say(move || {
            for &pid in &pids {
                // SAFETY: kill only sends a signal; the pids are this
                // process's unreaped children, so none is another's.
                unsafe {
                    libc::kill(pid, libc::SIGTERM);
                }
            }
        }));
        Ok(w)
    }

    /// Waits up to `grace` for the workers to leave, then kills the rest.
    pub fn stop(&mut self, grace: Duration) {
        // Reaped below: their pids may be another process's later.
        self._on_signal = None;
        let until = Instant::now() + grace;
        for c in &mut self.children {
            loop {
                match c.try_wait() {
                    Ok(Some(_)) | Err(_) => break,
                    Ok(None) if Instant::now() >= until => {
                        let _ = c.kill();
                        let _ = c.wait();
                        break;
                    }
                    Ok(None) => std::thread::sleep(Duration::from_millis(2)),
                }
            }
        }
        self.children.clear();
    }
}

impl Drop for LocalWorkers {
    fn drop(&mut self) {
        self.stop(Duration::ZERO);
    }
}
