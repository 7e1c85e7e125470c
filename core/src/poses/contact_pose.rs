//! The part poses that put three locators on three grown features, each a
//! line or an arc's circle (SPEC 8.4): the generalisation of
//! [`crate::poses::pose::solve_poses`] that arcs need.
//!
//! With `p_k = R(theta)^T L_k - w`, a line gives an equation linear in `w`
//! and a circle `|w|^2 +` terms linear in `w`. After moving both frames so
//! that one circle is centred at the origin and its locator at the origin,
//! that circle reads `|w|^2 = rho0^2`, the other two contacts give two rows
//! `b_i(theta) . w = r_i(theta)` (a line as is, a circle minus the first
//! circle), and `w = N / D` by Cramer's rule. Substituting gives one
//! trigonometric polynomial `F = |N|^2 - rho0^2 D^2` of degree <= 4 in
//! `theta` whose roots contain the angle of every isolated pose; where
//! `D(theta) = 0` (two parallel lines, or rows that are parallel at one
//! angle) `w` lies on a line and meets the circle twice, which is how two
//! poses come to share `theta`. Each candidate is polished by Newton's
//! method on the three original equations and kept only if it satisfies
//! them to `eps`, so the elimination only has to find candidates, never to
//! be accurate.
//!
//! Why no pose is missed: the reduction is an equivalence (`w = N / D`
//! wherever `D != 0`), so every isolated pose has its angle among the
//! roots of `F`, of `D`, or (when `D` vanishes identically) of `N`; the
//! root finder in `root_search` discards an interval of angles only when a Taylor
//! bound proves the polynomial nonzero there, and at each candidate angle
//! every `w` the reduced system allows is tried. Continua are recognised
//! structurally: `F` vanishing identically (every angle has a solution),
//! or three circles congruent to the locator triangle (a continuum at one
//! angle, whose fourfold root of `F` is handled in closed form).

mod classify;
mod half_angle;
mod limits;
mod lu3;
mod newton_reach;
mod root_search;
mod taylor5;
mod trig;
mod two_lines;

use crate::geometry::angle_set::{rem_tau, wrap_angle};
use crate::geometry::{cross, rot, rot_t, v2, BORDERLINE, EPS, V2};
use crate::poses::pose::{solve_poses, Line, Pose};
use limits::{CONTINUUM_REL, DEGENERATE_REL, NEAR_MISS, NEAR_PARALLEL_REL, ROUNDING_REL};
use nalgebra::{Matrix3, Vector3};
pub(crate) use newton_reach::Gap;
use trig::{circ_dist, Angles, Trig, COS16, SAMPLES, SIN16};
use two_lines::TwoLines;

/// An arc segment's grown circle `|p - centre| = radius` in the part frame;
/// the solver ignores the arc's span, which the caller checks afterwards as
/// it does a line segment's ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Circle {
    /// Centre in the part frame (lattice units).
    pub centre: V2,
    /// Grown radius `rho_e > 0`.
    pub radius: f64,
}

/// The feature a locator centre must lie on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Contact {
    /// A line segment's grown line; its normal must be a unit vector.
    Line(Line),
    /// An arc segment's grown circle.
    Circle(Circle),
}

impl Contact {
    /// Signed distance of a part-frame point from the feature (`n . p - c`,
    /// or `|p - C| - rho`): the quantity SPEC 8.4 bounds by `eps`.
    pub fn residual(&self, p: V2) -> f64 {
        match self {
            Contact::Line(l) => l.n.dot(&p) - l.c,
            Contact::Circle(c) => (p - c.centre).norm() - c.radius,
        }
    }
}

/// One isolated pose with what the enumeration needs besides the pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPose {
    /// `theta` in `[0, 2 pi)`, its cosine and sine, and `t = R w`.
    pub pose: Pose,
    /// `R^T t`: the unknown the equations are linear in, kept so that
    /// callers need not rotate back.
    pub w: V2,
    /// The Jacobian of the three equations is singular within 1e-6 (SPEC
    /// 8.4): a double root counted once, so the fixture is borderline.
    pub tangential: bool,
}

/// More isolated poses cannot exist: three circles allow at most six (the
/// 3-RPR bound; the eliminant has degree 3), fewer with lines.
pub const MAX_CONTACT_POSES: usize = 8;

/// The poses of one setup, in a fixed-capacity list so that the millions of
/// calls in an enumeration allocate nothing.
#[derive(Debug, Clone, Copy)]
pub struct ContactPoses {
    items: [ContactPose; MAX_CONTACT_POSES],
    len: usize,
}

/// Fills the unused slots of the fixed-capacity lists; a constant, so that
/// building an empty list is a plain copy.
const NO_POSE: ContactPose = ContactPose {
    pose: Pose {
        theta: 0.0,
        cos: 1.0,
        sin: 0.0,
        t: V2::new(0.0, 0.0),
    },
    w: V2::new(0.0, 0.0),
    tangential: false,
};

impl ContactPoses {
    fn new() -> ContactPoses {
        ContactPoses {
            items: [NO_POSE; MAX_CONTACT_POSES],
            len: 0,
        }
    }

    fn push(&mut self, pose: ContactPose) {
        debug_assert!(
            self.len < MAX_CONTACT_POSES,
            "more isolated poses than possible"
        );
        if self.len < MAX_CONTACT_POSES {
            self.items[self.len] = pose;
            self.len += 1;
        }
    }

    /// The poses found, sorted by `theta` (line-only setups keep the order
    /// of [`solve_poses`]).
    pub fn as_slice(&self) -> &[ContactPose] {
        &self.items[..self.len]
    }
}

impl std::ops::Deref for ContactPoses {
    type Target = [ContactPose];

    fn deref(&self) -> &[ContactPose] {
        self.as_slice()
    }
}

/// `|det J| <= TANGENTIAL_DET` (rows of the Jacobian in `(theta, w)` scaled
/// to unit length) makes a pose tangential: floating point locates a double
/// root only to about 1e-8, so a tighter test could not be met (SPEC 8.4).
pub const TANGENTIAL_DET: f64 = BORDERLINE;

/// The row of the Jacobian of one contact's equation in `(theta, w)` and
/// its residual. A locator exactly at a circle's centre has no normal: its
/// row is zero, which makes the pose tangential, as it is in the limit.
fn jacobian_row(contact: &Contact, locator: V2, cos: f64, sin: f64, w: V2) -> (Vector3<f64>, f64) {
    let a = rot_t(cos, sin, locator);
    let da = v2(a.y, -a.x);
    let p = a - w;
    let (u, f) = match contact {
        Contact::Line(line) => (line.n, line.n.dot(&p) - line.c),
        Contact::Circle(c) => {
            let d = p - c.centre;
            let dist = d.norm();
            let u = if dist > 0.0 { d / dist } else { V2::zeros() };
            (u, dist - c.radius)
        }
    };
    (Vector3::new(u.dot(&da), -u.x, -u.y), f)
}

/// `(cos theta, sin theta)`, computed once per angle: the pose solver
/// hands it on wherever the same angle is evaluated again.
fn cos_sin(theta: f64) -> (f64, f64) {
    let (s, c) = theta.sin_cos();
    (c, s)
}

/// Residuals and Jacobian of the three equations at the angle with cosine
/// `c` and sine `s`, and `w`.
fn system(
    contacts: &[Contact; 3],
    locs: &[V2; 3],
    (c, s): (f64, f64),
    w: V2,
) -> (Vector3<f64>, Matrix3<f64>) {
    let mut f = Vector3::zeros();
    let mut j = Matrix3::zeros();
    for k in 0..3 {
        let (row, r) = jacobian_row(&contacts[k], locs[k], c, s, w);
        f[k] = r;
        j.set_row(k, &row.transpose());
    }
    (f, j)
}

/// `det J` with every row scaled to unit length: the tangency measure of
/// SPEC 8.4, in `[-1, 1]` and independent of how each equation is written.
pub fn scaled_jacobian_det(
    contacts: &[Contact; 3],
    locs: &[V2; 3],
    cos: f64,
    sin: f64,
    w: V2,
) -> f64 {
    let mut j = Matrix3::zeros();
    for k in 0..3 {
        let (row, _) = jacobian_row(&contacts[k], locs[k], cos, sin, w);
        j.set_row(k, &row.transpose());
    }
    scaled_det(&j)
}

/// [`scaled_jacobian_det`] of the Jacobian `jacobian` (rows as
/// [`system`] builds them): Newton's last iterate has it at hand.
fn scaled_det(jacobian: &Matrix3<f64>) -> f64 {
    let mut j = Matrix3::zeros();
    for k in 0..3 {
        let row = Vector3::new(jacobian[(k, 0)], jacobian[(k, 1)], jacobian[(k, 2)]);
        let n = row.norm();
        if n == 0.0 {
            return 0.0;
        }
        j.set_row(k, &(row / n).transpose());
    }
    j.determinant()
}

/// Largest `|residual|` of the three equations for a reported pose, using
/// exactly the cosine and sine it reports.
fn max_residual(contacts: &[Contact; 3], locs: &[V2; 3], cos: f64, sin: f64, w: V2) -> f64 {
    largest_abs(&Vector3::from_fn(|k, _| {
        contacts[k].residual(rot_t(cos, sin, locs[k]) - w)
    }))
}

/// Largest `|residual|` of residuals computed already ([`system`] computes
/// each as [`Contact::residual`] does), as [`max_residual`] folds them.
fn largest_abs(residuals: &Vector3<f64>) -> f64 {
    residuals.iter().map(|r| r.abs()).fold(0.0, f64::max)
}

/// Every isolated pose `(theta, w)` that puts `locs[k]` (plate frame) on
/// `contacts[k]` (part frame), SPEC 8.4.
///
/// Three lines go to [`solve_poses`] unchanged, so line-only results (and
/// their `eps` rules for double roots and degenerate triangles) are those
/// of SPEC 3 bit for bit. Otherwise: continua (the equations leave a degree
/// of freedom) give no pose; every pose satisfies each equation to `eps`;
/// solutions within 1e-9 in `theta` and 1e-6 in `w`, or tangential and
/// within 1e-6, are one pose. Non-finite input or a radius `<= 0` gives
/// no pose.
pub fn solve_contact_poses(contacts: &[Contact; 3], locs: &[V2; 3]) -> ContactPoses {
    solve_contact_poses_at_angles(contacts, locs, &|_, _| true)
}

/// [`solve_contact_poses`] when only some angles matter: `within(lo, hi)`
/// is `false` only if no wanted pose has its angle in `[lo, hi]`, and the
/// root search skips those stretches of the circle (most of it, when the
/// setup sweep knows the angles at which two contacts stay on their
/// segments). Poses elsewhere may still be reported.
pub fn solve_contact_poses_at_angles(
    contacts: &[Contact; 3],
    locs: &[V2; 3],
    within: &dyn Fn(f64, f64) -> bool,
) -> ContactPoses {
    let mut out = ContactPoses::new();
    visit_contact_poses_at_angles(contacts, locs, within, None, |pose| out.push(*pose));
    out
}

/// [`solve_contact_poses_at_angles`] handing each pose, in the same order,
/// to `visit` rather than collecting them: the setup search looks at each
/// pose once, and the closed forms of two lines need not copy their
/// solutions into a list of their own first (a list is 520 bytes, moved
/// several times a solve). With `gap`, two lines and a circle drop the
/// starts whose pose `gap` shows the caller would reject (see
/// `newton_reach`): the poses it keeps are the same, in the same order,
/// to the bit, and others may be missing. Returns the number of poses.
pub(crate) fn visit_contact_poses_at_angles(
    contacts: &[Contact; 3],
    locs: &[V2; 3],
    within: &dyn Fn(f64, f64) -> bool,
    gap: Option<&Gap<'_>>,
    visit: impl FnMut(&ContactPose),
) -> usize {
    if !valid(contacts, locs) {
        return 0;
    }
    let lines = contacts.map(|c| match c {
        Contact::Line(l) => Some(l),
        Contact::Circle(_) => None,
    });
    if let [Some(a), Some(b), Some(c)] = lines {
        let poses = line_poses(&[a, b, c], contacts, locs);
        poses.iter().for_each(visit);
        return poses.len();
    }
    if let Some(two) = two_lines_of(contacts, locs) {
        let mut found = Found::new();
        if two_line_poses(&two, contacts, locs, (within, gap), &mut found) {
            let sorted = found.sorted();
            sorted.iter().for_each(visit);
            return sorted.len();
        }
    }
    let mut found = Found::new();
    if !eliminated_into(contacts, locs, within, &mut found) {
        return 0;
    }
    let sorted = found.sorted();
    sorted.iter().for_each(visit);
    sorted.len()
}

/// The general elimination, for any triple with a circle (valid input),
/// into `found` (empty; the caller's, so that its solutions are visited
/// where they lie rather than copied into a list first). `false` when it
/// gives no pose (continua, a degenerate reduction); `found` may then hold
/// candidates that must be ignored.
fn eliminated_into(
    contacts: &[Contact; 3],
    locs: &[V2; 3],
    within: &dyn Fn(f64, f64) -> bool,
    found: &mut Found,
) -> bool {
    Reduced::new(contacts, locs).is_some_and(|red| red.candidates(contacts, locs, within, found))
}

/// [`eliminated_into`] as a list: what the closed forms' tests compare
/// with.
#[cfg(test)]
fn eliminated_poses(
    contacts: &[Contact; 3],
    locs: &[V2; 3],
    within: &dyn Fn(f64, f64) -> bool,
) -> ContactPoses {
    let mut found = Found::new();
    if !eliminated_into(contacts, locs, within, &mut found) {
        return ContactPoses::new();
    }
    found.finish()
}

fn valid(contacts: &[Contact; 3], locs: &[V2; 3]) -> bool {
    let finite = |v: V2| v.x.is_finite() && v.y.is_finite();
    locs.iter().all(|&l| finite(l))
        && contacts.iter().all(|c| match c {
            Contact::Line(l) => finite(l.n) && l.c.is_finite(),
            Contact::Circle(c) => finite(c.centre) && c.radius.is_finite() && c.radius > 0.0,
        })
}

/// The two lines and the circle of a setup with exactly one circle.
fn two_lines_of(contacts: &[Contact; 3], locs: &[V2; 3]) -> Option<TwoLines> {
    let mut lines = [(
        Line {
            n: V2::zeros(),
            c: 0.0,
        },
        V2::zeros(),
    ); 2];
    let (mut count, mut circle) = (0, None);
    for (contact, &locator) in contacts.iter().zip(locs) {
        match contact {
            Contact::Line(line) if count < 2 => {
                lines[count] = (*line, locator);
                count += 1;
            }
            Contact::Line(_) => return None,
            Contact::Circle(c) => circle = Some(((c.centre, c.radius), locator)),
        }
    }
    let (circle, locator) = circle.filter(|_| count == 2)?;
    Some(TwoLines::new(lines, circle, locator))
}

/// The poses of two lines and a circle from the closed forms of
/// [`two_lines`], into `found` (empty; the caller's, so that it is not
/// moved on return): each start is polished by Newton's method like the
/// general elimination's, except exact tangencies, which are checked as
/// they are. `false`, having found nothing, when the closed forms leave
/// the setup to the general elimination (nearly parallel lines).
fn two_line_poses(
    two: &TwoLines,
    contacts: &[Contact; 3],
    locs: &[V2; 3],
    (within, gap): (&dyn Fn(f64, f64) -> bool, Option<&Gap<'_>>),
    found: &mut Found<MAX_CONTACT_POSES>,
) -> bool {
    two.starts(within, |start| {
        let got = if start.exact {
            let iterate = Vector3::new(start.theta, start.w.x, start.w.y);
            polished(contacts, locs, iterate, start.cs, None)
        } else {
            polish_within(contacts, locs, (start.theta, start.cs, start.w), gap)
        };
        if let Some((pose, res)) = got {
            found.insert(pose, res);
        }
    })
}

/// Three lines: SPEC 3's closed form, with `w` and the tangency flag added.
/// Its one-pose answer is a double root merged within `eps`, so tangential.
fn line_poses(lines: &[Line; 3], contacts: &[Contact; 3], locs: &[V2; 3]) -> ContactPoses {
    let (poses, count) = solve_poses(lines, locs);
    let mut out = ContactPoses::new();
    for p in &poses[..count] {
        let w = rot_t(p.cos, p.sin, p.t);
        let det = scaled_jacobian_det(contacts, locs, p.cos, p.sin, w);
        out.push(ContactPose {
            pose: *p,
            w,
            tangential: count == 1 || det.abs() <= TANGENTIAL_DET,
        });
    }
    out
}

/// One of the two linear rows of the reduced system, in the shifted frames.
#[derive(Debug, Clone, Copy)]
enum Row {
    /// `n . w = n . R^T l - c`.
    Line { n: V2, c: f64, l: V2 },
    /// Circle minus the origin circle: `g . w = (|g|^2 - rho^2 + rho0^2) / 2`
    /// with `g = R^T l - centre`.
    Circle { centre: V2, rho: f64, l: V2 },
}

/// The system after moving the part frame by `-part_shift` (the first
/// circle's centre to the origin) and the plate frame by `-plate_shift`
/// (its locator to the origin): `w' = w + part_shift - R^T plate_shift`,
/// that circle is `|w'| = rho0`, and `rows` are the other two contacts.
#[derive(Debug, Clone, Copy)]
struct Reduced {
    rows: [Row; 2],
    rho0: f64,
    part_shift: V2,
    plate_shift: V2,
    /// Angle at which both rows vanish identically with equal radii (three
    /// circles congruent to the locator triangle): the part can then slide
    /// round a circle without turning, a continuum at that angle only.
    continuum_angle: Option<f64>,
}

/// Trigonometric polynomials of the reduced system and the scales of
/// their rounding errors, which scale every tolerance so that the solver
/// does not depend on units.
struct Sampled {
    f: Trig,
    d: Trig,
    /// Samples of `N`'s components, transformed only for nearly parallel
    /// rows, the one case that solves them (most solutions never do).
    nx: [f64; SAMPLES],
    ny: [f64; SAMPLES],
    /// How far a relative error of 1 in every term would move `F`.
    scale_f: f64,
    /// Largest `|b1| |b2|`: the scale of `D`.
    max_dhat: f64,
    /// Largest sum of the magnitudes of the terms of `N`.
    max_nhat: f64,
}

fn perp(vector: V2) -> V2 {
    v2(vector.y, -vector.x)
}

impl Row {
    /// `(b, r, |terms of r|)` at the angle with cosine `cos`, sine `sin`.
    fn eval(&self, cos: f64, sin: f64, rho0: f64) -> (V2, f64, f64) {
        match *self {
            Row::Line { n, c: off, l } => {
                let a = n.dot(&rot_t(cos, sin, l));
                (n, a - off, a.abs() + off.abs())
            }
            Row::Circle { centre, rho, l } => {
                let g = rot_t(cos, sin, l) - centre;
                let g2 = g.norm_squared();
                let (r2, r02) = (rho * rho, rho0 * rho0);
                (g, 0.5 * (g2 - r2 + r02), 0.5 * (g2 + r2 + r02))
            }
        }
    }

    fn shifted(contact: &Contact, locator: V2, part: V2, plate: V2) -> Row {
        match contact {
            Contact::Line(line) => Row::Line {
                n: line.n,
                c: line.c - line.n.dot(&part),
                l: locator - plate,
            },
            Contact::Circle(c) => Row::Circle {
                centre: c.centre - part,
                rho: c.radius,
                l: locator - plate,
            },
        }
    }
}

impl Reduced {
    /// `None` without a circle (three lines take the closed form).
    fn new(contacts: &[Contact; 3], locs: &[V2; 3]) -> Option<Reduced> {
        let k0 = contacts
            .iter()
            .position(|c| matches!(c, Contact::Circle(_)))?;
        let Contact::Circle(c0) = contacts[k0] else {
            return None;
        };
        let (part, plate) = (c0.centre, locs[k0]);
        let others = [(k0 + 1) % 3, (k0 + 2) % 3];
        let rows = others.map(|k| Row::shifted(&contacts[k], locs[k], part, plate));
        let mut red = Reduced {
            rows,
            rho0: c0.radius,
            part_shift: part,
            plate_shift: plate,
            continuum_angle: None,
        };
        red.continuum_angle = red.congruent_angle();
        Some(red)
    }

    /// Both rows vanish at one angle only if both are circle rows with
    /// `l = R(theta0) centre` and equal radii (see `continuum_angle`).
    fn congruent_angle(&self) -> Option<f64> {
        let [Row::Circle {
            centre: c1,
            rho: r1,
            l: l1,
        }, Row::Circle {
            centre: c2,
            rho: r2,
            l: l2,
        }] = self.rows
        else {
            return None;
        };
        let eq = |a: f64, b: f64| (a - b).abs() <= EPS;
        if !eq(r1, self.rho0) || !eq(r2, self.rho0) || !eq(l1.norm(), c1.norm()) {
            return None;
        }
        let theta0 = cross(c1, l1).atan2(c1.dot(&l1));
        let (s, c) = theta0.sin_cos();
        let ok = (rot(c, s, c1) - l1).norm() <= EPS && (rot(c, s, c2) - l2).norm() <= EPS;
        ok.then_some(rem_tau(theta0))
    }

    /// Both rows at one angle, written out rather than mapped over the
    /// array: the sampling loop calls it sixteen times a solution, and the
    /// map's closure was left out of line in some builds (about 1% of the
    /// instructions of a motor mount sheet).
    #[inline]
    fn rows_at(&self, cos: f64, sin: f64) -> [(V2, f64, f64); 2] {
        let [first, second] = &self.rows;
        [
            first.eval(cos, sin, self.rho0),
            second.eval(cos, sin, self.rho0),
        ]
    }

    /// `F`, `D`, `N` sampled at 16 angles, `F` and `D` turned into
    /// coefficients (`N` only where it is solved); sampling the very
    /// expressions that are solved avoids expanding them symbolically (and
    /// the expansion's cancellation).
    fn sample(&self) -> Sampled {
        let (mut f, mut d, mut nx, mut ny) = (
            [0.0; SAMPLES],
            [0.0; SAMPLES],
            [0.0; SAMPLES],
            [0.0; SAMPLES],
        );
        let (mut scale_f, mut max_dhat, mut max_nhat) = (0.0f64, 0.0f64, 0.0f64);
        let r02 = self.rho0 * self.rho0;
        for m in 0..SAMPLES {
            let [(b1, r1, m1), (b2, r2, m2)] = self.rows_at(COS16[m], SIN16[m]);
            let det = cross(b1, b2);
            let n = perp(b2) * r1 - perp(b1) * r2;
            f[m] = n.norm_squared() - r02 * det * det;
            (d[m], nx[m], ny[m]) = (det, n.x, n.y);
            let dhat = b1.norm() * b2.norm();
            let nhat = m1 * b2.norm() + m2 * b1.norm();
            // A relative error e in N and D moves F by about
            // 2 e (|N| nhat + rho0^2 |D| dhat).
            scale_f = scale_f.max(2.0 * (nhat * n.norm() + r02 * dhat * det.abs()));
            max_dhat = max_dhat.max(dhat);
            max_nhat = max_nhat.max(nhat);
        }
        Sampled {
            f: Trig::from_samples(&f),
            d: Trig::from_samples(&d),
            nx,
            ny,
            scale_f,
            max_dhat,
            max_nhat,
        }
    }

    /// Every angle at which an isolated pose can lie; `false` for a
    /// continuum (or a polynomial too degenerate to trust, which is one to
    /// within rounding).
    fn angles(&self, sm: &Sampled, within: &dyn Fn(f64, f64) -> bool, out: &mut Angles) -> bool {
        if let Some(theta0) = self.continuum_angle {
            self.congruent_angles(theta0, out);
            return true;
        }
        if sm.f.max_abs() <= CONTINUUM_REL * sm.scale_f {
            return false;
        }
        let d_max = sm.d.max_abs();
        if d_max > DEGENERATE_REL * sm.max_dhat {
            let tol = NEAR_MISS * self.rho0 * sm.max_dhat * sm.max_dhat;
            root_search::roots(&sm.f, tol, ROUNDING_REL * sm.scale_f, within, out);
            // D has degree <= 1 (the rotation cancels from b1 x b2).
            trig::linear_roots(&sm.d, out);
        }
        if d_max <= NEAR_PARALLEL_REL * sm.max_dhat {
            // Parallel rows: the angle is where they are compatible,
            // N = 0 (both components vanish there; either will do unless
            // it vanishes identically).
            let tol = NEAR_MISS * sm.max_dhat;
            for n in [&sm.nx, &sm.ny].map(Trig::from_samples) {
                if n.max_abs() > ROUNDING_REL * sm.max_nhat {
                    root_search::roots(&n, tol, ROUNDING_REL * sm.max_nhat, within, out);
                }
            }
        }
        !out.overflow
    }

    /// Three circles congruent to the locator triangle turned by `theta0`
    /// (see `continuum_angle`). There `F` has a fourfold root at `theta0`
    /// (`D` and `N` both vanish twice), too flat to isolate in rounding
    /// noise, so the isolated poses are taken in closed form: turned by
    /// `delta` from `theta0`, the rows are the locator triangle scaled by
    /// `2 sin(delta / 2)`, `w'` is its circumcentre, and `|w'| = rho0`
    /// gives `cos(delta) = 1 - rho0^2 / (2 R^2)` (`R` the circumradius;
    /// collinear locators leave no isolated pose).
    fn congruent_angles(&self, theta0: f64, out: &mut Angles) {
        let [Row::Circle { l: l1, .. }, Row::Circle { l: l2, .. }] = self.rows else {
            return;
        };
        let den = 2.0 * cross(l1, l2);
        if den.abs() <= EPS {
            return;
        }
        let (n1, n2) = (l1.norm_squared(), l2.norm_squared());
        let z = v2(l2.y * n1 - l1.y * n2, l1.x * n2 - l2.x * n1) / den;
        let x = 1.0 - self.rho0 * self.rho0 / (2.0 * z.norm_squared());
        if x >= -1.0 - EPS {
            let delta = x.max(-1.0).acos();
            out.push(rem_tau(theta0 + delta));
            out.push(rem_tau(theta0 - delta));
        }
    }

    /// Starting points for `w'` at one angle: Cramer's solution, and where
    /// the rows are nearly parallel also the two points where the line of
    /// solutions of the longer row meets the circle `|w'| = rho0` (the
    /// shared-angle pair), or its closest point when it misses.
    fn w_starts(&self, cos: f64, sin: f64, out: &mut [V2; 3]) -> usize {
        let [(b1, r1, _), (b2, r2, _)] = self.rows_at(cos, sin);
        let (n1, n2) = (b1.norm(), b2.norm());
        let mut k = 0;
        let det = cross(b1, b2);
        if det.abs() > 1e-14 * n1 * n2 {
            // At a root of F, |w'| = rho0; far from it (a root of D that
            // is no root of F) this start is far from any solution.
            let w = (perp(b2) * r1 - perp(b1) * r2) / det;
            if (w.norm() - self.rho0).abs() <= self.rho0 {
                out[k] = w;
                k += 1;
            }
        }
        if det.abs() <= NEAR_PARALLEL_REL * n1 * n2 && n1.max(n2) > 0.0 {
            let (b, r, nb) = if n1 >= n2 { (b1, r1, n1) } else { (b2, r2, n2) };
            let u = b / nb;
            let along = r / nb;
            let tau = (self.rho0 * self.rho0 - along * along).max(0.0).sqrt();
            out[k] = u * along + perp(u) * tau;
            k += 1;
            if tau > 0.0 {
                out[k] = u * along - perp(u) * tau;
                k += 1;
            }
        }
        k
    }

    /// Polishes every candidate into `found`; `false` for a continuum.
    fn candidates(
        &self,
        contacts: &[Contact; 3],
        locs: &[V2; 3],
        within: &dyn Fn(f64, f64) -> bool,
        found: &mut Found,
    ) -> bool {
        let sm = self.sample();
        let mut thetas = Angles::new();
        if !self.angles(&sm, within, &mut thetas) {
            return false;
        }
        let mut starts = [V2::zeros(); 3];
        for &theta in thetas.as_slice() {
            let (c, s) = cos_sin(theta);
            let k = self.w_starts(c, s, &mut starts);
            for &w1 in &starts[..k] {
                let w = w1 - self.part_shift + rot_t(c, s, self.plate_shift);
                let Some((pose, res)) = polish(contacts, locs, theta, (c, s), w) else {
                    continue;
                };
                let on_continuum = self
                    .continuum_angle
                    .is_some_and(|t0| circ_dist(t0, pose.pose.theta) <= BORDERLINE);
                if !on_continuum {
                    found.insert(pose, res);
                }
            }
        }
        true
    }
}

/// Starting points whose residual exceeds this (lattice units) are not
/// near any solution: a root of `D` that is no root of `F`, or an extremum
/// of `F` that misses zero. Genuine candidates start within about 1e-4.
const START_RESIDUAL: f64 = 0.1;

/// Newton's method on the three original equations from `(theta, w)`,
/// keeping the best iterate (at a tangency the Jacobian is singular and the
/// steps stop improving); the pose if it satisfies every equation to `eps`.
///
/// Only converged runs count: quadratic convergence reaches the rounding
/// floor in a few steps, after which the residual merely fluctuates, so a
/// run stops after four steps without progress. A run that is still
/// improving at the iteration cap (60, enough for the linear convergence
/// at a double root) is dropped rather than reported half-polished.
fn polish(
    contacts: &[Contact; 3],
    locs: &[V2; 3],
    theta: f64,
    cs: (f64, f64),
    w: V2,
) -> Option<(ContactPose, f64)> {
    polish_within(contacts, locs, (theta, cs, w), None)
}

/// [`polish`] from `(theta, (cos, sin), w)`, which with `gap` first drops
/// a start that Newton's method cannot carry to a pose the caller keeps
/// (`newton_reach`), from the residuals and Jacobian it starts with.
fn polish_within(
    contacts: &[Contact; 3],
    locs: &[V2; 3],
    (theta, cs, w): (f64, (f64, f64), V2),
    gap: Option<&Gap<'_>>,
) -> Option<(ContactPose, f64)> {
    let mut x = Vector3::new(theta, w.x, w.y);
    let (mut f, mut j) = system(contacts, locs, cs, v2(x[1], x[2]));
    let mut best = (x, cs, f.amax());
    if best.2.is_nan() || best.2 > START_RESIDUAL {
        return None;
    }
    if let Some(gap) = gap {
        let centres = contacts.map(|contact| match contact {
            Contact::Line(_) => None,
            Contact::Circle(circle) => Some(circle.centre),
        });
        if newton_reach::beyond_reach(&centres, locs, cs, w, (&f, &j), gap) {
            return None;
        }
    }
    let mut best_system = (f, j);
    let mut stale = 0;
    let mut converged = false;
    for _ in 0..60 {
        if best.2 == 0.0 || stale >= 4 {
            converged = true;
            break;
        }
        let Some(step) = lu3::solve(&j, &(-f)) else {
            // Exactly singular: a tangency hit exactly.
            converged = true;
            break;
        };
        let len = step.norm();
        if !len.is_finite() {
            return None;
        }
        x += if len > 0.5 { step * (0.5 / len) } else { step };
        let cs = cos_sin(x[0]);
        (f, j) = system(contacts, locs, cs, v2(x[1], x[2]));
        let r = f.amax();
        if r < best.2 {
            best = (x, cs, r);
            best_system = (f, j);
            stale = 0;
        } else {
            stale += 1;
        }
        if len <= f64::EPSILON * (1.0 + x.norm()) {
            converged = true;
            break;
        }
    }
    if !converged {
        return None;
    }
    polished(contacts, locs, best.0, best.1, Some(&best_system))
}

/// The pose at Newton's best `iterate` (whose angle has cosine and sine
/// `cs`, and where the three equations have residuals and Jacobian `at`,
/// when known), if it satisfies every equation to `eps`, with its
/// residual. The angle is wrapped into `[0, 2 pi)`; only a wrap that moves
/// it needs its cosine and sine, residuals and Jacobian anew (the same
/// numbers: what is known was computed from the same angle, cosine, sine
/// and `w` by the same operations).
fn polished(
    contacts: &[Contact; 3],
    locs: &[V2; 3],
    iterate: Vector3<f64>,
    cs: (f64, f64),
    at: Option<&(Vector3<f64>, Matrix3<f64>)>,
) -> Option<(ContactPose, f64)> {
    let theta = wrap_angle(iterate[0]);
    let unmoved = theta.to_bits() == iterate[0].to_bits();
    let (cos, sin) = if unmoved { cs } else { cos_sin(theta) };
    let w = v2(iterate[1], iterate[2]);
    let known = at.filter(|_| unmoved);
    let res = match known {
        Some((f, _)) => largest_abs(f),
        None => max_residual(contacts, locs, cos, sin, w),
    };
    if res.is_nan() || res > EPS {
        return None;
    }
    let det = match known {
        Some((_, j)) => scaled_det(j),
        None => scaled_jacobian_det(contacts, locs, cos, sin, w),
    };
    let pose = ContactPose {
        pose: Pose {
            theta,
            cos,
            sin,
            t: rot(cos, sin, w),
        },
        w,
        tangential: det.abs() <= TANGENTIAL_DET,
    };
    Some((pose, res))
}

/// Working capacity for polished solutions before merging (each candidate
/// angle yields at most three starting points, most converging together).
const FOUND_CAP: usize = 24;

/// Polished solutions, merged by SPEC 8.4's rules as they arrive, at most
/// `CAP` distinct ones. Two lines and a circle take [`MAX_CONTACT_POSES`]:
/// no setup has more isolated poses than a list of them holds, so the
/// solutions of two lines, which were copied into such a list before the
/// setup search looked at them, fit, and a smaller buffer is cheaper to
/// set up (the general elimination's may hold near-duplicates before they
/// merge).
struct Found<const CAP: usize = FOUND_CAP> {
    poses: [ContactPose; CAP],
    res: [f64; CAP],
    n: usize,
}

/// SPEC 8.4: one pose when `theta` differs by <= 1e-9 and `w` by <= 1e-6,
/// or both are tangential and within 1e-6 in both.
fn same_pose(pose: &ContactPose, other: &ContactPose) -> bool {
    let dt = circ_dist(pose.pose.theta, other.pose.theta);
    let dw = (pose.w - other.w).norm();
    (dt <= EPS && dw <= BORDERLINE)
        || (pose.tangential && other.tangential && dt <= BORDERLINE && dw <= BORDERLINE)
}

impl<const CAP: usize> Found<CAP> {
    fn new() -> Found<CAP> {
        Found {
            poses: [NO_POSE; CAP],
            res: [0.0; CAP],
            n: 0,
        }
    }

    /// Adds a solution, or keeps the better-satisfied of it and the pose it
    /// duplicates (tangential if either is).
    fn insert(&mut self, pose: ContactPose, res: f64) {
        for i in 0..self.n {
            if same_pose(&self.poses[i], &pose) {
                let tangential = self.poses[i].tangential || pose.tangential;
                if res < self.res[i] {
                    self.poses[i] = pose;
                    self.res[i] = res;
                }
                self.poses[i].tangential = tangential;
                return;
            }
        }
        debug_assert!(self.n < CAP, "too many distinct solutions");
        if self.n < CAP {
            self.poses[self.n] = pose;
            self.res[self.n] = res;
            self.n += 1;
        }
    }

    /// The solutions sorted by `theta`, then `w`, for a deterministic
    /// order.
    fn sorted(&mut self) -> &[ContactPose] {
        let v = &mut self.poses[..self.n];
        v.sort_by(|a, b| {
            a.pose
                .theta
                .total_cmp(&b.pose.theta)
                .then(a.w.x.total_cmp(&b.w.x))
                .then(a.w.y.total_cmp(&b.w.y))
        });
        v
    }

    /// [`Self::sorted`], as a list of poses.
    #[cfg(test)]
    fn finish(mut self) -> ContactPoses {
        let mut out = ContactPoses::new();
        for p in self.sorted() {
            out.push(*p);
        }
        out
    }
}

#[cfg(test)]
mod reach_tests;
#[cfg(test)]
mod tests;
