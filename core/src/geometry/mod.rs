//! Planar geometry shared by every stage: the small exact-as-floats
//! primitives here (points, rotations, distances, boxes, polygon
//! clearance), and in submodules sets of angles, circular arcs and the
//! validation of input polygons.
//!
//! Hand-written rather than taken from parry2d because the enumeration needs
//! SPEC's `eps` semantics at each decision (strict = "by more than eps") and
//! allocation-free calls in the innermost loops; the test suite cross-checks
//! these against parry2d.

pub(crate) mod angle_set;
pub(crate) mod arc;
pub(crate) mod polygon;
pub(crate) mod rounding;

use nalgebra::Vector2;

/// A point or vector; nalgebra's, so the metric's matrices take it as is.
pub type V2 = Vector2<f64>;

/// SPEC's tolerance, in lattice units (and for det W, lambda and cosines).
pub const EPS: f64 = 1e-9;

/// Within this of a decision boundary a fixture is *borderline* (SPEC 1).
pub const BORDERLINE: f64 = 1e-6;

/// Shorthand for the many literal points of the geometry and its tests.
#[inline]
pub fn v2(x: f64, y: f64) -> V2 {
    V2::new(x, y)
}

/// 2-D cross product `a.x b.y - a.y b.x`.
#[inline]
pub fn cross(a: V2, b: V2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Rotation of `p` by angle with cosine `c` and sine `s`.
#[inline]
pub fn rot(c: f64, s: f64, p: V2) -> V2 {
    v2(c * p.x - s * p.y, s * p.x + c * p.y)
}

/// Inverse rotation (`R^T p`).
#[inline]
pub fn rot_t(c: f64, s: f64, p: V2) -> V2 {
    v2(c * p.x + s * p.y, -s * p.x + c * p.y)
}

/// Rotation by `k` quarter turns, exact.
#[inline]
pub fn rot90(k: u8, p: V2) -> V2 {
    match k & 3 {
        0 => p,
        1 => v2(-p.y, p.x),
        2 => v2(-p.x, -p.y),
        _ => v2(p.y, -p.x),
    }
}

/// Integer rotation by `k` quarter turns.
#[inline]
pub fn rot90i(k: u8, p: [i64; 2]) -> [i64; 2] {
    match k & 3 {
        0 => p,
        1 => [-p[1], p[0]],
        2 => [-p[0], -p[1]],
        _ => [p[1], -p[0]],
    }
}

/// Squared distance from `p` to the closed segment `[a, b]`.
#[inline]
pub fn point_segment_dist2(p: V2, a: V2, b: V2) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(&ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t - p).norm_squared()
}

/// Whether the closed segments `[a,b]` and `[c,d]` share a point.
///
/// The orientation signs are exact (Shewchuk's adaptive `orient2d`): with
/// plain floats, points that a rounded `a + t (b - a)` left a few ulps off
/// one line zigzag across it, and two disjoint pieces of that line far
/// apart then "cross", so a valid part with a long edge split in pieces
/// (a flattened outline, a DXF line drawn in parts) was refused as
/// self-intersecting.
pub fn segments_intersect(a: V2, b: V2, c: V2, d: V2) -> bool {
    // Disjoint boxes share no point: most pairs a clearance test meets
    // end here, before the four orientations.
    if a.x.max(b.x) < c.x.min(d.x)
        || c.x.max(d.x) < a.x.min(b.x)
        || a.y.max(b.y) < c.y.min(d.y)
        || c.y.max(d.y) < a.y.min(b.y)
    {
        return false;
    }
    let d1 = orientation(a, b, c);
    let d2 = orientation(a, b, d);
    let d3 = orientation(c, d, a);
    let d4 = orientation(c, d, b);
    if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
        return true;
    }
    let on = |p: V2, q: V2, r: V2, o: f64| {
        o == 0.0
            && r.x >= p.x.min(q.x)
            && r.x <= p.x.max(q.x)
            && r.y >= p.y.min(q.y)
            && r.y <= p.y.max(q.y)
    };
    on(a, b, c, d1) || on(a, b, d, d2) || on(c, d, a, d3) || on(c, d, b, d4)
}

/// The exact sign (-1, 0 or 1) of `cross(b - a, c - a)`: positive when
/// `a, b, c` turn counter-clockwise. Every collinearity decision of polygon
/// validation goes through it, so that a crossing and a fold-back are
/// judged alike.
pub(crate) fn orientation(a: V2, b: V2, c: V2) -> f64 {
    let at = |p: V2| robust::Coord { x: p.x, y: p.y };
    let o = robust::orient2d(at(a), at(b), at(c));
    if o == 0.0 {
        0.0
    } else {
        o.signum()
    }
}

/// Squared distance between closed segments (0 when they intersect).
pub fn segment_segment_dist2(a: V2, b: V2, c: V2, d: V2) -> f64 {
    if segments_intersect(a, b, c, d) {
        return 0.0;
    }
    point_segment_dist2(a, c, d)
        .min(point_segment_dist2(b, c, d))
        .min(point_segment_dist2(c, a, b))
        .min(point_segment_dist2(d, a, b))
}

/// Even-odd point in polygon (boundary points may go either way; callers
/// that care about the boundary combine this with a distance).
pub fn point_in_polygon(p: V2, poly: &[V2]) -> bool {
    let mut inside = false;
    let n = poly.len();
    let mut j = n - 1;
    for i in 0..n {
        let (a, b) = (poly[i], poly[j]);
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y);
            if p.x < x {
                inside = !inside;
            }
        }
        j = i;
    }
    inside
}

/// Squared distance from a point to a polygon's boundary.
pub fn boundary_distance2(p: V2, poly: &[V2]) -> f64 {
    let n = poly.len();
    let mut best = f64::INFINITY;
    for i in 0..n {
        best = best.min(point_segment_dist2(p, poly[i], poly[(i + 1) % n]));
    }
    best
}

/// Axis-aligned bounding box: a cheap lower bound on a clearance, so most
/// clamp placements skip the exact polygon test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Lower-left corner.
    pub min: V2,
    /// Upper-right corner.
    pub max: V2,
}

impl Aabb {
    /// The box of `points` (inverted, min above max, when empty).
    pub fn of(points: &[V2]) -> Aabb {
        let mut min = v2(f64::INFINITY, f64::INFINITY);
        let mut max = v2(f64::NEG_INFINITY, f64::NEG_INFINITY);
        for p in points {
            min = min.inf(p);
            max = max.sup(p);
        }
        Aabb { min, max }
    }

    /// Lower bound of the distance between anything in `self` and in `other`.
    pub fn gap(&self, other: &Aabb) -> f64 {
        self.gap2(other).sqrt()
    }

    /// Square of [`Self::gap`].
    #[inline]
    pub fn gap2(&self, other: &Aabb) -> f64 {
        let dx = (other.min.x - self.max.x)
            .max(self.min.x - other.max.x)
            .max(0.0);
        let dy = (other.min.y - self.max.y)
            .max(self.min.y - other.max.y)
            .max(0.0);
        dx * dx + dy * dy
    }
}

/// Clearance between two filled polygons: `None` when their interiors
/// overlap, otherwise the distance between them (0 when they only touch).
///
/// Overlap is decided by proper edge crossings and containment, so that
/// `min_clearance = 0` can allow touching and forbid overlap as SPEC asks.
/// Both polygons must be counter-clockwise.
pub fn polygon_clearance(p: &[V2], q: &[V2]) -> Option<f64> {
    polygon_clearance_below(p, q, f64::INFINITY)
}

/// [`polygon_clearance`] when only clearances up to `cap` matter: edges of
/// `q` whose box is farther than `cap` from `p`'s box are skipped (they can
/// neither cross `p` nor be the closest), so a clearance above `cap` may
/// come back as any value above `cap`. The clamp test needs the exact value
/// only near `min_clearance`, where it decides borderline fixtures; a part
/// edge far from the clamp then costs a box test instead of `|p|` distance
/// computations. Give the small polygon as `p`.
pub fn polygon_clearance_below(p: &[V2], q: &[V2], cap: f64) -> Option<f64> {
    let (n, m) = (p.len(), q.len());
    let pb = Aabb::of(p);
    let cap2 = cap * cap;
    let mut best2 = f64::INFINITY;
    for j in 0..m {
        let (c, d) = (q[j], q[(j + 1) % m]);
        let eb = Aabb {
            min: c.inf(&d),
            max: c.sup(&d),
        };
        if pb.gap2(&eb) > cap2 {
            continue;
        }
        for i in 0..n {
            let (a, b) = (p[i], p[(i + 1) % n]);
            if proper_crossing(a, b, c, d) {
                return None;
            }
            best2 = best2.min(segment_segment_dist2(a, b, c, d));
        }
    }
    let best = best2.sqrt();
    if best > EPS {
        // Disjoint boundaries: overlap only by containment.
        if point_in_polygon(p[0], q) || point_in_polygon(q[0], p) {
            return None;
        }
    } else if probes_inside(p, q) || probes_inside(q, p) {
        return None;
    }
    Some(best)
}

/// Touching boundaries: the interiors overlap iff a point just inside `p`
/// next to one of its edges (or a vertex) lies inside `q`. Needs CCW `p`.
fn probes_inside(p: &[V2], q: &[V2]) -> bool {
    const STEP: f64 = 1e-7;
    let n = p.len();
    (0..n).any(|i| {
        let (a, b) = (p[i], p[(i + 1) % n]);
        let d = b - a;
        let len = d.norm();
        if len == 0.0 {
            return false;
        }
        let inward = v2(-d.y, d.x) / len;
        let mid = (a + b) * 0.5 + inward * STEP;
        let deep = |x: V2| point_in_polygon(x, q) && boundary_distance2(x, q) > EPS * EPS;
        deep(mid) || deep(a)
    })
}

/// Segments cross at a single point interior to both.
pub(crate) fn proper_crossing(a: V2, b: V2, c: V2, d: V2) -> bool {
    let d1 = cross(b - a, c - a);
    let d2 = cross(b - a, d - a);
    let d3 = cross(d - c, a - c);
    let d4 = cross(d - c, b - c);
    let tol = EPS * ((b - a).norm() + (d - c).norm());
    ((d1 > tol && d2 < -tol) || (d1 < -tol && d2 > tol))
        && ((d3 > tol && d4 < -tol) || (d3 < -tol && d4 > tol))
}

/// Clearance between a filled polygon and a disk: `None` on overlap.
pub fn polygon_disk_clearance(poly: &[V2], centre: V2, radius: f64) -> Option<f64> {
    let d = boundary_distance2(centre, poly).sqrt();
    if point_in_polygon(centre, poly) || d < radius - EPS {
        return None;
    }
    Some((d - radius).max(0.0))
}

/// Signed area (positive for counter-clockwise).
pub fn signed_area(poly: &[V2]) -> f64 {
    let n = poly.len();
    let mut a = 0.0;
    for i in 0..n {
        a += cross(poly[i], poly[(i + 1) % n]);
    }
    a * 0.5
}

/// Area centroid and polar second moment about it (for SPEC 6's `c`, `rho`).
pub fn centroid_and_polar_moment(poly: &[V2]) -> (V2, f64) {
    let n = poly.len();
    // Shift to the first vertex for numerical stability.
    let o = poly[0];
    let mut a2 = 0.0;
    let mut cx = 0.0;
    let mut cy = 0.0;
    let mut ixx = 0.0;
    let mut iyy = 0.0;
    for i in 0..n {
        let p = poly[i] - o;
        let q = poly[(i + 1) % n] - o;
        let c = cross(p, q);
        a2 += c;
        cx += (p.x + q.x) * c;
        cy += (p.y + q.y) * c;
        ixx += (p.y * p.y + p.y * q.y + q.y * q.y) * c;
        iyy += (p.x * p.x + p.x * q.x + q.x * q.x) * c;
    }
    let area = a2 * 0.5;
    let c = v2(cx / (3.0 * a2), cy / (3.0 * a2));
    // Polar moment about the shifted origin, then parallel-axis to centroid.
    let j_o = (ixx + iyy) / 12.0;
    let j_c = j_o - area * c.norm_squared();
    (c + o, j_c.abs())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x0: f64, y0: f64, s: f64) -> Vec<V2> {
        vec![
            v2(x0, y0),
            v2(x0 + s, y0),
            v2(x0 + s, y0 + s),
            v2(x0, y0 + s),
        ]
    }

    #[test]
    fn segment_distances() {
        assert_eq!(
            segment_segment_dist2(v2(0., 0.), v2(2., 0.), v2(1., -1.), v2(1., 1.)),
            0.0
        );
        let d = segment_segment_dist2(v2(0., 0.), v2(1., 0.), v2(2., 1.), v2(3., 1.));
        assert!((d - 2.0).abs() < 1e-12);
        assert!((point_segment_dist2(v2(0.5, 2.), v2(0., 0.), v2(1., 0.)) - 4.0).abs() < 1e-12);
    }

    #[test]
    fn pieces_of_one_line_do_not_cross() {
        // From a proptest failure: a line cut in 71 pieces by a rounded
        // `a + t (b - a)`. With float orientation signs pieces 5 and 58,
        // 16 units apart, "crossed" (the points zigzag by an ulp).
        let (a, b) = (
            v2(-2.636239160009008, -10.03044312761639),
            v2(10.731626504360504, 11.46822085391039),
        );
        let p: Vec<V2> = (0..=71).map(|i| a + (b - a) * (i as f64 / 71.0)).collect();
        for i in 0..71 {
            if i < 70 {
                assert!(segments_intersect(p[i], p[i + 1], p[i + 1], p[i + 2]));
            }
            for j in i + 2..71 {
                assert!(
                    !segments_intersect(p[i], p[i + 1], p[j], p[j + 1]),
                    "{i} x {j}"
                );
            }
        }
        // Exactly collinear overlapping and touching pieces still meet.
        assert!(segments_intersect(
            v2(0., 0.),
            v2(2., 2.),
            v2(1., 1.),
            v2(3., 3.)
        ));
        assert!(!segments_intersect(
            v2(0., 0.),
            v2(1., 1.),
            v2(2., 2.),
            v2(3., 3.)
        ));
    }

    #[test]
    fn clearance_touch_overlap_contain() {
        let a = square(0., 0., 1.);
        assert_eq!(polygon_clearance(&a, &square(1., 0., 1.)), Some(0.0));
        assert_eq!(polygon_clearance(&a, &square(0.5, 0.5, 1.)), None);
        assert_eq!(polygon_clearance(&a, &square(0.25, 0.25, 0.5)), None);
        assert_eq!(polygon_clearance(&square(-1., -1., 3.), &a), None);
        let d = polygon_clearance(&a, &square(3., 0., 1.)).unwrap();
        assert!((d - 2.0).abs() < 1e-12);
        // Identical squares overlap although no edges cross.
        assert_eq!(polygon_clearance(&a, &a), None);
    }

    #[test]
    fn disk_clearance() {
        let a = square(0., 0., 1.);
        assert!(polygon_disk_clearance(&a, v2(0.5, 0.5), 0.1).is_none());
        assert!(polygon_disk_clearance(&a, v2(2.0, 0.5), 1.5).is_none());
        let d = polygon_disk_clearance(&a, v2(2.0, 0.5), 0.5).unwrap();
        assert!((d - 0.5).abs() < 1e-12);
    }

    #[test]
    fn centroid_and_moment_of_rectangle() {
        let r = vec![v2(1., 1.), v2(5., 1.), v2(5., 3.), v2(1., 3.)];
        let (c, j) = centroid_and_polar_moment(&r);
        assert!((c - v2(3., 2.)).norm() < 1e-12);
        // J = A (w^2 + h^2) / 12 = 8 * 20 / 12
        assert!((j - 8.0 * 20.0 / 12.0).abs() < 1e-9);
        assert!((signed_area(&r) - 8.0).abs() < 1e-12);
    }

    #[test]
    fn rotations() {
        assert_eq!(rot90(1, v2(1., 0.)), v2(0., 1.));
        assert_eq!(rot90i(3, [1, 0]), [0, -1]);
        let p = rot(0.5f64.cos(), 0.5f64.sin(), v2(1., 2.));
        assert!((rot_t(0.5f64.cos(), 0.5f64.sin(), p) - v2(1., 2.)).norm() < 1e-12);
    }
}
