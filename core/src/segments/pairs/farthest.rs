//! The farthest point of an arc from a point, which the bounds of the
//! pairs with an arc take their largest distance from.

use crate::geometry::arc::CircArc;
use crate::geometry::{cross, V2};

/// Within this of the cosine of the arc's half sweep, whether a point of
/// the circle lies on the arc is left to [`CircArc::contains_on_circle`]:
/// far above the rounding of a cosine worked out from a dot product (a few
/// 1e-16), so that outside it the cosine decides as the angle would.
const UNSURE_COS: f64 = 1e-9;

/// An arc piece with what the farthest-point test reads of it worked out
/// once: the bounds ask it of 65 sampled points of each other arc.
pub(super) struct FarArc<'a> {
    arc: &'a CircArc,
    /// [`CircArc::axis`].
    axis: V2,
    /// Cosine of half the sweep: the arc is the points of its circle whose
    /// angle from the axis has at least this cosine.
    cos_half: f64,
}

impl<'a> FarArc<'a> {
    pub(super) fn new(arc: &'a CircArc) -> FarArc<'a> {
        FarArc {
            arc,
            axis: arc.axis(),
            cos_half: (0.5 * arc.sweep.abs()).cos(),
        }
    }

    /// Largest distance from `p` to a point of the arc: an end, or the
    /// point opposite `p` across the centre when the arc reaches it.
    pub(super) fn farthest(&self, p: V2) -> f64 {
        let arc = self.arc;
        let ends = (p - arc.a).norm().max((p - arc.b).norm());
        let w = arc.center - p;
        let d = w.norm();
        if d > 0.0 && self.contains_on_circle(arc.center + w * (arc.radius / d)) {
            ends.max(d + arc.radius)
        } else if d == 0.0 {
            ends.max(arc.radius)
        } else {
            ends
        }
    }

    /// [`CircArc::contains_on_circle`] of `q` with no tolerance, without
    /// its arctangent where the cosine of the angle it compares decides:
    /// angles in `[0, pi]` order as their cosines do in reverse, and a
    /// cosine more than [`UNSURE_COS`] from that of the half sweep is an
    /// angle more than that from it (cosines change no faster than
    /// angles), far beyond the rounding of either. NaN is never sure.
    fn contains_on_circle(&self, q: V2) -> bool {
        let w = q - self.arc.center;
        let (sin, cos) = (cross(self.axis, w), self.axis.dot(&w));
        let cos = cos / (sin * sin + cos * cos).sqrt();
        if cos > self.cos_half + UNSURE_COS {
            true
        } else if cos < self.cos_half - UNSURE_COS {
            false
        } else {
            self.arc.contains_on_circle(q, 0.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v2;
    use proptest::prelude::*;
    use std::f64::consts::TAU;

    /// The farthest distance as it was computed before [`FarArc`]: the
    /// arctangent always.
    fn farthest_by_angle(arc: &CircArc, p: V2) -> f64 {
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

    /// The arc of radius `radius` about `center` from angle `start` over
    /// `sweep`.
    fn arc(center: V2, radius: f64, start: f64, sweep: f64) -> CircArc {
        let at = |t: f64| center + v2(t.cos(), t.sin()) * radius;
        CircArc {
            a: at(start),
            b: at(start + sweep),
            center,
            radius,
            bulge: (sweep / 4.0).tan(),
            sweep,
        }
    }

    proptest! {
        /// The cosine's shortcut decides as the arctangent does, to the
        /// bit of the distance, for points anywhere and points whose
        /// opposite point is (nearly) an end of the arc, where the two
        /// tests are closest to disagreeing.
        #[test]
        fn cosine_shortcut_is_the_arctangent(
            cx in -50.0f64..50.0,
            cy in -50.0f64..50.0,
            radius in 0.01f64..80.0,
            start in -7.0f64..7.0,
            turns in 1e-4f64..0.999,
            clockwise in proptest::bool::ANY,
            px in -200.0f64..200.0,
            py in -200.0f64..200.0,
            end_side in 0usize..3,
            nudge in -1e-8f64..1e-8,
            dist in 0.0f64..100.0,
        ) {
            let sweep = if clockwise { -turns } else { turns } * TAU;
            let piece = arc(v2(cx, cy), radius, start, sweep);
            let far = FarArc::new(&piece);
            // A point opposite an end (nudged along the circle) at `dist`
            // from the centre, or a free point.
            let p = match end_side {
                0 => v2(px, py),
                k => {
                    let t = start + if k == 1 { 0.0 } else { sweep } + nudge;
                    piece.center - v2(t.cos(), t.sin()) * dist
                }
            };
            prop_assert_eq!(
                far.farthest(p).to_bits(),
                farthest_by_angle(&piece, p).to_bits()
            );
        }
    }

    /// Exactly at the centre and exactly opposite an end: the boundary
    /// cases go to the arctangent, with the same answer.
    #[test]
    fn boundary_points_keep_their_distance() {
        let piece = arc(v2(3.0, -2.0), 5.0, 0.3, 2.0);
        let far = FarArc::new(&piece);
        for p in [
            piece.center,
            piece.center * 2.0 - piece.a,
            piece.center * 2.0 - piece.b,
            piece.a,
            piece.b,
        ] {
            assert_eq!(
                far.farthest(p).to_bits(),
                farthest_by_angle(&piece, p).to_bits()
            );
        }
    }
}
