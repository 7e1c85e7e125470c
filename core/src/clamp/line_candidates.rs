//! Clamp candidates on a straight segment (SPEC 4): the one file of the
//! clamp search that knows a segment is a line. The normal is the same
//! all along, so the angle test is made once per rotation, and the
//! form-closure interval is exact; [`super::ClampSearch`] picks this or
//! [`super::arc_candidates`] by the segment's feature, in one place.

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
        // The cosines that pass the angle test; the margins only for the
        // candidates scored.
        let mut cosines = [None; 4];
        let mut any = false;
        for (k, c) in (0..4u8).zip(cosines.iter_mut()) {
            if ctx.only_rotation.is_none_or(|ok| ok == k) {
                *c = self.angle_cos(k, f);
                any |= c.is_some();
            }
        }
        if !any {
            return;
        }
        // No axis line across the whole segment, none across its interval
        // (within it, see `axis_span`): the interval need not be solved.
        let crossed = (0..4u8).zip(cosines).any(|(k, c)| {
            c.is_some() && {
                let (_, _, gmin, gmax) = self.axis_span(k, q0, dq, s_lo, s_hi);
                ceil_i64(gmin) as f64 <= gmax
            }
        });
        if !crossed {
            return;
        }
        let Some((lo, hi)) = ctx.lw.clamp_interval(q0, dq, f, s_lo, s_hi) else {
            return;
        };
        for (k, cosine) in (0..4u8).zip(cosines) {
            let Some(cosine) = cosine else {
                continue;
            };
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
                                .min(self.angle_cos_margin(cosine)),
                        };
                        self.offer(ctx, &cand, acc, scratch);
                    }
                }
                line += 1;
            }
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
