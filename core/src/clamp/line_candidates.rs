//! Clamp candidates on a straight segment (SPEC 4): the one file of the
//! clamp search that knows a segment is a line. The normal is the same
//! all along, so the angle test is made once per rotation, and the
//! form-closure interval is exact; [`super::ClampSearch`] picks this or
//! [`super::arc_candidates`] by the segment's feature, in one place.

use super::axes::along;
use super::{Accumulator, Candidate, ClampSearch, SetupContext};
use crate::checks::admissibility::Scratch;
use crate::checks::form_closure::wrench;
use crate::geometry::rounding::ceil_i64;
use crate::geometry::{EPS, V2};
use crate::segments::{LineFeature, Segment};

impl ClampSearch<'_> {
    /// Candidates on a straight segment: the form-closure interval is exact
    /// (SPEC 4), and the normal is the same all along, so the angle test
    /// is made once per rotation. The force cone test is the caller's
    /// (`ClampSearch::segment_candidates`), made before the segment is read.
    #[inline(always)]
    pub(super) fn line_candidates(
        &self,
        ctx: &SetupContext,
        j: usize,
        seg: &Segment,
        line: &LineFeature,
        acc: &mut Accumulator,
        scratch: &mut Scratch,
    ) {
        let pose = &ctx.setup.pose;
        let (s_lo, s_hi) = (seg.s0 + EPS, seg.s1 - EPS);
        let f = -pose.rotate(line.n);
        let q0 = pose.apply(line.origin);
        let dq = pose.rotate(line.u);
        // The rotations whose angle test passes, a bit each; the margins
        // only for the candidates scored.
        let passing = self.angle_passes(f, ctx.only_rotation);
        if passing == 0 {
            return;
        }
        let rotations = move || (0..4u8).filter(move |k| passing >> k & 1 != 0);
        // No axis line across the whole segment, none across its interval
        // (within it, see `axis_span`): the interval need not be solved.
        let crossed = rotations().any(|k| {
            let (_, _, gmin, gmax) = self.axis_span(k, q0, dq, s_lo, s_hi);
            ceil_i64(gmin) as f64 <= gmax
        });
        if !crossed {
            return;
        }
        let Some((lo, hi)) = ctx.lw.clamp_interval(q0, dq, f, s_lo, s_hi) else {
            return;
        };
        for k in rotations() {
            let (g0, g1, gmin, gmax) = self.axis_span(k, q0, dq, lo, hi);
            let mut line = ceil_i64(gmin);
            while (line as f64) <= gmax {
                let s = (line as f64 - g0) / g1;
                if s > lo && s < hi {
                    if ctx.count_only.get() == Some(true) {
                        // What `offer` would do, without the candidate.
                        acc.counts.candidates += 1;
                    } else {
                        let q = q0 + dq * s;
                        let lam = ctx.lw.lambda(&wrench(q, f));
                        let cand = Candidate {
                            segment: j,
                            rotation: k,
                            line,
                            q,
                            f,
                            margin: ctx
                                .base_margin
                                .min(seg.inner_margin(s))
                                .min(lam.min() - EPS)
                                .min(self.angle_cos_margin(along(k, f))),
                        };
                        self.offer(ctx, &cand, acc, scratch);
                    }
                }
                line += 1;
            }
        }
    }

    /// The rotations `k` (bit `k`) whose push direction passes SPEC 4 (c)'s
    /// angle test against the normal `f`, [`ClampSearch::angle_margin`]'s
    /// test for the four at once: its cosines are `f`'s coordinates and
    /// their negations, each tested by one comparison (`ClampWindow`'s
    /// `pass`). Only `only` if given (re-deriving one fixture).
    #[inline(always)]
    pub(super) fn angle_passes(&self, f: V2, only: Option<u8>) -> u8 {
        let pass = self.window.pass;
        let mut passing = 0;
        for (k, c) in [f.x, f.y, -f.x, -f.y].into_iter().enumerate() {
            passing |= u8::from(c >= pass) << k;
        }
        match only {
            Some(k) if k < 4 => passing & 1 << k,
            Some(_) => 0,
            None => passing,
        }
    }

    /// The axis lines of rotation `k` (`e . q - y0 = line`) along the
    /// contacts `q0 + s dq`, `s` in `[lo, hi]`: `g(s) = g0 + g1 s` and
    /// the range of `g` there. Each step rounds monotonically in `s`, so a
    /// narrower `[lo, hi]` gives a range within this one, bit for bit.
    #[inline(always)]
    fn axis_span(&self, k: u8, q0: V2, dq: V2, lo: f64, hi: f64) -> (f64, f64, f64, f64) {
        let e = super::axes::axis_normal(k);
        let g0 = e.dot(&q0) - self.setting.clamp.y0;
        let g1 = e.dot(&dq);
        let (ga, gb) = (g0 + g1 * lo, g0 + g1 * hi);
        (g0, g1, ga.min(gb), ga.max(gb))
    }
}
