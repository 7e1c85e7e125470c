//! Coarse-to-fine search (`--grid-steps 4,2,1`) and early stop
//! (`--good-enough SCORE`) for one prepared part.
//!
//! Each grid step is a full enumeration at that step (SPEC `grid_step`:
//! locators 2 and 3 at multiples of the step from locator 1). The fixtures
//! of step `k*s` are a subset of those of step `s`, so each refinement only
//! adds fixtures; the part's result is the finest step's, the same bytes as
//! a plain run at that step. With `--good-enough`, every step stops at the
//! shortest prefix of the combination range (in combination order) that
//! admits a fixture scoring SCORE or better (`PreparedPart::enumerate`,
//! deterministic whatever the threads), and a hit ends the part: finer steps
//! are not run.

use super::enumerate::solve_prepared;
use fixplan_core::{
    report, BudgetHalt, Counts, EnumerateOptions, FixtureReport, PartialResult, PreparedPart,
    SolveResult, WorkBudget,
};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// How each part is searched (the default: one full enumeration).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SearchOptions {
    /// Grid steps, coarse to fine; each a multiple of the next.
    pub grid_steps: Option<Vec<u32>>,
    /// Stop a part at the first combination that admits a fixture with this
    /// score or better.
    pub good_enough: Option<f64>,
    /// `--part-budget`: a part whose estimated work (segment combinations
    /// x segments) is beyond it gets `over_budget` without enumerating.
    pub part_budget: Option<u64>,
    /// `--part-setups`: a part (each grid step of it) with more setups
    /// than this is stopped and gets `over_budget`; deterministic.
    pub part_setups: Option<u64>,
    /// `--part-fixtures`: a part (each grid step of it) keeping more
    /// fixtures than this (top-k 0 or above it) is stopped and gets
    /// `over_budget`; deterministic.
    pub part_fixtures: Option<u64>,
    /// `--part-seconds`: a part still enumerating after this many seconds
    /// is stopped and gets `over_budget`; wall clock, not deterministic.
    pub part_seconds: Option<f64>,
}

/// Why `--grid-steps` or `--good-enough` cannot be used.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SearchError {
    /// No step at all.
    #[error("--grid-steps is empty")]
    NoSteps,
    /// A step that is not a whole number of at least 1.
    #[error("--grid-steps: {0:?} is not a whole number >= 1")]
    BadStep(String),
    /// Steps whose fixture sets would not be nested.
    #[error("--grid-steps must go from coarse to fine, each step a multiple of the next (the subset property): {a} then {b} is not")]
    NotNested {
        /// The coarser step.
        a: u32,
        /// The next one, not a divisor of `a`.
        b: u32,
    },
    /// A threshold no score can be compared with.
    #[error("--good-enough {0} must be a finite number")]
    BadScore(f64),
    /// A time budget that is no duration.
    #[error("--part-seconds {0} must be a positive number of seconds, at most a year")]
    BadSeconds(f64),
}

/// Parses `4,2,1`.
pub fn parse_grid_steps(text: &str) -> Result<Vec<u32>, SearchError> {
    let steps = text
        .split(',')
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .map(|t| match t.parse::<u32>() {
            Ok(n) if n >= 1 => Ok(n),
            _ => Err(SearchError::BadStep(t.to_string())),
        })
        .collect::<Result<Vec<_>, _>>()?;
    let o = SearchOptions {
        grid_steps: Some(steps),
        ..SearchOptions::default()
    };
    o.validate()?;
    Ok(o.grid_steps.unwrap_or_default())
}

impl SearchOptions {
    /// A part's budget: the setups and the fixtures (for a part keeping
    /// its best `top_k`) of one enumeration, and the instant
    /// `--part-seconds` from `start`.
    pub fn work_budget(&self, start: std::time::Instant, top_k: usize) -> WorkBudget {
        let deadline = self
            .part_seconds
            .map(|s| start + std::time::Duration::from_secs_f64(s));
        WorkBudget::new(self.part_setups, deadline).with_fixtures(self.part_fixtures, top_k)
    }

    /// One full enumeration: neither option given.
    pub fn is_plain(&self) -> bool {
        self.grid_steps.is_none() && self.good_enough.is_none()
    }

    /// Checks the options before any work (a bad option must not end a
    /// run half-way).
    pub fn validate(&self) -> Result<(), SearchError> {
        if let Some(steps) = &self.grid_steps {
            if steps.is_empty() {
                return Err(SearchError::NoSteps);
            }
            if let Some(&s) = steps.iter().find(|&&s| s == 0) {
                return Err(SearchError::BadStep(s.to_string()));
            }
            for w in steps.windows(2) {
                if w[0] <= w[1] || w[0] % w[1] != 0 {
                    return Err(SearchError::NotNested { a: w[0], b: w[1] });
                }
            }
        }
        if let Some(g) = self.good_enough {
            if !g.is_finite() {
                return Err(SearchError::BadScore(g));
            }
        }
        if let Some(s) = self.part_seconds {
            if !(s > 0.0 && s <= 366.0 * 86400.0) {
                return Err(SearchError::BadSeconds(s));
            }
        }
        Ok(())
    }

    /// The grid step of the part's result: the finest step, or `default`.
    pub fn final_step(&self, default: u32) -> u32 {
        self.grid_steps
            .as_ref()
            .and_then(|s| s.last().copied())
            .unwrap_or(default)
    }
}

/// One grid step of a part (`/fixplan/part` field `refine`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct StepSummary {
    /// The step: locators 2 and 3 at multiples of it from locator 1.
    pub grid_step: u32,
    /// SPEC counts at this step.
    pub counts: Counts,
    /// Fixtures kept (top-k) at this step.
    pub fixtures: usize,
    /// Score of the best fixture at this step.
    pub best_score: Option<f64>,
    /// The best fixture at this step.
    pub best: Option<FixtureReport>,
    /// Admissible fixtures this step added to the previous (coarser) one;
    /// `null` in top-k mode, which does not count them (`--full-counts`).
    pub added: Option<u64>,
    /// How much this step lowered the best score (previous best - this best;
    /// absent for the first step or when either step holds nothing).
    pub improved_by: Option<f64>,
    /// `--good-enough`: the combination index where this step stopped.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stopped_at: Option<u64>,
    /// Wall time of this step.
    pub enumerate_ms: f64,
}

/// Why a part's enumeration ended early.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SearchInfo {
    /// `--grid-steps`: what each step found, coarse to fine.
    pub steps: Option<Vec<StepSummary>>,
    /// `Some(index)`: stopped by `--good-enough` at that combination index.
    pub stopped_at: Option<u64>,
    /// Shards enumerated over all steps.
    pub shards: usize,
}

/// The summary of one step, given the previous one.
pub fn step_summary(
    step: u32,
    res: &SolveResult,
    prev: Option<&StepSummary>,
    stopped_at: Option<u64>,
    enumerate_ms: f64,
) -> StepSummary {
    let counts = res.counts.unwrap_or_default();
    let best = res.fixtures.first().cloned();
    let best_score = best.as_ref().map(|f| f.score);
    StepSummary {
        grid_step: step,
        counts,
        fixtures: res.fixtures.len(),
        best_score,
        best,
        added: counts
            .admissible()
            .map(|a| a.saturating_sub(prev.and_then(|p| p.counts.admissible()).unwrap_or(0))),
        improved_by: match (prev.and_then(|p| p.best_score), best_score) {
            (Some(a), Some(b)) => Some(a - b),
            _ => None,
        },
        stopped_at,
        enumerate_ms,
    }
}

/// Solves a prepared part with the search options: the result of the last
/// step run, what each step found, and the budget that stopped a step
/// (each step has the setup budget; the deadline is the part's, from
/// `start`).
pub fn solve_search(
    prep: &PreparedPart,
    opts: &SearchOptions,
    shard_size: Option<u64>,
    start: std::time::Instant,
) -> (SolveResult, SearchInfo, Option<BudgetHalt>) {
    let steps: Vec<u32> = opts
        .grid_steps
        .clone()
        .unwrap_or_else(|| vec![prep.grid_step()]);
    let mut info = SearchInfo::default();
    let mut summaries: Vec<StepSummary> = Vec::new();
    let mut last = SolveResult::invalid("no grid step");
    for step in steps {
        let p = match prep.with_grid_step(step) {
            Ok(p) => p,
            Err(e) => {
                last = SolveResult::invalid(e.to_string());
                break;
            }
        };
        let t0 = std::time::Instant::now();
        let budget = opts.work_budget(start, p.top_k());
        let (res, hit, halt) = match opts.good_enough {
            Some(g) => {
                let options = EnumerateOptions {
                    budget: Some(&budget),
                    ..EnumerateOptions::good_enough(g)
                };
                let done = p.enumerate(0..p.combination_count(), options);
                let (partial, hit): (PartialResult, Option<u64>) = (done.result, done.stopped_at);
                info.shards += 1;
                let halt =
                    budget.verdict(done.halted, partial.counts.setups, partial.fixtures.len());
                (report(&p, &partial), hit, halt)
            }
            None => {
                let (res, n, halt) = solve_prepared(&p, shard_size, &budget);
                info.shards += n;
                (res, None, halt)
            }
        };
        if halt.is_some() {
            return (res, info, halt);
        }
        let ms = t0.elapsed().as_secs_f64() * 1e3;
        summaries.push(step_summary(step, &res, summaries.last(), hit, ms));
        last = res;
        if hit.is_some() {
            info.stopped_at = hit;
            break;
        }
    }
    if opts.grid_steps.is_some() {
        info.steps = Some(summaries);
    }
    (last, info, None)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_steps_parse() {
        assert_eq!(parse_grid_steps("4,2,1").unwrap(), vec![4, 2, 1]);
        assert_eq!(parse_grid_steps(" 6, 3 ").unwrap(), vec![6, 3]);
        assert_eq!(parse_grid_steps("2").unwrap(), vec![2]);
        assert_eq!(parse_grid_steps("").unwrap_err(), SearchError::NoSteps);
        assert!(matches!(
            parse_grid_steps("4,3"),
            Err(SearchError::NotNested { a: 4, b: 3 })
        ));
        assert!(matches!(
            parse_grid_steps("1,2"),
            Err(SearchError::NotNested { .. })
        ));
        assert!(matches!(
            parse_grid_steps("2,2"),
            Err(SearchError::NotNested { .. })
        ));
        assert!(matches!(
            parse_grid_steps("4,0"),
            Err(SearchError::BadStep(_))
        ));
        assert!(matches!(
            parse_grid_steps("x"),
            Err(SearchError::BadStep(_))
        ));
        let o = SearchOptions {
            good_enough: Some(f64::NAN),
            ..SearchOptions::default()
        };
        assert!(o.validate().is_err());
    }
}
