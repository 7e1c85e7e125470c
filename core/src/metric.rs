//! Quality metrics (SPEC section 6): lower is better.
//!
//! Both built-in metrics share one solve: with the four contact wrenches
//! `w1..w4` in form closure, the forces that balance an applied wrench `p`
//! form the ray `lambda0 + s mu`, `mu = (-W^-1 w4, 1) > 0`; the smallest
//! non-negative point of the ray is the answer for `p`.

use crate::geometry::{cross, V2};
use nalgebra::{Matrix3, Vector3};
use std::sync::{Arc, LazyLock};

/// A contact in the part frame: centre point (on the grown edge) and inward
/// unit normal. The centre and the true contact point lie on the same line of
/// action, so either gives the same wrench.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PartContact {
    /// Centre point.
    pub q: V2,
    /// Inward unit normal.
    pub f: V2,
}

/// A fixture quality metric. Implementations must be deterministic functions
/// of the contacts, so that shards agree bit for bit.
pub trait Metric: Send + Sync + std::fmt::Debug {
    /// Score of a fixture whose contacts (locators 1-3, then clamp) are given
    /// in the part frame, in lattice units. `None` when the contacts do not
    /// hold the part (never for a form-closed fixture).
    fn score(&self, contacts: &[PartContact; 4]) -> Option<f64>;

    /// [`Self::score`] when only a score of at most `bound` matters (the
    /// top-k mode): the same bits when the score is at most `bound`,
    /// otherwise any value above `bound` and no larger than the score, so
    /// a metric may stop as soon as it knows. `hint` is the metric's own
    /// state from one call to the next on a thread (where a search
    /// stopped last time, say); it never changes a score.
    fn score_bounded(
        &self,
        contacts: &[PartContact; 4],
        bound: f64,
        hint: &mut usize,
    ) -> Option<f64> {
        let _ = (bound, hint);
        self.score(contacts)
    }

    /// Whether every fixture with these three locator contacts scores
    /// above `bound` (`None` scores count as infinite), whatever the clamp
    /// contact: a top-k whose k-th score is `bound` then skips the setup's
    /// mount searches. `false` (the default) knows nothing. `hint` is as
    /// in [`Self::score_bounded`] (and may be the same state): it never
    /// changes the answer.
    fn locators_exceed(&self, locators: &[PartContact; 3], bound: f64, hint: &mut usize) -> bool {
        let _ = (locators, bound, hint);
        false
    }
}

/// SPEC 6 default: the largest contact force needed to resist any unit
/// wrench of a 256-point Fibonacci sphere, torques scaled by the radius of
/// gyration so forces and torques weigh alike.
#[derive(Debug, Clone)]
pub struct MaxForceMetric {
    centroid: V2,
    rho: f64,
    /// Shared by every part: computing the sphere was a fifth of `prepare`.
    directions: Arc<[Vector3<f64>]>,
    /// Largest `|p|` of `directions` (1 up to rounding).
    max_norm: f64,
}

static SPHERE: LazyLock<Arc<[Vector3<f64>]>> =
    LazyLock::new(|| fibonacci_sphere(MaxForceMetric::DIRECTIONS).into());

static SPHERE_MAX_NORM: LazyLock<f64> =
    LazyLock::new(|| SPHERE.iter().map(|p| p.norm()).fold(0.0, f64::max));

impl MaxForceMetric {
    /// Applied wrench directions (SPEC 6).
    pub const DIRECTIONS: usize = 256;

    /// The metric of a part with this centroid and radius of gyration
    /// (part frame, lattice units): torques are taken about the centroid
    /// and divided by `rho`, so the score does not depend on where the
    /// part frame's origin is.
    pub fn new(centroid: V2, rho: f64) -> Self {
        MaxForceMetric {
            centroid,
            rho,
            directions: SPHERE.clone(),
            max_norm: *SPHERE_MAX_NORM,
        }
    }
}

/// SPEC 6's applied wrench directions.
pub fn fibonacci_sphere(n: usize) -> Vec<Vector3<f64>> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
            let phi = i as f64 * golden;
            let r = (1.0 - z * z).sqrt();
            Vector3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

/// A metric of the max-force family: the largest contact force over a
/// set of applied wrenches, for contact wrenches written in its own way.
/// Every such metric gets [`Metric`], early stop and locator floor
/// included.
pub trait MaxForce: Send + Sync + std::fmt::Debug {
    /// The wrench of a contact, in the space of the applied wrenches.
    fn wrench(&self, c: &PartContact) -> Vector3<f64>;
    /// The applied wrenches to resist.
    fn applied(&self) -> &[Vector3<f64>];
    /// The largest `|p|` of [`Self::applied`], kept so that the locator
    /// floor can often answer without a loop.
    fn applied_max_norm(&self) -> f64;
}

impl<T: MaxForce> Metric for T {
    fn score(&self, contacts: &[PartContact; 4]) -> Option<f64> {
        max_force(&contacts.map(|c| self.wrench(&c)), self.applied())
    }

    fn score_bounded(
        &self,
        contacts: &[PartContact; 4],
        bound: f64,
        hint: &mut usize,
    ) -> Option<f64> {
        let w = contacts.map(|c| self.wrench(&c));
        max_force_bounded(&w, self.applied(), bound, hint)
    }

    fn locators_exceed(&self, locators: &[PartContact; 3], bound: f64, hint: &mut usize) -> bool {
        let w = locators.map(|c| self.wrench(&c));
        max_force_floor_exceeds(&w, self.applied(), self.applied_max_norm(), bound, hint)
    }
}

impl MaxForce for MaxForceMetric {
    fn wrench(&self, c: &PartContact) -> Vector3<f64> {
        Vector3::new(c.f.x, c.f.y, cross(c.q - self.centroid, c.f) / self.rho)
    }

    fn applied(&self) -> &[Vector3<f64>] {
        &self.directions
    }

    fn applied_max_norm(&self) -> f64 {
        self.max_norm
    }
}

/// User-given expected wrenches `(F_x, F_y, tau)` in physical units, `tau`
/// about the part-frame origin.
#[derive(Debug, Clone)]
pub struct WrenchListMetric {
    wrenches: Vec<Vector3<f64>>,
    /// Largest `|p|` of `wrenches`.
    max_norm: f64,
    /// Catalogue units per lattice unit, to put contact points in physical units.
    spacing: f64,
}

impl WrenchListMetric {
    /// `spacing` converts contact points back to the unit the wrenches'
    /// torques are given in.
    pub fn new(wrenches: &[[f64; 3]], spacing: f64) -> Self {
        let wrenches: Vec<Vector3<f64>> = wrenches
            .iter()
            .map(|w| Vector3::new(w[0], w[1], w[2]))
            .collect();
        let max_norm = wrenches.iter().map(|p| p.norm()).fold(0.0, f64::max);
        WrenchListMetric {
            wrenches,
            max_norm,
            spacing,
        }
    }
}

impl MaxForce for WrenchListMetric {
    fn wrench(&self, c: &PartContact) -> Vector3<f64> {
        Vector3::new(c.f.x, c.f.y, cross(c.q * self.spacing, c.f))
    }

    fn applied(&self) -> &[Vector3<f64>] {
        &self.wrenches
    }

    fn applied_max_norm(&self) -> f64 {
        self.max_norm
    }
}

/// Largest contact force over the applied wrenches, in closed form.
pub fn max_force(w: &[Vector3<f64>; 4], applied: &[Vector3<f64>]) -> Option<f64> {
    max_force_bounded(w, applied, f64::INFINITY, &mut 0)
}

/// [`max_force`], stopping as soon as the largest force so far exceeds
/// `bound` (then it is returned: above `bound`, at most the score). The
/// applied wrenches are taken from `*start` on, wrapping around, and
/// `*start` is left at the one that stopped the search: the wrench that
/// breaks one fixture tends to break its neighbours. A maximum does not
/// depend on the order its terms are taken in, so the score is the same
/// bits whatever `start`.
pub fn max_force_bounded(
    w: &[Vector3<f64>; 4],
    applied: &[Vector3<f64>],
    bound: f64,
    start: &mut usize,
) -> Option<f64> {
    let m = Matrix3::from_columns(&[w[0], w[1], w[2]]);
    let inv = m.try_inverse()?;
    let l = -(inv * w[3]);
    let mu = [l[0], l[1], l[2], 1.0];
    if mu.iter().any(|&x| x <= 0.0) {
        return None;
    }
    let first = if *start < applied.len() { *start } else { 0 };
    let (tail, head) = applied.split_at(first);
    let mut worst = 0.0f64;
    for (i, p) in head.iter().chain(tail).enumerate() {
        worst = fmax(worst, largest_force(&inv, &mu, p));
        if worst > bound {
            *start = (first + i) % applied.len();
            return Some(worst);
        }
    }
    Some(worst)
}

/// The larger of `a` and `b` as one `maxsd`: `f64::max`'s NaN rule costs
/// several instructions in the metric's inner loop, where the accumulator
/// `a` is never NaN (a NaN `b` is ignored, as `f64::max` would).
#[inline(always)]
fn fmax(a: f64, b: f64) -> f64 {
    if b > a {
        b
    } else {
        a
    }
}

/// The largest of the four contact forces that resist the applied wrench
/// `p`: the smallest non-negative point of the ray `lambda0 + s mu`.
#[inline(always)]
fn largest_force(inv: &Matrix3<f64>, mu: &[f64; 4], p: &Vector3<f64>) -> f64 {
    // lambda0 = (-W^-1 p, 0)
    let l0 = -(inv * p);
    let l0 = [l0[0], l0[1], l0[2], 0.0];
    let mut s = f64::NEG_INFINITY;
    for i in 0..4 {
        s = fmax(s, -l0[i] / mu[i]);
    }
    let mut worst = 0.0f64;
    for i in 0..4 {
        worst = fmax(worst, l0[i] + s * mu[i]);
    }
    worst
}

/// Whether a floor on [`max_force`] over every fourth wrench, from the
/// first three alone, is above `bound`: the clamp's share `s` is never
/// negative and `mu > 0`, so each locator force `lambda0_i + s mu_i` is at
/// least `lambda0_i`, which does not depend on the clamp. Computed with the
/// very operations of [`max_force`], so the floor is at most the score in
/// floating point too (adding a non-negative number never rounds below the
/// other). The first applied wrench above `bound` settles it, so most
/// setups that fail stop after a few, fewer still from `*start` on (the
/// wrench that floored the last setup tends to floor the next, as in
/// [`max_force_bounded`]; `*start` is left at it). Dependent wrenches: no
/// fourth wrench gives a score, so every score is infinite.
///
/// Most setups that pass are told without the loop: by Cauchy-Schwarz
/// each `lambda0_i = -(r_i . p)` is at most `|r_i| |p|` (`r_i` a row of
/// `W^-1`), so when the largest row norm times `max_norm` (a bound on
/// every `|p|`) is below `bound` no wrench can pass it. The relative
/// margin of 1e-12 is far above the rounding of the dot products and
/// norms (a few 1e-16).
pub fn max_force_floor_exceeds(
    w: &[Vector3<f64>; 3],
    applied: &[Vector3<f64>],
    max_norm: f64,
    bound: f64,
    start: &mut usize,
) -> bool {
    let m = Matrix3::from_columns(w);
    let Some(inv) = m.try_inverse() else {
        return true;
    };
    // The floor starts at 0, as the score does.
    if 0.0 > bound {
        return true;
    }
    let rows = (0..3).map(|i| inv.row(i).norm()).fold(0.0, f64::max);
    if rows * max_norm * (1.0 + 1e-12) <= bound {
        return false;
    }
    let first = if *start < applied.len() { *start } else { 0 };
    let (tail, head) = applied.split_at(first);
    for (i, p) in head.iter().chain(tail).enumerate() {
        if floor_above(&inv, p, bound) {
            *start = (first + i) % applied.len();
            return true;
        }
    }
    false
}

/// Whether a locator force resisting `p` is above `bound` with the
/// clamp's share at zero (`lambda0_i = -(W^-1 p)_i`): inlined in the loop
/// of [`max_force_floor_exceeds`] (as a closure it was a call per
/// wrench), the three comparisons without branches.
#[inline(always)]
fn floor_above(inv: &Matrix3<f64>, p: &Vector3<f64>, bound: f64) -> bool {
    let l0 = -(inv * p);
    (l0[0] > bound) | (l0[1] > bound) | (l0[2] > bound)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v2;

    #[test]
    fn fibonacci_directions_are_unit_and_balanced() {
        let d = fibonacci_sphere(256);
        assert_eq!(d.len(), 256);
        let sum: Vector3<f64> = d.iter().sum();
        assert!(d.iter().all(|x| (x.norm() - 1.0).abs() < 1e-12));
        assert!(sum.norm() < 1.0, "{sum}");
        assert!((d[0].z - (1.0 - 1.0 / 256.0)).abs() < 1e-15);
    }

    #[test]
    fn square_held_at_four_sides() {
        // Unit square, one contact per side, placed so that two turn it
        // each way (form closure).
        let c = [
            PartContact {
                q: v2(0.3, 0.0),
                f: v2(0.0, 1.0),
            },
            PartContact {
                q: v2(1.0, 0.7),
                f: v2(-1.0, 0.0),
            },
            PartContact {
                q: v2(0.7, 1.0),
                f: v2(0.0, -1.0),
            },
            PartContact {
                q: v2(0.0, 0.3),
                f: v2(1.0, 0.0),
            },
        ];
        let m = MaxForceMetric::new(v2(0.5, 0.5), (1.0f64 / 6.0).sqrt());
        let s = m.score(&c).unwrap();
        assert!(s.is_finite() && s > 0.5, "{s}");
        // A pure +x force of magnitude 1 needs at least a force of 1 at the
        // contact pushing -x.
        let wl = WrenchListMetric::new(&[[1.0, 0.0, 0.0]], 1.0);
        let f = wl.score(&c).unwrap();
        assert!(f >= 1.0 - 1e-12, "{f}");
    }

    /// The floor test against the plain maximum over every applied
    /// wrench, at bounds just below and above the floor and between the
    /// floor and the row-norm shortcut (where the loop must decide).
    #[test]
    fn floor_test_agrees_with_the_full_maximum() {
        let sphere = fibonacci_sphere(MaxForceMetric::DIRECTIONS);
        let max_norm = sphere.iter().map(|p| p.norm()).fold(0.0, f64::max);
        let mut rng = crate::test_rng::Xorshift::new(0x9e37_79b9_7f4a_7c15);
        let mut rnd = || rng.signed_unit();
        let mut decided_by_loop = 0;
        for _ in 0..500 {
            let w: [Vector3<f64>; 3] = std::array::from_fn(|_| Vector3::new(rnd(), rnd(), rnd()));
            let Some(inv) = Matrix3::from_columns(&w).try_inverse() else {
                continue;
            };
            let floor = sphere
                .iter()
                .map(|p| {
                    let l0 = -(inv * p);
                    l0[0].max(l0[1]).max(l0[2])
                })
                .fold(0.0, f64::max);
            let rows = (0..3).map(|i| inv.row(i).norm()).fold(0.0, f64::max);
            for bound in [
                floor * (1.0 - 1e-9),
                floor,
                0.5 * (floor + rows),
                rows * 1.01,
            ] {
                let want = floor > bound;
                // Any start gives the same answer (and a valid next start).
                for first in [0, 97, 255, 300] {
                    let mut start = first;
                    let got = max_force_floor_exceeds(&w, &sphere, max_norm, bound, &mut start);
                    assert_eq!(got, want, "floor {floor}, rows {rows}, bound {bound}");
                    assert!(start < sphere.len() || start == first, "{start}");
                }
                decided_by_loop += usize::from(bound > floor && bound < rows);
            }
        }
        assert!(decided_by_loop > 100, "{decided_by_loop}");
    }
}
