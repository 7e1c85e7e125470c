//! The sweeps' soundness: every setup's `L3` lies in the region built
//! from its `L2`, for every kind of pivot, and the row scan lists every
//! lattice point of a region.

use super::scan::{quad_spans, run_points, scan_span_list, scan_spans, Span};
use super::*;
use crate::geometry::{cross, rot, v2};
use crate::segments::{Feature, LineFeature};

#[test]
fn spans_cover_every_lattice_point_near_the_quad() {
    let q = Quad {
        pts: [v2(0.2, 0.1), v2(3.7, 1.2), v2(0.5, 2.9), v2(3.1, 4.4)],
        margin: 0.3,
    };
    let mut spans = Vec::new();
    quad_spans(&q, 1, &mut spans);
    let mut inside = 0;
    for x in -2..7 {
        for y in -2..7 {
            let d = hull_distance(&q.pts, v2(x as f64, y as f64));
            // Within the margin: listed. Far outside (the spans are a
            // box-shaped superset, up to sqrt 2 margins): not listed.
            if d <= q.margin {
                assert!(contains(&spans, [x, y]), "{x},{y}");
                inside += 1;
            } else if d > 1.5 * q.margin {
                assert!(!contains(&spans, [x, y]), "{x},{y} at {d}");
            }
        }
    }
    assert!(inside > 5);
}

/// A segment of the line through `origin` with direction angle `dir`,
/// contacts in `[s0, s1]`.
fn line(origin: V2, dir: f64, s0: f64, s1: f64) -> Segment {
    let u = v2(dir.cos(), dir.sin());
    let n = v2(u.y, -u.x);
    Segment {
        edge: 0,
        s0,
        s1,
        feature: Feature::Line(LineFeature::new(origin, u, n)),
    }
}

/// Checks that a known setup's `L3` lies in the region built from its
/// `L2`, and its angle in the angle set.
fn assert_covered(segs: [&Segment; 3], same_ab: bool, s: [f64; 3], theta: f64) -> bool {
    let p = [0, 1, 2].map(|k| segs[k].point(s[k]));
    let (sin, cos) = theta.sin_cos();
    let l2 = rot(cos, sin, p[1] - p[0]);
    let l3 = rot(cos, sin, p[2] - p[0]);
    let dmax_ac = crate::segments::PairBounds::between(segs[0], segs[2]).dmax;
    let swept = segs.map(SweptSegment::of);
    let Some(sweep) = LocatorSweep::new([&swept[0], &swept[1], &swept[2]], same_ab, dmax_ac) else {
        return false; // nearly parallel: the caller scans annuli
    };
    if matches!(
        sweep,
        LocatorSweep::Lines(LineSweep {
            degenerate: true,
            ..
        })
    ) {
        return false;
    }
    let t = crate::geometry::angle_set::wrap_angle(theta);
    let Some(pt) = sweep.pivot_point(l2) else {
        panic!("angle {t} not in an empty angle set");
    };
    assert!(pt.contains_angle(t), "angle {t} not in {pt:?}");
    let mut quads = Vec::new();
    if !sweep.region(&pt, &mut quads) {
        return false; // too many pieces: annuli
    }
    let best = quads
        .iter()
        .map(|q| hull_distance(&q.pts, l3) - q.margin)
        .fold(f64::INFINITY, f64::min);
    assert!(best <= 1e-9, "L3 {l3:?} outside by {best}: {quads:?}");
    true
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig {
        cases: 3000,
        failure_persistence: None,
        ..Default::default()
    })]

    /// Soundness of the pruning: for random segments and a random pose
    /// that puts three contacts on them, the region built from `L2`
    /// holds `L3`, whether the part turns or slides.
    #[test]
    fn every_setup_lies_in_its_region(
        o in proptest::array::uniform3((-5.0f64..5.0, -5.0f64..5.0)),
        dirs in proptest::array::uniform3(0.0f64..std::f64::consts::TAU),
        lens in proptest::array::uniform3(0.5f64..8.0),
        fr in proptest::array::uniform3(0.0f64..1.0),
        theta in 0.0f64..std::f64::consts::TAU,
        kind in 0u8..8,
        sweep in -6.0f64..6.0,
    ) {
        let mut dirs = dirs;
        match kind {
            1 | 5 => dirs[1] = dirs[0],                    // parallel, same way
            2 => dirs[1] = dirs[0] + std::f64::consts::PI, // facing
            _ => {}
        }
        let seg = |k: usize| line(v2(o[k].0, o[k].1), dirs[k], 0.0, lens[k]);
        // An arc (convex or concave, up to almost a full turn),
        // contacts on a piece of it.
        let arc_seg = |k: usize, sweep: f64| {
            let arc = crate::geometry::arc::GrownArc {
                center: v2(o[k].0, o[k].1),
                radius: lens[k] / 2.0,
                start_angle: dirs[k],
                sweep,
            };
            Segment {
                edge: 0,
                s0: 0.1 * arc.length(),
                s1: 0.9 * arc.length(),
                feature: Feature::Arc(arc),
            }
        };
        let (a, mut b, mut c) = (seg(0), seg(1), seg(2));
        if kind >= 4 {
            proptest::prop_assume!(sweep.abs() > 1e-3);
        }
        if kind == 4 || kind == 5 || kind == 7 {
            c = arc_seg(2, sweep);
        }
        if kind >= 6 {
            // A line and an arc pivot (the arc's sweep mirrored for
            // the third segment's, so both signs meet).
            b = arc_seg(1, -sweep);
        }
        let s = [0, 1, 2].map(|k| {
            let g = [&a, &b, &c][k];
            g.s0 + fr[k] * (g.s1 - g.s0)
        });
        if kind == 3 {
            // Locators 1 and 2 on one segment, in order along it.
            let s1 = fr[1] * a.s1;
            let (lo, hi) = (s[0].min(s1), s[0].max(s1));
            proptest::prop_assume!(hi - lo > 1e-3);
            assert_covered([&a, &a, &c], true, [lo, hi, s[2]], theta);
        } else {
            let checked = assert_covered([&a, &b, &c], false, s, theta);
            // The line-arc sweep has no fallback short of its piece
            // budget: it must have covered the setup.
            proptest::prop_assert!(checked || kind < 6);
        }
    }
}

fn contains(spans: &[Span], point: [i64; 2]) -> bool {
    let x = point[0] as f64;
    spans
        .iter()
        .any(|s| s.y == point[1] && s.lo <= x && x <= s.hi)
}

/// Distance from `p` to the convex hull of four points (brute force:
/// inside one of the triangles, else the nearest of the six sides).
fn hull_distance(pts: &[V2; 4], p: V2) -> f64 {
    let tri = |a: V2, b: V2, c: V2| {
        let s = [
            cross(b - a, p - a),
            cross(c - b, p - b),
            cross(a - c, p - c),
        ];
        s.iter().all(|&x| x >= 0.0) || s.iter().all(|&x| x <= 0.0)
    };
    for i in 0..4 {
        for j in 0..4 {
            for k in 0..4 {
                if i != j && j != k && i != k && tri(pts[i], pts[j], pts[k]) {
                    return 0.0;
                }
            }
        }
    }
    let mut best = f64::INFINITY;
    for i in 0..4 {
        for j in i + 1..4 {
            best = best.min(crate::geometry::point_segment_dist2(p, pts[i], pts[j]).sqrt());
        }
    }
    best
}

/// Whether some pose puts the locators `locs` strictly inside the three
/// segments, as the setup search keeps a pose (every angle solved).
fn has_setup(segs: [&Segment; 3], locs: &[V2; 3]) -> bool {
    let contacts = crate::poses::TripleContacts::of(segs.map(|s| &s.feature));
    let mut found = false;
    contacts.solve_at_angles(
        locs,
        |_| true,
        &|_, _| true,
        |pose, _| {
            found |= (0..3).all(|k| {
                let s = segs[k].param_of(pose.inverse_apply(locs[k]));
                segs[k].inner_margin(s) > 0.0
            });
        },
    );
    found
}

/// The lattice points a sweep lists for `L2 = l2`; `None` when it has no
/// pivot point there or sends the caller to the annuli.
fn listed(sweep: &LocatorSweep<'_>, l2: [i64; 2]) -> Option<Vec<[i64; 2]>> {
    let pt = sweep.pivot_point(v2(l2[0] as f64, l2[1] as f64))?;
    let mut out = Vec::new();
    let mut scratch = SweepScratch::default();
    sweep
        .for_each_third_locator(&pt, 1, &mut scratch, |l3, _| out.push(l3))
        .then_some(out)
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig {
        cases: 600,
        failure_persistence: None,
        ..Default::default()
    })]

    /// The finer pieces of two lines pivoting with an arc third
    /// (`ARC_THIRD_TARGET_MARGIN`) keep every lattice point of the cover
    /// they replaced (the straight segments' margin) that gives a setup:
    /// the old cover is the oracle, `L2` a lattice point near a posed
    /// triple's.
    #[test]
    fn the_finer_arc_cover_keeps_every_setup_of_the_coarser(
        o in proptest::array::uniform3((-5.0f64..5.0, -5.0f64..5.0)),
        dirs in proptest::array::uniform3(0.0f64..std::f64::consts::TAU),
        lens in proptest::array::uniform3(0.5f64..8.0),
        fr in proptest::array::uniform2(0.0f64..1.0),
        theta in 0.0f64..std::f64::consts::TAU,
        sweep in -6.0f64..6.0,
        nudge in (-1i64..=1, -1i64..=1),
    ) {
        proptest::prop_assume!(sweep.abs() > 1e-3);
        let seg = |k: usize| line(v2(o[k].0, o[k].1), dirs[k], 0.0, lens[k]);
        let arc = crate::geometry::arc::GrownArc {
            center: v2(o[2].0, o[2].1),
            radius: lens[2] / 4.0,
            start_angle: dirs[2],
            sweep,
        };
        let c = Segment {
            edge: 0,
            s0: 0.1 * arc.length(),
            s1: 0.9 * arc.length(),
            feature: Feature::Arc(arc),
        };
        let (a, b) = (seg(0), seg(1));
        let swept = [&a, &b, &c].map(SweptSegment::of);
        let mut coarse_third = swept[2];
        coarse_third.third.curved = false;
        let dmax = crate::segments::PairBounds::between(&a, &c).dmax;
        let fine = LocatorSweep::new([&swept[0], &swept[1], &swept[2]], false, dmax);
        let coarse = LocatorSweep::new([&swept[0], &swept[1], &coarse_third], false, dmax);
        let (Some(fine), Some(coarse)) = (fine, coarse) else {
            return Ok(()); // nearly parallel: annuli
        };
        let (p, q) = (a.point(fr[0] * lens[0]), b.point(fr[1] * lens[1]));
        let (sin, cos) = theta.sin_cos();
        let l2 = rot(cos, sin, q - p);
        let l2 = [l2.x.round() as i64 + nudge.0, l2.y.round() as i64 + nudge.1];
        let (Some(old), Some(new)) = (listed(&coarse, l2), listed(&fine, l2)) else {
            return Ok(());
        };
        let locs = |l3: [i64; 2]| [[0, 0], l2, l3].map(|p| v2(p[0] as f64, p[1] as f64));
        for l3 in old.iter().filter(|l3| !new.contains(l3)) {
            proptest::prop_assert!(
                !has_setup([&a, &b, &c], &locs(*l3)),
                "L2 {l2:?} L3 {l3:?} dropped"
            );
        }
    }
}

/// A coordinate for the scan tests: on a lattice line, a hair off one
/// (where rounding decides), or anywhere.
fn scan_coordinate() -> impl proptest::strategy::Strategy<Value = f64> {
    use proptest::prelude::*;
    prop_oneof![
        (-6i64..=6).prop_map(|k| k as f64),
        ((-6i64..=6), -3i32..=3).prop_map(|(k, ulps)| {
            let x = k as f64;
            let step = if x == 0.0 {
                1e-300
            } else {
                x.abs() * f64::EPSILON
            };
            x + f64::from(ulps) * step
        }),
        -6.5f64..6.5,
    ]
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig {
        cases: 4000,
        failure_persistence: None,
        ..Default::default()
    })]

    /// The scan by runs (empty spans dropped as they are made) lists the
    /// same lattice points in the same order as the scan of every span:
    /// corners and margins on, or an ulp off, lattice lines and steps.
    #[test]
    fn runs_scan_as_the_spans_did(
        corners in proptest::collection::vec(
            proptest::array::uniform4((scan_coordinate(), scan_coordinate())),
            1..5,
        ),
        margins in proptest::collection::vec(
            proptest::prop_oneof![
                proptest::strategy::Just(0.0),
                proptest::strategy::Just(0.25),
                proptest::strategy::Just(0.5),
                0.0f64..1.5,
            ],
            4,
        ),
        grid_step in 1i64..=3,
    ) {
        let quads: Vec<Quad> = corners
            .iter()
            .zip(&margins)
            .map(|(pts, &margin)| Quad { pts: pts.map(|(x, y)| v2(x, y)), margin })
            .collect();
        let (mut by_spans, mut by_runs) = (Vec::new(), Vec::new());
        scan_spans(&quads, grid_step, &mut Vec::new(), |p| by_spans.push(p));
        scan_quads(&quads, grid_step, &mut Vec::new(), |p| by_runs.push(p));
        proptest::prop_assert_eq!(by_runs, by_spans);
    }
}

/// A span's run holds exactly the lattice points the span scan visits,
/// at the places rounding decides: ends on a multiple of the step, an
/// ulp either side, and quotients that round onto an integer.
#[test]
fn a_run_holds_the_points_its_span_scan_visits() {
    let mut ends = vec![0.0, -0.0, f64::NAN, 1e-300, -1e-300];
    for k in -40i64..=40 {
        let x = k as f64;
        let mut up = x;
        let mut down = x;
        for _ in 0..3 {
            up = up.next_up();
            down = down.next_down();
            ends.extend([up, down]);
        }
        ends.extend([x, x + 0.5, x / 3.0, x * 0.1]);
    }
    for grid_step in 1..=3 {
        for &lo in &ends {
            for &hi in &ends {
                let mut scanned = Vec::new();
                let mut span = [Span { y: 0, lo, hi }];
                scan_span_list(&mut span, grid_step, |p| scanned.push(p[0]));
                let listed = run_points(lo, hi, grid_step);
                assert_eq!(listed, scanned, "[{lo:e}, {hi:e}] step {grid_step}");
            }
        }
    }
}
