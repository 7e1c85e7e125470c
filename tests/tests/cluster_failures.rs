//! Workers that die, join late, misbehave or speak another protocol: the
//! run completes with the embedded results every time.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

mod cluster_support;

use cluster_support::*;
use fixplan_coordinator::run_catalog;
use fixplan_coordinator::Stats;
use fixplan_coordinator::{run_distributed, Distributed, TransportChoice};
use fixplan_worker::protocol::{decode, encode, encode_as, Frame, Msg, Next, PROTOCOL_VERSION};
use fixplan_worker::zenoh_link::{open, request, ZenohOptions};
use std::time::Duration;

fn collect(mut d: Distributed) -> (Vec<Result<Vec<u8>, String>>, Stats) {
    let got = in_order(&mut d);
    (got, d.finish())
}

type Got = Vec<Result<Vec<u8>, String>>;

/// Two workers that report slowly, on 5 parts in 2-combination shards;
/// 1.5 s into the run `upset` is done to the first. Returns what the run
/// gave, its figures, and the embedded results to compare with.
fn upset_one_worker(
    tag: &str,
    transport: TransportChoice,
    lease: Duration,
    upset: fn(&mut Proc),
) -> (Got, Stats, Got) {
    let _g = serial();
    let net = Net::new(tag);
    let mut opts = net.options(transport);
    opts.shard_size = Some(2);
    opts.min_workers = 2;
    opts.lease = lease;
    let inputs = inputs(5);
    let want = embedded(&inputs);
    let flags: &[&str] = match transport {
        TransportChoice::Zenoh => &["--transport", "zenoh", "--fault", "slow:150"],
        _ => &["--fault", "slow:150"],
    };
    let mut w1 = net.worker(flags);
    let _w2 = net.worker(flags);
    let d = run_distributed(inputs, opts).unwrap();
    let upsetter = std::thread::spawn(move || {
        std::thread::sleep(Duration::from_millis(1500));
        upset(&mut w1);
        w1
    });
    let (got, stats) = collect(d);
    drop(upsetter.join()); // killed (SIGKILL works on a stopped process too)
                           // Checked while this test still holds the lock on shared memory.
    assert!(shm_left().is_empty(), "{:?}", shm_left());
    (got, stats, want)
}

#[test]
fn worker_killed_mid_run_loses_nothing() {
    let (got, stats, want) = upset_one_worker(
        "kill",
        TransportChoice::Zenoh,
        Duration::from_secs(300),
        Proc::sigkill,
    );
    assert_eq!(got, want);
    assert!(stats.workers_lost >= 1, "{stats:?}");
}

#[test]
fn worker_killed_mid_run_over_iceoryx2_loses_nothing() {
    let (got, stats, want) = upset_one_worker(
        "killiox",
        TransportChoice::Iceoryx2,
        Duration::from_secs(300),
        Proc::sigkill,
    );
    assert_eq!(got, want);
    assert!(stats.workers_lost >= 1, "{stats:?}");
}

/// A worker that hangs (SIGSTOP: its process and connections stay up, so
/// only the shard lease can tell) loses its shards to the other worker
/// once their lease runs out, and the run still ends with the embedded
/// results.
#[test]
fn a_hung_worker_loses_its_shards_when_their_lease_runs_out() {
    let (got, stats, want) = upset_one_worker(
        "hang",
        TransportChoice::Zenoh,
        Duration::from_secs(2),
        |w| w.signal("STOP"),
    );
    assert_eq!(got, want);
    assert!(stats.requeued >= 1, "{stats:?}");
}

#[test]
fn late_joiner_gets_work() {
    let _g = serial();
    let net = Net::new("late");
    let mut opts = net.options(TransportChoice::Auto);
    opts.shard_size = Some(2);
    let inputs = inputs(5);
    let want = embedded(&inputs);
    let _w1 = net.worker(&["--fault", "slow:100"]);
    let d = run_distributed(inputs, opts).unwrap();
    let ep = net.endpoint.clone();
    let prefix = net.prefix.clone();
    let late = std::thread::spawn(move || {
        std::thread::sleep(Duration::from_millis(1000));
        let n = Net {
            endpoint: ep,
            prefix,
        };
        let mut w = n.worker_captured(&["--name", "latecomer"]);
        w.wait_output(Duration::from_secs(60))
    });
    let (got, _) = collect(d);
    assert_eq!(got, want);
    let (code, err) = late.join().unwrap();
    assert_eq!(code, Some(0), "{err}");
    let done: u64 = err
        .lines()
        .find_map(|l| l.split("is over: ").nth(1))
        .and_then(|s| s.split_whitespace().next())
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    assert!(done >= 1, "the late worker did no shard:\n{err}");
    // Its threads' busy share of its assignments' time: a percentage.
    let busy: Option<u64> = err
        .lines()
        .find_map(|l| l.split("its threads busy ").nth(1))
        .and_then(|s| s.split('%').next())
        .and_then(|s| s.parse().ok());
    assert!(busy.is_some_and(|b| (1..=100).contains(&b)), "{err}");
}

#[test]
fn malformed_messages_and_other_protocol_versions_are_refused() {
    let _g = serial();
    let net = Net::new("bad");
    let mut opts = net.options(TransportChoice::Zenoh);
    opts.shard_size = Some(2);
    let inputs = inputs(5);
    let want = embedded(&inputs);
    let _w1 = net.worker(&["--transport", "zenoh", "--fault", "slow:50"]);
    let d = run_distributed(inputs, opts).unwrap();
    // A worker of another protocol version is refused with a clear message.
    let mut old = net.worker_captured(&["--protocol-version", "99"]);
    let (code, err) = old.wait_output(Duration::from_secs(30));
    assert_eq!(code, Some(3), "{err}");
    assert!(
        err.contains(&format!("protocol version {PROTOCOL_VERSION}")) && err.contains("version 99"),
        "{err}"
    );
    // Garbage, a truncated message and a foreign version on the work key.
    let s = open(&ZenohOptions {
        connect: vec![net.endpoint.clone()],
        ..ZenohOptions::default()
    })
    .unwrap();
    let work = format!("{}/work", net.prefix);
    let t = Duration::from_secs(5);
    match request(&s, &work, b"garbage".to_vec(), t).unwrap() {
        Frame::Refused(r) => assert!(r.contains("not a fixplan message"), "{r}"),
        f => panic!("{f:?}"),
    }
    let report = |w: &str| Msg::Report {
        worker: w.into(),
        outcomes: vec![],
        holding: vec![],
    };
    let mut cut = encode(&report("x")).unwrap();
    cut.truncate(6);
    match request(&s, &work, cut, t).unwrap() {
        Frame::Refused(r) => assert!(r.contains("malformed"), "{r}"),
        f => panic!("{f:?}"),
    }
    let v99 = encode_as(99, &report("x")).unwrap();
    match request(&s, &work, v99, t).unwrap() {
        Frame::Refused(r) => assert!(r.contains("version 99"), "{r}"),
        f => panic!("{f:?}"),
    }
    // A report from a worker that never joined is told to join.
    let pull = encode(&report("stranger")).unwrap();
    assert_eq!(
        request(&s, &work, pull, t).unwrap(),
        Frame::Msg(Msg::Reply {
            notes: vec![],
            next: Next::Rejoin
        })
    );
    assert!(decode(b"").is_err());
    drop(s);
    let (got, stats) = collect(d);
    assert_eq!(got, want);
    assert_eq!(stats.rejected, 0);
}

#[test]
fn a_worker_with_bad_results_is_rejected_by_name() {
    let _g = serial();
    let net = Net::new("corrupt");
    let mut opts = net.options(TransportChoice::Zenoh);
    opts.shard_size = Some(2);
    opts.min_workers = 1;
    let inputs = inputs(5);
    let want = embedded(&inputs);
    // The liar works alone until it is caught (it corrupts the first shard
    // that has a fixture), so the test does not depend on which worker
    // happens to pull the shards with fixtures; an honest worker finishes.
    let mut bad = net.worker_captured(&[
        "--transport",
        "zenoh",
        "--name",
        "liar-7",
        "--fault",
        "corrupt-score",
    ]);
    let d = run_distributed(inputs, opts).unwrap();
    let (code, err) = bad.wait_output(Duration::from_secs(60));
    assert_eq!(code, Some(3), "{err}");
    assert!(
        err.contains("liar-7") && err.contains("failed verification"),
        "{err}"
    );
    let _good = net.worker(&["--transport", "zenoh"]);
    let (got, stats) = collect(d);
    assert_eq!(got, want);
    assert!(stats.rejected >= 1, "{stats:?}");
}

/// A worker that sends honest results but finished parts that are not what
/// they make (another timing in the part message): the coordinator's check
/// of the re-derived ones catches it by name, and the file holds the
/// embedded run's fixtures and scenes.
#[test]
fn a_worker_whose_finished_parts_differ_from_its_results_is_rejected() {
    let _g = serial();
    let dir = tempfile::tempdir().unwrap();
    let (cat, spec) = catalog();
    let emb = dir.path().join("emb.mcap");
    let dist = dir.path().join("dist.mcap");
    run_catalog(&cat, &spec, &run_opts(&emb, 5, None)).unwrap();
    let net = Net::new("forge");
    let mut opts = net.options(TransportChoice::Zenoh);
    opts.min_workers = 1;
    let mut bad = net.worker_captured(&[
        "--transport",
        "zenoh",
        "--name",
        "forger-3",
        "--fault",
        "forge-finished",
    ]);
    let out = dist.clone();
    let run = std::thread::spawn(move || run_catalog(&cat, &spec, &run_opts(&out, 5, Some(opts))));
    let (code, err) = bad.wait_output(Duration::from_secs(60));
    assert_eq!(code, Some(3), "{err}");
    assert!(
        err.contains("forger-3") && err.contains("failed verification"),
        "{err}"
    );
    let _good = net.worker(&["--transport", "zenoh"]);
    run.join().unwrap().unwrap();
    assert_eq!(
        fixplan_tests::channels(&emb),
        fixplan_tests::channels(&dist)
    );
}
