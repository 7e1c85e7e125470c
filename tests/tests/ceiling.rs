//! `fixplan bench-coordinator`'s replay mode: simulated workers in this
//! process answer from recorded results, and the coordinator's results
//! file holds the same fixtures and scenes as the embedded run's. Loopback only (a
//! unix socket and iceoryx2 under a fresh prefix), a few seconds.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use fixplan_coordinator::bench::ceiling::{run_once, CeilingArgs};
use fixplan_coordinator::cluster::{TransportChoice, VerifyPolicy};
use fixplan_coordinator::run::backend::Backend;
use fixplan_coordinator::run::{run_catalog, RunOptions};
use fixplan_tests::{catalog, channels};
use fixplan_worker::replay::Replay;
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
        transport: TransportChoice::Auto,
        verify: VerifyPolicy::All,
        keep: None,
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
