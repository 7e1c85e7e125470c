//! Work sharing between the kits of a study, and the rows it fills.
//!
//! Every (kit, part) goes through the per-part path of `fixplan run`
//! ([`crate::run::solve_in_order::solve_in_order`] in this process, or the workers of
//! [`crate::cluster::run_distributed`] with `--workers N`), so a study scales out
//! like a run. Work is shared only where that is provably exact:
//!
//! - **the same kit twice** (a sweep point equal to a listed kit): solved
//!   once, the result copied;
//! - **prepared parts** (in [`super::engine`]): segments, pair bounds and
//!   the metric depend on the part, the lattice spacing, the locator
//!   radius, the edge trim and the wrenches only. They are prepared once
//!   per such key and the plate, clamp, angle, clearance, grid step and
//!   top-k come from `PreparedPart::with_kit` (the core's own conversion,
//!   which checks the key's fields and is tested equal to a fresh
//!   `prepare`);
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

use super::kits::StudyKit;
use super::messages::StudyPartRow;
use crate::output::fields::StatusName;
use fixplan_core::{Kit, Params, Units};
use std::collections::HashMap;

/// Everything a kit's results depend on: two kits with the same key are
/// the same kit.
fn config_key(kit: &Kit, params: &Params) -> String {
    serde_json::json!({"kit": kit, "params": params}).to_string()
}

/// The key of a kit but for its plate size: kits with the same one differ
/// only in `cols x rows`, so the larger plate's "no fixture" holds for the
/// smaller.
fn plate_free_key(kit: &Kit, params: &Params) -> String {
    let mut k = kit.clone();
    k.cols = 0;
    k.rows = 0;
    config_key(&k, params)
}

/// What prepared segments depend on (SPEC section 2 and the metric): jobs
/// with the same key share one `prepare`.
pub fn geometry_key(part: usize, kit: &Kit, params: &Params, units: Units) -> String {
    serde_json::json!({"part": part, "spacing": kit.spacing, "r": kit.locator_radius,
        "trim": params.edge_trim_or_default(units), "wrenches": params.wrenches})
    .to_string()
}

/// One (kit, part) to solve: indices into the study's kits and the
/// catalogue's parts.
#[derive(Debug, Clone, Copy)]
pub struct Job {
    /// Index of the kit in the study.
    pub kit: usize,
    /// Index of the part in the catalogue.
    pub part: usize,
}

/// The row of every (kit, part), filled phase by phase: solved, or copied
/// from another kit's row.
pub struct Rows(Vec<Vec<Option<StudyPartRow>>>);

impl Rows {
    /// No row yet for `kits` kits of `parts` parts.
    pub fn new(kits: usize, parts: usize) -> Rows {
        Rows(vec![vec![None; parts]; kits])
    }

    /// Stores the rows of `jobs`, in job order.
    pub fn fill(&mut self, jobs: &[Job], rows: Vec<StudyPartRow>) {
        for (j, r) in jobs.iter().zip(rows) {
            self.0[j.kit][j.part] = Some(r);
        }
    }

    /// Each kit's rows in catalogue order; a row no phase filled (none
    /// should be left) becomes [`StudyPartRow::missing`].
    pub fn into_kits(self) -> Vec<Vec<StudyPartRow>> {
        self.0
            .into_iter()
            .map(|rows| {
                rows.into_iter()
                    .map(|r| r.unwrap_or_else(StudyPartRow::missing))
                    .collect()
            })
            .collect()
    }
}

/// Which kits share work with which: decided from the kits alone, before
/// anything is solved.
pub struct SharePlan {
    /// For a kit equal to an earlier one, that kit: its rows are copied.
    same_as: Vec<Option<usize>>,
    /// For each distinct kit, the distinct kits equal to it but for a plate
    /// at least as large in both directions.
    larger: Vec<Vec<usize>>,
    /// Distinct kits with no larger plate among them: solved first.
    maximal: Vec<usize>,
    /// Distinct kits with a larger plate: solved second, less the parts
    /// the larger plate has no fixture for.
    dominated: Vec<usize>,
}

impl SharePlan {
    /// The plan for `kits` solved with `params`; with `share` false (to
    /// check the sharing), every kit is solved on its own.
    pub fn new(kits: &[StudyKit], params: &[Params], share: bool) -> SharePlan {
        let same_as = if share {
            same_kits(kits, params)
        } else {
            vec![None; kits.len()]
        };
        let distinct: Vec<usize> = (0..kits.len()).filter(|&k| same_as[k].is_none()).collect();
        let larger = if share {
            larger_plates(kits, params, &distinct)
        } else {
            vec![Vec::new(); kits.len()]
        };
        let (maximal, dominated) = distinct.iter().partition(|&&k| larger[k].is_empty());
        SharePlan {
            same_as,
            larger,
            maximal,
            dominated,
        }
    }

    /// Phase 1: every part with every maximal kit.
    pub fn first_jobs(&self, parts: usize) -> Vec<Job> {
        self.maximal
            .iter()
            .flat_map(|&k| (0..parts).map(move |part| Job { kit: k, part }))
            .collect()
    }

    /// Phase 2, after phase 1 is in `rows`: copies the row of each part a
    /// larger plate has no fixture for, and returns the jobs left to solve
    /// and the number of rows copied.
    pub fn copy_no_fixture(&self, rows: &mut Rows, kits: &[StudyKit]) -> (Vec<Job>, usize) {
        let mut copied = 0;
        let mut jobs = Vec::new();
        for &k in &self.dominated {
            for part in 0..rows.0[k].len() {
                let copy = self.maximal.iter().find_map(|&b| {
                    let r = rows.0[b][part].as_ref()?;
                    (self.larger[k].contains(&b) && r.status == StatusName::NoFixture).then(|| {
                        r.shared_as(format!(
                            "no fixture on the larger plate of {}",
                            kits[b].spec.name
                        ))
                    })
                });
                match copy {
                    Some(row) => {
                        rows.0[k][part] = Some(row);
                        copied += 1;
                    }
                    None => jobs.push(Job { kit: k, part }),
                }
            }
        }
        (jobs, copied)
    }

    /// Copies the rows of each kit equal to an earlier one from it; returns
    /// the number of rows copied.
    pub fn copy_same_kits(&self, rows: &mut Rows, kits: &[StudyKit]) -> usize {
        let mut copied = 0;
        for (k, same) in self.same_as.iter().enumerate() {
            if let Some(j) = *same {
                let why = format!("same kit as {}", kits[j].spec.name);
                rows.0[k] = rows.0[j]
                    .iter()
                    .map(|r| r.as_ref().map(|r| r.shared_as(why.clone())))
                    .collect();
                copied += rows.0[k].len();
            }
        }
        copied
    }
}

/// For each kit, the first earlier kit with the same key, if any.
fn same_kits(kits: &[StudyKit], params: &[Params]) -> Vec<Option<usize>> {
    let mut seen: HashMap<String, usize> = HashMap::new();
    (0..kits.len())
        .map(|k| {
            let key = config_key(&kits[k].spec.kit, &params[k]);
            match seen.get(&key) {
                Some(&j) => Some(j),
                None => {
                    seen.insert(key, k);
                    None
                }
            }
        })
        .collect()
}

/// Plate dominance among the `distinct` kits: for each, the others equal
/// to it but for a plate at least as large in both directions.
fn larger_plates(kits: &[StudyKit], params: &[Params], distinct: &[usize]) -> Vec<Vec<usize>> {
    let mut larger = vec![Vec::new(); kits.len()];
    for &a in distinct {
        for &b in distinct {
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
    larger
}
