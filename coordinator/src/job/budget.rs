//! `--part-budget`: a part whose estimated work is beyond the run's
//! budget gets `over_budget` before any enumeration, with the estimate,
//! and the run goes on.
//!
//! The budget is in the shard planner's cost unit ([`super::shards::cost`]:
//! segment combinations x segments), known once the part is prepared, so
//! the verdict is the same on every machine and at every thread count.

use fixplan_core::{PreparedPart, SolveResult, Status};

/// The estimated work of a prepared part, in [`super::shards::cost`]
/// units, with the counts it is made of.
pub fn estimated_cost(prep: &PreparedPart) -> (u64, u64, usize) {
    let segments = prep.segments().len();
    let combinations = prep.combination_count();
    (
        super::shards::cost(combinations, segments),
        combinations,
        segments,
    )
}

/// The part's [`Status::OverBudget`] result when its estimated work is
/// beyond `budget`; `None` when it is within (or there is no budget).
pub fn over_budget(prep: &PreparedPart, id: &str, budget: Option<u64>) -> Option<SolveResult> {
    let budget = budget?;
    let (cost, combinations, segments) = estimated_cost(prep);
    (cost > budget).then(|| {
        SolveResult::gave_up(
            Status::OverBudget,
            format!(
                "{id}: {combinations} segment combinations x {segments} segments = {cost}, beyond --part-budget {budget}; not enumerated"
            ),
        )
    })
}
