//! The setup budget checked inside the enumeration: a part stops iff it
//! has more setups than the budget, whatever the threads, the cut into
//! ranges or the top-k mode; within the budget the result is the
//! unbudgeted one bit for bit.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

mod support;

use fixplan_core::{merge, BudgetHalt, EnumerateOptions, Pattern, PreparedPart, WorkBudget};
use support::*;

/// `p` cut into `pieces` ranges sharing one budget of `setups`, each on
/// the pool or on this thread: the merged result and the verdict.
fn budgeted(
    p: &PreparedPart,
    setups: u64,
    pieces: u64,
    this_thread: bool,
) -> (fixplan_core::PartialResult, Option<BudgetHalt>) {
    let budget = WorkBudget::new(Some(setups), None);
    let n = p.combination_count();
    let size = n.div_ceil(pieces).max(1);
    let mut halted = None;
    let mut parts = Vec::new();
    for start in (0..n).step_by(size as usize) {
        let options = EnumerateOptions {
            this_thread,
            budget: Some(&budget),
            ..EnumerateOptions::default()
        };
        let done = p.enumerate(start..(start + size).min(n), options);
        halted = halted.or(done.halted);
        parts.push(done.result);
    }
    let merged = merge(p.top_k(), parts);
    let verdict = budget.verdict(halted, merged.counts.setups);
    (merged, verdict)
}

#[test]
fn a_part_stops_iff_its_setups_exceed_the_budget_however_split() {
    let kit = kit(Pattern::Square);
    for top_k in [0, 3] {
        let mut pr = params(30.0, 1);
        pr.top_k = top_k;
        let p = prep(&part(&notched(), &[]), &kit, &pr);
        let whole = p.enumerate_all();
        let total = whole.counts.setups;
        assert!(total > 20, "a part with setups to count: {total}");
        for (pieces, this_thread) in [(1, true), (1, false), (3, true), (7, false)] {
            let at = |b| budgeted(&p, b, pieces, this_thread);
            let (same, verdict) = at(total);
            assert_eq!(verdict, None, "budget = setups is within it");
            assert_eq!(same, whole, "within the budget: the same result");
            for b in [0, 1, total / 2, total - 1] {
                let (_, verdict) = at(b);
                assert_eq!(
                    verdict,
                    Some(BudgetHalt::Setups(b)),
                    "{pieces} pieces, top-k {top_k}, budget {b} of {total}"
                );
            }
        }
    }
}

#[test]
fn a_passed_deadline_stops_the_enumeration() {
    let p = prep(
        &part(&notched(), &[]),
        &kit(Pattern::Square),
        &params(30.0, 1),
    );
    let past = std::time::Instant::now();
    let budget = WorkBudget::new(None, Some(past));
    let options = EnumerateOptions {
        budget: Some(&budget),
        ..EnumerateOptions::this_thread()
    };
    let done = p.enumerate(0..p.combination_count(), options);
    assert_eq!(done.halted, Some(BudgetHalt::Deadline));
    assert_eq!(
        done.result.counts.combinations, 0,
        "stopped before the first"
    );
}
