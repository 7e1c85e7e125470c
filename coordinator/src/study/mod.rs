//! `fixplan study`: a catalogue against several kits (listed, and each
//! listed kit crossed with every point of a `--sweep`), to decide which kit
//! to buy or which clamp to add. Uses `run`, `job`, `output`, `view` (SVG
//! escaping) and the cluster options; nothing but `cli` and `bench` uses it.
//!
//! A study goes: [`kits`] (which kits), [`sharing`] (which work is shared,
//! and why that is exact), [`engine`] (the rest solved through the run
//! path), [`stats`] (each kit's message), then out as [`report`] (table,
//! CSV), [`chart`] (SVG) and [`mod@file`] (MCAP, [`messages`] and schemas).

pub(crate) mod chart;
pub(crate) mod engine;
pub(crate) mod file;
pub(crate) mod kits;
pub(crate) mod messages;
pub(crate) mod report;
pub(crate) mod sharing;
pub(crate) mod stats;
pub(crate) mod sweep;

pub use file::read_mcap;
pub use kits::{study_kits, StudyKit};
pub use messages::{StudyKitMsg, StudyReport};
pub use stats::{median, nearest_rank};

use crate::cluster::ClusterOptions;
use crate::run::backend::Backend;
use anyhow::{Context, Result};
use fixplan_catalog::{ArcMode, Catalog};
use sharing::{Rows, SharePlan};
use stats::{kit_messages, summary, StudyWork};
use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

/// Everything `fixplan study` needs.
#[derive(Debug, Clone)]
pub struct StudyOptions {
    /// The catalogue file (or the built-in one the command line defaults to).
    pub catalog: PathBuf,
    /// Kit names or files, in order.
    pub kits: Vec<String>,
    /// `--sweep`: kit variants around each listed kit ([`sweep`] grammar).
    pub sweep: Option<String>,
    /// Fixtures kept per part (default 1: the statistics need only the best
    /// one, and the counts and best score do not depend on top-k).
    pub top_k: Option<usize>,
    /// `--part-fixtures`: a (kit, part) keeping more fixtures is
    /// `over_budget`.
    pub part_fixtures: Option<u64>,
    /// Count admissible fixtures exactly (off: top-k mode).
    pub full_counts: bool,
    /// Threads of an embedded study (default: all cores).
    pub threads: Option<usize>,
    /// Where to write the study as MCAP.
    pub output: Option<PathBuf>,
    /// Where to write the CSV.
    pub csv: Option<PathBuf>,
    /// Where to write the SVG chart.
    pub chart: Option<PathBuf>,
    /// Solve every (kit, part) on its own (to check the sharing).
    pub no_share: bool,
    /// No progress line and no table (the files only).
    pub quiet: bool,
    /// `--arcs`: circular arcs exact or flattened (default: the manifest's).
    pub arcs: Option<ArcMode>,
}

/// Runs a study on a catalogue already loaded; `cluster` sends the work to
/// workers (`--workers N`).
pub fn run_study(
    catalog: &Catalog,
    kits: &[StudyKit],
    opts: &StudyOptions,
    cluster: Option<&ClusterOptions>,
) -> Result<StudyReport> {
    let t0 = Instant::now();
    let params = kits::solve_params(kits, opts.top_k, opts.full_counts);
    let plan = SharePlan::new(kits, &params, !opts.no_share);
    let backend = match cluster {
        Some(c) => Backend::Cluster(c.clone()),
        None => Backend::Embedded {
            threads: opts.threads,
        },
    };
    let search = crate::job::SearchOptions {
        part_fixtures: opts.part_fixtures,
        ..crate::job::SearchOptions::default()
    };
    let mut engine = engine::Engine::new(catalog, kits, &params, backend, search);
    let np = catalog.parts.len();
    let mut rows = Rows::new(kits.len(), np);
    // Phase 1: the kits no other kit has a larger plate than.
    let jobs = plan.first_jobs(np);
    rows.fill(&jobs, engine.solve(&jobs)?);
    // Phase 2: the others, but for the parts their larger plate has no
    // fixture for.
    let (jobs, shared_larger_plate) = plan.copy_no_fixture(&mut rows, kits);
    rows.fill(&jobs, engine.solve(&jobs)?);
    let shared_same_kit = plan.copy_same_kits(&mut rows, kits);
    let msgs = kit_messages(catalog, kits, &params, rows.into_kits());
    let work = StudyWork {
        part_runs: kits.len() * np,
        shared_same_kit,
        shared_larger_plate,
        prepares: engine.prepares(),
    };
    let summary = summary(
        catalog,
        &opts.catalog,
        kits,
        &msgs,
        work,
        cluster.map(|c| c.local_workers),
        t0.elapsed().as_secs_f64() * 1e3,
    );
    Ok(StudyReport {
        kits: msgs,
        summary,
    })
}

/// `fixplan study`: loads, runs, writes every output asked for.
pub fn study_main(opts: &StudyOptions, cluster: Option<&ClusterOptions>) -> Result<StudyReport> {
    let catalog = crate::run::load_catalog_arcs(&opts.catalog, opts.arcs)?;
    let kits = study_kits(&opts.kits, opts.sweep.as_deref(), catalog.units)?;
    if !opts.quiet {
        eprintln!(
            "fixplan study: {} parts of {} against {} kits{}",
            catalog.parts.len(),
            catalog.name,
            kits.len(),
            cluster.map_or(String::new(), |c| format!(
                " on {} workers",
                c.local_workers
            ))
        );
    }
    let rep = run_study(&catalog, &kits, opts, cluster)?;
    write_outputs(opts, &rep)?;
    if !opts.quiet {
        let mut out = std::io::stdout().lock();
        out.write_all(report::table(&rep).as_bytes())?;
        for (what, p) in [
            ("results", &opts.output),
            ("CSV", &opts.csv),
            ("chart", &opts.chart),
        ] {
            if let Some(p) = p {
                writeln!(out, "{what}: {}", p.display())?;
            }
        }
    }
    Ok(rep)
}

/// The files asked for: MCAP, CSV, chart.
fn write_outputs(opts: &StudyOptions, rep: &StudyReport) -> Result<()> {
    if let Some(p) = &opts.output {
        file::write_mcap(p, rep)?;
    }
    if let Some(p) = &opts.csv {
        std::fs::write(p, report::csv(rep))
            .with_context(|| format!("{}: cannot write", p.display()))?;
    }
    if let Some(p) = &opts.chart {
        std::fs::write(p, chart::chart_svg(rep))
            .with_context(|| format!("{}: cannot write", p.display()))?;
    }
    Ok(())
}
