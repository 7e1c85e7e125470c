//! Workers on "other hosts": each in its own network namespace (and UTS
//! namespace, so another host name), reaching the coordinator through a
//! veth pair over TCP. Needs root and `ip netns`; skipped otherwise.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

mod cluster_support;

use cluster_support::*;
use fixplan_coordinator::{run_distributed, TransportChoice};
use fixplan_worker::zenoh_link::ZenohOptions;
use std::process::{Command, Stdio};

fn sh(args: &[&str]) -> Result<(), String> {
    let out = Command::new(args[0])
        .args(&args[1..])
        .output()
        .map_err(|e| format!("{}: {e}", args[0]))?;
    if out.status.success() {
        Ok(())
    } else {
        Err(format!(
            "{}: {}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr).trim()
        ))
    }
}

/// Namespaces and veth pairs, removed on drop.
struct Lab {
    ns: Vec<String>,
    links: Vec<String>,
}

impl Drop for Lab {
    fn drop(&mut self) {
        for l in &self.links {
            let _ = sh(&["ip", "link", "del", l]);
        }
        for n in &self.ns {
            let _ = sh(&["ip", "netns", "del", n]);
        }
    }
}

fn lab(n: usize) -> Result<(Lab, Vec<(String, String)>), String> {
    let pid = std::process::id() % 100_000;
    let mut lab = Lab {
        ns: vec![],
        links: vec![],
    };
    let mut out = Vec::new();
    for i in 0..n {
        let ns = format!("fxw{pid}n{i}");
        let a = format!("vfx{pid}{i}a");
        let b = format!("vfx{pid}{i}b");
        let net = 100 + (pid % 100) as usize + i;
        let (ha, hb) = (format!("10.213.{net}.1"), format!("10.213.{net}.2"));
        sh(&["ip", "netns", "add", &ns])?;
        lab.ns.push(ns.clone());
        sh(&["ip", "link", "add", &a, "type", "veth", "peer", "name", &b])?;
        lab.links.push(a.clone());
        sh(&["ip", "link", "set", &b, "netns", &ns])?;
        sh(&["ip", "addr", "add", &format!("{ha}/24"), "dev", &a])?;
        sh(&["ip", "link", "set", &a, "up"])?;
        sh(&[
            "ip",
            "netns",
            "exec",
            &ns,
            "ip",
            "addr",
            "add",
            &format!("{hb}/24"),
            "dev",
            &b,
        ])?;
        sh(&["ip", "netns", "exec", &ns, "ip", "link", "set", &b, "up"])?;
        sh(&["ip", "netns", "exec", &ns, "ip", "link", "set", "lo", "up"])?;
        out.push((ns, ha));
    }
    Ok((lab, out))
}

#[test]
fn workers_in_separate_network_namespaces() {
    let _g = serial();
    // SAFETY: geteuid has no preconditions.
    if unsafe { libc::geteuid() } != 0 || Command::new("ip").arg("-V").output().is_err() {
        eprintln!("SKIPPED: needs root and ip netns");
        return;
    }
    let (_lab, hosts) = match lab(2) {
        Ok(l) => l,
        Err(e) => {
            eprintln!("SKIPPED: cannot set up network namespaces ({e})");
            return;
        }
    };
    let port = 20_000 + (std::process::id() % 20_000) as u16;
    let net = Net::new("netns");
    let mut opts = net.options(TransportChoice::Auto);
    opts.zenoh = ZenohOptions {
        listen: hosts
            .iter()
            .map(|(_, h)| format!("tcp/{h}:{port}"))
            .collect(),
        // Plain TCP between "hosts": refused without it.
        insecure: true,
        ..ZenohOptions::default()
    };
    opts.min_workers = 2;
    opts.shard_size = Some(2);
    let inputs = inputs(5);
    let want = embedded(&inputs);
    let d = run_distributed(inputs, opts).unwrap();
    let has_unshare = Command::new("unshare").arg("--version").output().is_ok();
    let mut workers = Vec::new();
    for (i, (ns, h)) in hosts.iter().enumerate() {
        let connect = format!("tcp/{h}:{port}");
        let args = [
            "worker",
            "--connect",
            &connect,
            "--key-prefix",
            &net.prefix,
            "--threads",
            "1",
        ];
        let mut c = Command::new("ip");
        c.args(["netns", "exec", ns]);
        if has_unshare {
            // Another host name: the worker is on "another host" (zenoh).
            let script = format!("hostname fxhost{i} && exec \"$0\" \"$@\"");
            c.args(["unshare", "--uts", "sh", "-c", &script, EXE]);
        } else {
            c.arg(EXE);
        }
        let child = c
            .args(args)
            .stdin(Stdio::null())
            .spawn()
            .expect("start a worker in a namespace");
        workers.push(Proc { child: Some(child) });
    }
    let mut d = d;
    let got = in_order(&mut d);
    let stats = d.finish();
    assert_eq!(got, want);
    assert_eq!(stats.workers_joined, 2, "{stats:?}");
}
