//! The numbers of a study: each kit's coverage and score percentiles from
//! its rows, and the summary over all kits.

use super::kits::StudyKit;
use super::messages::{StudyKitMsg, StudyPartRow, StudySummaryMsg};
use crate::output::fields::StatusName;
use crate::output::messages::CatalogInfo;
use fixplan_catalog::Catalog;
use fixplan_core::Params;
use std::path::Path;

/// Median of sorted values (mean of the two middle ones for an even
/// count), as documented on [`StudyKitMsg::median_score`]; `None` for none.
pub fn median(sorted: &[f64]) -> Option<f64> {
    let n = sorted.len();
    match n {
        0 => None,
        _ if n % 2 == 1 => Some(sorted[n / 2]),
        _ => Some((sorted[n / 2 - 1] + sorted[n / 2]) / 2.0),
    }
}

/// The `pct` percentile of sorted values by nearest rank (a value that
/// occurs, unlike an interpolated one), as documented on
/// [`StudyKitMsg::p90_score`]; `None` for none.
pub fn nearest_rank(sorted: &[f64], pct: f64) -> Option<f64> {
    let n = sorted.len();
    if n == 0 {
        return None;
    }
    let rank = ((pct / 100.0) * n as f64).ceil().max(1.0) as usize;
    Some(sorted[rank.min(n) - 1])
}

/// The message of kit `index` from its rows (one per part, catalogue
/// order); `total_qty` is the catalogue's total quantity.
pub fn kit_message(
    index: usize,
    sk: &StudyKit,
    params: &Params,
    results: Vec<StudyPartRow>,
    total_qty: f64,
) -> StudyKitMsg {
    let np = results.len();
    let held: Vec<&StudyPartRow> = results
        .iter()
        .filter(|r| r.status == StatusName::Ok)
        .collect();
    let mut scores: Vec<f64> = held.iter().filter_map(|r| r.best_score).collect();
    scores.sort_by(f64::total_cmp);
    let held_qty: f64 = held.iter().map(|r| r.quantity).sum();
    let shared = results.iter().filter(|r| r.shared.is_some()).count();
    let count = |s: StatusName| results.iter().filter(|r| r.status == s).count();
    StudyKitMsg {
        index,
        name: sk.spec.name.clone(),
        base: sk.base.clone(),
        sweep: sk.sweep.clone(),
        kit: (&sk.spec.kit).into(),
        params: params.into(),
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
        no_fixture: count(StatusName::NoFixture),
        invalid: count(StatusName::Invalid),
        time_ms: results.iter().map(|r| r.ms).sum(),
        enumerated: np - shared,
        shared,
        results,
    }
}

/// The message of every kit, from each kit's rows.
pub fn kit_messages(
    catalog: &Catalog,
    kits: &[StudyKit],
    params: &[Params],
    rows: Vec<Vec<StudyPartRow>>,
) -> Vec<StudyKitMsg> {
    let total_qty: f64 = catalog.parts.iter().map(|p| p.quantity).sum();
    rows.into_iter()
        .enumerate()
        .map(|(k, results)| kit_message(k, &kits[k], &params[k], results, total_qty))
        .collect()
}

/// How much of a study's work was done and how much was shared.
#[derive(Debug, Clone, Copy)]
pub struct StudyWork {
    /// Kits times parts.
    pub part_runs: usize,
    /// Rows copied from an identical kit.
    pub shared_same_kit: usize,
    /// Rows copied because a larger plate had no fixture.
    pub shared_larger_plate: usize,
    /// Distinct prepared geometries.
    pub prepares: usize,
}

/// The summary message of a study of `catalog` (read from `source`).
pub fn summary(
    catalog: &Catalog,
    source: &Path,
    kits: &[StudyKit],
    msgs: &[StudyKitMsg],
    work: StudyWork,
    workers: Option<usize>,
    elapsed_ms: f64,
) -> StudySummaryMsg {
    let unheld = (0..catalog.parts.len())
        .filter(|&i| msgs.iter().all(|m| m.results[i].status != StatusName::Ok))
        .map(|i| catalog.parts[i].id.clone())
        .collect();
    StudySummaryMsg {
        tool: "fixplan".into(),
        version: env!("CARGO_PKG_VERSION").into(),
        catalog: CatalogInfo::of(catalog, source),
        kits: kits.iter().map(|k| k.spec.name.clone()).collect(),
        unheld,
        part_runs: work.part_runs,
        enumerated: work.part_runs - work.shared_same_kit - work.shared_larger_plate,
        shared_same_kit: work.shared_same_kit,
        shared_larger_plate: work.shared_larger_plate,
        prepares: work.prepares,
        workers,
        elapsed_ms,
    }
}
