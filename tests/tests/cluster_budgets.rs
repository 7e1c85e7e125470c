//! Work budgets in the cluster (issue 31): `--part-setups` gives the
//! same parts `over_budget`, with the same message, in `fixplan run`, in
//! `run --workers` and in `fixplan coordinator`, whatever the shard size
//! (parts cut into shards each within the budget are judged on their
//! merged setups; whole parts stop on their worker), and with
//! `--good-enough` too (a shard past a part's stop does not count).
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

mod cluster_support;

use cluster_support::{unique, EXE};
use fixplan_tests::{fixtures_channel, ok};
use std::path::Path;
use std::process::Command;

const CATALOG: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/catalog");

/// Between the sample catalogue's parts: 219 to 1,456 setups over, 0 to
/// 384 within.
const SETUPS: &str = "400";

fn fixplan(args: &[&str], out: &Path) -> std::process::Output {
    ok(Command::new(EXE)
        .args(args)
        .args(["-q", "--catalog", CATALOG, "--part-setups", SETUPS, "-o"])
        .arg(out)
        .env_remove("RUST_LOG")
        .stdin(std::process::Stdio::null())
        .output()
        .unwrap())
}

/// Each part's status, error and counts, as `export --json` prints them.
fn verdicts(path: &Path) -> Vec<(String, String, String, String)> {
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

/// `run --workers 2` at each shard size, with `extra`, gives `embedded`'s
/// verdicts and fixtures.
fn workers_same_as(embedded: &Path, shard_sizes: &[&str], extra: &[&str]) {
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
        fixplan(&[&args[..], extra].concat(), &out);
        same_as(embedded, &out);
    }
}

#[test]
fn the_cluster_gives_the_same_parts_over_budget_as_run() {
    let dir = tempfile::tempdir().unwrap();
    let embedded = dir.path().join("embedded.mcap");
    fixplan(&["run", "--threads", "2"], &embedded);
    let v = verdicts(&embedded);
    let over: Vec<_> = v.iter().filter(|p| p.1 == "\"over_budget\"").collect();
    assert!(over.len() >= 5 && over.len() + 10 < v.len(), "{v:?}");
    assert!(
        over.iter().all(|p| p
            .2
            .contains("more than 400 setups, beyond --part-setups 400")),
        "{over:?}"
    );
    workers_same_as(&embedded, &["3", "40", "100000"], &[]);
    let sock = std::env::temp_dir().join(format!("{}.sock", unique("fixplan-budget")));
    let listen = format!("unixsock-stream/{}", sock.display());
    let prefix = format!("fxtest/{}", unique("budget"));
    let coordinated = dir.path().join("coordinator.mcap");
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
    fixplan(&args, &coordinated);
    let _ = std::fs::remove_file(&sock);
    same_as(&embedded, &coordinated);
}

#[test]
fn good_enough_and_the_budget_give_the_same_parts_in_the_cluster() {
    let dir = tempfile::tempdir().unwrap();
    let embedded = dir.path().join("embedded.mcap");
    // Some parts stop early (bracket-1 after 7 of 30 combinations), some
    // reach 400 setups before a fixture scores 1.3.
    let search = ["--good-enough", "1.3"];
    fixplan(
        &[&["run", "--threads", "2"], &search[..]].concat(),
        &embedded,
    );
    let v = verdicts(&embedded);
    assert!(v.iter().any(|p| p.1 == "\"over_budget\""), "{v:?}");
    assert!(v.iter().any(|p| p.1 == "\"ok\""), "{v:?}");
    workers_same_as(&embedded, &["2", "30", "100000"], &search);
}
