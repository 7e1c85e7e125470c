//! A part that kills the workers it is given (issue 31): the coordinator
//! suspects every part a lost worker held, hands a suspect's shards out
//! alone, and fails a part whose shards were with two lost workers, one
//! of them holding nothing else; it is never handed out again and every
//! other part, innocent ones batched with it included, has the embedded
//! run's bytes. The killer is cut into shards that can reach several
//! workers at once, so the test restarts the workers that die.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

mod cluster_support;

use cluster_support::*;
use fixplan_coordinator::{run_catalog, PartRecord, ResultsFile, TransportChoice, TOPIC_FIXTURES};
use fixplan_core::Status;
use std::os::unix::process::ExitStatusExt;
use std::path::Path;
use std::time::Duration;

/// Every part's id, status, error and fixtures channel.
fn parts(path: &Path) -> Vec<(String, Status, Option<String>, Vec<u8>)> {
    let mut v = Vec::new();
    ResultsFile::open(path)
        .unwrap()
        .for_each_part(|_, m| {
            let r = PartRecord::decode(&m).unwrap();
            let f = m.get(TOPIC_FIXTURES).unwrap().to_vec();
            v.push((r.part.id, r.part.status.into(), r.part.error, f));
            true
        })
        .unwrap();
    v
}

/// Keeps `n` workers with the abort fault running until `over`, starting
/// a new one for each that aborts; returns how many aborted. Workers left
/// are killed on drop, whatever happens.
fn supervise(net: &Net, n: usize, over: impl Fn() -> bool) -> usize {
    let flags = ["--transport", "zenoh", "--fault", "abort-on-vertices:7"];
    let mut workers: Vec<Proc> = (0..n).map(|_| net.worker(&flags)).collect();
    let mut deaths = 0;
    while !over() {
        for w in &mut workers {
            let gone = w
                .child
                .as_mut()
                .is_some_and(|c| matches!(c.try_wait(), Ok(Some(_))));
            if gone && aborted(w) {
                deaths += 1;
                *w = net.worker(&flags);
            }
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    // The run can end before the last abort was seen here: the workers
    // left are killed, and those that had aborted tell by their signal.
    deaths + workers.iter_mut().map(aborted).filter(|&a| a).count()
}

/// Kills and reaps the worker; whether it had aborted (SIGABRT, the
/// fault) rather than been killed here (SIGKILL) or exited (told the run
/// is over).
fn aborted(w: &mut Proc) -> bool {
    let Some(mut c) = w.child.take() else {
        return false;
    };
    let _ = c.kill();
    c.wait().is_ok_and(|s| s.signal() == Some(libc::SIGABRT))
}

/// The coordinator's unix socket and its lock file, removed on drop: a
/// run that panics leaves them behind.
struct SocketFiles(std::path::PathBuf);

impl Drop for SocketFiles {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
        let _ = std::fs::remove_file(self.0.with_extension("sock.lock"));
    }
}

#[test]
fn a_part_that_kills_two_workers_is_failed_and_the_rest_goes_on() {
    let _g = serial();
    let dir = tempfile::tempdir().unwrap();
    let (mut cat, spec) = catalog();
    // The only part of 7 vertices: the workers' fault aborts on it.
    let killer = fixplan_tests::part(
        "killer",
        vec![
            [0.0, 0.0],
            [80.0, 0.0],
            [80.0, 30.0],
            [60.0, 30.0],
            [60.0, 50.0],
            [20.0, 50.0],
            [0.0, 30.0],
        ],
    );
    cat.parts.insert(2, killer);
    let embedded = dir.path().join("embedded.mcap");
    run_catalog(&cat, &spec, &run_opts(&embedded, 5, None)).unwrap();
    let net = Net::new("killer");
    let _socket = SocketFiles(net.endpoint.trim_start_matches("unixsock-stream/").into());
    let mut options = net.options(TransportChoice::Zenoh);
    options.min_workers = 3;
    let out = dir.path().join("cluster.mcap");
    // The killer may be cut into shards that reach several workers at
    // once: like a supervisor, the test starts a new worker for each that
    // died, so the run always has three.
    let deaths = std::thread::scope(|s| {
        let run = s.spawn(|| run_catalog(&cat, &spec, &run_opts(&out, 5, Some(options))));
        let deaths = supervise(&net, 3, || run.is_finished());
        run.join().unwrap().unwrap();
        deaths
    });
    assert!(deaths >= 2, "{deaths} workers died");
    assert!(shm_left().is_empty(), "{:?}", shm_left());
    let (got, want) = (parts(&out), parts(&embedded));
    assert_eq!(got.len(), want.len());
    for (i, (g, w)) in got.iter().zip(&want).enumerate() {
        if i == 2 {
            assert_eq!((g.0.as_str(), g.1), ("killer", Status::Failed));
            let e = g.2.as_deref().unwrap();
            assert!(
                e.contains("workers while being solved") && e.contains("not handed out again"),
                "{e}"
            );
        } else {
            let head =
                |p: &(String, Status, Option<String>, Vec<u8>)| (p.0.clone(), p.1, p.2.clone());
            assert_eq!(head(g), head(w), "part #{i}");
            assert!(g.3 == w.3, "part #{i}: other fixtures");
        }
    }
}
