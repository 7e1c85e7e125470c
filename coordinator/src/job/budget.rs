//! `--part-budget`: a part whose estimated work is beyond the run's
//! budget gets `over_budget` before any enumeration, with the estimate,
//! and the run goes on.
//!
//! The budget is in the shard planner's cost unit ([`super::shards::cost`]:
//! segment combinations x segments), so the verdict is the same on every
//! machine and at every thread count. It is checked twice: before
//! preparing, on the planner's estimate from the outline (every edge one
//! segment), so that an outline of 20,000 vertices is not prepared at all
//! (preparing allocates a table of segments squared); then on the
//! prepared part's real segments.

use fixplan_core::combination_count;
use fixplan_core::{Part, PreparedPart, SolveResult, Status};

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
    verdict(id, estimated_cost(prep), budget?, "")
}

/// [`over_budget`] before preparing: the estimate of the outline and
/// access regions' edges, each taken for one segment.
pub fn over_budget_unprepared(part: &Part, id: &str, budget: Option<u64>) -> Option<SolveResult> {
    let edges = part.outline.len() + part.access.iter().map(Vec::len).sum::<usize>();
    let combinations = combination_count(edges);
    let cost = super::shards::cost(combinations, edges);
    verdict(
        id,
        (cost, combinations, edges),
        budget?,
        " (estimated from its edges, before preparing)",
    )
}

fn verdict(
    id: &str,
    (cost, combinations, segments): (u64, u64, usize),
    budget: u64,
    how: &str,
) -> Option<SolveResult> {
    (cost > budget).then(|| {
        SolveResult::gave_up(
            Status::OverBudget,
            format!(
                "{id}: {combinations} segment combinations x {segments} segments = {cost}{how}, beyond --part-budget {budget}; not enumerated"
            ),
        )
    })
}
