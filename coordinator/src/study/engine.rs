//! Solving a study's jobs: each (kit, part) through the run path
//! ([`solve_in_order`] on the run's [`Backend`]), with one `prepare` per
//! geometry in an embedded study (see [`super::sharing`] for why that is
//! exact).

use super::kits::StudyKit;
use super::messages::StudyPartRow;
use super::sharing::{geometry_key, Job};
use crate::job::solve_part::Preparation;
use crate::job::{part_params, JobContext, SearchOptions};
use crate::run::backend::{Backend, PartJob};
use crate::run::solve_in_order::solve_in_order;
use anyhow::{Context, Result};
use fixplan_catalog::Catalog;
use fixplan_core::{prepare, Params, PrepareError, PreparedPart};
use rayon::prelude::*;
use std::collections::{BTreeMap, HashMap};

/// Prepared parts by geometry key; a part that cannot be prepared keeps
/// its error, and each of its jobs prepares it afresh.
type Bases = HashMap<String, Result<PreparedPart, PrepareError>>;

/// Solves the jobs of one study, phase after phase.
pub struct Engine<'a> {
    catalog: &'a Catalog,
    kits: &'a [StudyKit],
    params: &'a [Params],
    backend: Backend,
    /// The budgets of every solve (`--part-fixtures`).
    search: SearchOptions,
    prepares: usize,
}

impl<'a> Engine<'a> {
    /// An engine for `kits` solved with `params` (one per kit) on `backend`.
    pub fn new(
        catalog: &'a Catalog,
        kits: &'a [StudyKit],
        params: &'a [Params],
        backend: Backend,
        search: SearchOptions,
    ) -> Engine<'a> {
        Engine {
            catalog,
            kits,
            params,
            backend,
            search,
            prepares: 0,
        }
    }

    /// Distinct geometries prepared so far, for the summary.
    pub fn prepares(&self) -> usize {
        self.prepares
    }

    /// Solves the jobs through the run path: rows in job order.
    pub fn solve(&mut self, jobs: &[Job]) -> Result<Vec<StudyPartRow>> {
        let units = self.catalog.units;
        let parts = &self.catalog.parts;
        let search = &self.search;
        let ctxs: Vec<JobContext> = (0..self.kits.len())
            .map(|k| JobContext {
                kit: &self.kits[k].spec.kit,
                params: &self.params[k],
                units,
                shard_size: None,
                search,
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
                StudyPartRow::solved(&cp.id, cp.quantity, &solved.result, ms)
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
    ) -> Result<Bases> {
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
            .num_threads(threads.unwrap_or_else(crate::job::threads::cores))
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
