//! Jobs through the cluster: each readable part goes to the workers once
//! per grid step, its steps come back merged and become the same result as
//! the embedded search's; unreadable parts never leave this process.

use super::backend::PartJob;
use crate::cluster::{run_distributed, ClusterError, ClusterOptions, Distributed};
use crate::job::search::step_summary;
use crate::job::solve::Preparation;
use crate::job::{part_params, solve_part, SearchInfo, Solved, StepSummary, Timing};
use fixplan_core::{report, SolveResult, Status};
use fixplan_worker::part_input::PartInput;
use std::collections::HashMap;
use std::time::Instant;

/// The jobs of a run handed to the cluster.
pub struct ClusterJobs {
    dist: Distributed,
    /// Job index and grid-step index of each distributed input (one input
    /// per part, or per part and step with `--grid-steps`).
    map: Vec<(usize, usize)>,
    /// Jobs that need no enumeration (unreadable parts).
    direct: Vec<usize>,
}

/// The grid steps a job is enumerated at, coarse to fine.
fn steps_of(job: &PartJob) -> Vec<u32> {
    job.ctx
        .search
        .grid_steps
        .clone()
        .unwrap_or_else(|| vec![job.ctx.params.grid_step])
}

/// Starts the coordinator for `jobs` (all of one search: the first job's
/// `--good-enough` is the run's).
pub fn start(jobs: &[PartJob], opts: &ClusterOptions) -> Result<ClusterJobs, ClusterError> {
    let mut inputs = Vec::new();
    let mut map = Vec::new();
    let mut direct = Vec::new();
    for (i, job) in jobs.iter().enumerate() {
        let Ok(part) = &job.part.part else {
            direct.push(i);
            continue;
        };
        for (k, step) in steps_of(job).into_iter().enumerate() {
            let mut params = part_params(job.ctx, job.part);
            params.grid_step = step;
            inputs.push(PartInput {
                part: part.clone(),
                kit: job.ctx.kit.clone(),
                params,
                units: job.ctx.units,
            });
            map.push((i, k));
        }
    }
    let mut opts = opts.clone();
    opts.good_enough = jobs.first().and_then(|j| j.ctx.search.good_enough);
    let dist = run_distributed(inputs, opts)?;
    Ok(ClusterJobs { dist, map, direct })
}

/// One grid step of a part as it came back: its result, the combination
/// where `--good-enough` stopped it, and the time since the result before.
type StepOut = (SolveResult, Option<u64>, f64);

/// A part's result from its steps, coarse to fine, as the embedded search
/// makes it: summaries up to the first step stopped by `--good-enough`
/// (the workers ran the finer ones all the same), the result of that step
/// or the last, unless a step failed.
fn from_steps(job: &PartJob, steps: Vec<StepOut>, ms: f64) -> Solved {
    let grid_steps = steps_of(job);
    let mut summaries: Vec<StepSummary> = Vec::new();
    let mut failed: Option<SolveResult> = None;
    let mut last = None;
    let mut stopped_at = None;
    // Steps past a `--good-enough` stop are not reported.
    for (k, (result, hit, step_ms)) in steps.into_iter().enumerate() {
        summaries.push(step_summary(
            grid_steps[k],
            &result,
            summaries.last(),
            hit,
            step_ms,
        ));
        if result.status == Status::Invalid && failed.is_none() {
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
        .unwrap_or_else(|| SolveResult::invalid(format!("{}: no grid step", job.part.id)));
    Solved {
        result,
        timing: Timing {
            enumerate_ms: ms,
            ..Timing::default()
        },
        search: SearchInfo {
            steps: job.ctx.search.grid_steps.is_some().then_some(summaries),
            stopped_at,
            ..SearchInfo::default()
        },
    }
}

impl ClusterJobs {
    /// Hands every job's result to `send` (the unreadable ones first, the
    /// others as their last grid step comes back), then ends the run. Stops early
    /// when `send` returns false (the caller is gone).
    pub fn deliver(mut self, jobs: &[PartJob], send: &dyn Fn(usize, Solved) -> bool) {
        for &i in &self.direct {
            let job = &jobs[i];
            if !send(i, solve_part(job.ctx, job.part, Preparation::Fresh)) {
                return;
            }
        }
        let mut t_prev = Instant::now();
        // Steps of a part, by step index, until all of them are in.
        let mut steps: HashMap<usize, Vec<Option<StepOut>>> = HashMap::new();
        while let Some((n, r)) = self.dist.next_part() {
            let (i, k) = self.map[n];
            let job = &jobs[i];
            let now = Instant::now();
            let ms = (now - t_prev).as_secs_f64() * 1e3;
            t_prev = now;
            let out = match r {
                Ok(s) => (report(&s.prep, &s.merged), s.stopped_at, ms),
                Err(msg) => {
                    let msg = format!("{}: {msg}", job.part.id);
                    (SolveResult::invalid(msg), None, ms)
                }
            };
            let n_steps = steps_of(job).len();
            let have = steps.entry(i).or_insert_with(|| vec![None; n_steps]);
            have[k] = Some(out);
            if have.iter().any(Option::is_none) {
                continue;
            }
            let done: Vec<StepOut> = steps.remove(&i).into_iter().flatten().flatten().collect();
            let ms = done.iter().map(|s| s.2).sum();
            if !send(i, from_steps(job, done, ms)) {
                break;
            }
        }
        let s = self.dist.finish();
        tracing::info!(
            role = "coordinator",
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
