//! A catalogue through the cluster: the parts of `fixplan run` from
//! `start` on go to [`run_distributed`]; their results come back in order
//! and become the same part messages as the embedded run's.

use super::{run_distributed, ClusterError, ClusterOptions, Distributed, PartInput};
use crate::messages::Timing;
use crate::part_job::{part_outcome_with, part_params, run_part, JobContext, PartOutcome};
use crate::refine::{step_summary, SearchInfo, StepSummary};
use fixplan_catalog::CatalogPart;
use fixplan_core::{report, SolveResult};
use std::sync::mpsc::Sender;

/// The distributed parts of a catalogue run.
pub struct CatalogJobs {
    dist: Distributed,
    /// Catalogue index and grid-step index of each distributed input (one
    /// input per part, or per part and step with `--grid-steps`).
    map: Vec<(usize, usize)>,
    /// The grid steps of each part (`[the run's step]` without `--grid-steps`).
    steps: Vec<u32>,
    /// Parts that need no enumeration (unreadable files).
    direct: Vec<usize>,
}

/// Starts the coordinator for the parts `start..` of a catalogue.
pub fn start(
    ctx: &JobContext,
    parts: &[CatalogPart],
    start: usize,
    opts: &ClusterOptions,
) -> Result<CatalogJobs, ClusterError> {
    let mut inputs = Vec::new();
    let mut map = Vec::new();
    let mut direct = Vec::new();
    let steps = ctx
        .search
        .grid_steps
        .clone()
        .unwrap_or_else(|| vec![ctx.params.grid_step]);
    for (i, cp) in parts.iter().enumerate().skip(start) {
        match &cp.part {
            Ok(part) => {
                for (k, &step) in steps.iter().enumerate() {
                    let mut params = part_params(ctx, cp);
                    params.grid_step = step;
                    inputs.push(PartInput {
                        part: part.clone(),
                        kit: ctx.kit.clone(),
                        params,
                        units: ctx.units,
                    });
                    map.push((i, k));
                }
            }
            Err(_) => direct.push(i),
        }
    }
    let mut opts = opts.clone();
    opts.good_enough = ctx.search.good_enough;
    let dist = run_distributed(inputs, opts)?;
    Ok(CatalogJobs {
        dist,
        map,
        steps,
        direct,
    })
}

/// One grid step of a part as it came back: its result, the combination
/// where `--good-enough` stopped it, and the time since the previous step.
type StepOut = (SolveResult, Option<u64>, f64);

impl CatalogJobs {
    /// The outcome of a part from its steps, coarse to fine, as the
    /// embedded search makes it: summaries up to the first step stopped by
    /// `--good-enough` (the workers ran the finer ones all the same), the
    /// result of that step or the last, unless a step failed.
    fn part_outcome(
        &self,
        ctx: &JobContext,
        i: usize,
        cp: &CatalogPart,
        steps: Vec<StepOut>,
        t0: std::time::Instant,
    ) -> Result<PartOutcome, serde_json::Error> {
        let mut summaries: Vec<StepSummary> = Vec::new();
        let mut failed: Option<SolveResult> = None;
        let mut last = None;
        let mut stopped_at = None;
        for (k, (result, hit, ms)) in steps.into_iter().enumerate() {
            summaries.push(step_summary(
                self.steps[k],
                &result,
                summaries.last(),
                hit,
                ms,
            ));
            if result.status == fixplan_core::Status::Invalid && failed.is_none() {
                failed = Some(result.clone());
            }
            last = Some(result);
            if hit.is_some() {
                stopped_at = hit;
                break;
            }
        }
        let result = failed
            .or(last)
            .unwrap_or_else(|| SolveResult::invalid(format!("{}: no grid step", cp.id)));
        let info = SearchInfo {
            steps: ctx.search.grid_steps.is_some().then_some(summaries),
            stopped_at,
            ..SearchInfo::default()
        };
        let timing = Timing {
            enumerate_ms: t0.elapsed().as_secs_f64() * 1e3,
            ..Timing::default()
        };
        part_outcome_with(ctx, i, cp, result, timing, &info)
    }

    /// Sends every part's outcome to `tx` (in catalogue order for the
    /// distributed ones), then ends the run.
    pub fn deliver(
        mut self,
        ctx: &JobContext,
        parts: &[CatalogPart],
        tx: &Sender<(usize, Result<PartOutcome, serde_json::Error>)>,
    ) {
        for &i in &self.direct {
            if tx.send((i, run_part(ctx, i, &parts[i]))).is_err() {
                return;
            }
        }
        let t0 = std::time::Instant::now();
        let mut t_step = t0;
        // The steps of one part come back one after another, in order.
        let mut steps: Vec<StepOut> = Vec::new();
        while let Some((j, r)) = self.dist.next_part() {
            let (i, k) = self.map[j];
            let cp = &parts[i];
            let now = std::time::Instant::now();
            let ms = (now - t_step).as_secs_f64() * 1e3;
            t_step = now;
            // Steps past a `--good-enough` stop are not reported.
            if steps.last().is_none_or(|s| s.1.is_none()) {
                steps.push(match r {
                    Ok(s) => (report(&s.prep, &s.merged), s.stopped_at, ms),
                    Err(msg) => (SolveResult::invalid(format!("{}: {msg}", cp.id)), None, ms),
                });
            }
            if k + 1 < self.steps.len() {
                continue;
            }
            let out = self.part_outcome(ctx, i, cp, std::mem::take(&mut steps), t0);
            if tx.send((i, out)).is_err() {
                break;
            }
        }
        let s = self.dist.finish();
        fixplan_worker::info!(
            "coordinator",
            "run over: {} shards, {} results ({} duplicate, {} rejected), {} re-queued, {} workers joined, {} lost, {} fixtures re-derived",
            s.shards,
            s.results,
            s.duplicates,
            s.rejected,
            s.requeued,
            s.workers_joined,
            s.workers_lost,
            s.fixtures_rederived
        );
    }
}
