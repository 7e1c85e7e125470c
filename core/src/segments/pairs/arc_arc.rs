//! Distance bounds between two segments on arcs: the smallest distance is
//! exact, the largest is sampled along one arc and bounded above by its
//! Lipschitz slack (no closed form is needed for pruning).

use super::farthest::farthest_on_arc;
use crate::geometry::arc::{arc_arc_closest, CircArc};

/// Smallest and largest distance between a point of the arc piece `p` and
/// a point of the arc piece `q` (the largest an upper bound).
pub(super) fn distance_range(p: &CircArc, q: &CircArc) -> (f64, f64) {
    let dmin = arc_arc_closest(p, q).distance;
    // Samples `step` apart along p: every point of p is within
    // step / 2 of one, and the farthest distance is 1-Lipschitz.
    const SAMPLES: usize = 64;
    let step = p.length() / SAMPLES as f64;
    let dmax = (0..=SAMPLES)
        .map(|k| farthest_on_arc(q, p.point_at(k as f64 / SAMPLES as f64)))
        .fold(0.0, f64::max)
        + 0.5 * step;
    (dmin, dmax)
}
