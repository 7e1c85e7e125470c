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

impl CatalogJobs {
    /// Sends one part's outcome; true when the receiver is gone.
    #[allow(clippy::too_many_arguments)]
    fn send_part(
        &self,
        ctx: &JobContext,
        cp: &CatalogPart,
        i: usize,
        result: SolveResult,
        summaries: &mut Vec<StepSummary>,
        stopped_at: Option<u64>,
        t0: std::time::Instant,
        tx: &Sender<(usize, Result<PartOutcome, serde_json::Error>)>,
    ) -> bool {
        let info = SearchInfo {
            steps: ctx
                .search
                .grid_steps
                .is_some()
                .then(|| std::mem::take(summaries)),
            stopped_at,
            ..SearchInfo::default()
        };
        let timing = Timing {
            enumerate_ms: t0.elapsed().as_secs_f64() * 1e3,
            ..Timing::default()
        };
        tx.send((i, part_outcome_with(ctx, i, cp, result, timing, &info)))
            .is_err()
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
        let mut summaries: Vec<StepSummary> = Vec::new();
        let mut failed: Option<SolveResult> = None;
        // `--good-enough`: the step that stopped a part ends it, as in the
        // embedded search (the workers ran its finer steps all the same).
        let mut stopped: Option<(usize, SolveResult, u64)> = None;
        while let Some((j, r)) = self.dist.next_part() {
            let (i, k) = self.map[j];
            let cp = &parts[i];
            if k == 0 {
                summaries.clear();
                failed = None;
                stopped = None;
            }
            let last_step = k + 1 == self.steps.len();
            if stopped.as_ref().is_some_and(|s| s.0 == i) {
                if last_step {
                    let (_, result, at) = stopped.take().expect("checked above");
                    if self.send_part(ctx, cp, i, result, &mut summaries, Some(at), t0, tx) {
                        break;
                    }
                }
                continue;
            }
            let (result, hit) = match r {
                Ok(s) => (report(&s.prep, &s.merged), s.stopped_at),
                Err(msg) => (SolveResult::invalid(format!("{}: {msg}", cp.id)), None),
            };
            let now = std::time::Instant::now();
            let ms = (now - t_step).as_secs_f64() * 1e3;
            t_step = now;
            if result.status == fixplan_core::Status::Invalid && failed.is_none() {
                failed = Some(result.clone());
            }
            summaries.push(step_summary(
                self.steps[k],
                &result,
                summaries.last(),
                hit,
                ms,
            ));
            if let Some(at) = hit {
                let result = failed.take().unwrap_or(result);
                if last_step {
                    if self.send_part(ctx, cp, i, result, &mut summaries, Some(at), t0, tx) {
                        break;
                    }
                } else {
                    stopped = Some((i, result, at));
                }
                continue;
            }
            if !last_step {
                continue;
            }
            let result = failed.take().unwrap_or(result);
            if self.send_part(ctx, cp, i, result, &mut summaries, None, t0, tx) {
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
