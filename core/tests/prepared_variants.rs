//! A prepared part re-used with another setting (`with_kit`,
//! `with_grid_step`) is the part a fresh `prepare` gives: a study and a
//! coarse-to-fine search rely on it to skip re-deriving the geometry.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

mod support;

use fixplan_core::{prepare, Kit, Params, Part, Pattern, PrepareError, PreparedPart, Units};
use support::*;

/// Square and alternating plates, with and without an access region.
fn parts() -> Vec<(String, Part, Pattern)> {
    let access = vec![vec![[3.0, -1.5], [4.5, -1.5], [4.5, -0.35], [3.0, -0.35]]];
    let mut out = Vec::new();
    for (name, shape) in [("L", l_shape()), ("T", t_shape()), ("notched", notched())] {
        for pattern in [Pattern::Square, Pattern::Alternating] {
            for acc in [&vec![], &access] {
                let what = format!("{name} {pattern:?} access={}", acc.len());
                out.push((what, part(&shape, acc), pattern));
            }
        }
    }
    out
}

/// Same value (`Debug` shows every field, floats to the last bit) and same
/// enumeration, counts included. Returns the admissible count, so a test
/// can check that it compared more than empty results. The enumerations
/// run first: they compute the segment pair bounds, which a part holds
/// only from its first enumeration on (shared with its variants), so that
/// `Debug` then shows them on both sides.
fn assert_same_part(got: &PreparedPart, want: &PreparedPart, what: &str) -> u64 {
    let (g, w) = (got.enumerate_all(), want.enumerate_all());
    assert_eq!(format!("{got:?}"), format!("{want:?}"), "{what}");
    assert_eq!(g.counts, w.counts, "{what}: counts");
    assert_eq!(g, w, "{what}: fixtures");
    w.counts.admissible
}

/// Everything a kit and parameters can change without changing the
/// geometry (spacing, locator radius, edge trim, wrenches).
fn settings(pattern: Pattern) -> Vec<(&'static str, Kit, Params)> {
    let base = kit(pattern);
    let other = match pattern {
        Pattern::Square => Pattern::Alternating,
        Pattern::Alternating => Pattern::Square,
    };
    let mut small = base.clone();
    (small.cols, small.rows) = (9, 7);
    let mut clamp = base.clone();
    clamp.clamp.travel = [1.0, 4.0];
    clamp.clamp.axis_offset = 0.2;
    let mut tight = params(45.0, 1);
    tight.min_clearance = Some(0.3);
    tight.top_k = 3;
    vec![
        ("other pattern", kit(other), params(90.0, 1)),
        ("small plate", small, params(90.0, 1)),
        ("other clamp", clamp, params(90.0, 1)),
        ("angle, clearance, top_k", base.clone(), tight),
        ("grid step 2", base, params(60.0, 2)),
    ]
}

#[test]
fn with_kit_equals_a_fresh_prepare() {
    let (mut checked, mut admissible) = (0, 0);
    for (what, p, pattern) in parts() {
        let base = prep(&p, &kit(pattern), &params(90.0, 1));
        for (change, k, pr) in settings(pattern) {
            let got = base.with_kit(&k, &pr, Units::Mm).expect("same geometry");
            let want = prep(&p, &k, &pr);
            admissible += assert_same_part(&got, &want, &format!("{what}, {change}"));
            checked += 1;
        }
    }
    assert_eq!(checked, 60);
    assert!(admissible > 1000, "{admissible}");
}

#[test]
fn with_kit_keeps_user_wrenches() {
    let p = part(&l_shape(), &[]);
    let mut pr = params(90.0, 1);
    pr.wrenches = Some(vec![[1.0, 0.0, 0.0], [0.0, -1.0, 0.5]]);
    let base = prep(&p, &kit(Pattern::Square), &pr);
    let mut other = pr.clone();
    other.max_clamp_angle_deg = 45.0;
    let got = base.with_kit(&kit(Pattern::Alternating), &other, Units::Mm);
    let want = prep(&p, &kit(Pattern::Alternating), &other);
    let admissible = assert_same_part(&got.expect("same geometry"), &want, "wrenches");
    assert!(admissible > 0);
}

#[test]
fn with_kit_refuses_another_geometry() {
    let p = part(&t_shape(), &[]);
    let (k, pr) = (kit(Pattern::Square), params(90.0, 1));
    let base = prep(&p, &k, &pr);
    let geometry = |e: Result<PreparedPart, PrepareError>| match e {
        Err(PrepareError::OtherGeometry(what)) => what,
        other => panic!("{other:?}"),
    };
    let mut wide = k.clone();
    wide.spacing = 1.25;
    assert_eq!(
        geometry(base.with_kit(&wide, &pr, Units::Mm)),
        "lattice spacing"
    );
    let mut thin = k.clone();
    thin.locator_radius = 0.2;
    assert_eq!(
        geometry(base.with_kit(&thin, &pr, Units::Mm)),
        "locator radius"
    );
    let mut trim = pr.clone();
    trim.edge_trim = Some(0.1);
    assert_eq!(geometry(base.with_kit(&k, &trim, Units::Mm)), "edge trim");
    // -0.0 and 0.0 are different inputs (and different study keys).
    let mut zero = pr.clone();
    zero.edge_trim = Some(0.0);
    let zero_base = prep(&p, &k, &zero);
    zero.edge_trim = Some(-0.0);
    assert_eq!(
        geometry(zero_base.with_kit(&k, &zero, Units::Mm)),
        "edge trim"
    );
    // The default trim depends on the unit.
    let mut default = pr.clone();
    default.edge_trim = None;
    let mm = prep(&p, &k, &default);
    assert_eq!(geometry(mm.with_kit(&k, &default, Units::In)), "edge trim");
    let mut ws = pr.clone();
    ws.wrenches = Some(vec![[1.0, 0.0, 0.0]]);
    assert_eq!(geometry(base.with_kit(&k, &ws, Units::Mm)), "wrenches");
    // Kit and parameter errors come first, as from `prepare`.
    let mut bad = wide.clone();
    bad.cols = 0;
    let fresh = prepare(&p, &bad, &pr, Units::Mm).unwrap_err();
    assert_eq!(base.with_kit(&bad, &pr, Units::Mm).unwrap_err(), fresh);
    assert!(matches!(fresh, PrepareError::Kit(_)), "{fresh:?}");
}

#[test]
fn with_grid_step_equals_a_fresh_prepare() {
    let mut admissible = 0;
    for (what, p, pattern) in parts() {
        let k = kit(pattern);
        let base = prep(&p, &k, &params(90.0, 1));
        for step in [1, 2, 3] {
            let got = base.with_grid_step(step).expect("step >= 1");
            assert_eq!(got.grid_step(), step);
            let want = prep(&p, &k, &params(90.0, step));
            admissible += assert_same_part(&got, &want, &format!("{what}, step {step}"));
        }
        let zero = prepare(&p, &k, &params(90.0, 0), Units::Mm).unwrap_err();
        assert_eq!(base.with_grid_step(0).unwrap_err(), zero, "{what}");
    }
    assert!(admissible > 1000, "{admissible}");
}

#[test]
fn accessors_report_the_inputs() {
    let k = kit(Pattern::Alternating);
    let mut pr = params(60.0, 2);
    pr.top_k = 4;
    let p = prep(&part(&notched(), &[]), &k, &pr);
    assert_eq!(p.top_k(), 4);
    assert_eq!(p.grid_step(), 2);
    assert_eq!(p.locator_radius(), k.locator_radius / k.spacing);
    assert_eq!(p.cos_max_angle(), 60f64.to_radians().cos());
    assert_eq!(p.outline().points().len(), notched().len());
    let res = p.enumerate_all();
    assert_eq!(res.counts.segments, p.segments().len() as u64);
    assert!(res.fixtures.len() <= 4);
}
