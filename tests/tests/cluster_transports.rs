//! Coordinator plus two worker processes on this host, over zenoh and over
//! iceoryx2: the results file equals the embedded run's in the fixture
//! channel, and no shared memory is left behind. Listening without TLS
//! where other hosts can reach it needs `--insecure`.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

mod cluster_support;

use cluster_support::*;
use fixplan_coordinator::{run_catalog, PartMsg, ResultsFile, TransportChoice, TOPIC_PART};
use fixplan_core::{Part, Vertex};
use fixplan_tests::{channels, fixtures_channel, part};

fn two_workers(transport: TransportChoice, flag: &str) {
    let _g = serial();
    let dir = tempfile::tempdir().unwrap();
    let (cat, spec) = catalog();
    let emb = dir.path().join("emb.mcap");
    let dist = dir.path().join("dist.mcap");
    run_catalog(&cat, &spec, &run_opts(&emb, 5, None)).unwrap();
    let net = Net::new("two");
    let mut opts = net.options(transport);
    opts.min_workers = 2;
    opts.shard_size = Some(3);
    let _w1 = net.worker(&["--transport", flag]);
    let _w2 = net.worker(&["--transport", flag]);
    let totals = run_catalog(&cat, &spec, &run_opts(&dist, 5, Some(opts))).unwrap();
    assert_eq!(totals.parts(), 6);
    assert_eq!(fixtures_channel(&emb), fixtures_channel(&dist));
    assert!(shm_left().is_empty(), "{:?}", shm_left());
}

#[test]
fn two_workers_over_zenoh_equal_embedded() {
    two_workers(TransportChoice::Zenoh, "zenoh");
}

#[test]
fn two_workers_over_iceoryx2_equal_embedded() {
    two_workers(TransportChoice::Iceoryx2, "iceoryx2");
}

/// The holes of every part message of a complete results file.
fn part_holes(path: &std::path::Path) -> Vec<Vec<Vec<Vertex>>> {
    let f = ResultsFile::open(path).unwrap();
    let mut v = Vec::new();
    f.for_each_part(|_, m| {
        let msg: PartMsg = serde_json::from_slice(m.get(TOPIC_PART).unwrap()).unwrap();
        v.push(msg.holes());
        true
    })
    .unwrap();
    v
}

/// A part with holes (SPEC 9) crosses the wire whole: one worker with
/// small shards, two with others, and the embedded run give the same
/// fixtures and scene bytes, and the part message (made on the worker that
/// finishes the part) keeps the holes in order.
#[test]
fn a_part_with_holes_is_the_same_whatever_the_workers() {
    let _g = serial();
    let dir = tempfile::tempdir().unwrap();
    let (mut cat, spec) = catalog();
    let holes = vec![
        vec![Vertex::new(15.0, 25.0, 1.0), Vertex::new(25.0, 25.0, 1.0)],
        [[45.0, 15.0], [65.0, 15.0], [65.0, 35.0], [45.0, 35.0]]
            .map(Vertex::from)
            .to_vec(),
    ];
    let mut holed = part("holed", vec![]);
    holed.part = Ok(Part {
        outline: [[0.0, 0.0], [80.0, 0.0], [80.0, 50.0], [0.0, 50.0]]
            .map(Vertex::from)
            .to_vec(),
        holes: holes.clone(),
        access: Vec::new(),
    });
    cat.parts = vec![holed, cat.parts[1].clone()];
    let emb = dir.path().join("emb.mcap");
    run_catalog(&cat, &spec, &run_opts(&emb, 5, None)).unwrap();
    assert_eq!(part_holes(&emb), [holes.clone(), Vec::new()]);
    for (workers, shard) in [(1, 2), (2, 7)] {
        let dist = dir.path().join(format!("dist{workers}.mcap"));
        let net = Net::new(&format!("holes{workers}"));
        let mut opts = net.options(TransportChoice::Zenoh);
        opts.min_workers = workers;
        opts.shard_size = Some(shard);
        let _w: Vec<_> = (0..workers)
            .map(|_| net.worker(&["--transport", "zenoh"]))
            .collect();
        run_catalog(&cat, &spec, &run_opts(&dist, 5, Some(opts))).unwrap();
        assert_eq!(channels(&emb), channels(&dist), "{workers} workers");
        assert_eq!(part_holes(&dist), [holes.clone(), Vec::new()]);
    }
    assert!(shm_left().is_empty(), "{:?}", shm_left());
}

#[test]
fn run_with_local_workers_equals_embedded() {
    let _g = serial();
    let dir = tempfile::tempdir().unwrap();
    let (cat, spec) = catalog();
    let emb = dir.path().join("emb.mcap");
    let dist = dir.path().join("dist.mcap");
    run_catalog(&cat, &spec, &run_opts(&emb, 0, None)).unwrap();
    let net = Net::new("local");
    let mut opts = net.options(TransportChoice::Auto);
    opts.local_workers = 2;
    opts.worker_threads = Some(1);
    opts.worker_exe = Some(EXE.into());
    opts.quiet = true;
    run_catalog(&cat, &spec, &run_opts(&dist, 0, Some(opts))).unwrap();
    assert_eq!(fixtures_channel(&emb), fixtures_channel(&dist));
    assert!(shm_left().is_empty(), "{:?}", shm_left());
}

/// More workers on the coordinator's host than its shared memory serves:
/// the extra ones fall back to zenoh, and the results do not change.
#[test]
fn workers_beyond_the_shared_memory_limit_use_zenoh() {
    let _g = serial();
    let net = Net::new("many");
    let mut opts = net.options(TransportChoice::Auto);
    let n = fixplan_worker::iox::DEFAULT_CLIENTS + 1;
    opts.min_workers = n;
    opts.shard_size = Some(4);
    let inputs = inputs(5);
    let want = embedded(&inputs);
    // Slow reports keep every worker connected while the last ones join.
    let mut workers: Vec<_> = (0..n)
        .map(|_| net.worker_captured(&["--fault", "slow:300"]))
        .collect();
    let mut d = fixplan_coordinator::run_distributed(inputs, opts).unwrap();
    let got = in_order(&mut d);
    d.finish();
    assert_eq!(got, want);
    let logs: Vec<String> = workers
        .iter_mut()
        .map(|w| w.wait_output(std::time::Duration::from_secs(30)).1)
        .collect();
    let over = |t: &str| {
        logs.iter()
            .filter(|l| l.contains(&format!("shards over {t}")))
            .count()
    };
    assert_eq!(over("iceoryx2"), n - 1, "{logs:#?}");
    assert_eq!(over("zenoh"), 1, "{logs:#?}");
    assert!(shm_left().is_empty(), "{:?}", shm_left());
}

/// Safe default: `fixplan coordinator` would listen on plain TCP on every
/// interface; it refuses before writing anything, and says what to do.
/// With `--insecure` it runs, with a warning.
#[test]
fn plain_listening_off_loopback_needs_insecure() {
    let _g = serial();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r.mcap");
    let catalog = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/catalog");
    let prefix = format!("fxtest/{}", unique("insecure"));
    let run = |extra: &[&str]| {
        std::process::Command::new(EXE)
            .args(["coordinator", "--catalog", catalog, "--key-prefix", &prefix])
            .arg("-o")
            .arg(&out)
            .args(extra)
            .env_remove("RUST_LOG")
            .stdin(std::process::Stdio::null())
            .output()
            .unwrap()
    };
    let refused = run(&[]);
    let err = String::from_utf8_lossy(&refused.stderr);
    eprintln!("{err}");
    assert_eq!(refused.status.code(), Some(1), "{err}");
    assert!(
        err.contains(
            "fixplan: refusing to listen on tcp/0.0.0.0:7447 without TLS: \
             any host that reaches it could join the run and send results. Listen on \
             tls/HOST:PORT with --tls-ca, --tls-cert and --tls-key"
        ),
        "{err}"
    );
    assert!(
        err.contains("or give --insecure on a trusted network"),
        "{err}"
    );
    assert!(!dir.path().join("r.mcap.partial").exists());

    let listen = format!("tcp/0.0.0.0:{}", free_port());
    let ok = run(&["--listen", &listen, "--insecure", "--workers", "1"]);
    let err = String::from_utf8_lossy(&ok.stderr);
    eprintln!("{err}");
    assert_eq!(ok.status.code(), Some(0), "{err}");
    let warning = format!(
        "WARN zenoh] listening on {listen} without TLS (--insecure): any host that reaches it can join"
    );
    assert!(err.contains(&warning), "{err}");
    assert!(out.exists());
}
