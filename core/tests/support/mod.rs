//! Shared test support: kits, shapes, random polygons and the brute-force
//! enumerator that the pruned enumeration must equal.
#![allow(dead_code)]

use fixplan_core::parts::{
    combinations_in, positively_spanning, v2, wrench, Accumulator, Feature, Pose, Scratch, V2,
};
use fixplan_core::{
    prepare, Clamp, Fixture, HoleKind, Kit, MountHole, Params, Part, PartialResult, Pattern,
    PreparedPart, Units,
};
use nalgebra::Vector3;

/// The paper-like kit in lattice units (spacing 1): 0.25 locators, toggle clamp.
pub fn kit(pattern: Pattern) -> Kit {
    let s = 1.0 / 0.75;
    let sc = |p: &[[f64; 2]]| p.iter().map(|q| [q[0] * s, q[1] * s]).collect::<Vec<_>>();
    Kit {
        spacing: 1.0,
        cols: 18,
        rows: 18,
        pattern,
        locator_radius: 0.25 * s,
        clamp: Clamp {
            mount_holes: vec![
                MountHole {
                    offset: [0, 0],
                    kind: HoleKind::Dowel,
                },
                MountHole {
                    offset: [1, 0],
                    kind: HoleKind::Tapped,
                },
            ],
            axis_offset: 0.0,
            travel: [1.5 * s, 2.75 * s],
            body: sc(&[[-0.4, -0.4], [1.2, -0.4], [1.2, 0.4], [-0.4, 0.4]]),
            plunger: sc(&[[-2.5, -0.12], [-0.25, -0.12], [-0.25, 0.12], [-2.5, 0.12]]),
        },
    }
}

pub fn params(max_angle: f64, grid_step: u32) -> Params {
    Params {
        max_clamp_angle_deg: max_angle,
        edge_trim: Some(0.05),
        min_clearance: Some(0.05),
        grid_step,
        top_k: 0,
        full_counts: false,
        wrenches: None,
    }
}

/// Random star-shaped polygons of 5 to 10 vertices around the origin,
/// lattice units for [`kit`].
pub fn shape_strategy() -> impl proptest::strategy::Strategy<Value = Vec<[f64; 2]>> {
    use proptest::prelude::*;
    (5usize..=10)
        .prop_flat_map(|n| {
            (
                prop::collection::vec(0.0..std::f64::consts::TAU, n),
                prop::collection::vec(1.2f64..3.2, n),
            )
        })
        .prop_map(|(a, r)| star([0.0, 0.0], &a, &r))
        .prop_filter("a valid polygon of at least 4 vertices", |p| {
            p.len() >= 4 && fixplan_core::parts::validate_polygon(p).is_ok()
        })
}

pub fn part(outline: &[[f64; 2]], access: &[Vec<[f64; 2]>]) -> Part {
    Part {
        outline: outline.iter().map(|&p| p.into()).collect(),
        holes: Vec::new(),
        access: access.to_vec(),
    }
}

pub fn prep(p: &Part, k: &Kit, pr: &Params) -> PreparedPart {
    prepare(p, k, pr, Units::Mm).expect("valid test input")
}

/// Star-shaped polygon around `centre`: always simple.
pub fn star(centre: [f64; 2], angles: &[f64], radii: &[f64]) -> Vec<[f64; 2]> {
    let mut a: Vec<(f64, f64)> = angles.iter().copied().zip(radii.iter().copied()).collect();
    a.sort_by(|x, y| x.0.total_cmp(&y.0));
    a.dedup_by(|x, y| (x.0 - y.0).abs() < 0.05);
    a.iter()
        .map(|&(t, r)| [centre[0] + r * t.cos(), centre[1] + r * t.sin()])
        .collect()
}

pub fn l_shape() -> Vec<[f64; 2]> {
    vec![
        [0., 0.],
        [4.3, 0.],
        [4.3, 1.7],
        [1.6, 1.7],
        [1.6, 4.1],
        [0., 4.1],
    ]
}

pub fn t_shape() -> Vec<[f64; 2]> {
    vec![
        [1.9, 0.],
        [3.3, 0.],
        [3.3, 3.],
        [5.2, 3.],
        [5.2, 4.4],
        [0., 4.4],
        [0., 3.],
        [1.9, 3.],
    ]
}

pub fn notched() -> Vec<[f64; 2]> {
    vec![
        [0., 0.],
        [2.1, 0.],
        [2.1, 0.9],
        [2.9, 0.9],
        [2.9, 0.],
        [5.0, 0.],
        [5.0, 3.2],
        [3.4, 3.6],
        [0., 3.2],
    ]
}

/// No pruning: every canonical `L2` and every `L3` within the grown part's
/// diameter, for every combination.
pub fn brute_force(p: &PreparedPart) -> PartialResult {
    // The part lies in its box (arcs included) and every segment within
    // the locator radius of the part.
    let b = p.outline().aabb();
    let pts = [b.min, b.max, v2(b.min.x, b.max.y), v2(b.max.x, b.min.y)];
    let mut diam: f64 = 0.0;
    for a in &pts {
        for b in &pts {
            diam = diam.max((a - b).norm());
        }
    }
    let diam = diam + 2.0 * p.locator_radius() + 1.0;
    let d = diam.ceil() as i64;
    let mut acc = Accumulator::new(0);
    let mut scratch = Scratch::default();
    let n = p.segments().len();
    for (_, combo) in combinations_in(n, 0..u64::MAX) {
        acc.counts.combinations += 1;
        for i in 1..=d {
            for j in 0..=d {
                let l2 = [i, j];
                if ((i * i + j * j) as f64) > diam * diam || !p.locator_point_allowed(l2) {
                    continue;
                }
                for x in -d..=d {
                    for y in -d..=d {
                        let l3 = [x, y];
                        if ((x * x + y * y) as f64) > diam * diam || !p.locator_point_allowed(l3) {
                            continue;
                        }
                        p.setups_for_locators(combo, l2, l3, |s| {
                            p.process_setup(s, &mut acc, &mut scratch)
                        });
                    }
                }
            }
        }
    }
    acc.counts.segments = n as u64;
    let count = p.combination_count();
    PartialResult {
        range: 0..count,
        counts: acc.counts,
        fixtures: acc.top.into_sorted(),
    }
}

/// A fixture's pose (cosine and sine recomputed from `theta`), its four
/// contact centres (plate frame: locators 1-3, then the clamp tip) and the
/// segments they touch.
pub fn fixture_contacts(f: &Fixture) -> (Pose, [V2; 4], [usize; 4]) {
    let pose = Pose {
        theta: f.theta,
        cos: f.theta.cos(),
        sin: f.theta.sin(),
        t: v2(f.t[0], f.t[1]),
    };
    let l = |i: usize| v2(f.locators[i][0] as f64, f.locators[i][1] as f64);
    let points = [l(0), l(1), l(2), v2(f.contact[0], f.contact[1])];
    let segs = [f.segments[0], f.segments[1], f.segments[2], f.clamp_segment];
    (pose, points, segs)
}

/// Recomputes a fixture's contacts from its pose and the part's segments,
/// and checks form closure without `W^-1`: the origin strictly inside the
/// hull of the four wrenches.
pub fn check_fixture_independently(p: &PreparedPart, f: &Fixture) {
    let (pose, points, segs) = fixture_contacts(f);
    let mut w = [Vector3::zeros(); 4];
    let mut normals = [V2::zeros(); 4];
    for i in 0..4 {
        let seg = &p.segments()[segs[i]];
        let local = pose.inverse_apply(points[i]);
        // On the grown edge line or circle, strictly inside the segment.
        let (off, s, inward) = match seg.feature {
            Feature::Line(l) => (l.n.dot(&local) - l.c, l.u.dot(&(local - l.origin)), -l.n),
            Feature::Arc(a) => {
                let r = local - a.center;
                let angle = (r.y.atan2(r.x) - a.start_angle) * a.sweep.signum();
                let s = angle.rem_euclid(std::f64::consts::TAU) * a.radius;
                let out = r / a.radius;
                (
                    r.norm() - a.radius,
                    s,
                    if a.sweep > 0.0 { -out } else { out },
                )
            }
        };
        assert!(off.abs() < 1e-7, "contact {i} off its line or arc");
        assert!(s > seg.s0 && s < seg.s1, "contact {i} outside its segment");
        normals[i] = pose.rotate(inward);
        w[i] = wrench(points[i], normals[i]);
    }
    assert!(positively_spanning(&w, 1e-12), "not in form closure: {f:?}");
    // The clamp tip pushes within the allowed angle.
    let d = fixplan_core::parts::rot90(f.rotation, v2(1.0, 0.0));
    assert!(d.dot(&normals[3]) >= p.cos_max_angle() - 1e-9);
    // Locators are distinct lattice points, L1 at the origin, L2 in Q.
    assert_eq!(f.locators[0], [0, 0]);
    assert!(f.locators[1][0] > 0 && f.locators[1][1] >= 0);
}

/// A part from `[x, y, bulge]` vertices (SPEC 8.1).
pub fn arc_part(outline: &[[f64; 3]], access: &[Vec<[f64; 2]>]) -> Part {
    Part {
        outline: outline.iter().map(|&v| v.into()).collect(),
        holes: Vec::new(),
        access: access.to_vec(),
    }
}

/// `tan(sweep / 4)`: the bulge of an arc of `sweep` radians.
pub fn bulge(sweep_deg: f64) -> f64 {
    (sweep_deg.to_radians() / 4.0).tan()
}

/// Hand-made outlines with arcs, lattice units for [`kit`] (locator radius
/// 1/3): what plants draw, each exercising one rule of SPEC 8.
pub fn arc_shapes() -> Vec<(&'static str, Vec<[f64; 3]>)> {
    let q = bulge(90.0);
    vec![
        // Convex fillets at every corner: smooth joints, untrimmed.
        (
            "fillet",
            vec![
                [0.8, 0., 0.],
                [3.8, 0., q],
                [4.6, 0.8, 0.],
                [4.6, 2.4, q],
                [3.8, 3.2, 0.],
                [0.8, 3.2, q],
                [0., 2.4, 0.],
                [0., 0.8, q],
            ],
        ),
        // A round-ended slot cut from the top: a concave half circle
        // (R = 0.6 > r) between tangent walls.
        (
            "slot",
            vec![
                [0., 0., 0.],
                [5., 0., 0.],
                [5., 3.4, 0.],
                [3.1, 3.4, 0.],
                [3.1, 1.6, -1.],
                [1.9, 1.6, 0.],
                [1.9, 3.4, 0.],
                [0., 3.4, 0.],
            ],
        ),
        // A convex half-round boss on the top edge, meeting it at corners.
        (
            "boss",
            vec![
                [0., 0., 0.],
                [5., 0., 0.],
                [5., 2.5, 0.],
                [3.5, 2.5, 1.],
                [1.5, 2.5, 0.],
                [0., 2.5, 0.],
            ],
        ),
        // A round flange with a flat: a D, one arc of 253.7 degrees.
        ("D", vec![[-1.6, -1.2, 0.], [1.6, -1.2, 2.0]]),
        // A concave half-circle notch in the bottom edge.
        (
            "notch",
            vec![
                [0., 0., 0.],
                [2., 0., -1.],
                [3.2, 0., 0.],
                [5., 0., 0.],
                [5., 3., 0.],
                [0., 3., 0.],
            ],
        ),
        // An L with a concave inner fillet (R = 0.8) and a convex outer
        // one, and a second inner corner rounded below the locator radius
        // (R = 0.2 < r: no contact there).
        (
            "L-fillets",
            vec![
                [0., 0., 0.],
                [4.3, 0., 0.],
                [4.3, 1.7, 0.],
                [2.4, 1.7, -q],
                [1.6, 2.5, 0.],
                [1.6, 3.3, q],
                [0.8, 4.1, 0.],
                [0.2, 4.1, -q],
                [0., 4.3, 0.],
            ],
        ),
    ]
}

/// The pruned enumeration of `p` against [`brute_force`]: same counts,
/// same fixtures, each passing [`check_fixture_independently`].
pub fn pruned_equals_brute_force(p: &PreparedPart, what: &str) -> PartialResult {
    let pruned = p.enumerate_all();
    let brute = brute_force(p);
    assert_eq!(pruned.counts, brute.counts, "{what}: counts differ");
    assert_eq!(pruned.fixtures, brute.fixtures, "{what}: fixtures differ");
    for f in &pruned.fixtures {
        check_fixture_independently(p, f);
    }
    pruned
}

/// The canonical key of a fixture without its frame-dependent numbers.
pub fn frame_free_key(f: &Fixture) -> (Vec<usize>, Vec<[i64; 2]>, usize, u8, [i64; 2]) {
    (
        f.segments.to_vec(),
        f.locators.to_vec(),
        f.clamp_segment,
        f.rotation,
        f.mount,
    )
}
