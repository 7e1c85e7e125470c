//! Area, centroid and polar second moment of the true region (SPEC 6, 8.1).

use super::edge::{edges_of, Edge};
use super::vertex::Vertex;
use crate::geometry::arc::segment_moments;
use crate::geometry::{centroid_and_polar_moment, cross, signed_area, v2, V2};

/// What SPEC 6's metric needs from a part: `A`, `c` and `J` (so that
/// `rho = sqrt(J / A)`), of the region bounded by the true curves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassProperties {
    /// Signed area: positive for a counter-clockwise outline. Its sign is
    /// the outline's orientation (SPEC 8.1).
    pub area: f64,
    /// Area centroid.
    pub centroid: V2,
    /// Polar second moment of area about the centroid, `>= 0`.
    pub polar_moment: f64,
}

impl MassProperties {
    /// Radius of gyration `sqrt(J / |A|)` about the centroid.
    pub fn radius_of_gyration(&self) -> f64 {
        (self.polar_moment / self.area.abs()).sqrt()
    }
}

/// Mass properties of the region of a vertex list, either orientation.
///
/// Without arcs these are `signed_area` and `centroid_and_polar_moment` of
/// the polygon, bit for bit. With arcs, Green's theorem splits each arc
/// edge into its chord (the polygon formulas) and the closed loop arc +
/// reversed chord, which bounds the arc's circular segment counter-
/// clockwise when the bulge is positive: each segment's area, first and
/// second moments (`segment_moments`) are added for `b > 0` and
/// subtracted for `b < 0`, then moved to the common origin (parallel axes).
pub fn mass_properties(vertices: &[Vertex]) -> MassProperties {
    if vertices.iter().any(Vertex::is_arc) {
        general(vertices)
    } else {
        let pts: Vec<V2> = vertices.iter().map(Vertex::point).collect();
        let (centroid, polar_moment) = centroid_and_polar_moment(&pts);
        MassProperties {
            area: signed_area(&pts),
            centroid,
            polar_moment,
        }
    }
}

/// The chord-plus-segments sum; also right (to rounding) without arcs,
/// which the tests check against the polygon formulas.
pub(super) fn general(vertices: &[Vertex]) -> MassProperties {
    let n = vertices.len();
    if n == 0 {
        return MassProperties {
            area: 0.0,
            centroid: v2(0.0, 0.0),
            polar_moment: 0.0,
        };
    }
    // Everything relative to the first vertex, as the polygon code does.
    let o = vertices[0].point();
    let (mut a2, mut qx, mut qy, mut j12) = (0.0, 0.0, 0.0, 0.0);
    for i in 0..n {
        let p = vertices[i].point() - o;
        let q = vertices[(i + 1) % n].point() - o;
        let c = cross(p, q);
        a2 += c;
        qx += (p.x + q.x) * c;
        qy += (p.y + q.y) * c;
        j12 += (p.y * p.y + p.y * q.y + q.y * q.y + p.x * p.x + p.x * q.x + q.x * q.x) * c;
    }
    let mut area = 0.5 * a2;
    let mut first = v2(qx, qy) / 6.0;
    let mut second = j12 / 12.0;
    for e in edges_of(vertices) {
        if let Edge::Arc(arc) = e {
            let (s, m, j) = segment_moments(&arc);
            let sign = arc.bulge.signum();
            let e = arc.axis();
            let mid = (arc.a + arc.b) * 0.5 - o;
            area += sign * s;
            first += (mid * s + e * m) * sign;
            second += sign * (j + 2.0 * m * mid.dot(&e) + s * mid.norm_squared());
        }
    }
    let c = first / area;
    MassProperties {
        area,
        centroid: c + o,
        polar_moment: (second - area * c.norm_squared()).abs(),
    }
}

/// The properties of a region bounded by several loops (SPEC 9.5: the
/// outline counter-clockwise, the holes clockwise, so their signed areas
/// and moments subtract): areas and first moments add, and each loop's
/// polar moment moves to the common centroid (parallel axes), with the
/// sign of its area.
pub(super) fn combined(loops: &[MassProperties]) -> MassProperties {
    let area: f64 = loops.iter().map(|m| m.area).sum();
    let first = loops
        .iter()
        .fold(v2(0.0, 0.0), |acc, m| acc + m.centroid * m.area);
    let centroid = first / area;
    let polar_moment: f64 = loops
        .iter()
        .map(|m| m.area.signum() * m.polar_moment + m.area * (m.centroid - centroid).norm_squared())
        .sum();
    MassProperties {
        area,
        centroid,
        polar_moment: polar_moment.abs(),
    }
}
