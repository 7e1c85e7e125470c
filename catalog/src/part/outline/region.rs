//! The region a loop of a drawing encloses, arcs included: its area, and
//! whether a point lies inside it. Both use the true arcs, never their
//! chords, because a hole centred on a round end of a part lies exactly on
//! the chord of that end, where a chord polygon and an arc segment disagree.

use fixplan_core::parts::{edges_of, mass_properties, signed_area, v2, Aabb, Edge, V2};
use fixplan_core::Vertex;

/// Unsigned area of the true region (arcs included: a circle is two
/// vertices) for choosing the largest loop; an overflowing loop counts as
/// the largest rather than as NaN, so the choice stays total.
pub(crate) fn loop_area(vertices: &[Vertex]) -> f64 {
    let a = if vertices.iter().any(Vertex::is_arc) {
        mass_properties(vertices).area.abs()
    } else {
        signed_area(&vertices.iter().map(Vertex::point).collect::<Vec<_>>()).abs()
    };
    if a.is_finite() {
        a
    } else {
        f64::INFINITY
    }
}

/// Bounding box of the true loop (arcs bulge out of their chords).
pub(crate) fn loop_aabb(vertices: &[Vertex]) -> Aabb {
    let mut pts = Vec::with_capacity(vertices.len() * 2);
    for e in edges_of(vertices) {
        let b = e.aabb();
        pts.push(b.min);
        pts.push(b.max);
    }
    Aabb::of(&pts)
}

/// Whether box `inner` lies within box `outer` (boundaries included).
pub(crate) fn aabb_within(inner: &Aabb, outer: &Aabb) -> bool {
    inner.min.x >= outer.min.x
        && inner.min.y >= outer.min.y
        && inner.max.x <= outer.max.x
        && inner.max.y <= outer.max.y
}

/// Crossings of the ray from `p` towards +x with a y-monotone piece of
/// curve from `s` to `edge` whose crossing lies at `x_at`: the half-open rule
/// (an end counts as above the ray when its y is greater) makes a ray
/// through a vertex count once.
fn crosses(p: V2, s: V2, edge: V2, x_at: impl Fn() -> f64) -> bool {
    (s.y > p.y) != (edge.y > p.y) && x_at() > p.x
}

/// Whether the ray from `p` towards +x crosses `edge` an odd number of times.
/// An arc is cut at the top and bottom of its circle into y-monotone
/// pieces, each on one half of the circle, where the crossing is
/// `cx +- sqrt(r^2 - (y - cy)^2)`; the cut points are the circle's exact
/// extremes, the ends the edge's own vertices, so neighbouring edges agree
/// on every shared point.
fn edge_parity(p: V2, edge: &Edge) -> bool {
    match edge {
        Edge::Line { a, b } => crosses(p, *a, *b, || a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y)),
        Edge::Arc(arc) => {
            let c = arc.center;
            let r = arc.radius;
            let a0 = (arc.a.y - c.y).atan2(arc.a.x - c.x);
            let sweep = arc.sweep;
            // The angles (pi/2 + k pi) strictly inside the sweep, in order.
            let (lo, hi) = if sweep >= 0.0 {
                (a0, a0 + sweep)
            } else {
                (a0 + sweep, a0)
            };
            let half = std::f64::consts::FRAC_PI_2;
            let pi = std::f64::consts::PI;
            let mut cuts = Vec::new();
            let mut k = ((lo - half) / pi).floor() + 1.0;
            while half + k * pi < hi && cuts.len() < 4 {
                // Angle pi/2 + k pi is the top of the circle for even k.
                let top = k.rem_euclid(2.0) < 0.5;
                cuts.push((half + k * pi, if top { c.y + r } else { c.y - r }));
                k += 1.0;
            }
            if sweep < 0.0 {
                cuts.reverse();
            }
            let mut pts = vec![(arc.a, a0)];
            for (t, y) in cuts {
                pts.push((v2(c.x, y), t));
            }
            pts.push((arc.b, a0 + sweep));
            let mut odd = false;
            for w in pts.windows(2) {
                let ((s, ts), (q, tq)) = (w[0], w[1]);
                let right = ((ts + tq) / 2.0).cos() > 0.0;
                let x_at = || {
                    let dy = p.y - c.y;
                    let dx = (r * r - dy * dy).max(0.0).sqrt();
                    if right {
                        c.x + dx
                    } else {
                        c.x - dx
                    }
                };
                odd ^= crosses(p, s, q, x_at);
            }
            odd
        }
    }
}

/// Even-odd location of `p` in the true region of `outline`, arcs exact;
/// an empty loop contains nothing. Points on the boundary may go either
/// way: [`test_point`] keeps away from it.
pub(crate) fn contains(outline: &[Vertex], p: V2) -> bool {
    let mut inside = false;
    for e in edges_of(outline) {
        inside ^= edge_parity(p, &e);
    }
    inside
}

/// A point of loop `inner` to tell whether it lies inside `outer`: its
/// vertex or edge midpoint farthest from `outer`'s boundary, because loops
/// of a drawing may touch (a hole tangent to the outline) and a point on
/// the boundary says nothing.
pub(crate) fn test_point(inner: &[Vertex], outer: &[Vertex]) -> Option<V2> {
    let outer_edges = edges_of(outer);
    let clearance = |q: V2| {
        outer_edges
            .iter()
            .map(|e| e.distance(q))
            .fold(f64::INFINITY, f64::min)
    };
    let mut best: Option<(f64, V2)> = None;
    for e in edges_of(inner) {
        for q in [e.start(), e.point_at(0.5)] {
            let d = clearance(q);
            if d.is_finite() && best.is_none_or(|b| d > b.0) {
                best = Some((d, q));
            }
            // Far enough from the boundary that no rounding can matter.
            if best.is_some_and(|b| b.0 > 1e-6 * (1.0 + q.x.abs() + q.y.abs())) {
                return best.map(|b| b.1);
            }
        }
    }
    best.map(|b| b.1)
}

/// Whether loop `inner` lies inside loop `outer` (loops of a drawing do
/// not cross, so one well-chosen point decides).
pub(crate) fn loop_inside(inner: &[Vertex], outer: &[Vertex]) -> bool {
    match test_point(inner, outer) {
        Some(q) => contains(outer, q),
        None => false,
    }
}

#[cfg(test)]
mod tests {
    use super::super::curves::{exact_arc, exact_circle, straight};
    use super::*;

    /// A link lying along `axis`: two half circles of radius 10 about
    /// (0, 0) and 40 along the axis, joined by straight sides.
    fn link(vertical: bool) -> Vec<Vertex> {
        let m = |x: f64, y: f64, b: f64| {
            if vertical {
                Vertex::new(-y, x, b)
            } else {
                Vertex::new(x, y, b)
            }
        };
        vec![
            m(0.0, -10.0, 0.0),
            m(40.0, -10.0, 1.0),
            m(40.0, 10.0, 0.0),
            m(0.0, 10.0, 1.0),
        ]
    }

    #[test]
    fn a_point_on_an_end_chord_is_inside_either_way_round() {
        for vertical in [false, true] {
            let l = link(vertical);
            let at = |x: f64, y: f64| if vertical { v2(-y, x) } else { v2(x, y) };
            // The centres of the round ends lie on their chords.
            assert!(contains(&l, at(0.0, 0.0)), "vertical {vertical}");
            assert!(contains(&l, at(40.0, 0.0)), "vertical {vertical}");
            // Points in the end caps, beyond the chords.
            assert!(contains(&l, at(-9.0, 0.0)));
            assert!(contains(&l, at(49.0, 0.0)));
            assert!(contains(&l, at(45.0, 5.0)));
            assert!(!contains(&l, at(-10.5, 0.0)));
            assert!(!contains(&l, at(50.5, 0.0)));
            assert!(!contains(&l, at(48.0, 9.0)));
            // A hole centred on each end.
            for cx in [0.0, 40.0] {
                let c = at(cx, 0.0);
                let hole = exact_circle([c.x, c.y], 4.0);
                assert!(loop_inside(&hole, &l), "hole at {cx}, vertical {vertical}");
            }
        }
    }

    #[test]
    fn arcs_of_any_sweep_and_direction() {
        // Three quarters of a circle, clockwise and counter-clockwise, closed
        // by two radii.
        for sign in [1.0, -1.0] {
            let mut arc = exact_arc([0.0, 0.0], 1.0, 0.0, sign * 1.5 * std::f64::consts::PI);
            arc.push(Vertex::new(0.0, 0.0, 0.0));
            let pts = arc;
            // The missing quarter is below the x axis for CCW (from 0 to
            // 270 degrees), above it for CW.
            let missing = v2(0.5, -0.5 * sign);
            let present = v2(-0.5, 0.5 * sign);
            assert!(!contains(&pts, missing), "sign {sign}");
            assert!(contains(&pts, present), "sign {sign}");
            assert!(contains(&pts, v2(-0.5, -0.5 * sign)), "sign {sign}");
        }
        let square = straight(vec![[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]);
        assert!(contains(&square, v2(1.0, 1.0)));
        // A ray through a vertex counts once.
        assert!(contains(&square, v2(1.0, 2.0 - 1e-12)));
        assert!(!contains(&square, v2(-1.0, 0.0)));
    }

    #[test]
    fn a_hole_touching_the_outline_is_still_inside() {
        let square = straight(vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]]);
        // A circle tangent to the left side at its first point (0, 5).
        let hole = vec![Vertex::new(0.0, 5.0, 1.0), Vertex::new(4.0, 5.0, 1.0)];
        assert!(loop_inside(&hole, &square));
        let outside = exact_circle([20.0, 5.0], 2.0);
        assert!(!loop_inside(&outside, &square));
    }
}
