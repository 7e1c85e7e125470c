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
        // `-W^-1 (0, 0, dq x f)`: the last column times `dq x f`. The
        // product's other terms are zeros (the entries are finite), which
        // change at most the sign of a zero `b`, read below as a zero.
        let tau = cross(dq, f);
        let m = &self.neg_inv;
        let beta = [m[(0, 2)] * tau, m[(1, 2)] * tau, m[(2, 2)] * tau];
        interval_above_eps(&alpha, beta, lo, hi)
    }
}

/// The open interval of `s` in `(lo, hi)` where every `alpha_i + s beta_i`
/// is above `eps`: each coefficient bounds `s` from one side by the sign
/// of `beta_i`, and a zero `beta_i` (of either sign) keeps all of it or
/// none.
#[inline(always)]
fn interval_above_eps(
    alpha: &Vector3<f64>,
    beta: [f64; 3],
    lo: f64,
    hi: f64,
) -> Option<(f64, f64)> {
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

/// How far, relative to the sizes involved, rounding can carry the
/// computed `lambda` of a clamp contact from its exact value: a few
/// units in the last place in the analysis of [`ForceCone`], taken a
/// couple of hundred times over.
const CONE_ROUNDING: f64 = 1e-13;

/// An absolute allowance for underflow (products of tiny entries).
const CONE_UNDERFLOW: f64 = 1e-280;

/// The clamp forces that can complete form closure with one setup's
/// locators, as at most two half-planes of force directions: a test of
/// the force alone, before any position, so that a setup can drop at
/// once the segments whose normals no position along them could make a
/// clamp force of, before solving their intervals.
///
/// With `M = -W^-1` (rows `A_i | b_i`, `A_i` the force columns), a clamp
/// contact's `lambda_i = A_i . f + b_i tau` where `tau = q x f`. Two
/// rows `p`, `m` with `b_p > 0 > b_m` both exceed `eps` at some `tau`
/// only if `D(f) = (b_p A_m - b_m A_p) . f > eps (b_p - b_m)`: scaling
/// them by `-b_m` and `b_p` and adding cancels `tau`. Rounding moves the
/// computed `lambda` by at most a few ulps of `|A_i|_1 + |b_i| |tau|`
/// (and of `eps`), so [`LocatorWrenches::clamp_interval`] and
/// [`LocatorWrenches::lambda`] (`> eps`) can only accept a force with
/// `D(f)` above that bound less the allowance scaled by `|b_p|`,
/// `|b_m|`: the cone excludes a force only below it. Rows of one sign
/// give no side: a large `|tau|` lifts them all.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ForceCone {
    sides: [ConeSide; 2],
}

/// One half-plane of a [`ForceCone`]: `D(f) = g . f` must not fall below
/// `-(slack + per_reach * reach)`, `reach` bounding `|tau|`.
#[derive(Debug, Clone, Copy)]
struct ConeSide {
    gx: f64,
    gy: f64,
    slack: f64,
    per_reach: f64,
}

impl ConeSide {
    /// No condition.
    const OPEN: ConeSide = ConeSide {
        gx: 0.0,
        gy: 0.0,
        slack: f64::INFINITY,
        per_reach: 0.0,
    };

    /// The side of rows `p` (`b_p > 0`) and `m` (`b_m < 0`) of `M`.
    fn of(neg_inv: &Matrix3<f64>, p: usize, m: usize) -> ConeSide {
        let row = |i: usize| (neg_inv[(i, 0)], neg_inv[(i, 1)], neg_inv[(i, 2)]);
        let ((px, py, bp), (mx, my, bm)) = (row(p), row(m));
        let (bp, bm) = (bp.abs(), bm.abs());
        let (ap, am) = (px.abs() + py.abs(), mx.abs() + my.abs());
        ConeSide {
            // b_p A_m - b_m A_p with b_m = -|b_m|.
            gx: bp * mx + bm * px,
            gy: bp * my + bm * py,
            // The rounding allowance, less the `eps` every `lambda` must
            // exceed: forces on the cone's edge (`D = 0`, a clamp pushing
            // straight against locators on a parallel edge) are excluded.
            slack: CONE_ROUNDING * (bm * (EPS + ap) + bp * (EPS + am)) + CONE_UNDERFLOW
                - EPS * (bp + bm),
            per_reach: 2.0 * CONE_ROUNDING * bp * bm + CONE_UNDERFLOW,
        }
    }

    /// Whether force `f` is below this side, `reach` bounding `|tau|`.
    #[inline(always)]
    fn excludes(&self, f: V2, reach: f64) -> bool {
        self.gx * f.x + self.gy * f.y < -(self.slack + self.per_reach * reach)
    }
}

impl ForceCone {
    /// No condition: every force passes (the search without its filters).
    pub(crate) fn open() -> ForceCone {
        ForceCone {
            sides: [ConeSide::OPEN; 2],
        }
    }

    /// The cone for normals `n` of a part posed with rotation `(cos, sin)`,
    /// in the part frame: `excludes(n)` is `excludes(f)` for the posed
    /// inward normal `f = -R n`, since `g . f = (-R^T g) . n`. The two
    /// computed products differ by a few ulps of `|g|_1`, at most
    /// `b_p |A_m|_1 + |b_m| |A_p|_1`, which the allowance covers many
    /// times over. A line segment is then tested before its normal is
    /// posed.
    pub(crate) fn unposed(&self, cos: f64, sin: f64) -> ForceCone {
        ForceCone {
            sides: self.sides.map(|s| ConeSide {
                // -R^T g.
                gx: -(cos * s.gx + sin * s.gy),
                gy: -(cos * s.gy - sin * s.gx),
                ..s
            }),
        }
    }

    /// Whether no contact whose normal `f` has `f . mid >= cos` (`mid` a
    /// unit vector, `cos >= 0`: a cap of at most a quarter turn either
    /// side) and whose `|tau|` is at most `reach` is in form closure:
    /// then [`LocatorWrenches::lambda`] of every such contact has a
    /// component at most `eps`. On the cap `f` is `mid cos(phi) +
    /// mid_perp sin(phi)`, `|phi| <= acos(cos)`: where `g . mid < 0` a
    /// maximum of `g . f` inside would have `g . mid > 0`, so `g . f` is
    /// largest at an edge, `g . mid cos + |g . mid_perp| sin`. The
    /// allowance covers the rounding of those products and `f`'s length.
    #[inline]
    pub(crate) fn excludes_cap(&self, mid: V2, cos: f64, reach: f64) -> bool {
        if cos.is_nan() || cos < 0.0 {
            return false;
        }
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        self.sides.iter().any(|s| {
            let along = s.gx * mid.x + s.gy * mid.y;
            let across = s.gx * mid.y - s.gy * mid.x;
            let limit = -(s.slack + s.per_reach * reach);
            let rounding = 1e-14 * (s.gx.abs() + s.gy.abs() + limit.abs());
            along < 0.0 && along * cos + across.abs() * sin < limit - rounding
        })
    }

    /// Whether no contact with inward normal `f` (a unit vector) and
    /// `|tau|` at most `reach` is in form closure. On the line `q0 + s dq`,
    /// `s` in `(lo, hi)`, `reach` at least `|q0|_1 + |dq|_1 max(|lo|, |hi|)`:
    /// then [`LocatorWrenches::clamp_interval`] is `None` (its computed
    /// bounds are within rounding of the exact ones: an `s` between them
    /// has every exact `lambda` above `eps` less a few ulps), and
    /// [`LocatorWrenches::lambda`] has a component at most `eps` at every
    /// contact on it.
    #[inline]
    pub(crate) fn excludes(&self, f: V2, reach: f64) -> bool {
        self.sides.iter().any(|side| side.excludes(f, reach))
    }
}

impl LocatorWrenches {
    /// The setup's [`ForceCone`].
    pub(crate) fn force_cone(&self) -> ForceCone {
        let m = &self.neg_inv;
        let mut sides = [ConeSide::OPEN; 2];
        let mut taken = 0;
        for (i, j) in [(0, 1), (0, 2), (1, 2)] {
            let (bi, bj) = (m[(i, 2)], m[(j, 2)]);
            let side = if bi > 0.0 && bj < 0.0 {
                ConeSide::of(m, i, j)
            } else if bi < 0.0 && bj > 0.0 {
                ConeSide::of(m, j, i)
            } else {
                continue;
            };
            // Three numbers of two signs make at most two such pairs.
            if let Some(slot) = sides.get_mut(taken) {
                *slot = side;
                taken += 1;
            }
        }
        ForceCone { sides }
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
    use crate::geometry::{rot, rot_t, v2};
    use std::f64::consts::PI;

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

    /// Unit vector at angle `a`.
    fn unit(a: f64) -> V2 {
        v2(a.cos(), a.sin())
    }

    /// Locator wrenches from angles and points in `[-1, 1]`, scaled by
    /// `size`: with `pinch` the second normal is within `10^-pinch` rad
    /// of the first, and the third contact's line of action nearly
    /// through the others' crossing (W nearly singular).
    fn locators(angles: [f64; 3], points: [f64; 6], size: f64, pinch: Option<f64>) -> [V2; 6] {
        let mut n = angles.map(|a| unit(a * PI));
        let mut q = [0, 1, 2].map(|k| v2(points[2 * k], points[2 * k + 1]) * size);
        if let Some(exp) = pinch {
            n[1] = unit(angles[0] * PI + 10f64.powf(-exp) * angles[1]);
            // Through where the first two lines of action (nearly) cross.
            let tilt = 10f64.powf(-exp) * angles[2];
            q[2] = q[0] + v2(-n[2].y, n[2].x) * (points[4] * size) + n[2] * tilt;
        }
        [q[0], q[1], q[2], n[0], n[1], n[2]]
    }

    /// A force direction: at `angle`, or (`near` = Some(side, exp)) within
    /// `10^-exp` rad of an edge of that side of the cone (where it
    /// excludes forces along a line through the origin).
    fn clamp_force(cone: &ForceCone, angle: f64, near: Option<(usize, f64)>) -> V2 {
        match near {
            Some((side, exp)) => {
                let s = cone.sides[side];
                let size = s.gx.hypot(s.gy);
                let edge = (-s.slack / size).clamp(-1.0, 1.0).acos();
                let boundary = s.gy.atan2(s.gx) + edge * angle.signum();
                // Either way off the edge, whichever edge.
                unit(boundary + 10f64.powf(-exp) * (2.0 * angle.abs() - 1.0))
            }
            None => unit(angle * PI),
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(20_000))]

        /// The cone excludes only forces `clamp_interval` (and the
        /// pointwise `lambda > eps` test) reject, with the same inputs:
        /// random locators (some with W nearly singular), line segments
        /// along or across the force, forces at random or a hair from
        /// either edge of the cone, positions up to 1e4 from the origin;
        /// and the same cone unposed, for the part's normal of the force.
        #[test]
        fn force_cone_excludes_only_what_the_exact_tests_reject(
            angles in proptest::array::uniform3(-1.0f64..1.0),
            points in proptest::array::uniform6(-1.0f64..1.0),
            size_exp in -1.0f64..3.0,
            pinch in proptest::option::weighted(0.3, 2.0f64..12.0),
            force_angle in -1.0f64..1.0,
            near in proptest::option::weighted(0.7, (0usize..2, 1.0f64..16.0)),
            along_force in proptest::bool::ANY,
            line in proptest::array::uniform5(-1.0f64..1.0),
            reach_exp in -1.0f64..4.0,
            theta in -PI..PI,
        ) {
            let size = 10f64.powf(size_exp);
            let [q1, q2, q3, n1, n2, n3] = locators(angles, points, size, pinch);
            let Some(lw) = LocatorWrenches::new([wrench(q1, n1), wrench(q2, n2), wrench(q3, n3)]) else {
                return Ok(());
            };
            let cone = lw.force_cone();
            // The force as the clamp search poses a part's normal `n`.
            let (cos, sin) = (theta.cos(), theta.sin());
            let n = -rot_t(cos, sin, clamp_force(&cone, force_angle, near));
            let f = -rot(cos, sin, n);
            // A line segment's normal is across it; the interval takes any.
            let dq = if along_force { v2(-f.y, f.x) } else { unit(line[0] * PI) };
            let reach = 10f64.powf(reach_exp);
            let q0 = v2(line[1], line[2]) * reach;
            let (lo, hi) = (line[3].min(line[4]) * reach, line[3].max(line[4]) * reach);
            let reach = q0.x.abs() + q0.y.abs() + (dq.x.abs() + dq.y.abs()) * lo.abs().max(hi.abs());
            let part_frame = cone.unposed(cos, sin).excludes(n, reach);
            if cone.excludes(f, reach) || part_frame {
                proptest::prop_assert_eq!(lw.clamp_interval(q0, dq, f, lo, hi), None);
                for s in [lo, hi, 0.5 * (lo + hi)] {
                    let lam = lw.lambda(&wrench(q0 + dq * s, f));
                    proptest::prop_assert!(lam.min() <= EPS, "{lam}");
                }
            }
        }
    }

    /// The cone is not empty-handed: over random setups and forces it
    /// excludes most of what the interval rejects, and near its edges
    /// it keeps forces the interval accepts.
    #[test]
    fn force_cone_excludes_most_rejected_forces() {
        let mut rng = crate::test_rng::Xorshift::new(0x3c6e_f372_fe94_f82b);
        let (mut rejected, mut excluded, mut kept_near) = (0u64, 0u64, 0u64);
        for case in 0..20_000 {
            let mut r = || rng.signed_unit();
            let angles = [r(), r(), r()];
            let points = [r(), r(), r(), r(), r(), r()];
            let [q1, q2, q3, n1, n2, n3] = locators(angles, points, 50.0, None);
            let Some(lw) = LocatorWrenches::new([wrench(q1, n1), wrench(q2, n2), wrench(q3, n3)])
            else {
                continue;
            };
            let cone = lw.force_cone();
            let near = (case % 2 == 0).then_some((case / 2 % 2, 12.0));
            let f = clamp_force(&cone, r(), near);
            let dq = v2(-f.y, f.x);
            let (q0, lo, hi) = (v2(r(), r()) * 50.0, -1e4, 1e4);
            let interval = lw.clamp_interval(q0, dq, f, lo, hi);
            if cone.excludes(f, q0.x.abs() + q0.y.abs() + 1.5 * hi) {
                excluded += 1;
            }
            rejected += u64::from(interval.is_none());
            kept_near += u64::from(near.is_some() && interval.is_some());
        }
        assert!(excluded * 2 > rejected, "{excluded} of {rejected}");
        assert!(kept_near > 1000, "{kept_near}");
    }

    /// [`LocatorWrenches::clamp_interval`] as first written, `beta`
    /// through the whole product `-W^-1 (0, 0, dq x f)`: the reference
    /// the last column's product must equal.
    fn interval_by_whole_product(
        lw: &LocatorWrenches,
        q0: V2,
        dq: V2,
        f: V2,
        lo: f64,
        hi: f64,
    ) -> Option<(f64, f64)> {
        let alpha = lw.lambda(&wrench(q0, f));
        let beta = lw.neg_inv * Vector3::new(0.0, 0.0, cross(dq, f));
        interval_above_eps(&alpha, [beta[0], beta[1], beta[2]], lo, hi)
    }

    /// The interval is the whole product's bit for bit: random locators
    /// (some with W nearly singular), lines at random, along the force
    /// (`dq x f` zero or tiny) and on the axes (zero coordinates).
    #[test]
    fn interval_equals_the_whole_products() {
        let mut rng = crate::test_rng::Xorshift::new(0x510e_527f_ade6_82d1);
        let (mut some, mut none) = (0u64, 0u64);
        for case in 0..50_000 {
            let mut r = || rng.signed_unit();
            let angles = [r(), r(), r()];
            let points = [r(), r(), r(), r(), r(), r()];
            let pinch = (case % 5 == 0).then_some(2.0 + 10.0 * r().abs());
            let [q1, q2, q3, n1, n2, n3] = locators(angles, points, 50.0, pinch);
            let Some(lw) = LocatorWrenches::new([wrench(q1, n1), wrench(q2, n2), wrench(q3, n3)])
            else {
                continue;
            };
            let f = match case % 3 {
                0 => unit(r() * PI),
                _ => [v2(1.0, 0.0), v2(0.0, -1.0), v2(-1.0, 0.0), v2(0.0, 1.0)][case % 4],
            };
            let dq = match case % 4 {
                0 => f,
                1 => unit(f.y.atan2(f.x) + 1e-12 * r()),
                _ => unit(r() * PI),
            };
            let q0 = v2(r(), r()) * 50.0;
            let (a, b) = (r() * 100.0, r() * 100.0);
            let (lo, hi) = (a.min(b), a.max(b));
            let got = lw.clamp_interval(q0, dq, f, lo, hi);
            let want = interval_by_whole_product(&lw, q0, dq, f, lo, hi);
            let bits = |i: Option<(f64, f64)>| i.map(|(l, h)| (l.to_bits(), h.to_bits()));
            assert_eq!(bits(got), bits(want), "case {case}");
            some += u64::from(got.is_some());
            none += u64::from(got.is_none());
        }
        assert!(some > 5_000 && none > 5_000, "{some} {none}");
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
