//! Command-line arguments of `fixplan coordinator`, `fixplan worker` and
//! the `--workers` option of `fixplan run` and `fixplan study`, and the
//! coordinator's and worker's entry points.

use super::fault::Fault;
use crate::cluster::{ClusterOptions, TransportChoice, VerifyPolicy};
use crate::job::SearchOptions;
use crate::run::backend::Backend;
use crate::run::progress::Totals;
use crate::run::{run_parts, RunOptions};
use anyhow::{Context, Result};
use clap::Args;
use fixplan_catalog::{load_kit, ArcMode};
use fixplan_worker::agent::{run_worker, WorkerError, WorkerOptions};
use fixplan_worker::protocol::PROTOCOL_VERSION;
use fixplan_worker::task::{Plain, Runner};
use fixplan_worker::zenoh_link::{zenoh_config, TlsFiles, ZenohOptions};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

/// How to reach the other processes (zenoh).
#[derive(Args, Debug, Clone, Default)]
pub struct NetArgs {
    /// zenoh endpoint to listen on, e.g. `tls/0.0.0.0:7447` (with the
    /// --tls-* files), `tcp/127.0.0.1:7447`, `unixsock-stream//tmp/fixplan.sock`
    /// (repeatable). Without TLS only loopback addresses and unix sockets
    /// are allowed, unless --insecure. `fixplan coordinator` default:
    /// `tls/0.0.0.0:7447` with --tls-cert, else `tcp/0.0.0.0:7447`.
    #[arg(long, value_name = "ENDPOINT")]
    pub listen: Vec<String>,
    /// zenoh endpoint to connect to: the coordinator or a zenoh router,
    /// e.g. `tcp/coordinator-host:7447` (repeatable).
    #[arg(long, value_name = "ENDPOINT")]
    pub connect: Vec<String>,
    /// zenoh mode: `peer` (default) or `client` (through a router).
    #[arg(long, value_name = "MODE")]
    pub mode: Option<String>,
    /// A zenoh configuration file (JSON5: TLS, access control, routers);
    /// `--listen`/`--connect` override its endpoints.
    #[arg(long, value_name = "FILE")]
    pub zenoh_config: Option<PathBuf>,
    /// Key-expression prefix: one per run when runs share a network.
    #[arg(long, value_name = "PREFIX", default_value = "fixplan")]
    pub key_prefix: String,
    /// Transport of shard requests and results: `auto` (iceoryx2 shared
    /// memory for a worker on the coordinator's host, zenoh otherwise),
    /// `zenoh` or `iceoryx2` (forced, for tests and benchmarks).
    #[arg(long, value_name = "auto|zenoh|iceoryx2", default_value = "auto")]
    pub transport: TransportChoice,
    /// Mutual TLS: the CA certificate (PEM) whose certificates are
    /// accepted, for `tls/...` endpoints. Alone (without --tls-cert), only
    /// the other side is checked. `fixplan certs` makes the files.
    #[arg(long, value_name = "FILE")]
    pub tls_ca: Option<PathBuf>,
    /// Mutual TLS: this process's certificate (PEM), signed by the CA.
    #[arg(long, value_name = "FILE", requires_all = ["tls_ca", "tls_key"])]
    pub tls_cert: Option<PathBuf>,
    /// Mutual TLS: the private key (PEM) of --tls-cert.
    #[arg(long, value_name = "FILE", requires = "tls_cert")]
    pub tls_key: Option<PathBuf>,
    /// Listen without TLS on an address other hosts can reach (a trusted
    /// network only: any host that reaches it can join and send results).
    #[arg(long)]
    pub insecure: bool,
}

impl NetArgs {
    fn zenoh(&self) -> ZenohOptions {
        ZenohOptions {
            mode: self.mode.clone(),
            listen: self.listen.clone(),
            connect: self.connect.clone(),
            config_file: self.zenoh_config.clone(),
            tls: self.tls_ca.clone().map(|ca| TlsFiles {
                ca,
                identity: self.tls_cert.clone().zip(self.tls_key.clone()),
            }),
            insecure: self.insecure,
        }
    }
}

/// `fixplan coordinator`.
#[derive(Args, Debug, Clone)]
pub struct CoordinatorArgs {
    /// How to reach the workers.
    #[command(flatten)]
    pub net: NetArgs,
    /// The catalogue (as for `fixplan run`; default: the sample catalogue).
    #[arg(long, value_name = "DIR|catalog.toml")]
    pub catalog: Option<PathBuf>,
    /// Circular arcs of the parts: `exact` (SPEC 8) or `flatten` (chords
    /// within the catalogue's chord tolerance, for comparison). Default:
    /// the manifest's `arcs`, else exact.
    #[arg(long, value_name = "exact|flatten")]
    pub arcs: Option<ArcMode>,
    /// The kit: a built-in name or a kit TOML file.
    #[arg(long, value_name = "NAME|kit.toml", default_value = "metric-25")]
    pub kit: String,
    /// Fixtures kept per part (0 keeps all).
    #[arg(long, value_name = "N")]
    pub top_k: Option<usize>,
    /// Count every admissible fixture, as `fixplan run --full-counts`
    /// (default: top-k mode, which leaves the admissible count out).
    #[arg(long)]
    pub full_counts: bool,
    /// The results file (MCAP), the same as `fixplan run` writes.
    #[arg(short, long, value_name = "FILE", default_value = "results.mcap")]
    pub output: PathBuf,
    /// Workers to wait for before the first shard is handed out.
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub min_workers: usize,
    /// Continue the interrupted run found in OUT.partial.
    #[arg(long)]
    pub resume: bool,
    /// Only the K-th of N consecutive slices of the catalogue's parts, one
    /// slice per coordinator when one does not keep all the workers busy
    /// (deploy/README.md); `fixplan merge` joins the slices' files into
    /// the whole run's.
    #[arg(long, value_name = "K/N")]
    pub slice: Option<crate::run::slice::Slice>,
    /// Segment combinations per shard (default: from a cost estimate).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub shard_size: Option<u64>,
    /// Worker threads expected in all, for the shard sizes (default: 4x
    /// this host's cores).
    #[arg(long, value_name = "N")]
    pub expected_threads: Option<usize>,
    /// Seconds a shard may stay with one worker before it is handed out
    /// again.
    #[arg(long, value_name = "SECONDS", default_value_t = 300)]
    pub lease: u64,
    /// How much of each shard result is re-derived before it is merged:
    /// `sample` (a worker's results in full until 16 of its fixtures
    /// checked out, then one result in 32), `all` (every fixture that
    /// enters a part's top-k, in every result; about 45 us per small part
    /// on the coordinator), or `1/N`.
    #[arg(long, value_name = "sample|all|1/N", default_value = "sample")]
    pub verify: VerifyPolicy,
    /// Worker processes to start on this host as well.
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub workers: usize,
    /// Stop a part (each grid step of it) once it has more than N setups,
    /// as `fixplan run --part-setups`: its status is `over_budget`, and
    /// the run goes on. Deterministic: the same parts as `fixplan run`,
    /// whatever the workers, shard size or threads. The default is
    /// `fixplan run`'s (10^7), so that a catalogue gives the same results
    /// in a run and in the cluster unless told otherwise.
    #[arg(long, value_name = "N", default_value_t = crate::job::budget::DEFAULT_PART_SETUPS)]
    pub part_setups: u64,
    /// Stop a part (each grid step of it) once it keeps more than N
    /// fixtures, as `fixplan run --part-fixtures` and with its default
    /// (about 650 MB of fixtures): the coordinator holds a part's shard
    /// results until the part is merged, so it needs the cap as much as
    /// a run. Deterministic: the same parts as `fixplan run`.
    #[arg(long, value_name = "N", default_value_t = crate::job::budget::DEFAULT_PART_FIXTURES)]
    pub part_fixtures: u64,
    /// Stop a part still enumerating S seconds (the coordinator's clock)
    /// after its first shard went out: its status is `over_budget`, its
    /// shards not handed out again. NOT deterministic. Default: no limit.
    #[arg(long, value_name = "S")]
    pub part_seconds: Option<f64>,
    /// No progress display, summary table or info logs.
    #[arg(short, long)]
    pub quiet: bool,
}

/// `fixplan worker`.
#[derive(Args, Debug, Clone)]
pub struct WorkerArgs {
    /// How to reach the coordinator.
    #[command(flatten)]
    pub net: NetArgs,
    /// Enumeration threads (default: all cores).
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Stay for the next run instead of exiting when a run is over (or
    /// when its coordinator is gone for 10 s).
    #[arg(long)]
    pub stay: bool,
    /// Name in logs (default: HOST-PID-NONCE).
    #[arg(long)]
    pub name: Option<String>,
    /// Warnings only.
    #[arg(short, long)]
    pub quiet: bool,
    /// Claim another protocol version (tests of the version check).
    #[arg(long, hide = true, default_value_t = PROTOCOL_VERSION)]
    pub protocol_version: u16,
    /// Stop once the process PID is no longer this worker's parent: given
    /// by `fixplan run --workers` to the workers it starts.
    #[arg(long, hide = true, value_name = "PID")]
    pub parent: Option<u32>,
    /// Misbehave (tests of the coordinator's checks): corrupt-score,
    /// forge-finished, slow:MS (every shard MS longer),
    /// abort-on-vertices:N (die on a part of N outline vertices).
    #[arg(long, hide = true)]
    pub fault: Option<Fault>,
}

/// `fixplan certs`.
#[cfg(feature = "tls")]
#[derive(Args, Debug, Clone)]
pub struct CertsArgs {
    /// Directory for the files (created if needed; one that already holds
    /// a `ca.pem` is refused).
    #[arg(long, value_name = "DIR")]
    pub dir: PathBuf,
    /// Worker certificates to make.
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub workers: usize,
    /// A name or address of the coordinator's (or router's) host that
    /// workers connect to, besides localhost, 127.0.0.1 and ::1
    /// (repeatable).
    #[arg(long, value_name = "NAME")]
    pub host: Vec<String>,
    /// Days the certificates are valid.
    #[arg(long, value_name = "N", default_value_t = 365)]
    pub days: u64,
}

/// `fixplan certs`: writes the files and lists them.
#[cfg(feature = "tls")]
pub fn certs_main(a: &CertsArgs) -> Result<()> {
    use crate::cluster::certs::{write_certs, CertsOptions};
    let files = write_certs(&CertsOptions {
        dir: a.dir.clone(),
        workers: a.workers,
        hosts: a.host.clone(),
        days: a.days,
    })?;
    for f in files {
        println!("{}", f.display());
    }
    Ok(())
}

/// `--workers` and `--transport` of `fixplan run`.
#[derive(Args, Debug, Clone, Default)]
pub struct RunClusterArgs {
    /// Solve the parts in N worker processes on this host, coordinated over
    /// zenoh and iceoryx2 exactly as across hosts (same results).
    #[arg(long, value_name = "N")]
    pub workers: Option<usize>,
    /// With --workers: transport of shard requests and results.
    #[arg(long, value_name = "auto|zenoh|iceoryx2", default_value = "auto")]
    pub transport: TransportChoice,
    /// With --workers: how much of each shard result is re-derived
    /// (`sample`, `all` or `1/N`; see `fixplan coordinator --help`).
    #[arg(long, value_name = "sample|all|1/N", default_value = "sample")]
    pub verify: VerifyPolicy,
}

impl RunClusterArgs {
    /// The cluster of `--workers N` (none without it): N local worker
    /// processes sharing `threads` (default: this host's cores).
    pub fn options(&self, threads: Option<usize>) -> Option<ClusterOptions> {
        let n = self.workers.filter(|&n| n > 0)?;
        Some(ClusterOptions {
            key_prefix: fixplan_worker::host::unique_name("fixplan-run"),
            transport: self.transport,
            min_workers: 1,
            local_workers: n,
            worker_threads: threads.map(|t| (t / n).max(1)),
            quiet: true,
            verify: self.verify,
            ..ClusterOptions::default()
        })
    }
}

/// `fixplan coordinator`.
pub fn coordinator_main(a: &CoordinatorArgs, default_catalog: PathBuf) -> Result<Totals> {
    let mut zenoh = a.net.zenoh();
    if zenoh.listen.is_empty() && zenoh.connect.is_empty() && zenoh.config_file.is_none() {
        // Refused without --insecure unless TLS files were given.
        let proto = if zenoh.tls.is_some() { "tls" } else { "tcp" };
        zenoh.listen = vec![format!("{proto}/0.0.0.0:7447")];
    }
    // Before anything is read or written (zenoh_link::open checks again).
    fixplan_worker::exposure::check_config(&zenoh_config(&zenoh)?, zenoh.insecure)?;
    let catalog_path = a.catalog.clone().unwrap_or(default_catalog);
    let catalog = crate::run::load_catalog_arcs(&catalog_path, a.arcs)?;
    let spec = load_kit(&a.kit, catalog.units)?;
    let cores = crate::job::threads::cores();
    let copts = ClusterOptions {
        zenoh,
        key_prefix: a.net.key_prefix.clone(),
        transport: a.net.transport,
        min_workers: a.min_workers,
        shard_size: a.shard_size,
        lease: Duration::from_secs(a.lease.max(1)),
        local_workers: a.workers,
        expected_threads: Some(a.expected_threads.unwrap_or(4 * cores)),
        quiet: a.quiet,
        verify: a.verify,
        ..ClusterOptions::default()
    };
    let opts = RunOptions {
        catalog: catalog_path,
        kit: a.kit.clone(),
        top_k: a.top_k,
        full_counts: a.full_counts,
        output: a.output.clone(),
        resume: a.resume,
        shard_size: a.shard_size,
        quiet: a.quiet,
        search: SearchOptions {
            part_setups: Some(a.part_setups),
            part_fixtures: Some(a.part_fixtures),
            part_seconds: a.part_seconds,
            ..SearchOptions::default()
        },
        backend: Backend::Cluster(copts),
        arcs: a.arcs,
    };
    let parts = match a.slice {
        Some(s) => s.parts(catalog.parts.len()),
        None => 0..catalog.parts.len(),
    };
    run_parts(&catalog, &spec, &opts, parts).context("coordinator")
}

/// `fixplan worker`: exit code 3 when refused.
pub fn worker_main(a: &WorkerArgs) -> Result<()> {
    let opts = WorkerOptions {
        zenoh: a.net.zenoh(),
        key_prefix: a.net.key_prefix.clone(),
        threads: a.threads,
        transport: a.net.transport,
        stay: a.stay,
        name: a.name.clone(),
        protocol_version: a.protocol_version,
        runner: match a.fault.clone() {
            Some(fault) => Arc::new(fault) as Arc<dyn Runner>,
            None => Arc::new(Plain),
        },
        finisher: Some(Arc::new(crate::run::finish::RunFinisher)),
        parent: a.parent,
    };
    match run_worker(opts) {
        Ok(_) => Ok(()),
        Err(WorkerError::Refused(r)) => {
            eprintln!("fixplan worker: {r}");
            std::process::exit(3);
        }
        Err(e) => Err(e.into()),
    }
}
