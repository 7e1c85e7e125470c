//! Hole walls that offer no segment, recognised at the cost of their own
//! loop (SPEC 9.3: most bolt holes are smaller than a locator).
//!
//! The cut of [`super::curved`] tests every piece of a grown edge between
//! crossings with the level curves of every edge of the part, a cost that
//! grows with the square of the edge count when a part has many holes.
//! A grown hole wall whose every point lies well within `rho` of another
//! edge of its own hole has every such piece removed, whatever the other
//! edges add, so it offers nothing: proving that needs only the hole's own
//! edges. The proof is kept exact with a margin, so the answer is the full
//! cut's answer bit for bit, and where the margin is not met the full cut
//! decides.

use super::cuts::edge_cuts;
use super::segment::Feature;
use crate::geometry::Aabb;
use crate::outline::Edge;
use std::ops::Range;

/// Margin of the proof, relative to the coordinates' size: far above the
/// rounding of a distance (`1e-15` of it) and far below any hole's size.
const MARGIN_REL: f64 = 1e-7;

/// Whether every point of the grown edge `f` (parameters `0..=len`) of
/// edge `i` lies closer than `rho` to another edge of its loop (`own`,
/// indices into `edges`), with a margin rounding cannot eat. Then
/// every piece the full cut tests is closer than `rho` to the part, and
/// the edge offers no segment.
///
/// Why it is exact: with `rho1 = rho - margin`, the distance from the
/// grown edge to `own` crosses `rho1` only at the cuts computed here, so
/// between two cuts it stays on one side of `rho1`; a piece whose middle
/// lies closer than `rho1 - margin` is closer than `rho1` all along, up to
/// rounding near its ends. Every point is then closer than `rho - margin /
/// 2`, which the full cut's test, to the same edges among others, sees.
pub(super) fn covered_by_own_loop(
    f: &Feature,
    len: f64,
    i: usize,
    edges: &[Edge],
    own: Range<usize>,
    rho: f64,
) -> bool {
    let margin = MARGIN_REL * (1.0 + size_of(f, len));
    let rho1 = rho - margin;
    if rho1 - margin <= 0.0 {
        return false;
    }
    let others = || own.clone().filter(move |&j| j != i).map(|j| &edges[j]);
    let mut cuts = vec![0.0, len];
    for e in others() {
        edge_cuts(f, e, rho1, &mut cuts);
    }
    cuts.retain(|s| *s >= 0.0 && *s <= len);
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    cuts.windows(2).all(|w| {
        let p = f.point(0.5 * (w[0] + w[1]));
        others().any(|e| e.distance(p) < rho1 - margin)
    })
}

/// The largest coordinate of the grown edge's ends and middle, for the
/// margin's scale.
fn size_of(f: &Feature, len: f64) -> f64 {
    let b = Aabb::of(&[f.point(0.0), f.point(0.5 * len), f.point(len)]);
    [b.min.x, b.min.y, b.max.x, b.max.y]
        .iter()
        .fold(0.0f64, |m, x| m.max(x.abs()))
}
