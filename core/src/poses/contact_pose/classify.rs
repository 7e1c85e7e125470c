//! How the root search of `root_search` classifies an interval of angles
//! from third-order Taylor bounds at its midpoint, and the start intervals'
//! cosine and sine tables that let it evaluate there without libm.
//!
//! Kept apart from the search loop because the fifth-order proofs of
//! `taylor5` reason about exactly these tests (and use the same bounds and
//! leaf width), and from `trig` because they are the search's, not the
//! polynomial's.

use super::trig::Trig;
use std::f64::consts::TAU;

/// The root search starts from intervals `[i STEP, (i + 1) STEP]`.
pub(super) const START: usize = 16;
pub(super) const STEP: f64 = TAU / START as f64;

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
#[inline]
pub(super) fn cos_sin_near(theta: f64, start: usize) -> (f64, f64) {
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

/// What the Taylor bounds at the midpoint of an interval prove about it.
pub(super) enum Class {
    /// `|f| > tol` throughout.
    Empty,
    /// `f' != 0` throughout; carries `f(lo)` and `f(hi)` as far as the
    /// Taylor bound tells them (`None` when their sign is uncertain).
    Monotone(Option<Ends>),
    /// `f'' != 0` throughout.
    Convex,
    /// `|f|` is within rounding of zero throughout: roots there cannot be
    /// told apart, so the interval is one candidate, not split further.
    Flat,
    /// Nothing yet: split. Carries the midpoint's values when they were
    /// computed (not for a node the fifth-order bounds decided).
    Split(Option<Mid>),
}

/// Taylor estimates of `f` at the ends of a monotone interval.
pub(super) struct Ends {
    pub flo: f64,
    pub fhi: f64,
    /// Whether `f` computed at `lo` and at `hi` (as the root polishers
    /// compute it) is sure to be nonzero with the signs of `flo` and
    /// `fhi`: then those evaluations can be skipped.
    pub computed_signs: bool,
}

/// The angle at which [`classify`] evaluated an interval (its midpoint),
/// as cosine and sine, and `f`, `f'`, `f''` there: `Taylor5` starts from
/// the same numbers instead of computing them again.
pub(super) struct Mid {
    pub cos: f64,
    pub sin: f64,
    pub f: [f64; 3],
}

/// The Taylor bounds of `root_search::roots`: `m3` bounds the third derivative, `tol`
/// is the band counted as zero, `noise1` and `noise2` the errors of the
/// first two derivatives (a derivative test must beat them, or rounding
/// could fake monotonicity and turn the noise near a multiple root into a
/// swarm of sign changes).
pub(super) struct Bounds {
    pub m3: f64,
    /// Bounds `|f^(5)|`, for `Taylor5`.
    pub m5: f64,
    /// How far `f` and its first four derivatives computed at an angle
    /// can be from their true values there (see `root_search::roots`).
    pub eval_err: [f64; 5],
    pub noise: f64,
    pub tol: f64,
    pub noise1: f64,
    pub noise2: f64,
    /// How far a Taylor estimate of `f` at an end of an interval (from the
    /// values at its midpoint) can be from `f` computed at that end, beyond
    /// the Taylor remainder: the evaluation errors at both angles, the
    /// midpoint's rounding (it is within an ulp of `lo + h`, which moves
    /// `f` by `|f'|` times that) and the rounding of the estimate.
    pub end_err: f64,
}

impl Bounds {
    /// The bounds for `poly`, whose `|f'''|` is at most `m3 > 0`.
    pub(super) fn new(poly: &Trig, m3: f64, tol: f64, noise: f64) -> Bounds {
        let noise = noise + 64.0 * f64::EPSILON * (poly.a[0].abs() + poly.bound(0));
        Bounds {
            m3,
            m5: poly.bound(5),
            noise,
            tol: tol + noise,
            noise1: 20.0 * noise + 64.0 * f64::EPSILON * poly.bound(1),
            noise2: 60.0 * noise + 64.0 * f64::EPSILON * poly.bound(2),
            end_err: 128.0
                * f64::EPSILON
                * (poly.a[0].abs() + poly.bound(0) + poly.bound(1) + poly.bound(2)),
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
#[inline]
pub(super) fn classify(poly: &Trig, bounds: &Bounds, start: usize, lo: f64, hi: f64) -> Class {
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
        let remainder = bounds.m3 * h2 * h / 6.0;
        let err = remainder + bounds.noise;
        let (flo, fhi) = (f0 - h * f1 + 0.5 * h2 * f2, f0 + h * f1 + 0.5 * h2 * f2);
        let sure = flo.abs() > err && fhi.abs() > err;
        // Far enough from zero, the values computed at the ends have the
        // estimates' signs (the 1e-9 covers the rounding of this test).
        let computed = (remainder + bounds.end_err) * (1.0 + 1e-9);
        let computed_signs = flo.abs() > computed && fhi.abs() > computed;
        Class::Monotone(sure.then_some(Ends {
            flo,
            fhi,
            computed_signs,
        }))
    } else if f2.abs() - bounds.m3 * h > bounds.noise2 {
        Class::Convex
    } else {
        Class::Split(Some(Mid {
            cos: c,
            sin: s,
            f: [f0, f1, f2],
        }))
    }
}

/// Intervals narrower than this are not split further: what is left there
/// is a root of multiplicity three or more (whose neighbourhood the crude
/// bound on `f'''` cannot certify at any reasonable depth), reported as the
/// point of smallest `|f|` of each run of adjacent such intervals.
pub(super) const LEAF: f64 = 1e-6;

#[cfg(test)]
mod tests {
    use super::*;

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

    /// An interval of `depth` halvings of start interval `start`, the
    /// `index`-th (modulo their number), built as the search builds it.
    fn interval(start: usize, depth: u32, index: u64) -> (f64, f64) {
        let (mut lo, mut hi) = (start as f64 * STEP, (start + 1) as f64 * STEP);
        for level in (0..depth).rev() {
            let m = 0.5 * (lo + hi);
            if (index >> level) & 1 == 1 {
                lo = m;
            } else {
                hi = m;
            }
        }
        (lo, hi)
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(3000))]

        /// What the root search skips evaluating: where `classify` claims
        /// the computed values at a monotone interval's ends have the
        /// estimates' signs, `f` computed there (as the polisher does) has
        /// them. The constant term is set so that `f(lo)` is tiny, where
        /// the claim is hardest.
        #[test]
        fn computed_signs_are_the_computed_values_signs(
            a in proptest::array::uniform5(-1.0f64..1.0),
            b in proptest::array::uniform5(-1.0f64..1.0),
            scale_exp in -6.0f64..6.0,
            start in 0usize..START,
            depth in 0u32..22,
            index in proptest::num::u64::ANY,
            offset_exp in -55.0f64..-1.0,
            at_hi in proptest::bool::ANY,
            tol_exp in -16.0f64..-6.0,
        ) {
            let scale = 10f64.powf(scale_exp);
            let mut poly = Trig {
                a: a.map(|x| x * scale),
                b: [0.0, b[1], b[2], b[3], b[4]].map(|x| x * scale),
            };
            let (lo, hi) = interval(start, depth, index);
            let end = if at_hi { hi } else { lo };
            poly.a[0] -= poly.value(end) + offset_exp.exp2() * scale * (if at_hi { 1.0 } else { -1.0 });
            let bounds = Bounds::new(&poly, poly.bound(3), scale * 10f64.powf(tol_exp), 0.0);
            if let Class::Monotone(Some(ends)) = classify(&poly, &bounds, start, lo, hi) {
                if ends.computed_signs {
                    let (vlo, vhi) = (poly.value(lo), poly.value(hi));
                    proptest::prop_assert!(vlo != 0.0 && (vlo < 0.0) == (ends.flo < 0.0));
                    proptest::prop_assert!(vhi != 0.0 && (vhi < 0.0) == (ends.fhi < 0.0));
                }
            }
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
}
