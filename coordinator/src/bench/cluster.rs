//! `fixplan bench-cluster`: catalogue throughput with 1 and 2 local
//! workers, coordinator time and bytes per shard, and the round trip of a
//! shard-sized message over zenoh and over iceoryx2. A measurement, not a
//! test: run it on an otherwise idle machine, in release mode.

use crate::cluster::{run_distributed, ClusterOptions, PartInput, TransportChoice, VerifyPolicy};
use crate::job::{part_params, JobContext, SearchOptions};
use anyhow::{Context, Result};
use fixplan_catalog::{load_catalog, load_kit};
use fixplan_worker::iox::{self, IoxClient};
use fixplan_worker::protocol::{encode, Answer, Msg, Next, Outcome, TaskDone};
use fixplan_worker::zenoh_link::{open, request, ZenohOptions};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};
use zenoh::Wait;

/// `fixplan bench-cluster` options.
#[derive(clap::Args, Debug, Clone)]
pub struct BenchArgs {
    /// The catalogue (default: the sample catalogue).
    #[arg(long, value_name = "DIR|catalog.toml")]
    pub catalog: Option<PathBuf>,
    /// The kit.
    #[arg(long, default_value = "metric-25")]
    pub kit: String,
    /// Round trips per transport.
    #[arg(long, default_value_t = 2000)]
    pub round_trips: usize,
    /// Segment combinations per shard (default: the cost estimate).
    #[arg(long)]
    pub shard_size: Option<u64>,
    /// The catalogue this many times over (a longer run, steadier figures).
    #[arg(long, default_value_t = 20)]
    pub repeat: usize,
    /// How much of each result the coordinator re-derives: `sample` (each
    /// worker's results until 16 of its fixtures check out, then one in
    /// 32), `all`, or `1/N`.
    #[arg(long, value_name = "sample|all|1/N", default_value = "sample")]
    pub verify: VerifyPolicy,
}

impl BenchArgs {
    fn verify_name(&self) -> String {
        match self.verify {
            VerifyPolicy::All => "all".into(),
            VerifyPolicy::Sample { one_in } => format!(
                "sample (each worker's results in full until {} fixtures checked out, then 1 result in {one_in})",
                crate::cluster::verify::FULL_CHECKS
            ),
        }
    }
}

fn inputs(args: &BenchArgs) -> Result<Vec<PartInput>> {
    let cat = load_catalog(
        &args
            .catalog
            .clone()
            .unwrap_or_else(crate::run::default_catalog),
    )?;
    let spec = load_kit(&args.kit, cat.units)?;
    let ctx = JobContext {
        kit: &spec.kit,
        params: &spec.params,
        units: cat.units,
        shard_size: None,
        search: &SearchOptions::default(),
    };
    let one: Vec<PartInput> = cat
        .parts
        .iter()
        .filter_map(|cp| {
            cp.part.as_ref().ok().map(|p| PartInput {
                part: p.clone(),
                kit: spec.kit.clone(),
                params: part_params(&ctx, cp),
                units: cat.units,
            })
        })
        .collect();
    Ok((0..args.repeat.max(1))
        .flat_map(|_| one.iter().cloned())
        .collect())
}

/// One measured run.
struct MeasuredRun {
    /// Start to finish (workers started, parts done, workers gone).
    wall: f64,
    /// First part out to last part out: the enumeration itself.
    steady: f64,
    /// CPU time of the coordinator process over the run.
    coordinator_cpu: f64,
    stats: crate::cluster::scheduler::Stats,
}

fn throughput(
    parts: &[PartInput],
    workers: usize,
    transport: TransportChoice,
    shard_size: Option<u64>,
    verify: VerifyPolicy,
) -> Result<MeasuredRun> {
    let opts = ClusterOptions {
        key_prefix: fixplan_worker::host::unique_name("bench"),
        transport,
        min_workers: workers,
        shard_size,
        local_workers: workers,
        worker_threads: Some(1),
        expected_threads: Some(2),
        quiet: true,
        verify,
        ..ClusterOptions::default()
    };
    let parts_in = parts.to_vec();
    let cpu0 = crate::cluster::cpu_time::process_micros();
    let t0 = Instant::now();
    let mut d = run_distributed(parts_in, opts)?;
    let mut first = None;
    let mut last = 0.0;
    let mut seen = 0;
    while seen < parts.len() {
        let Some((_, r)) = d.next_merged() else {
            break;
        };
        drop(r);
        seen += 1;
        last = t0.elapsed().as_secs_f64();
        first.get_or_insert(last);
    }
    let stats = d.finish();
    Ok(MeasuredRun {
        wall: t0.elapsed().as_secs_f64(),
        steady: last - first.unwrap_or(0.0),
        coordinator_cpu: crate::cluster::cpu_time::process_micros().saturating_sub(cpu0) as f64
            * 1e-6,
        stats,
    })
}

/// The `fraction` quantile of `values` (NaN for no sample: `--round-trips 0`).
fn percentile(values: &mut [f64], fraction: f64) -> f64 {
    values.sort_by(f64::total_cmp);
    let last = values.len().saturating_sub(1);
    values
        .get((last as f64 * fraction) as usize)
        .copied()
        .unwrap_or(f64::NAN)
}

/// A result message the size of a real one (best fixtures of a part).
fn sample_result(parts: &[PartInput]) -> Result<Vec<u8>> {
    let prep = parts.first().context("empty catalogue")?.prepare()?;
    let n = prep.combination_count().min(64);
    let result = prep.enumerate_range(0..n);
    Ok(encode(&Msg::Report {
        worker: "bench".into(),
        outcomes: vec![Outcome::Done(Box::new(TaskDone {
            shard_id: 1,
            digest: [0; 32],
            micros: 1,
            answer: Answer::Enumerated { result, hit: None },
        }))],
        holding: vec![],
    })?)
}

fn round_trips_zenoh(msg: &[u8], count: usize) -> Result<Vec<f64>> {
    let sock = std::env::temp_dir().join(format!(
        "{}.sock",
        fixplan_worker::host::unique_name("bench")
    ));
    let ep = format!("unixsock-stream/{}", sock.display());
    let server = open(&ZenohOptions {
        listen: vec![ep.clone()],
        ..ZenohOptions::default()
    })?;
    let reply = encode(&Msg::Reply {
        notes: Vec::new(),
        next: Next::Idle { retry_ms: 1 },
    })?;
    let q = server
        .declare_queryable("bench/rt")
        .callback(move |q| {
            let _ = q.reply(q.key_expr().clone(), reply.clone()).wait();
        })
        .wait()
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    let client = open(&ZenohOptions {
        connect: vec![ep],
        ..ZenohOptions::default()
    })?;
    std::thread::sleep(Duration::from_millis(300));
    let mut v = Vec::with_capacity(count);
    for _ in 0..count + 50 {
        let t = Instant::now();
        request(&client, "bench/rt", msg.to_vec(), Duration::from_secs(5))?;
        v.push(t.elapsed().as_secs_f64() * 1e6);
    }
    drop(q);
    let _ = client.close().wait();
    let _ = server.close().wait();
    let _ = std::fs::remove_file(sock);
    Ok(v.split_off(50))
}

fn round_trips_iox(msg: &[u8], count: usize) -> Result<Vec<f64>> {
    let prefix = iox::new_prefix();
    let service = "fixplan/bench".to_string();
    let ctl = Arc::new(iox::ServeControl::default());
    let (ready_tx, ready_rx) = std::sync::mpsc::channel();
    let reply = encode(&Msg::Reply {
        notes: Vec::new(),
        next: Next::Idle { retry_ms: 1 },
    })?;
    let (p, s, c) = (prefix.clone(), service.clone(), ctl.clone());
    let th = std::thread::spawn(move || {
        iox::serve(
            &p,
            &s,
            1,
            move || {
                let _ = ready_tx.send(());
            },
            &c,
            |_| reply.clone(),
        )
    });
    ready_rx
        .recv_timeout(Duration::from_secs(10))
        .context("iceoryx2 server")?;
    let client = IoxClient::open(&prefix, &service)?;
    let mut v = Vec::with_capacity(count);
    for _ in 0..count + 50 {
        let t = Instant::now();
        client.request(msg, Duration::from_secs(5))?;
        v.push(t.elapsed().as_secs_f64() * 1e6);
    }
    drop(client);
    ctl.closing.store(true, std::sync::atomic::Ordering::SeqCst);
    ctl.stop.store(true, std::sync::atomic::Ordering::SeqCst);
    let _ = th.join();
    iox::remove_prefix(&prefix);
    Ok(v.split_off(50))
}

/// Runs the measurements and prints them: throughput with 1 and 2 local
/// workers, what the coordinator spent per shard, and round trips.
pub fn bench_main(args: &BenchArgs) -> Result<()> {
    let parts = inputs(args)?;
    println!(
        "catalogue: {} parts, verification {}",
        parts.len(),
        args.verify_name()
    );
    let runs = [
        ("1 worker  (iceoryx2)", 1, TransportChoice::Auto),
        ("2 workers (iceoryx2)", 2, TransportChoice::Auto),
        ("2 workers (zenoh)   ", 2, TransportChoice::Zenoh),
    ];
    let mut out = Vec::new();
    for (name, workers, transport) in runs {
        out.push((
            name,
            throughput(&parts, workers, transport, args.shard_size, args.verify)?,
        ));
    }
    print_throughput(&out, parts.len());
    print_coordinator(&out);
    let msg = sample_result(&parts)?;
    let mut z = round_trips_zenoh(&msg, args.round_trips)?;
    let mut i = round_trips_iox(&msg, args.round_trips)?;
    println!(
        "round trip of a {} B result message (reply: idle), {} samples:",
        msg.len(),
        args.round_trips
    );
    for (name, v) in [
        ("zenoh (unix socket)", &mut z),
        ("iceoryx2 (shared memory)", &mut i),
    ] {
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        println!(
            "  {name:25} mean {mean:8.1} us  p50 {:8.1} us  p99 {:8.1} us",
            percentile(v, 0.5),
            percentile(v, 0.99)
        );
    }
    Ok(())
}

/// Wall and steady times of each run, against the first (one worker).
fn print_throughput(out: &[(&str, MeasuredRun)], parts: usize) {
    let Some((_, base)) = out.first() else {
        return;
    };
    let (base_wall, base_steady) = (base.wall, base.steady);
    println!(
        "{:22} {:>8} {:>9} {:>8} {:>9} {:>10} {:>12}",
        "", "wall s", "parts/s", "speed-up", "steady s", "speed-up", "coordinator"
    );
    for (name, r) in out {
        println!(
            "{name:22} {:8.3} {:9.1} {:7.2}x {:9.3} {:9.2}x {:10.2}% cpu",
            r.wall,
            parts as f64 / r.wall,
            base_wall / r.wall,
            r.steady,
            base_steady / r.steady.max(1e-9),
            100.0 * r.coordinator_cpu / r.wall,
        );
    }
    println!(
        "(wall: from starting the workers to their exit; steady: first part out to last part out; \
         coordinator: CPU time of the coordinator process over the wall time)"
    );
}

/// What the coordinator spent per shard in each run: time handling
/// requests, bytes in and out, checks.
fn print_coordinator(out: &[(&str, MeasuredRun)]) {
    for (name, r) in out {
        let s = &r.stats;
        let n = s.shards.max(1) as f64;
        println!(
            "{}: {} shards in {} requests, coordinator {:.1} us/shard handling requests, \
             {:.0} B/shard results + {:.0} B/shard assignments, {} results checked in full ({} fixtures re-derived)",
            name.trim_end(),
            s.shards,
            s.requests,
            s.handle_micros as f64 / n,
            s.result_bytes as f64 / n,
            s.assign_bytes as f64 / n,
            s.results_rederived,
            s.fixtures_rederived
        );
    }
}
