//! Distance bounds between two segments on arcs: the smallest distance is
//! exact, the largest is sampled along one arc and bounded above by its
//! Lipschitz slack (no closed form is needed for pruning).

use super::farthest::FarArc;
use crate::geometry::arc::{arc_arc_closest, CircArc};
use crate::geometry::V2;

/// Samples `step` apart along an arc: every point of it is within
/// `step / 2` of one.
const SAMPLES: usize = 64;

/// The points of the arc piece `p` the largest distance from it is
/// sampled at, `SAMPLES + 1` of them from end to end: the same for every
/// other arc, so worked out once per arc.
pub(super) fn samples(p: &CircArc) -> Vec<V2> {
    (0..=SAMPLES)
        .map(|k| p.point_at(k as f64 / SAMPLES as f64))
        .collect()
}

/// Smallest and largest distance between a point of the arc piece `p`
/// (whose [`samples`] are `samples`) and a point of the arc piece `q` (the
/// largest an upper bound).
pub(super) fn distance_range(p: &CircArc, samples: &[V2], q: &CircArc) -> (f64, f64) {
    let dmin = arc_arc_closest(p, q).distance;
    // The farthest distance is 1-Lipschitz.
    let step = p.length() / SAMPLES as f64;
    let far = FarArc::new(q);
    let dmax = samples.iter().map(|&x| far.farthest(x)).fold(0.0, f64::max) + 0.5 * step;
    (dmin, dmax)
}
