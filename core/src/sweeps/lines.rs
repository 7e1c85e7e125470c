//! The sweep when the pivot is two lines, the common case and the only
//! one of polygons.
//!
//! With `L1` at the origin on grown line `a` and `L2` on grown line `b`, the
//! part has one degree of freedom left. Over the angles at which both
//! contacts stay on their segments, segment `c` sweeps a region of the
//! plate; `L3` must be a lattice point of that region. The annuli that
//! pruned before bound only the distances to `L1` and `L2`, so most lattice
//! points they let through gave poses that failed the segment test (about
//! 50 pose solutions per setup kept on `housing-57`).
//!
//! The region is covered by quadrilaterals grown by a margin, each exact up
//! to the margin: for a piece `[t0, t1]` of the angle set, every point of
//! `c` moves along a smooth path whose distance from its chord is at most
//! `(t1 - t0)^2 / 8` times a bound on its second derivative, and the chords
//! of all points of `c` fill the convex hull of `c` posed at `t0` and `t1`.
//! So no setup is lost; the pose solver and the segment test still decide.

use super::pieces::{LinePiece, Quad, ThirdPiece, MAX_CHORDS, QUAD_SLACK, S_SLACK};
use crate::geometry::angle_set::{AngleSet, CAPACITY as ANGLE_SET_CAPACITY};
use crate::geometry::rounding::ceil;
use crate::geometry::{cross, rot, EPS, V2};

/// Angle slack of the angle sets, radians.
const ANGLE_SLACK: f64 = 1e-7;

/// Largest margin a piece may add around its quadrilateral (lattice
/// units): smaller means more pieces, larger more lattice points solved
/// for nothing.
const TARGET_MARGIN: f64 = 0.25;

/// Beyond this many pieces for one `L2` the annuli are cheaper.
const MAX_PIECES: usize = 48;

/// [`TARGET_MARGIN`] when `c` is an arc. Arcs are mostly grown rounded
/// corners a fraction of a lattice step long, whose swept region is thin:
/// most of its lattice points lay in the margin and each cost an arc pose
/// solution (tens of thousands of instructions) for nothing, where a piece
/// costs a few hundred. On the voron2 deck panel (ci profile, top-10) 0.25
/// and 0.05 solved 107 and 70 thousand triples with two lines pivoting
/// and an arc third for the same 50,672 setups (5,900 and 5,603 M
/// instructions in all); 0.02 saved under 1% more there and cost 0.5% on
/// the voron0 motor panel.
const ARC_THIRD_TARGET_MARGIN: f64 = 0.05;

/// [`MAX_PIECES`] when `c` is an arc: the finer pieces are about twice as
/// many (the step goes as the square root of the margin).
const ARC_THIRD_MAX_PIECES: usize = 200;

/// `|u_a x u_b|` at or below which lines `a` and `b` count as parallel:
/// the part then slides without turning. Between this and
/// [`NEAR_PARALLEL`] neither model is accurate enough and the caller falls
/// back to the annuli.
const PARALLEL: f64 = 1e-12;

/// See [`PARALLEL`].
const NEAR_PARALLEL: f64 = 1e-4;

/// What the sweep of one combination needs (`a`, `b` lines, `c` a line or
/// an arc), worked out once per combination: per `L2` only the part that
/// depends on `L2` is left (one `atan2`, at most four `acos` and the
/// `sin_cos` of the angles' ends), and that once per pivot pair
/// ([`LinesPoint`]).
#[derive(Debug, Clone, Copy)]
pub struct LineSweep<'s> {
    a: &'s LinePiece,
    b: &'s LinePiece,
    c: &'s ThirdPiece,
    same_ab: bool,
    /// No setup at all: the three normals are parallel (degenerate for the
    /// pose solver too).
    pub(super) degenerate: bool,
    mode: Mode,
    /// Bounds the distance between points of `a` and `c`.
    dmax_ac: f64,
}

/// How the part moves with its contacts on lines `a` and `b`: a property
/// of the pair alone, so that what depends on `L2` can be kept for every
/// combination pivoting on the pair ([`LinesPoint`]).
#[derive(Debug, Clone, Copy)]
enum Mode {
    /// `a` and `b` parallel: the part slides.
    Sliding,
    /// `a` and `b` cross: the part turns. `s_a(theta) = alpha_a + |L2| /
    /// |D| cos(theta - phi_L2 - kappa_a)`, likewise `s_b`.
    Turning {
        alpha: [f64; 2],
        kappa: [f64; 2],
        /// `(sin, cos)` of `kappa_a`, so `phi_a`'s need no `sin_cos` per `L2`.
        kappa_a_sc: (f64, f64),
        inv_d: f64,
    },
}

/// What the region of `L3` needs of `L2` beyond the third segment: the
/// angles that keep contacts 1 and 2 on their segments and how the part
/// moves through them. It depends only on the pivot pair and `L2`, so
/// combinations that pivot on the same pair share it, trig included.
#[derive(Debug, Clone, Copy)]
pub struct LinesPoint {
    pub(super) angles: AngleSet,
    motion: Motion,
}

/// How the part moves through a [`LinesPoint`]'s angles, with the trig
/// every third segment's region would otherwise redo.
#[derive(Debug, Clone, Copy)]
enum Motion {
    /// The part turns: `s_a(theta) = sa[0] + sa[1] cos(theta - phi_a)`.
    Turning {
        sa: [f64; 2],
        /// `(sin, cos)` of `phi_a`.
        phi_a_sc: (f64, f64),
        /// `(sin, cos)` of the ends of each interval of the angles.
        ends_sc: [[(f64, f64); 2]; ANGLE_SET_CAPACITY],
    },
    /// The part slides at one or two angles ([`Slide`]); `len` of them.
    Sliding { slides: [Slide; 2], len: usize },
}

/// One angle at which the part slides along parallel lines `a` and `b`:
/// its `(sin, cos)` and the range `[lo, hi]` of `s_a` keeping both
/// contacts on their segments.
#[derive(Debug, Clone, Copy)]
struct Slide {
    sc: (f64, f64),
    lo: f64,
    hi: f64,
}

impl<'s> LineSweep<'s> {
    /// The sweep pivoting on lines `a` then `b`, with `c` swept (`c_line`:
    /// its line, when it is one); `None` when this pruning does not apply
    /// (lines `a` and `b` nearly but not exactly parallel) and the caller
    /// must use the annuli. `dmax_ac` bounds the distance between points of
    /// `a` and `c`.
    pub(super) fn new(
        [a, b]: [&'s LinePiece; 2],
        c: &'s ThirdPiece,
        c_line: Option<&LinePiece>,
        same_ab: bool,
        dmax_ac: f64,
    ) -> Option<LineSweep<'s>> {
        let (na, nb) = (a.line.n, b.line.n);
        let d = cross(a.line.u, b.line.u);
        let three_parallel = match c_line {
            Some(lc) => {
                let nc = lc.line.n;
                [cross(nb, nc), cross(nc, na), cross(na, nb)]
                    .iter()
                    .all(|x| x.abs() <= EPS)
            }
            None => false,
        };
        let mode = if refuses(a, b) {
            return None;
        } else if d.abs() <= PARALLEL {
            Mode::Sliding
        } else {
            // p2 - p1 = R^T L2 gives s_a = cross(u_b, q) / D and s_b =
            // cross(u_a, q) / D for q = R^T L2 + o_a - o_b; the L2 terms
            // are |L2| cos(theta - phi_L2 + phi_u - sign(D) pi / 2) / |D|.
            let oab = a.line.origin - b.line.origin;
            let sign = d.signum();
            let quarter = sign * std::f64::consts::FRAC_PI_2;
            // sin and cos of -phi_u_b - sign pi / 2, from u_b itself.
            let ub = b.line.u;
            Mode::Turning {
                alpha: [cross(b.line.u, oab) / d, cross(a.line.u, oab) / d],
                kappa: [-b.direction - quarter, -a.direction - quarter],
                kappa_a_sc: (-sign * ub.x, -sign * ub.y),
                inv_d: 1.0 / d.abs(),
            }
        };
        Some(LineSweep {
            a,
            b,
            c,
            same_ab,
            degenerate: three_parallel,
            mode,
            dmax_ac,
        })
    }

    /// What the region needs of `L2 = l2`; `None` when no angle keeps both
    /// contacts on their segments. Depends on `a` and `b` only.
    pub fn pivot_point(&self, l2: V2) -> Option<LinesPoint> {
        let v = l2;
        match self.mode {
            Mode::Sliding => Some(LinesPoint {
                angles: AngleSet::full(),
                motion: slides(self.a, self.b, self.same_ab, l2),
            }),
            Mode::Turning {
                alpha,
                kappa,
                kappa_a_sc,
                inv_d,
            } => {
                let phi = v.y.atan2(v.x);
                let amp = v.norm() * inv_d;
                let band = |k: usize, p: &LinePiece| {
                    AngleSet::sinusoid_band(
                        alpha[k],
                        amp,
                        phi + kappa[k],
                        p.s0 - S_SLACK,
                        p.s1 + S_SLACK,
                        ANGLE_SLACK,
                    )
                };
                let on_a = band(0, self.a);
                if on_a.is_empty() {
                    return None;
                }
                let angles = on_a.intersect(&band(1, self.b));
                if angles.is_empty() {
                    return None;
                }
                // (sin, cos) of phi_a = phi_L2 + kappa_a by turning L2's
                // direction.
                let (sk, ck) = kappa_a_sc;
                let (sl, cl) = (v.y / v.norm(), v.x / v.norm());
                let mut ends_sc = [[(0.0, 1.0); 2]; ANGLE_SET_CAPACITY];
                for (sc, &[t0, t1]) in ends_sc.iter_mut().zip(angles.intervals()) {
                    *sc = [t0.sin_cos(), t1.sin_cos()];
                }
                Some(LinesPoint {
                    angles,
                    motion: Motion::Turning {
                        sa: [alpha[0], amp],
                        phi_a_sc: (sl * ck + cl * sk, cl * ck - sl * sk),
                        ends_sc,
                    },
                })
            }
        }
    }

    /// The region where `L3` may lie for `L1 = 0` on `a` and `L2` on `b`,
    /// as quadrilaterals pushed onto `out`; `false` when it needs too many
    /// pieces and the caller should use the annuli.
    pub fn region(&self, pt: &LinesPoint, out: &mut Vec<Quad>) -> bool {
        if self.degenerate {
            return true;
        }
        match pt.motion {
            Motion::Sliding { slides, len } => {
                sliding_region(self.a, self.c, &slides[..len], out);
                true
            }
            Motion::Turning {
                sa,
                phi_a_sc,
                ref ends_sc,
            } => turning_region(self, &pt.angles, (sa, phi_a_sc), ends_sc, out),
        }
    }
}

/// Whether the sweep refuses to pivot on lines `a` then `b` (nearly but
/// not exactly parallel, see [`PARALLEL`]): a property of the pair alone,
/// so the setup search can rank pivots without building sweeps.
pub(super) fn refuses(a: &LinePiece, b: &LinePiece) -> bool {
    let d = cross(a.line.u, b.line.u).abs();
    d > PARALLEL && d < NEAR_PARALLEL
}

/// Lines `a` and `b` not parallel: the part turns through `angles`
/// (`ends_sc`: the `(sin, cos)` of their ends), with `s_a(theta) = sa[0] +
/// sa[1] cos(theta - phi_a)`.
fn turning_region(
    sweep: &LineSweep,
    angles: &AngleSet,
    motion: ([f64; 2], (f64, f64)),
    ends_sc: &[[(f64, f64); 2]; ANGLE_SET_CAPACITY],
    out: &mut Vec<Quad>,
) -> bool {
    // A line third (the polygons' only kind, most regions) poses two
    // points: buffers of two, not of an arc's chord points, to fill and
    // turn over for every piece.
    if sweep.c.point_count() == 2 {
        turning_pieces::<2>(sweep, angles, motion, ends_sc, out)
    } else {
        turning_pieces::<{ MAX_CHORDS + 1 }>(sweep, angles, motion, ends_sc, out)
    }
}

/// [`turning_region`] with the third segment's points posed into buffers
/// of `N` (at least its point count).
fn turning_pieces<const N: usize>(
    sweep: &LineSweep,
    angles: &AngleSet,
    (sa, phi_a_sc): ([f64; 2], (f64, f64)),
    ends_sc: &[[(f64, f64); 2]; ANGLE_SET_CAPACITY],
    out: &mut Vec<Quad>,
) -> bool {
    let dmax_ac = sweep.dmax_ac;
    let (a, c) = (sweep.a, sweep.c);
    let h = sa[1];
    // |F''| <= |p - p1| + 2 |p1'| + |p1''| for F = R (p - p1); the widened
    // angles may carry p1 past a's ends by `ANGLE_SLACK h`.
    let k2 = dmax_ac + c.margin + 3.0 * h + ANGLE_SLACK * h + 1e-6;
    let (target, max_pieces) = if c.curved {
        (ARC_THIRD_TARGET_MARGIN, ARC_THIRD_MAX_PIECES)
    } else {
        (TARGET_MARGIN, MAX_PIECES)
    };
    let step = (8.0 * target / k2).sqrt();
    let (sin_p, cos_p) = phi_a_sc;
    let mut pieces = 0;
    let (mut first, mut second) = ([V2::zeros(); N], [V2::zeros(); N]);
    for (&[t0, t1], &[sc0, sc1]) in angles.intervals().iter().zip(ends_sc) {
        let n = ceil((t1 - t0) / step).max(1.0) as usize;
        pieces += n;
        if pieces > max_pieces {
            return false;
        }
        let w = (t1 - t0) / n as f64;
        let margin = w * w / 8.0 * k2 + QUAD_SLACK;
        let posed = |(sin, cos): (f64, f64), out: &mut [V2; N]| {
            // cos(theta - phi) = cos cos_p + sin sin_p.
            let p1 = a.point(sa[0] + sa[1] * (cos * cos_p + sin * sin_p));
            c.map_into(|p| rot(cos, sin, p - p1), out);
        };
        let mut sc = sc0;
        let (mut prev, mut next) = (&mut first, &mut second);
        posed(sc, prev);
        // Piece ends by turning the previous one: the rounding this adds,
        // n * 1e-16, is far below QUAD_SLACK.
        let step_sc = if n > 1 { w.sin_cos() } else { (0.0, 1.0) };
        for k in 1..=n {
            sc = if k == n {
                sc1
            } else {
                (
                    sc.0 * step_sc.1 + sc.1 * step_sc.0,
                    sc.1 * step_sc.1 - sc.0 * step_sc.0,
                )
            };
            posed(sc, next);
            c.push_quads(prev, next, margin, out);
            std::mem::swap(&mut prev, &mut next);
        }
    }
    true
}

/// Lines `a` and `b` parallel (or one segment twice): the ladder `L1 L2`
/// spans the gap between them at one or two angles, and the part slides
/// along them. Each angle gives a parallelogram per chord of `c`.
fn sliding_region(a: &LinePiece, c: &ThirdPiece, slides: &[Slide], out: &mut Vec<Quad>) {
    for &Slide {
        sc: (sin, cos),
        lo,
        hi,
    } in slides
    {
        let mut ends = [[V2::zeros(); MAX_CHORDS + 1]; 2];
        for (e, s1) in ends.iter_mut().zip([lo, hi]) {
            c.map_into(|p| rot(cos, sin, p - a.point(s1)), e);
        }
        c.push_quads(&ends[0], &ends[1], QUAD_SLACK, out);
    }
}

/// The angles at which the part slides along parallel lines `a` and `b`
/// with `L2 = l2`, and the range of `s_a` at each that keeps both contacts
/// on their segments.
fn slides(a: &LinePiece, b: &LinePiece, same_ab: bool, l2: V2) -> Motion {
    let none = Slide {
        sc: (0.0, 1.0),
        lo: 0.0,
        hi: 0.0,
    };
    let (mut slides, mut len) = ([none; 2], 0);
    let (ua, na) = (a.line.u, a.line.n);
    let sigma = if na.dot(&b.line.n) >= 0.0 { 1.0 } else { -1.0 };
    // n_a . (p2 - p1) is the signed gap; the rest of R^T L2 runs along a.
    let gap = sigma * b.line.c - a.line.c;
    // A ladder a hair shorter than the gap may still be a tangent pose
    // for the solver: keep it, at tau = 0.
    if l2.norm() < gap.abs() - 1e-6 {
        return Motion::Sliding { slides, len };
    }
    let tau = (l2.norm_squared() - gap * gap).max(0.0).sqrt();
    // On one segment, locator 2 comes after locator 1 along it.
    let taus: &[f64] = if same_ab { &[1.0] } else { &[1.0, -1.0] };
    for &sign in taus {
        let tau = sign * tau;
        let v = na * gap + ua * tau;
        let theta = l2.y.atan2(l2.x) - v.y.atan2(v.x);
        // s_b = sigma (s_a + k): the range of s_a keeping both on.
        let k = ua.dot(&(a.line.origin - b.line.origin)) + tau;
        let (b_lo, b_hi) = if sigma > 0.0 {
            (b.s0 - k, b.s1 - k)
        } else {
            (-b.s1 - k, -b.s0 - k)
        };
        let lo = a.s0.max(b_lo) - S_SLACK;
        let hi = a.s1.min(b_hi) + S_SLACK;
        if lo > hi {
            continue;
        }
        slides[len] = Slide {
            sc: theta.sin_cos(),
            lo,
            hi,
        };
        len += 1;
    }
    Motion::Sliding { slides, len }
}
