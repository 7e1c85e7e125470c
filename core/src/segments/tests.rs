//! The fast cut of a part with holes ([`super::curved`]: hole walls
//! settled by their own hole, far crossings dropped, midpoints tested
//! against near edges) against the plain cut it replaces, which cuts every
//! grown edge at the curves of every edge and tests every piece against
//! every edge: the same segments, bit for bit.

use super::curved::outline_segments;
use super::cuts::edge_cuts;
use super::grow::grown_feature;
use super::polygon::complement;
use super::segment::Segment;
use crate::geometry::{boundary_distance2, point_in_polygon, v2, EPS, V2};
use crate::outline::{validate_holes, Edge, Outline, Vertex};
use proptest::prelude::*;

/// The plain cut: SPEC 8.2 and 9.3 as the arc path first did it.
fn plain_segments(outline: &Outline, access: &[Vec<V2>], r: f64, trim: f64) -> Vec<Segment> {
    let edges = outline.edges();
    let rho = r - EPS;
    let mut out = Vec::new();
    for (i, edge) in edges.iter().enumerate() {
        let Some((feature, len)) = grown_feature(edge, r) else {
            continue;
        };
        let mut cuts = vec![0.0, len];
        for (j, e) in edges.iter().enumerate() {
            if j != i {
                edge_cuts(&feature, e, rho, &mut cuts);
            }
        }
        for poly in access {
            for k in 0..poly.len() {
                let side = Edge::Line {
                    a: poly[k],
                    b: poly[(k + 1) % poly.len()],
                };
                edge_cuts(&feature, &side, rho, &mut cuts);
            }
        }
        cuts.retain(|s| *s >= 0.0 && *s <= len);
        cuts.sort_by(f64::total_cmp);
        cuts.dedup();
        let too_close = |p: V2| {
            edges
                .iter()
                .enumerate()
                .any(|(j, e)| j != i && e.distance(p) < rho)
                || access.iter().any(|poly| {
                    point_in_polygon(p, poly) || boundary_distance2(p, poly).sqrt() < rho
                })
        };
        let mut removed: Vec<(f64, f64)> = cuts
            .windows(2)
            .filter(|w| w[1] > w[0] && too_close(feature.point(0.5 * (w[0] + w[1]))))
            .map(|w| (w[0], w[1]))
            .collect();
        let smooth_start = outline.smooth_joint(i);
        let smooth_end = outline.smooth_joint(outline.next_in_loop(i));
        for (lo, hi) in complement(&mut removed, 0.0, len) {
            let s0 = if lo == 0.0 && smooth_start {
                lo
            } else {
                lo + trim
            };
            let s1 = if hi == len && smooth_end {
                hi
            } else {
                hi - trim
            };
            if s1 - s0 > EPS {
                out.push(Segment {
                    edge: i,
                    s0,
                    s1,
                    feature,
                });
            }
        }
    }
    out
}

/// Bitwise equality of two segment lists (`==` would take `-0.0` for
/// `0.0`).
fn same_bits(a: &[Segment], b: &[Segment]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            x.edge == y.edge
                && x.s0.to_bits() == y.s0.to_bits()
                && x.s1.to_bits() == y.s1.to_bits()
                && x.feature == y.feature
        })
}

/// A hole: a rectangle `w` by `h` at `(x, y)`, or a circle of radius
/// `w / 2` there (two half circles), either orientation.
fn hole(x: f64, y: f64, w: f64, h: f64, round: bool, ccw: bool) -> Vec<Vertex> {
    let mut l: Vec<Vertex> = if round {
        let b = if ccw { 1.0 } else { -1.0 };
        vec![Vertex::new(x, y, b), Vertex::new(x + w, y, b)]
    } else {
        [[x, y], [x + w, y], [x + w, y + h], [x, y + h]]
            .iter()
            .map(|&[px, py]| Vertex::new(px, py, 0.0))
            .collect()
    };
    if !ccw && !round {
        l.reverse();
    }
    l
}

/// An outline (a rectangle with a notch in its top edge, so that it has
/// a concave corner, its right side an arc of bulge `bulge`) and the holes
/// that validate against it.
fn part(width: f64, bulge: f64, holes: &[(f64, f64, f64, f64, bool, bool)]) -> Option<Outline> {
    let mut outline: Vec<Vertex> = [
        [0.0, 0.0],
        [width, 0.0],
        [width, 6.0],
        [0.6 * width, 6.0],
        [0.6 * width, 5.0],
        [0.4 * width, 5.0],
        [0.4 * width, 6.0],
        [0.0, 6.0],
    ]
    .iter()
    .map(|&[x, y]| Vertex::new(x, y, 0.0))
    .collect();
    outline[1].bulge = bulge;
    let loops: Vec<Vec<Vertex>> = holes
        .iter()
        .map(|&(x, y, w, h, round, ccw)| hole(x, y, w, h, round, ccw))
        .collect();
    let holes = validate_holes(&outline, &loops).ok()?;
    Some(Outline::new(&outline).ok()?.with_holes(holes))
}

#[test]
fn small_holes_offer_nothing_and_big_ones_do() {
    // A bolt hole narrower than a locator and a window it fits in.
    let holes = [
        (2.0, 2.0, 0.4, 0.4, true, false),
        (5.0, 1.0, 2.5, 2.5, false, true),
    ];
    let outline = part(10.0, 0.0, &holes).unwrap();
    let (r, trim) = (0.4, 0.05);
    let fast = outline_segments(&outline, &[], r, trim);
    assert!(same_bits(&fast, &plain_segments(&outline, &[], r, trim)));
    let on_loop = |k: usize| {
        fast.iter()
            .filter(|s| outline.loop_of_edge(s.edge) == k)
            .count()
    };
    assert!(
        on_loop(0) > 0 && on_loop(1) == 0 && on_loop(2) > 0,
        "{fast:?}"
    );
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Random holes, round and square, small and large, near the edges
    /// and far, with and without an access region, trim and an arc in the
    /// outline.
    #[test]
    fn fast_cut_equals_plain_cut(
        width in 8.0f64..14.0,
        holes in prop::collection::vec(
            (0.2f64..13.0, 0.2f64..5.5, 0.1f64..2.0, 0.1f64..2.0, any::<bool>(), any::<bool>()),
            0..12,
        ),
        r in 0.15f64..0.7,
        trim in prop_oneof![Just(0.0), 0.01f64..0.3],
        access in any::<bool>(),
        bulge in prop_oneof![Just(0.0), -0.2f64..0.4],
    ) {
        // Keep the holes that fit and do not meet; a bad set is skipped.
        let mut kept: Vec<(f64, f64, f64, f64, bool, bool)> = Vec::new();
        for h in holes {
            let mut with = kept.clone();
            with.push(h);
            if part(width, bulge, &with).is_some() {
                kept = with;
            }
        }
        let outline =
            part(width, bulge, &kept).unwrap_or_else(|| part(width, bulge, &[]).unwrap());
        let access: Vec<Vec<V2>> = if access {
            vec![vec![v2(1.0, -1.0), v2(3.0, -1.0), v2(3.0, 0.3), v2(1.0, 0.3)]]
        } else {
            Vec::new()
        };
        let fast = outline_segments(&outline, &access, r, trim);
        let plain = plain_segments(&outline, &access, r, trim);
        prop_assert!(same_bits(&fast, &plain), "{fast:?}\n{plain:?}");
    }
}
