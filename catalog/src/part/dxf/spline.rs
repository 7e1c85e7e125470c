//! SPLINE entities as straight pieces within the chord tolerance.
//!
//! Flattened rather than fitted with arcs: a chord error bound holds for
//! any NURBS by subdivision, while an arc fit needs curvature analysis and
//! gives outlines whose arcs meet at tiny unwanted joints; the chord
//! tolerance already bounds what the part loses. The curve is evaluated
//! from its control points, knots and weights (de Boor's algorithm in
//! homogeneous coordinates, so rational splines and conics are exact);
//! fit points alone do not define the curve AutoCAD draws, so a spline
//! without control points is not read.

use super::super::outline::P;
use super::super::raw::LimitExceeded;
use fixplan_core::parts::{point_segment_dist2, v2};

/// Highest degree read; CAD tools write 1 to 3 (5 at most in some).
const MAX_DEGREE: usize = 11;
/// Deepest bisection of one knot span.
const MAX_DEPTH: u32 = 24;

/// Why a SPLINE gives no points.
#[derive(Debug)]
pub(super) enum SplineProblem {
    /// The entity is not a spline this reader can evaluate; the reason
    /// ends the warning.
    Unusable(&'static str),
    /// It needs more pieces than [`Limits::spline_pieces`](crate::part::Limits).
    Limit(LimitExceeded),
}

/// A NURBS curve in the plane: degree, knots, control points with weights.
struct Nurbs<'a> {
    degree: usize,
    knots: &'a [f64],
    /// Control points times their weights, and the weights.
    ctrl: Vec<[f64; 3]>,
}

impl Nurbs<'_> {
    /// The point at parameter `t` in the domain, by de Boor in the span
    /// `k` (`knots[k] <= t <= knots[k + 1]`).
    fn at(&self, t: f64, k: usize) -> P {
        let p = self.degree;
        let mut d: Vec<[f64; 3]> = (0..=p).map(|j| self.ctrl[j + k - p]).collect();
        for r in 1..=p {
            for j in (r..=p).rev() {
                let lo = self.knots[j + k - p];
                let hi = self.knots[j + 1 + k - r];
                let alpha = if hi > lo { (t - lo) / (hi - lo) } else { 0.0 };
                let prev = d[j - 1];
                for (x, q) in d[j].iter_mut().zip(prev) {
                    *x = (1.0 - alpha) * q + alpha * *x;
                }
            }
        }
        let w = d[p][2];
        [d[p][0] / w, d[p][1] / w]
    }
}

/// The points of a spline from its DXF fields: start included, each
/// straight piece within `tol` of the curve (checked at a quarter, half
/// and three quarters of it), at most `max_pieces` pieces.
pub(super) fn flatten(
    degree: i32,
    knots: &[f64],
    weights: &[f64],
    ctrl: &[[f64; 2]],
    tol: f64,
    max_pieces: usize,
) -> Result<Vec<P>, SplineProblem> {
    let bad = SplineProblem::Unusable;
    let p = usize::try_from(degree).map_err(|_| bad("has a negative degree"))?;
    if p == 0 || p > MAX_DEGREE {
        return Err(bad("has a degree other than 1 to 11"));
    }
    if ctrl.is_empty() {
        return Err(bad(
            "has fit points but no control points (save it from a CAD program that writes them)",
        ));
    }
    if ctrl.len() < p + 1 || knots.len() != ctrl.len() + p + 1 {
        return Err(bad("has knots that do not match its control points"));
    }
    if knots.iter().any(|k| !k.is_finite()) || knots.windows(2).any(|w| w[1] < w[0]) {
        return Err(bad("has knots that are not an ascending list of numbers"));
    }
    if !(weights.is_empty() || weights.len() == ctrl.len())
        || weights.iter().any(|w| !(w.is_finite() && *w > 0.0))
    {
        return Err(bad(
            "has weights that are not one positive number a control point",
        ));
    }
    if ctrl.iter().flatten().any(|c| !c.is_finite()) {
        return Err(bad("has a control point that is no number"));
    }
    let nurbs = Nurbs {
        degree: p,
        knots,
        ctrl: ctrl
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let w = weights.get(i).copied().unwrap_or(1.0);
                [c[0] * w, c[1] * w, w]
            })
            .collect(),
    };
    let n = ctrl.len() - 1;
    let mut out: Vec<P> = Vec::new();
    for k in p..=n {
        let (t0, t1) = (knots[k], knots[k + 1]);
        if t1 <= t0 {
            continue;
        }
        let (a, b) = (nurbs.at(t0, k), nurbs.at(t1, k));
        if out.is_empty() {
            out.push(a);
        }
        // Two halves at least: a span can start and end at one point.
        let tm = 0.5 * (t0 + t1);
        let m = nurbs.at(tm, k);
        for (s, e, ps, pe) in [(t0, tm, a, m), (tm, t1, m, b)] {
            subdivide(&nurbs, k, (s, ps), (e, pe), tol, 0, &mut out, max_pieces)?;
        }
    }
    if out.len() < 2 {
        return Err(bad("has no span of positive length"));
    }
    Ok(out)
}

/// Appends the points after `a` up to `b` of the curve between their
/// parameters, bisecting until each piece is within `tol`.
#[allow(clippy::too_many_arguments)] // one recursion's state, passed down as it is
fn subdivide(
    nurbs: &Nurbs,
    k: usize,
    a: (f64, P),
    b: (f64, P),
    tol: f64,
    depth: u32,
    out: &mut Vec<P>,
    max_pieces: usize,
) -> Result<(), SplineProblem> {
    let (ta, pa) = a;
    let (tb, pb) = b;
    let mid = 0.5 * (ta + tb);
    let pm = nurbs.at(mid, k);
    let flat = depth >= MAX_DEPTH
        || [0.25, 0.75]
            .iter()
            .map(|f| nurbs.at(ta + f * (tb - ta), k))
            .chain(std::iter::once(pm))
            .all(|q| {
                point_segment_dist2(v2(q[0], q[1]), v2(pa[0], pa[1]), v2(pb[0], pb[1])) <= tol * tol
            });
    if flat {
        if out.len() > max_pieces {
            return Err(SplineProblem::Limit(LimitExceeded {
                what: format!(
                    "a SPLINE flattened within the chord tolerance into more than {max_pieces} pieces"
                ),
                limit: max_pieces as u64,
                key: "spline_pieces",
            }));
        }
        out.push(pb);
        return Ok(());
    }
    subdivide(nurbs, k, a, (mid, pm), tol, depth + 1, out, max_pieces)?;
    subdivide(nurbs, k, (mid, pm), b, tol, depth + 1, out, max_pieces)
}

#[cfg(test)]
mod tests {
    use super::super::super::outline::dist;
    use super::*;

    #[test]
    fn a_rational_quadratic_is_a_circle_within_tolerance() {
        // A quarter circle of radius 10 as a rational quadratic Bezier:
        // weights 1, sqrt(2)/2, 1.
        let w = std::f64::consts::FRAC_1_SQRT_2;
        let pts = flatten(
            2,
            &[0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            &[1.0, w, 1.0],
            &[[10.0, 0.0], [10.0, 10.0], [0.0, 10.0]],
            0.01,
            1000,
        )
        .unwrap();
        assert_eq!(pts[0], [10.0, 0.0]);
        assert!(dist(pts[pts.len() - 1], [0.0, 10.0]) < 1e-12);
        for q in &pts {
            assert!((dist(*q, [0.0, 0.0]) - 10.0).abs() < 1e-9, "{q:?}");
        }
        for w in pts.windows(2) {
            let m = [(w[0][0] + w[1][0]) / 2.0, (w[0][1] + w[1][1]) / 2.0];
            assert!(10.0 - dist(m, [0.0, 0.0]) <= 0.01 + 1e-9);
        }
    }

    #[test]
    fn a_degree_one_spline_is_its_control_polygon() {
        let pts = flatten(
            1,
            &[0.0, 0.0, 1.0, 2.0, 2.0],
            &[],
            &[[0.0, 0.0], [5.0, 0.0], [5.0, 5.0]],
            0.1,
            100,
        )
        .unwrap();
        assert!(pts.iter().any(|p| dist(*p, [5.0, 0.0]) < 1e-12));
        assert!(dist(pts[pts.len() - 1], [5.0, 5.0]) < 1e-12);
    }

    #[test]
    fn broken_splines_and_the_piece_limit_are_reported() {
        let ctrl = [[0.0, 0.0], [5.0, 9.0], [9.0, -9.0], [14.0, 0.0]];
        let knots = [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        assert!(matches!(
            flatten(3, &knots[1..], &[], &ctrl, 0.1, 100),
            Err(SplineProblem::Unusable(_))
        ));
        assert!(matches!(
            flatten(3, &knots, &[], &[], 0.1, 100),
            Err(SplineProblem::Unusable(_))
        ));
        assert!(matches!(
            flatten(3, &knots, &[], &ctrl, 1e-9, 50),
            Err(SplineProblem::Limit(_))
        ));
        assert!(flatten(3, &knots, &[], &ctrl, 0.01, 10_000).is_ok());
    }
}
