//! `fixplan bench-coordinator`'s replay mode: simulated workers (in this
//! process, and in their own through the command) answer from recorded
//! results, and the coordinator's results
//! file holds the same fixtures and scenes as the embedded run's. Loopback only (a
//! unix socket and iceoryx2 under a fresh prefix), a few seconds.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use fixplan_coordinator::Backend;
use fixplan_coordinator::Replay;
use fixplan_coordinator::{run_catalog, RunOptions};
use fixplan_coordinator::{run_once, CeilingArgs};
use fixplan_coordinator::{TransportChoice, VerifyPolicy};
use fixplan_tests::{catalog, channels};
use std::path::PathBuf;
use std::sync::Arc;

#[test]
fn replayed_run_equals_embedded() {
    let dir = tempfile::tempdir().unwrap();
    let (cat, spec) = catalog();
    let args = CeilingArgs {
        catalog: None,
        kit: spec.name.clone(),
        repeat: 1,
        simulated_workers: vec![2],
        threads_per_worker: 1,
        transport: TransportChoice::Auto,
        verify: VerifyPolicy::All,
        keep: None,
        in_process: true,
        serve_replay: None,
        prefix: String::new(),
        rounds: 2,
    };
    let replay = Arc::new(Replay::default());
    let warm = dir.path().join("warm.mcap");
    let replayed = dir.path().join("replayed.mcap");
    let w = run_once(&cat, &spec, &args, 2, &replay, &warm).unwrap();
    assert!(w.replayed.1 > 0, "the warm-up enumerates: {w:?}");
    let r = run_once(&cat, &spec, &args, 2, &replay, &replayed).unwrap();
    assert_eq!(r.replayed.1, 0, "every shard replayed: {r:?}");
    assert!(r.replayed.0 > 0, "{r:?}");
    assert_eq!(r.parts, cat.parts.len());
    let embedded = dir.path().join("embedded.mcap");
    let opts = RunOptions {
        catalog: PathBuf::from("mem"),
        kit: spec.name.clone(),
        top_k: None,
        full_counts: false,
        output: embedded.clone(),
        resume: false,
        shard_size: None,
        quiet: true,
        search: Default::default(),
        backend: Backend::Embedded { threads: Some(2) },
        arcs: None,
    };
    run_catalog(&cat, &spec, &opts).unwrap();
    // Fixtures and scenes (made with the plate holes cached), byte for byte.
    let e = channels(&embedded);
    assert_eq!(e.len(), cat.parts.len());
    assert_eq!(channels(&warm), e);
    assert_eq!(channels(&replayed), e);
}

/// The command as shipped: the simulated workers in a process of their own
/// (this executable again), every shard of the measured run replayed (the
/// command fails otherwise), a row of figures for the count asked.
#[test]
fn bench_coordinator_runs_its_workers_in_their_own_process() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_fixplan-it"))
        .args([
            "bench-coordinator",
            "--repeat",
            "1",
            "--simulated-workers",
            "2",
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("2 workers: warm-up"), "{stderr}");
    let stdout = String::from_utf8(out.stdout).unwrap();
    let row: Vec<&str> = stdout
        .lines()
        .map(|l| l.split_whitespace().collect::<Vec<_>>())
        .find(|cols| cols.first() == Some(&"2"))
        .unwrap_or_else(|| panic!("no row for 2 workers in {stdout}"));
    let (parts, shards): (usize, u64) = (row[1].parse().unwrap(), row[4].parse().unwrap());
    let catalogue = format!("catalogue: {parts} parts");
    assert!(
        stdout.starts_with(&catalogue),
        "every part written: {stdout}"
    );
    assert!(shards > 0, "{stdout}");
    let us_per_part: f64 = row[5].parse().unwrap();
    assert!(
        us_per_part > 0.0,
        "the coordinator's CPU is measured: {stdout}"
    );
}
