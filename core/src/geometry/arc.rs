//! Circular arcs and their distances, intersections and offsets (SPEC 8).
//!
//! An arc is kept both as its DXF description (end points and bulge, exact
//! as read) and as circle, radius and signed sweep, because each question is
//! best answered in one of the two forms: membership of a point in the
//! arc's span is an angle about the midpoint direction (well conditioned at
//! the end points, where chord-side tests are not), while areas and side
//! tests use the chord and bulge (no cancellation when the radius is huge).
//!
//! Tolerances are absolute lengths passed by the caller: validation needs a
//! tolerance relative to the part's size, distances need none.

use crate::geometry::angle_set::rem_tau;
use crate::geometry::{cross, point_segment_dist2, segments_intersect, v2, Aabb, V2};
use std::f64::consts::PI;

/// A circular arc from `a` to `b` (SPEC 8.1).
///
/// `sweep = 4 atan(bulge)` is signed: positive turns counter-clockwise about
/// `center` from `a` to `b`. On a counter-clockwise outline a positive sweep
/// is a convex arc (it bulges outward, to the right of the chord `a -> b`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CircArc {
    /// Start point (exactly the vertex it was built from).
    pub a: V2,
    /// End point (exactly the next vertex).
    pub b: V2,
    /// Centre of the circle.
    pub center: V2,
    /// Radius of the circle, `> 0`.
    pub radius: f64,
    /// The DXF bulge `tan(sweep / 4)`, non-zero.
    pub bulge: f64,
    /// Signed included angle in `(-2 pi, 2 pi)`, non-zero.
    pub sweep: f64,
}

/// The closest pair of points between two curves (or a point and a curve).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Closest {
    /// Their distance (0 when the curves meet).
    pub distance: f64,
    /// The point on the first curve.
    pub p: V2,
    /// The point on the second curve (equal to `p` where the curves meet).
    pub q: V2,
}

impl Closest {
    fn of(p: V2, q: V2) -> Closest {
        Closest {
            distance: (p - q).norm(),
            p,
            q,
        }
    }

    fn meet(p: V2) -> Closest {
        Closest {
            distance: 0.0,
            p,
            q: p,
        }
    }

    fn min(self, other: Closest) -> Closest {
        if other.distance < self.distance {
            other
        } else {
            self
        }
    }

    /// The same pair seen from the other curve.
    pub fn swapped(self) -> Closest {
        Closest {
            distance: self.distance,
            p: self.q,
            q: self.p,
        }
    }
}

/// Counter-clockwise quarter turn.
#[inline]
fn perp(vector: V2) -> V2 {
    v2(-vector.y, vector.x)
}

/// Rotation of `vector` by `angle`.
#[inline]
fn rotate(vector: V2, angle: f64) -> V2 {
    let (s, c) = angle.sin_cos();
    v2(c * vector.x - s * vector.y, s * vector.x + c * vector.y)
}

impl CircArc {
    /// The arc of a vertex with bulge `bulge` to the next vertex; `None` for
    /// a straight edge (`bulge == 0`), a zero-length chord or non-finite
    /// numbers, which validation reports before anyone builds edges.
    ///
    /// The centre is `m + perp(b - a) (1/bulge - bulge) / 4` (`m` the chord
    /// midpoint) and the radius `|b - a| (1/|bulge| + |bulge|) / 4`, written
    /// so that neither overflows for large bulges.
    pub fn from_bulge(a: V2, b: V2, bulge: f64) -> Option<CircArc> {
        let chord = b - a;
        let len = chord.norm();
        if bulge == 0.0 || !bulge.is_finite() || !len.is_finite() || len <= 0.0 {
            return None;
        }
        let center = (a + b) * 0.5 + perp(chord) * ((1.0 / bulge - bulge) * 0.25);
        let radius = len * (1.0 / bulge.abs() + bulge.abs()) * 0.25;
        let arc = CircArc {
            a,
            b,
            center,
            radius,
            bulge,
            sweep: 4.0 * bulge.atan(),
        };
        (center.x.is_finite() && center.y.is_finite() && radius.is_finite()).then_some(arc)
    }

    /// Whether the arc turns counter-clockwise about its centre (convex on a
    /// counter-clockwise outline).
    pub fn is_ccw(&self) -> bool {
        self.sweep > 0.0
    }

    /// Unit vector from the centre to the arc's midpoint: the arc's axis of
    /// symmetry, from which span membership is an angle.
    pub fn axis(&self) -> V2 {
        let c = self.b - self.a;
        v2(c.y, -c.x) * (self.bulge.signum() / c.norm())
    }

    /// The arc's midpoint (chord midpoint plus the sagitta `bulge |b-a| / 2`
    /// to the right of the chord, exact for any radius).
    pub fn midpoint(&self) -> V2 {
        let c = self.b - self.a;
        (self.a + self.b) * 0.5 + v2(c.y, -c.x) * (0.5 * self.bulge)
    }

    /// Arc length.
    pub fn length(&self) -> f64 {
        self.radius * self.sweep.abs()
    }

    /// The point at fraction `t` in `[0, 1]` of the sweep (`a` at 0, `b` at
    /// 1 up to rounding; the end points themselves are `a` and `b`).
    pub fn point_at(&self, t: f64) -> V2 {
        self.center + rotate(self.a - self.center, t * self.sweep)
    }

    /// Unit tangent at `a` in the direction of travel: the chord direction
    /// turned by `-sweep / 2` (exact for huge radii, unlike `perp(a - c)`).
    pub fn tangent_start(&self) -> V2 {
        rotate((self.b - self.a).normalize(), -0.5 * self.sweep)
    }

    /// Unit tangent at `b` in the direction of travel.
    pub fn tangent_end(&self) -> V2 {
        rotate((self.b - self.a).normalize(), 0.5 * self.sweep)
    }

    /// Whether a point `q` of the circle lies on the arc, allowing `tol`
    /// (a length) past either end. The angle between `q - center` and the
    /// axis is compared with half the sweep.
    pub fn contains_on_circle(&self, q: V2, tol: f64) -> bool {
        let e = self.axis();
        let w = q - self.center;
        let angle = cross(e, w).atan2(e.dot(&w)).abs();
        angle <= 0.5 * self.sweep.abs() + tol / self.radius
    }

    /// Nearest point of the arc to `p`: the radial projection when it falls
    /// in the span, otherwise the nearer end point.
    pub fn closest_point(&self, p: V2) -> V2 {
        let w = p - self.center;
        let r = w.norm();
        if r > 0.0 {
            let q = self.center + w * (self.radius / r);
            if self.contains_on_circle(q, 0.0) {
                return q;
            }
        }
        if (p - self.a).norm_squared() <= (p - self.b).norm_squared() {
            self.a
        } else {
            self.b
        }
    }

    /// Distance from `p` to the arc.
    pub fn distance(&self, p: V2) -> f64 {
        (p - self.closest_point(p)).norm()
    }

    /// Whether `p` lies strictly inside the circular segment between the
    /// arc and its chord (boundary points may go either way).
    ///
    /// The segment is the disk cut by the chord's line on the arc's side.
    /// Disk membership uses the power of `p`, `(p-a).(p-b) - (1/bulge -
    /// bulge)/2 * cross(b-a, p-m)`, which needs no centre and stays exact
    /// for nearly straight arcs.
    pub fn segment_contains(&self, p: V2) -> bool {
        let chord = self.b - self.a;
        let m = (self.a + self.b) * 0.5;
        let beyond_chord = self.bulge * cross(chord, p - self.a) < 0.0;
        let power = (p - self.a).dot(&(p - self.b))
            - (1.0 / self.bulge - self.bulge) * 0.5 * cross(chord, p - m);
        beyond_chord && power < 0.0
    }

    /// Bounding box: end points plus the circle's extreme points that lie in
    /// the span.
    pub fn aabb(&self) -> Aabb {
        let mut pts = vec![self.a, self.b];
        for d in [v2(1., 0.), v2(0., 1.), v2(-1., 0.), v2(0., -1.)] {
            let q = self.center + d * self.radius;
            if self.contains_on_circle(q, 0.0) {
                pts.push(q);
            }
        }
        Aabb::of(&pts)
    }

    /// The arc run backwards (`b` to `a`, bulge and sweep negated).
    pub fn reversed(&self) -> CircArc {
        CircArc {
            a: self.b,
            b: self.a,
            bulge: -self.bulge,
            sweep: -self.sweep,
            ..*self
        }
    }

    /// SPEC 8.2's grown arc for a locator of radius `r` on a counter-clockwise
    /// outline: same centre and span, radius `R + r` when convex, `R - r`
    /// when concave, and none when that is `<= eps` (no contact possible).
    pub fn grown(&self, r: f64, eps: f64) -> Option<GrownArc> {
        let rho = if self.is_ccw() {
            self.radius + r
        } else {
            self.radius - r
        };
        if rho.is_nan() || rho <= eps {
            return None;
        }
        let s = self.a - self.center;
        Some(GrownArc {
            center: self.center,
            radius: rho,
            start_angle: s.y.atan2(s.x),
            sweep: self.sweep,
        })
    }
}

/// An arc grown from a part edge (SPEC 8.2), parametrised by arc length.
///
/// Positions run in the direction of the counter-clockwise outline:
/// counter-clockwise about the centre on a convex arc (`sweep > 0`),
/// clockwise on a concave one, from the grown edge's start (`s = 0`) to its
/// end (`s = length()`), like `s` along `u` on a grown line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GrownArc {
    /// Centre, shared with the part edge.
    pub center: V2,
    /// `rho_e`: `R + r` (convex) or `R - r` (concave).
    pub radius: f64,
    /// Angle of the start point about the centre.
    pub start_angle: f64,
    /// The part edge's signed sweep (positive: convex).
    pub sweep: f64,
}

impl GrownArc {
    /// Whether the part edge was convex (then the part lies towards the
    /// centre and the inward contact normal points to it).
    pub fn is_convex(&self) -> bool {
        self.sweep > 0.0
    }

    /// Arc length at radius `rho_e`.
    pub fn length(&self) -> f64 {
        self.radius * self.sweep.abs()
    }

    /// Angle about the centre at arc length `s`.
    pub fn angle_at(&self, s: f64) -> f64 {
        self.start_angle + self.sweep.signum() * s / self.radius
    }

    /// Point at arc length `s` from the start.
    pub fn point_at(&self, s: f64) -> V2 {
        let (sn, cs) = self.angle_at(s).sin_cos();
        self.center + v2(cs, sn) * self.radius
    }

    /// Arc-length parameter of the radial projection of `q`, measured from
    /// the start, in `[length/2 - pi rho, length/2 + pi rho)`: centred on the
    /// arc's midpoint so that points just before the start come out slightly
    /// negative and points just after the end slightly above `length()`,
    /// which is what "strictly inside (`s0 + eps < s < s1 - eps`)" needs.
    pub fn param_of(&self, q: V2) -> f64 {
        let w = q - self.center;
        let rel = self.sweep.signum() * (w.y.atan2(w.x) - self.start_angle);
        let half = 0.5 * self.sweep.abs();
        let wrapped = rem_tau(rel - half + PI) - PI + half;
        wrapped * self.radius
    }

    /// Unit tangent at `s` in the direction of increasing `s`.
    pub fn tangent_at(&self, s: f64) -> V2 {
        let (sn, cs) = self.angle_at(s).sin_cos();
        perp(v2(cs, sn)) * self.sweep.signum()
    }

    /// Unit normal at `s` pointing into the part (SPEC 8.3's `f` for a
    /// contact there): towards the centre on a convex arc, away from it on
    /// a concave one.
    pub fn inward_normal_at(&self, s: f64) -> V2 {
        let (sn, cs) = self.angle_at(s).sin_cos();
        v2(cs, sn) * -self.sweep.signum()
    }
}

/// Up to two points, without allocating (intersections are computed in
/// the pruning loops later).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Hits {
    pts: [V2; 2],
    n: usize,
}

impl Hits {
    fn push(&mut self, p: V2) {
        if self.n < 2 {
            self.pts[self.n] = p;
            self.n += 1;
        }
    }

    /// The points found.
    pub fn as_slice(&self) -> &[V2] {
        &self.pts[..self.n]
    }

    fn filter(self, keep: impl Fn(V2) -> bool) -> Hits {
        let mut out = Hits::default();
        for &p in self.as_slice() {
            if keep(p) {
                out.push(p);
            }
        }
        out
    }
}

/// Points of the closed segment `[a, b]` on the circle `(c, r)`; a line
/// passing within `tol` of tangency touches at the foot point, and points
/// up to `tol` beyond the segment's ends count (moved onto the segment).
pub fn segment_circle(a: V2, b: V2, c: V2, r: f64, tol: f64) -> Hits {
    let d = b - a;
    let len2 = d.norm_squared();
    let mut out = Hits::default();
    if !len2.is_finite() || len2 <= 0.0 {
        return out;
    }
    let len = len2.sqrt();
    let t0 = (c - a).dot(&d) / len2;
    let h = (a + d * t0 - c).norm();
    if h > r + tol {
        return out;
    }
    let w = if h >= r {
        0.0
    } else {
        ((r - h) * (r + h)).sqrt() / len
    };
    let slack = tol / len;
    let ts = if w == 0.0 {
        [t0, f64::NAN]
    } else {
        [t0 - w, t0 + w]
    };
    for t in ts {
        if t >= -slack && t <= 1.0 + slack {
            out.push(a + d * t.clamp(0.0, 1.0));
        }
    }
    out
}

/// Points common to the circles `(c1, r1)` and `(c2, r2)`; circles within
/// `tol` of tangency touch at one point. Circles whose centres are within
/// `tol` (or exactly, when `tol` is 0) give none: the caller decides what a
/// shared circle means.
pub fn circle_circle(c1: V2, r1: f64, c2: V2, r2: f64, tol: f64) -> Hits {
    if r1 > r2 {
        // From the smaller circle: `r1 - x` below then cancels at the
        // small radius, not at a nearly straight arc's huge one.
        return circle_circle(c2, r2, c1, r1, tol);
    }
    let dv = c2 - c1;
    let d = dv.norm();
    let mut out = Hits::default();
    if d.is_nan() || d <= tol || d > r1 + r2 + tol || d < (r1 - r2).abs() - tol {
        return out;
    }
    let e = dv / d;
    // Distance from c1 along e to the radical line, without d^2 + r1^2 - r2^2.
    let x = 0.5 * (d + (r1 - r2) * (r1 + r2) / d);
    let y2 = (r1 - x) * (r1 + x);
    let foot = c1 + e * x;
    if y2 > 0.0 {
        let y = y2.sqrt();
        out.push(foot - perp(e) * y);
        out.push(foot + perp(e) * y);
    } else {
        // Tangent within tol: the point of circle 1 facing circle 2.
        out.push(c1 + e * x.clamp(-r1, r1));
    }
    out
}

/// Points common to the segment `[a, b]` and the arc, with `tol` slack at
/// tangency and at the ends (see [`segment_circle`]).
pub fn segment_arc_intersections(a: V2, b: V2, arc: &CircArc, tol: f64) -> Hits {
    segment_circle(a, b, arc.center, arc.radius, tol).filter(|p| arc.contains_on_circle(p, tol))
}

/// Points common to two arcs on different circles (none for arcs on one
/// circle: see [`same_circle`]), with `tol` slack.
pub fn arc_arc_intersections(p: &CircArc, q: &CircArc, tol: f64) -> Hits {
    circle_circle(p.center, p.radius, q.center, q.radius, tol)
        .filter(|x| p.contains_on_circle(x, tol) && q.contains_on_circle(x, tol))
}

/// Whether two arcs lie on one circle, to within `tol` in centre and
/// radius; such arcs meet along sub-arcs, not at isolated points.
pub fn same_circle(p: &CircArc, q: &CircArc, tol: f64) -> bool {
    (p.center - q.center).norm() <= tol && (p.radius - q.radius).abs() <= tol
}

/// Closest points of a point and the segment `[a, b]`.
pub fn point_segment_closest(p: V2, a: V2, b: V2) -> Closest {
    let d = b - a;
    let len2 = d.norm_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(&d) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    Closest::of(p, a + d * t)
}

/// Closest points of segments `[a, b]` and `[c, d]`; where they cross, the
/// crossing point.
pub fn segment_segment_closest(a: V2, b: V2, c: V2, d: V2) -> Closest {
    if segments_intersect(a, b, c, d) {
        let (r, s) = (b - a, d - c);
        let den = cross(r, s);
        if den != 0.0 {
            let t = (cross(c - a, s) / den).clamp(0.0, 1.0);
            return Closest::meet(a + r * t);
        }
        // Collinear overlap: an end point lying on the other segment.
        for (p, (u, v)) in [(c, (a, b)), (d, (a, b)), (a, (c, d)), (b, (c, d))] {
            if point_segment_dist2(p, u, v) == 0.0 {
                return Closest::meet(p);
            }
        }
    }
    point_segment_closest(a, c, d)
        .min(point_segment_closest(b, c, d))
        .min(point_segment_closest(c, a, b).swapped())
        .min(point_segment_closest(d, a, b).swapped())
}

/// Closest points of a point and an arc.
pub fn point_arc_closest(p: V2, arc: &CircArc) -> Closest {
    Closest::of(p, arc.closest_point(p))
}

/// Closest points of the segment `[a, b]` (first) and an arc (second).
///
/// Without a crossing, the minimum is at an end point of either curve or
/// at an interior pair whose connecting line is normal to both, i.e. the
/// foot of the centre on the segment and the arc point in that direction.
pub fn segment_arc_closest(a: V2, b: V2, arc: &CircArc) -> Closest {
    if let Some(&p) = segment_arc_intersections(a, b, arc, 0.0).as_slice().first() {
        return Closest::meet(p);
    }
    let mut best = point_arc_closest(a, arc)
        .min(point_arc_closest(b, arc))
        .min(point_segment_closest(arc.a, a, b).swapped())
        .min(point_segment_closest(arc.b, a, b).swapped());
    let d = b - a;
    let len2 = d.norm_squared();
    if len2 > 0.0 {
        let t = (arc.center - a).dot(&d) / len2;
        if (0.0..=1.0).contains(&t) {
            let foot = a + d * t;
            let w = foot - arc.center;
            let r = w.norm();
            if r > 0.0 {
                let q = arc.center + w * (arc.radius / r);
                if arc.contains_on_circle(q, 0.0) {
                    best = best.min(Closest::of(foot, q));
                }
            }
        }
    }
    best
}

/// Closest points of two arcs.
///
/// Without a crossing, the minimum is at an end point of either arc or at
/// an interior pair on the line through both centres (the connecting line
/// is normal to both circles); concentric arcs need only the end points.
pub fn arc_arc_closest(p: &CircArc, q: &CircArc) -> Closest {
    if let Some(&x) = arc_arc_intersections(p, q, 0.0).as_slice().first() {
        return Closest::meet(x);
    }
    let mut best = point_arc_closest(p.a, q)
        .min(point_arc_closest(p.b, q))
        .min(point_arc_closest(q.a, p).swapped())
        .min(point_arc_closest(q.b, p).swapped());
    let dv = q.center - p.center;
    let d = dv.norm();
    if d > 0.0 {
        let e = dv / d;
        for sp in [1.0, -1.0] {
            let x = p.center + e * (sp * p.radius);
            if !p.contains_on_circle(x, 0.0) {
                continue;
            }
            for sq in [1.0, -1.0] {
                let y = q.center + e * (sq * q.radius);
                if q.contains_on_circle(y, 0.0) {
                    best = best.min(Closest::of(x, y));
                }
            }
        }
    }
    best
}

/// Area, first moment and polar second moment of the circular segment
/// between an arc and its chord, in the arc's frame: origin the chord
/// midpoint, axis the arc's [`CircArc::axis`]. Unsigned (the segment as a
/// region); see [`crate::outline`] for how it is added or removed.
///
/// With `h` the half chord and `phi = |sweep| / 2` (so `R = h / sin phi`):
/// `S = R^2 (phi - sin phi cos phi)`,
/// `M = R^3 (2/3 sin^3 phi - cos phi (phi - sin phi cos phi))` (first
/// moment along the axis), and `J = R^4 (phi/2 - sin 2phi (2 + cos 2phi)/12
/// - 4/3 cos phi sin^3 phi + cos^2 phi (phi - sin phi cos phi))` (sector
/// minus triangle about the centre, moved to the chord midpoint). Below
/// `phi = 0.5` these cancel badly and their Taylor series in `phi` are used.
pub fn segment_moments(arc: &CircArc) -> (f64, f64, f64) {
    let h = 0.5 * (arc.b - arc.a).norm();
    let phi = 0.5 * arc.sweep.abs();
    let (s, m, j) = if phi < 0.5 {
        unit_segment_series(phi)
    } else {
        unit_segment_closed(phi)
    };
    let h2 = h * h;
    (s * h2, m * h2 * h, j * h2 * h2)
}

/// `(S, M, J)` of the segment of half chord 1 and half angle `phi`, closed
/// form (divided by `sin phi` powers: `R = 1 / sin phi`).
fn unit_segment_closed(phi: f64) -> (f64, f64, f64) {
    let (sn, cs) = phi.sin_cos();
    let core = phi - sn * cs;
    let (sn2, cs2) = (2.0 * phi).sin_cos();
    let sn3 = sn * sn * sn;
    let s = core / (sn * sn);
    let m = (2.0 / 3.0 * sn3 - cs * core) / sn3;
    let f = phi / 2.0 - sn2 * (2.0 + cs2) / 12.0 - 4.0 / 3.0 * cs * sn3 + cs * cs * core;
    (s, m, f / (sn3 * sn))
}

/// The same from the Taylor series (exact to rounding for `phi < 0.5`,
/// where the terms of the closed form are in `phi` and their sum in
/// `phi^5`).
fn unit_segment_series(phi: f64) -> (f64, f64, f64) {
    let x = phi * phi;
    (
        phi * horner(&SERIES_S, x),
        x * horner(&SERIES_M, x),
        phi * horner(&SERIES_J, x),
    )
}

fn horner(c: &[f64], x: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &k| acc * x + k)
}

/// `S / h^2 = phi * sum SERIES_S[k] phi^(2k)` (from sympy).
const SERIES_S: [f64; 13] = [
    0.6666666666666666,
    0.08888888888888889,
    0.012698412698412698,
    0.0016931216931216932,
    0.00021377799155576933,
    2.5972851369676765e-05,
    3.069632699262329e-06,
    3.5543374063967485e-07,
    4.0514123730256185e-08,
    4.561030240918436e-09,
    5.083415171780577e-10,
    5.6188096367579724e-11,
    6.16746452406075e-12,
];

/// `M / h^3 = phi^2 * sum SERIES_M[k] phi^(2k)`.
const SERIES_M: [f64; 13] = [
    0.13333333333333333,
    0.031746031746031744,
    0.005925925925925926,
    0.000962000962000962,
    0.00014285068253322222,
    1.995261254520514e-05,
    2.6657530547975617e-06,
    3.4437005170717757e-07,
    4.332978728872515e-08,
    5.337585930369606e-09,
    6.461631082271668e-10,
    7.709330655075938e-11,
    9.085008995990314e-12,
];

/// `J / h^4 = phi * sum SERIES_J[k] phi^(2k)`.
const SERIES_J: [f64; 13] = [
    0.13333333333333333,
    0.06349206349206349,
    0.017777777777777778,
    0.003848003848003848,
    0.0007142534126661111,
    0.00011971567527123082,
    1.866027138358293e-05,
    2.7549604136574206e-06,
    3.899680855985263e-07,
    5.337585930369606e-08,
    7.107794190498835e-09,
    9.251196786091125e-10,
    1.1810511694787406e-10,
];

#[cfg(test)]
mod tests;
