//! Clearance between a filled polygon (a clamp body or plunger) and the
//! true part region, arcs included (SPEC 8.5: "clearance is measured to the
//! true posed part region"), with the rules of
//! [`crate::geometry::polygon_clearance`]: `None` when the interiors
//! overlap, otherwise the distance (0 when they only touch), so that
//! `min_clearance = 0` allows touching and forbids overlap.

use super::{Edge, Outline};
use crate::geometry::arc::{segment_circle, CircArc};
use crate::geometry::{
    boundary_distance2, cross, point_in_polygon, proper_crossing, v2, Aabb, EPS, V2,
};

/// How far inside a boundary the overlap probes look (as polygons do).
const PROBE_STEP: f64 = 1e-7;

impl Outline {
    /// Clearance between the CCW polygon `poly` and the region (the
    /// material: SPEC 9.4), in the outline's frame.
    ///
    /// A hole whose box lies farther from the polygon's than the nearest
    /// edge found so far can neither cross it nor be nearer, so it is
    /// skipped: a part's many small bolt holes cost a box test each.
    /// With boundaries apart, the polygon overlaps the material exactly
    /// when a vertex of it lies in the material (it may lie in a hole,
    /// then all of it does) or the outline lies in it.
    pub fn polygon_clearance(&self, poly: &[V2]) -> Option<f64> {
        let mut best = side_distance(poly, self.outline_edges(), f64::INFINITY)?;
        if !self.holes.is_empty() {
            let poly_box = Aabb::of(poly);
            for h in &self.holes {
                let gap = poly_box.gap(&h.aabb);
                if gap > 0.0 && gap >= best {
                    continue;
                }
                best = side_distance(poly, &self.edges()[h.edges.clone()], best)?;
            }
        }
        let inside_poly = |x: V2| point_in_polygon(x, poly);
        if best > EPS {
            // Disjoint boundaries: overlap only by containment.
            if self.contains(poly[0]) || inside_poly(self.points()[0]) {
                return None;
            }
        } else if self.probes_inside(poly) || polygon_probes_inside_region(poly, self) {
            return None;
        }
        Some(best)
    }

    /// Bounding box of the region.
    pub fn aabb(&self) -> Aabb {
        let mut b = Aabb::of(&[]);
        for e in self.edges() {
            let eb = e.aabb();
            b.min = b.min.inf(&eb.min);
            b.max = b.max.sup(&eb.max);
        }
        b
    }

    /// Touching boundaries: whether a point just inside the region, next
    /// to the middle of one of its edges, lies deep inside `poly`.
    fn probes_inside(&self, poly: &[V2]) -> bool {
        self.edges().iter().any(|e| {
            let (mid, inward) = match e {
                Edge::Line { a, b } => {
                    let d = (b - a).normalize();
                    ((a + b) * 0.5, v2(-d.y, d.x))
                }
                Edge::Arc(arc) => {
                    // Towards the centre on a convex (CCW) arc.
                    let sign = if arc.is_ccw() { -1.0 } else { 1.0 };
                    (arc.midpoint(), arc.axis() * sign)
                }
            };
            let x = mid + inward * PROBE_STEP;
            point_in_polygon(x, poly) && boundary_distance2(x, poly) > EPS * EPS
        })
    }
}

/// The smallest of `best` and the distances between the sides of `poly`
/// and `edges`, or `None` when a side crosses an edge.
fn side_distance(poly: &[V2], edges: &[Edge], mut best: f64) -> Option<f64> {
    let m = poly.len();
    for j in 0..m {
        let (a, b) = (poly[j], poly[(j + 1) % m]);
        let side = Edge::Line { a, b };
        for e in edges {
            if crosses(a, b, e) {
                return None;
            }
            best = best.min(side.closest(e).distance);
        }
    }
    Some(best)
}

/// Whether a point just inside `poly` next to an edge's middle or at a
/// vertex lies deep inside the region.
fn polygon_probes_inside_region(poly: &[V2], region: &Outline) -> bool {
    let n = poly.len();
    (0..n).any(|i| {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        let d = b - a;
        let len = d.norm();
        if len == 0.0 {
            return false;
        }
        let inward = v2(-d.y, d.x) / len;
        let mid = (a + b) * 0.5 + inward * PROBE_STEP;
        let deep = |x: V2| region.contains(x) && region.boundary_distance(x) > EPS;
        deep(mid) || deep(a)
    })
}

/// Whether the segment `[a, b]` crosses the edge at a point interior to
/// both, transversally (touching is not crossing).
fn crosses(a: V2, b: V2, edge: &Edge) -> bool {
    match edge {
        Edge::Line { a: c, b: d } => proper_crossing(a, b, *c, *d),
        Edge::Arc(arc) => segment_crosses_arc(a, b, arc),
    }
}

fn segment_crosses_arc(a: V2, b: V2, arc: &CircArc) -> bool {
    let d = b - a;
    let len = d.norm();
    if len == 0.0 {
        return false;
    }
    let tol = EPS * (len + arc.radius);
    segment_circle(a, b, arc.center, arc.radius, 0.0)
        .as_slice()
        .iter()
        .any(|&p| {
            let radial = (p - arc.center) / arc.radius;
            let transversal = cross(d / len, radial).abs() > EPS;
            let inside_segment = (p - a).norm() > tol && (p - b).norm() > tol;
            let half = 0.5 * arc.sweep.abs() - tol / arc.radius;
            let e = arc.axis();
            let w = p - arc.center;
            let inside_arc = cross(e, w).atan2(e.dot(&w)).abs() < half;
            transversal && inside_segment && inside_arc
        })
}
