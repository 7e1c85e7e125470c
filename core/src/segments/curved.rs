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
//!
//! Only the edges whose boxes come near the grown edge can make a piece
//! too close; midpoints are tested against them alone, which gives the
//! same answers since the others are farther than `r - eps`. Their
//! crossings still cut a grown arc (those of the curves that run on past
//! them: the others fall off the arc), and cut a grown line where they can
//! change a piece's ends ([`super::far`]), so pieces end where they always
//! did, bit for bit. A hole wall that its own hole leaves no room for (but
//! stretches shorter than the trims) is known to offer nothing without
//! the full cut ([`super::walls`]).

use super::cuts::{edge_cuts, far_edge_cuts};
use super::far::{EdgeSpans, NearZones};
use super::line::complement;
use super::segment::{Feature, LineFeature, Segment};
use super::walls::{offers_nothing, Trim};
use crate::geometry::{boundary_distance2, point_in_polygon, Aabb, EPS, V2};
use crate::outline::{Edge, GrownEdge, Outline};

/// Slack of the box tests that choose the edges a midpoint is tested
/// against, relative to the coordinates' size: boxes and distances are
/// rounded by far less.
const NEAR_SLACK_REL: f64 = 1e-7;

/// The segments of a part region with arcs or holes, lattice units.
pub(super) fn outline_segments(
    outline: &Outline,
    access: &[Vec<V2>],
    r: f64,
    trim: f64,
) -> Vec<Segment> {
    let edges = outline.edges();
    let rho = r - EPS;
    let mut out = Vec::new();
    let mut near = Vec::new();
    for (k, own) in outline.loop_edges().enumerate() {
        for i in own.clone() {
            let edge = &edges[i];
            let Some(feature) = edge.grown(r, EPS).map(feature_of) else {
                continue;
            };
            let len = feature_length(&feature, edge);
            let smooth_start = outline.smooth_joint(i);
            let smooth_end = outline.smooth_joint(outline.next_in_loop(i));
            let trims = Trim {
                trim,
                smooth_start,
                smooth_end,
            };
            if k > 0 && offers_nothing(&feature, len, i, edges, own.clone(), rho, trims) {
                continue;
            }
            // The grown edge lies within r of the edge: an edge farther
            // than r + rho from the edge's box is farther than rho from it.
            let edge_box = edge.aabb();
            let slack = NEAR_SLACK_REL * (1.0 + size_of(&edge_box) + r);
            outline.edges_near(&edge_box, r + rho + slack, i, &mut near);
            let mut removed = removed_pieces(&feature, len, i, outline, &near, access, rho, slack);
            let pieces = complement(&mut removed, 0.0, len);
            push_pieces(&mut out, i, &feature, pieces, len, trims);
        }
    }
    out
}

/// The segments of edge `i` from the pieces its cut keeps: each trimmed
/// at both ends, except (SPEC 8.2) where it runs into a smooth joint.
fn push_pieces(
    out: &mut Vec<Segment>,
    i: usize,
    feature: &Feature,
    pieces: Vec<(f64, f64)>,
    len: f64,
    trims: Trim,
) {
    for (lo, hi) in pieces {
        let s0 = if lo == 0.0 && trims.smooth_start {
            lo
        } else {
            lo + trims.trim
        };
        let s1 = if hi == len && trims.smooth_end {
            hi
        } else {
            hi - trims.trim
        };
        if s1 - s0 > EPS {
            out.push(Segment {
                edge: i,
                s0,
                s1,
                feature: *feature,
            });
        }
    }
}

/// The largest coordinate of a box.
fn size_of(b: &Aabb) -> f64 {
    [b.min.x, b.min.y, b.max.x, b.max.y]
        .iter()
        .fold(0.0f64, |m, x| m.max(x.abs()))
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
/// `rho` to another edge or to a filled access region. Cut at the curves
/// of every edge (on a grown line, those of far edges only where they can
/// change the answer: [`super::far`]); `near` lists the edges a point of
/// the grown edge can be closer than `rho` to, `slack` the rounding
/// allowance of the box tests that chose them.
#[allow(clippy::too_many_arguments)] // the cut's inputs, each used
fn removed_pieces(
    f: &Feature,
    len: f64,
    i: usize,
    outline: &Outline,
    near: &[usize],
    access: &[Vec<V2>],
    rho: f64,
    slack: f64,
) -> Vec<(f64, f64)> {
    let edges = outline.edges();
    let mut cuts = vec![0.0, len];
    match f {
        Feature::Line(line) => {
            for &j in near {
                edge_cuts(f, &edges[j], rho, &mut cuts);
            }
            let mut far = Vec::with_capacity(2 * edges.len());
            let mut near_iter = near.iter().peekable();
            for (j, e) in edges.iter().enumerate() {
                if near_iter.next_if_eq(&&j).is_none() && j != i {
                    far_edge_cuts(f, e, rho, &mut far);
                }
            }
            let boxes = near
                .iter()
                .map(|&j| outline.edge_boxes()[j])
                .chain(access.iter().map(|poly| Aabb::of(poly)));
            NearZones::of(line, len, boxes, rho + slack, slack).add_far_cuts(&far, len, &mut cuts);
        }
        Feature::Arc(_) => {
            // A far edge's end-point circles cannot reach the grown arc:
            // their crossings with its circle lie off the arc and would be
            // dropped below, so only the curves that run on are computed.
            let mut near_iter = near.iter().peekable();
            for (j, e) in edges.iter().enumerate() {
                if near_iter.next_if_eq(&&j).is_some() {
                    edge_cuts(f, e, rho, &mut cuts);
                } else if j != i {
                    far_edge_cuts(f, e, rho, &mut cuts);
                }
            }
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
    let near_access = |p: V2| {
        access
            .iter()
            .any(|poly| point_in_polygon(p, poly) || boundary_distance2(p, poly).sqrt() < rho)
    };
    // The pieces come in order of `s`: on a line, each middle is tested
    // against the near edges whose boxes can reach it.
    let mut spans = match f {
        Feature::Line(line) => Some(EdgeSpans::of(
            line,
            near,
            outline.edge_boxes(),
            rho + slack,
            slack,
        )),
        Feature::Arc(_) => None,
    };
    let mut too_close = |s: f64| {
        let p = f.point(s);
        let near_edge = match spans.as_mut() {
            Some(spans) => spans.at(s).any(|j| edges[j].distance(p) < rho),
            None => near.iter().any(|&j| edges[j].distance(p) < rho),
        };
        near_edge || near_access(p)
    };
    cuts.windows(2)
        .filter(|w| w[1] > w[0] && too_close(0.5 * (w[0] + w[1])))
        .map(|w| (w[0], w[1]))
        .collect()
}
