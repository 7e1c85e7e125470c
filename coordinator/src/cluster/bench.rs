//! `fixplan bench-cluster`: catalogue throughput with 1 and 2 local
//! workers, coordinator time and bytes per shard, and the round trip of a
//! shard-sized message over zenoh and over iceoryx2. A measurement, not a
//! test: run it on an otherwise idle machine, in release mode.

use super::{run_distributed, ClusterOptions, PartInput, TransportChoice};
use crate::part_job::{part_params, JobContext};
use anyhow::{Context, Result};
use fixplan_catalog::{load_catalog, load_kit};
use fixplan_worker::iox::{self, IoxClient};
use fixplan_worker::protocol::{encode, Msg, ShardDone};
use fixplan_worker::zenoh_link::{open, request, ZenohOptions};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::{Duration, Instant};
use zenoh::Wait;

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
    #[arg(long, default_value_t = 10)]
    pub repeat: usize,
}

fn inputs(a: &BenchArgs) -> Result<Vec<PartInput>> {
    let cat = load_catalog(
        &a.catalog
            .clone()
            .unwrap_or_else(crate::run::default_catalog),
    )?;
    let spec = load_kit(&a.kit, cat.units)?;
    let ctx = JobContext {
        kit: &spec.kit,
        params: &spec.params,
        units: cat.units,
        shard_size: None,
        search: &crate::refine::SearchOptions::default(),
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
    Ok((0..a.repeat.max(1))
        .flat_map(|_| one.iter().cloned())
        .collect())
}

fn throughput(
    parts: &[PartInput],
    workers: usize,
    transport: TransportChoice,
    shard_size: Option<u64>,
) -> Result<(f64, super::state::Stats)> {
    let opts = ClusterOptions {
        key_prefix: fixplan_worker::host::unique_name("bench"),
        transport,
        min_workers: workers,
        shard_size,
        local_workers: workers,
        worker_threads: Some(1),
        expected_threads: Some(2),
        quiet: true,
        ..ClusterOptions::default()
    };
    let t0 = Instant::now();
    let mut d = run_distributed(parts.to_vec(), opts)?;
    let mut first = None;
    let mut last = 0.0;
    let mut seen = 0;
    while seen < parts.len() {
        let Some((_, r)) = d.next() else { break };
        drop(r);
        seen += 1;
        last = t0.elapsed().as_secs_f64();
        first.get_or_insert(last);
    }
    let stats = d.finish();
    let secs = t0.elapsed().as_secs_f64();
    eprintln!("  [{workers} {transport}] first part {:.3} s, last part {last:.3} s, finished {secs:.3} s", first.unwrap_or(0.0));
    Ok((secs, stats))
}

fn percentile(v: &mut [f64], p: f64) -> f64 {
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * p) as usize]
}

/// A result message the size of a real one (best fixtures of a part).
fn sample_result(parts: &[PartInput]) -> Result<Vec<u8>> {
    let prep = parts.first().context("empty catalogue")?.prepare()?;
    let n = prep.combination_count().min(64);
    let result = prep.enumerate_range(0..n);
    Ok(encode(&Msg::Result(Box::new(ShardDone {
        worker: "bench".into(),
        shard_id: 1,
        digest: [0; 32],
        micros: 1,
        result,
    })))?)
}

fn round_trips_zenoh(msg: &[u8], n: usize) -> Result<Vec<f64>> {
    let sock = std::env::temp_dir().join(format!(
        "{}.sock",
        fixplan_worker::host::unique_name("bench")
    ));
    let ep = format!("unixsock-stream/{}", sock.display());
    let server = open(&ZenohOptions {
        listen: vec![ep.clone()],
        ..ZenohOptions::default()
    })?;
    let reply = encode(&Msg::Ack {
        accepted: true,
        note: String::new(),
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
    let mut v = Vec::with_capacity(n);
    for _ in 0..n + 50 {
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

fn round_trips_iox(msg: &[u8], n: usize) -> Result<Vec<f64>> {
    let prefix = iox::new_prefix();
    let service = "fixplan/bench".to_string();
    let stop = Arc::new(AtomicBool::new(false));
    let cleanup = Arc::new(AtomicBool::new(false));
    let (ready_tx, ready_rx) = std::sync::mpsc::channel();
    let reply = encode(&Msg::Ack {
        accepted: true,
        note: String::new(),
    })?;
    let (p, s, st, cl) = (
        prefix.clone(),
        service.clone(),
        stop.clone(),
        cleanup.clone(),
    );
    let th = std::thread::spawn(move || {
        iox::serve(
            &p,
            &s,
            move || {
                let _ = ready_tx.send(());
            },
            &st,
            &cl,
            |_| reply.clone(),
        )
    });
    ready_rx
        .recv_timeout(Duration::from_secs(10))
        .context("iceoryx2 server")?;
    let client = IoxClient::open(&prefix, &service)?;
    let mut v = Vec::with_capacity(n);
    for _ in 0..n + 50 {
        let t = Instant::now();
        client.request(msg, Duration::from_secs(5))?;
        v.push(t.elapsed().as_secs_f64() * 1e6);
    }
    drop(client);
    stop.store(true, std::sync::atomic::Ordering::SeqCst);
    let _ = th.join();
    iox::remove_prefix(&prefix);
    Ok(v.split_off(50))
}

pub fn bench_main(a: &BenchArgs) -> Result<()> {
    fixplan_worker::log::set_quiet(true);
    let parts = inputs(a)?;
    println!("catalogue: {} parts", parts.len());
    let (t1, s1) = throughput(&parts, 1, TransportChoice::Auto, a.shard_size)?;
    let (t2, s2) = throughput(&parts, 2, TransportChoice::Auto, a.shard_size)?;
    let (t2z, s2z) = throughput(&parts, 2, TransportChoice::Zenoh, a.shard_size)?;
    println!(
        "1 worker  (iceoryx2): {t1:7.3} s  {:6.2} parts/s",
        parts.len() as f64 / t1
    );
    println!(
        "2 workers (iceoryx2): {t2:7.3} s  {:6.2} parts/s  speed-up {:.2}x",
        parts.len() as f64 / t2,
        t1 / t2
    );
    println!(
        "2 workers (zenoh):    {t2z:7.3} s  {:6.2} parts/s  speed-up {:.2}x",
        parts.len() as f64 / t2z,
        t1 / t2z
    );
    for (name, s) in [
        ("1 worker", &s1),
        ("2 workers", &s2),
        ("2 workers zenoh", &s2z),
    ] {
        let n = s.shards.max(1) as f64;
        println!(
            "{name}: {} shards, coordinator {:.1} us/shard (handling requests, verification included), \
             {:.0} B/shard results + {:.0} B/shard assignments, {} fixtures re-derived",
            s.shards,
            s.handle_micros as f64 / n,
            s.result_bytes as f64 / n,
            s.assign_bytes as f64 / n,
            s.fixtures_rederived
        );
    }
    let msg = sample_result(&parts)?;
    let mut z = round_trips_zenoh(&msg, a.round_trips)?;
    let mut i = round_trips_iox(&msg, a.round_trips)?;
    println!(
        "round trip of a {} B result message (reply: ack), {} samples:",
        msg.len(),
        a.round_trips
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
