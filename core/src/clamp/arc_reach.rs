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

use super::axes::along;
use crate::geometry::arc::GrownArc;
use crate::geometry::{v2, EPS, V2};
use crate::poses::pose::Pose;
use crate::segments::Segment;
use std::f64::consts::PI;

/// How much wider, in angle, the filter's window is than the angle
/// test's: its cosine gap ([`ClampWindow::tolerance`]) must exceed the
/// rounding of a contact's computed `d . f`, at least 4.5e-11 even at a
/// zero clamp angle (where `eps` alone opens the window by 4.5e-5 rad).
const WINDOW_SLACK: f64 = 1e-6;

/// How much further apart, in angle, than the window's and the piece's
/// half-angles together a piece's middle and a window's centre must be
/// before [`PosedMiddle::misses_each`] gives the rotation up: above the angle
/// by which [`PosedPiece::offsets`]'s widening opens a piece (`err` in the
/// cosine is at most `1.5 sqrt(2 err)` in angle, 6.7e-5 at
/// [`REACH_ERR`]), and far above the rounding of one dot product.
const REACH_SLACK: f64 = 1e-4;

/// The largest `err` with which [`PosedMiddle::misses_each`] decides.
const REACH_ERR: f64 = 1e-9;

/// `misses` decides only when the half-angles and slack add up to at most
/// this: away from a half turn, where the cosine flattens out.
const REACH_MAX: f64 = PI - 0.1;

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
    /// The widened half-angle plus [`REACH_SLACK`], its cosine and sine.
    reach: f64,
    reach_cos: f64,
    reach_sin: f64,
    /// The angle test itself, `c > eps && c >= cos_max_angle - eps` for a
    /// cosine `c`, as the one comparison `c >= pass` (see [`angle_pass`]).
    pub(super) pass: f64,
}

/// The smallest cosine the angle test `c > eps && c >= limit` passes,
/// so that the test is `c >= angle_pass(limit)` for every `c`: no `f64`
/// lies strictly between `eps` and its successor, so `c > eps` is
/// `c >= next_up(eps)`, and two lower bounds are their maximum. A NaN
/// `limit` passes no `c`, nor does a NaN bound (`max` would drop it).
pub(super) fn angle_pass(limit: f64) -> f64 {
    if limit.is_nan() {
        f64::NAN
    } else {
        limit.max(EPS.next_up())
    }
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
        let reach = angle + REACH_SLACK;
        let (reach_sin, reach_cos) = reach.sin_cos();
        ClampWindow {
            cos,
            sin,
            tolerance: floor - cos,
            reach,
            reach_cos,
            reach_sin,
            pass: angle_pass(limit),
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
    /// The piece's half-angle and its sine.
    half: f64,
    sin_half: f64,
    /// The piece's ends (`s0`, `s1`).
    ends: [V2; 2],
    /// `1 / rho`: a setup's rounding bound then needs no division.
    inv_rho: f64,
}

impl ArcReach {
    /// The piece of an arc segment, `None` for a line.
    #[cfg(test)]
    pub(crate) fn of(seg: &Segment) -> Option<ArcReach> {
        use crate::segments::Feature;
        match &seg.feature {
            Feature::Arc(arc) => Some(Self::on(seg, arc)),
            Feature::Line(_) => None,
        }
    }

    /// The piece of `seg`, an arc segment on `arc`.
    pub(crate) fn on(seg: &Segment, arc: &GrownArc) -> ArcReach {
        let dir = |s: f64| {
            let (sn, cs) = arc.angle_at(s).sin_cos();
            v2(cs, sn)
        };
        let half = 0.5 * (seg.s1 - seg.s0) / arc.radius;
        ArcReach {
            mid: dir(0.5 * (seg.s0 + seg.s1)),
            cos_half: if half >= PI { -1.0 } else { half.cos() },
            half,
            sin_half: half.sin(),
            ends: [dir(seg.s0), dir(seg.s1)],
            inv_rho: 1.0 / arc.radius,
        }
    }

    /// The piece in the plate frame for one setup. `center` is the arc's
    /// centre in the part frame and `rho` its grown radius: with the pose
    /// they size the rounding the widening must cover. `window` gives
    /// [`PosedMiddle::misses_each`] its threshold. The search takes the two
    /// steps apart, the force cone between them.
    #[cfg(test)]
    pub(crate) fn posed(
        &self,
        pose: &Pose,
        center: V2,
        rho: f64,
        window: &ClampWindow,
    ) -> PosedPiece {
        let middle = self.posed_middle(pose, center, rho);
        PosedPiece {
            reach: middle.miss_threshold(self, window),
            ..middle.piece(self, pose)
        }
    }

    /// The first step of [`Self::posed`]: the middle and the rounding
    /// bound, all [`PosedMiddle::normal_cap`] needs, so that an arc the
    /// force cone drops is never posed further. The two steps make the
    /// same roundings as one.
    #[inline]
    pub(crate) fn posed_middle(&self, pose: &Pose, center: V2, rho: f64) -> PosedMiddle {
        let posed_center = pose.apply(center);
        let scale = posed_center.x.abs()
            + posed_center.y.abs()
            + pose.t.x.abs()
            + pose.t.y.abs()
            + center.x.abs()
            + center.y.abs()
            + rho;
        PosedMiddle {
            mid: pose.rotate(self.mid),
            cos_half: self.cos_half,
            err: 1e-12 + 1e-14 * scale * self.inv_rho,
        }
    }
}

/// An [`ArcReach`]'s middle posed for one setup (see
/// [`ArcReach::posed_middle`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct PosedMiddle {
    mid: V2,
    cos_half: f64,
    /// [`PosedPiece`]'s `err`.
    err: f64,
}

impl PosedMiddle {
    /// The rest of [`ArcReach::posed`]: the piece's ends, for
    /// [`PosedPiece::axis_lines`] (the search takes the threshold of
    /// [`PosedMiddle::misses_each`] from [`Self::miss_threshold`]).
    #[inline]
    pub(crate) fn piece(&self, reach: &ArcReach, pose: &Pose) -> PosedPiece {
        PosedPiece {
            mid: self.mid,
            cos_half: self.cos_half,
            ends: [pose.rotate(reach.ends[0]), pose.rotate(reach.ends[1])],
            err: self.err,
            #[cfg(test)]
            reach: f64::NEG_INFINITY,
        }
    }

    /// [`Self::misses_each`]'s threshold (a piece's `reach`), worked out without
    /// posing the piece's ends: a search that tests a rotation's lines
    /// without [`PosedPiece::axis_lines`] never needs them.
    #[inline]
    pub(crate) fn miss_threshold(&self, reach: &ArcReach, window: &ClampWindow) -> f64 {
        let err = self.err;
        // Where `offsets` decides nothing (`err` above the window's
        // tolerance), neither does `misses`.
        let decides = err <= REACH_ERR && err <= window.tolerance;
        if decides && reach.half + window.reach <= REACH_MAX {
            // cos(half + reach), a few ulps off.
            reach.cos_half * window.reach_cos - reach.sin_half * window.reach_sin
        } else {
            f64::NEG_INFINITY
        }
    }

    /// Whether each rotation `k` (window centre `n`, as in [`PosedPiece::axis_lines`])
    /// surely has no axis line, in one comparison where [`PosedPiece::offsets`]
    /// makes a dozen: the piece's middle is further from `n` than the
    /// window's widened half-angle `A`, the piece's `h` and [`REACH_SLACK`]
    /// together. A direction `offsets` takes is within `A` of `n` (an end
    /// or a window edge, `v . n >= cos A`, or `e` when `A >= 90` degrees)
    /// and within `h + 1.5 sqrt(2 err)` of the middle (its widened piece
    /// test, `err <= REACH_ERR`; above the window's tolerance `offsets`
    /// takes every line, and `misses` none), so it would find none: the lines kept are
    /// the same (`misses_only_where_offsets_finds_none`). The margin of
    /// `REACH_SLACK` over those angles is at least 2.8e-9 in the cosine,
    /// against a few ulps of rounding here.
    /// `threshold` is [`Self::miss_threshold`]. For the four rotations at
    /// once (`k` a constant in each, the coordinate is read directly).
    #[inline(always)]
    pub(crate) fn misses_each(&self, threshold: f64, convex: bool) -> [bool; 4] {
        [0u8, 1, 2, 3].map(|k| misses(self.mid, threshold, k, convex))
    }

    /// The inward normals `f` of contacts that can pass the inner test, as
    /// a cap `f . mid >= cos` about the piece's middle normal `mid`
    /// (`-mid` of the directions on a `convex` arc): the piece widened by
    /// `err` as [`PosedPiece::offsets`] widens it. `None` where `err` is not
    /// small enough to decide ([`REACH_ERR`], as for [`PosedMiddle::misses_each`]).
    #[inline]
    pub(crate) fn normal_cap(&self, convex: bool) -> Option<(V2, f64)> {
        let sign = if convex { -1.0 } else { 1.0 };
        (self.err <= REACH_ERR).then(|| (self.mid * sign, self.cos_half - self.err))
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
    /// Below this `n . mid`, the window about `n` misses the piece
    /// (see [`PosedMiddle::misses_each`]); minus infinity when that is not decided.
    /// The search reads it off [`PosedMiddle::miss_threshold`] instead.
    #[cfg(test)]
    reach: f64,
}

impl PosedPiece {
    /// [`PosedMiddle::misses_each`] with the threshold this piece holds.
    #[cfg(test)]
    pub(crate) fn misses(&self, k: u8, convex: bool) -> bool {
        misses(self.mid, self.reach, k, convex)
    }

    /// The axis lines that can give a contact passing the angle and inner
    /// tests for clamp rotation `k` (window centre `n`: `-d` on a `convex`
    /// arc, `d` on a concave one, see the module doc), as bounds
    /// `(lo, hi)` on the line index: `gc` is the posed centre's offset
    /// `e . C' - y0` and `rho` the radius. `None` when no line can.
    #[inline]
    pub(crate) fn axis_lines(
        &self,
        window: &ClampWindow,
        k: u8,
        convex: bool,
        gc: f64,
        rho: f64,
    ) -> Option<(f64, f64)> {
        let (lo, hi) = self.offsets(window, k, convex)?;
        // Covers the rounding of `line - gc` for any |gc| below 1e6.
        const LINE_SLACK: f64 = 1e-9;
        Some((gc + rho * lo - LINE_SLACK, gc + rho * hi + LINE_SLACK))
    }

    /// The range of `e . v` over the directions `v` of contacts that can
    /// pass both tests, widened by `err`. `n` and `e` are unit axis
    /// vectors, so every dot product with them is a coordinate read off
    /// ([`along`]), and those of the window's edges `n cos + e side sin`
    /// with `mid` are `cos (n . mid) + side sin (e . mid)`: the same
    /// roundings as the vector products, whose other terms are zeros
    /// (`e . n` among them). The values are the vector formulas' but for
    /// the sign of a zero, which the comparisons and the non-zero `err`
    /// added do not see (`offsets_match_the_vector_formulas`).
    #[inline]
    fn offsets(&self, window: &ClampWindow, k: u8, convex: bool) -> Option<(f64, f64)> {
        let err = self.err;
        if err > window.tolerance {
            // A tiny radius far from the origin: no sound filter.
            return Some((-1.0, 1.0));
        }
        let sign = if convex { -1.0 } else { 1.0 };
        let normal = |v: V2| sign * along(k, v);
        let across = |v: V2| along(k + 1, v);
        let floor = self.cos_half - err;
        let (mid_n, mid_e) = (normal(self.mid), across(self.mid));
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let mut take = |x: f64| {
            lo = lo.min(x);
            hi = hi.max(x);
        };
        for v in self.ends {
            if normal(v) >= window.cos {
                take(across(v));
            }
        }
        for side in [-1.0, 1.0] {
            // The window's edge on this side, in the piece.
            if window.cos * mid_n + side * window.sin * mid_e >= floor {
                take(side * window.sin);
            }
            // `side e`, in the window (`e . n = 0`) and in the piece.
            if 0.0 >= window.cos && side * mid_e >= floor {
                take(side);
            }
        }
        (lo <= hi).then_some((lo - err, hi + err))
    }
}

/// [`PosedMiddle::misses_each`] of a piece whose middle direction is `mid`.
#[inline(always)]
fn misses(mid: V2, threshold: f64, k: u8, convex: bool) -> bool {
    let sign = if convex { -1.0 } else { 1.0 };
    sign * along(k, mid) < threshold
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::checks::form_closure::{wrench, LocatorWrenches};
    use crate::geometry::rot90;
    use crate::segments::arc_inward_normal;
    use crate::segments::Feature;
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

    /// The one comparison `c >= angle_pass(limit)` decides as the angle
    /// test `c > eps && c >= limit` for every cosine `c`, with `limit =
    /// cos_max_angle - eps` for clamp angles up to a half turn and the
    /// limits and cosines at the boundaries: `eps` and its neighbours,
    /// each limit and its neighbours, zeros of both signs, infinities and
    /// NaN.
    #[test]
    fn angle_pass_decides_as_the_angle_test() {
        let mut rng = Xorshift::new(0x3c6e_f372_fe94_f82b);
        let mut limits = vec![
            EPS,
            EPS.next_up(),
            EPS.next_down(),
            2.0 * EPS,
            0.0,
            -0.0,
            -EPS,
            1.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        for degrees in [0.0, 45.0, 89.9999, 90.0, 135.0, 180.0] {
            limits.push(f64::to_radians(degrees).cos() - EPS);
        }
        for _ in 0..2_000 {
            let cos_max_angle = 1.5 * rng.signed_unit();
            limits.push(cos_max_angle - EPS);
        }
        let (mut passed, mut failed) = (0u64, 0u64);
        for &limit in &limits {
            let pass = angle_pass(limit);
            let mut cs = vec![
                EPS,
                EPS.next_up(),
                EPS.next_down(),
                limit,
                limit.next_up(),
                limit.next_down(),
                0.0,
                -0.0,
                1.0,
                -1.0,
                f64::NAN,
                f64::INFINITY,
                f64::NEG_INFINITY,
            ];
            cs.extend((0..200).map(|_| rng.signed_unit()));
            for c in cs {
                let want = c > EPS && c >= limit;
                assert_eq!(c >= pass, want, "c {c:e} limit {limit:e}");
                passed += u64::from(want);
                failed += u64::from(!want);
            }
        }
        // The window's own `pass` is this one.
        let window = ClampWindow::new(0.5);
        assert_eq!(window.pass.to_bits(), angle_pass(0.5 - EPS).to_bits());
        assert!(passed > 100_000 && failed > 100_000, "{passed} {failed}");
    }

    /// [`PosedPiece::offsets`] as first written, with the vectors `n` and
    /// `e` (the module doc's formulas): the reference it must equal.
    fn vector_offsets(
        piece: &PosedPiece,
        window: &ClampWindow,
        n: V2,
        e: V2,
    ) -> Option<(f64, f64)> {
        let err = piece.err;
        if err > window.tolerance {
            return Some((-1.0, 1.0));
        }
        let in_window = |v: V2| v.dot(&n) >= window.cos;
        let in_piece = |v: V2| v.dot(&piece.mid) >= piece.cos_half - err;
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let mut take = |x: f64| {
            lo = lo.min(x);
            hi = hi.max(x);
        };
        for v in piece.ends {
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

    /// The offsets read off coordinates equal the vector formulas' bit
    /// for bit (a zero's sign aside), so the filter keeps the lines it
    /// kept: random arcs and poses, clamp angles from 0 to 180 degrees
    /// (windows past a half turn take the `side e` branch), pieces from
    /// a sliver to the whole circle, and poses at exact quarter turns
    /// (zero coordinates).
    #[test]
    fn offsets_match_the_vector_formulas() {
        let mut rng = Xorshift::new(0x1d87_2b41_55a3_90c7);
        let mut seen = [0u64; 2];
        for case in 0..40_000 {
            let seg = random_segment(&mut rng);
            let Feature::Arc(arc) = seg.feature else {
                unreachable!()
            };
            let theta = match case % 5 {
                0 => PI * f64::from(case % 4) / 2.0,
                _ => PI * (rng.signed_unit() + 1.0),
            };
            let pose = Pose {
                theta,
                cos: theta.cos(),
                sin: theta.sin(),
                t: v2(20.0 * rng.signed_unit(), 20.0 * rng.signed_unit()),
            };
            let degrees = match case % 4 {
                0 => 0.0,
                1 => 90.0,
                _ => 90.0 * (rng.signed_unit() + 1.0),
            };
            let window = ClampWindow::new(f64::to_radians(degrees).cos());
            let piece = ArcReach::of(&seg)
                .expect("an arc")
                .posed(&pose, arc.center, arc.radius, &window);
            for k in 0..4u8 {
                let d = rot90(k, v2(1.0, 0.0));
                let e = rot90(k, v2(0.0, 1.0));
                for convex in [false, true] {
                    let n = if convex { -d } else { d };
                    let want = vector_offsets(&piece, &window, n, e);
                    let got = piece.offsets(&window, k, convex);
                    assert_eq!(got, want, "case {case} k {k} convex {convex}");
                    seen[usize::from(want.is_some())] += 1;
                }
            }
        }
        // Both outcomes, many times.
        assert!(seen[0] > 10_000 && seen[1] > 10_000, "{seen:?}");
    }

    /// Locators whose force cone has an edge near `edge` (a force
    /// direction): the first normal is `-edge` turned by `10^-exp` rad,
    /// the others turned further the same way, so `-edge` is near the
    /// cone's boundary; points within 30 of the origin.
    fn locators_near(rng: &mut Xorshift, edge: V2, exp: f64) -> Option<LocatorWrenches> {
        let base = (-edge.y).atan2(-edge.x);
        let turn = rng.signed_unit().signum();
        let tilt = 10f64.powf(-exp) * turn;
        let angles = [
            tilt,
            tilt + turn * 1.5 * (rng.signed_unit() + 1.0),
            rng.signed_unit() * PI,
        ];
        let ws = angles.map(|a| {
            let n = v2((base + a).cos(), (base + a).sin());
            wrench(v2(rng.signed_unit(), rng.signed_unit()) * 30.0, n)
        });
        LocatorWrenches::new(ws)
    }

    /// [`ForceCone::excludes_cap`] with [`PosedMiddle::normal_cap`] drops an
    /// arc only where no contact on its posed circle passes both the
    /// inner test and the form-closure test (`lambda > eps`) as the clamp
    /// search computes them: random arcs, poses and locators, many with
    /// a cone edge a hair from the cap's edge, contacts near the piece's
    /// ends and at random.
    #[test]
    fn force_cone_drops_only_arcs_without_a_closing_contact() {
        let mut rng = Xorshift::new(0xbb67_ae85_84ca_a73b);
        let (mut dropped, mut closing) = (0u64, 0u64);
        for case in 0..40_000 {
            let seg = random_segment(&mut rng);
            let Feature::Arc(arc) = seg.feature else {
                unreachable!()
            };
            let theta = PI * (rng.signed_unit() + 1.0);
            let pose = Pose {
                theta,
                cos: theta.cos(),
                sin: theta.sin(),
                t: v2(20.0 * rng.signed_unit(), 20.0 * rng.signed_unit()),
            };
            let reach = ArcReach::of(&seg).expect("an arc");
            let (rho, convex) = (arc.radius, arc.is_convex());
            let Some((mid, cos)) = reach
                .posed_middle(&pose, arc.center, rho)
                .normal_cap(convex)
            else {
                continue;
            };
            // A cap edge, or a random force direction.
            let edge = if case % 4 == 0 {
                let a = PI * rng.signed_unit();
                v2(a.cos(), a.sin())
            } else {
                let half = cos.clamp(-1.0, 1.0).acos() * rng.signed_unit().signum();
                let a = mid.y.atan2(mid.x) + half;
                v2(a.cos(), a.sin())
            };
            let exp = 3.0 + 13.0 * rng.signed_unit().abs();
            let Some(lw) = locators_near(&mut rng, edge, exp) else {
                continue;
            };
            let centre = pose.apply(arc.center);
            let excluded =
                lw.force_cone()
                    .excludes_cap(mid, cos, centre.x.abs() + centre.y.abs() + 2.0 * rho);
            dropped += u64::from(excluded);
            // Contacts at the piece's ends (a hair either side) and inside.
            let (a0, a1) = (arc.angle_at(seg.s0), arc.angle_at(seg.s1));
            for i in 0..24 {
                let a = match i % 3 {
                    0 => a0 + 1e-9 * rng.signed_unit(),
                    1 => a1 + 1e-9 * rng.signed_unit(),
                    _ => a0 + (a1 - a0) * 0.5 * (rng.signed_unit() + 1.0),
                } + theta;
                let q = centre + v2(a.cos(), a.sin()) * rho;
                let f = arc_inward_normal(centre, rho, convex, q);
                let inner = seg.inner_margin(seg.param_of(pose.inverse_apply(q)));
                let lam = lw.lambda(&wrench(q, f)).min() - EPS;
                if inner > 0.0 && lam > 0.0 {
                    closing += 1;
                    assert!(!excluded, "case {case}: q {q} f {f} lambda {lam}");
                }
            }
        }
        // Both outcomes, many times.
        assert!(dropped > 5_000 && closing > 5_000, "{dropped} {closing}");
    }

    /// [`PosedMiddle::misses_each`] gives a rotation up only where
    /// [`PosedPiece::offsets`] finds no line, so the lines tried are the
    /// same: random arcs, poses and clamp angles, and poses turning the
    /// piece's middle to just inside and outside the threshold angle
    /// `h + A + REACH_SLACK` from each window's centre.
    #[test]
    fn misses_only_where_offsets_finds_none() {
        let mut rng = Xorshift::new(0x6a09_e667_f3bc_c908);
        let (mut missed, mut near) = (0u64, 0u64);
        for case in 0..40_000 {
            let seg = random_segment(&mut rng);
            let Feature::Arc(arc) = seg.feature else {
                unreachable!()
            };
            let reach = ArcReach::of(&seg).expect("an arc");
            let degrees = match case % 4 {
                0 => 0.0,
                1 => 90.0,
                _ => 90.0 * (rng.signed_unit() + 1.0),
            };
            let window = ClampWindow::new(f64::to_radians(degrees).cos());
            let k = (case % 4) as u8;
            let convex = arc.is_convex();
            // The angle of the part-frame middle, and where window k's
            // centre points in the plate frame.
            let mid_angle = reach.mid.y.atan2(reach.mid.x);
            let centre_angle = f64::from(k) * PI / 2.0 + if convex { PI } else { 0.0 };
            let threshold = reach.half + window.reach;
            let theta = if case % 2 == 0 && threshold < PI {
                // Just inside or outside the threshold, either side.
                let off = threshold * (1.0 + 1e-7 * rng.signed_unit());
                near += 1;
                centre_angle - mid_angle + off * rng.signed_unit().signum()
            } else {
                PI * (rng.signed_unit() + 1.0)
            };
            let pose = Pose {
                theta,
                cos: theta.cos(),
                sin: theta.sin(),
                t: v2(20.0 * rng.signed_unit(), 20.0 * rng.signed_unit()),
            };
            let piece = reach.posed(&pose, arc.center, arc.radius, &window);
            if piece.misses(k, convex) {
                missed += 1;
                assert_eq!(piece.offsets(&window, k, convex), None, "case {case}");
            }
        }
        assert!(missed > 5_000 && near > 10_000, "{missed} {near}");
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
                .posed(&pose, arc.center, arc.radius, &window);
            let (centre, rho, convex) = (pose.apply(arc.center), arc.radius, arc.is_convex());
            let y0 = rng.signed_unit();
            for k in 0..4u8 {
                let d = rot90(k, v2(1.0, 0.0));
                let e = rot90(k, v2(0.0, 1.0));
                let n = if convex { -d } else { d };
                let gc = e.dot(&centre) - y0;
                let kept = piece.axis_lines(&window, k, convex, gc, rho);
                let mut line = (gc - rho).ceil() as i64;
                while (line as f64) <= gc + rho {
                    let at = line as f64;
                    let h = at - gc;
                    line += 1;
                    lines_all += 1;
                    let keeps = !piece.misses(k, convex)
                        && kept.is_some_and(|(lo, hi)| at >= lo && at <= hi);
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
