//! The `fixplan` command line: arguments, help texts and dispatch to the
//! folders that do the work. A library function, so that the binary of
//! this crate and the one the workspace integration tests build (`tests/`)
//! are the same program. Uses every other folder; nothing uses it.

pub(crate) mod case_file;
pub(crate) mod cluster;
pub(crate) mod fault;
pub(crate) mod log;
pub(crate) mod study;

use crate::run::backend::Backend;
use crate::run::{default_catalog, load_and_run, RunOptions};
use anyhow::Result;
use clap::{Parser, Subcommand};
use fixplan_catalog::{ArcMode, HoleMode, LoadOptions};
use std::path::PathBuf;

/// Design modular fixtures for planar parts: every fixture of three round
/// locators and one sliding clamp on a lattice plate that holds the part in
/// form closure, ranked by quality (Brost & Goldberg 1996, as in SPEC.md).
///
/// Start with `fixplan run` (the bundled sample catalogue with the metric-25
/// kit, into results.mcap), then `fixplan show results.mcap` and
/// `fixplan render results.mcap --out pictures`.
#[derive(Parser)]
#[command(name = "fixplan", version, about, long_about)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Solve one part from a case file (SPEC Appendix A) and print the
    /// ranked fixtures as JSON. `params.top_k: 0` prints all of them.
    ///
    /// With `top_k > 0` (the default, 10) only candidates that could enter
    /// the top-k get a clamp mount search: the same fixtures, but the
    /// counts leave `admissible` out and say `"counts_exact": false`.
    /// `--full-counts` (or `params.full_counts: true`) counts them all.
    ///
    /// Exit code 0 for `ok` and `no_fixture`, 2 for `invalid`.
    Solve {
        /// Case file: units, part, access, kit, params.
        case: PathBuf,
        /// Count every admissible fixture (slower on big parts), as
        /// `params.full_counts: true` does.
        #[arg(long)]
        full_counts: bool,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
    },
    /// Design fixtures for every part of a catalogue and write the rankings
    /// to an MCAP file.
    ///
    /// Every part is solved in this process (no server), split into shards
    /// of its segment combinations exactly as distributed workers would do,
    /// so the results are the same bytes whatever the threads or shards.
    /// A broken part is reported as `invalid` with its message; the others
    /// go on. Results stream to OUT.partial part by part and the file is
    /// renamed to OUT when the run is complete; `--resume` continues a run
    /// that was interrupted (even by SIGKILL) without redoing finished parts.
    ///
    /// Exit code 0 when the run completed (whatever the parts' outcomes).
    Run {
        /// The catalogue: a `catalog.toml` manifest or a directory of part
        /// files. Default: the bundled sample catalogue
        /// (examples/catalog/catalog.toml).
        #[arg(long, value_name = "DIR|catalog.toml")]
        catalog: Option<PathBuf>,
        /// The kit: a built-in name (`paper-inch`, `metric-25`) or a kit TOML
        /// file. Its lengths are converted to the catalogue's unit (a kit
        /// file states its own `units`).
        #[arg(long, value_name = "NAME|kit.toml", default_value = "metric-25")]
        kit: String,
        /// Circular arcs of the parts (DXF bulges, ARC, CIRCLE, SVG circular
        /// arcs): `exact` (SPEC 8) or `flatten` (chords within the
        /// catalogue's chord tolerance, as before arcs, for comparison).
        /// Default: the manifest's `arcs`, else exact.
        #[arg(long, value_name = "exact|flatten")]
        arcs: Option<ArcMode>,
        /// Fixtures kept per part (0 keeps all). Default: the kit's
        /// parameters (10). A part's own `top_k` in the catalogue wins.
        #[arg(long, value_name = "N")]
        top_k: Option<usize>,
        /// Count every admissible fixture: search the clamp mount of every
        /// candidate. By default a run keeping a top-k (`--top-k` > 0)
        /// searches mounts only for candidates that could still enter it:
        /// the same fixtures, several times faster on big parts, but the
        /// admissible count is then left out (`"counts_exact": false`).
        /// Also `full_counts = true` in the kit's `[params]`.
        #[arg(long)]
        full_counts: bool,
        /// Threads (default: all cores). Results do not depend on it.
        #[arg(long, value_name = "N")]
        threads: Option<usize>,
        /// The results file (MCAP).
        #[arg(short, long, value_name = "FILE", default_value = "results.mcap")]
        output: PathBuf,
        /// Continue the interrupted run found in OUT.partial: its finished
        /// parts are kept, the others are solved. The catalogue, kit and
        /// parameters must be the same as when it started.
        #[arg(long)]
        resume: bool,
        /// Segment combinations per shard (default: from a cost estimate,
        /// about four shards per thread for big parts). Results do not
        /// depend on it.
        #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
        shard_size: Option<u64>,
        /// No progress display and no summary table.
        #[arg(short, long)]
        quiet: bool,
        /// Read every part file as a sheet: each outer loop a part of its
        /// own (`id#1`, `id#2`, ... by position: bottom edge, then left
        /// edge), whatever the manifest's `sheet` says. See
        /// docs/cad-files.md.
        #[arg(long)]
        sheet: bool,
        /// Loops drawn inside a part's outline: `keep` (its holes, SPEC 9:
        /// a locator may stand in a bore and push on its wall, a clamp may
        /// pass over a window, the metric weighs the material) or `ignore`
        /// (dropped with a warning each: the solid outline, as before
        /// holes, for comparison). Default: the manifest's `holes`, else
        /// keep.
        #[arg(long, value_name = "keep|ignore")]
        holes: Option<HoleMode>,
        #[command(flatten)]
        cluster: cluster::RunClusterArgs,
        #[command(flatten)]
        search: study::SearchArgs,
        /// Die on purpose (tests of the journal): abort-on:ID aborts the
        /// process when part ID's solve starts.
        #[arg(long, hide = true, value_name = "abort-on:ID")]
        fault: Option<fault::Fault>,
    },
    /// Compare kits on a catalogue: which kit to buy, which clamp to add.
    #[command(long_about = study::STUDY_HELP)]
    Study(study::StudyArgs),
    /// Coordinate a distributed run: shard every part of a catalogue over
    /// the workers that join (`fixplan worker`), verify and merge their
    /// results, and write the same results file as `fixplan run`.
    ///
    /// Workers pull shards over zenoh (iceoryx2 shared memory for workers
    /// on this host), may join or leave at any time, and a lost worker's
    /// shards are handed out again. See deploy/README.md.
    Coordinator(cluster::CoordinatorArgs),
    /// Make the certificates of mutual TLS: a CA (`ca.pem`, `ca-key.pem`),
    /// the coordinator's and a zenoh router's (`coordinator.pem`,
    /// `router.pem`), and N workers' (`worker-1.pem`...), each with its
    /// `-key.pem`, in DIR.
    ///
    /// Then: `fixplan coordinator --listen tls/0.0.0.0:7447 --tls-ca
    /// DIR/ca.pem --tls-cert DIR/coordinator.pem --tls-key
    /// DIR/coordinator-key.pem ...` and on each worker host `fixplan worker
    /// --connect tls/COORDINATOR-HOST:7447 --tls-ca ca.pem --tls-cert
    /// worker-1.pem --tls-key worker-1-key.pem`. Keep `ca-key.pem` off the
    /// cluster: it signs new certificates.
    #[cfg(feature = "tls")]
    Certs(cluster::CertsArgs),
    /// Work for a coordinator: `fixplan worker --connect tcp/HOST:7447`.
    ///
    /// Exits when the run is over (or stays with --stay); exit code 3 when
    /// the coordinator refuses it (e.g. another protocol version).
    Worker(cluster::WorkerArgs),
    /// Measure the cluster: catalogue throughput with 1 and 2 local workers,
    /// coordinator time and bytes per shard, zenoh vs iceoryx2 round trip.
    ///
    /// Per run: wall time from starting the workers to their exit, the
    /// speed-up over one worker, the steady part (first part out to last
    /// part out), and the coordinator process's CPU time as a share of the
    /// wall time. Run it on an otherwise idle machine; `--repeat 100` for
    /// figures where the start and stop of the run weigh little.
    BenchCluster(crate::bench::cluster::BenchArgs),
    /// Measure the coordinator's ceiling: parts/s and its CPU per part when
    /// workers cost nothing.
    ///
    /// Simulated workers (`--simulated-workers 1,8,64`, one thread each
    /// unless `--threads-per-worker`), in a process of their own, answer
    /// every shard (and every cut part's finishing) at once with its real
    /// result, computed in a warm-up run of the same catalogue and replayed
    /// in the measured run, over the transport of a real run. The
    /// `shards` column counts both. The coordinator is the `fixplan run
    /// --workers` path, results file included. Prints per count: wall time, parts/s, and the
    /// coordinator's CPU per part (this process's CPU). Profile it with
    /// `perf record -k CLOCK_MONOTONIC fixplan bench-coordinator
    /// --in-process ...` and the printed `perf report --time` window.
    BenchCoordinator(crate::bench::ceiling::CeilingArgs),
    /// Measure the enumeration per part on one thread: wall time, where it
    /// goes (setup enumeration, clamp placement, admissibility checks,
    /// metric) and pose solutions computed per setup kept (what the pruning
    /// wastes).
    ///
    /// Each part runs twice: with full counts (every candidate's mount
    /// searched: `fixtures` is the admissible count), then in top-k mode
    /// (`--top-k`, the default of `run` and `solve`), which must report the
    /// same first k fixtures. `scored` counts metric evaluations, `mounts`
    /// mount searches (clearance, plate fit), `floored` setups whose
    /// locators alone score worse than the k-th fixture.
    ///
    /// With no arguments: the bundled bench cases (examples/cases; the big
    /// ones of examples/cases/large take minutes).
    Bench(crate::bench::PartsBenchArgs),
    /// Print the ranked fixtures of a results file as tables.
    Show {
        /// A results file written by `fixplan run`.
        results: PathBuf,
        /// Only this part (its catalogue id).
        #[arg(long, value_name = "ID")]
        part: Option<String>,
        /// Rows per part (0: every kept fixture).
        #[arg(long, value_name = "N", default_value_t = 5)]
        top: usize,
    },
    /// Join the results files of a catalogue's slices (`fixplan
    /// coordinator --slice K/N`, one coordinator per slice) into the file
    /// one coordinator would have written: the same run, every part once.
    Merge {
        /// The slices' results files, in any order.
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// The merged results file.
        #[arg(short, long, value_name = "FILE")]
        output: PathBuf,
    },
    /// Print a results file as JSON lines, one per part:
    /// `{"part": ID, "status": ..., "counts": ..., "fixtures": [...]}`
    /// (the result format of SPEC Appendix A, plus contacts and plate
    /// placement per fixture).
    Export {
        /// A results file written by `fixplan run`.
        results: PathBuf,
        /// JSON lines on standard output (the only format so far).
        #[arg(long, required = true)]
        json: bool,
        /// Only this part (its catalogue id).
        #[arg(long, value_name = "ID")]
        part: Option<String>,
    },
    /// Draw the fixtures of a results file as SVG pictures, with an
    /// `index.html` gallery of all parts.
    ///
    /// Each picture shows the plate holes around the fixture (dowel holes
    /// filled, tapped holes dashed), the part in its pose, access regions
    /// hatched, the locators L1-L3, the clamp body and its plunger at its
    /// extension, the contact points with their inward normals, and the
    /// score and plate holes in the caption.
    Render {
        /// A results file written by `fixplan run`.
        results: PathBuf,
        /// Directory for the SVGs and index.html (created if needed).
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
        /// Only this part (its catalogue id).
        #[arg(long, value_name = "ID")]
        part: Option<String>,
        /// Pictures per part, best first (0: every kept fixture).
        #[arg(long, value_name = "N", default_value_t = 3)]
        top: usize,
    },
}

/// Runs the `fixplan` command line on this process's arguments and exits.
pub fn main() {
    if let Err(e) = real_main() {
        // `fixplan export ... | head` closes the pipe early: not an error.
        let broken_pipe = e.chain().any(|c| {
            c.downcast_ref::<std::io::Error>()
                .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
        });
        if broken_pipe {
            std::process::exit(0);
        }
        // The chain, without repeating a cause that a context already quotes.
        let mut msg = String::new();
        for cause in e.chain().map(|c| c.to_string()) {
            if !msg.contains(&cause) {
                if !msg.is_empty() {
                    msg.push_str(": ");
                }
                msg.push_str(&cause);
            }
        }
        eprintln!("fixplan: {msg}");
        std::process::exit(1);
    }
}

/// Whether the command asked for warnings only in its logs (`--quiet`;
/// `bench-cluster` always, its tables are the output).
fn quiet_logs(cmd: &Cmd) -> bool {
    match cmd {
        Cmd::Run { quiet, .. } => *quiet,
        Cmd::Study(a) => a.quiet,
        Cmd::Coordinator(a) => a.quiet,
        Cmd::Worker(a) => a.quiet,
        #[cfg(feature = "tls")]
        Cmd::Certs(_) => false,
        Cmd::BenchCluster(_) | Cmd::BenchCoordinator(_) => true,
        Cmd::Solve { .. }
        | Cmd::Bench(_)
        | Cmd::Show { .. }
        | Cmd::Export { .. }
        | Cmd::Merge { .. }
        | Cmd::Render { .. } => false,
    }
}

/// Where `fixplan run` solves: on its workers with `--workers` and the
/// like, else embedded.
fn run_backend(
    cluster: &cluster::RunClusterArgs,
    threads: Option<usize>,
    shard_size: Option<u64>,
) -> Backend {
    match cluster.options(threads) {
        Some(mut c) => {
            c.shard_size = shard_size;
            Backend::Cluster(c)
        }
        None => Backend::Embedded { threads },
    }
}

/// How `fixplan run` reads the catalogue: `--sheet` over the manifest.
/// How `fixplan run` reads the catalogue: `--sheet` and `--holes`.
fn run_load(sheet: bool, holes: Option<HoleMode>) -> LoadOptions {
    LoadOptions {
        sheet: sheet.then_some(true),
        holes,
        ..LoadOptions::default()
    }
}

/// `fixplan run --fault`: only the fault of a run in this process. They
/// act when a part's solve starts in this process, which never happens
/// with `--workers` (the workers solve): refused there rather than
/// silently doing nothing.
fn run_fault(fault: Option<fault::Fault>, backend: &Backend) -> Result<()> {
    if let (Some(fault), Backend::Cluster(_)) = (&fault, backend) {
        anyhow::bail!(
            "--fault {fault:?} acts on parts solved in this process; with --workers the workers \
             solve them (to kill a worker on a part: fixplan worker --fault abort-on-vertices:N)"
        );
    }
    match fault {
        None => Ok(()),
        Some(fault::Fault::AbortOn(id)) => {
            crate::run::journal::fault::abort_on(&id);
            Ok(())
        }
        Some(fault::Fault::StallOn(id)) => {
            crate::run::journal::fault::stall_on(&id);
            Ok(())
        }
        Some(other) => {
            anyhow::bail!("--fault {other:?} is a worker's fault (fixplan worker --fault)")
        }
    }
}

fn real_main() -> Result<()> {
    let cli = Cli::parse();
    // Once per process, before any work: library code only emits events.
    log::init(quiet_logs(&cli.cmd));
    match cli.cmd {
        Cmd::Solve {
            case,
            threads,
            full_counts,
        } => case_file::solve_main(&case, threads, full_counts)?,
        Cmd::Run {
            catalog,
            kit,
            arcs,
            top_k,
            full_counts,
            threads,
            output,
            resume,
            shard_size,
            quiet,
            sheet,
            holes,
            cluster,
            search,
            fault,
        } => {
            let backend = run_backend(&cluster, threads, shard_size);
            run_fault(fault, &backend)?;
            crate::interrupt::catch()?;
            load_and_run(
                &RunOptions {
                    catalog: catalog.unwrap_or_else(default_catalog),
                    kit,
                    top_k,
                    full_counts,
                    output,
                    resume,
                    shard_size,
                    quiet,
                    search: search.options(),
                    backend,
                    arcs,
                },
                &run_load(sheet, holes),
            )?;
        }
        Cmd::Study(a) => {
            study::study_cli_main(&a, default_catalog())?;
        }
        Cmd::Coordinator(a) => {
            crate::interrupt::catch()?;
            cluster::coordinator_main(&a, default_catalog())?;
        }
        Cmd::Worker(a) => cluster::worker_main(&a)?,
        #[cfg(feature = "tls")]
        Cmd::Certs(a) => cluster::certs_main(&a)?,
        Cmd::BenchCluster(a) => crate::bench::cluster::bench_main(&a)?,
        Cmd::BenchCoordinator(a) => crate::bench::ceiling::bench_main(&a)?,
        Cmd::Bench(a) => crate::bench::bench_main(&a)?,
        Cmd::Show { results, part, top } => {
            let stdout = std::io::stdout();
            crate::view::show::show(&results, part.as_deref(), top, &mut stdout.lock())?;
        }
        Cmd::Merge { files, output } => {
            let m = crate::run::slice::merge_files(&files, &output)?;
            eprintln!(
                "{} parts from {} files in {}",
                m.parts,
                m.files,
                output.display()
            );
        }
        Cmd::Export {
            results,
            json: _,
            part,
        } => {
            let stdout = std::io::stdout();
            crate::view::show::export_json(&results, part.as_deref(), &mut stdout.lock())?;
        }
        Cmd::Render {
            results,
            out,
            part,
            top,
        } => {
            let n = crate::view::render::render(&results, &out, part.as_deref(), top)?;
            eprintln!("{n} pictures and index.html in {}", out.display());
        }
    }
    Ok(())
}
