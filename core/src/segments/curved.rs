//! The segments of an outline with arcs (SPEC 8.2).
//!
//! A point of a grown edge is removed when it lies closer than `r - eps`
//! to another part edge or to an access region. That set is bounded by the
//! level curves at distance `r - eps`: circles about end points and
//! vertices, lines parallel to straight edges, circles concentric with arcs.
//! So the grown edge is cut at every crossing with those curves, and each
//! piece between two cuts is kept or removed as a whole by testing its
//! midpoint with exact distances. No piece can be half in, half out: its
//! distance function crosses `r - eps` only at cuts.

use super::line::complement;
use super::segment::{Feature, LineFeature, Segment};
use crate::geometry::arc::{circle_circle, GrownArc};
use crate::geometry::{boundary_distance2, cross, point_in_polygon, v2, EPS, V2};
use crate::outline::{Edge, GrownEdge, Outline};

/// The segments of a part region with arcs or holes, lattice units.
pub(super) fn outline_segments(
    outline: &Outline,
    access: &[Vec<V2>],
    r: f64,
    trim: f64,
) -> Vec<Segment> {
    let edges = outline.edges();
    let mut out = Vec::new();
    for (i, edge) in edges.iter().enumerate() {
        let Some(feature) = edge.grown(r, EPS).map(feature_of) else {
            continue;
        };
        let len = feature_length(&feature, edge);
        let mut removed = removed_pieces(&feature, len, i, edges, access, r - EPS);
        let smooth_start = outline.smooth_joint(i);
        let smooth_end = outline.smooth_joint(outline.next_in_loop(i));
        for (lo, hi) in complement(&mut removed, 0.0, len) {
            // SPEC 8.2: no trim where the piece runs into a smooth joint.
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

/// The grown edge as a segment feature (the whole grown edge, `s` from 0).
fn feature_of(grown: GrownEdge) -> Feature {
    match grown {
        GrownEdge::Line { a, b, normal } => {
            let u = (b - a).normalize();
            Feature::Line(LineFeature::new(a, u, normal))
        }
        GrownEdge::Arc(arc) => Feature::Arc(arc),
    }
}

/// Length of the whole grown edge (the range of `s`): a grown line is the
/// edge moved along its normal, so it keeps the edge's length.
fn feature_length(f: &Feature, edge: &Edge) -> f64 {
    match f {
        Feature::Line(_) => edge.length(),
        Feature::Arc(a) => a.length(),
    }
}

/// The open parameter intervals of the grown edge `i` that lie closer than
/// `rho` to another edge or to a filled access region.
fn removed_pieces(
    f: &Feature,
    len: f64,
    i: usize,
    edges: &[Edge],
    access: &[Vec<V2>],
    rho: f64,
) -> Vec<(f64, f64)> {
    let mut cuts = vec![0.0, len];
    for (j, e) in edges.iter().enumerate() {
        if j != i {
            edge_cuts(f, e, rho, &mut cuts);
        }
    }
    for poly in access {
        for k in 0..poly.len() {
            let e = Edge::Line {
                a: poly[k],
                b: poly[(k + 1) % poly.len()],
            };
            edge_cuts(f, &e, rho, &mut cuts);
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
            || access
                .iter()
                .any(|poly| point_in_polygon(p, poly) || boundary_distance2(p, poly).sqrt() < rho)
    };
    cuts.windows(2)
        .filter(|w| w[1] > w[0] && too_close(f.point(0.5 * (w[0] + w[1]))))
        .map(|w| (w[0], w[1]))
        .collect()
}

/// Parameters where the grown edge `f` crosses the curves at distance
/// `rho` from edge `edge`.
fn edge_cuts(f: &Feature, edge: &Edge, rho: f64, cuts: &mut Vec<f64>) {
    match edge {
        Edge::Line { a, b } => {
            let d = b - a;
            let len = d.norm();
            if len > 0.0 {
                let m = v2(-d.y, d.x) / len;
                line_cuts(f, a + m * rho, d, cuts);
                line_cuts(f, a - m * rho, d, cuts);
            }
            circle_cuts(f, *a, rho, cuts);
            circle_cuts(f, *b, rho, cuts);
        }
        Edge::Arc(arc) => {
            circle_cuts(f, arc.a, rho, cuts);
            circle_cuts(f, arc.b, rho, cuts);
            circle_cuts(f, arc.center, arc.radius + rho, cuts);
            if arc.radius - rho > 0.0 {
                circle_cuts(f, arc.center, arc.radius - rho, cuts);
            }
        }
    }
}

/// Parameters where `f` meets the circle `(c, rad)`.
fn circle_cuts(f: &Feature, c: V2, rad: f64, cuts: &mut Vec<f64>) {
    match f {
        Feature::Line(l) => {
            let w = l.origin - c;
            let bh = l.u.dot(&w);
            let disc = bh * bh - (w.norm_squared() - rad * rad);
            if disc >= 0.0 {
                let sq = disc.sqrt();
                cuts.extend([-bh - sq, -bh + sq]);
            }
        }
        Feature::Arc(a) => {
            for &p in circle_circle(a.center, a.radius, c, rad, 0.0).as_slice() {
                cuts.push(a.param_of(p));
            }
        }
    }
}

/// Parameters where `f` meets the line through `p` along `d`.
fn line_cuts(f: &Feature, p: V2, d: V2, cuts: &mut Vec<f64>) {
    match f {
        Feature::Line(l) => {
            let den = cross(l.u, d);
            if den != 0.0 {
                cuts.push(cross(p - l.origin, d) / den);
            }
        }
        Feature::Arc(a) => line_circle_cuts(a, p, d, cuts),
    }
}

fn line_circle_cuts(a: &GrownArc, p: V2, d: V2, cuts: &mut Vec<f64>) {
    let len2 = d.norm_squared();
    if len2 == 0.0 {
        return;
    }
    let t0 = (a.center - p).dot(&d) / len2;
    let foot = p + d * t0;
    let h2 = (foot - a.center).norm_squared();
    let w2 = a.radius * a.radius - h2;
    if w2 < 0.0 {
        return;
    }
    let w = (w2 / len2).sqrt();
    for t in [t0 - w, t0 + w] {
        cuts.push(a.param_of(p + d * t));
    }
}
