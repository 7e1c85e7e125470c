//! Fifth-order Taylor bounds that prove what `classify` would answer on a
//! whole subtree below a `Split` node, so that the root search can skip
//! classifying it (near a root cluster the third-order bounds split down to
//! the leaves).
//!
//! Kept apart from the search loop: the proofs are the delicate part (each
//! test keeps a margin over rounding) and are read against `classify`.

use super::classify::{cos_sin_near, Bounds, LEAF};
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
    pub(super) fn new(poly: &Trig, bounds: &Bounds, start: usize, lo: f64, hi: f64) -> Taylor5 {
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

    /// Whether the subtree below this node is sure to push nothing, and an
    /// upper bound on how many intervals it would have examined. It is when
    /// `|f|` stays above the noise and the evaluation error (so no interval
    /// is `Flat` and every computed sign is the true one), `f'` too (so a
    /// `Convex` interval is monotone to its polisher and no extremum is
    /// pushed), and `classify`'s monotone test passes at leaf width (so no
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
