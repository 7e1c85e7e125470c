//! A usable segment and what it lies on: a grown line or a grown arc, with
//! its contact parameter and inward normals (SPEC 2, 8.2, 8.3).
//!
//! The accessors of one segment (point, parameter, normal, kind, arc
//! piece) are one-line matches on its [`Feature`] and stay here, beside
//! the enum: a new feature kind adds its arm to each. What differs by more
//! than a line (growing, cutting, distance bounds) is chosen once per
//! operation in its own module (see the stage's module doc).

use crate::geometry::arc::{CircArc, GrownArc};
use crate::geometry::{EPS, V2};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// A grown edge line: where a segment of a straight part edge lies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineFeature {
    /// Start of the grown edge (`v_i + r n`): the origin of `s`.
    pub origin: V2,
    /// Unit direction of the edge (CCW).
    pub u: V2,
    /// Outward unit normal.
    pub n: V2,
    /// Right-hand side of the grown edge line `n . p = c`.
    pub c: f64,
}

impl LineFeature {
    /// The grown line through `origin` along `u` with outward normal `n`;
    /// `c` is derived, so it always agrees with `origin`.
    pub fn new(origin: V2, u: V2, n: V2) -> LineFeature {
        LineFeature {
            origin,
            u,
            n,
            c: n.dot(&origin),
        }
    }
}

/// What a segment lies on, in the part frame (lattice units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Feature {
    /// A grown straight edge; `s` runs along `u` from `origin`.
    Line(LineFeature),
    /// A grown arc (SPEC 8.2); `s` is the arc length from its start.
    Arc(GrownArc),
}

impl Feature {
    /// The point at parameter `s` of the whole grown line or arc.
    #[inline]
    pub fn point(&self, s: f64) -> V2 {
        match self {
            Feature::Line(l) => l.origin + l.u * s,
            Feature::Arc(a) => a.point_at(s),
        }
    }
}

/// The kind of a segment, as results list it (SPEC 8.6).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum SegmentKind {
    /// On a straight part edge.
    Line,
    /// On a circular arc of the part.
    Arc,
}

/// One usable segment in the part frame (lattice units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// Index of the part edge it comes from.
    pub edge: usize,
    /// Contact parameters of the segment's ends; contacts lie strictly inside.
    pub s0: f64,
    /// See `s0`.
    pub s1: f64,
    /// The grown line or arc the segment is a piece of.
    pub feature: Feature,
}

impl Segment {
    /// Line or arc.
    pub fn kind(&self) -> SegmentKind {
        match self.feature {
            Feature::Line(_) => SegmentKind::Line,
            Feature::Arc(_) => SegmentKind::Arc,
        }
    }

    /// The contact centre at parameter `s` (on the grown line or arc).
    #[inline]
    pub fn point(&self, s: f64) -> V2 {
        self.feature.point(s)
    }

    /// The contact parameter of a point on the grown line or arc (its
    /// projection, for a point slightly off it).
    #[inline]
    pub fn param_of(&self, p: V2) -> f64 {
        match &self.feature {
            Feature::Line(l) => l.u.dot(&(p - l.origin)),
            Feature::Arc(a) => a.param_of(p),
        }
    }

    /// The inward unit normal (into the part) of a contact centred at `p`,
    /// part frame: `-n` on a line; on an arc SPEC 8.3's `(C - p) / rho_e`
    /// (convex) or `(p - C) / rho_e` (concave), through the centre.
    #[inline]
    pub fn inward_normal(&self, p: V2) -> V2 {
        match &self.feature {
            Feature::Line(l) => -l.n,
            Feature::Arc(a) => arc_inward_normal(a.center, a.radius, a.is_convex(), p),
        }
    }

    /// Whether `s` lies strictly inside (by more than eps), and by how much.
    #[inline]
    pub fn inner_margin(&self, s: f64) -> f64 {
        (s - self.s0).min(self.s1 - s) - EPS
    }

    /// A lower bound on the distance from the part-frame point `p` to every
    /// point whose contact parameter lies strictly inside (an
    /// [`Self::inner_margin`] above 0), 0 when `p` may be one: how far a
    /// contact at `p` is from being kept, which lets the pose solver drop a
    /// start that cannot get there. On a line the kept points form a slab
    /// across it, `-inner_margin` away. On an arc the parameter depends
    /// only on the direction from the centre, so they form a wedge from
    /// it, at least `d sin(alpha)` away, `d` the distance from the centre
    /// and `alpha` (at most a quarter turn) the angle from the wedge's
    /// directions the shorter way round: the parameter lies in a window of
    /// one circumference that holds `[s0, s1]`, so the other way round is
    /// the rest of the circumference.
    pub fn distance_outside(&self, p: V2) -> f64 {
        let s = self.param_of(p);
        let outside = -self.inner_margin(s);
        if outside.is_nan() || outside <= 0.0 {
            return 0.0;
        }
        match &self.feature {
            Feature::Line(_) => outside,
            Feature::Arc(a) => {
                let (lo, hi) = (self.s0 + EPS, self.s1 - EPS);
                let period = std::f64::consts::TAU * a.radius;
                let around = if s < lo {
                    s + period - hi
                } else {
                    lo + period - s
                };
                let alpha = (outside.min(around) / a.radius).min(std::f64::consts::FRAC_PI_2);
                (p - a.center).norm() * alpha.sin()
            }
        }
    }

    /// First end (parameter `s0`); with [`Self::end`] it bounds the
    /// distances that prune locator positions.
    pub fn start(&self) -> V2 {
        self.point(self.s0)
    }

    /// Last end (parameter `s1`).
    pub fn end(&self) -> V2 {
        self.point(self.s1)
    }

    /// The piece of arc the segment covers, `None` on a line.
    pub fn arc_piece(&self) -> Option<CircArc> {
        let Feature::Arc(a) = &self.feature else {
            return None;
        };
        Some(self.piece_of_arc(a))
    }

    /// The piece of the grown arc `a` (the segment's feature) the segment
    /// covers, for the code that has matched the feature already.
    pub(crate) fn piece_of_arc(&self, a: &GrownArc) -> CircArc {
        let sweep = a.sweep.signum() * (self.s1 - self.s0) / a.radius;
        CircArc {
            a: self.start(),
            b: self.end(),
            center: a.center,
            radius: a.radius,
            bulge: (sweep / 4.0).tan(),
            sweep,
        }
    }
}

/// SPEC 8.3's inward normal of a contact centred at `q` on a grown circle
/// of centre `center` and radius `rho` (any frame).
#[inline]
pub fn arc_inward_normal(center: V2, rho: f64, convex: bool, q: V2) -> V2 {
    if convex {
        (center - q) / rho
    } else {
        (q - center) / rho
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v2;
    use crate::test_rng::Xorshift;

    fn random_segment(rng: &mut Xorshift) -> Segment {
        let mut r = |k: f64| k * rng.signed_unit();
        let feature = if r(1.0) > 0.0 {
            let a = 4.0 * r(1.0);
            let u = v2(a.cos(), a.sin());
            Feature::Line(LineFeature::new(v2(r(5.0), r(5.0)), u, v2(u.y, -u.x)))
        } else {
            Feature::Arc(GrownArc {
                center: v2(r(5.0), r(5.0)),
                radius: 0.1 + r(3.0).abs(),
                start_angle: 4.0 * r(1.0),
                sweep: 6.0 * r(1.0),
            })
        };
        let length = match &feature {
            Feature::Line(_) => 5.0,
            Feature::Arc(a) => a.length(),
        };
        let (x, y) = (r(1.0).abs() * length, r(1.0).abs() * length);
        Segment {
            edge: 0,
            s0: x.min(y),
            s1: x.max(y),
            feature,
        }
    }

    /// No point a contact is kept at (inner margin above 0) lies closer to
    /// a point than `distance_outside` says: random segments, points and
    /// points near them (most within twice the bound).
    #[test]
    fn no_kept_point_is_closer_than_distance_outside() {
        let mut rng = Xorshift::new(0xbb67_ae85_84ca_a73b);
        let mut tight = 0;
        for _ in 0..3000 {
            let segment = random_segment(&mut rng);
            let p = v2(8.0 * rng.signed_unit(), 8.0 * rng.signed_unit());
            let bound = segment.distance_outside(p);
            assert!(bound >= 0.0);
            for _ in 0..200 {
                let reach = 2.0 * bound.max(0.01) * rng.signed_unit().abs();
                let a = 4.0 * rng.signed_unit();
                let q = p + v2(a.cos(), a.sin()) * reach;
                if segment.inner_margin(segment.param_of(q)) > 0.0 {
                    let d = (q - p).norm();
                    assert!(d >= bound - 1e-12, "{segment:?} {p:?} {q:?} {bound} {d}");
                    tight += usize::from(bound > 0.0 && d < 1.5 * bound);
                }
            }
        }
        assert!(tight > 100, "{tight}");
    }
}
