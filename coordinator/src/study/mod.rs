//! `fixplan study`: a catalogue against several kits (listed, and each
//! listed kit crossed with every point of a `--sweep`), to decide which kit
//! to buy or which clamp to add.
//!
//! Every (kit, part) goes through the per-part path of `fixplan run`
//! ([`crate::run::solve::solve_in_order`] in this process, or the workers of
//! [`crate::cluster::run_distributed`] with `--workers N`), so a study scales out
//! like a run. Work is shared only where that is provably exact:
//!
//! - **the same kit twice** (a sweep point equal to a listed kit): solved
//!   once, the result copied;
//! - **prepared parts**: segments, pair bounds and the metric depend on the
//!   part, the lattice spacing, the locator radius, the edge trim and the
//!   wrenches only. They are prepared once per such key and the plate,
//!   clamp, angle, clearance, grid step and top-k come from
//!   [`PreparedPart::with_kit`] (the core's own conversion, which checks
//!   the key's fields and is tested equal to a fresh `prepare`);
//! - **no fixture on a larger plate**: the plate size enters SPEC only in
//!   the last admissibility test (the fixture fits the `cols x rows` holes),
//!   and what fits a plate fits any plate at least as large in both
//!   directions. So a candidate admissible on the smaller plate is
//!   admissible on the larger one (maybe with an earlier mount), and a part
//!   that has no fixture on the larger plate has none on the smaller: its
//!   result there (counts included, which do not depend on the plate) is
//!   copied without enumerating. Kits whose plate is not dominated are
//!   solved first, the others second.
//!
//! A part's best score and its fixtures on a smaller plate are *not* derived
//! from the larger plate's: the clamp mount is the first (smallest travel)
//! one that passes every test, the plate test included, so a fixture may
//! take another mount on a smaller plate, and the top-k may differ.

pub mod sweep;

use crate::cluster::ClusterOptions;
use crate::job::solve::Preparation;
use crate::job::{part_params, JobContext, SearchOptions};
use crate::output::messages::CatalogInfo;
use crate::run::backend::{Backend, PartJob};
use crate::run::solve::solve_in_order;
use sweep::{apply, point_label, Sweep};

use anyhow::{bail, Context, Result};
use fixplan_catalog::{load_catalog, load_kit, Catalog, KitSpec};
use fixplan_core::{
    prepare, Counts, Kit, Params, PrepareError, PreparedPart, SolveResult, Status, Units,
};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::time::Instant;

pub const TOPIC_STUDY: &str = "/fixplan/study";
pub const TOPIC_STUDY_SUMMARY: &str = "/fixplan/study_summary";
pub const SCHEMA_STUDY: &str = "fixplan.StudyKit";
pub const SCHEMA_STUDY_SUMMARY: &str = "fixplan.StudySummary";

/// Everything `fixplan study` needs.
#[derive(Debug, Clone)]
pub struct StudyOptions {
    pub catalog: PathBuf,
    /// Kit names or files, in order.
    pub kits: Vec<String>,
    pub sweep: Option<String>,
    /// Fixtures kept per part (default 1: the statistics need only the best
    /// one, and the counts and best score do not depend on top-k).
    pub top_k: Option<usize>,
    pub threads: Option<usize>,
    pub output: Option<PathBuf>,
    pub csv: Option<PathBuf>,
    pub chart: Option<PathBuf>,
    /// Solve every (kit, part) on its own (to check the sharing).
    pub no_share: bool,
    pub quiet: bool,
}

/// One kit of a study.
#[derive(Debug, Clone)]
pub struct StudyKit {
    pub spec: KitSpec,
    /// The listed kit it comes from.
    pub base: String,
    /// The sweep point applied, if any.
    pub sweep: Option<String>,
}

/// The result of one part with one kit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StudyPartRow {
    pub id: String,
    pub status: Status,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    pub quantity: f64,
    pub counts: Option<Counts>,
    pub best_score: Option<f64>,
    /// Wall time of prepare + enumeration (0 when shared).
    pub ms: f64,
    /// How the result was obtained without enumerating, if it was.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shared: Option<String>,
}

/// `/fixplan/study`: one message per kit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StudyKitMsg {
    pub index: usize,
    pub name: String,
    pub base: String,
    pub sweep: Option<String>,
    pub kit: Kit,
    pub params: Params,
    pub parts: usize,
    pub held: usize,
    /// Share of parts held, percent.
    pub held_pct: f64,
    /// Share of parts held weighted by `quantity` (parts per year), percent.
    pub held_quantity_pct: f64,
    /// Median best score over the parts held (mean of the two middle ones
    /// for an even count).
    pub median_score: Option<f64>,
    /// 90th percentile (nearest rank) of the best score over the parts held.
    pub p90_score: Option<f64>,
    pub no_fixture: usize,
    pub invalid: usize,
    /// Sum of the parts' solve times (prepare + enumerate), milliseconds; in
    /// a distributed study, the time between result deliveries.
    pub time_ms: f64,
    /// Parts enumerated for this kit, and parts whose result was shared.
    pub enumerated: usize,
    pub shared: usize,
    pub results: Vec<StudyPartRow>,
}

/// `/fixplan/study_summary`: once, at the end.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StudySummaryMsg {
    pub tool: String,
    pub version: String,
    pub catalog: CatalogInfo,
    pub kits: Vec<String>,
    /// Parts no kit of the study holds, with their status per kit.
    pub unheld: Vec<String>,
    pub part_runs: usize,
    pub enumerated: usize,
    pub shared_same_kit: usize,
    pub shared_larger_plate: usize,
    /// Distinct prepared geometries (embedded studies).
    pub prepares: usize,
    pub workers: Option<usize>,
    pub elapsed_ms: f64,
}

/// What a study found.
#[derive(Debug, Clone)]
pub struct StudyReport {
    pub kits: Vec<StudyKitMsg>,
    pub summary: StudySummaryMsg,
}

/// The kits of a study: each listed kit, then each listed kit crossed with
/// every sweep point.
pub fn study_kits(names: &[String], sweep: Option<&str>, units: Units) -> Result<Vec<StudyKit>> {
    if names.is_empty() {
        bail!("fixplan study needs at least one --kit");
    }
    let sweep = sweep.map(|s| Sweep::parse(s, units)).transpose()?;
    let mut out = Vec::new();
    let mut bases = Vec::new();
    for n in names {
        let spec = load_kit(n, units)?;
        fixplan_core::prepare::validate_kit(&spec.kit)
            .with_context(|| format!("kit {}", spec.name))?;
        out.push(StudyKit {
            base: spec.name.clone(),
            sweep: None,
            spec: spec.clone(),
        });
        bases.push(spec);
    }
    if let Some(sw) = &sweep {
        for b in &bases {
            for p in sw.points() {
                out.push(StudyKit {
                    spec: apply(b, &p)?,
                    base: b.name.clone(),
                    sweep: Some(point_label(&p)),
                });
            }
        }
    }
    Ok(out)
}

fn config_key(kit: &Kit, params: &Params) -> String {
    serde_json::json!({"kit": kit, "params": params}).to_string()
}

fn plate_free_key(kit: &Kit, params: &Params) -> String {
    let mut k = kit.clone();
    k.cols = 0;
    k.rows = 0;
    config_key(&k, params)
}

/// What prepared segments depend on (SPEC section 2 and the metric).
fn geometry_key(part: usize, kit: &Kit, params: &Params, units: Units) -> String {
    serde_json::json!({"part": part, "spacing": kit.spacing, "r": kit.locator_radius,
        "trim": params.edge_trim_or_default(units), "wrenches": params.wrenches})
    .to_string()
}

/// Percentiles as documented on [`StudyKitMsg`].
pub fn median(sorted: &[f64]) -> Option<f64> {
    let n = sorted.len();
    match n {
        0 => None,
        _ if n % 2 == 1 => Some(sorted[n / 2]),
        _ => Some((sorted[n / 2 - 1] + sorted[n / 2]) / 2.0),
    }
}

pub fn nearest_rank(sorted: &[f64], pct: f64) -> Option<f64> {
    let n = sorted.len();
    if n == 0 {
        return None;
    }
    let rank = ((pct / 100.0) * n as f64).ceil().max(1.0) as usize;
    Some(sorted[rank.min(n) - 1])
}

fn row_of(id: &str, quantity: f64, r: &SolveResult, ms: f64) -> StudyPartRow {
    StudyPartRow {
        id: id.to_string(),
        status: r.status,
        error: r.error.clone(),
        quantity,
        counts: r.counts,
        best_score: r.fixtures.first().map(|f| f.score),
        ms,
        shared: None,
    }
}

/// One (kit, part) to solve.
#[derive(Debug, Clone, Copy)]
struct Job {
    kit: usize,
    part: usize,
}

struct Engine<'a> {
    catalog: &'a Catalog,
    kits: &'a [StudyKit],
    params: Vec<Params>,
    backend: Backend,
    prepares: usize,
}

impl Engine<'_> {
    /// Solves the jobs through the run path: rows in job order.
    fn solve(&mut self, jobs: &[Job]) -> Result<Vec<StudyPartRow>> {
        let units = self.catalog.units;
        let parts = &self.catalog.parts;
        let search = SearchOptions::default();
        let ctxs: Vec<JobContext> = (0..self.kits.len())
            .map(|k| JobContext {
                kit: &self.kits[k].spec.kit,
                params: &self.params[k],
                units,
                shard_size: None,
                search: &search,
            })
            .collect();
        let bases = match self.backend {
            Backend::Embedded { threads } => {
                let bases = self.prepare_bases(jobs, &ctxs, threads)?;
                self.prepares += bases.len();
                bases
            }
            Backend::Cluster(_) => HashMap::new(),
        };
        let part_jobs: Vec<PartJob> = jobs
            .iter()
            .map(|j| {
                let (cp, ctx) = (&parts[j.part], &ctxs[j.kit]);
                let key = geometry_key(j.part, ctx.kit, &part_params(ctx, cp), units);
                PartJob {
                    part: cp,
                    ctx,
                    // A part that cannot be prepared is prepared with each
                    // kit, for that kit's exact message.
                    preparation: match bases.get(&key) {
                        Some(Ok(base)) => Preparation::Derived(base),
                        _ => Preparation::Fresh,
                    },
                }
            })
            .collect();
        let mut rows = Vec::with_capacity(jobs.len());
        solve_in_order(
            &part_jobs,
            &self.backend,
            |i, solved| {
                let cp = part_jobs[i].part;
                let ms = solved.timing.prepare_ms + solved.timing.enumerate_ms;
                row_of(&cp.id, cp.quantity, &solved.result, ms)
            },
            |_, row| {
                rows.push(row);
                Ok(())
            },
        )?;
        Ok(rows)
    }

    /// One `prepare` per geometry key (part, spacing, locator radius, edge
    /// trim, wrenches), in parallel; every job of that key derives its
    /// prepared part from it.
    fn prepare_bases(
        &self,
        jobs: &[Job],
        ctxs: &[JobContext],
        threads: Option<usize>,
    ) -> Result<HashMap<String, Result<PreparedPart, PrepareError>>> {
        let units = self.catalog.units;
        let parts = &self.catalog.parts;
        let mut keys: BTreeMap<String, (usize, usize)> = BTreeMap::new();
        for j in jobs {
            let cp = &parts[j.part];
            if cp.part.is_ok() {
                let params = part_params(&ctxs[j.kit], cp);
                let key = geometry_key(j.part, ctxs[j.kit].kit, &params, units);
                keys.entry(key).or_insert((j.kit, j.part));
            }
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads.unwrap_or_else(fixplan_worker::host::cores))
            .build()
            .context("cannot start the thread pool")?;
        Ok(pool.install(|| {
            keys.into_par_iter()
                .filter_map(|(key, (k, i))| {
                    let cp = &parts[i];
                    let part = cp.part.as_ref().ok()?;
                    let params = part_params(&ctxs[k], cp);
                    Some((key, prepare(part, ctxs[k].kit, &params, units)))
                })
                .collect()
        }))
    }
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
    let params: Vec<Params> = kits
        .iter()
        .map(|k| {
            let mut p = k.spec.params.clone();
            p.top_k = opts.top_k.unwrap_or(1);
            p
        })
        .collect();
    let mut engine = Engine {
        catalog,
        kits,
        params: params.clone(),
        backend: match cluster {
            Some(c) => Backend::Cluster(c.clone()),
            None => Backend::Embedded {
                threads: opts.threads,
            },
        },
        prepares: 0,
    };
    let nk = kits.len();
    let np = catalog.parts.len();
    // Same kit as an earlier one: solved once.
    let mut same_as: Vec<Option<usize>> = vec![None; nk];
    let mut seen: HashMap<String, usize> = HashMap::new();
    for k in 0..nk {
        let key = config_key(&kits[k].spec.kit, &params[k]);
        match seen.get(&key) {
            Some(&j) if !opts.no_share => same_as[k] = Some(j),
            _ => {
                seen.insert(key, k);
            }
        }
    }
    // Plate dominance among the distinct kits.
    let distinct: Vec<usize> = (0..nk).filter(|&k| same_as[k].is_none()).collect();
    let mut larger: Vec<Vec<usize>> = vec![Vec::new(); nk];
    if !opts.no_share {
        for &a in &distinct {
            for &b in &distinct {
                let (ka, kb) = (&kits[a].spec.kit, &kits[b].spec.kit);
                if a != b
                    && plate_free_key(ka, &params[a]) == plate_free_key(kb, &params[b])
                    && kb.cols >= ka.cols
                    && kb.rows >= ka.rows
                {
                    larger[a].push(b);
                }
            }
        }
    }
    let maximal: Vec<usize> = distinct
        .iter()
        .copied()
        .filter(|&k| larger[k].is_empty())
        .collect();
    let rest: Vec<usize> = distinct
        .iter()
        .copied()
        .filter(|&k| !larger[k].is_empty())
        .collect();
    let mut rows: Vec<Vec<Option<StudyPartRow>>> = vec![vec![None; np]; nk];
    let jobs: Vec<Job> = maximal
        .iter()
        .flat_map(|&k| (0..np).map(move |i| Job { kit: k, part: i }))
        .collect();
    for (j, r) in jobs.iter().zip(engine.solve(&jobs)?) {
        rows[j.kit][j.part] = Some(r);
    }
    // Phase 2: kits with a larger plate among the maximal ones.
    let mut shared_plate = 0;
    let mut jobs = Vec::new();
    #[allow(clippy::needless_range_loop)] // rows[b][i] and rows[k][i]
    for &k in &rest {
        for i in 0..np {
            let from = maximal.iter().copied().find(|&b| {
                larger[k].contains(&b)
                    && rows[b][i]
                        .as_ref()
                        .is_some_and(|r| r.status == Status::NoFixture)
            });
            match from {
                Some(b) => {
                    let mut r = rows[b][i].clone().unwrap_or_else(unreachable_row);
                    r.ms = 0.0;
                    r.shared = Some(format!(
                        "no fixture on the larger plate of {}",
                        kits[b].spec.name
                    ));
                    rows[k][i] = Some(r);
                    shared_plate += 1;
                }
                None => jobs.push(Job { kit: k, part: i }),
            }
        }
    }
    for (j, r) in jobs.iter().zip(engine.solve(&jobs)?) {
        rows[j.kit][j.part] = Some(r);
    }
    let mut shared_same = 0;
    for k in 0..nk {
        if let Some(j) = same_as[k] {
            rows[k] = rows[j]
                .iter()
                .map(|r| {
                    r.clone().map(|mut r| {
                        r.ms = 0.0;
                        r.shared = Some(format!("same kit as {}", kits[j].spec.name));
                        r
                    })
                })
                .collect();
            shared_same += np;
        }
    }
    let total_qty: f64 = catalog.parts.iter().map(|p| p.quantity).sum();
    let mut msgs = Vec::new();
    for (k, sk) in kits.iter().enumerate() {
        let results: Vec<StudyPartRow> = rows[k]
            .iter_mut()
            .map(|r| r.take().unwrap_or_else(unreachable_row))
            .collect();
        let held: Vec<&StudyPartRow> = results.iter().filter(|r| r.status == Status::Ok).collect();
        let mut scores: Vec<f64> = held.iter().filter_map(|r| r.best_score).collect();
        scores.sort_by(f64::total_cmp);
        let held_qty: f64 = held.iter().map(|r| r.quantity).sum();
        let shared = results.iter().filter(|r| r.shared.is_some()).count();
        msgs.push(StudyKitMsg {
            index: k,
            name: sk.spec.name.clone(),
            base: sk.base.clone(),
            sweep: sk.sweep.clone(),
            kit: sk.spec.kit.clone(),
            params: params[k].clone(),
            parts: np,
            held: held.len(),
            held_pct: if np == 0 {
                0.0
            } else {
                100.0 * held.len() as f64 / np as f64
            },
            held_quantity_pct: if total_qty > 0.0 {
                100.0 * held_qty / total_qty
            } else {
                0.0
            },
            median_score: median(&scores),
            p90_score: nearest_rank(&scores, 90.0),
            no_fixture: results
                .iter()
                .filter(|r| r.status == Status::NoFixture)
                .count(),
            invalid: results
                .iter()
                .filter(|r| r.status == Status::Invalid)
                .count(),
            time_ms: results.iter().map(|r| r.ms).sum(),
            enumerated: np - shared,
            shared,
            results,
        });
    }
    let unheld = (0..np)
        .filter(|&i| msgs.iter().all(|m| m.results[i].status != Status::Ok))
        .map(|i| catalog.parts[i].id.clone())
        .collect();
    let summary = StudySummaryMsg {
        tool: "fixplan".into(),
        version: env!("CARGO_PKG_VERSION").into(),
        catalog: CatalogInfo::of(catalog, &opts.catalog),
        kits: kits.iter().map(|k| k.spec.name.clone()).collect(),
        unheld,
        part_runs: nk * np,
        enumerated: nk * np - shared_same - shared_plate,
        shared_same_kit: shared_same,
        shared_larger_plate: shared_plate,
        prepares: engine.prepares,
        workers: cluster.map(|c| c.local_workers),
        elapsed_ms: t0.elapsed().as_secs_f64() * 1e3,
    };
    Ok(StudyReport {
        kits: msgs,
        summary,
    })
}

fn unreachable_row() -> StudyPartRow {
    StudyPartRow {
        id: String::new(),
        status: Status::Invalid,
        error: Some("internal error: no result".into()),
        quantity: 0.0,
        counts: None,
        best_score: None,
        ms: 0.0,
        shared: None,
    }
}

/// `fixplan study`: loads, runs, writes every output asked for.
pub fn study_main(opts: &StudyOptions, cluster: Option<&ClusterOptions>) -> Result<StudyReport> {
    let catalog = load_catalog(&opts.catalog)?;
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
    if let Some(p) = &opts.output {
        write_mcap(p, &rep)?;
    }
    if let Some(p) = &opts.csv {
        std::fs::write(p, csv(&rep)).with_context(|| format!("{}: cannot write", p.display()))?;
    }
    if let Some(p) = &opts.chart {
        std::fs::write(p, chart_svg(&rep))
            .with_context(|| format!("{}: cannot write", p.display()))?;
    }
    if !opts.quiet {
        use std::io::Write;
        let mut out = std::io::stdout().lock();
        out.write_all(table(&rep).as_bytes())?;
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

fn opt(x: Option<f64>, prec: usize) -> String {
    x.map_or("-".into(), |v| format!("{v:.prec$}"))
}

/// The terminal table.
pub fn table(rep: &StudyReport) -> String {
    let w = rep
        .kits
        .iter()
        .map(|k| k.name.chars().count())
        .max()
        .unwrap_or(3)
        .max(3);
    let mut s = format!(
        "{:>3}  {:<w$}  {:>7}  {:>6}  {:>9}  {:>7}  {:>7}  {:>6}  {:>7}  {:>7}\n",
        "#", "kit", "held", "held%", "qty held%", "median", "p90", "no fix", "invalid", "time s"
    );
    for k in &rep.kits {
        s.push_str(&format!(
            "{:>3}  {:<w$}  {:>7}  {:>5.1}%  {:>8.1}%  {:>7}  {:>7}  {:>6}  {:>7}  {:>7.2}\n",
            k.index + 1,
            k.name,
            format!("{}/{}", k.held, k.parts),
            k.held_pct,
            k.held_quantity_pct,
            opt(k.median_score, 4),
            opt(k.p90_score, 4),
            k.no_fixture,
            k.invalid,
            k.time_ms / 1e3
        ));
    }
    let sm = &rep.summary;
    if sm.unheld.is_empty() {
        s.push_str("every part is held by at least one kit\n");
    } else {
        s.push_str(&format!(
            "parts no kit holds ({}): {}\n",
            sm.unheld.len(),
            sm.unheld.join(", ")
        ));
    }
    s.push_str(&format!(
        "work: {} part runs, {} enumerated, {} shared ({} same kit, {} no fixture on a larger plate); {:.2} s\n",
        sm.part_runs,
        sm.enumerated,
        sm.shared_same_kit + sm.shared_larger_plate,
        sm.shared_same_kit,
        sm.shared_larger_plate,
        sm.elapsed_ms / 1e3
    ));
    s
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// One row per kit.
pub fn csv(rep: &StudyReport) -> String {
    let mut s = String::from(
        "index,kit,base,sweep,parts,held,held_pct,held_quantity_pct,median_score,p90_score,no_fixture,invalid,time_ms,enumerated,shared\n",
    );
    let num = |x: Option<f64>| x.map_or(String::new(), |v| format!("{v}"));
    for k in &rep.kits {
        s.push_str(&format!(
            "{},{},{},{},{},{},{:.3},{:.3},{},{},{},{},{:.3},{},{}\n",
            k.index + 1,
            csv_field(&k.name),
            csv_field(&k.base),
            csv_field(k.sweep.as_deref().unwrap_or("")),
            k.parts,
            k.held,
            k.held_pct,
            k.held_quantity_pct,
            num(k.median_score),
            num(k.p90_score),
            k.no_fixture,
            k.invalid,
            k.time_ms,
            k.enumerated,
            k.shared
        ));
    }
    s
}

/// A hand-written SVG: per kit, the share of parts held (by count and by
/// quantity) and the best score over the parts held (median, with a
/// whisker to the 90th percentile).
pub fn chart_svg(rep: &StudyReport) -> String {
    let name_w = rep
        .kits
        .iter()
        .map(|k| k.name.chars().count())
        .max()
        .unwrap_or(10)
        .clamp(10, 60) as f64
        * 6.6
        + 40.0;
    let (cov_x, cov_w) = (name_w, 300.0);
    let (sc_x, sc_w) = (cov_x + cov_w + 60.0, 300.0);
    let width = sc_x + sc_w + 30.0;
    let row_h = 30.0;
    let top = 86.0;
    let height = top + row_h * rep.kits.len() as f64 + 60.0;
    let max_score = rep
        .kits
        .iter()
        .filter_map(|k| k.p90_score.or(k.median_score))
        .fold(0.0_f64, f64::max);
    let smax = if max_score > 0.0 {
        (max_score * 1.15 * 2.0).ceil() / 2.0
    } else {
        1.0
    };
    let sx = |v: f64| sc_x + sc_w * (v / smax);
    let mut s = String::new();
    s.push_str(&format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width:.0}\" height=\"{height:.0}\" viewBox=\"0 0 {width:.0} {height:.0}\" font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\" font-size=\"12\">\n"
    ));
    s.push_str(&format!(
        "<rect width=\"{width:.0}\" height=\"{height:.0}\" fill=\"white\"/>\n"
    ));
    s.push_str(&format!(
        "<text x=\"20\" y=\"26\" font-size=\"16\" font-weight=\"bold\">fixplan study: {} ({} parts), {} kits</text>\n",
        crate::view::svg::escape(&rep.summary.catalog.name),
        rep.summary.catalog.parts,
        rep.kits.len()
    ));
    s.push_str(&format!(
        "<text x=\"{cov_x:.0}\" y=\"56\" font-weight=\"bold\">parts held (%)</text>\n\
         <rect x=\"{:.0}\" y=\"47\" width=\"12\" height=\"8\" fill=\"#2b6cb0\"/><text x=\"{:.0}\" y=\"55\" font-size=\"11\">by count</text>\n\
         <rect x=\"{:.0}\" y=\"47\" width=\"12\" height=\"8\" fill=\"#90cdf4\"/><text x=\"{:.0}\" y=\"55\" font-size=\"11\">by quantity</text>\n",
        cov_x + 110.0, cov_x + 126.0, cov_x + 190.0, cov_x + 206.0
    ));
    s.push_str(&format!(
        "<text x=\"{sc_x:.0}\" y=\"56\" font-weight=\"bold\">best score of the parts held (lower is better)</text>\n\
         <text x=\"{sc_x:.0}\" y=\"72\" font-size=\"11\" fill=\"#444\">dot: median, bar: to the 90th percentile</text>\n"
    ));
    let bottom = top + row_h * rep.kits.len() as f64;
    // Grid lines and axes.
    for i in 0..=4 {
        let x = cov_x + cov_w * i as f64 / 4.0;
        s.push_str(&format!(
            "<line x1=\"{x:.1}\" y1=\"{top:.0}\" x2=\"{x:.1}\" y2=\"{bottom:.0}\" stroke=\"#ddd\"/>\n<text x=\"{x:.1}\" y=\"{:.0}\" text-anchor=\"middle\" font-size=\"11\">{}</text>\n",
            bottom + 16.0,
            i * 25
        ));
    }
    let ticks = 5;
    for i in 0..=ticks {
        let v = smax * i as f64 / ticks as f64;
        let x = sx(v);
        s.push_str(&format!(
            "<line x1=\"{x:.1}\" y1=\"{top:.0}\" x2=\"{x:.1}\" y2=\"{bottom:.0}\" stroke=\"#ddd\"/>\n<text x=\"{x:.1}\" y=\"{:.0}\" text-anchor=\"middle\" font-size=\"11\">{v:.2}</text>\n",
            bottom + 16.0
        ));
    }
    for (n, k) in rep.kits.iter().enumerate() {
        let y = top + row_h * n as f64;
        if n % 2 == 1 {
            s.push_str(&format!(
                "<rect x=\"10\" y=\"{y:.0}\" width=\"{:.0}\" height=\"{row_h:.0}\" fill=\"#f5f7fa\"/>\n",
                width - 20.0
            ));
        }
        s.push_str(&format!(
            "<text x=\"{:.0}\" y=\"{:.0}\" text-anchor=\"end\">{}</text>\n",
            cov_x - 10.0,
            y + 19.0,
            crate::view::svg::escape(&k.name)
        ));
        let wc = cov_w * k.held_pct / 100.0;
        let wq = cov_w * k.held_quantity_pct / 100.0;
        s.push_str(&format!(
            "<rect x=\"{cov_x:.0}\" y=\"{:.1}\" width=\"{wc:.1}\" height=\"10\" fill=\"#2b6cb0\"/>\n\
             <rect x=\"{cov_x:.0}\" y=\"{:.1}\" width=\"{wq:.1}\" height=\"8\" fill=\"#90cdf4\"/>\n\
             <text x=\"{:.1}\" y=\"{:.1}\" font-size=\"10\">{}/{}</text>\n",
            y + 5.0,
            y + 16.0,
            cov_x + wc.max(wq) + 4.0,
            y + 18.0,
            k.held,
            k.parts
        ));
        if let Some(m) = k.median_score {
            let cy = y + row_h / 2.0;
            if let Some(p) = k.p90_score {
                s.push_str(&format!(
                    "<line x1=\"{:.1}\" y1=\"{cy:.1}\" x2=\"{:.1}\" y2=\"{cy:.1}\" stroke=\"#c05621\" stroke-width=\"3\"/>\n",
                    sx(m),
                    sx(p)
                ));
            }
            s.push_str(&format!(
                "<circle cx=\"{:.1}\" cy=\"{cy:.1}\" r=\"5\" fill=\"#dd6b20\"/>\n<text x=\"{:.1}\" y=\"{:.1}\" font-size=\"10\">{m:.3}</text>\n",
                sx(m),
                sx(k.p90_score.unwrap_or(m)) + 8.0,
                cy + 4.0
            ));
        }
    }
    let sm = &rep.summary;
    let foot = if sm.unheld.is_empty() {
        "every part is held by at least one kit".to_string()
    } else {
        format!("parts no kit holds: {}", sm.unheld.join(", "))
    };
    s.push_str(&format!(
        "<text x=\"20\" y=\"{:.0}\" font-size=\"11\" fill=\"#444\">{}</text>\n</svg>\n",
        bottom + 42.0,
        crate::view::svg::escape(&foot)
    ));
    s
}

fn study_schema() -> serde_json::Value {
    let num_or_null = serde_json::json!({"type": ["number", "null"]});
    serde_json::json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": SCHEMA_STUDY,
        "description": "One kit of a fixplan study: coverage of the catalogue, best scores over the parts held, time, and every part's outcome.",
        "type": "object",
        "required": ["index", "name", "kit", "params", "parts", "held", "held_pct", "held_quantity_pct", "results"],
        "properties": {
            "index": {"type": "integer"}, "name": {"type": "string"}, "base": {"type": "string"},
            "sweep": {"type": ["string", "null"]},
            "kit": {"type": "object", "description": "SPEC Appendix A kit, catalogue units"},
            "params": {"type": "object", "description": "SPEC Appendix A params"},
            "parts": {"type": "integer"}, "held": {"type": "integer"},
            "held_pct": {"type": "number"},
            "held_quantity_pct": {"type": "number", "description": "share held weighted by quantity (parts per year)"},
            "median_score": num_or_null, "p90_score": num_or_null,
            "no_fixture": {"type": "integer"}, "invalid": {"type": "integer"},
            "time_ms": {"type": "number"}, "enumerated": {"type": "integer"}, "shared": {"type": "integer"},
            "results": {"type": "array", "items": {"type": "object", "properties": {
                "id": {"type": "string"}, "status": {"enum": ["ok", "no_fixture", "invalid"]},
                "error": {"type": "string"}, "quantity": {"type": "number"},
                "counts": {"type": ["object", "null"]}, "best_score": num_or_null,
                "ms": {"type": "number"}, "shared": {"type": "string"}}}}
        }
    })
}

fn summary_schema() -> serde_json::Value {
    serde_json::json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": SCHEMA_STUDY_SUMMARY,
        "description": "A fixplan study: catalogue, kits, parts no kit holds, work shared.",
        "type": "object",
        "properties": {
            "tool": {"type": "string"}, "version": {"type": "string"},
            "catalog": {"type": "object"},
            "kits": {"type": "array", "items": {"type": "string"}},
            "unheld": {"type": "array", "items": {"type": "string"}},
            "part_runs": {"type": "integer"}, "enumerated": {"type": "integer"},
            "shared_same_kit": {"type": "integer"}, "shared_larger_plate": {"type": "integer"},
            "prepares": {"type": "integer"}, "workers": {"type": ["integer", "null"]},
            "elapsed_ms": {"type": "number"}
        }
    })
}

/// The study as MCAP: `/fixplan/study` (one message per kit) and
/// `/fixplan/study_summary`.
pub fn write_mcap(path: &Path, rep: &StudyReport) -> Result<()> {
    let file = std::fs::File::create(path)
        .with_context(|| format!("{}: cannot create", path.display()))?;
    let mut w = crate::output::writer::write_options().create(std::io::BufWriter::new(file))?;
    let none = BTreeMap::new();
    let s1 = w.add_schema(
        SCHEMA_STUDY,
        "jsonschema",
        &serde_json::to_vec_pretty(&study_schema())?,
    )?;
    let c1 = w.add_channel(s1, TOPIC_STUDY, "json", &none)?;
    let s2 = w.add_schema(
        SCHEMA_STUDY_SUMMARY,
        "jsonschema",
        &serde_json::to_vec_pretty(&summary_schema())?,
    )?;
    let c2 = w.add_channel(s2, TOPIC_STUDY_SUMMARY, "json", &none)?;
    let ns = crate::output::messages::NS_PER_PART;
    for k in &rep.kits {
        let t = k.index as u64 * ns;
        w.write_to_known_channel(
            &mcap::records::MessageHeader {
                channel_id: c1,
                sequence: k.index as u32,
                log_time: t,
                publish_time: t,
            },
            &serde_json::to_vec(k)?,
        )?;
    }
    let t = rep.kits.len() as u64 * ns;
    w.write_to_known_channel(
        &mcap::records::MessageHeader {
            channel_id: c2,
            sequence: 0,
            log_time: t,
            publish_time: t,
        },
        &serde_json::to_vec(&rep.summary)?,
    )?;
    w.finish()?;
    Ok(())
}

/// Reads the `/fixplan/study` messages of a study file back.
pub fn read_mcap(path: &Path) -> Result<(Vec<StudyKitMsg>, Option<StudySummaryMsg>)> {
    let bytes = std::fs::read(path).with_context(|| format!("{}: cannot read", path.display()))?;
    let mut kits = Vec::new();
    let mut summary = None;
    for m in mcap::MessageStream::new(&bytes)? {
        let m = m?;
        match m.channel.topic.as_str() {
            TOPIC_STUDY => kits.push(serde_json::from_slice(&m.data)?),
            TOPIC_STUDY_SUMMARY => summary = Some(serde_json::from_slice(&m.data)?),
            _ => {}
        }
    }
    Ok((kits, summary))
}
