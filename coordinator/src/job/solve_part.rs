//! One catalogue part solved in this process: prepared, cut into shards,
//! each shard through the worker's own entry point (the one the cluster
//! uses), merged. Never fails: a broken part, or even a panic in the
//! enumeration, becomes an `invalid` result naming the part.

use super::enumerate::solve_prepared;
use super::search::{solve_search, SearchInfo, SearchOptions};
use fixplan_catalog::CatalogPart;
use fixplan_core::{prepare, Kit, Params, PrepareError, PreparedPart, SolveResult, Units};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// The inputs every part of a run shares.
pub struct JobContext<'a> {
    /// The kit, in the catalogue's unit.
    pub kit: &'a Kit,
    /// The run's parameters; a part's own `top_k` and wrenches override
    /// them ([`part_params`]).
    pub params: &'a Params,
    /// The catalogue's unit.
    pub units: Units,
    /// Combinations per shard (default:
    /// [`super::shards::embedded_shard_size`]).
    pub shard_size: Option<u64>,
    /// `--grid-steps` / `--good-enough` (default: one full enumeration).
    pub search: &'a SearchOptions,
}

/// Wall-clock timings: the only fields of a results file that differ from
/// one run to the next.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
// The results file's schema names it as it always did.
#[schemars(rename = "Timing")]
pub struct SolveTiming {
    /// Validating and preparing the part.
    pub prepare_ms: f64,
    /// Enumerating its shards (all grid steps).
    pub enumerate_ms: f64,
    /// Shards it was cut into.
    pub shards: usize,
}

/// A part solved: its result, timings and what a search found per step.
#[derive(Debug, Clone)]
pub struct Solved {
    /// SPEC Appendix A result (fixtures in the catalogue's unit).
    pub result: SolveResult,
    /// How long it took.
    pub timing: SolveTiming,
    /// `--grid-steps` summaries and the `--good-enough` stop, if any.
    pub search: SearchInfo,
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

/// How a job gets its prepared part.
#[derive(Debug, Clone, Copy, Default)]
pub enum Preparation<'a> {
    /// `prepare` the part with the job's kit and parameters.
    #[default]
    Fresh,
    /// Derive it from the same part prepared with another kit of the same
    /// geometry (a study's cache; see [`PreparedPart::with_kit`]).
    Derived(&'a PreparedPart),
}

impl Preparation<'_> {
    fn prepare(
        self,
        part: &fixplan_core::Part,
        ctx: &JobContext,
        params: &Params,
    ) -> Result<PreparedPart, PrepareError> {
        match self {
            Preparation::Fresh => prepare(part, ctx.kit, params, ctx.units),
            Preparation::Derived(base) => base.with_kit(ctx.kit, params, ctx.units),
        }
    }
}

/// Solves one catalogue part on the current rayon pool.
pub fn solve_part(ctx: &JobContext, cp: &CatalogPart, preparation: Preparation) -> Solved {
    let start = Instant::now();
    let mut timing = SolveTiming::default();
    let part = match &cp.part {
        Err(e) => {
            return Solved {
                result: SolveResult::invalid(e.to_string()),
                timing,
                search: SearchInfo::default(),
            }
        }
        Ok(part) => part,
    };
    if let Some(result) =
        super::budget::over_budget_unprepared(part, &cp.id, ctx.search.part_budget)
    {
        return Solved {
            result,
            timing,
            search: SearchInfo::default(),
        };
    }
    let t0 = Instant::now();
    let prepared = preparation.prepare(part, ctx, &part_params(ctx, cp));
    timing.prepare_ms = t0.elapsed().as_secs_f64() * 1e3;
    let prep = match prepared {
        Ok(prep) => prep,
        Err(e) => {
            return Solved {
                result: SolveResult::invalid(format!("{}: {e}", cp.id)),
                timing,
                search: SearchInfo::default(),
            }
        }
    };
    if let Some(result) = super::budget::over_budget(&prep, &cp.id, ctx.search.part_budget) {
        return Solved {
            result,
            timing,
            search: SearchInfo::default(),
        };
    }
    let t1 = Instant::now();
    let solved = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        if ctx.search.is_plain() {
            let budget = ctx.search.work_budget(start, prep.top_k());
            let (res, n, halt) = solve_prepared(&prep, ctx.shard_size, &budget);
            let info = SearchInfo {
                shards: n,
                ..SearchInfo::default()
            };
            (res, info, halt)
        } else {
            solve_search(&prep, ctx.search, ctx.shard_size, start)
        }
    }));
    timing.enumerate_ms = t1.elapsed().as_secs_f64() * 1e3;
    let (result, search) = match solved {
        Ok((res, info, None)) => {
            timing.shards = info.shards;
            (res, info)
        }
        Ok((_, info, Some(halt))) => {
            timing.shards = info.shards;
            let result = super::budget::halted(&cp.id, halt, ctx.search, prep.top_k());
            (result, SearchInfo::default())
        }
        Err(p) => (
            SolveResult::gave_up(
                fixplan_core::Status::Failed,
                format!(
                    "{}: internal error in the enumeration: {}",
                    cp.id,
                    fixplan_worker::panic_text(p)
                ),
            ),
            SearchInfo::default(),
        ),
    };
    Solved {
        result,
        timing,
        search,
    }
}
