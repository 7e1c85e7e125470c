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

/// How far beyond the asked cap [`Outline::polygon_clearance_below`]
/// still measures edges: far above the rounding of a distance or a box gap
/// (about 1e-16 times the coordinates), so that an edge it skips is surely
/// farther than the cap.
const CAP_SLACK: f64 = 1e-6;

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
        self.polygon_clearance_below(poly, f64::INFINITY)
    }

    /// [`Self::polygon_clearance`] where only a clearance up to `cap`
    /// matters: the same `None`, the same distance when
    /// [`Self::polygon_clearance`]'s is at most `cap`, otherwise some
    /// distance above `cap`. An edge whose box lies farther than `cap`
    /// (plus a slack of 1e-6) from the polygon's is then skipped, a box test
    /// instead of one distance per polygon side: the clamp checks of a
    /// straight outline with holes cost what a polygon's do.
    ///
    /// Why the answer is the same (not only within rounding): a skipped
    /// edge's box is apart from the polygon's, so no side properly crosses
    /// it (`proper_crossing` asks for a crossing by far more than the
    /// rounding of coordinates below 1e6), and its computed distance
    /// exceeds `cap` since it is at least the box gap less a rounding far
    /// below the slack. The edge at the minimum, when that is at most
    /// `cap`, has its box within `cap` and is kept; the holes kept beyond
    /// those [`Self::polygon_clearance`] keeps lie in the slack band and
    /// are farther than `cap`. So the minimum and the overlap verdicts
    /// agree.
    pub fn polygon_clearance_below(&self, poly: &[V2], cap: f64) -> Option<f64> {
        let poly_box = Aabb::of(poly);
        let reach = cap + CAP_SLACK;
        let outer = self.outline_edges();
        let boxes = &self.edge_boxes()[..outer.len()];
        let mut best = f64::INFINITY;
        for (e, b) in outer.iter().zip(boxes) {
            if poly_box.gap(b) <= reach {
                best = side_distance(poly, std::slice::from_ref(e), best)?;
            }
        }
        if !self.holes.is_empty() {
            best = self.holes_side_distance(poly, &poly_box, best, reach)?;
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

    /// [`side_distance`] over the holes whose boxes come within `best`
    /// (and within `reach`) of the polygon's: the others can neither
    /// cross it nor be nearer.
    /// Holes are swept by the left side of their boxes, from the first
    /// that can reach the polygon's left (no box is wider than the widest)
    /// to the last that starts before its right; `best` only shrinks on
    /// the way, so the window stays right. Holes beyond `reach` are skipped
    /// whatever their order, so it narrows the window too.
    fn holes_side_distance(
        &self,
        poly: &[V2],
        poly_box: &Aabb,
        mut best: f64,
        reach: f64,
    ) -> Option<f64> {
        let index = &self.by_left;
        let from = poly_box.min.x - best.min(reach) - index.widest;
        let first = index.left.partition_point(|&x| x < from);
        for (&k, &left) in index.order[first..].iter().zip(&index.left[first..]) {
            if left > poly_box.max.x + best.min(reach) {
                break;
            }
            let h = &self.holes[k];
            let gap = poly_box.gap(&h.aabb);
            if (gap > 0.0 && gap >= best) || gap > reach {
                continue;
            }
            best = side_distance(poly, &self.edges()[h.edges.clone()], best)?;
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

#[cfg(test)]
mod tests {
    //! The capped clearance against the full one: it must give the same
    //! verdicts, and the same bits wherever the clamp checks read them.

    use super::*;
    use crate::outline::Vertex;
    use proptest::prelude::*;

    /// A plate 20 x 12 with a grid of square holes and two round ones.
    fn plate() -> Outline {
        let outer: Vec<Vertex> = [[0.0, 0.0], [20.0, 0.0], [20.0, 12.0], [0.0, 12.0]]
            .iter()
            .map(|&p| Vertex::from(p))
            .collect();
        let mut holes: Vec<Vec<Vertex>> = Vec::new();
        for i in 0..5 {
            for j in 0..3 {
                let (x, y) = (1.0 + 3.5 * f64::from(i), 1.0 + 3.5 * f64::from(j));
                let square = [[x, y], [x, y + 2.0], [x + 2.0, y + 2.0], [x + 2.0, y]];
                holes.push(square.iter().map(|&p| Vertex::from(p)).collect());
            }
        }
        for cx in [18.0, 18.5] {
            let cy = if cx == 18.0 { 2.0 } else { 9.0 };
            holes.push(vec![
                Vertex::new(cx - 0.7, cy, -1.0),
                Vertex::new(cx + 0.7, cy, -1.0),
            ]);
        }
        Outline::new(&outer)
            .expect("valid outline")
            .with_holes(holes)
    }

    /// A CCW rectangle, at quarter turns when `angle` is 0, often with
    /// sides on the plate's (touching cases).
    fn rectangle(corner: V2, size: V2, angle: f64) -> Vec<V2> {
        let (s, c) = angle.sin_cos();
        let turn = |p: V2| corner + v2(c * p.x - s * p.y, s * p.x + c * p.y);
        [v2(0.0, 0.0), v2(size.x, 0.0), size, v2(0.0, size.y)]
            .map(turn)
            .to_vec()
    }

    proptest! {
        #![proptest_config(ProptestConfig {
            cases: 2000,
            rng_seed: proptest::test_runner::RngSeed::Fixed(0x0c1e_a0ce),
            failure_persistence: None,
            ..ProptestConfig::default()
        })]

        #[test]
        fn capped_clearance_agrees_with_full(
            x in -4i32..96, y in -4i32..64, w in 1i32..30, h in 1i32..30,
            turned in proptest::bool::ANY, angle in 0.0..std::f64::consts::TAU,
            cap in 0.0f64..3.0,
        ) {
            let region = plate();
            let angle = if turned { angle } else { 0.0 };
            let corner = v2(f64::from(x) * 0.25, f64::from(y) * 0.25);
            let poly = rectangle(corner, v2(f64::from(w) * 0.25, f64::from(h) * 0.25), angle);
            let full = region.polygon_clearance(&poly);
            let capped = region.polygon_clearance_below(&poly, cap);
            match (full, capped) {
                (None, None) => {}
                (Some(d), Some(e)) if d <= cap => prop_assert_eq!(d.to_bits(), e.to_bits()),
                (Some(_), Some(e)) => prop_assert!(e > cap, "{e} not above {cap}"),
                other => prop_assert!(false, "verdicts differ: {other:?}"),
            }
        }
    }
}
