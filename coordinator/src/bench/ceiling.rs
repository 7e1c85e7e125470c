//! `fixplan bench-coordinator`: the coordinator's ceiling. Simulated
//! workers ([`super::replay_workers`]) answer every shard at once with its
//! real result, computed beforehand ([`Replay`]), over the transport a real
//! run uses (join over zenoh on a unix socket, shards over iceoryx2 or
//! zenoh); the coordinator is the real `fixplan run --workers` path
//! ([`run_catalog`] with a cluster backend), results file included. So
//! the run's time and CPU are the coordinator's own work.
//!
//! Per count of simulated workers: a warm-up run (the same run, whose
//! shards are enumerated once and recorded, and whose cut parts are
//! finished and recorded) then the measured run, in which every shard and
//! every finishing is replayed. The coordinator's CPU is this process's
//! CPU time over the measured run; with `--in-process` (workers in this
//! process), minus the simulated workers' threads' (what their zenoh
//! sessions do on zenoh's shared threads then counts as the
//! coordinator's).

use super::replay::Replay;
use super::replay_workers::{round_endpoint, serve_main, start_workers, WorkerProcess};
use crate::cluster::cpu_time::{monotonic_micros, process_micros};
use crate::cluster::{ClusterOptions, TransportChoice, VerifyPolicy};
use crate::job::SearchOptions;
use crate::run::backend::Backend;
use crate::run::{run_catalog, RunOptions};
use anyhow::{bail, Context, Result};
use fixplan_catalog::{load_catalog, load_kit, Catalog, KitSpec};
use fixplan_worker::host::unique_name;
use fixplan_worker::zenoh_link::ZenohOptions;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// `fixplan bench-coordinator` options.
#[derive(clap::Args, Debug, Clone)]
pub struct CeilingArgs {
    /// The catalogue (default: the sample catalogue).
    #[arg(long, value_name = "DIR|catalog.toml")]
    pub catalog: Option<PathBuf>,
    /// The kit.
    #[arg(long, default_value = "metric-25")]
    pub kit: String,
    /// The catalogue this many times over (more parts, steadier figures).
    #[arg(long, default_value_t = 50)]
    pub repeat: usize,
    /// Simulated workers of each measurement (one thread each), e.g.
    /// `1,8,64`.
    #[arg(long, value_delimiter = ',', default_value = "1,8,64")]
    pub simulated_workers: Vec<usize>,
    /// Threads of each simulated worker (as `fixplan worker --threads`):
    /// a few workers of many threads against many of one.
    #[arg(long, default_value_t = 1)]
    pub threads_per_worker: usize,
    /// The simulated workers' transport, as `fixplan worker --transport`.
    #[arg(long, default_value = "auto")]
    pub transport: TransportChoice,
    /// How much of each result the coordinator re-derives: `sample`,
    /// `all`, or `1/N` (as `fixplan run --verify`).
    #[arg(long, value_name = "sample|all|1/N", default_value = "sample")]
    pub verify: VerifyPolicy,
    /// Keep the results files in this directory (`replay-N.mcap`); by
    /// default they go to a temporary directory, removed at the end.
    #[arg(long, value_name = "DIR")]
    pub keep: Option<PathBuf>,
    /// Run the simulated workers in this process rather than in one of
    /// their own: one `perf record` sees both sides, but the workers'
    /// zenoh sessions then share the coordinator's zenoh threads, whose
    /// CPU counts as the coordinator's.
    #[arg(long)]
    pub in_process: bool,
    /// Be the simulated workers of another measurement, joining at
    /// `BASE-R.sock` for its run R (started by the measurement itself).
    #[arg(long, value_name = "BASE", hide = true)]
    pub serve_replay: Option<PathBuf>,
    /// With `--serve-replay`: the measurement's key prefix.
    #[arg(long, hide = true, default_value = "")]
    pub prefix: String,
    /// With `--serve-replay`: how many runs to serve.
    #[arg(long, hide = true, default_value_t = 2)]
    pub rounds: usize,
}

impl CeilingArgs {
    /// Threads of each simulated worker (0 taken as 1).
    fn worker_threads(&self) -> usize {
        self.threads_per_worker.max(1)
    }
}

/// One run's figures.
#[derive(Debug, Clone)]
pub struct Ceiling {
    /// Simulated workers.
    pub workers: usize,
    /// Parts written.
    pub parts: usize,
    /// Start of the run to its end (workers gone, file renamed), seconds.
    pub wall: f64,
    /// This process's CPU over the run, seconds.
    pub process_cpu: f64,
    /// The simulated workers' threads' CPU, seconds.
    pub workers_cpu: f64,
    /// Shards replayed and shards enumerated during the run.
    pub replayed: (u64, u64),
    /// The run's start and end, monotonic clock microseconds (for `perf
    /// report --time`).
    pub window: (u64, u64),
}

impl Ceiling {
    /// The coordinator's CPU over the run, seconds.
    pub fn coordinator_cpu(&self) -> f64 {
        (self.process_cpu - self.workers_cpu).max(0.0)
    }
}

/// The catalogue `count` times over (the same entries again: the same ids).
fn repeated(cat: &Catalog, count: usize) -> Catalog {
    let mut c = cat.clone();
    c.parts = (0..count.max(1)).flat_map(|_| cat.parts.clone()).collect();
    c
}

/// The options of a cluster run of `catalog` for `workers` one-thread workers
/// joining at `sock` under `prefix`, writing `output`.
fn run_options(
    catalog: &Catalog,
    args: &CeilingArgs,
    workers: usize,
    sock: &Path,
    prefix: &str,
    output: &Path,
) -> RunOptions {
    let copts = ClusterOptions {
        zenoh: ZenohOptions {
            listen: vec![format!("unixsock-stream/{}", sock.display())],
            ..ZenohOptions::default()
        },
        key_prefix: prefix.to_string(),
        transport: args.transport,
        min_workers: workers,
        expected_threads: Some(workers * args.worker_threads()),
        worker_threads: Some(args.worker_threads()),
        iox_clients: Some(workers),
        quiet: true,
        verify: args.verify,
        ..ClusterOptions::default()
    };
    RunOptions {
        catalog: catalog.source.clone(),
        kit: args.kit.clone(),
        top_k: None,
        full_counts: false,
        output: output.to_path_buf(),
        resume: false,
        shard_size: None,
        quiet: true,
        search: SearchOptions::default(),
        backend: Backend::Cluster(copts),
        arcs: None,
    }
}

/// One coordinator run, its workers started elsewhere: the figures of
/// [`Ceiling`] but the workers'.
fn coordinate(
    catalog: &Catalog,
    spec: &KitSpec,
    opts: &RunOptions,
    sock: &Path,
    worker_count: usize,
) -> Result<Ceiling> {
    let cpu0 = process_micros();
    let from = monotonic_micros();
    let t0 = Instant::now();
    let totals = run_catalog(catalog, spec, opts);
    let wall = t0.elapsed().as_secs_f64();
    let process = process_micros().saturating_sub(cpu0);
    let to = monotonic_micros();
    let _ = std::fs::remove_file(sock);
    Ok(Ceiling {
        workers: worker_count,
        parts: totals?.parts(),
        wall,
        process_cpu: process as f64 * 1e-6,
        workers_cpu: 0.0,
        replayed: (0, 0),
        window: (from, to),
    })
}

/// One run of the real coordinator path with `worker_count` simulated workers in
/// this process, writing `output`.
pub fn run_once(
    catalog: &Catalog,
    spec: &KitSpec,
    args: &CeilingArgs,
    worker_count: usize,
    replay: &Arc<Replay>,
    output: &Path,
) -> Result<Ceiling> {
    let base = std::env::temp_dir().join(unique_name("ceiling"));
    let (sock, prefix) = round_endpoint(&base, &unique_name("ceiling"), 0);
    let opts = run_options(catalog, args, worker_count, &sock, &prefix, output);
    let (h0, m0) = replay.counts();
    let threads = args.worker_threads();
    let workers = start_workers(
        worker_count,
        threads,
        sock.clone(),
        &prefix,
        args.transport,
        replay,
    );
    let run = coordinate(catalog, spec, &opts, &sock, worker_count);
    let worker_micros: u64 = workers.join().unwrap_or_default().iter().sum();
    let (h1, m1) = replay.counts();
    Ok(Ceiling {
        workers_cpu: worker_micros as f64 * 1e-6,
        replayed: (h1 - h0, m1 - m0),
        ..run?
    })
}

/// Removes the warm-up's results file: the measured run would replace
/// it, and the kernel's freeing of its pages would count as the
/// coordinator's work (a run writing a new file has none of that).
fn forget_warm_up(output: &Path) -> Result<()> {
    std::fs::remove_file(output).with_context(|| format!("removing {}", output.display()))
}

/// The warm-up and measured runs with `worker_count` simulated workers
/// in a process of their own, writing `output`.
fn run_twice_apart(
    catalog: &Catalog,
    spec: &KitSpec,
    args: &CeilingArgs,
    worker_count: usize,
    output: &Path,
) -> Result<[Ceiling; 2]> {
    let base = std::env::temp_dir().join(unique_name("ceiling"));
    let prefix = unique_name("ceiling");
    let workers = WorkerProcess::spawn(
        &base,
        &prefix,
        (worker_count, args.worker_threads()),
        args.transport,
        2,
    )?;
    let run = |round| {
        let (sock, prefix) = round_endpoint(&base, &prefix, round);
        let opts = run_options(catalog, args, worker_count, &sock, &prefix, output);
        coordinate(catalog, spec, &opts, &sock, worker_count)
    };
    let warm = run(0)?;
    forget_warm_up(output)?;
    let measured = run(1)?;
    match workers.finish()?[..] {
        [w, m] => Ok([
            Ceiling {
                replayed: w.replayed,
                ..warm
            },
            Ceiling {
                replayed: m.replayed,
                ..measured
            },
        ]),
        ref other => bail!("the simulated workers served {} runs of 2", other.len()),
    }
}

/// Runs the measurements and prints them.
pub fn bench_main(args: &CeilingArgs) -> Result<()> {
    if let Some(base) = &args.serve_replay {
        let n = args.simulated_workers.first().copied().unwrap_or(1).max(1);
        let workers = (n, args.worker_threads());
        return serve_main(base, &args.prefix, workers, args.transport, args.rounds);
    }
    let path = args
        .catalog
        .clone()
        .unwrap_or_else(crate::run::default_catalog);
    let t = Instant::now();
    let cat = load_catalog(&path)?;
    let load_us = t.elapsed().as_secs_f64() * 1e6 / cat.parts.len().max(1) as f64;
    let spec = load_kit(&args.kit, cat.units)?;
    let catalog = repeated(&cat, args.repeat);
    // Removed when dropped, on an error too (a failed run left its files).
    let tmp = tempfile::Builder::new()
        .prefix("ceiling-")
        .tempdir()
        .context("creating a temporary directory")?;
    let dir = args
        .keep
        .clone()
        .unwrap_or_else(|| tmp.path().to_path_buf());
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    println!(
        "catalogue: {} parts ({} x {}), kit {}, transport {}, {} thread(s) a worker, results files in {}",
        catalog.parts.len(),
        args.repeat,
        cat.parts.len(),
        spec.name,
        args.transport,
        args.worker_threads(),
        dir.display()
    );
    let replay = Arc::new(Replay::default());
    let mut rows = Vec::new();
    for &n in &args.simulated_workers {
        let n = n.max(1);
        let out = dir.join(format!("replay-{n}.mcap"));
        let [warm, run] = if args.in_process {
            let warm = run_once(&catalog, &spec, args, n, &replay, &out)?;
            forget_warm_up(&out)?;
            [warm, run_once(&catalog, &spec, args, n, &replay, &out)?]
        } else {
            run_twice_apart(&catalog, &spec, args, n, &out)?
        };
        let (from, to) = run.window;
        if run.replayed.1 > 0 {
            bail!(
                "{n} workers: {} shards were not replayed (the plan changed between the runs)",
                run.replayed.1
            );
        }
        eprintln!(
            "{n} workers: warm-up {:.2} s ({} shards enumerated), measured {:.2} s \
             (perf report --time {}.{:06},{}.{:06} with perf record -k CLOCK_MONOTONIC)",
            warm.wall,
            warm.replayed.1,
            run.wall,
            from / 1_000_000,
            from % 1_000_000,
            to / 1_000_000,
            to % 1_000_000
        );
        rows.push(run);
    }
    print_table(&rows);
    println!(
        "reading the catalogue (once here, once per part in a run): {load_us:.1} us/part wall"
    );
    Ok(())
}

fn print_table(rows: &[Ceiling]) {
    println!(
        "{:>8} {:>7} {:>8} {:>9} {:>10} {:>12} {:>10}",
        "workers", "parts", "wall s", "parts/s", "shards", "coord us/pt", "coord cpu"
    );
    for r in rows {
        let parts = r.parts.max(1) as f64;
        println!(
            "{:>8} {:>7} {:8.3} {:9.1} {:>10} {:12.1} {:9.0}%",
            r.workers,
            r.parts,
            r.wall,
            parts / r.wall,
            r.replayed.0,
            r.coordinator_cpu() * 1e6 / parts,
            100.0 * r.coordinator_cpu() / r.wall
        );
    }
    println!(
        "(wall: coordinator start to results file renamed; shards: shards and finishings replayed in the run; coord us/pt: \
         this process's CPU per part (with --in-process, minus the simulated workers' threads'); \
         coord cpu: that over the wall time, 100% = one core)"
    );
}
