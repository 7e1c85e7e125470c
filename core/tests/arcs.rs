//! Outlines with arcs (SPEC 8): the pruned enumeration equals a brute force
//! on hand-made and random parts, every fixture passes the independent
//! form-closure check, the fixture set is invariant under rigid motions,
//! clockwise listing and grid steps, and it converges to the enumeration of
//! a finely flattened outline.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

mod support;

use fixplan_core::parts::ccw_of_cw_outline;
use fixplan_core::{Fixture, Pattern, PreparedPart, SegmentKind, Vertex};
use proptest::prelude::*;
use support::*;

fn assert_same(p: &PreparedPart, what: &str) -> u64 {
    pruned_equals_brute_force(p, what).counts.admissible
}

#[test]
fn hand_made_arc_parts_pruned_equals_brute_force() {
    let mut on_arcs = 0;
    let mut total = 0;
    for (name, shape) in arc_shapes() {
        for pattern in [Pattern::Square, Pattern::Alternating] {
            for angle in [45.0, 90.0] {
                let p = prep(&arc_part(&shape, &[]), &kit(pattern), &params(angle, 1));
                total += assert_same(&p, &format!("{name} {pattern:?} {angle}"));
                let arc = |i: usize| p.segments()[i].kind() == SegmentKind::Arc;
                on_arcs += p
                    .enumerate_all()
                    .fixtures
                    .iter()
                    .filter(|f| f.segments.iter().any(|&i| arc(i)) || arc(f.clamp_segment))
                    .count();
            }
        }
    }
    // The comparison means something only if fixtures touch arcs.
    assert!(
        total > 500 && on_arcs > 200,
        "{total} fixtures, {on_arcs} on arcs"
    );
}

#[test]
fn a_full_circle_has_segments_but_no_pose() {
    // Three locators on one circle (or two half circles sharing a centre)
    // leave the part free to turn: a continuum, no pose (SPEC 8.4).
    let disc = [[2.0, 0.0, 1.0], [-2.0, 0.0, 1.0]];
    let p = prep(
        &arc_part(&disc, &[]),
        &kit(Pattern::Square),
        &params(90.0, 1),
    );
    assert_eq!(p.segments().len(), 2);
    let r = p.enumerate_all();
    assert_eq!(r.counts.setups, 0);
    assert_eq!(r.counts.admissible, 0);
}

#[test]
fn an_arc_that_reaches_past_the_size_limit_is_refused_before_the_sweep() {
    // Bulges of +-1e9 on a 10-spacing chord: circles of radius ~2.5e9
    // spacings, though every vertex is within 10 of the origin. The sweep
    // would allocate one span per lattice row it reaches.
    for b in [1e9, -1e9] {
        let part = arc_part(&[[0.0, 0.0, b], [10.0, 0.0, 0.0], [5.0, 5.0, 0.0]], &[]);
        let e = fixplan_core::prepare(
            &part,
            &kit(Pattern::Square),
            &params(90.0, 1),
            fixplan_core::Units::Mm,
        );
        match e {
            Err(fixplan_core::PrepareError::TooLarge { extent, .. }) => {
                assert!(extent > 1e9, "{extent}")
            }
            Err(other) => panic!("bulge {b}: refused for another reason: {other}"),
            Ok(_) => panic!("bulge {b}: accepted"),
        }
    }
}

/// Random polygons with random convex and concave bulges, invalid ones
/// (self-crossing arcs) filtered out.
fn arc_outline_strategy() -> impl Strategy<Value = (Vec<[f64; 3]>, bool, f64)> {
    (4usize..=7)
        .prop_flat_map(|n| {
            (
                prop::collection::vec(0.0..std::f64::consts::TAU, n),
                prop::collection::vec(1.2f64..2.6, n),
                prop::collection::vec(prop_oneof![Just(0.0), -0.6f64..0.6], n),
                any::<bool>(),
                prop_oneof![Just(45.0), Just(90.0)],
            )
        })
        .prop_map(|(a, r, b, alt, ang)| {
            let pts = star([0.2, -0.1], &a, &r);
            let v: Vec<[f64; 3]> = pts
                .iter()
                .zip(b.iter().cycle())
                .map(|(p, &b)| [p[0], p[1], b])
                .collect();
            (v, alt, ang)
        })
        .prop_filter("a valid outline with an arc", |(v, ..)| {
            let vs: Vec<Vertex> = v.iter().map(|&x| x.into()).collect();
            v.len() >= 3
                && v.iter().any(|x| x[2] != 0.0)
                && fixplan_core::parts::validate_outline(&vs).is_ok()
        })
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 12,
        rng_seed: proptest::test_runner::RngSeed::Fixed(0xa2c5_0001),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn random_arc_outlines_pruned_equals_brute_force((shape, alt, angle) in arc_outline_strategy()) {
        let pattern = if alt { Pattern::Alternating } else { Pattern::Square };
        let p = prep(&arc_part(&shape, &[]), &kit(pattern), &params(angle, 1));
        assert_same(&p, &format!("{shape:?}"));
    }
}

#[test]
fn rigid_motion_and_clockwise_listing_leave_the_fixtures() {
    for (name, shape) in arc_shapes() {
        let k = kit(Pattern::Alternating);
        let pr = params(90.0, 1);
        let base = prep(&arc_part(&shape, &[]), &k, &pr).enumerate_all();
        // Clockwise listing: normalised back to the same CCW list, so the
        // result is the same bit for bit.
        let vs: Vec<Vertex> = shape.iter().map(|&x| x.into()).collect();
        let cw: Vec<[f64; 3]> = ccw_of_cw_outline(&vs)
            .iter()
            .map(|v| [v.x, v.y, v.bulge])
            .collect();
        let cw_res = prep(&arc_part(&cw, &[]), &k, &pr).enumerate_all();
        assert_eq!(cw_res, base, "{name}: clockwise listing");
        // A rotation by 0.7 rad and a shift: bulges do not change.
        let (s, c) = 0.7f64.sin_cos();
        let moved: Vec<[f64; 3]> = shape
            .iter()
            .map(|p| [c * p[0] - s * p[1] + 13.25, s * p[0] + c * p[1] - 7.5, p[2]])
            .collect();
        let m = prep(&arc_part(&moved, &[]), &k, &pr).enumerate_all();
        let keys = |fs: &[Fixture], all: bool| -> Vec<_> {
            let mut v: Vec<_> = fs
                .iter()
                .filter(|f| all || !f.borderline)
                .map(frame_free_key)
                .collect();
            v.sort();
            v
        };
        // Every non-borderline fixture of one is a fixture of the other.
        let (ka, kb) = (keys(&base.fixtures, true), keys(&m.fixtures, true));
        for k in keys(&base.fixtures, false) {
            assert!(kb.binary_search(&k).is_ok(), "{name}: {k:?} lost by moving");
        }
        for k in keys(&m.fixtures, false) {
            assert!(
                ka.binary_search(&k).is_ok(),
                "{name}: {k:?} appeared by moving"
            );
        }
        // SPEC 6's sphere of applied wrenches is fixed in the part frame:
        // turning the part inside it moves the samples, so scores agree to
        // the sampling error only (as for polygons); a translation keeps
        // them to rounding.
        let best = |fs: &[Fixture]| fs.iter().map(|f| f.score).fold(f64::INFINITY, f64::min);
        let (a, b) = (best(&base.fixtures), best(&m.fixtures));
        assert!((a - b).abs() < 0.05 * a, "{name}: best {a} vs {b}");
        let shifted: Vec<[f64; 3]> = shape
            .iter()
            .map(|p| [p[0] - 31.5, p[1] + 8.125, p[2]])
            .collect();
        let tp = prep(&arc_part(&shifted, &[]), &k, &pr);
        let t = tp.enumerate_all();
        // Setups with a contact within rounding of a smooth joint, or a
        // tangential pose, are borderline (SPEC 8.4): only they may come
        // and go with the rounding of another frame.
        let slack =
            borderline_setups(&prep(&arc_part(&shape, &[]), &k, &pr)).max(borderline_setups(&tp));
        assert!(
            t.counts.setups.abs_diff(base.counts.setups) <= slack,
            "{name}: translation changed setups beyond the {slack} borderline ones"
        );
        assert_eq!(
            t.counts.admissible, base.counts.admissible,
            "{name}: translation"
        );
        for (x, ys) in [(&base.fixtures, &t.fixtures), (&t.fixtures, &base.fixtures)] {
            for f in x.iter().filter(|f| !f.borderline) {
                let found = ys.iter().any(|g| {
                    frame_free_key(g) == frame_free_key(f)
                        && (g.score - f.score).abs() < 1e-9 * f.score
                });
                assert!(found, "{name}: translation lost {f:?}");
            }
        }
    }
}

/// Setups whose decision margin is below SPEC's borderline band.
fn borderline_setups(p: &PreparedPart) -> u64 {
    let mut n = 0;
    let count = p.segments().len();
    for (_, c) in fixplan_core::parts::combinations_in(count, 0..u64::MAX) {
        p.setups_of_combination(c, |s| n += u64::from(s.margin < 1e-6));
    }
    n
}

#[test]
fn grid_step_two_is_a_subset_of_step_one_with_arcs() {
    for (name, shape) in arc_shapes() {
        for pattern in [Pattern::Square, Pattern::Alternating] {
            let one = prep(&arc_part(&shape, &[]), &kit(pattern), &params(90.0, 1)).enumerate_all();
            let two = prep(&arc_part(&shape, &[]), &kit(pattern), &params(90.0, 2)).enumerate_all();
            for f in &two.fixtures {
                assert!(one.fixtures.contains(f), "{name} {pattern:?}: {f:?}");
            }
        }
    }
}

/// Fraction of the non-borderline fixtures of `a` that `b` has too, by
/// lattice points, clamp rotation and mount, with a pose angle within
/// `dtheta` (segment indices differ: a flattened arc is many segments).
fn matched(a: &[Fixture], b: &[Fixture], dtheta: f64) -> (usize, usize) {
    let firm: Vec<&Fixture> = a.iter().filter(|f| !f.borderline).collect();
    let hits = firm
        .iter()
        .filter(|f| {
            b.iter().any(|g| {
                let d = (g.theta - f.theta).rem_euclid(std::f64::consts::TAU);
                g.locators == f.locators
                    && g.rotation == f.rotation
                    && g.mount == f.mount
                    && d.min(std::f64::consts::TAU - d) < dtheta
            })
        })
        .count();
    (hits, firm.len())
}

/// An arc part and the same part flattened very finely, both with
/// `edge_trim` 0, give corresponding fixtures: the flattened part's are
/// (almost all) the exact part's, and the exact part finds most of the
/// flattened part's and more (its contacts are not lost in the gaps that a
/// flattened convex arc leaves between the grown chords, about r / R of
/// its length).
#[test]
fn fine_flattening_converges_to_the_exact_arcs() {
    let shape = [[0., 0., 0.], [4.5, 0., 1.], [4.5, 3., 0.], [0., 3., 0.]];
    let vs: Vec<Vertex> = shape.iter().map(|&x| x.into()).collect();
    let flat = fixplan_core::parts::Outline::new(&vs)
        .unwrap()
        .flatten(2e-4);
    let flat: Vec<[f64; 2]> = flat.iter().map(|p| [p.x, p.y]).collect();
    let mut pr = params(60.0, 1);
    pr.edge_trim = Some(0.0);
    let k = kit(Pattern::Square);
    let exact = prep(&arc_part(&shape, &[]), &k, &pr);
    let fine = prep(&part(&flat, &[]), &k, &pr);
    assert!(
        fine.segments().len() > 60,
        "{} segments",
        fine.segments().len()
    );
    let (e, f) = (exact.enumerate_all(), fine.enumerate_all());
    let (hits_f, n_f) = matched(&f.fixtures, &e.fixtures, 2e-3);
    let (hits_e, n_e) = matched(&e.fixtures, &f.fixtures, 2e-3);
    println!(
        "exact {} fixtures, flattened ({} segments) {}; flattened in exact {hits_f}/{n_f}, exact in flattened {hits_e}/{n_e}",
        e.counts.admissible,
        fine.segments().len(),
        f.counts.admissible
    );
    assert!(n_f > 100 && hits_f as f64 >= 0.97 * n_f as f64);
    assert!(hits_e as f64 >= 0.6 * n_e as f64);
    let best = |fs: &[Fixture]| fs.iter().map(|f| f.score).fold(f64::INFINITY, f64::min);
    let (be, bf) = (best(&e.fixtures), best(&f.fixtures));
    assert!(
        (be - bf).abs() <= 0.01 * be,
        "best {be} exact vs {bf} flattened"
    );
}
