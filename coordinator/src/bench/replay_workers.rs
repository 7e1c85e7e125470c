//! The simulated workers of `fixplan bench-coordinator`: worker agents
//! that answer every shard from recorded results ([`Replay`]). By default
//! they run in a process of their own (`fixplan bench-coordinator
//! --serve-replay`, started by the measurement), so that the coordinator's
//! CPU is its process's: in one process, the workers' zenoh sessions run
//! on the coordinator's zenoh threads and their work cannot be told
//! apart. `--in-process` keeps them in the coordinator's process (one
//! `perf record` for both sides).

use super::replay::Replay;
use crate::cluster::cpu_time::{process_micros, thread_micros};
use crate::cluster::TransportChoice;
use crate::run::finish::RunFinisher;
use anyhow::{bail, Context, Result};
use fixplan_worker::agent::{run_worker, WorkerOptions};
use fixplan_worker::zenoh_link::ZenohOptions;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Where run `round` of a measurement listens and names its keys: each
/// run its own, so that nothing of the last run is in the way.
pub fn round_endpoint(base: &Path, prefix: &str, round: usize) -> (PathBuf, String) {
    let mut sock = base.as_os_str().to_owned();
    sock.push(format!("-{round}.sock"));
    (PathBuf::from(sock), format!("{prefix}-{round}"))
}

/// Starts `count` simulated workers of `threads` threads once the coordinator
/// listens on `sock`; each returns its agent thread's CPU time in
/// microseconds.
pub fn start_workers(
    count: usize,
    threads: usize,
    sock: PathBuf,
    prefix: &str,
    transport: TransportChoice,
    replay: &Arc<Replay>,
) -> JoinHandle<Vec<u64>> {
    let (prefix, replay) = (prefix.to_string(), replay.clone());
    std::thread::spawn(move || {
        let until = Instant::now() + Duration::from_secs(30);
        while std::os::unix::net::UnixStream::connect(&sock).is_err() && Instant::now() < until {
            std::thread::sleep(Duration::from_millis(1));
        }
        let ep = format!("unixsock-stream/{}", sock.display());
        let agents: Vec<_> = (0..count)
            .map(|i| {
                let opts = WorkerOptions {
                    zenoh: ZenohOptions {
                        connect: vec![ep.clone()],
                        ..ZenohOptions::default()
                    },
                    key_prefix: prefix.clone(),
                    threads: Some(threads),
                    transport,
                    name: Some(format!("replay-{i}")),
                    runner: replay.clone(),
                    finisher: Some(Arc::new(RunFinisher)),
                    ..WorkerOptions::default()
                };
                std::thread::Builder::new()
                    .name(format!("replay-{i}"))
                    .spawn(move || {
                        if let Err(e) = run_worker(opts) {
                            eprintln!("simulated worker {i}: {e}");
                        }
                        thread_micros()
                    })
            })
            .collect();
        agents
            .into_iter()
            .flatten()
            .map(|t| t.join().unwrap_or(0))
            .collect()
    })
}

/// What the simulated workers did in one run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Served {
    /// Shards replayed and shards enumerated.
    pub replayed: (u64, u64),
    /// The workers' process CPU over the run, microseconds.
    pub cpu_micros: u64,
}

const SERVED: &str = "served";

/// `fixplan bench-coordinator --serve-replay BASE`: `rounds` runs of
/// `workers` (count, threads each) simulated workers, run `r` joining the
/// coordinator at
/// [`round_endpoint`]`(BASE, prefix, r)`, one [`Replay`] for all (the
/// first run records, the next replay). Prints one line per run.
pub fn serve_main(
    base: &Path,
    prefix: &str,
    (n, threads): (usize, usize),
    transport: TransportChoice,
    rounds: usize,
) -> Result<()> {
    let replay = Arc::new(Replay::default());
    for round in 0..rounds {
        let (sock, prefix) = round_endpoint(base, prefix, round);
        let (h0, m0) = replay.counts();
        let cpu0 = process_micros();
        let workers = start_workers(n, threads, sock, &prefix, transport, &replay);
        if workers.join().is_err() {
            bail!("the simulated workers of run {round} panicked");
        }
        let (h1, m1) = replay.counts();
        let cpu = process_micros().saturating_sub(cpu0);
        println!("{SERVED} {} {} {cpu}", h1 - h0, m1 - m0);
    }
    Ok(())
}

/// A process of simulated workers serving the runs of one measurement.
/// Dropped before [`WorkerProcess::finish`] (the measurement failed), it
/// is killed.
pub struct WorkerProcess {
    child: Option<Child>,
}

impl WorkerProcess {
    /// Starts this executable as `rounds` runs of `workers` (count,
    /// threads each) simulated workers.
    pub fn spawn(
        base: &Path,
        prefix: &str,
        (n, threads): (usize, usize),
        transport: TransportChoice,
        rounds: usize,
    ) -> Result<WorkerProcess> {
        let exe = std::env::current_exe().context("finding this executable")?;
        let mut cmd = Command::new(exe);
        if std::env::var_os("RUST_LOG").is_none() {
            // Not zenoh's link retries when the coordinator closes at the
            // end of each run: that is the measurement ending, not news.
            cmd.env("RUST_LOG", "error");
        }
        let child = cmd
            .arg("bench-coordinator")
            .arg("--serve-replay")
            .arg(base)
            .args(["--prefix", prefix])
            .args(["--simulated-workers", &n.to_string()])
            .args(["--threads-per-worker", &threads.to_string()])
            .args(["--transport", &transport.to_string()])
            .args(["--rounds", &rounds.to_string()])
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .spawn()
            .context("starting the simulated workers' process")?;
        Ok(WorkerProcess { child: Some(child) })
    }

    /// Waits for the process to end: what its workers did in each run.
    pub fn finish(mut self) -> Result<Vec<Served>> {
        let Some(mut child) = self.child.take() else {
            bail!("the simulated workers' process is gone");
        };
        let mut out = String::new();
        if let Some(mut o) = child.stdout.take() {
            o.read_to_string(&mut out)
                .context("reading the simulated workers' report")?;
        }
        let status = child.wait().context("waiting for the simulated workers")?;
        if !status.success() {
            bail!("the simulated workers' process failed ({status})");
        }
        out.lines().map(parse_served).collect()
    }
}

impl Drop for WorkerProcess {
    fn drop(&mut self) {
        if let Some(mut c) = self.child.take() {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

fn parse_served(line: &str) -> Result<Served> {
    let nums: Vec<u64> = line
        .strip_prefix(SERVED)
        .map(|rest| {
            rest.split_whitespace()
                .filter_map(|w| w.parse().ok())
                .collect()
        })
        .unwrap_or_default();
    match nums[..] {
        [hits, misses, cpu_micros] => Ok(Served {
            replayed: (hits, misses),
            cpu_micros,
        }),
        _ => bail!("unexpected line from the simulated workers: {line:?}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reports_read_back_and_rounds_get_their_own_endpoints() {
        assert_eq!(
            parse_served("served 12 3 4500").expect("a report"),
            Served {
                replayed: (12, 3),
                cpu_micros: 4500
            }
        );
        assert!(parse_served("served 12").is_err());
        assert!(parse_served("hello").is_err());
        let base = Path::new("/tmp/ceiling-x");
        let (s0, p0) = round_endpoint(base, "p", 0);
        let (s1, p1) = round_endpoint(base, "p", 1);
        assert_eq!(s0, Path::new("/tmp/ceiling-x-0.sock"));
        assert_ne!((s0, p0), (s1, p1));
    }
}
