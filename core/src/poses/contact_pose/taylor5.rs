//! Fifth-order Taylor bounds that prove what `classify` would answer on a
//! whole subtree below a `Split` node, so that the root search can skip
//! classifying it (near a root cluster the third-order bounds split down to
//! the leaves).
//!
//! Kept apart from the search loop: the proofs are the delicate part (each
//! test keeps a margin over rounding) and are read against `classify`.

use super::classify::{Bounds, Mid, LEAF};
use super::trig::{Trig, DEG};

/// What [`Taylor5`] proves about the subtree below a `Split` node.
pub(super) enum Below {
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
/// Taylor bound, much tighter than `classify`'s third-order one on small
/// intervals). They bound the values `classify` and the root polishers
/// compute at any angle inside: those are within `64 eps` of the sums of
/// their terms' magnitudes (see `root_search::roots`).
pub(super) struct Taylor5 {
    /// Upper bounds on the computed `|f|`, `|f'|`, `|f''|` anywhere inside.
    upper: [f64; 3],
    /// Lower bounds on the computed `|f|` and `|f'|` anywhere inside (`f`
    /// and `f'` keep one sign there when positive).
    lower: [f64; 2],
}

impl Taylor5 {
    /// The bounds over an interval of width `width` whose midpoint
    /// `classify` evaluated (`mid`): `f`, `f'`, `f''` are its, the third
    /// and fourth derivatives are added at the same angle.
    pub(super) fn new(poly: &Trig, bounds: &Bounds, mid: &Mid, width: f64) -> Taylor5 {
        let h = 0.5 * width;
        let [d3, d4] = higher_derivatives(poly, mid.cos, mid.sin);
        let d = [mid.f[0], mid.f[1], mid.f[2], d3, d4];
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

    /// Whether `classify`'s monotone test passes on every interval of
    /// half-width at most `half` inside.
    fn monotone_at(&self, bounds: &Bounds, half: f64) -> bool {
        self.lower[1] - half * self.upper[2] - 0.5 * bounds.m3 * half * half
            > bounds.noise1 * (1.0 + MARGIN) + MARGIN * self.upper[1]
    }

    /// What the bounds prove about the subtree below a node of width
    /// `width` that `classify` has just found `Class::Split`.
    pub(super) fn below(&self, bounds: &Bounds, width: f64) -> Below {
        match self.silent(bounds, width) {
            Some(nodes) => Below::Silent(nodes),
            None => Below::Split(self.split_levels(bounds, width)),
        }
    }

    /// Whether `classify`'s empty test passes on every interval of
    /// half-width at most `half` inside.
    fn empty_at(&self, bounds: &Bounds, half: f64) -> bool {
        let spread = half * self.upper[1]
            + 0.5 * half * half * self.upper[2]
            + bounds.m3 * half * half * half / 6.0;
        self.lower[0] - spread > bounds.tol * (1.0 + MARGIN) + MARGIN * self.upper[0]
    }

    /// Whether the subtree below this node is sure to push nothing, and an
    /// upper bound on how many intervals it would have examined: when
    /// [`Taylor5::monotone_silent`] or else [`Taylor5::empty_silent`] says
    /// so (the second test only when the first fails: it rarely gives a
    /// smaller count, and the count only matters against the budget).
    fn silent(&self, bounds: &Bounds, width: f64) -> Option<usize> {
        let levels = if self.monotone_silent(bounds) {
            levels_until(width, |half| self.monotone_at(bounds, half))
        } else if self.empty_silent(bounds) {
            levels_until(width, |half| self.empty_at(bounds, half))
        } else {
            return None;
        };
        Some((2usize << levels.min(30)) - 2)
    }

    /// It is when `|f|` stays above the noise and the evaluation error (so
    /// no interval is `Flat` and every computed sign is the true one), `f'`
    /// too (so a `Convex` interval is monotone to its polisher and no
    /// extremum is pushed), and `classify`'s monotone test passes at leaf
    /// width (so no leaf joins a run): then every interval examined is
    /// `Empty`, `Monotone` or `Convex` without a sign change, or is split.
    fn monotone_silent(&self, bounds: &Bounds) -> bool {
        self.lower[0] > bounds.noise * (1.0 + MARGIN)
            && self.lower[1] > 0.0
            && self.monotone_at(bounds, 0.5 * LEAF * (1.0 + 1e-6))
    }

    /// It is also when `|f|` stays above `tol` and the error of estimating
    /// `f` at an interval's ends (so no interval is `Flat`, every estimated
    /// or computed sign is the true one, which is the same throughout, and
    /// a `Convex` interval's extremum is no near miss), and `classify`'s
    /// empty test passes at leaf width (so no leaf joins a run): then
    /// every interval examined is `Empty`, `Monotone` or `Convex` without
    /// a sign change, or is split. This covers the subtrees round an
    /// extremum that misses zero, where `f'` changes sign.
    fn empty_silent(&self, bounds: &Bounds) -> bool {
        self.lower[0] > (bounds.tol + bounds.end_err) * (1.0 + MARGIN) + MARGIN * self.upper[0]
            && self.empty_at(bounds, 0.5 * LEAF * (1.0 + 1e-6))
    }

    /// How many levels of descendants (a node `classify` has just found
    /// `Class::Split`) are sure to be classified `Split` too, or, at leaf
    /// width, to join a run: `classify`'s tests on a narrower interval
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

/// Levels of descendants of a node of width `width` the search examines
/// at most when every interval of half-width `half` passing `test` ends
/// the search there (the test is monotone in `half`): the first level
/// where it surely passes, or leaf width.
fn levels_until(width: f64, test: impl Fn(f64) -> bool) -> u32 {
    let mut levels = 1;
    let mut w = width * 0.5;
    while !test(0.5 * w * (1.0 + 1e-6) + 1e-13) && w * (1.0 + 1e-6) > LEAF {
        levels += 1;
        w *= 0.5;
    }
    levels
}

/// `f'''` and `f''''` at the angle with cosine `cos` and sine `sin`,
/// summed as [`derivatives`] sums them.
fn higher_derivatives(poly: &Trig, cos: f64, sin: f64) -> [f64; 2] {
    let (mut c, mut s) = (1.0, 0.0);
    let mut d = [0.0, 0.0];
    for j in 1..=DEG {
        (c, s) = (c * cos - s * sin, s * cos + c * sin);
        let jf = j as f64;
        let even = poly.a[j] * c + poly.b[j] * s;
        let odd = jf * (poly.b[j] * c - poly.a[j] * s);
        d[0] -= jf * jf * odd;
        d[1] += jf * jf * jf * jf * even;
    }
    d
}

/// `f` and its first four derivatives at the angle with cosine `cos` and
/// sine `sin` (the first three as `Trig::eval3_cs` computes them, the
/// last two as [`higher_derivatives`]: the tests check both to the bit).
#[cfg(test)]
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derivatives_are_classify_values_and_higher_ones_to_the_bit() {
        // `Taylor5::new` takes `f`, `f'`, `f''` from `classify` (computed by
        // `Trig::eval3_cs`) and adds `higher_derivatives`: the same numbers
        // as computing all five in one loop.
        let mut rng = crate::test_rng::Xorshift::new(0x6a09_e667_f3bc_c908);
        for _ in 0..2000 {
            let mut poly = Trig::default();
            for j in 0..=DEG {
                poly.a[j] = rng.signed_unit() * 1e4;
                if j > 0 {
                    poly.b[j] = rng.signed_unit() * 1e4;
                }
            }
            let (s, c) = (rng.signed_unit() * 7.0).sin_cos();
            let all = derivatives(&poly, c, s);
            let (f0, f1, f2) = poly.eval3_cs(c, s);
            let [d3, d4] = higher_derivatives(&poly, c, s);
            let bits = |v: [f64; 5]| v.map(f64::to_bits);
            assert_eq!(bits(all), bits([f0, f1, f2, d3, d4]));
        }
    }
}
