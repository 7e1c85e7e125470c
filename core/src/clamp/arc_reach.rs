//! Which plunger axis lines can give an arc segment a clamp contact: a
//! sound filter ahead of SPEC 8.5's exact per-point tests, so that a
//! setup stops paying an `atan2` (the inner test) for every crossing of
//! every axis line with every posed arc, most of which fail.
//!
//! Seen from the arc's posed centre, a contact is a unit direction `v`.
//! The angle test (SPEC 4 (c)) passes only for `v` within the clamp angle
//! of `n` (`-d` on a convex arc, `d` on a concave one, `d` the push
//! direction), the inner test only on the segment's piece of the circle:
//! two arcs of directions. An axis line at offset `h` from the centre
//! (along the line normal `e`) meets the circle at `e . v = h / rho`, so
//! only the lines whose `h / rho` lies in the range of `e . v` over the
//! two arcs' intersection can give a candidate. The range's ends are
//! among the arcs' ends lying in the other arc, and `+-1` where `+-e`
//! lies in both. Both arcs are widened, far beyond the rounding of the
//! exact tests (see `PosedPiece::err`), so that the filter only skips
//! lines whose points the exact tests reject.
//!
//! The side of the line is decided exactly, not by the filter: the angle
//! test needs `d . f > eps`, and the point on the wrong side has
//! `d . f <= 0` in floating point too (see `ClampSearch::arc_candidates`).

use crate::geometry::{v2, EPS, V2};
use crate::poses::pose::Pose;
use crate::segments::{Feature, Segment};
use std::f64::consts::PI;

/// How much wider, in angle, the filter's window is than the angle
/// test's: its cosine gap ([`ClampWindow::tolerance`]) must exceed the
/// rounding of a contact's computed `d . f`, at least 4.5e-11 even at a
/// zero clamp angle (where `eps` alone opens the window by 4.5e-5 rad).
const WINDOW_SLACK: f64 = 1e-6;

/// The directions the angle test can accept, about the push direction:
/// one per setting, shared by every setup and arc.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ClampWindow {
    /// Cosine of the widened half-angle.
    cos: f64,
    /// Its sine.
    sin: f64,
    /// By how much a contact's computed `d . f` may be off before the
    /// widening stops covering it: `cos(angle) - cos(widened)`.
    tolerance: f64,
}

impl ClampWindow {
    /// The window for a clamp whose angle test is
    /// `d . f >= cos_max_angle - eps` and `d . f > eps`: a `d . f` below
    /// `max(cos_max_angle - eps, 0)` never passes. A NaN limit (no contact
    /// passes) gives the half circle, still sound.
    pub(crate) fn new(cos_max_angle: f64) -> ClampWindow {
        let limit = cos_max_angle - EPS;
        let floor = if limit >= 0.0 { limit.min(1.0) } else { 0.0 };
        let angle = floor.acos() + WINDOW_SLACK;
        let (sin, cos) = angle.sin_cos();
        ClampWindow {
            cos,
            sin,
            tolerance: floor - cos,
        }
    }
}

/// An arc segment's piece of its circle as directions from the centre,
/// part frame: computed once per part so that a setup only rotates it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ArcReach {
    /// The piece's middle.
    mid: V2,
    /// Cosine of the piece's half-angle (-1: the whole circle).
    cos_half: f64,
    /// The piece's ends (`s0`, `s1`).
    ends: [V2; 2],
    /// `1 / rho`: a setup's rounding bound then needs no division.
    inv_rho: f64,
}

impl ArcReach {
    /// The piece of an arc segment, `None` for a line.
    pub(crate) fn of(seg: &Segment) -> Option<ArcReach> {
        let Feature::Arc(arc) = &seg.feature else {
            return None;
        };
        let dir = |s: f64| {
            let (sn, cs) = arc.angle_at(s).sin_cos();
            v2(cs, sn)
        };
        let half = 0.5 * (seg.s1 - seg.s0) / arc.radius;
        Some(ArcReach {
            mid: dir(0.5 * (seg.s0 + seg.s1)),
            cos_half: if half >= PI { -1.0 } else { half.cos() },
            ends: [dir(seg.s0), dir(seg.s1)],
            inv_rho: 1.0 / arc.radius,
        })
    }

    /// The piece in the plate frame for one setup. `center` is the arc's
    /// centre in the part frame and `rho` its grown radius: with the pose
    /// they size the rounding the widening must cover.
    #[inline]
    pub(crate) fn posed(&self, pose: &Pose, center: V2, rho: f64) -> PosedPiece {
        let posed_center = pose.apply(center);
        let scale = posed_center.x.abs()
            + posed_center.y.abs()
            + pose.t.x.abs()
            + pose.t.y.abs()
            + center.x.abs()
            + center.y.abs()
            + rho;
        PosedPiece {
            mid: pose.rotate(self.mid),
            cos_half: self.cos_half,
            ends: [pose.rotate(self.ends[0]), pose.rotate(self.ends[1])],
            err: 1e-12 + 1e-14 * scale * self.inv_rho,
        }
    }
}

/// An [`ArcReach`] posed for one setup.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PosedPiece {
    mid: V2,
    cos_half: f64,
    ends: [V2; 2],
    /// A bound, with a wide margin, on how far rounding moves a contact's
    /// direction as the exact tests compute it (in angle, and in the
    /// cosine `d . f`): some ulps of the coordinates over the radius (the
    /// contact and the centre are both near the pose's translation, their
    /// difference is `rho`), about 45 times the few roundings on the way.
    err: f64,
}

impl PosedPiece {
    /// The axis lines that can give a contact passing the angle and inner
    /// tests, for window centre `n` (see the module doc) and the axis
    /// normal `e` (perpendicular unit axis vectors), as bounds `(lo, hi)`
    /// on the line index: `gc` is the posed centre's offset `e . C' - y0`
    /// and `rho` the radius. `None` when no line can.
    #[inline]
    pub(crate) fn axis_lines(
        &self,
        window: &ClampWindow,
        n: V2,
        e: V2,
        gc: f64,
        rho: f64,
    ) -> Option<(f64, f64)> {
        let (lo, hi) = self.offsets(window, n, e)?;
        // Covers the rounding of `line - gc` for any |gc| below 1e6.
        const LINE_SLACK: f64 = 1e-9;
        Some((gc + rho * lo - LINE_SLACK, gc + rho * hi + LINE_SLACK))
    }

    /// The range of `e . v` over the directions `v` of contacts that can
    /// pass both tests, widened by `err`.
    #[inline]
    fn offsets(&self, window: &ClampWindow, n: V2, e: V2) -> Option<(f64, f64)> {
        let err = self.err;
        if err > window.tolerance {
            // A tiny radius far from the origin: no sound filter.
            return Some((-1.0, 1.0));
        }
        let in_window = |v: V2| v.dot(&n) >= window.cos;
        let in_piece = |v: V2| v.dot(&self.mid) >= self.cos_half - err;
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let mut take = |x: f64| {
            lo = lo.min(x);
            hi = hi.max(x);
        };
        for v in self.ends {
            if in_window(v) {
                take(e.dot(&v));
            }
        }
        for side in [-1.0, 1.0] {
            if in_piece(n * window.cos + e * (side * window.sin)) {
                take(side * window.sin);
            }
            if in_window(e * side) && in_piece(e * side) {
                take(side);
            }
        }
        (lo <= hi).then_some((lo - err, hi + err))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::arc::GrownArc;
    use crate::geometry::rot90;
    use crate::segments::arc_inward_normal;
    use crate::test_rng::Xorshift;

    /// A random arc segment: centre up to 1000 from the origin, radius from
    /// 1e-3 to 50, any sweep and piece of it.
    fn random_segment(rng: &mut Xorshift) -> Segment {
        let mut u = || 0.5 * (rng.signed_unit() + 1.0);
        let scale = 10f64.powf(3.0 * u());
        let center = v2(scale * (2.0 * u() - 1.0), scale * (2.0 * u() - 1.0));
        let radius = 10f64.powf(-3.0 + 4.7 * u());
        let sweep = (2.0 * u() - 1.0) * 2.0 * PI;
        let arc = GrownArc {
            center,
            radius,
            start_angle: 2.0 * PI * u(),
            sweep,
        };
        let length = arc.length();
        let (a, b) = (u() * length, u() * length);
        Segment {
            edge: 0,
            s0: a.min(b),
            s1: a.max(b),
            feature: Feature::Arc(arc),
        }
    }

    /// Every crossing of an axis line with a posed arc that passes SPEC
    /// 8.5's angle and inner tests (computed as the clamp search computes
    /// them) lies on a line [`PosedPiece::offsets`] keeps, on the side the
    /// clamp search keeps: the filter never drops a candidate. Random
    /// arcs, poses and clamp angles; the angle limits include 0 and 90
    /// degrees.
    #[test]
    fn filter_keeps_every_point_the_exact_tests_pass() {
        let mut rng = Xorshift::new(0x2545_f491_4f6c_dd1d);
        let (mut passed, mut lines_all, mut lines_kept) = (0u64, 0u64, 0u64);
        for case in 0..40_000 {
            let seg = random_segment(&mut rng);
            let Feature::Arc(arc) = seg.feature else {
                unreachable!()
            };
            let theta = PI * (rng.signed_unit() + 1.0);
            let t = v2(20.0 * rng.signed_unit(), 20.0 * rng.signed_unit());
            let pose = Pose {
                theta,
                cos: theta.cos(),
                sin: theta.sin(),
                t,
            };
            let degrees = match case % 4 {
                0 => 0.0,
                1 => 90.0,
                _ => 90.0 * (rng.signed_unit() + 1.0) / 2.0,
            };
            let limit = f64::to_radians(degrees).cos();
            let window = ClampWindow::new(limit);
            let piece = ArcReach::of(&seg)
                .expect("an arc")
                .posed(&pose, arc.center, arc.radius);
            let (centre, rho, convex) = (pose.apply(arc.center), arc.radius, arc.is_convex());
            let y0 = rng.signed_unit();
            for k in 0..4u8 {
                let d = rot90(k, v2(1.0, 0.0));
                let e = rot90(k, v2(0.0, 1.0));
                let n = if convex { -d } else { d };
                let gc = e.dot(&centre) - y0;
                let kept = piece.axis_lines(&window, n, e, gc, rho);
                let mut line = (gc - rho).ceil() as i64;
                while (line as f64) <= gc + rho {
                    let at = line as f64;
                    let h = at - gc;
                    line += 1;
                    lines_all += 1;
                    let keeps = kept.is_some_and(|(lo, hi)| at >= lo && at <= hi);
                    lines_kept += u64::from(keeps);
                    let w2 = (rho - h.abs()) * (rho + h.abs());
                    if w2 < 0.0 {
                        continue;
                    }
                    let half = w2.sqrt();
                    for side in [-1.0, 1.0] {
                        let q = centre + e * h + d * (side * half);
                        let f = arc_inward_normal(centre, rho, convex, q);
                        let c = d.dot(&f);
                        let angle_ok = c > EPS && c >= limit - EPS;
                        let inner = seg.inner_margin(seg.param_of(pose.inverse_apply(q)));
                        if angle_ok && inner > 0.0 {
                            passed += 1;
                            assert!(keeps, "case {case} k {k} h {h} {kept:?} rho {rho}");
                            assert_eq!(side, n.dot(&d), "case {case}: the other side passed");
                        }
                    }
                }
            }
        }
        // The test saw many candidates, and the filter dropped most lines.
        assert!(passed > 20_000, "{passed}");
        assert!(lines_kept * 2 < lines_all, "{lines_kept} of {lines_all}");
    }
}
