//! `fixplan run`: every part of a catalogue, in-process, streamed part by
//! part into an MCAP results file, resumable after a kill.
//!
//! The file is written as `OUT.partial` and renamed to `OUT` when complete.
//! Parts are computed in parallel (a few in flight, each split into shards
//! on the rayon pool) but written strictly in catalogue order, one flushed
//! chunk per part; so the bytes do not depend on timing, and the complete
//! chunks of a killed run's file are exactly a prefix of the catalogue.
//! `--resume` copies that prefix into a fresh file and carries on.

use crate::mcap_out::ResultsWriter;
use crate::messages::{CatalogInfo, PartMsg, RunMsg};
use crate::part_job::{run_part, JobContext, PartOutcome};
use crate::progress::{summary_table, Progress, Totals};
use crate::refine::SearchOptions;
use crate::results::{ReadError, ResultsFile};
use anyhow::{bail, Context, Result};
use fixplan_catalog::{load_catalog, load_kit, Catalog, KitSpec};
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{mpsc, Condvar, Mutex};

/// Everything `fixplan run` needs (the CLI fills it in).
#[derive(Debug, Clone)]
pub struct RunOptions {
    pub catalog: PathBuf,
    pub kit: String,
    pub top_k: Option<usize>,
    pub threads: Option<usize>,
    pub output: PathBuf,
    pub resume: bool,
    pub shard_size: Option<u64>,
    pub quiet: bool,
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

/// `OUT.partial`: where an unfinished run writes.
pub fn partial_path(output: &Path) -> PathBuf {
    let mut s = output.as_os_str().to_owned();
    s.push(".partial");
    PathBuf::from(s)
}

/// What the run and study channels say of the catalogue.
pub fn catalog_info(catalog: &Catalog, source: &Path) -> CatalogInfo {
    CatalogInfo {
        name: catalog.name.clone(),
        source: source.display().to_string(),
        units: catalog.units,
        parts: catalog.parts.len(),
        digest: catalog_digest(catalog),
    }
}

/// `sha256:` of the catalogue's content, independent of where it lives.
pub fn catalog_digest(c: &Catalog) -> String {
    let mut h = Sha256::new();
    h.update(format!("units={:?}\n", c.units));
    for p in &c.parts {
        let part = match &p.part {
            Ok(part) => serde_json::json!({"ok": part}),
            Err(e) => serde_json::json!({"err": e.to_string()}),
        };
        let entry = serde_json::json!({"id": p.id, "part": part, "quantity": p.quantity,
            "top_k": p.top_k, "wrenches": p.wrenches});
        h.update(entry.to_string());
        h.update(b"\n");
    }
    let d = h.finalize();
    let hex: String = d.iter().map(|b| format!("{b:02x}")).collect();
    format!("sha256:{hex}")
}

fn outcome_of_message(m: &crate::mcap_out::PartMessages) -> Option<PartMsg> {
    serde_json::from_slice(&m.part).ok()
}

/// Copies the finished parts of an interrupted run into a new writer.
/// Returns the writer and the index of the first part still to do.
fn resume_from(
    partial: &Path,
    run_msg: &RunMsg,
    progress: &mut Progress,
) -> Result<Option<(ResultsWriter, usize)>> {
    let old = match ResultsFile::open(partial) {
        Ok(f) => f,
        Err(e) => bail!("{e}"),
    };
    let mut new_path = partial.as_os_str().to_owned();
    new_path.push(".new");
    let new_path = PathBuf::from(new_path);
    let file = File::create(&new_path)
        .with_context(|| format!("{}: cannot create", new_path.display()))?;
    let mut w = ResultsWriter::create(file, run_msg)?;
    let mut next = 0usize;
    let mut mismatch = false;
    let mut write_err = None;
    let read = old.for_each_part(|run, m| {
        if !run.same_run(run_msg) {
            mismatch = true;
            return false;
        }
        if m.index != next {
            return false;
        }
        if let Err(e) = w.write_part(&m) {
            write_err = Some(e);
            return false;
        }
        if let Some(p) = outcome_of_message(&m) {
            progress.resumed(p.status, p.counts.map_or(0, |c| c.admissible), p.fixtures);
        }
        next += 1;
        true
    });
    match read {
        Err(ReadError::Format { message, .. }) => {
            progress.log(&format!(
                "{}: nothing usable to resume ({message}); starting from the beginning",
                partial.display()
            ));
            let _ = std::fs::remove_file(&new_path);
            return Ok(None);
        }
        Err(e) => return Err(e.into()),
        Ok(_) => {}
    }
    if mismatch {
        let _ = std::fs::remove_file(&new_path);
        bail!(
            "{} was written by a different run (catalogue content, kit, parameters or fixplan version differ); \
             delete it or run without --resume",
            partial.display()
        );
    }
    if let Some(e) = write_err {
        return Err(e.into());
    }
    std::fs::rename(&new_path, partial).with_context(|| {
        format!(
            "cannot rename {} to {}",
            new_path.display(),
            partial.display()
        )
    })?;
    progress.log(&format!(
        "resuming {}: {next} parts already done",
        partial.display()
    ));
    Ok(Some((w, next)))
}

/// Runs the whole catalogue; returns the totals (also printed as a table).
pub fn run(opts: &RunOptions) -> Result<Totals> {
    let catalog = load_catalog(&opts.catalog)?;
    let spec = load_kit(&opts.kit, catalog.units)?;
    run_loaded(&catalog, &spec, opts)
}

/// [`run`] on a catalogue and kit already loaded (`opts.catalog` and
/// `opts.kit` are only recorded).
pub fn run_loaded(catalog: &Catalog, spec: &KitSpec, opts: &RunOptions) -> Result<Totals> {
    run_loaded_with(catalog, spec, opts, None)
}

/// [`run_loaded`], with the parts solved by the workers of a cluster
/// (`fixplan coordinator`, `fixplan run --workers N`) when `cluster` is
/// given: the same file, byte for byte in the fixture channel.
pub fn run_loaded_with(
    catalog: &Catalog,
    spec: &KitSpec,
    opts: &RunOptions,
    cluster: Option<&crate::cluster::ClusterOptions>,
) -> Result<Totals> {
    run_loaded_search(catalog, spec, opts, cluster, &SearchOptions::default())
}

/// [`run`] with `--grid-steps` / `--good-enough`.
pub fn run_search(opts: &RunOptions, search: &SearchOptions) -> Result<Totals> {
    let catalog = load_catalog(&opts.catalog)?;
    let spec = load_kit(&opts.kit, catalog.units)?;
    run_loaded_search(&catalog, &spec, opts, None, search)
}

/// [`run_loaded_with`] with `--grid-steps` / `--good-enough`: the run's
/// `grid_step` becomes the finest step, so the fixtures channel holds the
/// same bytes as a plain run at that step; the part channel gets the
/// per-step summary (`refine`) and the early stop (`stopped`,
/// `stopped_at`).
pub fn run_loaded_search(
    catalog: &Catalog,
    spec: &KitSpec,
    opts: &RunOptions,
    cluster: Option<&crate::cluster::ClusterOptions>,
    search: &SearchOptions,
) -> Result<Totals> {
    fixplan_core::prepare::validate_kit(&spec.kit).with_context(|| format!("kit {}", spec.name))?;
    search.validate()?;
    let mut params = spec.params.clone();
    if let Some(k) = opts.top_k {
        params.top_k = k;
    }
    params.grid_step = search.final_step(params.grid_step);
    let run_msg = RunMsg {
        tool: "fixplan".into(),
        version: env!("CARGO_PKG_VERSION").into(),
        catalog: catalog_info(catalog, &opts.catalog),
        kit_name: spec.name.clone(),
        kit: spec.kit.clone(),
        params: params.clone(),
        grid_steps: search.grid_steps.clone(),
        good_enough: search.good_enough,
    };
    let threads = opts.threads.unwrap_or_else(|| {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    });
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("cannot start the thread pool")?;
    let n = catalog.parts.len();
    let mut progress = Progress::new(n, opts.quiet);
    progress.log(&format!(
        "fixplan run: {} parts of {} ({}) with kit {} on {threads} threads",
        n,
        catalog.name,
        opts.catalog.display(),
        spec.name
    ));
    let partial = partial_path(&opts.output);
    let resumed = if opts.resume && partial.exists() {
        resume_from(&partial, &run_msg, &mut progress)?
    } else {
        if opts.resume {
            progress.log(&format!(
                "no interrupted run at {}; starting from the beginning",
                partial.display()
            ));
        } else if partial.exists() {
            progress.log(&format!(
                "overwriting the interrupted run at {} (use --resume to continue it)",
                partial.display()
            ));
        }
        None
    };
    let (mut writer, start) = match resumed {
        Some(r) => r,
        None => {
            let file = File::create(&partial)
                .with_context(|| format!("{}: cannot create", partial.display()))?;
            (ResultsWriter::create(file, &run_msg)?, 0)
        }
    };

    let ctx = JobContext {
        kit: &spec.kit,
        params: &params,
        units: catalog.units,
        shard_size: opts.shard_size,
        search,
    };
    // Parts in flight at once: enough to keep the pool busy on small parts,
    // few enough that finished parts waiting for a slow one stay bounded.
    let drivers = threads.max(1);
    let window = 2 * drivers + 2;
    let next = AtomicUsize::new(start);
    let abort = AtomicBool::new(false);
    let gate = (Mutex::new(start), Condvar::new());
    let (tx, rx) = mpsc::channel::<(usize, Result<PartOutcome, serde_json::Error>)>();
    let mut failure: Option<anyhow::Error> = None;
    let jobs = match cluster {
        Some(c) => Some(crate::cluster::catalog_run::start(
            &ctx,
            &catalog.parts,
            start,
            c,
        )?),
        None => None,
    };
    std::thread::scope(|s| {
        if let Some(jobs) = jobs {
            let (tx, ctx, parts) = (tx.clone(), &ctx, &catalog.parts);
            s.spawn(move || jobs.deliver(ctx, parts, &tx));
        }
        for _ in 0..if cluster.is_some() { 0 } else { drivers } {
            let tx = tx.clone();
            let (next, abort, gate, pool, ctx, parts) =
                (&next, &abort, &gate, &pool, &ctx, &catalog.parts);
            s.spawn(move || loop {
                let i = next.fetch_add(1, Ordering::SeqCst);
                if i >= n {
                    break;
                }
                {
                    let mut written = gate.0.lock().unwrap_or_else(|e| e.into_inner());
                    while i >= *written + window && !abort.load(Ordering::SeqCst) {
                        written = gate.1.wait(written).unwrap_or_else(|e| e.into_inner());
                    }
                }
                if abort.load(Ordering::SeqCst) {
                    break;
                }
                let out = pool.install(|| run_part(ctx, i, &parts[i]));
                if tx.send((i, out)).is_err() {
                    break;
                }
            });
        }
        drop(tx);
        // However this loop ends (even by a panic), the drivers must not be
        // left waiting at the gate, or the scope would never close.
        struct Release<'a>(&'a AtomicBool, &'a Condvar);
        impl Drop for Release<'_> {
            fn drop(&mut self) {
                self.0.store(true, Ordering::SeqCst);
                self.1.notify_all();
            }
        }
        let _release = Release(&abort, &gate.1);
        let mut pending = BTreeMap::new();
        let mut expected = start;
        'recv: for (i, out) in rx.iter() {
            pending.insert(i, out);
            while let Some(out) = pending.remove(&expected) {
                let res = out.map_err(anyhow::Error::from).and_then(|o| {
                    writer
                        .write_part(&o.messages)
                        .map(|_| o)
                        .map_err(anyhow::Error::from)
                });
                match res {
                    Ok(o) => {
                        if let Some(line) = crate::refine::progress_line(&o) {
                            progress.log(&line);
                        }
                        progress.part_done(&o)
                    }
                    Err(e) => {
                        failure = Some(e.context(format!("writing {}", partial.display())));
                        abort.store(true, Ordering::SeqCst);
                        gate.1.notify_all();
                        break 'recv;
                    }
                }
                expected += 1;
                *gate.0.lock().unwrap_or_else(|e| e.into_inner()) = expected;
                gate.1.notify_all();
            }
        }
    });
    progress.finish();
    if let Some(e) = failure {
        return Err(e);
    }
    let file = writer
        .finish()
        .with_context(|| format!("finishing {}", partial.display()))?;
    file.sync_all().ok();
    drop(file);
    std::fs::rename(&partial, &opts.output).with_context(|| {
        format!(
            "cannot rename {} to {}",
            partial.display(),
            opts.output.display()
        )
    })?;
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
