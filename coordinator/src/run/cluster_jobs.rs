//! Jobs through the cluster: each readable part goes to the workers once
//! per grid step, its steps come back merged and become the same result as
//! the embedded search's; unreadable parts, and parts over `--part-budget`
//! before preparing, never leave this process.

use super::backend::{PartJob, RemoteFinish};
use crate::cluster::distributed::map_batch;
use crate::cluster::{
    run_distributed_finishing, ClusterError, ClusterOptions, Distributed, MergedPart, PartFailure,
    Returned,
};
use crate::job::search::step_summary;
use crate::job::solve_part::Preparation;
use crate::job::{part_params, solve_guarded, SearchInfo, SolveTiming, Solved, StepSummary};
use bytes::Bytes;
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

/// Where the jobs go as they come back ([`ClusterJobs::deliver`]).
pub struct Sink<'a, T> {
    /// What the caller keeps of job `i`, solved.
    pub solved: &'a (dyn Fn(usize, Solved) -> T + Sync),
    /// What the caller keeps of job `i` finished by its worker; `None` if
    /// no job was sent to be finished.
    pub finished: Option<&'a (dyn Fn(usize, Bytes) -> T + Sync)>,
    /// Hands what is kept of job `i` over; false when the caller is gone.
    pub send: &'a (dyn Fn(usize, T) -> bool + Sync),
}

/// A job that came back finished by its worker though none was sent to
/// be finished: a bug of the coordinator, reported rather than given a
/// made-up result.
#[derive(Debug, thiserror::Error)]
#[error("job {0}: finished by a worker, but no job was sent to be finished")]
pub struct FinishedUnasked(pub usize);

/// Starts the coordinator for `jobs` (all of one search: the first job's
/// `--good-enough` is the run's). Jobs of one plain enumeration (no grid
/// steps, no `--good-enough`) go with `remote`'s context, for their
/// worker to finish them.
pub fn start<T>(
    jobs: &[PartJob],
    opts: &ClusterOptions,
    remote: Option<&RemoteFinish<T>>,
) -> Result<ClusterJobs, ClusterError> {
    let mut inputs = Vec::new();
    let mut map = Vec::new();
    let mut direct = Vec::new();
    for (i, job) in jobs.iter().enumerate() {
        let Ok(part) = &job.part.part else {
            direct.push(i);
            continue;
        };
        // Over the cost budget before preparing: answered here at once,
        // as the embedded run does, never sent to a worker.
        let budget = job.ctx.search.part_budget;
        if crate::job::budget::over_budget_unprepared(part, &job.part.id, budget).is_some() {
            direct.push(i);
            continue;
        }
        let steps = steps_of(job);
        let plain = steps.len() == 1 && job.ctx.search.good_enough.is_none();
        for (k, step) in steps.into_iter().enumerate() {
            let mut params = part_params(job.ctx, job.part);
            params.grid_step = step;
            let input = PartInput {
                part: part.clone(),
                kit: job.ctx.kit.clone(),
                params,
                units: job.ctx.units,
            };
            inputs.push((input, remote.filter(|_| plain).and_then(|r| (r.context)(i))));
            map.push((i, k));
        }
    }
    let mut opts = opts.clone();
    let search = jobs.first().map(|j| j.ctx.search);
    opts.good_enough = search.and_then(|s| s.good_enough);
    opts.part_setups = search.and_then(|s| s.part_setups);
    opts.part_fixtures = search.and_then(|s| s.part_fixtures);
    opts.part_seconds = search.and_then(|s| s.part_seconds);
    let dist = run_distributed_finishing(inputs, opts, remote.map(|r| r.finisher.clone()))?;
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
        // A step over budget ends the part, as in the embedded search.
        if result.status == Status::OverBudget && failed.is_none() {
            return Solved {
                result,
                timing: SolveTiming {
                    enumerate_ms: ms,
                    ..SolveTiming::default()
                },
                search: SearchInfo::default(),
            };
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
        timing: SolveTiming {
            enumerate_ms: ms,
            ..SolveTiming::default()
        },
        search: SearchInfo {
            steps: job.ctx.search.grid_steps.is_some().then_some(summaries),
            stopped_at,
            ..SearchInfo::default()
        },
    }
}

/// A part's step as it came back, reported as the embedded run reports it
/// (its fixtures in catalogue units, placed on the plate).
fn step_out(job: &PartJob, returned: Result<MergedPart, PartFailure>, ms: f64) -> StepOut {
    match returned {
        Ok(s) => (report(&s.prep, &s.merged), s.stopped_at, ms),
        Err(PartFailure::OverBudget(stop)) => {
            let top_k = job.part.top_k.unwrap_or(job.ctx.params.top_k);
            let result =
                crate::job::budget::halted(&job.part.id, stop.into(), job.ctx.search, top_k);
            (result, None, ms)
        }
        Err(failure) => {
            let msg = format!("{}: {failure}", job.part.id);
            (SolveResult::gave_up(failure.status(), msg), None, ms)
        }
    }
}

impl ClusterJobs {
    /// Hands every job to `sink` (the unreadable ones first, the others
    /// as their last grid step comes back), then ends the run. Stops early
    /// when the caller is gone. The parts that came back together are
    /// prepared, reported and kept in parallel (`sink` makes their
    /// messages): the coordinator's work per part is what limits how many
    /// workers it serves.
    pub fn deliver<T>(mut self, jobs: &[PartJob], sink: &Sink<T>) -> Result<(), FinishedUnasked> {
        let solved = |i, s| (sink.send)(i, (sink.solved)(i, s));
        for &i in &self.direct {
            let job = &jobs[i];
            if !solved(i, solve_guarded(job.ctx, job.part, Preparation::Fresh)) {
                return Ok(());
            }
        }
        let mut t_prev = Instant::now();
        // Steps of a part, by step index, until all of them are in.
        let mut steps: HashMap<usize, Vec<Option<StepOut>>> = HashMap::new();
        while let Some(parts) = self.dist.next_parts() {
            let now = Instant::now();
            // The time since the results before, shared by those that came
            // back together.
            let ms = (now - t_prev).as_secs_f64() * 1e3 / parts.len() as f64;
            t_prev = now;
            let map = &self.map;
            // Parts their workers finished are handed over as they are.
            let mut finished = Vec::new();
            let mut merged = Vec::new();
            for (n, r) in parts {
                match r {
                    Ok(Returned::Finished(bytes)) => finished.push((map[n].0, bytes)),
                    Ok(Returned::Merged(m)) => merged.push((n, Ok(*m))),
                    Err(e) => merged.push((n, Err(e))),
                }
            }
            for (i, bytes) in finished {
                let Some(keep) = sink.finished else {
                    self.end();
                    return Err(FinishedUnasked(i));
                };
                if !(sink.send)(i, keep(i, bytes)) {
                    self.end();
                    return Ok(());
                }
            }
            let outs = map_batch(merged, |(n, r)| {
                let (i, k) = map[n];
                (i, k, step_out(&jobs[i], r, ms))
            });
            let done: Vec<(usize, Vec<StepOut>)> = outs
                .into_iter()
                .filter_map(|(i, k, out)| {
                    let have = steps
                        .entry(i)
                        .or_insert_with(|| vec![None; steps_of(&jobs[i]).len()]);
                    have[k] = Some(out);
                    let complete = have.iter().all(Option::is_some);
                    complete.then(|| {
                        (
                            i,
                            steps.remove(&i).into_iter().flatten().flatten().collect(),
                        )
                    })
                })
                .collect();
            let taken = map_batch(done, |(i, done)| {
                let ms = done.iter().map(|s| s.2).sum();
                solved(i, from_steps(&jobs[i], done, ms))
            });
            if !taken.into_iter().all(|t| t) {
                break;
            }
        }
        self.end();
        Ok(())
    }

    /// Ends the run and logs its figures.
    fn end(mut self) {
        let s = self.dist.finish();
        tracing::info!(
            role = "coordinator",
            "run over: {} shards, {} cut parts sent to workers to finish, {} results ({} duplicate, {} rejected), {} re-queued, {} workers joined, {} lost, {} results checked in full ({} fixtures re-derived)",
            s.shards,
            s.finishings,
            s.results,
            s.duplicates,
            s.rejected,
            s.requeued,
            s.workers_joined,
            s.workers_lost,
            s.results_rederived,
            s.fixtures_rederived
        );
    }
}
