//! Mutual TLS (feature `tls`): a coordinator and two workers over
//! `tls/127.0.0.1:PORT` give the embedded run's results while workers
//! without a client certificate, with one of another CA or an expired one
//! are refused; the shipped router configuration keeps workers off the
//! coordinator's queryables and liveliness token. Certificates are made
//! at run time (rcgen, through `fixplan certs`' module).
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

mod cluster_support;

use cluster_support::{free_port, serial, unique, Proc, EXE};
use fixplan_coordinator::{Authority, Issued, Validity, COORDINATOR_CN, ROUTER_CN, WORKER_CN};
use fixplan_tests::fixtures_channel;
use fixplan_worker::zenoh_link::{open, TlsFiles, ZenohOptions};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, SystemTime};
use zenoh::Wait;

fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(rel)
}

/// Certificates written as `NAME.pem` and `NAME-key.pem` in one directory.
struct Pki {
    dir: tempfile::TempDir,
    ca: Authority,
}

impl Pki {
    fn new() -> Pki {
        let ca = Authority::new("fixplan-test-ca", Validity::days(1)).unwrap();
        let p = Pki {
            dir: tempfile::tempdir().unwrap(),
            ca,
        };
        std::fs::write(p.dir.path().join("ca.pem"), &p.ca.own.cert_pem).unwrap();
        p
    }
    fn ca(&self) -> PathBuf {
        self.dir.path().join("ca.pem")
    }
    fn write(&self, name: &str, i: &Issued) -> (PathBuf, PathBuf) {
        let cert = self.dir.path().join(format!("{name}.pem"));
        let key = self.dir.path().join(format!("{name}-key.pem"));
        std::fs::write(&cert, &i.cert_pem).unwrap();
        std::fs::write(&key, &i.key_pem).unwrap();
        (cert, key)
    }
    /// A certificate of this CA for `cn`, valid for loopback names.
    fn issue(&self, name: &str, cn: &str) -> (PathBuf, PathBuf) {
        let hosts = ["127.0.0.1", "localhost"].map(String::from);
        self.write(name, &self.ca.issue(cn, &hosts, Validity::days(1)).unwrap())
    }
    fn files(&self, identity: (PathBuf, PathBuf)) -> TlsFiles {
        TlsFiles {
            ca: self.ca(),
            identity: Some(identity),
        }
    }
}

/// `--tls-*` arguments.
fn tls_args(ca: &Path, identity: Option<&(PathBuf, PathBuf)>) -> Vec<String> {
    let mut a = vec!["--tls-ca".to_string(), ca.display().to_string()];
    if let Some((c, k)) = identity {
        a.extend([
            "--tls-cert".into(),
            c.display().to_string(),
            "--tls-key".into(),
            k.display().to_string(),
        ]);
    }
    a
}

fn spawn(args: &[String]) -> Proc {
    let child = Command::new(EXE)
        .args(args)
        .env_remove("RUST_LOG")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    Proc { child: Some(child) }
}

fn worker(endpoint: &str, prefix: &str, tls: Vec<String>) -> Proc {
    let mut a: Vec<String> = [
        "worker",
        "--connect",
        endpoint,
        "--key-prefix",
        prefix,
        "--threads",
        "1",
        "--transport",
        "zenoh",
    ]
    .map(String::from)
    .to_vec();
    a.extend(tls);
    spawn(&a)
}

/// Waits until something listens on the loopback `port` (a plain TCP
/// connection, which a TLS listener logs as a failed handshake).
fn wait_listening(port: u16) {
    let until = std::time::Instant::now() + Duration::from_secs(60);
    while std::net::TcpStream::connect(("127.0.0.1", port)).is_err() {
        assert!(std::time::Instant::now() < until, "nothing on {port}");
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// Lines of `log` that contain `what`.
fn lines_with<'a>(log: &'a str, what: &str) -> Vec<&'a str> {
    log.lines().filter(|l| l.contains(what)).collect()
}

/// The certificates of the run: (certificate, key) files.
struct Identities {
    coordinator: (PathBuf, PathBuf),
    good: Vec<(PathBuf, PathBuf)>,
    /// A worker's, signed by another CA.
    stranger: (PathBuf, PathBuf),
    /// A worker's, of the right CA, that expired yesterday.
    expired: (PathBuf, PathBuf),
}

fn identities(pki: &Pki) -> Identities {
    let other_ca = Authority::new("another-ca", Validity::days(1)).unwrap();
    let day = Duration::from_secs(86_400);
    let past = Validity {
        not_before: SystemTime::now() - 10 * day,
        not_after: SystemTime::now() - day,
    };
    Identities {
        coordinator: pki.issue("coordinator", COORDINATOR_CN),
        good: (1..=2)
            .map(|n| pki.issue(&format!("worker-{n}"), WORKER_CN))
            .collect(),
        stranger: pki.write(
            "stranger",
            &other_ca.issue(WORKER_CN, &[], Validity::days(1)).unwrap(),
        ),
        expired: pki.write("expired", &pki.ca.issue(WORKER_CN, &[], past).unwrap()),
    }
}

/// `fixplan coordinator` on `endpoint` for the catalogue into `out`,
/// waiting for two workers.
fn coordinator_args(
    endpoint: &str,
    prefix: &str,
    tls: Vec<String>,
    catalog: &Path,
    out: &Path,
) -> Vec<String> {
    let mut args: Vec<String> = ["coordinator", "--listen", endpoint, "--key-prefix", prefix]
        .map(String::from)
        .to_vec();
    args.extend(tls);
    args.extend(["--catalog".into(), catalog.display().to_string()]);
    args.extend(["-o".into(), out.display().to_string()]);
    let rest = [
        "--min-workers",
        "2",
        "--transport",
        "zenoh",
        "--expected-threads",
        "2",
    ];
    args.extend(rest.map(String::from));
    args
}

#[test]
fn mutual_tls_run_equals_embedded_and_bad_certificates_are_refused() {
    let _g = serial();
    let pki = Pki::new();
    let ids = identities(&pki);
    let catalog = repo("examples/catalog");
    let emb = pki.dir.path().join("emb.mcap");
    let dist = pki.dir.path().join("dist.mcap");
    let status = Command::new(EXE)
        .args(["run", "-q", "--threads", "1", "--catalog"])
        .arg(&catalog)
        .arg("-o")
        .arg(&emb)
        .status()
        .unwrap();
    assert!(status.success());

    let port = free_port();
    let endpoint = format!("tls/127.0.0.1:{port}");
    let prefix = format!("fxtest/{}", unique("tls"));
    let tls = tls_args(&pki.ca(), Some(&ids.coordinator));
    let args = coordinator_args(&endpoint, &prefix, tls, &catalog, &dist);
    let mut coord = spawn(&args);

    // The refused ones first, once the coordinator listens (their first
    // try then reaches it); the run can only start with the good ones.
    wait_listening(port);
    let refused_worker = |identity: Option<&(PathBuf, PathBuf)>| {
        worker(&endpoint, &prefix, tls_args(&pki.ca(), identity))
    };
    let mut refused = vec![
        ("CertificateRequired", refused_worker(None)),
        ("UnknownCA", refused_worker(Some(&ids.stranger))),
        ("CertificateExpired", refused_worker(Some(&ids.expired))),
    ];
    std::thread::sleep(Duration::from_millis(1500));
    let mut workers: Vec<Proc> = ids
        .good
        .iter()
        .map(|id| worker(&endpoint, &prefix, tls_args(&pki.ca(), Some(id))))
        .collect();

    let (code, coord_log) = coord.wait_output(Duration::from_secs(120));
    eprintln!("--- coordinator\n{coord_log}");
    assert_eq!(code, Some(0), "{coord_log}");
    assert_eq!(fixtures_channel(&emb), fixtures_channel(&dist));
    assert_eq!(
        lines_with(&coord_log, "joined (pid").len(),
        2,
        "{coord_log}"
    );
    for w in &mut workers {
        let (code, log) = w.wait_output(Duration::from_secs(30));
        assert_eq!(code, Some(0), "{log}");
    }

    // Each refused worker says why, and the coordinator says it refused.
    for (alert, w) in &mut refused {
        let (_, log) = w.wait_output(Duration::ZERO);
        eprintln!("--- worker refused with {alert}\n{log}");
        assert!(!log.contains("joined run"), "{log}");
        let refusal = format!(
            "WARN zenoh::net::runtime::orchestrator] Unable to connect to configured \
             peer {endpoint}! received fatal alert: {alert}"
        );
        assert!(!lines_with(&log, &refusal).is_empty(), "{refusal}: {log}");
    }
    for what in [
        "TLS handshake refused: peer sent no certificates",
        "TLS handshake refused: invalid peer certificate: UnknownIssuer",
        "TLS handshake refused: invalid peer certificate: certificate expired",
    ] {
        assert!(
            !lines_with(&coord_log, what).is_empty(),
            "{what}: {coord_log}"
        );
    }
}

/// Replies of `get` on `key`, as text.
fn ask(s: &zenoh::Session, key: &str) -> Vec<String> {
    let replies = s.get(key).timeout(Duration::from_secs(1)).wait().unwrap();
    let mut got = Vec::new();
    while let Ok(r) = replies.recv() {
        if let Ok(sample) = r.result() {
            got.push(String::from_utf8_lossy(&sample.payload().to_bytes()).into_owned());
        }
    }
    got
}

/// Keys of the liveliness tokens under `key`.
fn alive(s: &zenoh::Session, key: &str) -> Vec<String> {
    let replies = s
        .liveliness()
        .get(key)
        .timeout(Duration::from_secs(1))
        .wait()
        .unwrap();
    let mut got = Vec::new();
    while let Ok(r) = replies.recv() {
        if let Ok(sample) = r.result() {
            got.push(sample.key_expr().to_string());
        }
    }
    got.sort();
    got
}

fn token(s: &zenoh::Session, key: &str) -> zenoh::liveliness::LivelinessToken {
    s.liveliness().declare_token(key).wait().unwrap()
}

/// What `f` gives once it is not empty (declarations take a moment to
/// reach the router), within 20 s.
fn eventually(f: impl Fn() -> Vec<String>) -> Vec<String> {
    let until = std::time::Instant::now() + Duration::from_secs(20);
    loop {
        let v = f();
        if !v.is_empty() || std::time::Instant::now() > until {
            return v;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
}

fn declare_join(s: &zenoh::Session, answer: &'static str) -> zenoh::query::Queryable<()> {
    s.declare_queryable("fixplan/join")
        .callback(move |q| {
            let _ = q.reply(q.key_expr().clone(), answer).wait();
        })
        .wait()
        .unwrap()
}

/// The shipped router configuration with its access control, run here
/// (in router mode, in this process) on loopback with test certificates:
/// a worker's certificate cannot serve the coordinator's queryable nor hold
/// its liveliness token, and can do what a worker does.
#[test]
fn router_access_control_keeps_workers_off_the_coordinators_keys() {
    let _g = serial();
    let pki = Pki::new();
    let router_id = pki.issue("router", ROUTER_CN);
    let endpoint = format!("tls/127.0.0.1:{}", free_port());
    let mut rc = zenoh::Config::from_file(repo("deploy/zenoh/router.json5")).unwrap();
    rc.insert_json5("listen/endpoints", &format!("[{endpoint:?}]"))
        .unwrap();
    for (k, v) in [
        ("root_ca_certificate", pki.ca()),
        ("listen_certificate", router_id.0.clone()),
        ("listen_private_key", router_id.1.clone()),
    ] {
        rc.insert_json5(
            &format!("transport/link/tls/{k}"),
            &format!("{:?}", v.display().to_string()),
        )
        .unwrap();
    }
    let _router = zenoh::open(rc).wait().unwrap();
    let session = |config: &str, name: &str, cn: &str| {
        open(&ZenohOptions {
            config_file: Some(repo(&format!("deploy/zenoh/{config}.json5"))),
            connect: vec![endpoint.clone()],
            tls: Some(pki.files(pki.issue(name, cn))),
            ..ZenohOptions::default()
        })
        .unwrap()
    };
    let coordinator = session("coordinator", "coordinator", COORDINATOR_CN);
    let observer = session("coordinator", "observer", COORDINATOR_CN);
    let worker = session("worker", "worker-1", WORKER_CN);
    let rogue = session("worker", "worker-2", WORKER_CN);

    // The rogue worker tries to be the coordinator, before the worker
    // holds its token (seen by then, the rogue's would be too).
    let _rq = declare_join(&rogue, "rogue");
    let _rt = token(&rogue, "fixplan/coordinator");
    let _wt = token(&worker, "fixplan/alive/worker-1");
    let workers = eventually(|| alive(&observer, "fixplan/alive/*"));
    assert_eq!(workers, vec!["fixplan/alive/worker-1"]);
    assert_eq!(
        alive(&observer, "fixplan/coordinator"),
        Vec::<String>::new()
    );

    // The coordinator's certificate may; only it answers.
    let _cq = declare_join(&coordinator, "coordinator");
    let _ct = token(&coordinator, "fixplan/coordinator");
    assert_eq!(
        eventually(|| ask(&worker, "fixplan/join")),
        vec!["coordinator"]
    );
    assert_eq!(
        eventually(|| alive(&observer, "fixplan/coordinator")),
        vec!["fixplan/coordinator"]
    );
}
