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

/// The root search starts from intervals `[i STEP, (i + 1) STEP]`.
const START: usize = 16;
const STEP: f64 = TAU / START as f64;

/// Midpoints of the start intervals, computed as [`classify`] computes a
/// midpoint, so that the tables below hold the cosine and sine of the very
/// `f64` values the search evaluates at.
const START_MID: [f64; START] = {
    let mut mid = [0.0; START];
    let mut i = 0;
    while i < START {
        let (lo, hi) = (i as f64 * STEP, (i + 1) as f64 * STEP);
        mid[i] = lo + 0.5 * (hi - lo);
        i += 1;
    }
    mid
};

/// `cos(START_MID[i])`, correctly rounded (checked against 200-bit
/// arithmetic when generated; libm agrees to the bit).
const START_COS: [f64; START] = [
    0.980_785_280_403_230_4,
    0.831_469_612_302_545_2,
    0.555_570_233_019_602_3,
    0.195_090_322_016_128_33,
    -0.195_090_322_016_128_2,
    -0.555_570_233_019_602,
    -0.831_469_612_302_545_3,
    -0.980_785_280_403_230_4,
    -0.980_785_280_403_230_4,
    -0.831_469_612_302_545_5,
    -0.555_570_233_019_602_2,
    -0.195_090_322_016_128_66,
    0.195_090_322_016_128_3,
    0.555_570_233_019_601_8,
    0.831_469_612_302_545_2,
    0.980_785_280_403_230_3,
];

/// `sin(START_MID[i])`, correctly rounded.
const START_SIN: [f64; START] = [
    0.195_090_322_016_128_25,
    0.555_570_233_019_602_2,
    0.831_469_612_302_545_2,
    0.980_785_280_403_230_4,
    0.980_785_280_403_230_4,
    0.831_469_612_302_545_5,
    0.555_570_233_019_602_2,
    0.195_090_322_016_128_6,
    -0.195_090_322_016_128_36,
    -0.555_570_233_019_602,
    -0.831_469_612_302_545_2,
    -0.980_785_280_403_230_3,
    -0.980_785_280_403_230_4,
    -0.831_469_612_302_545_5,
    -0.555_570_233_019_602_2,
    -0.195_090_322_016_128_72,
];

/// `(cos t, sin t)` for `t` in start interval `i`, without libm: the
/// tabulated values at its midpoint `t0` turned by `d = t - t0`
/// (`|d| <= pi / 16`), whose cosine and sine come from their Taylor series
/// (truncated where the next term is below 2e-19). The table is within
/// eps / 4, `cos d - 1` and `sin d` within about 2 eps relative, so the
/// correction (at most 0.22) is within 0.6 eps and the final sum adds at
/// most eps / 2: within 2 eps of the true values all told, against libm's
/// 1 ulp, and the same `f64` angle is evaluated.
fn cos_sin_near(theta: f64, start: usize) -> (f64, f64) {
    let d = theta - START_MID[start];
    debug_assert!(
        d.abs() <= 0.5 * STEP * (1.0 + 1e-12),
        "{theta} outside {start}"
    );
    let z = d * d;
    let cm = z
        * (-1.0 / 2.0
            + z * (1.0 / 24.0
                + z * (-1.0 / 720.0
                    + z * (1.0 / 40_320.0
                        + z * (-1.0 / 3_628_800.0 + z * (1.0 / 479_001_600.0))))));
    let sd = d + d
        * z
        * (-1.0 / 6.0
            + z * (1.0 / 120.0
                + z * (-1.0 / 5_040.0 + z * (1.0 / 362_880.0 + z * (-1.0 / 39_916_800.0)))));
    let (c0, s0) = (START_COS[start], START_SIN[start]);
    (c0 + (c0 * cm - s0 * sd), s0 + (s0 * cm + c0 * sd))
}

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
    fn bound(&self, power: i32) -> f64 {
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
    fn eval3_cs(&self, cos: f64, sin: f64) -> (f64, f64, f64) {
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

    fn value(&self, theta: f64) -> f64 {
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

/// The sign-change root of `f` in `[lo, hi]`, if any (the caller knows `f`
/// is monotone there, so there is at most one).
fn monotone_root(poly: &Trig, lo: f64, hi: f64, out: &mut Angles) {
    let (flo, fhi) = (poly.value(lo), poly.value(hi));
    if flo == 0.0 {
        out.push(lo);
    } else if fhi == 0.0 {
        out.push(hi);
    } else if (flo < 0.0) != (fhi < 0.0) {
        let g = |t: f64| {
            let (v, d, _) = poly.eval3(t);
            (v, d)
        };
        out.push(bracketed_root(g, lo, hi, flo));
    }
}

/// `f` is strictly convex or concave on `[lo, hi]`: at most two roots, one
/// on each side of the extremum, and when there is none the extremum itself
/// is a candidate if `|f| <= tol` there (a tangency or a near miss).
fn convex_roots(poly: &Trig, tol: f64, lo: f64, hi: f64, out: &mut Angles) {
    let (flo, dlo, _) = poly.eval3(lo);
    let (fhi, dhi, _) = poly.eval3(hi);
    if dlo != 0.0 && dhi != 0.0 && (dlo < 0.0) == (dhi < 0.0) {
        monotone_root(poly, lo, hi, out);
        return;
    }
    let tc = if dlo == 0.0 {
        lo
    } else if dhi == 0.0 {
        hi
    } else {
        let g = |t: f64| {
            let (_, d, dd) = poly.eval3(t);
            (d, dd)
        };
        bracketed_root(g, lo, hi, dlo)
    };
    let fc = poly.value(tc);
    let before = out.n;
    let mut side = |a: f64, b: f64, fa: f64, fb: f64| {
        if fa == 0.0 {
            out.push(a);
        } else if fb == 0.0 {
            out.push(b);
        } else if (fa < 0.0) != (fb < 0.0) {
            let g = |t: f64| {
                let (v, d, _) = poly.eval3(t);
                (v, d)
            };
            out.push(bracketed_root(g, a, b, fa));
        }
    };
    side(lo, tc, flo, fc);
    side(tc, hi, fc, fhi);
    if out.n == before && fc.abs() <= tol {
        out.push(tc);
    }
}

/// What the Taylor bounds at the midpoint of an interval prove about it.
enum Class {
    /// `|f| > tol` throughout.
    Empty,
    /// `f' != 0` throughout; carries `f(lo)` and `f(hi)` as far as the
    /// Taylor bound tells them (`None` when their sign is uncertain).
    Monotone(Option<(f64, f64)>),
    /// `f'' != 0` throughout.
    Convex,
    /// `|f|` is within rounding of zero throughout: roots there cannot be
    /// told apart, so the interval is one candidate, not split further.
    Flat,
    /// Nothing yet: split.
    Split,
}

/// The Taylor bounds of [`roots`]: `m3` bounds the third derivative, `tol`
/// is the band counted as zero, `noise1` and `noise2` the errors of the
/// first two derivatives (a derivative test must beat them, or rounding
/// could fake monotonicity and turn the noise near a multiple root into a
/// swarm of sign changes).
struct Bounds {
    m3: f64,
    noise: f64,
    tol: f64,
    noise1: f64,
    noise2: f64,
}

/// What [`Class`] `[lo, hi]`, inside start interval `start`, falls in.
fn classify(poly: &Trig, bounds: &Bounds, start: usize, lo: f64, hi: f64) -> Class {
    let h = 0.5 * (hi - lo);
    let (c, s) = cos_sin_near(lo + h, start);
    let (f0, f1, f2) = poly.eval3_cs(c, s);
    let h2 = h * h;
    let spread = h * f1.abs() + 0.5 * h2 * f2.abs() + bounds.m3 * h2 * h / 6.0;
    if f0.abs() - spread > bounds.tol {
        Class::Empty
    } else if f0.abs() + spread <= bounds.noise {
        Class::Flat
    } else if f1.abs() - h * f2.abs() - 0.5 * bounds.m3 * h2 > bounds.noise1 {
        // Most monotone intervals hold no root, which the Taylor values at
        // the ends show without evaluating there.
        let err = bounds.m3 * h2 * h / 6.0 + bounds.noise;
        let (flo, fhi) = (f0 - h * f1 + 0.5 * h2 * f2, f0 + h * f1 + 0.5 * h2 * f2);
        let sure = flo.abs() > err && fhi.abs() > err;
        Class::Monotone(sure.then_some((flo, fhi)))
    } else if f2.abs() - bounds.m3 * h > bounds.noise2 {
        Class::Convex
    } else {
        Class::Split
    }
}

/// Intervals narrower than this are not split further: what is left there
/// is a root of multiplicity three or more (whose neighbourhood the crude
/// bound on `f'''` cannot certify at any reasonable depth), reported as the
/// point of smallest `|f|` of each run of adjacent such intervals.
const LEAF: f64 = 1e-6;

/// A run of adjacent leaf intervals and its point of smallest `|f|`.
struct Run {
    end: f64,
    best: (f64, f64),
}

impl Run {
    fn add(run: &mut Option<Run>, lo: f64, hi: f64, poly: &Trig, out: &mut Angles) {
        let m = 0.5 * (lo + hi);
        let v = poly.value(m).abs();
        match run {
            Some(r) if lo <= r.end + 1e-12 => {
                r.end = hi;
                if v < r.best.1 {
                    r.best = (m, v);
                }
            }
            _ => {
                Run::flush(run, out);
                *run = Some(Run {
                    end: hi,
                    best: (m, v),
                });
            }
        }
    }

    fn flush(run: &mut Option<Run>, out: &mut Angles) {
        if let Some(r) = run.take() {
            out.push(r.best.0);
        }
    }
}

/// Which angles a caller wants: `within(lo, hi)` is `false` only when no
/// wanted angle lies in `[lo, hi]`.
pub(super) type Within<'a> = dyn Fn(f64, f64) -> bool + 'a;

/// Every root of `f` in `[0, 2 pi)` (in the start intervals `within`
/// allows), plus every local extremum where
/// `|f| <= tol` without a sign change (tangencies and near misses), pushed
/// onto `out`.
///
/// Why nothing is missed: an interval is dropped only when the third-order
/// Taylor bound (with `|f'''| <= sum j^3 (|a_j| + |b_j|)`) proves `|f| > tol`
/// on all of it; a monotone interval has at most one root, found when the
/// ends differ in sign; a convex or concave one has at most two, one on each
/// side of its single extremum; what is left after splitting down to
/// `LEAF`, or what is zero to within rounding throughout, is reported by
/// the point of smallest `|f|` of each connected run. `noise` bounds the error of the coefficients (this
/// adds the error of evaluating them); `tol` widens the band of values
/// counted as zero beyond it, to catch near misses. The work is
/// bounded (`out.overflow` is set if the bound is reached, which takes a
/// polynomial that is zero to within `tol` almost everywhere).
pub(super) fn roots(poly: &Trig, tol: f64, noise: f64, within: &Within, out: &mut Angles) {
    let m3 = poly.bound(3);
    if m3 == 0.0 {
        // A constant: no isolated root (zero is a continuum, caught earlier).
        return;
    }
    // Evaluation adds a few ulps of the coefficients' sum: with cos t and
    // sin t within 2 eps (libm's, or `cos_sin_near`'s in `classify`), the
    // recurrence keeps cos jt and sin jt within 3.5 j eps, so f, f' and f''
    // come within about 25 eps of the sums of their terms' magnitudes, well
    // inside the 64 eps allowed below. A coefficient error `noise` moves f'
    // by up to sum 2j noise and f'' by sum 2j^2 noise.
    let noise = noise + 64.0 * f64::EPSILON * (poly.a[0].abs() + poly.bound(0));
    let b = Bounds {
        m3,
        noise,
        tol: tol + noise,
        noise1: 20.0 * noise + 64.0 * f64::EPSILON * poly.bound(1),
        noise2: 60.0 * noise + 64.0 * f64::EPSILON * poly.bound(2),
    };
    let mut budget = 20_000usize;
    let mut run = None;
    let mut stack = [(0.0, 0.0); 48];
    for i in 0..START {
        stack[0] = (i as f64 * STEP, (i + 1) as f64 * STEP);
        if !within(stack[0].0, stack[0].1) {
            continue;
        }
        let mut n = 1;
        while n > 0 {
            n -= 1;
            let (lo, hi) = stack[n];
            budget = budget.saturating_sub(1);
            match classify(poly, &b, i, lo, hi) {
                Class::Empty => {}
                Class::Monotone(Some((flo, fhi))) if (flo < 0.0) == (fhi < 0.0) => {}
                Class::Monotone(_) => monotone_root(poly, lo, hi, out),
                Class::Convex => convex_roots(poly, b.tol, lo, hi, out),
                Class::Split if hi - lo > LEAF && n + 2 <= stack.len() && budget > 0 => {
                    // Halves with no wanted angle are dropped unexamined:
                    // the halves kept are split exactly as before.
                    let m = 0.5 * (lo + hi);
                    if within(m, hi) {
                        stack[n] = (m, hi);
                        n += 1;
                    }
                    if within(lo, m) {
                        stack[n] = (lo, m);
                        n += 1;
                    }
                }
                Class::Split | Class::Flat => {
                    out.overflow |= budget == 0;
                    Run::add(&mut run, lo, hi, poly, out);
                }
            }
        }
    }
    Run::flush(&mut run, out);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sampled(func: impl Fn(f64) -> f64) -> [f64; SAMPLES] {
        std::array::from_fn(|m| func(TAU * m as f64 / SAMPLES as f64))
    }

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

    #[test]
    fn start_tables_match_libm() {
        for i in 0..START {
            let (lo, hi) = (i as f64 * STEP, (i + 1) as f64 * STEP);
            assert_eq!(START_MID[i], lo + 0.5 * (hi - lo));
            let (s, c) = START_MID[i].sin_cos();
            assert!((START_COS[i] - c).abs() <= 0.5 * f64::EPSILON, "{i}");
            assert!((START_SIN[i] - s).abs() <= 0.5 * f64::EPSILON, "{i}");
        }
    }

    #[test]
    fn cos_sin_near_matches_libm_across_each_start_interval() {
        let n = 20_000;
        let mut worst = 0.0f64;
        for i in 0..START {
            let (lo, hi) = (i as f64 * STEP, (i + 1) as f64 * STEP);
            for m in 0..=n {
                let t = lo + (hi - lo) * m as f64 / n as f64;
                let (c, s) = cos_sin_near(t, i);
                let (s1, c1) = t.sin_cos();
                worst = worst.max((c - c1).abs()).max((s - s1).abs());
            }
        }
        // The bound `roots` relies on is 2 eps from the true values; libm
        // is within 1 ulp of them.
        assert!(worst <= f64::EPSILON, "{worst:e}");
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

    fn found(poly: &Trig, tol: f64) -> Vec<f64> {
        let mut out = Angles::new();
        roots(poly, tol, 0.0, &|_, _| true, &mut out);
        assert!(!out.overflow);
        out.as_slice().to_vec()
    }

    #[test]
    fn simple_roots_to_machine_precision() {
        // cos(4t): eight equispaced roots, the symmetric case that stalls
        // unshifted QR on its companion matrix.
        let mut f = Trig::default();
        f.a[4] = 1.0;
        let r = found(&f, 0.0);
        assert_eq!(r.len(), 8, "{r:?}");
        for (k, t) in r.iter().enumerate() {
            let want = (std::f64::consts::PI / 8.0) * (2 * k + 1) as f64;
            assert!((t - want).abs() < 1e-14, "{t} vs {want}");
        }
    }

    #[test]
    fn double_root_and_near_miss_are_one_candidate() {
        // 1 - cos(t - 1) + delta: double root at t = 1 when delta = 0.
        for delta in [0.0, 1e-16, 1e-13, -1e-16] {
            let mut f = Trig::default();
            f.a[0] = 1.0 + delta;
            f.a[1] = -(1.0f64).cos();
            f.b[1] = -(1.0f64).sin();
            let r = found(&f, 1e-12);
            assert!(!r.is_empty() && r.len() <= 2, "{delta}: {r:?}");
            for t in r {
                assert!((t - 1.0).abs() < 2e-6, "{delta}: {t}");
            }
        }
        // Clearly positive minimum: nothing.
        let mut f = Trig::default();
        f.a[0] = 1.0 + 1e-6;
        f.a[1] = -1.0;
        assert!(found(&f, 1e-12).is_empty());
    }

    #[test]
    fn random_polynomials_agree_with_dense_sign_changes() {
        let mut rng = crate::test_rng::Xorshift::new(0x2545_f491_4f6c_dd1d);
        let mut rnd = || rng.signed_unit();
        for _ in 0..300 {
            let mut f = Trig::default();
            for j in 0..=DEG {
                f.a[j] = rnd();
                if j > 0 {
                    f.b[j] = rnd();
                }
            }
            let r = found(&f, 1e-13);
            let n = 100_000;
            let mut changes = 0;
            let mut prev = f.value(0.0);
            for m in 1..=n {
                let t = TAU * m as f64 / n as f64;
                let v = f.value(t);
                if (v < 0.0) != (prev < 0.0) {
                    changes += 1;
                    assert!(
                        r.iter().any(|&u| circ_dist(u, t) <= TAU / n as f64),
                        "missed a root near {t}: {r:?}"
                    );
                }
                prev = v;
            }
            assert!(r.len() >= changes);
            for &t in &r {
                assert!(f.value(t).abs() < 1e-12, "{t}");
            }
        }
    }
}
