//! The farthest point of an arc from a point, which the bounds of the
//! pairs with an arc take their largest distance from.

use crate::geometry::arc::CircArc;
use crate::geometry::V2;

/// Largest distance from `p` to a point of `arc`: an end, or the point
/// opposite `p` across the centre when the arc reaches it.
pub(super) fn farthest_on_arc(arc: &CircArc, p: V2) -> f64 {
    let ends = (p - arc.a).norm().max((p - arc.b).norm());
    let w = arc.center - p;
    let d = w.norm();
    if d > 0.0 && arc.contains_on_circle(arc.center + w * (arc.radius / d), 0.0) {
        ends.max(d + arc.radius)
    } else if d == 0.0 {
        ends.max(arc.radius)
    } else {
        ends
    }
}
