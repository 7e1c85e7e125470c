//! Where locator 3 can be once locators 1 and 2 touch their segments
//! (issue 15's pruning, SPEC 3 allows any pruning that keeps the set).
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

mod line_arc;
mod pieces;

pub use line_arc::{ArcPoint, LineArcSweep};

use crate::geometry::angle_set::AngleSet;
use crate::geometry::{cross, rot, EPS, V2};
use crate::segments::Segment;
use line_arc::ArcPiece;
pub use pieces::Quad;
use pieces::{LinePiece, ThirdPiece, MAX_CHORDS, QUAD_SLACK, S_SLACK};

/// Angle slack of the angle sets, radians.
const ANGLE_SLACK: f64 = 1e-7;

/// Largest margin a piece may add around its quadrilateral (lattice
/// units): smaller means more pieces, larger more lattice points solved
/// for nothing.
const TARGET_MARGIN: f64 = 0.25;

/// Beyond this many pieces for one `L2` the annuli are cheaper.
const MAX_PIECES: usize = 48;

/// `|u_a x u_b|` at or below which lines `a` and `b` count as parallel:
/// the part then slides without turning. Between this and
/// [`NEAR_PARALLEL`] neither model is accurate enough and the caller falls
/// back to the annuli.
const PARALLEL: f64 = 1e-12;

/// See [`PARALLEL`].
const NEAR_PARALLEL: f64 = 1e-4;

/// What the sweep needs of one segment, worked out once per part: a
/// combination only borrows these, so choosing its pivot costs no trig
/// and no copy of the arc's chord points.
#[derive(Debug, Clone, Copy)]
pub struct SweptSegment {
    line: Option<LinePiece>,
    arc: Option<ArcPiece>,
    third: ThirdPiece,
}

impl SweptSegment {
    /// Whether the segment is a line (else an arc).
    pub fn is_line(&self) -> bool {
        self.line.is_some()
    }

    /// The segment as a pivot (a line or an arc) and as a third segment.
    pub fn of(seg: &Segment) -> SweptSegment {
        SweptSegment {
            line: LinePiece::of(seg),
            arc: ArcPiece::of(seg),
            third: ThirdPiece::of(seg),
        }
    }
}

/// The sweep of one combination, by the kind of its pivot: two lines
/// (exact angle sets, the common case) or a line and an arc.
#[derive(Debug, Clone, Copy)]
pub enum LocatorSweep<'s> {
    /// Pivot on two lines.
    Lines(LineSweep<'s>),
    /// Pivot on a line (locator 1) and an arc (locator 2).
    LineArc(LineArcSweep<'s>),
}

/// What the region of `L3` needs of `L2` beyond the third segment, by the
/// kind of sweep; shared by every combination with the same pivot pair.
#[derive(Debug, Clone)]
pub enum PivotPoint {
    /// See [`LinesPoint`].
    Lines(LinesPoint),
    /// See [`ArcPoint`] (boxed: five times the size of the other).
    LineArc(Box<ArcPoint>),
}

impl<'s> LocatorSweep<'s> {
    /// The sweep pivoting on `segs[0]` and `segs[1]` (two lines, or a line
    /// then an arc) with `segs[2]` third; `None` when neither applies
    /// (arcs first, nearly parallel lines). `dmax_ac` bounds the distance
    /// between points of `segs[0]` and `segs[2]`.
    pub fn new(
        segs: [&'s SweptSegment; 3],
        same_ab: bool,
        dmax_ac: f64,
    ) -> Option<LocatorSweep<'s>> {
        if let (Some(p), Some(q)) = (&segs[0].line, &segs[1].arc) {
            return Some(LocatorSweep::LineArc(LineArcSweep::new(
                p,
                q,
                &segs[2].third,
                dmax_ac,
            )));
        }
        LineSweep::new(segs, same_ab, dmax_ac).map(LocatorSweep::Lines)
    }

    /// Whether the pivot is two lines.
    pub fn is_lines(&self) -> bool {
        matches!(self, LocatorSweep::Lines(_))
    }

    /// What the region needs of `L2 = l2`; `None` when no angle keeps both
    /// pivot contacts on their segments.
    pub fn pivot_point(&self, l2: V2) -> Option<PivotPoint> {
        match self {
            LocatorSweep::Lines(s) => s.pivot_point(l2).map(PivotPoint::Lines),
            LocatorSweep::LineArc(s) => s.pivot_point(l2).map(|p| PivotPoint::LineArc(Box::new(p))),
        }
    }

    /// Calls `visit` once for every lattice point (multiples of `grid_step`) of the
    /// region of `L3` for the pivot point's `L2`, row by row, with (a
    /// superset of) the angles at which the pivot's contacts stay on their
    /// segments, for the pose solver to look only there; `false` (and no call)
    /// when the region needs too many pieces and the caller should scan
    /// the annuli instead.
    pub fn for_each_third_locator(
        &self,
        pt: &PivotPoint,
        grid_step: i64,
        scratch: &mut SweepScratch,
        mut visit: impl FnMut([i64; 2], Option<&AngleSet>),
    ) -> bool {
        let SweepScratch { quads, spans } = scratch;
        quads.clear();
        if !self.region(pt, quads) {
            return false;
        }
        let angles = match pt {
            PivotPoint::Lines(p) => &p.angles,
            PivotPoint::LineArc(p) => &p.angles,
        };
        scan_quads(quads, grid_step, spans, |l3| visit(l3, Some(angles)));
        true
    }

    /// The region of `L3` for a pivot point, as quadrilaterals grown by
    /// their margins pushed onto `out`; `false` when it needs too many
    /// pieces.
    pub fn region(&self, pt: &PivotPoint, out: &mut Vec<Quad>) -> bool {
        match (self, pt) {
            (LocatorSweep::Lines(s), PivotPoint::Lines(p)) => s.region(p, out),
            (LocatorSweep::LineArc(s), PivotPoint::LineArc(p)) => s.region(p, out),
            // A point of another kind of pivot: nothing is known, so the
            // caller scans the annuli (never happens: points are kept per
            // pivot pair, whose kind is fixed).
            _ => false,
        }
    }
}

impl PivotPoint {
    /// Whether the angle `theta` keeps both pivot contacts on their
    /// segments (up to the slack), for the soundness tests.
    #[cfg(test)]
    fn contains_angle(&self, theta: f64) -> bool {
        match self {
            PivotPoint::Lines(p) => p.angles.contains(theta),
            PivotPoint::LineArc(p) => p.contains_angle(theta),
        }
    }
}

/// What the sweep of one combination needs (`a`, `b` lines, `c` a line or
/// an arc), worked out once per combination: per `L2` only the part that
/// depends on `L2` is left (one `atan2`, at most four `acos` and two
/// `sin_cos`).
#[derive(Debug, Clone, Copy)]
pub struct LineSweep<'s> {
    a: &'s LinePiece,
    b: &'s LinePiece,
    c: &'s ThirdPiece,
    same_ab: bool,
    /// No setup at all: the three normals are parallel (degenerate for the
    /// pose solver too).
    degenerate: bool,
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
/// angles that keep contacts 1 and 2 on their segments and, when the part
/// turns, the sinusoid of `s_a`. It depends only on the pivot pair and
/// `L2`, so combinations that pivot on the same pair share it.
#[derive(Debug, Clone, Copy)]
pub struct LinesPoint {
    l2: V2,
    angles: AngleSet,
    /// `s_a(theta) = sa[0] + sa[1] cos(theta - phi_a)` (turning only).
    sa: [f64; 2],
    /// `(sin, cos)` of `phi_a`.
    phi_a_sc: (f64, f64),
}

impl LineSweep<'_> {
    /// `None` when this pruning does not apply (`a` or `b` is an arc, or
    /// lines `a` and `b` nearly but not exactly parallel) and the caller
    /// must use the annuli. `dmax_ac` bounds the distance between points of
    /// `a` and `c`.
    pub fn new(segs: [&SweptSegment; 3], same_ab: bool, dmax_ac: f64) -> Option<LineSweep<'_>> {
        let a = segs[0].line.as_ref()?;
        let b = segs[1].line.as_ref()?;
        let c = &segs[2].third;
        let (na, nb) = (a.line.n, b.line.n);
        let d = cross(a.line.u, b.line.u);
        let three_parallel = match &segs[2].line {
            Some(lc) => {
                let nc = lc.line.n;
                [cross(nb, nc), cross(nc, na), cross(na, nb)]
                    .iter()
                    .all(|x| x.abs() <= EPS)
            }
            None => false,
        };
        let mode = if d.abs() <= PARALLEL {
            Mode::Sliding
        } else if d.abs() < NEAR_PARALLEL {
            return None;
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
                l2,
                angles: AngleSet::full(),
                sa: [0.0; 2],
                phi_a_sc: (0.0, 1.0),
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
                Some(LinesPoint {
                    l2,
                    angles,
                    sa: [alpha[0], amp],
                    phi_a_sc: (sl * ck + cl * sk, cl * ck - sl * sk),
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
        match self.mode {
            Mode::Sliding => {
                sliding_region(self.a, self.b, self.c, self.same_ab, pt.l2, out);
                true
            }
            Mode::Turning { .. } => turning_region(self, pt, out),
        }
    }
}

/// Lines `a` and `b` not parallel: the part turns through the point's
/// angles, with `s_a(theta) = sa[0] + sa[1] cos(theta - phi_a)`.
fn turning_region(sweep: &LineSweep, pt: &LinesPoint, out: &mut Vec<Quad>) -> bool {
    let (angles, sa, phi_a_sc, dmax_ac) = (&pt.angles, pt.sa, pt.phi_a_sc, sweep.dmax_ac);
    let (a, c) = (sweep.a, sweep.c);
    let h = sa[1];
    // |F''| <= |p - p1| + 2 |p1'| + |p1''| for F = R (p - p1); the widened
    // angles may carry p1 past a's ends by `ANGLE_SLACK h`.
    let k2 = dmax_ac + c.margin + 3.0 * h + ANGLE_SLACK * h + 1e-6;
    let step = (8.0 * TARGET_MARGIN / k2).sqrt();
    let (sin_p, cos_p) = phi_a_sc;
    let mut pieces = 0;
    for &[t0, t1] in angles.intervals() {
        let n = ((t1 - t0) / step).ceil().max(1.0) as usize;
        pieces += n;
        if pieces > MAX_PIECES {
            return false;
        }
        let w = (t1 - t0) / n as f64;
        let margin = w * w / 8.0 * k2 + QUAD_SLACK;
        let posed = |(sin, cos): (f64, f64), out: &mut [V2; MAX_CHORDS + 1]| {
            // cos(theta - phi) = cos cos_p + sin sin_p.
            let p1 = a.point(sa[0] + sa[1] * (cos * cos_p + sin * sin_p));
            c.map_into(|p| rot(cos, sin, p - p1), out);
        };
        let mut sc = t0.sin_cos();
        let mut prev = [V2::zeros(); MAX_CHORDS + 1];
        let mut next = prev;
        posed(sc, &mut prev);
        // Piece ends by turning the previous one: the rounding this adds,
        // n * 1e-16, is far below QUAD_SLACK.
        let step_sc = if n > 1 { w.sin_cos() } else { (0.0, 1.0) };
        for k in 1..=n {
            sc = if k == n {
                t1.sin_cos()
            } else {
                (
                    sc.0 * step_sc.1 + sc.1 * step_sc.0,
                    sc.1 * step_sc.1 - sc.0 * step_sc.0,
                )
            };
            posed(sc, &mut next);
            c.push_quads(&prev, &next, margin, out);
            std::mem::swap(&mut prev, &mut next);
        }
    }
    true
}

/// Lines `a` and `b` parallel (or one segment twice): the ladder `L1 L2`
/// spans the gap between them at one or two angles, and the part slides
/// along them. Each angle gives a parallelogram.
fn sliding_region(
    a: &LinePiece,
    b: &LinePiece,
    c: &ThirdPiece,
    same_ab: bool,
    l2: V2,
    out: &mut Vec<Quad>,
) {
    let (ua, na) = (a.line.u, a.line.n);
    let sigma = if na.dot(&b.line.n) >= 0.0 { 1.0 } else { -1.0 };
    // n_a . (p2 - p1) is the signed gap; the rest of R^T L2 runs along a.
    let gap = sigma * b.line.c - a.line.c;
    // A ladder a hair shorter than the gap may still be a tangent pose
    // for the solver: keep it, at tau = 0.
    if l2.norm() < gap.abs() - 1e-6 {
        return;
    }
    let tau = (l2.norm_squared() - gap * gap).max(0.0).sqrt();
    // On one segment, locator 2 comes after locator 1 along it.
    let taus: &[f64] = if same_ab { &[1.0] } else { &[1.0, -1.0] };
    for &sign in taus {
        let tau = sign * tau;
        let v = na * gap + ua * tau;
        let theta = l2.y.atan2(l2.x) - v.y.atan2(v.x);
        let (sin, cos) = theta.sin_cos();
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
        let mut ends = [[V2::zeros(); MAX_CHORDS + 1]; 2];
        for (e, s1) in ends.iter_mut().zip([lo, hi]) {
            c.map_into(|p| rot(cos, sin, p - a.point(s1)), e);
        }
        c.push_quads(&ends[0], &ends[1], QUAD_SLACK, out);
    }
}

/// A horizontal run of the plate, `y` a lattice row, `x` in `[lo, hi]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Span {
    /// Row.
    pub y: i64,
    /// Smallest x.
    pub lo: f64,
    /// Largest x.
    pub hi: f64,
}

/// Pushes, for every lattice row (multiple of `grid_step`) that `q` reaches, the
/// x range of `q` on that row (a superset: the hull clipped to the strip
/// `|y - row| <= margin`, widened by the margin).
pub fn quad_spans(q: &Quad, grid_step: i64, out: &mut Vec<Span>) {
    let e = q.margin;
    let gf = grid_step as f64;
    let (xs, ys) = (q.pts.map(|p| p.x), q.pts.map(|p| p.y));
    let x_min = xs.iter().copied().fold(f64::INFINITY, f64::min) - e;
    let x_max = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max) + e;
    // Most regions are slivers between lattice columns or rows.
    if (x_min / gf).ceil() * gf > x_max {
        return;
    }
    let y_min = ys.iter().copied().fold(f64::INFINITY, f64::min) - e;
    let y_max = ys.iter().copied().fold(f64::NEG_INFINITY, f64::max) + e;
    let mut y = (y_min / gf).ceil() as i64 * grid_step;
    while (y as f64) <= y_max {
        let (s_lo, s_hi) = (y as f64 - e, y as f64 + e);
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for i in 0..4 {
            for j in i + 1..4 {
                if let Some((x0, x1)) = clip_to_strip(q.pts[i], q.pts[j], s_lo, s_hi) {
                    lo = lo.min(x0);
                    hi = hi.max(x1);
                }
            }
        }
        if lo <= hi {
            out.push(Span {
                y,
                lo: lo - e,
                hi: hi + e,
            });
        }
        y += grid_step;
    }
}

/// The x range of the part of segment `p q` with `y` in `[y0, y1]`.
fn clip_to_strip(p: V2, q: V2, y0: f64, y1: f64) -> Option<(f64, f64)> {
    let dy = q.y - p.y;
    let (t0, t1) = if dy.abs() < 1e-300 {
        if p.y < y0 || p.y > y1 {
            return None;
        }
        (0.0, 1.0)
    } else {
        let (ta, tb) = ((y0 - p.y) / dy, (y1 - p.y) / dy);
        (ta.min(tb).max(0.0), ta.max(tb).min(1.0))
    };
    if t0 > t1 {
        return None;
    }
    let (xa, xb) = (p.x + (q.x - p.x) * t0, p.x + (q.x - p.x) * t1);
    Some((xa.min(xb), xa.max(xb)))
}

/// Buffers of [`LocatorSweep::for_each_third_locator`], reused across `L2`.
#[derive(Debug, Default)]
pub struct SweepScratch {
    quads: Vec<Quad>,
    spans: Vec<Span>,
}

/// Every lattice point (multiples of `grid_step`) of the union of `quads`, row
/// by row, each once.
fn scan_quads(
    quads: &[Quad],
    grid_step: i64,
    spans: &mut Vec<Span>,
    mut visit: impl FnMut([i64; 2]),
) {
    spans.clear();
    for q in quads {
        quad_spans(q, grid_step, spans);
    }
    spans.sort_unstable_by(|a, b| a.y.cmp(&b.y).then(a.lo.total_cmp(&b.lo)));
    let gf = grid_step as f64;
    let mut row = i64::MIN;
    let mut next_x = i64::MIN;
    for s in spans.iter() {
        if s.y != row {
            row = s.y;
            next_x = i64::MIN;
        }
        let mut x = ((s.lo / gf).ceil() as i64 * grid_step).max(next_x);
        while (x as f64) <= s.hi {
            visit([x, s.y]);
            x += grid_step;
        }
        next_x = next_x.max(x);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v2;
    use crate::segments::{Feature, LineFeature};

    #[test]
    fn spans_cover_every_lattice_point_near_the_quad() {
        let q = Quad {
            pts: [v2(0.2, 0.1), v2(3.7, 1.2), v2(0.5, 2.9), v2(3.1, 4.4)],
            margin: 0.3,
        };
        let mut spans = Vec::new();
        quad_spans(&q, 1, &mut spans);
        let mut inside = 0;
        for x in -2..7 {
            for y in -2..7 {
                let d = hull_distance(&q.pts, v2(x as f64, y as f64));
                // Within the margin: listed. Far outside (the spans are a
                // box-shaped superset, up to sqrt 2 margins): not listed.
                if d <= q.margin {
                    assert!(contains(&spans, [x, y]), "{x},{y}");
                    inside += 1;
                } else if d > 1.5 * q.margin {
                    assert!(!contains(&spans, [x, y]), "{x},{y} at {d}");
                }
            }
        }
        assert!(inside > 5);
    }

    /// A segment of the line through `origin` with direction angle `dir`,
    /// contacts in `[s0, s1]`.
    fn line(origin: V2, dir: f64, s0: f64, s1: f64) -> Segment {
        let u = v2(dir.cos(), dir.sin());
        let n = v2(u.y, -u.x);
        Segment {
            edge: 0,
            s0,
            s1,
            feature: Feature::Line(LineFeature::new(origin, u, n)),
        }
    }

    /// Checks that a known setup's `L3` lies in the region built from its
    /// `L2`, and its angle in the angle set.
    fn assert_covered(segs: [&Segment; 3], same_ab: bool, s: [f64; 3], theta: f64) -> bool {
        let p = [0, 1, 2].map(|k| segs[k].point(s[k]));
        let (sin, cos) = theta.sin_cos();
        let l2 = rot(cos, sin, p[1] - p[0]);
        let l3 = rot(cos, sin, p[2] - p[0]);
        let dmax_ac = crate::segments::PairBounds::between(segs[0], segs[2]).dmax;
        let swept = segs.map(SweptSegment::of);
        let Some(sweep) = LocatorSweep::new([&swept[0], &swept[1], &swept[2]], same_ab, dmax_ac)
        else {
            return false; // nearly parallel: the caller scans annuli
        };
        if matches!(
            sweep,
            LocatorSweep::Lines(LineSweep {
                degenerate: true,
                ..
            })
        ) {
            return false;
        }
        let t = crate::geometry::angle_set::wrap_angle(theta);
        let Some(pt) = sweep.pivot_point(l2) else {
            panic!("angle {t} not in an empty angle set");
        };
        assert!(pt.contains_angle(t), "angle {t} not in {pt:?}");
        let mut quads = Vec::new();
        if !sweep.region(&pt, &mut quads) {
            return false; // too many pieces: annuli
        }
        let best = quads
            .iter()
            .map(|q| hull_distance(&q.pts, l3) - q.margin)
            .fold(f64::INFINITY, f64::min);
        assert!(best <= 1e-9, "L3 {l3:?} outside by {best}: {quads:?}");
        true
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig {
            cases: 3000,
            failure_persistence: None,
            ..Default::default()
        })]

        /// Soundness of the pruning: for random segments and a random pose
        /// that puts three contacts on them, the region built from `L2`
        /// holds `L3`, whether the part turns or slides.
        #[test]
        fn every_setup_lies_in_its_region(
            o in proptest::array::uniform3((-5.0f64..5.0, -5.0f64..5.0)),
            dirs in proptest::array::uniform3(0.0f64..std::f64::consts::TAU),
            lens in proptest::array::uniform3(0.5f64..8.0),
            fr in proptest::array::uniform3(0.0f64..1.0),
            theta in 0.0f64..std::f64::consts::TAU,
            kind in 0u8..8,
            sweep in -6.0f64..6.0,
        ) {
            let mut dirs = dirs;
            match kind {
                1 | 5 => dirs[1] = dirs[0],                    // parallel, same way
                2 => dirs[1] = dirs[0] + std::f64::consts::PI, // facing
                _ => {}
            }
            let seg = |k: usize| line(v2(o[k].0, o[k].1), dirs[k], 0.0, lens[k]);
            // An arc (convex or concave, up to almost a full turn),
            // contacts on a piece of it.
            let arc_seg = |k: usize, sweep: f64| {
                let arc = crate::geometry::arc::GrownArc {
                    center: v2(o[k].0, o[k].1),
                    radius: lens[k] / 2.0,
                    start_angle: dirs[k],
                    sweep,
                };
                Segment {
                    edge: 0,
                    s0: 0.1 * arc.length(),
                    s1: 0.9 * arc.length(),
                    feature: Feature::Arc(arc),
                }
            };
            let (a, mut b, mut c) = (seg(0), seg(1), seg(2));
            if kind >= 4 {
                proptest::prop_assume!(sweep.abs() > 1e-3);
            }
            if kind == 4 || kind == 5 || kind == 7 {
                c = arc_seg(2, sweep);
            }
            if kind >= 6 {
                // A line and an arc pivot (the arc's sweep mirrored for
                // the third segment's, so both signs meet).
                b = arc_seg(1, -sweep);
            }
            let s = [0, 1, 2].map(|k| {
                let g = [&a, &b, &c][k];
                g.s0 + fr[k] * (g.s1 - g.s0)
            });
            if kind == 3 {
                // Locators 1 and 2 on one segment, in order along it.
                let s1 = fr[1] * a.s1;
                let (lo, hi) = (s[0].min(s1), s[0].max(s1));
                proptest::prop_assume!(hi - lo > 1e-3);
                assert_covered([&a, &a, &c], true, [lo, hi, s[2]], theta);
            } else {
                let checked = assert_covered([&a, &b, &c], false, s, theta);
                // The line-arc sweep has no fallback short of its piece
                // budget: it must have covered the setup.
                proptest::prop_assert!(checked || kind < 6);
            }
        }
    }

    fn contains(spans: &[Span], p: [i64; 2]) -> bool {
        let x = p[0] as f64;
        spans.iter().any(|s| s.y == p[1] && s.lo <= x && x <= s.hi)
    }

    /// Distance from `p` to the convex hull of four points (brute force:
    /// inside one of the triangles, else the nearest of the six sides).
    fn hull_distance(pts: &[V2; 4], p: V2) -> f64 {
        let tri = |a: V2, b: V2, c: V2| {
            let s = [
                cross(b - a, p - a),
                cross(c - b, p - b),
                cross(a - c, p - c),
            ];
            s.iter().all(|&x| x >= 0.0) || s.iter().all(|&x| x <= 0.0)
        };
        for i in 0..4 {
            for j in 0..4 {
                for k in 0..4 {
                    if i != j && j != k && i != k && tri(pts[i], pts[j], pts[k]) {
                        return 0.0;
                    }
                }
            }
        }
        let mut best = f64::INFINITY;
        for i in 0..4 {
            for j in i + 1..4 {
                best = best.min(crate::geometry::point_segment_dist2(p, pts[i], pts[j]).sqrt());
            }
        }
        best
    }
}
