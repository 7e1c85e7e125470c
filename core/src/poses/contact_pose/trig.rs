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
    /// Bounds `|f^(5)|`, for [`Taylor5`].
    m5: f64,
    /// How far `f` and its first four derivatives computed at an angle
    /// can be from their true values there (see [`roots`]).
    eval_err: [f64; 5],
    noise: f64,
    tol: f64,
    noise1: f64,
    noise2: f64,
}

impl Bounds {
    /// The bounds for `poly`, whose `|f'''|` is at most `m3 > 0`.
    fn new(poly: &Trig, m3: f64, tol: f64, noise: f64) -> Bounds {
        let noise = noise + 64.0 * f64::EPSILON * (poly.a[0].abs() + poly.bound(0));
        Bounds {
            m3,
            m5: poly.bound(5),
            noise,
            tol: tol + noise,
            noise1: 20.0 * noise + 64.0 * f64::EPSILON * poly.bound(1),
            noise2: 60.0 * noise + 64.0 * f64::EPSILON * poly.bound(2),
            eval_err: [
                64.0 * f64::EPSILON * (poly.a[0].abs() + poly.bound(0)),
                64.0 * f64::EPSILON * poly.bound(1),
                64.0 * f64::EPSILON * poly.bound(2),
                64.0 * f64::EPSILON * poly.bound(3),
                64.0 * f64::EPSILON * poly.bound(4),
            ],
        }
    }
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

/// What [`Taylor5`] proves about the subtree below a `Split` node.
enum Below {
    /// No interval in it pushes an angle or joins a run; the plain search
    /// would examine at most this many intervals there.
    Silent(usize),
    /// Intervals this many levels down are `Split` too (at leaf width:
    /// join a run, as `Split` and `Flat` leaves both do).
    Split(u32),
}

/// Relative margin every proved test keeps over its threshold, far above
/// the rounding of the few operations in each.
const MARGIN: f64 = 1e-9;

/// Bounds over a whole interval `[lo, hi]`, from `f` and its first four
/// derivatives at the midpoint and the bound on `|f^(5)|` (a fifth-order
/// Taylor bound, much tighter than [`classify`]'s third-order one on small
/// intervals). They bound the values [`classify`] and the root polishers
/// compute at any angle inside: those are within `64 eps` of the sums of
/// their terms' magnitudes (see [`roots`]).
struct Taylor5 {
    /// Upper bounds on the computed `|f|`, `|f'|`, `|f''|` anywhere inside.
    upper: [f64; 3],
    /// Lower bounds on the computed `|f|` and `|f'|` anywhere inside (`f`
    /// and `f'` keep one sign there when positive).
    lower: [f64; 2],
}

impl Taylor5 {
    fn new(poly: &Trig, bounds: &Bounds, start: usize, lo: f64, hi: f64) -> Taylor5 {
        let h = 0.5 * (hi - lo);
        let (c1, s1) = cos_sin_near(lo + h, start);
        let d = derivatives(poly, c1, s1);
        let err = &bounds.eval_err;
        // Descendants' midpoints lie in [lo, hi], within rounding.
        let r = h * (1.0 + 1e-6) + 1e-12;
        let mut upper = [0.0; 3];
        let mut lower = [0.0; 2];
        for k in 0..3 {
            // |f^(k)(x) - f^(k)(mid)| <= spread for every x inside.
            let mut term = r;
            let mut spread = 0.0;
            for i in 1..=(4 - k) {
                spread += (d[k + i].abs() + err[k + i]) * term;
                term *= r / (i + 1) as f64;
            }
            spread += bounds.m5 * term;
            let centre = d[k].abs();
            upper[k] = (centre + err[k] + spread + err[k]) * (1.0 + MARGIN);
            if k < 2 {
                lower[k] = (centre - err[k] - spread) * (1.0 - MARGIN)
                    - (centre + spread) * MARGIN
                    - err[k];
            }
        }
        Taylor5 { upper, lower }
    }

    /// Whether [`classify`]'s monotone test passes on every interval of
    /// half-width at most `half` inside.
    fn monotone_at(&self, bounds: &Bounds, half: f64) -> bool {
        self.lower[1] - half * self.upper[2] - 0.5 * bounds.m3 * half * half
            > bounds.noise1 * (1.0 + MARGIN) + MARGIN * self.upper[1]
    }

    /// What the bounds prove about the subtree below a node of width
    /// `width` that [`classify`] has just found [`Class::Split`].
    fn below(&self, bounds: &Bounds, width: f64) -> Below {
        match self.silent(bounds, width) {
            Some(nodes) => Below::Silent(nodes),
            None => Below::Split(self.split_levels(bounds, width)),
        }
    }

    /// Whether the subtree below this node is sure to push nothing, and an
    /// upper bound on how many intervals it would have examined. It is when
    /// `|f|` stays above the noise and the evaluation error (so no interval
    /// is `Flat` and every computed sign is the true one), `f'` too (so a
    /// `Convex` interval is monotone to its polisher and no extremum is
    /// pushed), and [`classify`]'s monotone test passes at leaf width (so no
    /// leaf joins a run): then every interval examined is `Empty`,
    /// `Monotone` or `Convex` without a sign change, or is split.
    fn silent(&self, bounds: &Bounds, width: f64) -> Option<usize> {
        let sure = self.lower[0] > bounds.noise * (1.0 + MARGIN)
            && self.lower[1] > 0.0
            && self.monotone_at(bounds, 0.5 * LEAF * (1.0 + 1e-6));
        if !sure {
            return None;
        }
        // Every interval ends at the first level where the monotone test
        // is sure to pass, or at leaf width.
        let mut levels = 1;
        let mut w = width * 0.5;
        while !self.monotone_at(bounds, 0.5 * w * (1.0 + 1e-6) + 1e-13) && w * (1.0 + 1e-6) > LEAF {
            levels += 1;
            w *= 0.5;
        }
        Some((2usize << levels.min(30)) - 2)
    }

    /// How many levels of descendants (a node [`classify`] has just found
    /// [`Class::Split`]) are sure to be classified `Split` too, or, at leaf
    /// width, to join a run: [`classify`]'s tests on a narrower interval
    /// are monotone in its width.
    fn split_levels(&self, bounds: &Bounds, width: f64) -> u32 {
        let m3 = bounds.m3;
        let keep = 1.0 - MARGIN;
        let mut levels = 0;
        let mut width = width;
        while levels < 40 {
            width *= 0.5;
            let (wlo, whi) = (width * (1.0 - 1e-6) - 1e-13, width * (1.0 + 1e-6) + 1e-13);
            let hj = 0.5 * wlo;
            let run_member = self.upper[0] <= (bounds.tol + m3 * hj * hj * hj / 6.0) * keep
                && self.upper[1] <= (bounds.noise1 + 0.5 * m3 * hj * hj) * keep
                && self.upper[2] <= (bounds.noise2 + m3 * hj) * keep;
            if !run_member {
                break;
            }
            if whi <= LEAF {
                // A leaf: Split and Flat both join the run.
                return levels + 1;
            }
            if wlo <= LEAF || m3 * hj * hj * hj / 6.0 <= bounds.noise * (1.0 + MARGIN) {
                break;
            }
            levels += 1;
        }
        levels
    }
}

/// `f` and its first four derivatives at the angle with cosine `cos` and
/// sine `sin`.
fn derivatives(poly: &Trig, cos: f64, sin: f64) -> [f64; 5] {
    let (mut c, mut s) = (1.0, 0.0);
    let mut d = [poly.a[0], 0.0, 0.0, 0.0, 0.0];
    for j in 1..=DEG {
        (c, s) = (c * cos - s * sin, s * cos + c * sin);
        let jf = j as f64;
        let even = poly.a[j] * c + poly.b[j] * s;
        let odd = jf * (poly.b[j] * c - poly.a[j] * s);
        d[0] += even;
        d[1] += odd;
        d[2] -= jf * jf * even;
        d[3] -= jf * jf * odd;
        d[4] += jf * jf * jf * jf * even;
    }
    d
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
///
/// Near a cluster of roots (a near-multiple root, or a stretch where `f`
/// stays within `tol` of zero) the third-order bound splits down to the
/// leaves; fifth-order bounds ([`Taylor5`]) decide most of those intervals
/// without classifying them, and only where they prove [`classify`]'s
/// answer, so the angles reported are the same to the bit.
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
    let b = Bounds::new(poly, m3, tol, noise);
    let saved = *out;
    if search(poly, &b, within, out, true).is_none() {
        *out = saved;
        search(poly, &b, within, out, false);
    }
}

/// Intervals examined per call before the search gives up on a polynomial
/// that is zero to within `tol` almost everywhere.
const BUDGET: usize = 20_000;

/// The subdivision of [`roots`]; the number of intervals classified.
///
/// With `prove`, what the fifth-order bounds of [`Taylor5`] decide below a
/// `Split` node is not classified: a subtree proved silent is dropped, and
/// nodes proved `Split` are split unexamined (still counted against the
/// budget). The output is the same as without, except that a dropped
/// subtree's intervals no longer count against the budget: `None` when
/// they might have exhausted it, which would have changed the answer (the
/// caller then searches again without `prove`).
fn search(
    poly: &Trig,
    b: &Bounds,
    within: &Within,
    out: &mut Angles,
    prove: bool,
) -> Option<usize> {
    let mut budget = BUDGET;
    let (mut reserve, mut classified) = (0usize, 0usize);
    let mut run = None;
    let mut stack = [(0.0, 0.0, 0u32); 48];
    for i in 0..START {
        stack[0] = (i as f64 * STEP, (i + 1) as f64 * STEP, 0);
        if !within(stack[0].0, stack[0].1) {
            continue;
        }
        let mut n = 1;
        while n > 0 {
            n -= 1;
            let (lo, hi, known) = stack[n];
            budget = budget.saturating_sub(1);
            let class = if known > 0 {
                Class::Split
            } else {
                classified += 1;
                classify(poly, b, i, lo, hi)
            };
            match class {
                Class::Empty => {}
                Class::Monotone(Some((flo, fhi))) if (flo < 0.0) == (fhi < 0.0) => {}
                Class::Monotone(_) => monotone_root(poly, lo, hi, out),
                Class::Convex => convex_roots(poly, b.tol, lo, hi, out),
                Class::Split if hi - lo > LEAF && n + 2 <= stack.len() && budget > 0 => {
                    let next = if known > 0 {
                        known - 1
                    } else if prove {
                        match Taylor5::new(poly, b, i, lo, hi).below(b, hi - lo) {
                            Below::Silent(nodes) => {
                                reserve += nodes;
                                if BUDGET - budget + reserve >= BUDGET {
                                    return None;
                                }
                                continue;
                            }
                            Below::Split(levels) => levels,
                        }
                    } else {
                        0
                    };
                    // Halves with no wanted angle are dropped unexamined:
                    // the halves kept are split exactly as before.
                    let m = 0.5 * (lo + hi);
                    if within(m, hi) {
                        stack[n] = (m, hi, next);
                        n += 1;
                    }
                    if within(lo, m) {
                        stack[n] = (lo, m, next);
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
    // The plain search examines at most `reserve` more intervals.
    (reserve == 0 || BUDGET - budget + reserve < BUDGET).then_some(classified)
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

    /// `roots` and the plain search (the subdivision before the
    /// fifth-order proofs, kept as the oracle) on the same input: the same
    /// angles to the bit and the same overflow flag. Returns how many
    /// intervals each classified.
    fn same_as_plain(poly: &Trig, tol: f64, noise: f64, within: &Within) -> (usize, usize) {
        let mut got = Angles::new();
        got.push(1.0);
        let mut want = got;
        roots(poly, tol, noise, within, &mut got);
        let b = Bounds::new(poly, poly.bound(3), tol, noise);
        let plain = search(poly, &b, within, &mut want, false).expect("plain search is complete");
        let bits = |a: &Angles| a.as_slice().iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(
            bits(&got),
            bits(&want),
            "{poly:?} tol {tol:e} noise {noise:e}"
        );
        assert_eq!(got.overflow, want.overflow, "{poly:?}");
        let mut fresh = Angles::new();
        let proved = search(poly, &b, within, &mut fresh, true).unwrap_or(plain);
        (proved, plain)
    }

    fn from_bits(bits: [u64; 12]) -> (Trig, f64, f64) {
        let v = bits.map(f64::from_bits);
        let poly = Trig {
            a: [v[0], v[1], v[2], v[3], v[4]],
            b: [v[5], v[6], v[7], v[8], v[9]],
        };
        (poly, v[10], v[11])
    }

    #[test]
    fn recorded_clusters_are_found_as_before_with_fewer_intervals() {
        // Eliminants of the deck panel of the real-files set, with the
        // tolerances the pose solver passed: a near-sixfold root at 0
        // (F ~ K (1 - cos)^3), a long stretch within `tol` of zero, one
        // that exhausts the budget, and a cluster elsewhere.
        let recorded: [[u64; 12]; 4] = [
            [
                0x4136860f557122c0,
                0xc140e48980abac12,
                0x412b0738cea0594c,
                0xc10204c5db4fba0d,
                0xbdf9840000000000,
                0x0,
                0x3e081eac00000000,
                0xbe049ce000000000,
                0x3de1ef2000000000,
                0xbdaea40000000000,
                0x3f1a754f18409b49,
                0x3e796609d666fd9c,
            ],
            [
                0x418a3253e32ba9b9,
                0x418a47f880b53b60,
                0xc14a7d4ee5401b30,
                0xc150f7af0c541749,
                0xbe30000000000000,
                0x0,
                0x418d3648b4d37924,
                0x417f42569d89d8b7,
                0x4148978d9462fd3a,
                0x3e4c000000000000,
                0x3f72498fcd6fcb8f,
                0x3ee4d3940b262788,
            ],
            [
                0x4163c39a002e8a11,
                0xc1427c838630617d,
                0xc15691c571914250,
                0x411ca203cbd7cac9,
                0xbe111a0000000000,
                0x0,
                0x416d490dbf484497,
                0xc13d38baa0a01275,
                0xc12c36e179830cad,
                0xbe0b400000000000,
                0x3f4608b80f9edeaf,
                0x3eb291cb17b1e6ac,
            ],
            [
                0x41414c9d6e40978a,
                0xc149d5ac190cdfbd,
                0x413464cfa59417f6,
                0xc10a95927fdc3c7b,
                0xbdf7800000000000,
                0x0,
                0xc114e125d6388fb4,
                0x4110a7034cfbcaf2,
                0xc0f0912bafa94049,
                0xbdd6fc0000000000,
                0x3f21a2d39094e842,
                0x3e83667efdb68b01,
            ],
        ];
        let mut saved = 0;
        for bits in recorded {
            let (poly, tol, noise) = from_bits(bits);
            let (proved, plain) = same_as_plain(&poly, tol, noise, &|_, _| true);
            assert!(proved <= plain);
            saved += plain - proved;
            // Part of the circle only, as the setup sweep asks.
            same_as_plain(&poly, tol, noise, &|lo, hi| hi >= 1.0 && lo <= 4.0);
            same_as_plain(&poly, tol, noise, &|lo, _| lo <= 0.2 || lo >= 6.1);
        }
        assert!(saved > 10_000, "{saved}");
    }

    /// `K (1 - cos(t - t0))^power (c + cos(t - t1))` plus a small random
    /// remainder: a near-multiple root at `t0`.
    fn cluster(
        k: f64,
        power: i32,
        (t0, t1, c): (f64, f64, f64),
        remainder: [f64; 9],
        size: f64,
    ) -> Trig {
        let g = |t: f64| {
            let base = k * (1.0 - (t - t0).cos()).powi(power);
            let r = remainder[0]
                + (1..=DEG)
                    .map(|j| {
                        let jt = j as f64 * t;
                        remainder[2 * j - 1] * jt.cos() + remainder[2 * j] * jt.sin()
                    })
                    .sum::<f64>();
            if power <= 3 {
                base * (c + (t - t1).cos()) + size * k * r
            } else {
                base + size * k * r
            }
        };
        Trig::from_samples(&sampled(g))
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(300))]

        #[test]
        fn proved_search_is_the_plain_search_on_clusters(
            k in 1e-3f64..1e8,
            power in 1i32..=4,
            shape in (0.0f64..TAU, 0.0f64..TAU, 1.5f64..3.0),
            at_zero in proptest::bool::ANY,
            remainder in proptest::array::uniform9(-1.0f64..1.0),
            size_exp in -18.0f64..-8.0,
            tol_exp in -14.0f64..-9.0,
            noise_exp in -17.0f64..-12.0,
        ) {
            let shape = if at_zero { (0.0, shape.1, shape.2) } else { shape };
            let poly = cluster(k, power, shape, remainder, 10f64.powf(size_exp));
            let (tol, noise) = (k * 10f64.powf(tol_exp), k * 10f64.powf(noise_exp));
            same_as_plain(&poly, tol, noise, &|_, _| true);
            let (lo, hi) = (shape.0 - 0.3, shape.0 + 0.05);
            same_as_plain(&poly, tol, noise, &|a, b| b >= lo && a <= hi);
        }

        #[test]
        fn proved_search_is_the_plain_search_on_random_polynomials(
            a in proptest::array::uniform5(-1.0f64..1.0),
            b in proptest::array::uniform5(-1.0f64..1.0),
            tol_exp in -14.0f64..-2.0,
        ) {
            let poly = Trig { a, b: [0.0, b[1], b[2], b[3], b[4]] };
            same_as_plain(&poly, 10f64.powf(tol_exp), 1e-15, &|_, _| true);
        }
    }
}
