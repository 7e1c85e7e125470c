//! Work budgets in the cluster (issue 31): `--part-setups` gives the
//! same parts `over_budget`, with the same message, in `fixplan run`, in
//! `run --workers` and in `fixplan coordinator`, whatever the shard size
//! (parts cut into shards each within the budget are judged on their
//! merged setups; whole parts stop on their worker), and with
//! `--good-enough` too (a shard past a part's stop does not count).
//! `--part-fixtures` likewise, on the fixtures a part keeps.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

mod cluster_support;

use cluster_support::{unique, EXE};
use fixplan_tests::{fixtures_channel, ok};
use std::path::Path;
use std::process::Command;

const CATALOG: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/catalog");

/// Between the sample catalogue's parts: 219 to 1,456 setups over, 0 to
/// 384 within.
const SETUPS: [&str; 2] = ["--part-setups", "400"];

/// With `--top-k 0`, exactly `bracket-2`'s fixtures: 262 to 1,922 over,
/// 0 to 252 within.
const FIXTURES: [&str; 4] = ["--top-k", "0", "--part-fixtures", "252"];

/// `fixplan ARGS` on the sample catalogue within `budget`, to `out`.
fn fixplan_within(budget: &[&str], args: &[&str], out: &Path) -> std::process::Output {
    ok(Command::new(EXE)
        .args(args)
        .args(budget)
        .args(["-q", "--catalog", CATALOG, "-o"])
        .arg(out)
        .env_remove("RUST_LOG")
        .stdin(std::process::Stdio::null())
        .output()
        .unwrap())
}

/// Each part's status, error and counts, as `export --json` prints them.
fn verdicts(path: &Path) -> Vec<Verdict> {
    let mut printed = Vec::new();
    fixplan_coordinator::export_json(path, None, &mut printed).unwrap();
    printed
        .split(|&b| b == b'\n')
        .filter(|l| !l.is_empty())
        .map(|l| {
            let v: serde_json::Value = serde_json::from_slice(l).unwrap();
            let text = |k: &str| v[k].to_string();
            (text("part"), text("status"), text("error"), text("counts"))
        })
        .collect()
}

fn same_as(want: &Path, got: &Path) {
    assert_eq!(verdicts(got), verdicts(want), "{}", got.display());
    assert_eq!(fixtures_channel(got), fixtures_channel(want));
}

/// `run --workers 2` at each shard size within `budget`, with `extra`,
/// gives `embedded`'s verdicts and fixtures.
fn workers_within(budget: &[&str], embedded: &Path, shard_sizes: &[&str], extra: &[&str]) {
    let dir = embedded.parent().unwrap();
    for shard_size in shard_sizes {
        let out = dir.join(format!("workers-{shard_size}.mcap"));
        let args = [
            "run",
            "--workers",
            "2",
            "--threads",
            "2",
            "--shard-size",
            shard_size,
        ];
        fixplan_within(budget, &[&args[..], extra].concat(), &out);
        same_as(embedded, &out);
    }
}

/// `fixplan coordinator` with 2 local workers and shards of 5, with
/// `budget`, to `out`.
fn coordinator_within(budget: &[&str], out: &Path) {
    let sock = std::env::temp_dir().join(format!("{}.sock", unique("fixplan-budget")));
    let listen = format!("unixsock-stream/{}", sock.display());
    let prefix = format!("fxtest/{}", unique("budget"));
    let args = [
        "coordinator",
        "--listen",
        &listen,
        "--key-prefix",
        &prefix,
        "--workers",
        "2",
        "--shard-size",
        "5",
    ];
    fixplan_within(budget, &args, out);
    let _ = std::fs::remove_file(&sock);
}

/// A part's status, error and counts, as `export --json` prints them.
type Verdict = (String, String, String, String);

/// `fixplan run` within `budget` gives some parts, not most,
/// `over_budget` with `message`; `run --workers 2` at several shard sizes
/// and `fixplan coordinator` give the same verdicts and fixtures. The
/// verdicts.
fn over_budget_everywhere(budget: &[&str], message: &str) -> Vec<Verdict> {
    let dir = tempfile::tempdir().unwrap();
    let embedded = dir.path().join("embedded.mcap");
    fixplan_within(budget, &["run", "--threads", "2"], &embedded);
    let v = verdicts(&embedded);
    let over: Vec<_> = v.iter().filter(|p| p.1 == "\"over_budget\"").collect();
    assert!(over.len() >= 5 && over.len() + 10 < v.len(), "{v:?}");
    assert!(over.iter().all(|p| p.2.contains(message)), "{over:?}");
    workers_within(budget, &embedded, &["3", "40", "100000"], &[]);
    let coordinated = dir.path().join("coordinator.mcap");
    coordinator_within(budget, &coordinated);
    same_as(&embedded, &coordinated);
    v
}

#[test]
fn the_cluster_gives_the_same_parts_over_budget_as_run() {
    over_budget_everywhere(&SETUPS, "more than 400 setups, beyond --part-setups 400");
}

/// A part keeping more fixtures than `--part-fixtures` is `over_budget`
/// with no fixture, the same parts with the same message in every mode
/// and at every shard size (whole parts stop on their worker, cut ones
/// on the results the coordinator holds or on their merge); a part
/// keeping exactly the cap is not.
#[test]
fn the_cluster_gives_the_same_parts_over_the_fixture_cap_as_run() {
    // `--part-setups` binds too (its default), so the message names both:
    // which one a piece meets first depends on how the work was cut.
    let message = "more than 10000000 setups or more than 252 fixtures kept, \
                   beyond --part-setups 10000000 or --part-fixtures 252";
    let v = over_budget_everywhere(&FIXTURES, message);
    let at_cap = v.iter().find(|p| p.0 == "\"bracket-2\"").unwrap();
    assert_eq!(at_cap.1, "\"ok\"", "252 fixtures are within a cap of 252");
}

/// With `--good-enough`, the budgets count the combinations up to the
/// stop: `bracket-1` stops after 7 of its 30 combinations with 56 of its
/// 223 fixtures, within a cap of 56, and a shard past its stop that went
/// over does not count.
#[test]
fn good_enough_and_the_budget_give_the_same_parts_in_the_cluster() {
    let dir = tempfile::tempdir().unwrap();
    let embedded = dir.path().join("embedded.mcap");
    // Some parts stop early, some reach 400 setups (or keep 56 fixtures)
    // before a fixture scores 1.3.
    let search = ["--good-enough", "1.3"];
    let capped = ["--top-k", "0", "--part-fixtures", "56"];
    for budget in [&SETUPS[..], &capped[..]] {
        fixplan_within(
            budget,
            &[&["run", "--threads", "2"], &search[..]].concat(),
            &embedded,
        );
        let v = verdicts(&embedded);
        assert!(v.iter().any(|p| p.1 == "\"over_budget\""), "{v:?}");
        assert!(v.iter().any(|p| p.1 == "\"ok\""), "{v:?}");
        let bracket = v.iter().find(|p| p.0 == "\"bracket-1\"").unwrap();
        assert_eq!(bracket.1, "\"ok\"", "{bracket:?}");
        workers_within(budget, &embedded, &["2", "30", "100000"], &search);
    }
}
