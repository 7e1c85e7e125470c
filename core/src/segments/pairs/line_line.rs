//! Distance bounds between two segments on lines, exact: the smallest
//! distance between the two pieces, the largest at a pair of end points
//! (the code of polygons, unchanged).

use crate::geometry::{segment_segment_dist2, V2};

/// Smallest and largest distance between a point of the piece `[start,
/// end]` of `a` and a point of that of `b`, both on lines.
pub(super) fn distance_range([a0, a1]: [V2; 2], [b0, b1]: [V2; 2]) -> (f64, f64) {
    let dmin = segment_segment_dist2(a0, a1, b0, b1).sqrt();
    let dmax = [
        (a0 - b0).norm(),
        (a0 - b1).norm(),
        (a1 - b0).norm(),
        (a1 - b1).norm(),
    ]
    .into_iter()
    .fold(0.0, f64::max);
    (dmin, dmax)
}
