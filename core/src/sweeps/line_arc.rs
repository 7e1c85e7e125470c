//! The sweep when the pivot is a line and an arc: combinations with one
//! line and two arcs, which before went through the annuli and solved for
//! poses at about twenty lattice points per setup found.
//!
//! `L1` at the origin touches line `p` at `x1 = o + s u`, `L2 = d` touches
//! the circle of arc `q` (centre `C`, radius `rho`). With `C' = C - o -
//! R^T d`, the second contact is `x1 + R^T d`, on the circle when
//! `(s - h)^2 + g^2 = rho^2` for `g = n . C'` and `h = u . C'`, both
//! sinusoids of the angle. So `s = h +- sqrt(rho^2 - g^2)` (two branches), and the contact
//! direction on the circle is a function of `g` alone on each branch: the
//! arc's span is a set of values of `g`, hence a sinusoid band of angles,
//! exact like the bands of two lines.
//!
//! The square root has branch points where the circle touches the line, so
//! the region is not covered through derivatives as for two lines. Each
//! angle piece `I` instead bounds `s` by interval arithmetic on `g` and `h`
//! over `I`; the third segment's points, relative to `x1`, then lie within
//! half that range of their position at the middle `s`, and turning them
//! through `I` moves each point `z` at most `|z| w^2 / 8` off its chord
//! (`w` the piece's width). Sound without derivatives, tight where the
//! pieces are narrow.

use super::pieces::{LinePiece, Quad, ThirdPiece, MAX_CHORDS, QUAD_SLACK, S_SLACK};
use crate::geometry::angle_set::{rem_tau, AngleSet};
use crate::geometry::arc::GrownArc;
use crate::geometry::{cross, rot, V2};
use crate::segments::Segment;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// Angle slack of the bands, radians (as for two lines).
const ANGLE_SLACK: f64 = 1e-7;

/// Most angle pieces tried for one `L2` (each costs far less than a pose
/// solution); beyond, the annuli are cheaper.
const MAX_PIECES: usize = 400;

/// Pieces are not halved below this width (radians): at a branch point
/// `s` moves like a square root, and the margin it adds must stop shrinking
/// somewhere.
const MIN_PIECE: f64 = 1e-4;

/// Largest margin of a piece (lattice units). Finer pieces solve fewer
/// lattice points for nothing but cost more pieces: on `bracket-arcs`
/// 0.1, 0.25 and 0.5 took 278, 235 and 256 M instructions.
const ARC_TARGET_MARGIN: f64 = 0.25;

/// An arc segment as a pivot: its grown circle and the directions from the
/// centre its contacts may take.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ArcPiece {
    center: V2,
    radius: f64,
    /// Contact directions `[beta0, beta1]`, `beta0 <= beta1`.
    beta: [f64; 2],
}

impl ArcPiece {
    /// Segment `seg`, which lies on `arc`; `None` for an arc of no radius,
    /// which no sweep pivots on.
    pub(super) fn of(seg: &Segment, arc: &GrownArc) -> Option<ArcPiece> {
        if arc.radius.is_nan() || arc.radius <= 0.0 {
            return None;
        }
        let (b0, b1) = (arc.angle_at(seg.s0), arc.angle_at(seg.s1));
        Some(ArcPiece {
            center: arc.center,
            radius: arc.radius,
            beta: [b0.min(b1), b0.max(b1)],
        })
    }
}

/// `alpha + amp cos(theta - phi)`.
#[derive(Debug, Clone, Copy)]
struct Sinusoid {
    alpha: f64,
    amp: f64,
    phi: f64,
}

impl Sinusoid {
    /// Bounds over `[t0, t1]` (`t1 - t0 <= 2 pi`), widened by rounding;
    /// `cos0`, `cos1` are `cos(t0 - phi)`, `cos(t1 - phi)`, which a piece
    /// shares with its neighbours and its halves ([`PieceEnd`]).
    fn range(&self, t0: f64, t1: f64, cos0: f64, cos1: f64) -> (f64, f64) {
        let v0 = self.alpha + self.amp * cos0;
        let v1 = self.alpha + self.amp * cos1;
        let (mut lo, mut hi) = (v0.min(v1), v0.max(v1));
        let inside = |x: f64| rem_tau(x - t0) <= t1 - t0;
        if inside(self.phi) {
            hi = self.alpha + self.amp;
        }
        if inside(self.phi + PI) {
            lo = self.alpha - self.amp;
        }
        let e = 1e-12 * (self.alpha.abs() + self.amp) + 1e-12;
        (lo - e, hi + e)
    }
}

/// What one combination pivoting on line `p` and arc `q` needs.
#[derive(Debug, Clone, Copy)]
pub struct LineArcSweep<'s> {
    /// The pivot's line `p`.
    line: &'s LinePiece,
    /// The pivot's arc `q`.
    arc: &'s ArcPiece,
    /// The third segment.
    third: &'s ThirdPiece,
    /// `n . (C - o)` and `u . (C - o)`.
    gc: f64,
    hc: f64,
    /// Angles of `n` and `u`.
    psi_n: f64,
    psi_u: f64,
    /// `u x n`: `+1` when `n` is `u` turned counterclockwise.
    nu: f64,
    /// Bounds `|y - x1|` for `y` on `c` and `x1` on `p`.
    rmax: f64,
}

/// The angles of one branch of `s` over which the arc contact stays on
/// the arc: `sigma` is `+1` or `-1`.
#[derive(Debug, Clone, Copy)]
struct Branch {
    sigma: f64,
    angles: AngleSet,
}

/// What the region needs of `L2 = d` for a line-arc pivot: two branches,
/// each of a few bands (the arc's span can cover both ends of the half
/// turn a branch reaches).
#[derive(Debug, Clone, Copy)]
pub struct ArcPoint {
    branches: [Branch; 6],
    len: usize,
    /// A superset of every branch's angles, which lets the pose solver
    /// skip the rest of the circle.
    pub(super) angles: AngleSet,
    g: Sinusoid,
    h: Sinusoid,
    /// The ends of the first [`KEPT_INTERVALS`] intervals of the branches
    /// (in the order [`LineArcSweep::region`] covers them) with their trig:
    /// every third segment swept for this point starts from them.
    ends: [[PieceEnd; 2]; KEPT_INTERVALS],
}

/// Intervals of a pivot point whose ends keep their trig (most points have
/// one or two): each point serves about fifteen third segments on
/// `voron0_motor_panel`, and a region is mostly a single piece, whose trig
/// was all at these ends.
const KEPT_INTERVALS: usize = 4;

/// An end of an angle piece with the phases' cosines of `g` and `h` there
/// (and `(sin, cos)` of `t`, at an interval's end): a piece and its
/// halves, or two neighbouring pieces, share ends, so each end is worked
/// out once, not once by every piece that ends there.
#[derive(Debug, Clone, Copy)]
struct PieceEnd {
    t: f64,
    g_cos: f64,
    h_cos: f64,
    sc: Option<(f64, f64)>,
}

/// What covering one pivot point's angles carries from piece to piece: the
/// pieces left, where the quadrilaterals go, and the `(sin, cos)` of the
/// last piece kept's far end (the near end of the next, when they touch).
struct CoverState<'o> {
    budget: usize,
    out: &'o mut Vec<Quad>,
    last: Option<(u64, (f64, f64))>,
}

impl CoverState<'_> {
    /// `t.sin_cos()`, reused when `t` is (to the bit) the last piece's end.
    fn sin_cos(&self, t: f64) -> (f64, f64) {
        match self.last {
            Some((bits, sc)) if bits == t.to_bits() => sc,
            _ => t.sin_cos(),
        }
    }
}

impl ArcPoint {
    /// The end `t` of a piece.
    fn end(&self, t: f64) -> PieceEnd {
        PieceEnd {
            t,
            g_cos: (t - self.g.phi).cos(),
            h_cos: (t - self.h.phi).cos(),
            sc: None,
        }
    }

    /// The ends of an interval, with their `(sin, cos)`.
    fn interval_ends(&self, [t0, t1]: [f64; 2]) -> [PieceEnd; 2] {
        [t0, t1].map(|t| PieceEnd {
            sc: Some(t.sin_cos()),
            ..self.end(t)
        })
    }

    /// Whether some branch allows `theta` (soundness tests).
    #[cfg(test)]
    pub(super) fn contains_angle(&self, theta: f64) -> bool {
        self.branches[..self.len]
            .iter()
            .any(|b| b.angles.contains(theta))
    }
}

impl<'s> LineArcSweep<'s> {
    /// The sweep pivoting on `line` (`p`) then `arc` (`q`), with `third`
    /// swept; `dmax_pc` bounds the distance between points of `p` and
    /// `third`.
    pub(super) fn new(
        line: &'s LinePiece,
        arc: &'s ArcPiece,
        third: &'s ThirdPiece,
        dmax_pc: f64,
    ) -> LineArcSweep<'s> {
        let (u, n) = (line.line.u, line.line.n);
        let co = arc.center - line.line.origin;
        LineArcSweep {
            line,
            arc,
            third,
            gc: n.dot(&co),
            hc: u.dot(&co),
            psi_n: n.y.atan2(n.x),
            psi_u: line.direction,
            nu: cross(u, n).signum(),
            rmax: dmax_pc + third.margin + 2.0 * S_SLACK + 1e-6,
        }
    }

    /// The branches of `L2 = l2` with some angle; `None` when there is none.
    pub fn pivot_point(&self, l2: V2) -> Option<ArcPoint> {
        let amp = l2.norm();
        let phi_d = l2.y.atan2(l2.x);
        // n . R^T d = |d| cos(theta + psi - phi_d), so g = gc - that.
        let g = Sinusoid {
            alpha: self.gc,
            amp,
            phi: phi_d - self.psi_n + PI,
        };
        let h = Sinusoid {
            alpha: self.hc,
            amp,
            phi: phi_d - self.psi_u + PI,
        };
        let mut pt = ArcPoint {
            branches: [Branch {
                sigma: 0.0,
                angles: AngleSet::empty(),
            }; 6],
            len: 0,
            angles: AngleSet::empty(),
            g,
            h,
            ends: [[PieceEnd {
                t: 0.0,
                g_cos: 1.0,
                h_cos: 1.0,
                sc: None,
            }; 2]; KEPT_INTERVALS],
        };
        for sigma in [1.0, -1.0] {
            for [m0, m1] in self.mu_ranges(sigma).into_iter().flatten() {
                let rho = self.arc.radius;
                let (g0, g1) = (rho * m0.sin() - S_SLACK, rho * m1.sin() + S_SLACK);
                let angles = AngleSet::sinusoid_band(g.alpha, g.amp, g.phi, g0, g1, ANGLE_SLACK);
                if !angles.is_empty() {
                    pt.angles = pt.angles.union_covering(&angles);
                    pt.branches[pt.len] = Branch { sigma, angles };
                    pt.len += 1;
                }
            }
        }
        let intervals = pt.branches[..pt.len]
            .iter()
            .flat_map(|br| br.angles.intervals());
        for (k, &interval) in intervals.take(KEPT_INTERVALS).enumerate() {
            pt.ends[k] = pt.interval_ends(interval);
        }
        (pt.len > 0).then_some(pt)
    }

    /// The values of `mu = asin(g / rho)` in `[-pi/2, pi/2]` at which the
    /// contact of branch `sigma` lies on the arc: its direction is `psi_u -
    /// nu mu` (`sigma = 1`) or `psi_u + nu (mu + pi)` (`sigma = -1`).
    fn mu_ranges(&self, sigma: f64) -> [Option<[f64; 2]>; 3] {
        let [b0, b1] = self.arc.beta;
        // direction in [b0, b1] as a range of nu-signed offsets.
        let (lo, hi) = if sigma > 0.0 {
            (b0 - self.psi_u, b1 - self.psi_u)
        } else {
            (
                b0 - self.psi_u - self.nu * PI,
                b1 - self.psi_u - self.nu * PI,
            )
        };
        // nu * mu (sigma = -1) or -nu * mu (sigma = 1) lies in [lo, hi].
        let sign = if sigma > 0.0 { -self.nu } else { self.nu };
        let (m0, m1) = if sign > 0.0 { (lo, hi) } else { (-hi, -lo) };
        let slack = 1e-7 + S_SLACK / self.arc.radius;
        // An interval of at most a turn meets a half turn at most twice.
        let mut out = [None; 3];
        let mut k = 0;
        // Every turn of [m0, m1] that meets [-pi/2, pi/2].
        let mut t = ((-FRAC_PI_2 - slack - m1) / TAU).ceil();
        while m0 + t * TAU - slack <= FRAC_PI_2 && k < out.len() {
            let a = (m0 + t * TAU - slack).max(-FRAC_PI_2);
            let b = (m1 + t * TAU + slack).min(FRAC_PI_2);
            if a <= b {
                out[k] = Some([a, b]);
                k += 1;
            }
            t += 1.0;
        }
        out
    }

    /// The region of `L3` for one pivot point, as quadrilaterals grown by
    /// their margins; `false` when it needs too many pieces.
    pub fn region(&self, pt: &ArcPoint, out: &mut Vec<Quad>) -> bool {
        let mut state = CoverState {
            budget: MAX_PIECES,
            out,
            last: None,
        };
        let mut k = 0;
        for br in &pt.branches[..pt.len] {
            for &interval in br.angles.intervals() {
                let ends = pt
                    .ends
                    .get(k)
                    .copied()
                    .unwrap_or_else(|| pt.interval_ends(interval));
                k += 1;
                if !self.cover(pt, br.sigma, ends, &mut state) {
                    return false;
                }
            }
        }
        true
    }

    /// Covers the angles `[t0, t1]` of branch `sigma`, halving a piece
    /// while its margin (half the range of `s`, plus the turn's) is above
    /// [`ARC_TARGET_MARGIN`]: `s` changes fastest near the branch points, so
    /// pieces are narrow only there. Pieces where `s` misses the segment
    /// are dropped whole. `false` once the budget of pieces is spent.
    fn cover(
        &self,
        pt: &ArcPoint,
        sigma: f64,
        [e0, e1]: [PieceEnd; 2],
        state: &mut CoverState<'_>,
    ) -> bool {
        if state.budget == 0 {
            return false;
        }
        state.budget -= 1;
        let Some((lo, hi)) = self.contact_range(pt, sigma, e0, e1) else {
            return true;
        };
        let (t0, t1) = (e0.t, e1.t);
        let w = t1 - t0;
        let margin = 0.5 * (hi - lo) + self.rmax * w * w / 8.0;
        if margin > ARC_TARGET_MARGIN && w > MIN_PIECE {
            let mid = pt.end(0.5 * (t0 + t1));
            return self.cover(pt, sigma, [e0, mid], state)
                && self.cover(pt, sigma, [mid, e1], state);
        }
        let x1 = self.line.point(0.5 * (lo + hi));
        let ends_sc = [
            e0.sc.unwrap_or_else(|| state.sin_cos(t0)),
            e1.sc.unwrap_or_else(|| t1.sin_cos()),
        ];
        state.last = Some((t1.to_bits(), ends_sc[1]));
        let mut ends = [[V2::zeros(); MAX_CHORDS + 1]; 2];
        for (e, (sin, cos)) in ends.iter_mut().zip(ends_sc) {
            self.third.map_into(|y| rot(cos, sin, y - x1), e);
        }
        self.third
            .push_quads(&ends[0], &ends[1], margin + QUAD_SLACK, state.out);
        true
    }

    /// The range of the line contact `s` over the angles `[t0, t1]` of
    /// branch `sigma`, within the segment (with slack); `None` when it
    /// misses the segment.
    fn contact_range(
        &self,
        pt: &ArcPoint,
        sigma: f64,
        e0: PieceEnd,
        e1: PieceEnd,
    ) -> Option<(f64, f64)> {
        let rho = self.arc.radius;
        let (g_lo, g_hi) = pt.g.range(e0.t, e1.t, e0.g_cos, e1.g_cos);
        let (h_lo, h_hi) = pt.h.range(e0.t, e1.t, e0.h_cos, e1.h_cos);
        let g2_max = (g_lo * g_lo).max(g_hi * g_hi);
        let g2_min = if g_lo <= 0.0 && g_hi >= 0.0 {
            0.0
        } else {
            (g_lo * g_lo).min(g_hi * g_hi)
        };
        let sq_lo = (rho * rho - g2_max).max(0.0).sqrt();
        let sq_hi = (rho * rho - g2_min).max(0.0).sqrt();
        let (s_lo, s_hi) = if sigma > 0.0 {
            (h_lo + sq_lo, h_hi + sq_hi)
        } else {
            (h_lo - sq_hi, h_hi - sq_lo)
        };
        // The square root's rounding: a few ulps of rho.
        let e = S_SLACK + 1e-12 * (rho + h_lo.abs().max(h_hi.abs()));
        let lo = (s_lo - e).max(self.line.s0 - S_SLACK);
        let hi = (s_hi + e).min(self.line.s1 + S_SLACK);
        (lo <= hi).then_some((lo, hi))
    }
}
