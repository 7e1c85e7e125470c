//! Form closure of three locators plus one clamp contact (SPEC section 4),
//! and the exact interval of clamp contacts on a segment that completes it.

use crate::geometry::{cross, EPS, V2};
use nalgebra::{Matrix3, Vector3};

/// Planar contact wrench `(f.x, f.y, q x f)`.
#[inline]
pub fn wrench(q: V2, f: V2) -> Vector3<f64> {
    Vector3::new(f.x, f.y, cross(q, f))
}

/// The locator wrenches of a setup, ready to test clamp contacts.
#[derive(Debug, Clone, Copy)]
pub struct LocatorWrenches {
    /// `det W`: its size is a decision margin (borderline detection).
    pub det: f64,
    /// `-W^-1`.
    pub neg_inv: Matrix3<f64>,
}

impl LocatorWrenches {
    /// `None` when `|det W| <= eps`: no clamp can complete form closure.
    pub fn new(w: [Vector3<f64>; 3]) -> Option<Self> {
        let m = Matrix3::from_columns(&w);
        let det = m.determinant();
        if det.abs() <= EPS {
            return None;
        }
        let inv = m.try_inverse()?;
        Some(LocatorWrenches { det, neg_inv: -inv })
    }

    /// `lambda = -W^-1 w` for a clamp wrench `w`.
    #[inline]
    pub fn lambda(&self, w: &Vector3<f64>) -> Vector3<f64> {
        self.neg_inv * w
    }

    /// The open interval of contact parameters `s` on the line
    /// `q(s) = q0 + s dq` with inward normal `f` where every
    /// `lambda_i(s) > eps`, intersected with `(lo, hi)`.
    pub fn clamp_interval(&self, q0: V2, dq: V2, f: V2, lo: f64, hi: f64) -> Option<(f64, f64)> {
        // w(s) = w0 + s w1, both through -W^-1: lambda(s) = alpha + s beta.
        let alpha = self.lambda(&wrench(q0, f));
        let beta = self.neg_inv * Vector3::new(0.0, 0.0, cross(dq, f));
        let (mut lo, mut hi) = (lo, hi);
        for i in 0..3 {
            let (a, b) = (alpha[i], beta[i]);
            if b > 0.0 {
                lo = lo.max((EPS - a) / b);
            } else if b < 0.0 {
                hi = hi.min((EPS - a) / b);
            } else if a <= EPS {
                return None;
            }
        }
        (lo < hi).then_some((lo, hi))
    }
}

/// Independent check (no `W^-1`): the four wrenches positively span R^3 iff
/// the origin lies strictly inside their convex hull, i.e. strictly on the
/// inner side of each face of the tetrahedron they span.
pub fn positively_spanning(w: &[Vector3<f64>; 4], tol: f64) -> bool {
    let faces = [(1, 2, 3, 0), (0, 2, 3, 1), (0, 1, 3, 2), (0, 1, 2, 3)];
    for (i, j, k, opp) in faces {
        let normal = (w[j] - w[i]).cross(&(w[k] - w[i]));
        let side_opp = normal.dot(&(w[opp] - w[i]));
        let side_origin = normal.dot(&(-w[i]));
        if side_opp.abs() <= tol || side_origin * side_opp.signum() <= tol {
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v2;

    #[test]
    fn interval_matches_pointwise_lambda() {
        // Locators on a unit square's bottom, right and top sides.
        // With the clamp on the left at height s: lambda_2 = 1,
        // lambda_1 = lambda_3 = (0.3 - s) / 0.4.
        let ws = [
            wrench(v2(0.3, 0.0), v2(0.0, 1.0)),
            wrench(v2(1.0, 0.3), v2(-1.0, 0.0)),
            wrench(v2(0.7, 1.0), v2(0.0, -1.0)),
        ];
        let lw = LocatorWrenches::new(ws).unwrap();
        // Clamp along the left side x = 0 pushing +x, q(s) = (0, s).
        let (lo, hi) = lw
            .clamp_interval(v2(0., 0.), v2(0., 1.), v2(1., 0.), -10.0, 10.0)
            .unwrap();
        for k in 0..200 {
            let s = -2.0 + k as f64 * 0.02;
            let l = lw.lambda(&wrench(v2(0., s), v2(1., 0.)));
            let inside = l.iter().all(|&x| x > EPS);
            if s > lo + 1e-9 && s < hi - 1e-9 {
                assert!(inside, "s = {s}, {l}");
                let w4 = wrench(v2(0., s), v2(1., 0.));
                assert!(positively_spanning(&[ws[0], ws[1], ws[2], w4], 0.0));
            } else if s < lo - 1e-9 || s > hi + 1e-9 {
                assert!(!inside, "s = {s}, {l}");
            }
        }
        // lambda_1 = (0.3 - s) / 0.4: the clamp must be below y = 0.3.
        assert!(lo == -10.0 && (hi - 0.3).abs() < 1e-6, "({lo}, {hi})");
    }

    #[test]
    fn singular_setup_is_rejected() {
        let ws = [
            wrench(v2(0.0, 0.0), v2(0.0, 1.0)),
            wrench(v2(1.0, 0.0), v2(0.0, 1.0)),
            wrench(v2(2.0, 0.0), v2(0.0, 1.0)),
        ];
        assert!(LocatorWrenches::new(ws).is_none());
    }
}
