//! One catalogue part end to end: prepare, split its combination range into
//! shards, run them through the worker entry point (the one the distributed
//! mode uses), merge, report, and serialise the part's three messages.

use crate::mcap_out::PartMessages;
use crate::messages::{FixturesMsg, PartMsg, Timing, STOPPED_GOOD_ENOUGH};
use crate::refine::{solve_search, SearchInfo, SearchOptions};
use crate::scene::scene_update;
use fixplan_catalog::CatalogPart;
use fixplan_core::{
    merge, prepare, report, Kit, Params, PrepareError, PreparedPart, SolveResult, Status, Units,
};
use rayon::prelude::*;
use std::ops::Range;
use std::time::Instant;

/// Combinations per shard when not given: a cost estimate that gives each
/// thread a few shards of a big part and keeps small parts in one shard.
pub fn auto_shard_size(combinations: u64, threads: usize) -> u64 {
    let target_shards = (threads.max(1) * 4) as u64;
    combinations.div_ceil(target_shards).max(256)
}

/// The shards of `0..count`, `size` combinations each (the last may be
/// shorter). An empty range still gives one (empty) shard.
pub fn shard_ranges(count: u64, size: u64) -> Vec<Range<u64>> {
    let size = size.max(1);
    if count == 0 {
        return std::iter::once(0..0).collect();
    }
    (0..count)
        .step_by(size as usize)
        .map(|s| s..(s + size).min(count))
        .collect()
}

/// Enumerates a prepared part shard by shard and merges the pieces: the
/// same bytes whatever the shard size or thread count.
pub fn solve_prepared(prep: &PreparedPart, shard_size: Option<u64>) -> (SolveResult, usize) {
    let count = prep.combination_count();
    let size = shard_size.unwrap_or_else(|| auto_shard_size(count, rayon::current_num_threads()));
    let shards = shard_ranges(count, size);
    let n = shards.len();
    let parts: Vec<_> = shards
        .into_par_iter()
        .map(|r| fixplan_worker::run_shard(prep, r))
        .collect();
    let merged = merge(prep.top_k(), parts);
    (report(prep, &merged), n)
}

/// The run-wide inputs every part shares.
pub struct JobContext<'a> {
    pub kit: &'a Kit,
    pub params: &'a Params,
    pub units: Units,
    pub shard_size: Option<u64>,
    /// `--grid-steps` / `--good-enough` (default: one full enumeration).
    pub search: &'a SearchOptions,
}

/// The outcome of one part, for the progress display and summary.
#[derive(Debug, Clone)]
pub struct PartOutcome {
    pub messages: PartMessages,
    pub id: String,
    pub status: Status,
    pub error: Option<String>,
    pub admissible: u64,
    pub kept: usize,
    /// `--grid-steps`: what each step found.
    pub steps: Option<Vec<crate::refine::StepSummary>>,
    /// `--good-enough`: the combination index where the part stopped.
    pub stopped_at: Option<u64>,
}

fn name_part(id: &str, msg: &str) -> String {
    if msg.contains(id) {
        msg.to_string()
    } else {
        format!("{id}: {msg}")
    }
}

fn panic_message(p: Box<dyn std::any::Any + Send>) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        s.to_string()
    } else if let Some(s) = p.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic".into()
    }
}

/// Solves one catalogue part. Never fails: a broken part, or even a panic
/// in the enumeration, becomes an `invalid` result naming the part.
pub fn run_part(
    ctx: &JobContext,
    index: usize,
    cp: &CatalogPart,
) -> Result<PartOutcome, serde_json::Error> {
    let (result, timing, info) = solve_part(ctx, cp, None);
    part_outcome_with(ctx, index, cp, result, timing, &info)
}

/// The enumeration of one catalogue part (what [`run_part`] does before
/// writing messages). `prepared`: the part already prepared with
/// [`part_params`] (a study's cache), or `None` to prepare it here.
pub fn solve_part(
    ctx: &JobContext,
    cp: &CatalogPart,
    prepared: Option<Result<PreparedPart, PrepareError>>,
) -> (SolveResult, Timing, SearchInfo) {
    let mut timing = Timing::default();
    let mut info = SearchInfo::default();
    let result = match &cp.part {
        Err(msg) => SolveResult::invalid(name_part(&cp.id, msg)),
        Ok(part) => {
            let t0 = Instant::now();
            let prepared = prepared.unwrap_or_else(|| {
                let params = part_params(ctx, cp);
                prepare(part, ctx.kit, &params, ctx.units)
            });
            timing.prepare_ms = t0.elapsed().as_secs_f64() * 1e3;
            match prepared {
                Err(e) => SolveResult::invalid(format!("{}: {e}", cp.id)),
                Ok(prep) => {
                    let t1 = Instant::now();
                    let solved = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                        if ctx.search.is_plain() {
                            let (res, n) = solve_prepared(&prep, ctx.shard_size);
                            (
                                res,
                                SearchInfo {
                                    shards: n,
                                    ..SearchInfo::default()
                                },
                            )
                        } else {
                            solve_search(&prep, ctx.search, ctx.shard_size)
                        }
                    }));
                    timing.enumerate_ms = t1.elapsed().as_secs_f64() * 1e3;
                    match solved {
                        Ok((res, i)) => {
                            timing.shards = i.shards;
                            info = i;
                            res
                        }
                        Err(p) => SolveResult::invalid(format!(
                            "{}: internal error in the enumeration: {}",
                            cp.id,
                            panic_message(p)
                        )),
                    }
                }
            }
        }
    };
    (result, timing, info)
}

/// The run's parameters with the part's own `top_k` and wrenches.
pub fn part_params(ctx: &JobContext, cp: &CatalogPart) -> Params {
    let mut params = ctx.params.clone();
    if let Some(k) = cp.top_k {
        params.top_k = k;
    }
    if cp.wrenches.is_some() {
        params.wrenches = cp.wrenches.clone();
    }
    params
}

/// The messages and summary of a part solved elsewhere (the embedded path
/// above, or the workers of a distributed run).
pub fn part_outcome(
    ctx: &JobContext,
    index: usize,
    cp: &CatalogPart,
    result: SolveResult,
    timing: Timing,
) -> Result<PartOutcome, serde_json::Error> {
    part_outcome_with(ctx, index, cp, result, timing, &SearchInfo::default())
}

/// [`part_outcome`] with the per-step summary and early stop of a
/// `--grid-steps` / `--good-enough` search.
pub fn part_outcome_with(
    ctx: &JobContext,
    index: usize,
    cp: &CatalogPart,
    result: SolveResult,
    timing: Timing,
    info: &SearchInfo,
) -> Result<PartOutcome, serde_json::Error> {
    let (outline, access) = match &cp.part {
        Ok(p) => (p.outline.clone(), p.access.clone()),
        Err(_) => (Vec::new(), Vec::new()),
    };
    let best = result.fixtures.first();
    let part_msg = PartMsg {
        index,
        id: cp.id.clone(),
        file: cp.file.as_ref().map(|f| f.display().to_string()),
        status: result.status,
        error: result.error.clone(),
        warnings: cp.warnings.clone(),
        units: ctx.units,
        quantity: cp.quantity,
        outline: outline.clone(),
        access: access.clone(),
        counts: result.counts,
        fixtures: result.fixtures.len(),
        best_score: best.map(|f| f.score),
        timing,
        refine: info.steps.clone(),
        stopped: info.stopped_at.map(|_| STOPPED_GOOD_ENOUGH.to_string()),
        stopped_at: info.stopped_at,
    };
    let scene = scene_update(index, &cp.id, ctx.units, ctx.kit, &outline, &access, best);
    let outcome = PartOutcome {
        id: cp.id.clone(),
        status: result.status,
        error: result.error.clone(),
        admissible: result.counts.map_or(0, |c| c.admissible),
        kept: result.fixtures.len(),
        steps: info.steps.clone(),
        stopped_at: info.stopped_at,
        messages: PartMessages {
            index,
            part: serde_json::to_vec(&part_msg)?,
            fixtures: Vec::new(),
            scene: serde_json::to_vec(&scene)?,
        },
    };
    let fixtures = serde_json::to_vec(&FixturesMsg {
        part: cp.id.clone(),
        result,
    })?;
    Ok(PartOutcome {
        messages: PartMessages {
            fixtures,
            ..outcome.messages
        },
        ..outcome
    })
}
