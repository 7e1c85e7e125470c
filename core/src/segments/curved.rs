//! The segments of an outline with arcs or holes (SPEC 8.2 and 9.3),
//! whatever its edges' kinds: each edge is grown ([`super::grow`]), the
//! pieces too close to the part are removed ([`super::pieces`], which
//! picks the feature's code once) and the rest are trimmed here.
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
//! change a piece's ends (`pieces/far.rs`), so pieces end where they always
//! did, bit for bit. A hole wall that its own hole leaves no room for (but
//! stretches shorter than the trims) is known to offer nothing without
//! the full cut ([`super::walls`]).

use super::grow::grown_feature;
use super::pieces::{removed_pieces, EdgeCut};
use super::polygon::complement;
use super::segment::{Feature, Segment};
use super::walls::{offers_nothing, Trim};
use crate::geometry::{Aabb, EPS, V2};
use crate::outline::Outline;

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
            let Some((feature, len)) = grown_feature(edge, r) else {
                continue;
            };
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
            let cut = EdgeCut {
                edge: i,
                len,
                outline,
                near: &near,
                access,
                rho,
                slack,
            };
            let mut removed = removed_pieces(&feature, &cut);
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
