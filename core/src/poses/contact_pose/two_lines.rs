//! Closed forms for the commonest curved setup: two locators on lines and
//! one on a circle (SPEC 8.4), which the sweep produces whenever a
//! combination has two line segments and an arc.
//!
//! Two lines fix `w` linearly: `n_k . w = A_k cos + B_k sin - c_k` with
//! `A_k = n_k . L_k`, `B_k = n_k x L_k` (SPEC 3). When the normals cross,
//! Cramer's rule with their constant determinant makes `w` affine in
//! `(cos theta, sin theta)`, so the circle's equation `|R^T L - w - C|^2 =
//! rho^2` is a trigonometric polynomial of degree 2, solved by
//! `half_angle` without subdivision. When they are parallel, they are
//! compatible only at the (at most two) angles of `A cos + B sin = C`,
//! where `w` is free along the lines and meets the circle at `tau0 +-
//! sqrt(rho^2 - dl^2)`. Both tangencies there are taken exactly: a
//! compatibility or circle discriminant within rounding of zero is a
//! double root, placed at its closed-form angle or point, where Newton's
//! method (whose Jacobian is singular there) would only wander off by
//! about 1e-8, enough to move a contact exactly at a smooth joint
//! (`s = 0`, inside neither segment, SPEC 8.4) a little inside one.
//! Nearly parallel lines (between the two cases) are left to the general
//! elimination, which tries both.

use super::half_angle;
use super::limits::{CONTINUUM_REL, DEGENERATE_REL, NEAR_MISS, NEAR_PARALLEL_REL, ROUNDING_REL};
use super::trig::{Angles, Trig, Within};
use crate::geometry::{cross, rot90, rot_t, EPS, V2};
use crate::poses::pose::Line;

/// A discriminant within this many ulps of its terms' magnitudes is zero:
/// the double root of an exact tangency, split or lost only by rounding.
const SNAP_REL: f64 = 64.0 * f64::EPSILON;

/// A starting point for one pose.
#[derive(Debug, Clone, Copy)]
pub(super) struct Start {
    /// The angle, in `[0, 2 pi)` or within rounding of it.
    pub theta: f64,
    /// Its cosine and sine.
    pub cs: (f64, f64),
    /// `w` solving both line equations at `theta`.
    pub w: V2,
    /// An exact tangency in closed form: to be checked as it is, not
    /// polished (Newton's method is singular there).
    pub exact: bool,
}

/// The two lines with their locators, and the circle with its locator.
#[derive(Debug, Clone, Copy)]
pub(super) struct TwoLines {
    lines: [(Line, V2); 2],
    centre: V2,
    radius: f64,
    locator: V2,
}

/// `vector` turned a quarter clockwise, as Cramer's rule takes it.
fn clockwise(vector: V2) -> V2 {
    rot90(3, vector)
}

impl TwoLines {
    /// Lines `n . p = c` with the locators on them, and the circle
    /// `|p - centre| = radius` with its locator.
    pub(super) fn new(lines: [(Line, V2); 2], (centre, radius): (V2, f64), locator: V2) -> Self {
        TwoLines {
            lines,
            centre,
            radius,
            locator,
        }
    }

    /// Calls `visit` with a start for every pose (and near miss) at angles
    /// `within` wants; `false`, having called nothing, when the lines are
    /// nearly but not exactly parallel (the general elimination's case).
    pub(super) fn starts(&self, within: &Within, visit: impl FnMut(Start)) -> bool {
        let det = cross(self.lines[0].0.n, self.lines[1].0.n);
        if det.abs() <= DEGENERATE_REL {
            self.parallel(within, visit);
            true
        } else if det.abs() > NEAR_PARALLEL_REL {
            self.crossing(det, within, visit);
            true
        } else {
            false
        }
    }

    /// Crossing lines: `q = R^T L - C - w = q0 + cos qc + sin qs`, and
    /// `|q|^2 - rho^2` expanded into harmonics 0 to 2.
    fn crossing(&self, det: f64, within: &Within, mut visit: impl FnMut(Start)) {
        let [(l1, p1), (l2, p2)] = self.lines;
        let (m1, m2) = (clockwise(l1.n), clockwise(l2.n));
        let w0 = (m1 * l2.c - m2 * l1.c) / det;
        let wc = (m2 * l1.n.dot(&p1) - m1 * l2.n.dot(&p2)) / det;
        let ws = (m2 * cross(l1.n, p1) - m1 * cross(l2.n, p2)) / det;
        let loc = self.locator;
        let (q0, qc, qs) = (-self.centre - w0, loc - wc, clockwise(loc) - ws);
        let rho2 = self.radius * self.radius;
        let (cc, ss) = (qc.norm_squared(), qs.norm_squared());
        let mut f = Trig::default();
        f.a[0] = q0.norm_squared() - rho2 + 0.5 * (cc + ss);
        f.a[1] = 2.0 * q0.dot(&qc);
        f.b[1] = 2.0 * q0.dot(&qs);
        f.a[2] = 0.5 * (cc - ss);
        f.b[2] = qc.dot(&qs);
        let mag = q0.norm() + qc.norm() + qs.norm();
        let scale = mag * mag + rho2;
        if f.max_abs() <= CONTINUUM_REL * scale {
            return; // every angle has a solution: a continuum, no pose
        }
        // A miss by d in the circle moves F by about 2 rho d; the general
        // elimination's band, NEAR_MISS rho / det^2 here, is kept where
        // it is the wider (lines far from perpendicular).
        let tol = NEAR_MISS * self.radius * (2.0f64).max(1.0 / (det * det));
        let mut angles = Angles::new();
        half_angle::roots(&f, tol, ROUNDING_REL * scale, within, &mut angles);
        for &theta in angles.as_slice() {
            let (s, c) = theta.sin_cos();
            visit(Start {
                theta,
                cs: (c, s),
                w: w0 + wc * c + ws * s,
                exact: false,
            });
        }
    }

    /// Parallel lines: the angles where they are compatible, then `w`
    /// along them where the circle's locator meets its circle.
    fn parallel(&self, within: &Within, mut visit: impl FnMut(Start)) {
        let [(l1, p1), (l2, p2)] = self.lines;
        let sign = if l1.n.dot(&l2.n) > 0.0 { 1.0 } else { -1.0 };
        // n1 . w = A1 cos + B1 sin - c1 and sign (n2 . w) = n1 . w.
        let a = l1.n.dot(&p1) - sign * l2.n.dot(&p2);
        let b = cross(l1.n, p1) - sign * cross(l2.n, p2);
        let c = l1.c - sign * l2.c;
        let reach = a.hypot(b);
        if reach == 0.0 {
            return; // the angle is free (or nothing fits): no isolated pose
        }
        let gap = reach - c.abs();
        let noise = SNAP_REL * (p1.norm() + p2.norm() + l1.c.abs() + l2.c.abs());
        let phi = b.atan2(a);
        if gap <= noise {
            if gap >= -EPS {
                // A double root (or a near miss the residual test decides).
                let theta = if c >= 0.0 {
                    phi
                } else {
                    phi + std::f64::consts::PI
                };
                self.along(theta, gap.abs() <= noise, within, &mut visit);
            }
            return;
        }
        let delta = (c / reach).clamp(-1.0, 1.0).acos();
        for theta in [phi - delta, phi + delta] {
            self.along(theta, false, within, &mut visit);
        }
    }

    /// The starts at one angle of two parallel lines: `w = beta n + tau m`
    /// with `beta` from the first line, and `tau` where the locator meets
    /// the circle; `double` when the angle is a double root.
    fn along(&self, theta: f64, double: bool, within: &Within, visit: &mut impl FnMut(Start)) {
        const SLACK: f64 = 1e-6;
        let theta = crate::geometry::angle_set::rem_tau(theta);
        if !within(theta - SLACK, theta + SLACK) {
            return;
        }
        let (s, c) = theta.sin_cos();
        let [(l1, p1), _] = self.lines;
        let (n, m) = (l1.n, rot90(1, l1.n));
        let beta = n.dot(&rot_t(c, s, p1)) - l1.c;
        let g = rot_t(c, s, self.locator) - self.centre;
        let (dl, tau0) = (g.dot(&n) - beta, g.dot(&m));
        let rho = self.radius;
        let noise =
            SNAP_REL * (self.locator.norm() + self.centre.norm() + p1.norm() + l1.c.abs() + rho);
        let start = |tau: f64, exact: bool| Start {
            theta,
            cs: (c, s),
            w: n * beta + m * tau,
            exact,
        };
        if (dl.abs() - rho).abs() <= noise {
            // The locator's line of motion touches the circle.
            visit(start(tau0, true));
        } else if dl.abs() > rho {
            // A near miss, if any, is the closest point.
            if dl.abs() - rho <= NEAR_MISS {
                visit(start(tau0, double));
            }
        } else {
            let root = (rho * rho - dl * dl).sqrt();
            visit(start(tau0 - root, double));
            visit(start(tau0 + root, double));
        }
    }
}
