//! The top-k mode (`top_k > 0` without `full_counts`) skips the mount
//! search of candidates that cannot enter the top-k: it must report the
//! first k fixtures of the full enumeration bit for bit, ties included,
//! however the work is split, and say that its admissible count is not
//! known.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

mod support;

use fixplan_core::{
    merge, solve, EnumerateOptions, Kit, Params, Part, PartialResult, Pattern, PreparedPart, Units,
};
use proptest::prelude::*;
use support::*;

/// Values of k around the interesting places: one, a few, more than most
/// parts hold.
const KS: [usize; 4] = [1, 2, 7, 40];

/// Every wrench zero: every fixture scores the same, so the ranking is the
/// canonical key alone and every comparison with the k-th fixture is a tie.
fn all_tied(mut pr: Params) -> Params {
    pr.wrenches = Some(vec![[0.0, 0.0, 0.0]]);
    pr
}

fn with_k(pr: &Params, top_k: usize, full_counts: bool) -> Params {
    Params {
        top_k,
        full_counts,
        ..pr.clone()
    }
}

/// The top-k mode's result at every k of [`KS`] against the full
/// enumeration (`top_k: 0`): the same first k fixtures, the same counts
/// but the admissible one, and `exact` false; with `full_counts` the same
/// fixtures and every count.
fn assert_top_k_mode_exact(part: &Part, kit: &Kit, pr: &Params) {
    let full = prep(part, kit, &with_k(pr, 0, false)).enumerate_all();
    assert!(full.counts.exact);
    for k in KS {
        let want = &full.fixtures[..k.min(full.fixtures.len())];
        let p = prep(part, kit, &with_k(pr, k, false));
        assert!(!p.counts_exact());
        let fast = p.enumerate_all();
        assert_eq!(fast.fixtures, want, "top-{k} mode, parallel");
        let serial = p
            .enumerate(0..p.combination_count(), EnumerateOptions::this_thread())
            .result;
        assert_eq!(serial.fixtures, want, "top-{k} mode, serial");
        assert!(!fast.counts.exact && !serial.counts.exact);
        assert_eq!(fast.counts.admissible(), None);
        let known = |c: &fixplan_core::Counts| (c.segments, c.combinations, c.setups, c.candidates);
        assert_eq!(known(&fast.counts), known(&full.counts));
        assert_eq!(known(&serial.counts), known(&full.counts));
        let counted = prep(part, kit, &with_k(pr, k, true)).enumerate_all();
        assert_eq!(counted.fixtures, want, "top-{k} with full counts");
        assert_eq!(counted.counts, full.counts);
    }
}

/// The pieces of `p`'s range cut at `cuts` (fractions), each enumerated
/// on its own and merged.
fn merged_pieces(p: &PreparedPart, cuts: &[f64]) -> PartialResult {
    let n = p.combination_count();
    let mut points: Vec<u64> = cuts.iter().map(|c| (c * n as f64) as u64).collect();
    points.extend([0, n]);
    points.sort();
    let pieces = points
        .windows(2)
        .map(|w| {
            p.enumerate(w[0]..w[1], EnumerateOptions::this_thread())
                .result
        })
        .collect();
    merge(p.top_k(), pieces)
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 12,
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x70b_c0de),
        ..ProptestConfig::default()
    })]

    #[test]
    fn top_k_mode_reports_the_first_k_of_the_full_enumeration(
        shape in shape_strategy(),
        alt in any::<bool>(),
        angle in prop_oneof![Just(45.0), Just(90.0)],
        holes in 5u32..=18,
        clearance in 0.0f64..0.2,
        tied in any::<bool>(),
    ) {
        let mut k = kit(if alt { Pattern::Alternating } else { Pattern::Square });
        k.cols = holes;
        k.rows = holes;
        let mut pr = params(angle, 1);
        pr.min_clearance = Some(clearance);
        let pr = if tied { all_tied(pr) } else { pr };
        assert_top_k_mode_exact(&part(&shape, &[]), &k, &pr);
    }

    #[test]
    fn any_split_of_a_top_k_mode_run_merges_to_the_same_bytes(
        shape in shape_strategy(),
        cuts in prop::collection::vec(0.0f64..1.0, 1..6),
        top_k in prop_oneof![Just(1usize), Just(3), Just(10)],
        tied in any::<bool>(),
    ) {
        let pr = with_k(&params(90.0, 1), top_k, false);
        let pr = if tied { all_tied(pr) } else { pr };
        let p = prep(&part(&shape, &[]), &kit(Pattern::Square), &pr);
        let whole = p.enumerate(0..p.combination_count(), EnumerateOptions::this_thread()).result;
        let merged = merged_pieces(&p, &cuts);
        prop_assert_eq!(&merged.counts, &whole.counts);
        prop_assert_eq!(
            serde_json::to_string(&merged.fixtures).unwrap(),
            serde_json::to_string(&whole.fixtures).unwrap()
        );
        prop_assert_eq!(&p.enumerate_all(), &whole);
    }
}

#[test]
fn top_k_mode_is_exact_on_parts_with_arcs() {
    for (name, outline) in arc_shapes() {
        for tied in [false, true] {
            let pr = params(90.0, 1);
            let pr = if tied { all_tied(pr) } else { pr };
            let p = arc_part(&outline, &[]);
            assert_top_k_mode_exact(&p, &kit(Pattern::Square), &pr);
            eprintln!("{name} (tied: {tied}) ok");
        }
    }
}

#[test]
fn top_k_mode_says_its_admissible_count_is_not_known() {
    let k = kit(Pattern::Alternating);
    let p = part(&l_shape(), &[]);
    let json = |pr: &Params| serde_json::to_value(solve(&p, &k, pr, Units::Mm)).unwrap();
    let fast = json(&with_k(&params(90.0, 1), 3, false));
    let counted = json(&with_k(&params(90.0, 1), 3, true));
    assert_eq!(fast["counts"]["counts_exact"], false);
    assert!(fast["counts"].get("admissible").is_none(), "{fast}");
    assert!(counted["counts"].get("counts_exact").is_none(), "{counted}");
    assert!(counted["counts"]["admissible"].as_u64().unwrap() >= 3);
    assert_eq!(fast["fixtures"], counted["fixtures"]);
    assert_eq!(fast["status"], "ok");
    // The JSON reads back to the same counts.
    let back: fixplan_core::Counts = serde_json::from_value(fast["counts"].clone()).unwrap();
    assert!(!back.exact && back.admissible().is_none());
    // It did skip work: one mount search per candidate is the full mode.
    let one = prep(&p, &k, &with_k(&params(90.0, 1), 1, false));
    let done = one.enumerate(0..one.combination_count(), EnumerateOptions::this_thread());
    let (res, profile) = (done.result, done.profile);
    assert!(
        profile.work.mount_searches < res.counts.candidates / 2,
        "{profile:?}"
    );
    // Keeping all fixtures counts them all anyway.
    let all = json(&with_k(&params(90.0, 1), 0, false));
    assert!(all["counts"]["admissible"].as_u64().is_some());
}
