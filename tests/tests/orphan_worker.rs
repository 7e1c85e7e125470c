//! A worker started by `fixplan run --workers` (`--parent PID`) stops once
//! that process is gone, even if it never reached it: a coordinator killed
//! by SIGKILL before its workers joined used to leave them retrying its
//! socket for ever.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Whether process `pid` still exists (`kill -0`).
fn alive(pid: &str) -> bool {
    Command::new("kill")
        .args(["-0", pid])
        .stderr(Stdio::null())
        .status()
        .unwrap()
        .success()
}

#[test]
fn a_worker_whose_parent_died_before_it_joined_stops() {
    // A loopback port with nothing behind it: the coordinator "died".
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    // The shell starts the worker with itself as `--parent`, prints the
    // worker's pid and exits: the worker is orphaned at once.
    let script = format!(
        "\"$0\" worker --connect tcp/127.0.0.1:{port} --key-prefix orphan-test --threads 1 \
         --quiet --parent $$ >/dev/null 2>&1 & echo $!"
    );
    let out = Command::new("sh")
        .args(["-c", &script, env!("CARGO_BIN_EXE_fixplan-it")])
        .output()
        .unwrap();
    assert!(out.status.success());
    let pid = String::from_utf8(out.stdout).unwrap().trim().to_string();
    assert!(pid.parse::<u32>().is_ok(), "worker pid {pid:?}");
    // A bound on a hang, not a speed test: it stops after one failed
    // attempt to reach the coordinator, well within a second here.
    let until = Instant::now() + Duration::from_secs(60);
    while alive(&pid) && Instant::now() < until {
        std::thread::sleep(Duration::from_millis(50));
    }
    let still_there = alive(&pid);
    if still_there {
        let _ = Command::new("kill").args(["-9", &pid]).status();
    }
    assert!(
        !still_there,
        "the orphaned worker {pid} was still waiting after 60 s"
    );
}
