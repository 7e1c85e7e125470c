//! Completeness: the pruned enumeration finds exactly the fixtures that an
//! enumeration of every lattice point within the part's diameter finds.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

mod support;

use fixplan_core::Pattern;
use proptest::prelude::*;
use support::*;

fn assert_same(p: &fixplan_core::PreparedPart, what: &str) {
    let pruned = p.enumerate_all();
    let brute = brute_force(p);
    assert_eq!(pruned.counts, brute.counts, "{what}: counts differ");
    assert_eq!(pruned.fixtures.len(), brute.fixtures.len(), "{what}");
    for (a, b) in pruned.fixtures.iter().zip(&brute.fixtures) {
        assert_eq!(a, b, "{what}: fixture differs");
    }
}

#[test]
fn hand_made_shapes_square_and_alternating_with_and_without_access() {
    let access = vec![vec![[3.0, -1.5], [4.5, -1.5], [4.5, -0.35], [3.0, -0.35]]];
    let mut total = 0;
    for (name, shape) in [("L", l_shape()), ("T", t_shape()), ("notched", notched())] {
        for pattern in [Pattern::Square, Pattern::Alternating] {
            for acc in [&vec![], &access] {
                for angle in [45.0, 90.0] {
                    let p = prep(&part(&shape, acc), &kit(pattern), &params(angle, 1));
                    let what = format!("{name} {pattern:?} access={} angle={angle}", acc.len());
                    assert_same(&p, &what);
                    total += p.enumerate_all().counts.admissible;
                }
            }
        }
    }
    // The comparison means something only if fixtures exist.
    assert!(
        total > 100,
        "only {total} fixtures over all hand-made cases"
    );
}

#[test]
fn access_constraints_remove_fixtures() {
    let shape = notched();
    let k = kit(Pattern::Square);
    let free = prep(&part(&shape, &[]), &k, &params(90.0, 1)).enumerate_all();
    let access = vec![vec![[-1.0, 1.0], [1.0, 1.0], [1.0, 2.5], [-1.0, 2.5]]];
    let p = prep(&part(&shape, &access), &k, &params(90.0, 1));
    let held = p.enumerate_all();
    assert!(held.counts.admissible < free.counts.admissible);
    assert_same(&p, "notched with a large access region");
}

fn polygon_strategy() -> impl Strategy<Value = (Vec<[f64; 2]>, bool, bool, f64)> {
    (4usize..=12)
        .prop_flat_map(|n| {
            (
                prop::collection::vec(0.0..std::f64::consts::TAU, n),
                prop::collection::vec(1.2f64..3.0, n),
                any::<bool>(),
                any::<bool>(),
                prop_oneof![Just(45.0), Just(90.0)],
            )
        })
        .prop_map(|(a, r, alt, acc, ang)| (star([0.3, -0.2], &a, &r), alt, acc, ang))
        .prop_filter("a valid polygon of at least 4 vertices", |(p, ..)| {
            p.len() >= 4 && fixplan_core::parts::validate_polygon(p).is_ok()
        })
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 24,
        // Fixed seed: the same 24 polygons on every run and machine; failures
        // found while developing are kept in `regressions/` as well.
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x5eed_f1c5),
        failure_persistence: Some(Box::new(
            proptest::test_runner::FileFailurePersistence::WithSource("regressions"),
        )),
        ..ProptestConfig::default()
    })]

    #[test]
    fn random_polygons_pruned_equals_brute_force((shape, alt, with_access, angle) in polygon_strategy()) {
        let pattern = if alt { Pattern::Alternating } else { Pattern::Square };
        let access = if with_access {
            let c = shape[0];
            vec![vec![[c[0] + 0.3, c[1] - 0.4], [c[0] + 1.2, c[1] - 0.1], [c[0] + 0.6, c[1] + 0.9]]]
        } else {
            vec![]
        };
        // A region may swallow the whole part's outline: that part is still valid.
        let p = prep(&part(&shape, &access), &kit(pattern), &params(angle, 1));
        assert_same(&p, &format!("{shape:?}"));
    }
}

/// The paper-like bench part with its three access regions, in inches on the
/// 0.75 in alternating plate: a real case, not just random shapes.
#[test]
fn gluegun_bench_case_pruned_equals_brute_force() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/cases/gluegun-28.json"
    );
    let text = std::fs::read_to_string(path).expect("bench case in examples/cases");
    let mut case: fixplan_core::Case = serde_json::from_str(&text).expect("valid case");
    case.params.top_k = 0;
    for angle in [45.0, 90.0] {
        case.params.max_clamp_angle_deg = angle;
        let p = fixplan_core::prepare(&case.part(), &case.kit, &case.params, case.units)
            .expect("valid case");
        assert_same(&p, &format!("gluegun at {angle} degrees"));
        assert!(p.enumerate_all().counts.admissible > 10);
    }
}

/// The 57-edge housing against brute force: minutes, so run on demand
/// (`cargo test --profile ci -p fixplan-core --test brute_force -- --ignored`).
#[test]
#[ignore]
fn housing_bench_case_pruned_equals_brute_force() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/cases/housing-57.json"
    );
    let text = std::fs::read_to_string(path).expect("bench case in examples/cases");
    let mut case: fixplan_core::Case = serde_json::from_str(&text).expect("valid case");
    case.params.top_k = 0;
    let p = fixplan_core::prepare(&case.part(), &case.kit, &case.params, case.units)
        .expect("valid case");
    assert_same(&p, "housing");
}
