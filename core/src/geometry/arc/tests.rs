//! Arc primitives against hand values and brute-force sampling.

use super::*;
use proptest::prelude::*;
use std::f64::consts::{FRAC_1_SQRT_2, FRAC_PI_2, FRAC_PI_4, PI};

fn close(a: V2, b: V2, tol: f64) -> bool {
    (a - b).norm() <= tol
}

#[test]
fn from_bulge_semicircle_and_quarter() {
    let s = CircArc::from_bulge(v2(0., 0.), v2(2., 0.), 1.0).unwrap();
    assert!(close(s.center, v2(1., 0.), 1e-15));
    assert_eq!(s.radius, 1.0);
    assert!((s.sweep - PI).abs() < 1e-15);
    // Counter-clockwise from (0,0) to (2,0) about (1,0) passes below.
    assert!(close(s.midpoint(), v2(1., -1.), 1e-15));
    assert!(close(s.point_at(0.5), v2(1., -1.), 1e-15));
    assert!(close(s.tangent_start(), v2(0., -1.), 1e-15));
    assert!(close(s.tangent_end(), v2(0., 1.), 1e-15));

    let q = CircArc::from_bulge(v2(1., 0.), v2(0., 1.), (PI / 8.0).tan()).unwrap();
    assert!(close(q.center, v2(0., 0.), 1e-15));
    assert!((q.radius - 1.0).abs() < 1e-15);
    assert!((q.sweep - FRAC_PI_2).abs() < 1e-15);
    assert!(close(q.midpoint(), v2(FRAC_1_SQRT_2, FRAC_1_SQRT_2), 1e-15));
    assert!(close(q.tangent_start(), v2(0., 1.), 1e-15));
    assert!(close(q.tangent_end(), v2(-1., 0.), 1e-15));
    assert!((q.length() - FRAC_PI_2).abs() < 1e-15);
    // Clockwise (negative bulge) over the same chord: the centre moves to
    // the other side and the arc bulges left of the chord.
    let c = CircArc::from_bulge(v2(1., 0.), v2(0., 1.), -(PI / 8.0).tan()).unwrap();
    assert!(close(c.center, v2(1., 1.), 1e-15));
    assert!(close(
        c.midpoint(),
        v2(1. - FRAC_1_SQRT_2, 1. - FRAC_1_SQRT_2),
        1e-15
    ));
    assert!(CircArc::from_bulge(v2(1., 0.), v2(1., 0.), 1.0).is_none());
    assert!(CircArc::from_bulge(v2(1., 0.), v2(2., 0.), 0.0).is_none());
    assert!(CircArc::from_bulge(v2(1., 0.), v2(2., 0.), f64::NAN).is_none());
    // Huge bulges: nearly a full circle, no overflow.
    let big = CircArc::from_bulge(v2(0., 0.), v2(1e-3, 0.), 1e200).unwrap();
    assert!(big.radius.is_finite() && (big.sweep - 2.0 * PI).abs() < 1e-12);
}

#[test]
fn span_membership_at_the_ends() {
    let q = CircArc::from_bulge(v2(1., 0.), v2(0., 1.), (PI / 8.0).tan()).unwrap();
    let at = |deg: f64| v2(deg.to_radians().cos(), deg.to_radians().sin());
    assert!(q.contains_on_circle(at(0.0), 0.0));
    assert!(q.contains_on_circle(at(45.0), 0.0));
    assert!(q.contains_on_circle(at(90.0), 1e-12));
    assert!(!q.contains_on_circle(at(-1e-6), 0.0));
    assert!(!q.contains_on_circle(at(90.0 + 1e-6), 0.0));
    assert!(!q.contains_on_circle(at(225.0), 0.0));
    assert!(q.contains_on_circle(at(-1e-6), 1e-7));
    // A major arc (270 degrees, clockwise from (1,0) to (0,1)).
    let m = CircArc::from_bulge(v2(1., 0.), v2(0., 1.), -(3.0 * PI / 8.0).tan()).unwrap();
    assert!(close(m.center, v2(0., 0.), 1e-15));
    assert!(m.contains_on_circle(at(225.0), 0.0));
    assert!(m.contains_on_circle(at(-80.0), 0.0));
    assert!(!m.contains_on_circle(at(45.0), 0.0));
}

/// Minimum of `f` on `[0, 1]`: dense samples, then golden-section search
/// around every local minimum of the samples (the brute-force reference
/// for distances; a curve can pass near another in several places).
fn brute_min(f: impl Fn(f64) -> f64) -> f64 {
    const N: usize = 4000;
    let h = 1.0 / N as f64;
    let v: Vec<f64> = (0..=N).map(|i| f(i as f64 * h)).collect();
    let mut best = v.iter().copied().fold(f64::INFINITY, f64::min);
    for i in 0..=N {
        let left = if i > 0 { v[i - 1] } else { f64::INFINITY };
        let right = if i < N { v[i + 1] } else { f64::INFINITY };
        if v[i] <= left && v[i] <= right {
            best = best.min(golden(&f, (i as f64 - 1.0) * h, (i as f64 + 1.0) * h));
        }
    }
    best
}

/// Golden-section minimum of a unimodal `f` on `[lo, hi]` clipped to
/// `[0, 1]`.
fn golden(f: &impl Fn(f64) -> f64, lo: f64, hi: f64) -> f64 {
    let (mut lo, mut hi) = (lo.max(0.0), hi.min(1.0));
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..80 {
        let (x1, x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if f(x1) < f(x2) {
            hi = x2;
        } else {
            lo = x1;
        }
    }
    f(0.5 * (lo + hi))
}

fn arc_strategy() -> impl Strategy<Value = CircArc> {
    (
        (-3.0..3.0f64, -3.0..3.0f64),
        (-3.0..3.0f64, -3.0..3.0f64),
        prop_oneof![-6.0..-0.02f64, 0.02..6.0f64],
    )
        .prop_filter_map("chord too short", |((ax, ay), (bx, by), bulge)| {
            let (a, b) = (v2(ax, ay), v2(bx, by));
            ((b - a).norm() > 0.05)
                .then(|| CircArc::from_bulge(a, b, bulge))
                .flatten()
        })
}

fn point_strategy() -> impl Strategy<Value = V2> {
    (-6.0..6.0f64, -6.0..6.0f64).prop_map(|(x, y)| v2(x, y))
}

/// `c` is a pair of points on the two curves at the distance it claims.
fn check_pair(c: &Closest, on_first: impl Fn(V2) -> f64, on_second: impl Fn(V2) -> f64) {
    assert!(
        on_first(c.p) < 1e-9,
        "p off the first curve by {}",
        on_first(c.p)
    );
    assert!(
        on_second(c.q) < 1e-9,
        "q off the second curve by {}",
        on_second(c.q)
    );
    assert!((c.distance - (c.p - c.q).norm()).abs() < 1e-12);
}

/// How far `x` is from the arc as a set of points, by sampling.
fn off_arc(arc: &CircArc, x: V2) -> f64 {
    ((x - arc.center).norm() - arc.radius).abs()
        + if arc.contains_on_circle(x, 1e-9) {
            0.0
        } else {
            1.0
        }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn point_arc_distance_vs_sampling(arc in arc_strategy(), p in point_strategy()) {
        let exact = point_arc_closest(p, &arc);
        check_pair(&exact, |x| (x - p).norm(), |x| off_arc(&arc, x));
        let brute = brute_min(|t| (arc.point_at(t) - p).norm());
        prop_assert!((exact.distance - brute).abs() < 1e-9, "exact {} brute {}", exact.distance, brute);
    }

    #[test]
    fn segment_arc_distance_vs_sampling(arc in arc_strategy(), a in point_strategy(), b in point_strategy()) {
        let exact = segment_arc_closest(a, b, &arc);
        check_pair(&exact, |x| point_segment_dist2(x, a, b).sqrt(), |x| off_arc(&arc, x));
        let along_segment = brute_min(|t| arc.distance(a + (b - a) * t));
        let along_arc = brute_min(|t| point_segment_dist2(arc.point_at(t), a, b).sqrt());
        let brute = along_segment.min(along_arc);
        prop_assert!((exact.distance - brute).abs() < 1e-8, "exact {} brute {}", exact.distance, brute);
    }

    #[test]
    fn arc_arc_distance_vs_sampling(p in arc_strategy(), q in arc_strategy()) {
        let exact = arc_arc_closest(&p, &q);
        check_pair(&exact, |x| off_arc(&p, x), |x| off_arc(&q, x));
        let brute = brute_min(|t| q.distance(p.point_at(t))).min(brute_min(|t| p.distance(q.point_at(t))));
        prop_assert!((exact.distance - brute).abs() < 1e-8, "exact {} brute {}", exact.distance, brute);
    }

    #[test]
    fn segment_contains_vs_disk_and_chord_side(arc in arc_strategy(), p in point_strategy()) {
        let r = (p - arc.center).norm();
        let side = cross(arc.b - arc.a, p - arc.a) * arc.bulge.signum();
        // Away from the boundary (disk and chord line) the two must agree.
        prop_assume!((r - arc.radius).abs() > 1e-6 && side.abs() > 1e-6);
        prop_assert_eq!(arc.segment_contains(p), r < arc.radius && side < 0.0);
    }

    #[test]
    fn grown_arc_round_trip(arc in arc_strategy(), r in 0.0..1.0f64, t in -0.2..1.2f64) {
        // Parameters are unique within half a turn of the arc's midpoint.
        prop_assume!(((t - 0.5) * arc.sweep).abs() < PI - 1e-6);
        let Some(g) = arc.grown(r, 1e-9) else {
            prop_assert!(!arc.is_ccw() && arc.radius - r <= 1e-9);
            return Ok(());
        };
        let s = t * g.length();
        let q = g.point_at(s);
        prop_assert!(((q - g.center).norm() - g.radius).abs() < 1e-12);
        // Points slightly outside the span keep their sign (param centred
        // on the midpoint).
        prop_assert!((g.param_of(q) - s).abs() < 1e-9 * (1.0 + g.length()), "{} vs {}", g.param_of(q), s);
        // The grown arc's ends lie radially outward (convex) or inward
        // (concave) from the part arc's ends, at distance r.
        prop_assert!((g.point_at(0.0) - arc.a).norm() - r < 1e-9);
        prop_assert!((g.point_at(g.length()) - arc.b).norm() - r < 1e-9);
        // The tangent follows increasing s; the inward normal is normal.
        let ds = 1e-6 * g.radius;
        let fd = (g.point_at(s + ds) - g.point_at(s - ds)) / (2.0 * ds);
        prop_assert!((fd - g.tangent_at(s)).norm() < 1e-5);
        prop_assert!(g.inward_normal_at(s).dot(&g.tangent_at(s)).abs() < 1e-12);
    }
}

#[test]
fn grown_arcs_convex_and_concave() {
    let k = (PI / 8.0).tan();
    // Convex quarter arc about the origin, R = 1.
    let convex = CircArc::from_bulge(v2(1., 0.), v2(0., 1.), k).unwrap();
    let g = convex.grown(0.5, 1e-9).unwrap();
    assert!(g.is_convex() && (g.radius - 1.5).abs() < 1e-15);
    assert!((g.length() - 1.5 * FRAC_PI_2).abs() < 1e-14);
    assert!(close(g.point_at(0.0), v2(1.5, 0.), 1e-15));
    assert!(close(g.point_at(g.length()), v2(0., 1.5), 1e-14));
    assert!(close(
        g.point_at(0.5 * g.length()),
        v2(1.5, 1.5) * FRAC_1_SQRT_2,
        1e-14
    ));
    assert!(close(g.tangent_at(0.0), v2(0., 1.), 1e-15));
    assert!(close(g.inward_normal_at(0.0), v2(-1., 0.), 1e-15));
    assert!((g.param_of(v2(3., -0.03)) - 1.5 * (-0.01f64).atan2(1.0)).abs() < 1e-12);
    assert!(g.param_of(v2(3., -0.03)) < 0.0);
    // The same arc as a concave edge (outline running the other way):
    // radius R - r, positions clockwise about the centre.
    let concave = convex.reversed();
    let h = concave.grown(0.25, 1e-9).unwrap();
    assert!(!h.is_convex() && (h.radius - 0.75).abs() < 1e-15);
    assert!(close(h.point_at(0.0), v2(0., 0.75), 1e-15));
    assert!(close(h.point_at(h.length()), v2(0.75, 0.), 1e-14));
    assert!(close(h.tangent_at(0.0), v2(1., 0.), 1e-15));
    assert!(close(h.inward_normal_at(0.0), v2(0., 1.), 1e-15));
    assert!((h.param_of(v2(FRAC_1_SQRT_2, FRAC_1_SQRT_2)) - 0.75 * FRAC_PI_4).abs() < 1e-14);
    assert!(concave.grown(1.0, 1e-9).is_none());
    assert!(concave.grown(1.0 - 1e-10, 1e-9).is_none());
    assert!(concave.grown(0.999, 1e-9).is_some());
}

#[test]
fn segment_moments_series_meets_closed_form() {
    for phi in [0.05, 0.1, 0.2, 0.3, 0.4, 0.45, 0.5, 0.6] {
        let (s1, m1, j1) = unit_segment_series(phi);
        let (s2, m2, j2) = unit_segment_closed(phi);
        // The closed form loses about 1e-15 / phi^4 (relative) to
        // cancellation; the series is exact to rounding.
        let tol = 1e-14 / phi.powi(4);
        assert!((s1 / s2 - 1.0).abs() < tol, "S at {phi}: {s1} vs {s2}");
        assert!((m1 / m2 - 1.0).abs() < tol, "M at {phi}: {m1} vs {m2}");
        assert!((j1 / j2 - 1.0).abs() < tol, "J at {phi}: {j1} vs {j2}");
    }
    // Half disk of radius 1 about its diameter's midpoint.
    let half = CircArc::from_bulge(v2(-1., 0.), v2(1., 0.), 1.0).unwrap();
    let (s, m, j) = segment_moments(&half);
    assert!((s - FRAC_PI_2).abs() < 1e-15);
    assert!((m - 2.0 / 3.0).abs() < 1e-15);
    assert!((j - FRAC_PI_4).abs() < 1e-15);
    // A thin segment is nearly a parabolic one: S = 4/3 h sagitta.
    let thin = CircArc::from_bulge(v2(-1., 0.), v2(1., 0.), 1e-7).unwrap();
    let (s, _, j) = segment_moments(&thin);
    assert!((s / (4.0 / 3.0 * 1e-7) - 1.0).abs() < 1e-12);
    assert!((j / (4.0 / 15.0 * 1e-7) - 1.0).abs() < 1e-12);
}

#[test]
fn intersections_of_hand_made_curves() {
    let c = segment_circle(v2(-2., 0.), v2(2., 0.), v2(0., 0.), 1.0, 0.0);
    assert_eq!(c.as_slice(), &[v2(-1., 0.), v2(1., 0.)]);
    let t = segment_circle(v2(-2., 1.), v2(2., 1.), v2(0., 0.), 1.0, 0.0);
    assert_eq!(t.as_slice(), &[v2(0., 1.)]);
    assert!(segment_circle(
        v2(-2., 1.0 + 1e-6),
        v2(2., 1.0 + 1e-6),
        v2(0., 0.),
        1.0,
        0.0
    )
    .as_slice()
    .is_empty());
    assert_eq!(
        segment_circle(
            v2(-2., 1.0 + 1e-12),
            v2(2., 1.0 + 1e-12),
            v2(0., 0.),
            1.0,
            1e-9
        )
        .as_slice()
        .len(),
        1
    );
    let cc = circle_circle(v2(0., 0.), 1.0, v2(1., 0.), 1.0, 0.0);
    let y = 0.75f64.sqrt();
    assert!(
        close(cc.as_slice()[0], v2(0.5, -y), 1e-15) && close(cc.as_slice()[1], v2(0.5, y), 1e-15)
    );
    assert_eq!(
        circle_circle(v2(0., 0.), 1.0, v2(2., 0.), 1.0, 0.0).as_slice(),
        &[v2(1., 0.)]
    );
    assert!(circle_circle(v2(0., 0.), 1.0, v2(0., 0.), 1.0, 0.0)
        .as_slice()
        .is_empty());
    // Upper half of the unit circle against the x axis and a lower arc.
    let upper = CircArc::from_bulge(v2(1., 0.), v2(-1., 0.), 1.0).unwrap();
    let hits = segment_arc_intersections(v2(-2., 0.5), v2(2., 0.5), &upper, 0.0);
    assert_eq!(hits.as_slice().len(), 2);
    assert!(
        segment_arc_intersections(v2(-2., -0.5), v2(2., -0.5), &upper, 0.0)
            .as_slice()
            .is_empty()
    );
    let other = CircArc::from_bulge(v2(1., 0.5), v2(1., -2.), 1.0).unwrap();
    let h = arc_arc_intersections(&upper, &other, 0.0);
    for p in h.as_slice() {
        assert!(off_arc(&upper, *p) < 1e-12 && off_arc(&other, *p) < 1e-12);
    }
}

#[test]
fn circle_circle_with_a_nearly_straight_arc() {
    // Through the origin: a circle of radius 5e4 tangent to the x axis
    // there, and one of radius 5. Computed from the huge circle, `r - x`
    // cancels at 5e4 and the points come out 1e-8 off; from the small one
    // they are good to rounding of the huge centre (5e4 * 1e-16).
    let (c1, r1) = (v2(0., -5e4), 5e4);
    let (c2, r2) = (v2(3., 4.), 5.0);
    for hits in [
        circle_circle(c1, r1, c2, r2, 0.0),
        circle_circle(c2, r2, c1, r1, 0.0),
    ] {
        assert_eq!(hits.as_slice().len(), 2);
        for p in hits.as_slice() {
            assert!(((p - c1).norm() - r1).abs() < 1e-10, "{p:?}");
            assert!(((p - c2).norm() - r2).abs() < 1e-10, "{p:?}");
        }
        assert!(hits.as_slice().iter().any(|p| p.norm() < 1e-10));
    }
}
