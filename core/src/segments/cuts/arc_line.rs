//! A grown arc crossing a line (a level line of a straight edge): the two
//! points of the arc's circle on the line, as arc parameters (the caller
//! drops those off the arc).

use crate::geometry::arc::GrownArc;
use crate::geometry::V2;

/// The parameters where the circle of the grown arc `a` meets the line
/// through `p` along `d`.
#[inline]
pub(super) fn crossings(a: &GrownArc, p: V2, d: V2, cuts: &mut Vec<f64>) {
    let len2 = d.norm_squared();
    if len2 == 0.0 {
        return;
    }
    let t0 = (a.center - p).dot(&d) / len2;
    let foot = p + d * t0;
    let h2 = (foot - a.center).norm_squared();
    let w2 = a.radius * a.radius - h2;
    if w2 < 0.0 {
        return;
    }
    let w = (w2 / len2).sqrt();
    for t in [t0 - w, t0 + w] {
        cuts.push(a.param_of(p + d * t));
    }
}
