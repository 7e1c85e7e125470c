//! Catalogue runs: every part of a catalogue solved (in this process or by
//! a cluster, [`backend::Backend`]) and streamed in catalogue order into a
//! resumable MCAP results file, with progress and a summary.
//! Uses `job`, `cluster`, `output` and `view` (for the scene message).
//!
//! The file is written as `OUT.partial` and renamed to `OUT` when complete.
//! Parts are computed in parallel but written strictly in catalogue order,
//! one flushed chunk per part; so the bytes do not depend on timing, and the
//! complete chunks of a killed run's file are exactly a prefix of the
//! catalogue. `--resume` copies that prefix into a fresh file and carries
//! on.

pub(crate) mod backend;
pub(crate) mod cluster_jobs;
pub(crate) mod finish;
pub(crate) mod journal;
pub(crate) mod ordered;
pub(crate) mod outcome;
pub(crate) mod progress;
pub(crate) mod resume;
pub(crate) mod slice;
pub(crate) mod solve_in_order;

use crate::job::solve_part::Preparation;
use crate::job::{solve_guarded, JobContext, SearchOptions};
use crate::output::messages::{CatalogInfo, RunMsg};
use anyhow::{Context, Result};
use backend::{Backend, PartJob};
use fixplan_catalog::{load_catalog_with, load_kit, ArcMode, Catalog, KitSpec, LoadOptions};
use fixplan_core::Params;
use outcome::{part_outcome, OutcomeError, PartOutcome};
use progress::{progress_line, summary_table, Progress, Totals};
use solve_in_order::solve_in_order_finishing;
use std::path::{Path, PathBuf};

/// Everything a catalogue run needs besides the catalogue and the kit.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// Where the catalogue was read from (recorded in the file).
    pub catalog: PathBuf,
    /// The kit's name or file, as given.
    pub kit: String,
    /// Fixtures kept per part (default: the kit's parameters).
    pub top_k: Option<usize>,
    /// `--full-counts`: count every admissible fixture (no top-k mode),
    /// whatever the kit's parameters say.
    pub full_counts: bool,
    /// The results file.
    pub output: PathBuf,
    /// Continue the interrupted run in `OUT.partial`.
    pub resume: bool,
    /// Combinations per shard (default: from a cost estimate).
    pub shard_size: Option<u64>,
    /// No progress display and no summary table.
    pub quiet: bool,
    /// `--grid-steps` / `--good-enough`.
    pub search: SearchOptions,
    /// Threads of this process, or a cluster.
    pub backend: Backend,
    /// `--arcs`: circular arcs exact or flattened, over the manifest's
    /// `arcs` (default: the manifest's, else exact).
    pub arcs: Option<ArcMode>,
}

/// The built-in sample catalogue: `examples/catalog/catalog.toml` of the
/// current directory if there is one, else of the source tree this binary
/// was built from.
pub fn default_catalog() -> PathBuf {
    let rel = Path::new("examples/catalog/catalog.toml");
    if rel.is_file() {
        return rel.to_path_buf();
    }
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(rel)
}

/// Loads a catalogue with `--arcs` applied (`None`: as its manifest says).
pub fn load_catalog_arcs(path: &Path, arcs: Option<ArcMode>) -> Result<Catalog> {
    let opts = LoadOptions {
        arcs,
        ..LoadOptions::default()
    };
    Ok(load_catalog_with(path, &opts)?)
}

/// Loads `opts.catalog` (read with `load`, e.g. `--sheet`, and
/// `opts.arcs` over it) and `opts.kit`, then [`run_catalog`].
pub fn load_and_run(opts: &RunOptions, load: &LoadOptions) -> Result<Totals> {
    let load = LoadOptions {
        arcs: opts.arcs,
        ..*load
    };
    let catalog = load_catalog_with(&opts.catalog, &load)?;
    let spec = load_kit(&opts.kit, catalog.units)?;
    run_catalog(&catalog, &spec, opts)
}

/// The parameters of a run: the kit's with `--top-k` applied, and the
/// finest grid step as the run's step, so the fixtures channel holds the
/// same bytes as a plain run at that step.
fn run_params(spec: &KitSpec, opts: &RunOptions) -> Params {
    let mut params = spec.params.clone();
    if let Some(k) = opts.top_k {
        params.top_k = k;
    }
    params.full_counts |= opts.full_counts;
    params.grid_step = opts.search.final_step(params.grid_step);
    params
}

/// The `/fixplan/run` message of a run with `params` ([`run_params`]).
fn run_message(catalog: &Catalog, spec: &KitSpec, opts: &RunOptions, params: &Params) -> RunMsg {
    RunMsg {
        tool: "fixplan".into(),
        version: env!("CARGO_PKG_VERSION").into(),
        catalog: CatalogInfo::of(catalog, &opts.catalog),
        kit_name: spec.name.clone(),
        kit: (&spec.kit).into(),
        params: params.into(),
        grid_steps: opts.search.grid_steps.clone(),
        good_enough: opts.search.good_enough,
        budgets: crate::output::messages::BudgetsField::of(&opts.search),
    }
}

/// Runs a catalogue with a kit into the results file: the one way into a
/// run (`fixplan run`, `run --workers`, `fixplan coordinator`). Returns the
/// totals, also printed as a table unless quiet.
pub fn run_catalog(catalog: &Catalog, spec: &KitSpec, opts: &RunOptions) -> Result<Totals> {
    run_parts(catalog, spec, opts, 0..catalog.parts.len())
}

/// [`run_catalog`] of the catalogue's parts `parts` only (`fixplan
/// coordinator --slice`): the file holds them under their places in the
/// whole catalogue, after the whole run's message, so `fixplan merge` of
/// the slices' files is the whole run's file.
pub fn run_parts(
    catalog: &Catalog,
    spec: &KitSpec,
    opts: &RunOptions,
    parts: std::ops::Range<usize>,
) -> Result<Totals> {
    fixplan_core::validate_kit(&spec.kit).with_context(|| format!("kit {}", spec.name))?;
    opts.search.validate()?;
    let params = run_params(spec, opts);
    let run_msg = run_message(catalog, spec, opts, &params);
    let n = parts.len();
    let mut progress = Progress::new(n, opts.quiet);
    progress.log(&format!(
        "fixplan run: {} parts of {} ({}) with kit {} on {} threads",
        n,
        catalog.name,
        opts.catalog.display(),
        spec.name,
        opts.backend.threads()
    ));
    let run_parts = resume::RunParts {
        message: &run_msg,
        parts: parts.clone(),
        ids: catalog.parts.iter().map(|p| p.id.as_str()).collect(),
    };
    let (mut writer, start) =
        resume::open_output(&opts.output, opts.resume, &run_parts, &mut progress)?;
    let journal = open_journal(opts, &run_parts, start)?;
    let ctx = JobContext {
        kit: &spec.kit,
        params: &params,
        units: catalog.units,
        shard_size: opts.shard_size,
        search: &opts.search,
    };
    let jobs: Vec<PartJob> = catalog.parts[start..parts.end]
        .iter()
        .map(|part| PartJob {
            part,
            ctx: &ctx,
            preparation: Preparation::Fresh,
        })
        .collect();
    let partial = resume::partial_path(&opts.output);
    // Held while a chunk is written: a signal's last words wait for it.
    let writing = std::sync::Arc::new(std::sync::Mutex::new(()));
    let _last_words =
        crate::interrupt::LastWords::say(interrupted_words(journal.as_ref(), &writing, &partial));
    let context = |i: usize| finish::context(start + i, jobs[i].part);
    let keep = |i: usize, bytes| {
        finish::outcome(bytes, start + i, jobs[i].part).or_else(|e| {
            // Never from a fixplan worker of this version: solved here
            // rather than lost.
            tracing::warn!(
                role = "coordinator",
                "{}: a worker's finished part is unusable ({e}); solving it here",
                jobs[i].part.id
            );
            let s = solve_guarded(&ctx, jobs[i].part, Preparation::Fresh);
            part_outcome(&ctx, start + i, jobs[i].part, s)
        })
    };
    let remote = backend::RemoteFinish {
        context: &context,
        finisher: std::sync::Arc::new(finish::RunFinisher),
        keep: &keep,
    };
    let solved = solve_in_order_finishing(
        &jobs,
        &opts.backend,
        Some(&remote),
        journal.as_ref().map(|j| j as &dyn journal::Watch),
        |i, s| part_outcome(&ctx, start + i, jobs[i].part, s),
        |_, out: Result<PartOutcome, OutcomeError>| {
            let o = out.with_context(|| format!("writing {}", partial.display()))?;
            let _writing = writing.lock().unwrap_or_else(|e| e.into_inner());
            writer
                .write_chunk(&o.chunk)
                .with_context(|| format!("writing {}", partial.display()))?;
            if let Some(line) = progress_line(&o) {
                progress.log(&line);
            }
            progress.part_done(&o);
            Ok(())
        },
    );
    progress.finish();
    solved?;
    resume::close_output(writer, &opts.output)?;
    if let Some(j) = journal {
        j.remove();
    }
    let totals = progress.totals.clone();
    if !opts.quiet {
        // `?`, not `print!`: a closed stdout (`| head`) is an error the
        // command line ends quietly on, not a panic.
        let table = summary_table(
            &totals,
            progress.elapsed(),
            &opts.output.display().to_string(),
        );
        std::io::Write::write_all(&mut std::io::stdout(), table.as_bytes())?;
    }
    Ok(totals)
}

/// The parts in flight, for the next resume: in this process only (a
/// cluster's workers solve elsewhere). Job 0 is catalogue part `start`.
fn open_journal(
    opts: &RunOptions,
    run_parts: &resume::RunParts,
    start: usize,
) -> Result<Option<journal::Journal>> {
    Ok(match opts.backend {
        Backend::Embedded { .. } => {
            let mut j = journal::Journal::open(
                &opts.output,
                run_parts.message,
                &run_parts.ids,
                opts.resume,
            )?;
            j.set_first(start);
            Some(j)
        }
        Backend::Cluster(_) => None,
    })
}

/// What a run says when a signal stops it ([`crate::interrupt`]): the journal's
/// `end interrupted`, no chunk cut in half (the lock on `writing` is kept
/// until the process ends), and how to go on.
fn interrupted_words(
    journal: Option<&journal::Journal>,
    writing: &std::sync::Arc<std::sync::Mutex<()>>,
    partial: &Path,
) -> impl Fn() + Send + 'static {
    let journal = journal.map(journal::Journal::interrupted_words);
    let writing = std::sync::Arc::clone(writing);
    let partial = partial.display().to_string();
    move || {
        std::mem::forget(writing.lock().unwrap_or_else(|e| e.into_inner()));
        if let Some(words) = &journal {
            words();
        }
        eprintln!(
            "fixplan: run interrupted; {partial} keeps the parts written so far: resume with the same command and --resume"
        );
    }
}
