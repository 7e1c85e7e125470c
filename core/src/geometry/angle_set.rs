//! Sets of rotation angles, as sorted closed intervals of `[0, 2 pi]`: where
//! a part may turn while its contacts stay on their segments. Setup pruning
//! intersects them, so they must never lose an angle: every operation
//! returns a superset of the exact set, by at most the slack it is given.

use std::f64::consts::{PI, TAU};

/// Most intervals a set holds: a sinusoid band is at most three pieces of
/// `[0, 2 pi]`, the intersection of two at most five.
pub(crate) const CAPACITY: usize = 6;

/// A finite union of closed angle intervals in `[0, 2 pi]`, sorted and
/// disjoint. An interval that crosses `0` is stored as two pieces. Held
/// inline: pruning builds two per lattice point, where a heap allocation
/// cost more than the arithmetic.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AngleSet {
    intervals: [[f64; 2]; CAPACITY],
    len: usize,
}

impl Default for AngleSet {
    fn default() -> Self {
        AngleSet {
            intervals: [[0.0; 2]; CAPACITY],
            len: 0,
        }
    }
}

impl AngleSet {
    /// Every angle.
    pub fn full() -> Self {
        let mut s = AngleSet::default();
        s.push([0.0, TAU]);
        s
    }

    /// No angle.
    pub fn empty() -> Self {
        AngleSet::default()
    }

    fn push(&mut self, iv: [f64; 2]) {
        // Capacity holds by construction (see `CAPACITY`); an overflow
        // would mean a bug, and dropping an interval would lose setups.
        assert!(self.len < CAPACITY, "angle set overflow");
        self.intervals[self.len] = iv;
        self.len += 1;
    }

    /// The angles `theta` with `lo <= alpha + amp cos(theta - phi) <= hi`,
    /// widened by `slack` radians at every end (`amp >= 0`).
    pub fn sinusoid_band(alpha: f64, amp: f64, phi: f64, lo: f64, hi: f64, slack: f64) -> Self {
        // A zero (or NaN) amplitude: the value is alpha at every angle.
        if amp.is_nan() || amp <= 1e-300 {
            return if (lo..=hi).contains(&alpha) {
                AngleSet::full()
            } else {
                AngleSet::empty()
            };
        }
        // alpha + amp cos(theta - phi): with x = theta - phi in (-pi, pi],
        // cos x >= l iff |x| <= acos(l), cos x <= h iff |x| >= acos(h).
        let l = (lo - alpha) / amp;
        let h = (hi - alpha) / amp;
        if l > 1.0 || h < -1.0 || l > h {
            return AngleSet::empty();
        }
        if l <= -1.0 && h >= 1.0 {
            return AngleSet::full();
        }
        let outer = if l <= -1.0 { PI } else { l.acos() } + slack;
        let inner = if h >= 1.0 { 0.0 } else { h.acos() } - slack;
        let mut set = AngleSet::empty();
        if inner <= 0.0 {
            set.add_wrapped(phi - outer, phi + outer);
        } else {
            set.add_wrapped(phi - outer, phi - inner);
            set.add_wrapped(phi + inner, phi + outer);
        }
        set.normalise();
        set
    }

    /// The angles in both sets.
    pub fn intersect(&self, other: &AngleSet) -> AngleSet {
        let mut out = AngleSet::empty();
        let (a, b) = (self.intervals(), other.intervals());
        let (mut i, mut j) = (0, 0);
        while i < a.len() && j < b.len() {
            let [a0, a1] = a[i];
            let [b0, b1] = b[j];
            let (lo, hi) = (a0.max(b0), a1.min(b1));
            if lo <= hi {
                out.push([lo, hi]);
            }
            if a1 < b1 {
                i += 1;
            } else {
                j += 1;
            }
        }
        out
    }

    /// A superset of the angles in either set: their union, with the
    /// narrowest gaps filled while it has more intervals than a set holds
    /// (a filter that may only over-approximate can afford that).
    pub fn union_covering(&self, other: &AngleSet) -> AngleSet {
        let mut all = [[0.0; 2]; 2 * CAPACITY];
        let n = self.len + other.len;
        all[..self.len].copy_from_slice(self.intervals());
        all[self.len..n].copy_from_slice(other.intervals());
        let all = &mut all[..n];
        all.sort_unstable_by(|a, b| a[0].total_cmp(&b[0]));
        let mut merged: [[f64; 2]; 2 * CAPACITY] = [[0.0; 2]; 2 * CAPACITY];
        let mut m = 0;
        for &[lo, hi] in all.iter() {
            if m > 0 && lo <= merged[m - 1][1] {
                merged[m - 1][1] = merged[m - 1][1].max(hi);
            } else {
                merged[m] = [lo, hi];
                m += 1;
            }
        }
        while m > CAPACITY {
            // Fill the narrowest gap.
            let k = (1..m)
                .min_by(|&i, &j| {
                    let gi = merged[i][0] - merged[i - 1][1];
                    let gj = merged[j][0] - merged[j - 1][1];
                    gi.total_cmp(&gj)
                })
                .unwrap_or(1);
            merged[k - 1][1] = merged[k - 1][1].max(merged[k][1]);
            merged.copy_within(k + 1..m, k);
            m -= 1;
        }
        let mut out = AngleSet::empty();
        for &iv in &merged[..m] {
            out.push(iv);
        }
        out
    }

    /// Whether `theta` (in `[0, 2 pi)`) is in the set.
    pub fn contains(&self, theta: f64) -> bool {
        self.intervals()
            .iter()
            .any(|&[lo, hi]| lo <= theta && theta <= hi)
    }

    /// Whether some angle of `[lo, hi]` (any real angles, `hi - lo <= 2
    /// pi`) is in the set, the circle wrapping round.
    pub fn meets(&self, lo: f64, hi: f64) -> bool {
        let start = wrap_angle(lo);
        let end = start + (hi - lo);
        let overlaps = |a: f64, b: f64| self.intervals().iter().any(|&[x, y]| x <= b && y >= a);
        if end <= TAU {
            overlaps(start, end)
        } else {
            overlaps(start, TAU) || overlaps(0.0, end - TAU)
        }
    }

    /// Whether the set has no angle.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The intervals, sorted.
    pub fn intervals(&self) -> &[[f64; 2]] {
        &self.intervals[..self.len]
    }

    /// Adds `[lo, hi]` (any real angles, `hi - lo < 2 pi` or the whole
    /// circle), cut at `0` into pieces of `[0, 2 pi]`.
    fn add_wrapped(&mut self, lo: f64, hi: f64) {
        if hi - lo >= TAU {
            self.push([0.0, TAU]);
            return;
        }
        let shift = (lo / TAU).floor() * TAU;
        let (lo, hi) = (lo - shift, hi - shift);
        if hi <= TAU {
            self.push([lo, hi.min(TAU)]);
        } else {
            self.push([lo, TAU]);
            self.push([0.0, hi - TAU]);
        }
    }

    /// Sorts and merges overlapping intervals.
    fn normalise(&mut self) {
        // At most a few intervals: insertion sort beats the library's.
        for k in 1..self.len {
            let mut j = k;
            while j > 0 && self.intervals[j - 1][0] > self.intervals[j][0] {
                self.intervals.swap(j - 1, j);
                j -= 1;
            }
        }
        let mut n = 0;
        for k in 0..self.len {
            let [lo, hi] = self.intervals[k];
            if n > 0 && lo <= self.intervals[n - 1][1] {
                self.intervals[n - 1][1] = self.intervals[n - 1][1].max(hi);
            } else {
                self.intervals[n] = [lo, hi];
                n += 1;
            }
        }
        self.len = n;
    }
}

/// `x.rem_euclid(TAU)` to the bit, without its cost where it is paid:
/// `%` on `f64` is a soft-float `fmod` call (about 4% of an arc part's
/// enumeration, from contact parameters, sweeps and angle sets), yet
/// nearly every angle reduced lies within two turns, where `fmod` is exact
/// and equals `x` itself (`|x| < 2 pi`) or `x -+ 2 pi` (`2 pi < |x| <
/// 4 pi`, exact by Sterbenz's lemma). `|x| = 2 pi`, whose `fmod` is a zero
/// carrying the sign of `x`, and larger or non-finite `x` take `%`.
#[inline]
pub fn rem_tau(x: f64) -> f64 {
    let a = x.abs();
    let r = if a < TAU {
        x
    } else if a > TAU && a < 2.0 * TAU {
        x - TAU.copysign(x)
    } else {
        x % TAU
    };
    if r < 0.0 {
        r + TAU
    } else {
        r
    }
}

/// `theta` reduced to `[0, 2 pi)`: `rem_euclid` alone rounds a tiny
/// negative angle up to `2 pi`, which would make one pose two.
pub fn wrap_angle(theta: f64) -> f64 {
    let t = rem_tau(theta);
    if t >= TAU {
        0.0
    } else {
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The angles with `lo <= alpha + beta cos(t) + gamma sin(t) <= hi`:
    /// the band in the form tests write by hand.
    fn between(alpha: f64, beta: f64, gamma: f64, lo: f64, hi: f64, slack: f64) -> AngleSet {
        let amp = (beta * beta + gamma * gamma).sqrt();
        AngleSet::sinusoid_band(alpha, amp, gamma.atan2(beta), lo, hi, slack)
    }

    fn value(a: f64, b: f64, g: f64, t: f64) -> f64 {
        a + b * t.cos() + g * t.sin()
    }

    #[test]
    fn rem_tau_is_rem_euclid_to_the_bit() {
        let same = |x: f64| {
            let (got, want) = (rem_tau(x), x.rem_euclid(TAU));
            assert!(
                got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()),
                "{x:e}: {got:e} vs {want:e}"
            );
        };
        let mut edges = vec![0.0, f64::MIN_POSITIVE, 5e-324, 1e-18, PI, 1e300];
        edges.extend([f64::INFINITY, f64::NAN, f64::MAX, f64::EPSILON]);
        for k in 1..=6 {
            let t = TAU * k as f64;
            edges.extend([t, t.next_up(), t.next_down(), t + 0.5, t - 0.5]);
        }
        // Arc parameters reduce by `2.0 * PI`, the same `f64` as `TAU`.
        assert_eq!((2.0 * PI).to_bits(), TAU.to_bits());
        for &e in &edges {
            same(e);
            same(-e);
        }
        let mut rng = crate::test_rng::Xorshift::new(0x51ed_2701_a3c4_9f13);
        for m in 0..200_000 {
            let scale = [1.0, 4.0, 8.0, 13.0, 30.0, 1e6][m % 6];
            same(rng.signed_unit() * scale);
        }
    }

    #[test]
    fn sinusoid_sets_hold_exactly_the_angles_that_satisfy_the_bounds() {
        // Dense sampling: every angle inside the bounds is in the set, and
        // every angle in the set is within the slack of the bounds.
        let cases = [
            (0.3, 1.0, 0.5, -0.2, 0.9),
            (0.0, -2.0, 1.0, -0.5, 0.5),
            (1.0, 0.5, -0.5, 0.0, 5.0),
            (0.0, 1.0, 0.0, -2.0, 2.0),
            (0.0, 1.0, 0.0, 1.5, 2.0),
            (0.0, 0.0, 0.0, -1.0, 1.0),
            (0.2, 0.0, 1.0, 0.9, 1.2),
        ];
        for (a, b, g, lo, hi) in cases {
            let set = between(a, b, g, lo, hi, 1e-12);
            for k in 0..20_000 {
                let t = TAU * k as f64 / 20_000.0;
                let v = value(a, b, g, t);
                if v >= lo + 1e-9 && v <= hi - 1e-9 {
                    assert!(set.contains(t), "{t} value {v} missing from {set:?}");
                }
                if set.contains(t) {
                    assert!(v >= lo - 1e-6 && v <= hi + 1e-6, "{t} value {v} in {set:?}");
                }
            }
        }
    }

    #[test]
    fn intersection_keeps_common_angles_only() {
        let a = between(0.0, 1.0, 0.0, 0.0, 1.0, 0.0); // |t| <= pi/2
        let b = between(0.0, 0.0, 1.0, 0.0, 1.0, 0.0); // t in [0, pi]
        let c = a.intersect(&b);
        assert!(c.contains(0.3) && c.contains(1.5));
        assert!(!c.contains(2.0) && !c.contains(6.0));
        assert!(AngleSet::empty().intersect(&a).is_empty());
        assert_eq!(AngleSet::full().intersect(&a), a);
    }

    #[test]
    fn intervals_across_zero_are_split() {
        let s = between(0.0, 1.0, 0.0, 0.9, 2.0, 0.0);
        assert_eq!(s.intervals().len(), 2);
        assert!(s.contains(0.0) && s.contains(TAU - 0.1) && !s.contains(PI));
        assert_eq!(wrap_angle(-1e-18), 0.0);
    }

    /// A set of intervals `[c - w, c + w]` around the given centres.
    fn bands(centres: &[(f64, f64)]) -> AngleSet {
        let mut s = AngleSet::empty();
        for &(c, w) in centres {
            s.add_wrapped(c - w, c + w);
        }
        s.normalise();
        s
    }

    #[test]
    fn meets_sees_every_stretch_that_holds_an_angle() {
        let s = bands(&[(1.0, 0.1), (3.0, 0.2), (6.2, 0.2)]);
        for k in 0..2000 {
            let lo = -7.0 + 14.0 * k as f64 / 2000.0;
            for w in [0.0, 0.05, 0.5, 3.0, TAU] {
                let sampled = (0..=400).any(|m| s.contains(wrap_angle(lo + w * m as f64 / 400.0)));
                if sampled {
                    assert!(s.meets(lo, lo + w), "[{lo}, {}] in {s:?}", lo + w);
                }
            }
        }
        assert!(!s.meets(1.5, 2.5) && !s.meets(1.5 - TAU, 2.5 - TAU));
    }

    #[test]
    fn covering_union_holds_both_sets_within_capacity() {
        let a = bands(&[
            (0.5, 0.05),
            (1.5, 0.05),
            (2.5, 0.05),
            (3.5, 0.05),
            (4.5, 0.05),
        ]);
        let b = bands(&[
            (1.0, 0.05),
            (2.0, 0.01),
            (3.0, 0.05),
            (4.0, 0.05),
            (5.5, 0.05),
        ]);
        let u = a.union_covering(&b);
        assert!(u.intervals().len() <= CAPACITY);
        for k in 0..20_000 {
            let t = TAU * k as f64 / 20_000.0;
            if a.contains(t) || b.contains(t) {
                assert!(u.contains(t), "{t} lost from {u:?}");
            }
        }
        // The narrowest gaps were filled, the widest kept.
        assert!(!u.contains(5.0));
        assert_eq!(a.union_covering(&AngleSet::empty()), a);
    }
}
