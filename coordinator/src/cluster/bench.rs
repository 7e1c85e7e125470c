//! `fixplan bench-cluster`: catalogue throughput with 1 and 2 local
//! workers, coordinator time and bytes per shard, and the round trip of a
//! shard-sized message over zenoh and over iceoryx2. A measurement, not a
//! test: run it on an otherwise idle machine, in release mode.

use super::{run_distributed, ClusterOptions, PartInput, TransportChoice};
use crate::part_job::{part_params, JobContext};
use anyhow::{Context, Result};
use fixplan_catalog::{load_catalog, load_kit};
use fixplan_worker::host::cpu_times;
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

/// One measured run.
struct Run {
    /// Wall time, from the call to the end of `finish` (workers gone).
    secs: f64,
    stats: super::state::Stats,
    /// Start to the first shard out; to the last part complete.
    startup: f64,
    to_last: f64,
    /// CPU time of this process (the coordinator) and of the local
    /// workers (children, counted once reaped).
    cpu_self: f64,
    cpu_workers: f64,
}

fn throughput(
    parts: &[PartInput],
    workers: usize,
    transport: TransportChoice,
    shard_size: Option<u64>,
) -> Result<Run> {
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
    let parts = parts.to_vec();
    let (c0, w0) = cpu_times();
    let t0 = Instant::now();
    let mut d = run_distributed(parts, opts)?;
    for (_, r) in d.by_ref() {
        drop(r);
    }
    let stats = d.finish();
    let secs = t0.elapsed().as_secs_f64();
    let (c1, w1) = cpu_times();
    let since = |t: Option<Instant>| t.map_or(f64::NAN, |t| (t - t0).as_secs_f64());
    Ok(Run {
        secs,
        startup: since(stats.first_assign),
        to_last: since(stats.last_part),
        stats,
        cpu_self: (c1 - c0).as_secs_f64(),
        cpu_workers: (w1 - w0).as_secs_f64(),
    })
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
        more: true,
    })))?)
}

/// The ack of a result carrying the next shard of a new part (its input
/// included), as a worker gets it.
fn sample_ack(parts: &[PartInput]) -> Result<Vec<u8>> {
    let input = parts.first().context("empty catalogue")?.encode()?;
    Ok(encode(&Msg::Ack {
        accepted: true,
        note: String::new(),
        next: Some(Box::new(Msg::Assign(fixplan_worker::protocol::Assign {
            shard_id: 2,
            digest: fixplan_worker::part_input::digest(&input),
            range: 0..64,
            input: Some(input),
        }))),
    })?)
}

fn round_trips_zenoh(msg: &[u8], reply: &[u8], n: usize) -> Result<Vec<f64>> {
    let sock = std::env::temp_dir().join(format!(
        "{}.sock",
        fixplan_worker::host::unique_name("bench")
    ));
    let ep = format!("unixsock-stream/{}", sock.display());
    let server = open(&ZenohOptions {
        listen: vec![ep.clone()],
        ..ZenohOptions::default()
    })?;
    let reply = reply.to_vec();
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

fn round_trips_iox(msg: &[u8], reply: &[u8], n: usize) -> Result<Vec<f64>> {
    let prefix = iox::new_prefix();
    let service = "fixplan/bench".to_string();
    let stop = Arc::new(AtomicBool::new(false));
    let cleanup = Arc::new(AtomicBool::new(false));
    let (ready_tx, ready_rx) = std::sync::mpsc::channel();
    let reply = reply.to_vec();
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
    profile_parts(&parts)?;
    let r1 = throughput(&parts, 1, TransportChoice::Auto, a.shard_size)?;
    let r2 = throughput(&parts, 2, TransportChoice::Auto, a.shard_size)?;
    let r2z = throughput(&parts, 2, TransportChoice::Zenoh, a.shard_size)?;
    let (t1, t2, t2z) = (r1.secs, r2.secs, r2z.secs);
    println!("workers of 1 thread each on {} cores:", super::cores());
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
    for (name, r) in [
        ("1 worker", &r1),
        ("2 workers", &r2),
        ("2 workers zenoh", &r2z),
    ] {
        let s = &r.stats;
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
        println!(
            "  first shard out at {:.0} ms, last part done at {:.0} ms, end (workers gone) at {:.0} ms; \
             CPU: coordinator {:.0} ms ({:.1}% of the run; handling requests {:.1}%), workers {:.0} ms",
            r.startup * 1e3,
            r.to_last * 1e3,
            r.secs * 1e3,
            r.cpu_self * 1e3,
            100.0 * r.cpu_self / r.secs,
            100.0 * s.handle_micros as f64 * 1e-6 / r.secs,
            r.cpu_workers * 1e3
        );
    }
    let msg = sample_result(&parts)?;
    let ack = sample_ack(&parts)?;
    let mut z = round_trips_zenoh(&msg, &ack, a.round_trips)?;
    let mut i = round_trips_iox(&msg, &ack, a.round_trips)?;
    println!(
        "round trip of a {} B result message (reply: a {} B ack with the next shard), {} samples:",
        msg.len(),
        ack.len(),
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

/// Where the time of one part goes, on this thread: what the coordinator
/// does per part (prepare, encode and digest the input, decode and verify
/// the result) against what a worker does (prepare, enumerate).
pub fn profile_parts(parts: &[PartInput]) -> Result<()> {
    use fixplan_worker::protocol::decode;
    let (mut prep_us, mut enc_us, mut enum_us, mut ver_us, mut dec_us) = (0.0, 0.0, 0.0, 0.0, 0.0);
    let mut rederived = 0;
    let mut triples = 0;
    let us = |t: Instant| t.elapsed().as_secs_f64() * 1e6;
    for p in parts {
        let t = Instant::now();
        let Ok(prep) = p.prepare() else { continue };
        prep_us += us(t);
        let t = Instant::now();
        let b = p.encode()?;
        let _d = fixplan_worker::part_input::digest(&b);
        enc_us += us(t);
        let t = Instant::now();
        let n = prep.combination_count();
        let r = prep.enumerate_range_serial(0..n);
        enum_us += us(t);
        let frame = encode(&Msg::Result(Box::new(ShardDone {
            worker: "w".into(),
            shard_id: 0,
            digest: [0; 32],
            micros: 0,
            result: r,
            more: true,
        })))?;
        let t = Instant::now();
        let Ok(fixplan_worker::protocol::Frame::Msg(Msg::Result(r))) = decode(&frame) else {
            anyhow::bail!("decode");
        };
        dec_us += us(t);
        let mut tri: Vec<_> = r
            .result
            .fixtures
            .iter()
            .map(|f| (f.segments, f.locators))
            .collect();
        tri.sort();
        tri.dedup();
        triples += tri.len();
        let t = Instant::now();
        rederived +=
            super::verify::check(&prep, &(0..n), &r.result, &[]).map_err(|e| anyhow::anyhow!(e))?;
        ver_us += us(t);
    }
    let k = parts.len() as f64;
    println!(
        "per part, one thread: prepare {:.1} us, encode+digest {:.1} us, enumerate {:.1} us, \
         decode result {:.1} us, verify {:.1} us ({:.1} fixtures re-derived, {:.1} locator setups)",
        prep_us / k,
        enc_us / k,
        enum_us / k,
        dec_us / k,
        ver_us / k,
        rederived as f64 / k,
        triples as f64 / k
    );
    Ok(())
}
