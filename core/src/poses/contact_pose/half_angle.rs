//! The roots of a trigonometric polynomial of degree at most 2 without
//! subdivision: two locators on lines leave an eliminant of that degree
//! (`two_lines`), and for it the general root search of `root_search` (Taylor
//! bounds on sixteen intervals, then splitting) costs far more than the
//! answer needs.
//!
//! Each half turn is mapped onto `t` in `[-1, 1]` by the half-angle
//! substitution, `theta = theta0 + 2 atan(t)` with `theta0` `0` or `pi`,
//! and `(1 + t^2)^2 F` is then a real quartic `P(t)`: the factor lies in
//! `[1, 4]`, so `P` and `F` have the same roots and near misses, and
//! keeping `|t| <= 1` keeps the substitution well conditioned (no root
//! runs off to infinity). The real roots of `P` are isolated through its
//! derivatives: the inflections (roots of the quadratic `P''`) in closed
//! form cut `[-1, 1]` into pieces on which `P'` is monotone, so each holds
//! at most one critical point; the critical points cut it into pieces on
//! which `P` is monotone, so each holds at most one root, found by a
//! bracketed Newton iteration. Why nothing is missed: a piece without a
//! sign change at its ends has no root, as `P` is monotone on it; rounding
//! can only misplace a critical point by a few ulps, where `P` is at its
//! extremum, and every extremum with `|P|` within the near-miss band is
//! passed on as a candidate (a tangency, or a near miss that the caller's
//! residual test decides), as `root_search::roots` does.

use super::trig::{bracketed_root, Angles, Trig, Within};
use crate::geometry::angle_set::rem_tau;
use std::f64::consts::{FRAC_PI_2, PI};

/// `P`, `P'` and `P''` at `t` (coefficients in ascending powers).
fn eval(p: &[f64; 5], t: f64) -> (f64, f64, f64) {
    let v = (((p[4] * t + p[3]) * t + p[2]) * t + p[1]) * t + p[0];
    let d1 = ((4.0 * p[4] * t + 3.0 * p[3]) * t + 2.0 * p[2]) * t + p[1];
    let d2 = (12.0 * p[4] * t + 6.0 * p[3]) * t + 2.0 * p[2];
    (v, d1, d2)
}

/// `(1 + t^2)^2 F(theta0 + 2 atan t)`, with `flip` for `theta0 = pi`
/// (which negates the first harmonic and keeps the second): with
/// `cos = (1 - t^2) / (1 + t^2)`, `sin = 2t / (1 + t^2)` and the double
/// angle formulas, every term is a polynomial of degree <= 4 in `t`.
fn quartic(f: &Trig, flip: bool) -> [f64; 5] {
    let sign = if flip { -1.0 } else { 1.0 };
    let (f0, c1, s1, c2, s2) = (f.a[0], sign * f.a[1], sign * f.b[1], f.a[2], f.b[2]);
    [
        f0 + c1 + c2,
        2.0 * s1 + 4.0 * s2,
        2.0 * f0 - 6.0 * c2,
        2.0 * s1 - 4.0 * s2,
        f0 - c1 + c2,
    ]
}

/// The real roots of `a t^2 + b t + c` strictly inside `(-1, 1)`, sorted,
/// by the cancellation-free form of the quadratic formula.
fn quadratic_roots(a: f64, b: f64, c: f64) -> ([f64; 2], usize) {
    let mut out = [0.0; 2];
    let mut n = 0;
    let mut keep = |t: f64| {
        if t.is_finite() && t > -1.0 && t < 1.0 {
            out[n] = t;
            n += 1;
        }
    };
    if a == 0.0 {
        if b != 0.0 {
            keep(-c / b);
        }
    } else {
        let disc = b * b - 4.0 * a * c;
        if disc >= 0.0 {
            let q = -0.5 * (b + disc.sqrt().copysign(b));
            if q != 0.0 {
                keep(q / a);
                keep(c / q);
            } else {
                keep(0.0);
            }
        }
    }
    if n == 2 && out[0] > out[1] {
        out.swap(0, 1);
    }
    (out, n)
}

/// Points of `[-1, 1]`, in increasing order, at most six.
struct Cuts {
    v: [f64; 6],
    n: usize,
}

impl Cuts {
    fn new() -> Cuts {
        Cuts {
            v: [-1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            n: 1,
        }
    }

    /// Appends `t` unless it does not lie beyond the last point.
    fn push(&mut self, t: f64) {
        if self.n < self.v.len() && t > self.v[self.n - 1] {
            self.v[self.n] = t;
            self.n += 1;
        }
    }

    fn as_slice(&self) -> &[f64] {
        &self.v[..self.n]
    }
}

/// The critical points of `P` in `(-1, 1)` as cuts (with `-1` and `1`):
/// one per monotone piece of `P'` whose ends differ in sign, and every
/// inflection where `|P'|` is within `noise1` of zero (a critical point
/// rounding could hide; an extra cut never hurts).
fn critical_cuts(p: &[f64; 5], noise1: f64) -> Cuts {
    let (inflections, k) = quadratic_roots(12.0 * p[4], 6.0 * p[3], 2.0 * p[2]);
    let mut pieces = Cuts::new();
    for &t in &inflections[..k] {
        pieces.push(t);
    }
    pieces.push(1.0);
    let slope = |t: f64| {
        let (_, d1, d2) = eval(p, t);
        (d1, d2)
    };
    let mut cuts = Cuts::new();
    let ends = pieces.as_slice();
    for (i, w) in ends.windows(2).enumerate() {
        let (lo, hi) = (w[0], w[1]);
        let (dlo, dhi) = (slope(lo).0, slope(hi).0);
        if i > 0 && dlo.abs() <= noise1 {
            cuts.push(lo);
        }
        if dlo != 0.0 && dhi != 0.0 && (dlo < 0.0) != (dhi < 0.0) {
            cuts.push(bracketed_root(slope, lo, hi, dlo));
        }
    }
    cuts.push(1.0);
    cuts
}

/// Every root of `P` in `[-1, 1]`, and every interior extremum with
/// `|P| <= tol` that has no root beside it, mapped to `theta0 + 2 atan t`
/// and pushed onto `out` if `within` wants it.
fn quartic_angles(
    p: &[f64; 5],
    theta0: f64,
    (tol, noise1): (f64, f64),
    within: &Within,
    out: &mut Angles,
) {
    let cuts = critical_cuts(p, noise1);
    let value = |t: f64| {
        let (v, d1, _) = eval(p, t);
        (v, d1)
    };
    let mut push = |t: f64| {
        let theta = rem_tau(theta0 + 2.0 * t.atan());
        if within(theta - ANGLE_SLACK, theta + ANGLE_SLACK) {
            out.push(theta);
        }
    };
    let ends = cuts.as_slice();
    let mut root_before = false;
    for (i, w) in ends.windows(2).enumerate() {
        let (lo, hi) = (w[0], w[1]);
        let (vlo, vhi) = (value(lo).0, value(hi).0);
        let root = if vlo == 0.0 {
            push(lo);
            true
        } else if vhi == 0.0 {
            push(hi);
            true
        } else if (vlo < 0.0) != (vhi < 0.0) {
            push(bracketed_root(value, lo, hi, vlo));
            true
        } else {
            false
        };
        // The ends of the half turn are extrema too as far as this half
        // knows (the other half may go on either way).
        let extremum_alone = (i == 0 || !root_before) && !root;
        if extremum_alone && vlo.abs() <= tol {
            push(lo);
        }
        if i + 2 == ends.len() && !root && vhi.abs() <= tol {
            push(hi);
        }
        root_before = root;
    }
}

/// Roots pushed are checked against `within` over this much either side,
/// far above their rounding and far below any angle band's width.
const ANGLE_SLACK: f64 = 1e-6;

/// Every root of `f` (degree <= 2: harmonics 3 and 4 are ignored, rounding
/// noise for the callers) in `[0, 2 pi)` that `within` wants, plus every
/// local extremum with `|f| <= tol` and no root beside it (tangencies and
/// near misses), pushed onto `out`; `noise` bounds the error of the
/// coefficients, as for `root_search::roots`.
pub(super) fn roots(f: &Trig, tol: f64, noise: f64, within: &Within, out: &mut Angles) {
    roots_of_halves(f, (tol, noise), within, out, true);
}

/// A half turn's angles `theta0 + 2 atan t` (`|t| <= 1`) lie within a
/// quarter turn of `theta0`, and each is pushed only if `within` wants
/// some angle `ANGLE_SLACK` either side of it: all of them lie in the
/// quarter turns either side widened by this, a margin far above their
/// rounding.
const HALF_REACH: f64 = FRAC_PI_2 + 1e-3;

/// [`roots`], with `skip`: a half turn none of whose angles `within`
/// wants is not searched. It would push nothing: every angle it pushes is
/// one `within` wants (to `ANGLE_SLACK`), and a `within` that wants none
/// in a stretch wants none in a part of it (as an angle set's `meets`
/// does), so the output is the same to the bit. The setup sweep's angles
/// (where both line contacts stay on their segments) are mostly a narrow
/// band, so one half turn of many calls is skipped. The tests compare
/// with `skip` off.
fn roots_of_halves(
    f: &Trig,
    (tol, noise): (f64, f64),
    within: &Within,
    out: &mut Angles,
    skip: bool,
) {
    // P = (1 + t^2)^2 F with the factor at most 4 on |t| <= 1; evaluating
    // the quartic adds a few ulps of the sum of its coefficients'
    // magnitudes, which is at most 16 times that of F's.
    let mag = f.a[0].abs() + f.a[1].abs() + f.b[1].abs() + f.a[2].abs() + f.b[2].abs();
    let noise = 4.0 * noise + 64.0 * 16.0 * f64::EPSILON * mag;
    let band = (4.0 * tol + noise, 20.0 * noise);
    for (theta0, flip) in [(0.0, false), (PI, true)] {
        if !skip || within(theta0 - HALF_REACH, theta0 + HALF_REACH) {
            quartic_angles(&quartic(f, flip), theta0, band, within, out);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::angle_set::wrap_angle;
    use crate::poses::contact_pose::trig::circ_dist;
    use std::f64::consts::TAU;

    fn found(f: &Trig, tol: f64) -> Vec<f64> {
        let mut out = Angles::new();
        roots(f, tol, 0.0, &|_, _| true, &mut out);
        assert!(!out.overflow);
        out.as_slice().to_vec()
    }

    fn value(f: &Trig, theta: f64) -> f64 {
        f.a[0]
            + (1..=2)
                .map(|j| {
                    let (s, c) = (j as f64 * theta).sin_cos();
                    f.a[j] * c + f.b[j] * s
                })
                .sum::<f64>()
    }

    #[test]
    fn quartic_is_the_polynomial_times_the_factor() {
        let f = Trig {
            a: [0.3, -1.2, 0.7, 0.0, 0.0],
            b: [0.0, 0.4, -0.9, 0.0, 0.0],
        };
        for (theta0, flip) in [(0.0, false), (PI, true)] {
            let p = quartic(&f, flip);
            for t in [-1.0, -0.6, 0.0, 0.25, 1.0] {
                let want = (1.0 + t * t) * (1.0 + t * t) * value(&f, theta0 + 2.0 * f64::atan(t));
                assert!((eval(&p, t).0 - want).abs() < 1e-13, "{t}");
            }
        }
    }

    /// Four roots at chosen angles, including the ends of the half turns
    /// (`pi / 2`, `3 pi / 2`) and `0`: `cos(2 (t - u)) - cos(2 v)` has
    /// roots at `u +- v` and `u + pi +- v`.
    #[test]
    fn roots_at_chosen_angles_and_half_turn_ends() {
        for (u, v) in [(0.3, 0.2), (0.0, PI / 4.0), (PI / 2.0, 0.5), (1.0, 0.0001)] {
            let (s, c) = (2.0 * u).sin_cos();
            let f = Trig {
                a: [-(2.0 * v).cos(), 0.0, c, 0.0, 0.0],
                b: [0.0, 0.0, s, 0.0, 0.0],
            };
            let r = found(&f, 0.0);
            for want in [u + v, u - v, u + PI + v, u + PI - v].map(wrap_angle) {
                assert!(
                    r.iter().any(|&t| circ_dist(t, want) < 1e-12),
                    "{u} {v}: {want} not in {r:?}"
                );
            }
            assert_eq!(r.len(), 4, "{u} {v}: {r:?}");
        }
    }

    #[test]
    fn double_roots_are_candidates() {
        // 1 - cos(t - u): a double root at u, for u anywhere, the ends of
        // the half turns included.
        for u in [0.0, 1.0, PI / 2.0, PI, 4.0, 3.0 * PI / 2.0] {
            let f = Trig {
                a: [1.0, -f64::cos(u), 0.0, 0.0, 0.0],
                b: [0.0, -f64::sin(u), 0.0, 0.0, 0.0],
            };
            let r = found(&f, 1e-12);
            assert!(!r.is_empty(), "{u}");
            assert!(r.iter().all(|&t| circ_dist(t, u) < 1e-7), "{u}: {r:?}");
        }
        // A clear miss: nothing.
        let f = Trig {
            a: [1.0 + 1e-6, -1.0, 0.0, 0.0, 0.0],
            b: [0.0; 5],
        };
        assert!(found(&f, 1e-12).is_empty());
    }

    /// A trigonometric polynomial of degree 2 with coefficients in `[-1, 1]`.
    fn random_quadratic(rng: &mut crate::test_rng::Xorshift) -> Trig {
        let mut f = Trig::default();
        f.a[0] = rng.signed_unit();
        for j in 1..=2 {
            f.a[j] = rng.signed_unit();
            f.b[j] = rng.signed_unit();
        }
        f
    }

    /// Skipping the half turns `within` rejects changes nothing: random
    /// polynomials of degree 2 (some with double roots) and angle sets
    /// (one or two sinusoid bands, as the setup sweep builds them, turned
    /// by quarter turns as `Allowed::meets` turns them), the same angles
    /// to the bit with and without skipping.
    #[test]
    fn skipping_rejected_half_turns_changes_nothing() {
        use crate::geometry::angle_set::AngleSet;
        let mut rng = crate::test_rng::Xorshift::new(0x2f8c_51d3_a9e0_7b41);
        let mut skipped = 0;
        for case in 0..4000 {
            let mut f = random_quadratic(&mut rng);
            if case % 4 == 0 {
                // 1 - cos(t - u): a double root, the tangency case.
                let u = 4.0 * rng.signed_unit();
                f = Trig {
                    a: [1.0, -u.cos(), 0.0, 0.0, 0.0],
                    b: [0.0, -u.sin(), 0.0, 0.0, 0.0],
                };
            }
            let mut band = || {
                let (alpha, amp) = (rng.signed_unit(), rng.signed_unit().abs());
                let (lo, phi) = (rng.signed_unit(), 4.0 * rng.signed_unit());
                let hi = lo + rng.signed_unit().abs();
                AngleSet::sinusoid_band(alpha, amp, phi, lo, hi, 1e-6)
            };
            let mut set = band();
            if case % 3 == 0 {
                set = set.intersect(&band());
            }
            let back = f64::from((case % 4) as u8) * FRAC_PI_2;
            let within = |lo: f64, hi: f64| set.meets(lo - back, hi - back);
            let (tol, noise) = (1e-12, 1e-15);
            let (mut got, mut want) = (Angles::new(), Angles::new());
            roots_of_halves(&f, (tol, noise), &within, &mut got, true);
            roots_of_halves(&f, (tol, noise), &within, &mut want, false);
            let bits = |a: &Angles| a.as_slice().iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&got), bits(&want), "{f:?} {set:?} {back}");
            skipped += usize::from(!within(-HALF_REACH, HALF_REACH))
                + usize::from(!within(PI - HALF_REACH, PI + HALF_REACH));
        }
        assert!(skipped > 1000, "{skipped}");
    }

    /// Against the general certified search on random polynomials of
    /// degree 2: the same roots.
    #[test]
    fn agrees_with_the_general_search() {
        let mut rng = crate::test_rng::Xorshift::new(0x5851_f42d_4c95_7f2d);
        for _ in 0..3000 {
            let f = random_quadratic(&mut rng);
            let mine = found(&f, 1e-13);
            let mut general = Angles::new();
            super::super::root_search::roots(&f, 1e-13, 0.0, &|_, _| true, &mut general);
            for &t in general.as_slice() {
                if value(&f, t).abs() < 1e-12 {
                    assert!(
                        mine.iter().any(|&u| circ_dist(u, t) < 1e-7),
                        "{f:?}: {t} missed, {mine:?}"
                    );
                }
            }
            for &t in &mine {
                assert!(value(&f, t).abs() < 1e-12, "{f:?}: {t}");
                assert!((0.0..TAU).contains(&t));
            }
        }
    }
}
