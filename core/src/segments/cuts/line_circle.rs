//! A grown line crossing a circle (an end point's level circle, or one
//! concentric with an arc edge): the roots of a quadratic in the line's
//! parameter, kept when it touches too (`disc >= 0`).

use crate::geometry::V2;
use crate::segments::segment::LineFeature;

/// The parameters where the grown line `l` meets the circle `(c, rad)`.
#[inline]
pub(super) fn crossings(l: &LineFeature, c: V2, rad: f64, cuts: &mut Vec<f64>) {
    let w = l.origin - c;
    let bh = l.u.dot(&w);
    let disc = bh * bh - (w.norm_squared() - rad * rad);
    if disc >= 0.0 {
        let sq = disc.sqrt();
        cuts.extend([-bh - sq, -bh + sq]);
    }
}
