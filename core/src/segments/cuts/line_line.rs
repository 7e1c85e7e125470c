//! A grown line crossing a line (SPEC 8.2's level lines of a straight
//! edge): one parameter, none when they are parallel.

use crate::geometry::{cross, V2};
use crate::segments::segment::LineFeature;

/// The parameter where the grown line `l` meets the line through `p`
/// along `d`, if they are not parallel.
#[inline]
pub(super) fn crossings(l: &LineFeature, p: V2, d: V2, cuts: &mut Vec<f64>) {
    let den = cross(l.u, d);
    if den != 0.0 {
        cuts.push(cross(p - l.origin, d) / den);
    }
}
