//! The affine maps of drawings: an SVG element's `transform` (and its
//! parents'), a DXF INSERT's placement of a block (and the INSERTs above
//! it). One type for both readers, so that composing maps, telling
//! whether circles stay circles and turning arcs round under a mirror
//! are decided the same way whatever the file.

use fixplan_core::Vertex;

/// Affine map `(x, y) -> (a x + c y + e, b x + d y + f)`, SVG's order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Affine(pub(crate) [f64; 6]);

impl Affine {
    /// The identity: no transform.
    pub(crate) const ID: Affine = Affine([1.0, 0.0, 0.0, 1.0, 0.0, 0.0]);

    /// `self` then `other` applied first (SVG nesting: parent * child).
    pub(crate) fn mul(self, other: Affine) -> Affine {
        let [a, b, c, d, e, f] = self.0;
        let [a2, b2, c2, d2, e2, f2] = other.0;
        Affine([
            a * a2 + c * b2,
            b * a2 + d * b2,
            a * c2 + c * d2,
            b * c2 + d * d2,
            a * e2 + c * f2 + e,
            b * e2 + d * f2 + f,
        ])
    }

    /// The image of `p`.
    pub(crate) fn apply(self, p: [f64; 2]) -> [f64; 2] {
        let [a, b, c, d, e, f] = self.0;
        [a * p[0] + c * p[1] + e, b * p[0] + d * p[1] + f]
    }

    /// Whether the map keeps circles circles: a uniform scale, a rotation,
    /// a translation and possibly a reflection (columns orthogonal and of
    /// equal length, to a relative `1e-9`).
    pub(crate) fn is_similarity(self) -> bool {
        let [a, b, c, d, _, _] = self.0;
        let (p, q) = (a * a + b * b, c * c + d * d);
        let tol = 1e-9 * p.max(q);
        p > 0.0
            && p.is_finite()
            && q.is_finite()
            && (p - q).abs() <= tol
            && (a * c + b * d).abs() <= tol
    }

    /// Whether the map mirrors (negative determinant), which turns every
    /// arc the other way.
    pub(crate) fn mirrors(self) -> bool {
        let [a, b, c, d, _, _] = self.0;
        a * d - b * c < 0.0
    }

    /// Largest stretch of the map, to keep chord errors within tolerance
    /// after scaling.
    pub(crate) fn max_scale(self) -> f64 {
        let [a, b, c, d, _, _] = self.0;
        let s = a.hypot(b).max(c.hypot(d));
        if s.is_finite() && s > 0.0 {
            s
        } else {
            1.0
        }
    }
}

impl Affine {
    /// `pts` mapped: positions moved, bulges kept, and negated by a
    /// mirroring map (it turns every arc the other way). Arcs stay arcs
    /// only under a similarity: callers flatten them first otherwise.
    pub(crate) fn vertices(self, pts: Vec<Vertex>) -> Vec<Vertex> {
        let mirror = self.mirrors();
        pts.into_iter()
            .map(|v| {
                let [x, y] = self.apply([v.x, v.y]);
                let bulge = if mirror && v.bulge != 0.0 {
                    -v.bulge
                } else {
                    v.bulge
                };
                Vertex::new(x, y, bulge)
            })
            .collect()
    }
}
