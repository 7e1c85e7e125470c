//! The setup budget and the fixture cap checked inside the enumeration:
//! a part stops iff it has more setups than the budget, or keeps more
//! fixtures than the cap, whatever the threads, the cut into ranges or
//! the top-k mode; within them the result is the unbudgeted one bit for
//! bit.
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
    within(p, &WorkBudget::new(Some(setups), None), pieces, this_thread)
}

/// [`budgeted`] with any budget.
fn within(
    p: &PreparedPart,
    budget: &WorkBudget,
    pieces: u64,
    this_thread: bool,
) -> (fixplan_core::PartialResult, Option<BudgetHalt>) {
    let n = p.combination_count();
    let size = n.div_ceil(pieces).max(1);
    let mut halted = None;
    let mut parts = Vec::new();
    for start in (0..n).step_by(size as usize) {
        let options = EnumerateOptions {
            this_thread,
            budget: Some(budget),
            ..EnumerateOptions::default()
        };
        let done = p.enumerate(start..(start + size).min(n), options);
        halted = halted.or(done.halted);
        parts.push(done.result);
    }
    let merged = merge(p.top_k(), parts);
    let verdict = budget.verdict(halted, merged.counts.setups, merged.fixtures.len());
    (merged, verdict)
}

/// [`within`] a cap of `cap` fixtures, on a pool of `threads`.
fn capped(
    p: &PreparedPart,
    cap: u64,
    (pieces, this_thread, threads): (u64, bool, usize),
) -> (fixplan_core::PartialResult, Option<BudgetHalt>) {
    let budget = WorkBudget::new(None, None).with_fixtures(Some(cap), p.top_k());
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| within(p, &budget, pieces, this_thread))
}

/// The cuts and pools every verdict must agree over: one range or many,
/// on this thread or on pools of 1 and 3 threads.
const CUTS: [(u64, bool, usize); 5] = [
    (1, true, 1),
    (1, false, 3),
    (3, true, 1),
    (7, false, 1),
    (7, false, 3),
];

#[test]
fn a_part_stops_iff_it_keeps_more_fixtures_than_the_cap_however_split() {
    let kit = kit(Pattern::Square);
    let mut pr = params(30.0, 1);
    pr.top_k = 0;
    let all = prep(&part(&notched(), &[]), &kit, &pr);
    let total = all.enumerate_all().fixtures.len() as u64;
    assert!(total > 20, "a part with fixtures to keep: {total}");
    // top-k 0 keeps them all; top-k above the cap (pruned) keeps k, and
    // the cap bites only when k is above it.
    for top_k in [0, total as usize - 2] {
        pr.top_k = top_k;
        let p = prep(&part(&notched(), &[]), &kit, &pr);
        let whole = p.enumerate_all();
        let kept = whole.fixtures.len() as u64;
        for cut in CUTS {
            let (same, verdict) = capped(&p, kept, cut);
            assert_eq!(verdict, None, "a cap at the count is within it");
            assert_eq!(same, whole, "within the cap: the same result");
            for cap in [0, 1, kept / 2, kept - 1] {
                assert_eq!(
                    capped(&p, cap, cut).1,
                    Some(BudgetHalt::Fixtures(cap)),
                    "{cut:?}, top-k {top_k}, cap {cap} of {kept}"
                );
            }
        }
    }
    // A top-k within the cap never exceeds it: no cap at all.
    pr.top_k = 3;
    let p = prep(&part(&notched(), &[]), &kit, &pr);
    let (same, verdict) = capped(&p, 3, CUTS[4]);
    assert_eq!((same, verdict), (p.enumerate_all(), None));
}

/// With `--good-enough` the kept fixtures are those of the combinations
/// up to the first hit: a cap below them stops the part, one at them
/// does not, whatever the pool.
#[test]
fn the_cap_counts_the_fixtures_up_to_a_good_enough_stop() {
    let mut pr = params(30.0, 1);
    pr.top_k = 0;
    let p = prep(&part(&notched(), &[]), &kit(Pattern::Square), &pr);
    let whole = p.enumerate_all();
    // The median score: a hit well inside the range, after some fixtures.
    let good = whole.fixtures[whole.fixtures.len() / 2].score;
    let stop = |cap: u64, threads: usize| {
        let budget = WorkBudget::new(None, None).with_fixtures(Some(cap), 0);
        let options = EnumerateOptions {
            budget: Some(&budget),
            ..EnumerateOptions::good_enough(good)
        };
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let done = pool.install(|| p.enumerate(0..p.combination_count(), options));
        let verdict = budget.verdict(
            done.halted,
            done.result.counts.setups,
            done.result.fixtures.len(),
        );
        (done.result.fixtures.len() as u64, done.stopped_at, verdict)
    };
    let (kept, hit, verdict) = stop(u64::MAX - 1, 1);
    assert!(hit.is_some() && verdict.is_none(), "{hit:?} {verdict:?}");
    assert!(kept > 2 && kept < whole.fixtures.len() as u64, "{kept}");
    for threads in [1, 3] {
        assert_eq!(stop(kept, threads), (kept, hit, None), "{threads} threads");
        for cap in [0, kept / 2, kept - 1] {
            assert_eq!(
                stop(cap, threads).2,
                Some(BudgetHalt::Fixtures(cap)),
                "{threads} threads, cap {cap} of {kept}"
            );
        }
    }
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
