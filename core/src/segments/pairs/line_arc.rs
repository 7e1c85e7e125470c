//! Distance bounds between a segment on a line and one on an arc, exact:
//! the farthest point of an arc is a convex function of the other point,
//! so over the line's piece it peaks at an end.

use super::farthest::farthest_on_arc;
use crate::geometry::arc::{segment_arc_closest, CircArc};
use crate::segments::segment::Segment;

/// Smallest and largest distance between a point of the segment `line`
/// (on a line) and a point of the arc piece `arc`.
pub(super) fn distance_range(line: &Segment, arc: &CircArc) -> (f64, f64) {
    let dmin = segment_arc_closest(line.start(), line.end(), arc).distance;
    let dmax = farthest_on_arc(arc, line.start()).max(farthest_on_arc(arc, line.end()));
    (dmin, dmax)
}
