//! Distance bounds between two segments on lines, exact: the smallest
//! distance between the two pieces, the largest at a pair of end points
//! (the code of polygons, unchanged).

use crate::geometry::segment_segment_dist2;
use crate::segments::segment::Segment;

/// Smallest and largest distance between a point of `a` and a point of
/// `b`, both on lines.
pub(super) fn distance_range(a: &Segment, b: &Segment) -> (f64, f64) {
    let dmin = segment_segment_dist2(a.start(), a.end(), b.start(), b.end()).sqrt();
    let dmax = [
        (a.start() - b.start()).norm(),
        (a.start() - b.end()).norm(),
        (a.end() - b.start()).norm(),
        (a.end() - b.end()).norm(),
    ]
    .into_iter()
    .fold(0.0, f64::max);
    (dmin, dmax)
}
