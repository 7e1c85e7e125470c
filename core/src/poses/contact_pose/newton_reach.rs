//! How far the pose polisher can carry a start, so that a start whose
//! contact lies farther than that off its segment is dropped before it is
//! polished: the setup search would reject its pose (SPEC 8.4: contacts
//! strictly inside their segments), and about half the starts of two
//! lines and an arc end that way (61 k of 112 k on the voron2 deck panel).
//!
//! The bound is the Newton-Kantorovich theorem (Ortega and Rheinboldt,
//! Iterative Solution of Nonlinear Equations, section 12.6), in the
//! Euclidean norm on `x = (theta, w)`. Let `J` be the
//! Jacobian of the three equations and `x0` the start, with
//! `|J(x0)^-1| <= beta`, `|J(x0)^-1 F(x0)| <= eta`, and `J` Lipschitz with
//! constant `lip` on the ball `B(x0, r)`. If `h = beta lip eta <= 1/2` and
//! `r >= t* = (1 - sqrt(1 - 2 h)) / (beta lip)`, every Newton iterate lies
//! in `B(x0, t*)` (and they converge to the one root there). Here `h <=
//! 1/4` is required, so `t* <= 1.18 eta`, and `r = 2 eta` is taken.
//!
//! * `beta`: the Frobenius norm of the inverse (at least its spectral
//!   norm), widened by a millionth for rounding; the condition number is
//!   capped at 1e8, so the computed inverse is accurate to 1e-8.
//! * `eta <= beta |F(x0)|`.
//! * `lip <= sum_k lip_k`, `lip_k` bounding the Hessian of equation `k`
//!   on the ball (the Frobenius norm of the Jacobian's change is at most
//!   the root of the rows' squares). With `a = R^T L` (`|a| = |L|`,
//!   `da / dtheta` and `d2a / dtheta2` of length `|L|`): a line's equation
//!   `n . (a - w) - c` has one second derivative, `-n . a`, so `lip_k =
//!   |L|`; a circle's `|a - w - C| - rho`, at distance `d` from the
//!   centre, has Hessian blocks `|L|^2 / d + |L|` (theta theta), `|L| / d`
//!   (theta w) and `1 / d` (w w), so `lip_k = (|L|^2 + |L| + 1) / d_min +
//!   |L|` with `d_min = d0 - (|L| + 1) r` the least distance on the ball
//!   (required to be at least `d0 / 2`).
//!
//! The polisher is Newton's method but for three things, none of which
//! leaves the ball: steps longer than 0.5 are shortened (`r <= 1/4` is
//! required, so no step is); it reports its best iterate, or the start,
//! all in the ball; and it rounds. Rounding perturbs each step by a few
//! ulps of the numbers involved (coordinates of at most about 1e4 lattice
//! units), which with the condition number capped stays far below
//! `REACH_SLACK`.
//!
//! Contact `k` of a pose in the ball lies within `(|L_k| + 1) r` of its
//! place at the start (`R^T L_k` moves by `|L_k| |dtheta|`, `w` by
//! `|dw|`). A dropped start's pose could also have merged with another
//! (SPEC 8.4, `Found::insert`) and changed which bits or tangency flag that
//! one keeps; every pose whose outcome can differ is linked to the dropped
//! one by a chain of merges, each within `BORDERLINE` in `theta` and in
//! `w`, at most one link per start (`ANGLE_CAP` starts at most), so
//! within `ANGLE_CAP BORDERLINE` of it: `CHAIN`. So a start is dropped
//! only when some contact lies farther than `(|L_k| + 1) (r + CHAIN) +
//! REACH_SLACK` from every point its segment keeps: then that pose and
//! every pose whose bits could differ without it are rejected by the
//! setup search whatever their bits, and every other pose is the same, in
//! the same order.

use super::trig::ANGLE_CAP;
use crate::geometry::{rot_t, BORDERLINE, V2};
use nalgebra::{Matrix3, Vector3};

/// How far merges can move a pose whose outcome depends on a dropped one
/// (see the module doc).
const CHAIN: f64 = ANGLE_CAP as f64 * BORDERLINE;

/// Absolute slack (lattice units) for rounding in the contacts, their
/// distances and Newton's iterates.
const REACH_SLACK: f64 = 1e-6;

/// Condition numbers above this give no bound (the inverse would not be
/// accurate enough to bound by).
const MAX_CONDITION: f64 = 1e8;

/// Locators and starts farther than this from the origin (lattice units)
/// give no bound: the rounding argument of the module doc assumes
/// coordinates of at most about 1e4, so bigger ones are polished as before
/// rather than trusted to `REACH_SLACK`.
const MAX_COORDINATE: f64 = 1e4;

/// Which contacts a pose must keep where: `gap(k, p)` is a lower bound on
/// the distance from the part-frame point `p` to every point at which
/// contact `k` is kept (0 when `p` may be one). The solver drops starts
/// by it; a `gap` that is always 0 drops none.
pub(crate) type Gap<'a> = dyn Fn(usize, V2) -> f64 + 'a;

/// Whether Newton's method from the start `w` at the angle with cosine and
/// sine `cs`, where the equations have residuals `f` and Jacobian `j`,
/// surely ends in a pose the setup search rejects, or in none (see the
/// module doc). `centres` holds each circle contact's centre (`None` for
/// a line).
pub(super) fn beyond_reach(
    centres: &[Option<V2>; 3],
    locs: &[V2; 3],
    (c, s): (f64, f64),
    w: V2,
    (f, j): (&Vector3<f64>, &Matrix3<f64>),
    gap: &Gap<'_>,
) -> bool {
    // Every contact's gap first: the bound is worked out only for a start
    // with one outside (stopping at the first such contact costs more
    // than the calls it saves).
    let gaps: [f64; 3] = std::array::from_fn(|k| gap(k, rot_t(c, s, locs[k]) - w));
    if gaps.iter().all(|&g| g.is_nan() || g <= 0.0) {
        return false;
    }
    let Some(r) = newton_radius(centres, locs, (c, s), w, (f, j)) else {
        return false;
    };
    (0..3).any(|k| gaps[k] > (locs[k].norm() + 1.0) * (r + CHAIN) + REACH_SLACK)
}

/// The radius `r` of a ball round the start that holds every Newton
/// iterate, when the Kantorovich conditions hold (see the module doc).
fn newton_radius(
    centres: &[Option<V2>; 3],
    locs: &[V2; 3],
    (c, s): (f64, f64),
    w: V2,
    (f, j): (&Vector3<f64>, &Matrix3<f64>),
) -> Option<f64> {
    let coordinates = locs.iter().map(|l| l.amax()).fold(w.amax(), f64::max);
    if coordinates.is_nan() || coordinates > MAX_COORDINATE {
        return None;
    }
    let inverse = j.try_inverse()?;
    let beta = inverse.norm() * (1.0 + 1e-6);
    let condition = beta * j.norm();
    if condition.is_nan() || condition > MAX_CONDITION {
        return None; // ill-conditioned, or not finite
    }
    let eta = beta * f.norm();
    let r = 2.0 * eta;
    if r.is_nan() || r > 0.25 {
        return None;
    }
    let mut lip = 0.0;
    for (centre, &locator) in centres.iter().zip(locs) {
        let l = locator.norm();
        lip += match centre {
            None => l,
            Some(centre) => {
                let d0 = (rot_t(c, s, locator) - w - centre).norm();
                let d_min = d0 - (l + 1.0) * r;
                if d_min.is_nan() || d_min < 0.5 * d0 || d_min <= 0.0 {
                    return None;
                }
                (l * l + l + 1.0) / d_min + l
            }
        };
    }
    (beta * lip * eta <= 0.25).then_some(r)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v2;

    fn radius(far: f64) -> Option<f64> {
        let locs = [v2(far, 0.0), v2(0.0, 1.0), v2(1.0, 0.0)];
        let f = Vector3::new(1e-9, 0.0, 0.0);
        newton_radius(
            &[None; 3],
            &locs,
            (1.0, 0.0),
            v2(0.0, 0.0),
            (&f, &Matrix3::identity()),
        )
    }

    #[test]
    fn coordinates_beyond_the_rounding_argument_give_no_bound() {
        assert!(radius(10.0).is_some());
        assert!(radius(2.0 * MAX_COORDINATE).is_none());
        assert!(radius(f64::NAN).is_none());
    }
}
