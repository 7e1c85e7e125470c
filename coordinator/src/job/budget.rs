//! `--part-budget`: a part whose work is beyond the run's budget gets
//! `over_budget` before any enumeration, and the run goes on.
//!
//! The budget is in the shard planner's cost unit ([`super::shards::cost`]:
//! segment combinations x segments), so the verdict is the same on every
//! machine and at every thread count. It is checked twice: before
//! preparing, on the work preparing itself does (each outline edge is
//! tested against every outline and access edge), so that an outline of
//! a million vertices is not prepared at all; then on the prepared part's
//! real segments. The first is a sound lower bound of the part's work:
//! no part is refused before preparing whose preparation is within the
//! budget, whatever its segments turn out to be (an outline's edge count
//! bounds its segments from neither side: trimming drops edges, access
//! regions split them). The setup budget and the deadline are checked
//! inside the enumeration ([`fixplan_core::WorkBudget`]), and so is the
//! fixture cap (`--part-fixtures`): what a part keeps is what it holds in
//! memory and writes in one results chunk.

use super::search::SearchOptions;
use fixplan_core::{fixture_cap, BudgetHalt, Part, PreparedPart, SolveResult, Status};

/// `--part-setups`'s default (`run`, `study`, `coordinator`): seconds to
/// minutes of a core, 17 times the setups of the largest example part
/// (`housing-57` x3).
pub const DEFAULT_PART_SETUPS: u64 = 10_000_000;

/// `--part-fixtures`'s default (`run`, `study`, `coordinator`): a kept
/// fixture costs about 2.6 KB at the peak of a run (shard results, merge,
/// report, chunk: 11.4 GB max RSS for `housing-57` x3's 4.38 M fixtures
/// with `--top-k 0`, 1.07 GB for x2's 413 k), so a part stays under about
/// 650 MB, well under 2 GiB.
pub const DEFAULT_PART_FIXTURES: u64 = 250_000;

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
    verdict(id, estimated_cost(prep), budget?)
}

/// [`over_budget`] before preparing: the edge-against-edge tests that
/// preparing does, `outline edges x (outline edges + access edges)`, a
/// sound lower bound of the part's work (counted in the same unit).
pub fn over_budget_unprepared(part: &Part, id: &str, budget: Option<u64>) -> Option<SolveResult> {
    let budget = budget?;
    let outline = part.outline.len() as u64;
    let access = part.access.iter().map(Vec::len).sum::<usize>() as u64;
    let tests = outline.saturating_mul(outline.saturating_add(access));
    (tests > budget).then(|| {
        SolveResult::gave_up(
            Status::OverBudget,
            format!(
                "{id}: {outline} outline edges x {} outline and access edges = {tests} edge tests to prepare it, beyond --part-budget {budget}; not prepared",
                outline + access
            ),
        )
    })
}

fn verdict(
    id: &str,
    (cost, combinations, segments): (u64, u64, usize),
    budget: u64,
) -> Option<SolveResult> {
    (cost > budget).then(|| {
        SolveResult::gave_up(
            Status::OverBudget,
            format!(
                "{id}: {combinations} segment combinations x {segments} segments = {cost}, beyond --part-budget {budget}; not enumerated"
            ),
        )
    })
}

/// The part's [`Status::OverBudget`] result when a budget stopped its
/// enumeration (`--part-setups`, `--part-fixtures`, `--part-seconds`):
/// what it exceeded. When both deterministic budgets bind the part (its
/// `top_k` lets the fixture cap bite), which of them a piece meets first
/// depends on threads and shards, so the message names both: the bytes of
/// a result must not depend on how the work was cut.
pub fn halted(id: &str, halt: BudgetHalt, search: &SearchOptions, top_k: usize) -> SolveResult {
    let fixtures = fixture_cap(search.part_fixtures, top_k);
    let why = match (halt, search.part_setups, fixtures) {
        (BudgetHalt::Setups(_) | BudgetHalt::Fixtures(_), Some(setups), Some(cap)) => format!(
            "more than {setups} setups or more than {cap} fixtures kept, beyond --part-setups {setups} or --part-fixtures {cap}"
        ),
        (BudgetHalt::Setups(budget), ..) => {
            format!("more than {budget} setups, beyond --part-setups {budget}")
        }
        (BudgetHalt::Fixtures(cap), ..) => {
            format!("more than {cap} fixtures kept, beyond --part-fixtures {cap}")
        }
        (BudgetHalt::Deadline, ..) => format!(
            "still enumerating after {} s, beyond --part-seconds (wall clock)",
            search.part_seconds.unwrap_or_default()
        ),
    };
    SolveResult::gave_up(
        Status::OverBudget,
        format!("{id}: {why}; enumeration stopped"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn part(outline: usize, access: &[usize]) -> Part {
        let ring = |n: usize| -> Vec<[f64; 2]> {
            (0..n)
                .map(|i| {
                    let a = i as f64 * std::f64::consts::TAU / n as f64;
                    [50.0 * a.cos(), 50.0 * a.sin()]
                })
                .collect()
        };
        Part {
            outline: ring(outline).into_iter().map(Into::into).collect(),
            holes: Vec::new(),
            access: access.iter().map(|&n| ring(n)).collect(),
        }
    }

    /// Access edges are never segments: a part with few outline edges
    /// and a big access region is not refused before preparing for the
    /// combinations its access edges would make as segments (4 outline
    /// edges and 60 access edges: 41,664 combinations x 64 would be
    /// 2,666,496), only for the edge tests preparing does.
    #[test]
    fn the_check_before_preparing_counts_what_preparing_does() {
        let p = part(4, &[60]);
        assert!(over_budget_unprepared(&p, "p", Some(4 * 64)).is_none());
        let over = over_budget_unprepared(&p, "p", Some(4 * 64 - 1)).unwrap();
        assert_eq!(over.status, Status::OverBudget);
        let e = over.error.unwrap();
        assert!(e.contains("256 edge tests") && e.contains("255"), "{e}");
        let ring = part(20_000, &[]);
        assert!(over_budget_unprepared(&ring, "r", Some(1_000_000)).is_some());
        assert!(over_budget_unprepared(&ring, "r", None).is_none());
    }
}
