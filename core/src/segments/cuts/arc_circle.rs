//! A grown arc crossing a circle (an end point's level circle, or one
//! concentric with an arc edge): the circles' intersection points, as arc
//! parameters (the caller drops those off the arc).

use crate::geometry::arc::{circle_circle, GrownArc};
use crate::geometry::V2;

/// The parameters where the circle of the grown arc `a` meets the circle
/// `(c, rad)`.
#[inline]
pub(super) fn crossings(a: &GrownArc, c: V2, rad: f64, cuts: &mut Vec<f64>) {
    for &p in circle_circle(a.center, a.radius, c, rad, 0.0).as_slice() {
        cuts.push(a.param_of(p));
    }
}
