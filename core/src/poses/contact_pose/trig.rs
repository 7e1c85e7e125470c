//! Real trigonometric polynomials of degree at most 4 and a root finder that
//! proves every interval it discards root-free.
//!
//! The pose solver reduces three contact equations to one such polynomial in
//! `theta`. Companion-matrix eigenvalues would do too, but nalgebra's Schur
//! iteration has no exceptional shifts (it can stall on the very symmetric
//! polynomials rectilinear parts produce) and a double root comes back as a
//! complex pair whose distance from the unit circle needs its own threshold.
//! Subdivision with Taylor bounds has neither problem, reports the near-zero
//! minimum of a near-tangent configuration directly, and allocates nothing.
//!
//! The root search itself is in `root_search` (with `classify` and
//! `taylor5`, the bounds it decides intervals with); this file keeps the
//! polynomial (samples, harmonics, bounds, evaluation) and the small pieces
//! the other solvers share (the angle list, the bracketed polisher).

use crate::geometry::angle_set::rem_tau;
use std::f64::consts::{FRAC_1_SQRT_2, TAU};

/// Highest harmonic kept: the eliminant of SPEC 8.4 has degree <= 4.
pub(super) const DEG: usize = 4;

/// Samples per turn; 16 > 2 * DEG, so harmonics up to 7 do not alias.
pub(super) const SAMPLES: usize = 16;

const C8: f64 = 0.923_879_532_511_286_7; // cos(pi / 8)
const S8: f64 = 0.382_683_432_365_089_8; // sin(pi / 8)

/// `cos(2 pi m / 16)`, exact to the last bit so that the samples and the
/// transform use the same angles.
pub(super) const COS16: [f64; SAMPLES] = [
    1.0,
    C8,
    FRAC_1_SQRT_2,
    S8,
    0.0,
    -S8,
    -FRAC_1_SQRT_2,
    -C8,
    -1.0,
    -C8,
    -FRAC_1_SQRT_2,
    -S8,
    0.0,
    S8,
    FRAC_1_SQRT_2,
    C8,
];

/// `sin(2 pi m / 16)`.
pub(super) const SIN16: [f64; SAMPLES] = [
    0.0,
    S8,
    FRAC_1_SQRT_2,
    C8,
    1.0,
    C8,
    FRAC_1_SQRT_2,
    S8,
    0.0,
    -S8,
    -FRAC_1_SQRT_2,
    -C8,
    -1.0,
    -C8,
    -FRAC_1_SQRT_2,
    -S8,
];

/// `a[0] + sum_j a[j] cos(j t) + b[j] sin(j t)`; `b[0]` is unused (zero).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct Trig {
    pub a: [f64; DEG + 1],
    pub b: [f64; DEG + 1],
}

/// Fourier coefficient `j` (cosine and sine parts) of 16 equispaced samples.
fn harmonic(samples: &[f64; SAMPLES], order: usize) -> (f64, f64) {
    let (mut ca, mut sb) = (0.0, 0.0);
    for (m, &x) in samples.iter().enumerate() {
        let k = (order * m) % SAMPLES;
        ca += x * COS16[k];
        sb += x * SIN16[k];
    }
    scaled((ca, sb), order)
}

/// The sums of [`harmonic`] for a constant `J`, written out term by term so
/// that the zero and unit table entries fold away at compile time (see
/// [`Trig::from_samples`] for why the result is the same).
#[inline(always)]
fn harmonic_sums<const J: usize>(samples: &[f64; SAMPLES]) -> (f64, f64) {
    let (mut ca, mut sb) = (0.0, 0.0);
    macro_rules! terms {
        ($($m:literal)*) => {$(
            let k = (J * $m) % SAMPLES;
            if COS16[k] != 0.0 {
                ca += samples[$m] * COS16[k];
            }
            if SIN16[k] != 0.0 {
                sb += samples[$m] * SIN16[k];
            }
        )*};
    }
    terms!(0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15);
    (ca, sb)
}

/// Sums of harmonic `j` divided into its coefficients.
fn scaled((ca, sb): (f64, f64), j: usize) -> (f64, f64) {
    let n = SAMPLES as f64;
    if j == 0 || 2 * j == SAMPLES {
        (ca / n, sb / n)
    } else {
        (2.0 * ca / n, 2.0 * sb / n)
    }
}

impl Trig {
    /// The polynomial through samples at `2 pi m / 16`, exact when the
    /// sampled function has degree <= 4 (up to rounding).
    ///
    /// The sums are those of [`harmonic`], term by term in the same order,
    /// with the terms whose table entry is `0` left out (and products with
    /// `+-1`, exact, folded by the compiler): for finite samples adding
    /// `x * 0 = +-0` leaves a sum that starts at `+0` unchanged, so the
    /// coefficients are the same to the bit. A non-finite sample makes the plain sum of harmonic 0
    /// non-finite, and then the literal transform is used.
    pub fn from_samples(samples: &[f64; SAMPLES]) -> Trig {
        let sums = [
            harmonic_sums::<0>(samples),
            harmonic_sums::<1>(samples),
            harmonic_sums::<2>(samples),
            harmonic_sums::<3>(samples),
            harmonic_sums::<4>(samples),
        ];
        if !sums[0].0.is_finite() {
            return Trig::from_samples_literal(samples);
        }
        let mut t = Trig::default();
        for (j, &sum) in sums.iter().enumerate() {
            let (a, b) = scaled(sum, j);
            t.a[j] = a;
            t.b[j] = if j == 0 { 0.0 } else { b };
        }
        t
    }

    /// [`Trig::from_samples`] without the shortcuts.
    fn from_samples_literal(samples: &[f64; SAMPLES]) -> Trig {
        let mut t = Trig::default();
        for j in 0..=DEG {
            let (a, b) = harmonic(samples, j);
            t.a[j] = a;
            t.b[j] = if j == 0 { 0.0 } else { b };
        }
        t
    }

    /// Largest coefficient of harmonics 5..=8 of the samples: zero (up to
    /// rounding) exactly when the sampled function has degree <= 4, which
    /// the tests use to check the elimination's degree claim.
    #[cfg(test)]
    pub fn alias(samples: &[f64; SAMPLES]) -> f64 {
        (DEG + 1..=SAMPLES / 2)
            .map(|j| {
                let (a, b) = harmonic(samples, j);
                a.abs().max(b.abs())
            })
            .fold(0.0, f64::max)
    }

    /// Largest coefficient in absolute value.
    pub fn max_abs(&self) -> f64 {
        self.a
            .iter()
            .chain(self.b.iter())
            .fold(0.0, |m, x| m.max(x.abs()))
    }

    /// `sum_j j^p (|a_j| + |b_j|)`: bounds `|f^(p)|` everywhere.
    pub(super) fn bound(&self, power: i32) -> f64 {
        (1..=DEG)
            .map(|j| (j as f64).powi(power) * (self.a[j].abs() + self.b[j].abs()))
            .sum()
    }

    /// Value and first two derivatives at `t`.
    ///
    /// `t = TAU` is evaluated as `t = 0`: the root search's last interval
    /// ends where its first begins, and `sin(TAU)` is `-2.4e-16`, not `0`,
    /// so a root at exactly `theta = 0` (common: an axis-aligned part on
    /// the lattice) would otherwise read as a tiny value of the same sign
    /// as its neighbour at both ends of the circle and be missed.
    pub fn eval3(&self, theta: f64) -> (f64, f64, f64) {
        let theta = if theta == TAU { 0.0 } else { theta };
        let (s1, c1) = theta.sin_cos();
        self.eval3_cs(c1, s1)
    }

    /// [`Trig::eval3`] at the angle with cosine `cos` and sine `sin`.
    #[inline]
    pub(super) fn eval3_cs(&self, cos: f64, sin: f64) -> (f64, f64, f64) {
        let (mut c, mut s) = (1.0, 0.0);
        let (mut f, mut d1, mut d2) = (self.a[0], 0.0, 0.0);
        for j in 1..=DEG {
            (c, s) = (c * cos - s * sin, s * cos + c * sin);
            let jf = j as f64;
            let (cc, ss) = (self.a[j] * c, self.b[j] * s);
            f += cc + ss;
            d1 += jf * (self.b[j] * c - self.a[j] * s);
            d2 -= jf * jf * (cc + ss);
        }
        (f, d1, d2)
    }

    pub(super) fn value(&self, theta: f64) -> f64 {
        self.eval3(theta).0
    }
}

/// The roots of a polynomial of degree <= 1 (`a[0] + a[1] cos t + b[1] sin
/// t`; higher harmonics, rounding noise for the callers, are ignored), in
/// closed form; a double root when the line only touches the circle.
pub(super) fn linear_roots(poly: &Trig, out: &mut Angles) {
    let r = poly.a[1].hypot(poly.b[1]);
    if r == 0.0 {
        return;
    }
    let x = -poly.a[0] / r;
    if x.abs() > 1.0 + 1e-12 {
        return;
    }
    let phi = poly.b[1].atan2(poly.a[1]);
    let delta = x.clamp(-1.0, 1.0).acos();
    out.push(rem_tau(phi - delta));
    out.push(rem_tau(phi + delta));
}

/// Up to this many angles are kept; more means a degenerate (near-constant
/// or near-continuum) polynomial, reported through `overflow`.
pub(super) const ANGLE_CAP: usize = 32;

/// A fixed-capacity list of angles, so that the hot path never allocates.
#[derive(Debug, Clone, Copy)]
pub(super) struct Angles {
    pub v: [f64; ANGLE_CAP],
    pub n: usize,
    /// Set when an angle had to be dropped: callers must not trust the list.
    pub overflow: bool,
}

impl Angles {
    pub fn new() -> Angles {
        Angles {
            v: [0.0; ANGLE_CAP],
            n: 0,
            overflow: false,
        }
    }

    /// Adds `t` unless an angle within 1e-12 (around the circle) is listed.
    pub fn push(&mut self, angle: f64) {
        if !angle.is_finite() {
            return;
        }
        if self.v[..self.n]
            .iter()
            .any(|&u| circ_dist(u, angle) <= 1e-12)
        {
            return;
        }
        if self.n == ANGLE_CAP {
            self.overflow = true;
            return;
        }
        self.v[self.n] = angle;
        self.n += 1;
    }

    pub fn as_slice(&self) -> &[f64] {
        &self.v[..self.n]
    }
}

/// Distance between two angles around the circle.
pub(super) fn circ_dist(angle: f64, other: f64) -> f64 {
    let d = rem_tau(angle - other);
    d.min(TAU - d)
}

/// Root of `value_slope` (value, derivative) in `[lo, hi]`, given that it changes
/// sign there and `glo` is its value at `lo`: Newton steps, falling back to
/// bisection whenever a step would leave the shrinking bracket.
pub(super) fn bracketed_root(
    value_slope: impl Fn(f64) -> (f64, f64),
    mut lo: f64,
    mut hi: f64,
    glo: f64,
) -> f64 {
    let neg_lo = glo < 0.0;
    let mut x = 0.5 * (lo + hi);
    for _ in 0..100 {
        let (v, d) = value_slope(x);
        if v == 0.0 {
            return x;
        }
        if (v < 0.0) == neg_lo {
            lo = x;
        } else {
            hi = x;
        }
        let newton = x - v / d;
        let next = if newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        let done = (next - x).abs() <= 4.0 * f64::EPSILON * (1.0 + x.abs())
            || hi - lo <= 4.0 * f64::EPSILON * (1.0 + x.abs());
        x = next;
        if done {
            break;
        }
    }
    x
}

/// Which angles a caller wants: `within(lo, hi)` is `false` only when no
/// wanted angle lies in `[lo, hi]`.
pub(super) type Within<'a> = dyn Fn(f64, f64) -> bool + 'a;

/// The samples of `func` at `2 pi m / 16`.
#[cfg(test)]
pub(super) fn sampled(func: impl Fn(f64) -> f64) -> [f64; SAMPLES] {
    std::array::from_fn(|m| func(TAU * m as f64 / SAMPLES as f64))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_matches_libm() {
        for m in 0..SAMPLES {
            let t = TAU * m as f64 / SAMPLES as f64;
            assert!((COS16[m] - t.cos()).abs() < 1e-15);
            assert!((SIN16[m] - t.sin()).abs() < 1e-15);
        }
    }

    #[test]
    fn transform_recovers_coefficients() {
        let g = |t: f64| 0.5 - 2.0 * t.cos() + 0.25 * (3.0 * t).sin() + 1.5 * (4.0 * t).cos();
        let f = Trig::from_samples(&sampled(g));
        let want_a = [0.5, -2.0, 0.0, 0.0, 1.5];
        let want_b = [0.0, 0.0, 0.0, 0.25, 0.0];
        for j in 0..=DEG {
            assert!((f.a[j] - want_a[j]).abs() < 1e-14, "{f:?}");
            assert!((f.b[j] - want_b[j]).abs() < 1e-14, "{f:?}");
        }
        for t in [0.1, 1.0, 2.5, 6.0] {
            assert!((f.value(t) - g(t)).abs() < 1e-13);
        }
        assert!(Trig::alias(&sampled(g)) < 1e-14);
        assert!(Trig::alias(&sampled(|t| (5.0 * t).cos())) > 0.9);
    }

    fn bits(poly: &Trig) -> Vec<u64> {
        poly.a
            .iter()
            .chain(poly.b.iter())
            .map(|x| x.to_bits())
            .collect()
    }

    #[test]
    fn from_samples_is_the_literal_transform_to_the_bit() {
        let mut rng = crate::test_rng::Xorshift::new(0x9e37_79b9_7f4a_7c15);
        let mut rnd = || rng.signed_unit() * 1e3;
        for _ in 0..1000 {
            let v: [f64; SAMPLES] = std::array::from_fn(|_| rnd());
            let want = bits(&Trig::from_samples_literal(&v));
            assert_eq!(bits(&Trig::from_samples(&v)), want);
        }
        // Exact zeros and a non-finite sample (the literal fallback).
        let mut v = [0.0; SAMPLES];
        v[5] = -2.5;
        let want = bits(&Trig::from_samples_literal(&v));
        assert_eq!(bits(&Trig::from_samples(&v)), want);
        v[3] = f64::INFINITY;
        let want = bits(&Trig::from_samples_literal(&v));
        assert_eq!(bits(&Trig::from_samples(&v)), want);
    }
}
