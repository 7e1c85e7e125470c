//! Distance bounds between a segment on a line and one on an arc, exact:
//! the farthest point of an arc is a convex function of the other point,
//! so over the line's piece it peaks at an end.

use super::farthest::FarArc;
use crate::geometry::arc::{segment_arc_closest, CircArc};
use crate::geometry::V2;

/// Smallest and largest distance between a point of the piece `[start,
/// end]` of a line and a point of the arc piece `arc`.
pub(super) fn distance_range([start, end]: [V2; 2], arc: &CircArc) -> (f64, f64) {
    let dmin = segment_arc_closest(start, end, arc).distance;
    let far = FarArc::new(arc);
    let dmax = far.farthest(start).max(far.farthest(end));
    (dmin, dmax)
}
