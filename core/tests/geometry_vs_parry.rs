//! Our clearance primitives against parry2d on convex shapes, where parry's
//! distance is exact: the hand-written versions exist for eps semantics and
//! speed, not to disagree.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use fixplan_core::parts::{polygon_clearance, polygon_disk_clearance, v2, V2};
use parry2d_f64::math::{Pose, Vector};
use parry2d_f64::query;
use parry2d_f64::shape::{Ball, ConvexPolygon};
use proptest::prelude::*;

fn hull(points: &[(f64, f64)]) -> Option<(ConvexPolygon, Vec<V2>)> {
    let pts: Vec<Vector> = points.iter().map(|&(x, y)| Vector::new(x, y)).collect();
    let poly = ConvexPolygon::from_convex_hull(&pts)?;
    let ours: Vec<V2> = poly.points().iter().map(|p| v2(p.x, p.y)).collect();
    // parry returns the hull counter-clockwise, as our polygons are.
    (ours.len() >= 3 && fixplan_core::parts::signed_area(&ours) > 1e-6).then_some((poly, ours))
}

fn points() -> impl Strategy<Value = Vec<(f64, f64)>> {
    prop::collection::vec((-3.0f64..3.0, -3.0f64..3.0), 3..9)
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 300,
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x9a77_7e00),
        ..ProptestConfig::default()
    })]

    #[test]
    fn polygon_distance_matches_parry(a in points(), b in points(), dx in -6.0f64..6.0, dy in -6.0f64..6.0) {
        let Some((pa, qa)) = hull(&a) else { return Ok(()) };
        let moved: Vec<(f64, f64)> = b.iter().map(|&(x, y)| (x + dx, y + dy)).collect();
        let Some((pb, qb)) = hull(&moved) else { return Ok(()) };
        let theirs = query::distance(&Pose::identity(), &pa, &Pose::identity(), &pb)
            .expect("convex-convex is supported");
        match polygon_clearance(&qa, &qb) {
            None => prop_assert!(theirs.distance <= 1e-9, "we say overlap, parry says {}", theirs.distance),
            Some(d) => {
                prop_assert!((d - theirs.distance).abs() < 1e-9, "{} vs {}", d, theirs.distance);
                if d > 1e-9 {
                    let hit = query::intersection_test(&Pose::identity(), &pa, &Pose::identity(), &pb)
                        .expect("supported");
                    prop_assert!(!hit.intersecting);
                }
            }
        }
    }

    #[test]
    fn disk_distance_matches_parry(a in points(), cx in -6.0f64..6.0, cy in -6.0f64..6.0, r in 0.05f64..1.0) {
        let Some((pa, qa)) = hull(&a) else { return Ok(()) };
        let ball = Ball::new(r);
        let theirs = query::distance(&Pose::identity(), &pa, &Pose::translation(cx, cy), &ball)
            .expect("supported")
            .distance;
        match polygon_disk_clearance(&qa, v2(cx, cy), r) {
            None => prop_assert!(theirs <= 1e-9),
            Some(d) => prop_assert!((d - theirs).abs() < 1e-9, "{} vs {}", d, theirs),
        }
    }
}
