//! Clamp candidates on an arc segment (SPEC 8.5): the one file of the
//! clamp search that knows a segment is an arc (with [`super::arc_reach`],
//! which narrows its axis lines). Every point where a plunger axis line
//! crosses the posed grown circle is tested on its own normal.

use super::arc_reach::ArcReach;
use super::axes::{along, axis_normal, push_direction};
use super::{Accumulator, Candidate, ClampSearch, SetupContext};
use crate::checks::admissibility::Scratch;
use crate::checks::form_closure::wrench;
use crate::geometry::arc::GrownArc;
use crate::geometry::rounding::ceil_i64;
use crate::geometry::{EPS, V2};
use crate::segments::{arc_inward_normal, Segment};

impl ClampSearch<'_> {
    /// Candidates on an arc segment (SPEC 8.5): the points where each
    /// plunger axis line crosses the posed grown circle, each tested for
    /// span, angle and form closure on its own normal. Where more than one
    /// line crosses the circle only those [`arc_reach`] keeps are tried
    /// (one line is tested for less than the filter costs), and on each
    /// only the side facing
    /// the push: at the other point `q_d - C'_d` (along `d`, an axis) is
    /// `fl(C'_d + side half) - C'_d`, of the sign of `side` or zero since
    /// rounding is monotone, so `d . f <= 0 < eps` there (and at a
    /// tangency, `half = 0`, on both). The tests that remain are those of
    /// every point kept, the cheap form-closure test before the `atan2`
    /// of the inner one: the candidates are the same, in the same order.
    /// The cheapest test first: [`super::arc_reach::PosedMiddle::misses_each`]
    /// (one comparison), then whether any axis line crosses the circle.
    #[inline(always)]
    pub(super) fn arc_candidates(
        &self,
        ctx: &SetupContext,
        j: usize,
        seg: &Segment,
        (arc, piece): (&GrownArc, Option<&ArcReach>),
        acc: &mut Accumulator,
        scratch: &mut Scratch,
    ) {
        let pose = &ctx.setup.pose;
        let centre = pose.apply(arc.center);
        let rho = arc.radius;
        let convex = arc.is_convex();
        let y0 = self.setting.clamp.y0;
        // Without a piece (a test's reference search) every line across
        // the circle is tried.
        let middle = piece.map(|p| p.posed_middle(pose, arc.center, rho));
        // No normal of the piece makes a force the locators balance: every
        // point below would fail the form-closure test. A contact is
        // within `2 rho` of the centre along each axis, hence `|tau|`.
        // Tested before the rest of the piece is posed.
        let cap = middle.and_then(|m| m.normal_cap(convex));
        let reach = centre.x.abs() + centre.y.abs() + 2.0 * rho;
        if cap.is_some_and(|(mid, cos)| ctx.cone.excludes_cap(mid, cos, reach)) {
            return;
        }
        // The piece, its posed middle and the middle's miss threshold.
        let posed = piece
            .zip(middle)
            .map(|(p, m)| (p, m, m.miss_threshold(p, &self.window)));
        let missed = posed.map_or([false; 4], |(_, m, t)| m.misses_each(t, convex));
        for (k, missed) in (0..4u8).zip(missed) {
            if ctx.only_rotation.is_some_and(|ok| ok != k) || missed {
                continue;
            }
            // Axis line `line`: e . q - y0 = line. Whether one crosses the
            // circle is told from `e . C'` read off a coordinate: only a
            // zero's sign can differ from the product's, which `gc +- rho`
            // does not see.
            let across = along(k + 1, centre) - y0;
            let first = ceil_i64(across - rho);
            if first as f64 > across + rho {
                continue;
            }
            let d = push_direction(k);
            let e = axis_normal(k);
            let gc = e.dot(&centre) - y0;
            // One line at most across the circle: its point is tested for
            // less than the filter costs (posing the piece's ends, a dozen
            // products), and the filter only skips points the tests reject,
            // so the candidates are the same.
            let single = first.saturating_add(1) as f64 > across + rho;
            let lines = match posed {
                Some((p, m, _)) if !single => {
                    m.piece(p, pose)
                        .axis_lines(&self.window, k, convex, gc, rho)
                }
                _ => Some((gc - rho, gc + rho)),
            };
            let Some((lo, hi)) = lines else {
                continue;
            };
            // The window's centre: where the inward normal is `d`.
            let n = if convex { -d } else { d };
            let side = n.dot(&d);
            let mut line = first.max(ceil_i64(lo));
            while (line as f64) <= gc + rho && (line as f64) <= hi {
                let h = line as f64 - gc;
                let w2 = (rho - h.abs()) * (rho + h.abs());
                if w2 > 0.0 {
                    let half = w2.sqrt();
                    let q = centre + e * h + d * (side * half);
                    // Near tangency the two points merge: borderline.
                    let tangency = rho - h.abs();
                    if let Some((f, margin)) = self.arc_point(ctx, seg, arc, k, centre, q) {
                        let cand = Candidate {
                            segment: j,
                            rotation: k,
                            line,
                            q,
                            f,
                            margin: margin.min(tangency),
                        };
                        self.offer(ctx, &cand, acc, scratch);
                    }
                }
                line += 1;
            }
        }
    }

    /// SPEC 8.5's tests of one point `q` of an arc segment posed with
    /// its centre at `centre`: the inward normal there and the decision
    /// margin of a candidate before tangency, `None` when a test fails.
    #[inline(always)]
    fn arc_point(
        &self,
        ctx: &SetupContext,
        seg: &Segment,
        arc: &GrownArc,
        k: u8,
        centre: V2,
        q: V2,
    ) -> Option<(V2, f64)> {
        let f = arc_inward_normal(centre, arc.radius, arc.is_convex(), q);
        let angle_margin = self.angle_margin(k, f)?;
        let lam = ctx.lw.lambda(&wrench(q, f)).min() - EPS;
        if lam <= 0.0 {
            return None;
        }
        let inner = seg.inner_margin(seg.param_of(ctx.setup.pose.inverse_apply(q)));
        if inner <= 0.0 {
            return None;
        }
        Some((f, ctx.base_margin.min(inner).min(lam).min(angle_margin)))
    }
}
