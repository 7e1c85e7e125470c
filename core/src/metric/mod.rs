//! Quality metrics (SPEC section 6): lower is better.
//!
//! Both built-in metrics are of the max-force family ([`MaxForce`]): one
//! solve per fixture, whose part from the three locators alone
//! ([`Locators`]) a setup works out once for all its clamp candidates,
//! and a loop over the applied wrenches laid out for the vector unit
//! ([`lanes`]); the locator floor is mostly told by the few applied
//! wrenches farthest along each row's direction ([`directions`]).

mod directions;
mod lanes;

use crate::geometry::{cross, V2};
use directions::Directions;
use lanes::{Block, Solve};
use nalgebra::{Matrix3, Vector3};
use std::sync::{Arc, LazyLock, OnceLock};

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

/// A setup's three locator contacts with what a metric works out from
/// them alone ([`Metric::locators`]), once for every clamp candidate of
/// the setup and its locator floor.
#[derive(Debug, Clone)]
pub struct Locators {
    contacts: [PartContact; 3],
    inverse: Inverse,
}

/// The inverse of the locator wrench matrix `[w1 w2 w3]` of the
/// max-force family.
#[derive(Debug, Clone, Copy)]
enum Inverse {
    /// Not worked out (a metric of another family made the [`Locators`]).
    Unknown,
    /// The wrenches are dependent: no fourth contact closes the part.
    Singular,
    /// `W^-1`.
    Of(Matrix3<f64>),
}

impl Locators {
    /// The contacts alone, nothing worked out.
    pub fn new(contacts: [PartContact; 3]) -> Self {
        Locators {
            contacts,
            inverse: Inverse::Unknown,
        }
    }

    /// The three locator contacts.
    pub fn contacts(&self) -> &[PartContact; 3] {
        &self.contacts
    }
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

    /// What the metric can work out from a setup's locators alone, for
    /// [`Self::score_with_locators`] and [`Self::prepared_locators_exceed`]
    /// to share between the setup's candidates (the default: nothing).
    fn locators(&self, contacts: &[PartContact; 3]) -> Locators {
        Locators::new(*contacts)
    }

    /// [`Self::score_bounded`] of the locators and the clamp contact:
    /// the same value, bit for bit.
    fn score_with_locators(
        &self,
        locators: &Locators,
        clamp: &PartContact,
        bound: f64,
        hint: &mut usize,
    ) -> Option<f64> {
        let [a, b, c] = locators.contacts;
        self.score_bounded(&[a, b, c, *clamp], bound, hint)
    }

    /// [`Self::locators_exceed`] of prepared locators: the same answer.
    fn prepared_locators_exceed(&self, locators: &Locators, bound: f64, hint: &mut usize) -> bool {
        self.locators_exceed(&locators.contacts, bound, hint)
    }
}

/// The applied wrenches of a max-force metric, in the blocks its loops
/// take (see [`lanes`]). Its `Debug` leaves out the cells of directions:
/// they are a cache, built as the threads ask, and a part's `Debug` says
/// what it is (`prepared_variants` compares it with a fresh one's).
#[derive(Clone)]
pub struct AppliedWrenches {
    blocks: Vec<Block>,
    /// Largest `|p|`, kept so that the locator floor can often answer
    /// without a loop.
    max_norm: f64,
    /// The wrenches, for [`Self::directions`].
    coords: Vec<[f64; 3]>,
    /// The cells of directions the locator floor and the score ask
    /// first, made at the first question.
    directions: OnceLock<Option<Directions>>,
}

impl std::fmt::Debug for AppliedWrenches {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AppliedWrenches")
            .field("blocks", &self.blocks)
            .field("max_norm", &self.max_norm)
            .finish_non_exhaustive()
    }
}

impl AppliedWrenches {
    /// The wrenches `list`, in any order (a maximum over them is taken).
    pub fn new(list: &[Vector3<f64>]) -> Self {
        let coords: Vec<[f64; 3]> = list.iter().map(|p| [p.x, p.y, p.z]).collect();
        AppliedWrenches {
            blocks: lanes::blocks(&coords),
            max_norm: list.iter().map(|p| p.norm()).fold(0.0, f64::max),
            coords,
            directions: OnceLock::new(),
        }
    }

    /// See `directions`: `None` when the wrenches have no cells (the
    /// blocks decide).
    fn directions(&self) -> Option<&Directions> {
        self.directions
            .get_or_init(|| Directions::new(&self.coords))
            .as_ref()
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
    directions: Arc<AppliedWrenches>,
}

static SPHERE: LazyLock<Arc<AppliedWrenches>> = LazyLock::new(|| {
    Arc::new(AppliedWrenches::new(&fibonacci_sphere(
        MaxForceMetric::DIRECTIONS,
    )))
});

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
/// Every such metric gets [`Metric`], early stop, locator floor and the
/// locators' solve shared by a setup's candidates included.
///
/// With the four contact wrenches `w1..w4` in form closure, the forces
/// that balance an applied wrench `p` form the ray `lambda0 + s mu`,
/// `lambda0 = (-W^-1 p, 0)`, `mu = (-W^-1 w4, 1) > 0` (`W = [w1 w2 w3]`);
/// the smallest non-negative point of the ray is the answer for `p`.
pub trait MaxForce: Send + Sync + std::fmt::Debug {
    /// The wrench of a contact, in the space of the applied wrenches.
    fn wrench(&self, c: &PartContact) -> Vector3<f64>;
    /// The applied wrenches to resist.
    fn applied(&self) -> &AppliedWrenches;
}

impl<T: MaxForce> Metric for T {
    fn score(&self, contacts: &[PartContact; 4]) -> Option<f64> {
        self.score_bounded(contacts, f64::INFINITY, &mut 0)
    }

    fn score_bounded(
        &self,
        contacts: &[PartContact; 4],
        bound: f64,
        hint: &mut usize,
    ) -> Option<f64> {
        let [a, b, c, clamp] = contacts;
        self.score_with_locators(&self.locators(&[*a, *b, *c]), clamp, bound, hint)
    }

    fn locators_exceed(&self, locators: &[PartContact; 3], bound: f64, hint: &mut usize) -> bool {
        self.prepared_locators_exceed(&self.locators(locators), bound, hint)
    }

    fn locators(&self, contacts: &[PartContact; 3]) -> Locators {
        Locators {
            contacts: *contacts,
            inverse: Inverse::of(self, contacts),
        }
    }

    fn score_with_locators(
        &self,
        locators: &Locators,
        clamp: &PartContact,
        bound: f64,
        hint: &mut usize,
    ) -> Option<f64> {
        let inv = Inverse::known(self, locators).matrix()?;
        max_force_bounded(&inv, &self.wrench(clamp), self.applied(), bound, hint)
    }

    fn prepared_locators_exceed(&self, locators: &Locators, bound: f64, hint: &mut usize) -> bool {
        let inv = Inverse::known(self, locators).matrix();
        max_force_floor_exceeds(inv.as_ref(), self.applied(), bound, hint)
    }
}

impl Inverse {
    /// `W^-1` of the locators' wrenches under `metric`.
    fn of<T: MaxForce>(metric: &T, contacts: &[PartContact; 3]) -> Inverse {
        let m = Matrix3::from_columns(&contacts.map(|c| metric.wrench(&c)));
        m.try_inverse().map_or(Inverse::Singular, Inverse::Of)
    }

    /// The inverse `locators` hold, worked out now if a metric of another
    /// family made them.
    fn known<T: MaxForce>(metric: &T, locators: &Locators) -> Inverse {
        match locators.inverse {
            Inverse::Unknown => Inverse::of(metric, &locators.contacts),
            known => known,
        }
    }

    /// The matrix, if there is one.
    fn matrix(self) -> Option<Matrix3<f64>> {
        match self {
            Inverse::Of(inv) => Some(inv),
            Inverse::Unknown | Inverse::Singular => None,
        }
    }
}

impl MaxForce for MaxForceMetric {
    fn wrench(&self, c: &PartContact) -> Vector3<f64> {
        Vector3::new(c.f.x, c.f.y, cross(c.q - self.centroid, c.f) / self.rho)
    }

    fn applied(&self) -> &AppliedWrenches {
        &self.directions
    }
}

/// User-given expected wrenches `(F_x, F_y, tau)` in physical units, `tau`
/// about the part-frame origin.
#[derive(Debug, Clone)]
pub struct WrenchListMetric {
    wrenches: AppliedWrenches,
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
        WrenchListMetric {
            wrenches: AppliedWrenches::new(&wrenches),
            spacing,
        }
    }
}

impl MaxForce for WrenchListMetric {
    fn wrench(&self, c: &PartContact) -> Vector3<f64> {
        Vector3::new(c.f.x, c.f.y, cross(c.q * self.spacing, c.f))
    }

    fn applied(&self) -> &AppliedWrenches {
        &self.wrenches
    }
}

/// `inv`'s rows, as the loops of [`lanes`] take them.
fn rows_of(inv: &Matrix3<f64>) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| inv[(i, j)]))
}

/// The largest contact force over the applied wrenches, in closed form,
/// for the locators' `W^-1` and the clamp's wrench `w4`; stopping as soon
/// as the largest force so far exceeds `bound` (then it is returned:
/// above `bound`, at most the score). The applied wrenches are taken from
/// block `*start` on, wrapping around, and `*start` is left at the one
/// that stopped the search: the wrench that breaks one fixture tends to
/// break its neighbours. A maximum does not depend on the order its terms
/// are taken in, so the score is the same bits whatever `start`. Most
/// scores without a bound (full counts) are told by the few wrenches the
/// cells of directions pick ([`Directions::largest_force`]), which leave
/// `start` as it is.
fn max_force_bounded(
    inv: &Matrix3<f64>,
    w4: &Vector3<f64>,
    applied: &AppliedWrenches,
    bound: f64,
    start: &mut usize,
) -> Option<f64> {
    let l = -(inv * w4);
    let mu = [l[0], l[1], l[2]];
    // The fourth entry of `mu` is 1.
    if mu.iter().any(|&x| x <= 0.0) {
        return None;
    }
    let solve = Solve {
        rows: rows_of(inv),
        mu,
    };
    // With a bound, the blocks mostly stop at the first one (`start`).
    let told = (bound == f64::INFINITY)
        .then(|| {
            applied
                .directions()?
                .largest_force(&solve, applied.max_norm)
        })
        .flatten();
    Some(told.unwrap_or_else(|| lanes::largest_force(&solve, &applied.blocks, bound, start)))
}

/// Whether a floor on the max-force score over every fourth wrench, from
/// the locators' `W^-1` alone (`None`: dependent wrenches), is above
/// `bound`: the clamp's share `s` is never negative and `mu > 0`, so each
/// locator force `lambda0_i + s mu_i` is at least `lambda0_i`, which does
/// not depend on the clamp. Computed with the very operations of the
/// score, so the floor is at most the score in floating point too (adding
/// a non-negative number never rounds below the other). Dependent
/// wrenches: no fourth wrench gives a score, so every score is infinite.
///
/// A row `r_i` of `W^-1` whose length times `max_norm` (a bound on every
/// `|p|`) is below `bound` passes no wrench: by Cauchy-Schwarz each
/// `lambda0_i = -(r_i . p)` is at most `|r_i| |p|`, and the relative
/// margin of 1e-12 is far above the rounding of the dot products and
/// norms (a few 1e-16). Most setups are told so, or by the few wrenches
/// farthest along `-r_i` ([`Directions::row_exceeds`]); the rest by the
/// blocks of every applied wrench ([`lanes::floor_exceeds`], from block
/// `*start` on, left at the block that told: the wrench that floored the
/// last setup tends to floor the next), which give the same answers.
fn max_force_floor_exceeds(
    inv: Option<&Matrix3<f64>>,
    applied: &AppliedWrenches,
    bound: f64,
    start: &mut usize,
) -> bool {
    floor_exceeds_asking(inv, applied, bound, start, AppliedWrenches::directions)
}

/// The floor test through the blocks of every applied wrench alone, as it
/// was before [`Directions`]: the reference the cells must match.
#[cfg(test)]
fn max_force_floor_blocks(
    inv: Option<&Matrix3<f64>>,
    applied: &AppliedWrenches,
    bound: f64,
    start: &mut usize,
) -> bool {
    floor_exceeds_asking(inv, applied, bound, start, |_| None)
}

/// [`max_force_floor_exceeds`], asking `cells` for the cells of
/// directions (none: the blocks decide every row the norms leave open).
fn floor_exceeds_asking<'a>(
    inv: Option<&Matrix3<f64>>,
    applied: &'a AppliedWrenches,
    bound: f64,
    start: &mut usize,
    cells: impl FnOnce(&'a AppliedWrenches) -> Option<&'a Directions>,
) -> bool {
    let Some(inv) = inv else {
        return true;
    };
    // The floor starts at 0, as the score does.
    if 0.0 > bound {
        return true;
    }
    let norms: [f64; 3] = std::array::from_fn(|i| inv.row(i).norm());
    let rows = rows_of(inv);
    let weak = |i: usize| norms[i] * applied.max_norm * (1.0 + 1e-12) <= bound;
    if (0..3).all(weak) {
        return false;
    }
    if let Some(directions) = cells(applied) {
        let mut told = true;
        for i in (0..3).filter(|&i| !weak(i)) {
            if !norms[i].is_finite() {
                told = false;
                break;
            }
            match directions.row_exceeds(&rows[i], norms[i], applied.max_norm, bound) {
                Some(true) => return true,
                Some(false) => {}
                None => told = false,
            }
        }
        if told {
            return false;
        }
    }
    lanes::floor_exceeds(&rows, &norms, &applied.blocks, bound, start)
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
        let applied = AppliedWrenches::new(&sphere);
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
                for first in [0, 7, 31, 300] {
                    let mut start = first;
                    let got = max_force_floor_exceeds(Some(&inv), &applied, bound, &mut start);
                    assert_eq!(got, want, "floor {floor}, rows {rows}, bound {bound}");
                    assert!(start < applied.blocks.len() || start == first, "{start}");
                }
                decided_by_loop += usize::from(bound > floor && bound < rows);
            }
        }
        assert!(decided_by_loop > 100, "{decided_by_loop}");
    }

    /// The floor test with its cells of directions against the blocks
    /// alone (the path before the cells), on random `W^-1` of many
    /// scales, for the sphere, a scattered list and a list with a NaN
    /// (no cells), at bounds at the floor, an ulp either side, a little
    /// below and above it and between it and the row-norm shortcut; and
    /// the cells tell most answers themselves.
    #[test]
    fn floor_through_the_cells_matches_the_blocks() {
        let sphere = fibonacci_sphere(MaxForceMetric::DIRECTIONS);
        let mut rng = crate::test_rng::Xorshift::new(0xf100_7ce1_15ab_cdef);
        let mut rnd = || rng.signed_unit();
        let scattered: Vec<Vector3<f64>> = (0..45)
            .map(|_| Vector3::new(rnd(), 2.0 * rnd(), 0.3 * rnd()))
            .collect();
        let mut with_nan = scattered.clone();
        with_nan[3].y = f64::NAN;
        let (mut told, mut asked, mut yes) = (0, 0, 0);
        for list in [&sphere, &scattered, &with_nan] {
            let applied = AppliedWrenches::new(list);
            for _ in 0..3000 {
                let scale = 10f64.powf(3.0 * rnd());
                let w: [Vector3<f64>; 3] = std::array::from_fn(|_| {
                    Vector3::new(scale * rnd(), scale * rnd(), scale * rnd())
                });
                let Some(inv) = Matrix3::from_columns(&w).try_inverse() else {
                    continue;
                };
                let rows = rows_of(&inv);
                let floor = list
                    .iter()
                    .flat_map(|p| rows.map(|r| -(r[0] * p.x + r[1] * p.y + r[2] * p.z)))
                    .fold(0.0, lanes::fmax);
                let norm = (0..3).map(|i| inv.row(i).norm()).fold(0.0, f64::max);
                let up = f64::from_bits(floor.to_bits() + 1);
                let down = f64::from_bits(floor.to_bits() - 1);
                for bound in [
                    floor,
                    up,
                    down,
                    floor * 0.9,
                    floor * 0.999,
                    floor * 1.001,
                    0.5 * (floor + norm),
                    norm * 0.995,
                    0.0,
                    -0.0,
                    -1.0,
                ] {
                    for first in [0, 9] {
                        let (mut a, mut b) = (first, first);
                        let want = max_force_floor_blocks(Some(&inv), &applied, bound, &mut a);
                        let got = max_force_floor_exceeds(Some(&inv), &applied, bound, &mut b);
                        assert_eq!(got, want, "floor {floor}, bound {bound}, {inv}");
                        assert_eq!(want, floor > bound || 0.0 > bound);
                        yes += usize::from(want);
                    }
                    if let Some(directions) = applied.directions() {
                        asked += 1;
                        let norms: [f64; 3] = std::array::from_fn(|i| inv.row(i).norm());
                        let answers: Vec<Option<bool>> = (0..3)
                            .map(|i| {
                                directions.row_exceeds(&rows[i], norms[i], applied.max_norm, bound)
                            })
                            .collect();
                        told += usize::from(
                            answers.contains(&Some(true)) || answers.iter().all(Option::is_some),
                        );
                    }
                }
            }
        }
        assert!(applied_has_no_cells(&with_nan));
        assert!(
            yes > 20_000 && 10 * told > 8 * asked,
            "{yes} yes, {told} of {asked}"
        );
    }

    fn applied_has_no_cells(list: &[Vector3<f64>]) -> bool {
        AppliedWrenches::new(list).directions().is_none()
    }

    /// The max-force score as it was computed before the loops were laid
    /// out in blocks: one applied wrench at a time through nalgebra, the
    /// reference the blocks must match bit for bit.
    fn one_wrench_score(w: &[Vector3<f64>; 4], applied: &[Vector3<f64>]) -> Option<f64> {
        let inv = Matrix3::from_columns(&[w[0], w[1], w[2]]).try_inverse()?;
        let l = -(inv * w[3]);
        let mu = [l[0], l[1], l[2], 1.0];
        if mu.iter().any(|&x| x <= 0.0) {
            return None;
        }
        let mut worst = 0.0f64;
        for p in applied {
            let l0 = -(inv * p);
            let l0 = [l0[0], l0[1], l0[2], 0.0];
            let mut s = f64::NEG_INFINITY;
            for i in 0..4 {
                s = lanes::fmax(s, -l0[i] / mu[i]);
            }
            for i in 0..4 {
                worst = lanes::fmax(worst, l0[i] + s * mu[i]);
            }
        }
        Some(worst)
    }

    /// The one-wrench floor (`lambda0_i > bound` for some wrench).
    fn one_wrench_floor(w: &[Vector3<f64>; 3], applied: &[Vector3<f64>], bound: f64) -> bool {
        let Some(inv) = Matrix3::from_columns(w).try_inverse() else {
            return true;
        };
        0.0 > bound
            || applied.iter().any(|p| {
                let l0 = -(inv * p);
                (l0[0] > bound) | (l0[1] > bound) | (l0[2] > bound)
            })
    }

    /// Random contacts, one on each side of the square `[-1, 1]^2` (most
    /// in form closure): points on a coarse grid (so that wrenches repeat
    /// and forces tie), normals within 22.5 degrees of the side's in steps
    /// of 11.25, and now and then a repeated or mirrored contact
    /// (dependent wrenches).
    fn random_contacts(rng: &mut crate::test_rng::Xorshift) -> [PartContact; 4] {
        let mut grid = |n: f64| (rng.signed_unit() * n).round() / n;
        let turn = (grid(2.0) * 2.0) as i64;
        let mut c: [PartContact; 4] = std::array::from_fn(|i| {
            let side = (i as i64 + turn).rem_euclid(4) as f64 * std::f64::consts::FRAC_PI_2;
            let a = side + grid(2.0) * std::f64::consts::FRAC_PI_8;
            let (along, across) = (grid(4.0), 1.0);
            let (sin, cos) = side.sin_cos();
            PartContact {
                // The side's inward normal is (cos, sin): the side lies at
                // -across along it.
                q: v2(-across * cos - along * sin, -across * sin + along * cos),
                f: v2(a.cos(), a.sin()),
            }
        });
        match (grid(8.0) * 8.0) as i64 {
            7 => c[2] = c[0],
            6 => c[3] = c[1],
            5 => c[1].f = -c[0].f,
            _ => {}
        }
        c
    }

    /// Every score (full, bounded at, below and above it, from any start)
    /// against the one-wrench formula, bit for bit, for both metrics, a
    /// wrench list whose length is not a multiple of the block (its last
    /// block padded), zero and NaN wrenches included; and the floor's
    /// answer against the one-wrench floor.
    #[test]
    fn scores_match_the_one_wrench_formula_bit_for_bit() {
        let sphere = fibonacci_sphere(MaxForceMetric::DIRECTIONS);
        let list = [
            [1.0, 0.0, 0.0],
            [0.0, -2.0, 0.5],
            [0.0, 0.0, 0.0],
            [-0.3, 0.3, -1.0],
            [f64::NAN, 1.0, 0.0],
            [0.7, 0.7, 0.2],
            [-0.0, 0.0, -0.0],
            [0.2, -0.9, 0.4],
            [1.0, 0.0, 0.0],
            [0.1, 0.1, 3.0],
            [-1.5, 0.4, 0.0],
        ];
        let sphere_metric = MaxForceMetric::new(v2(0.1, -0.2), 0.7);
        let list_metric = WrenchListMetric::new(&list, 2.5);
        let list_vectors: Vec<Vector3<f64>> = list
            .iter()
            .map(|w| Vector3::new(w[0], w[1], w[2]))
            .collect();
        let mut rng = crate::test_rng::Xorshift::new(0x0123_4567_89ab_cdef);
        let (mut scored, mut none) = (0, 0);
        for round in 0..4000 {
            let contacts = random_contacts(&mut rng);
            let (metric, applied): (&dyn Metric, &[Vector3<f64>]) = if round % 3 == 0 {
                (&list_metric, &list_vectors)
            } else {
                (&sphere_metric, &sphere)
            };
            let w = if round % 3 == 0 {
                contacts.map(|c| list_metric.wrench(&c))
            } else {
                contacts.map(|c| sphere_metric.wrench(&c))
            };
            let want = one_wrench_score(&w, applied);
            let bits = |x: Option<f64>| x.map(f64::to_bits);
            assert_eq!(bits(metric.score(&contacts)), bits(want), "{contacts:?}");
            let [a, b, c, clamp] = contacts;
            let locators = metric.locators(&[a, b, c]);
            // Locators a metric of another family made: worked out on use.
            let plain = Locators::new([a, b, c]);
            let got = metric.score_with_locators(&plain, &clamp, f64::INFINITY, &mut 0);
            assert_eq!(bits(got), bits(want));
            for first in [0, 1, 5, 31, 1000] {
                let mut hint = first;
                let got = metric.score_with_locators(&locators, &clamp, f64::INFINITY, &mut hint);
                assert_eq!(bits(got), bits(want));
                let Some(score) = want else {
                    none += 1;
                    continue;
                };
                scored += 1;
                // At the score: the same bits; below it: above the bound,
                // no larger than the score.
                let got = metric.score_bounded(&contacts, score, &mut hint);
                assert_eq!(bits(got), bits(want));
                for below in [score * 0.5, score * (1.0 - 1e-12), 0.0, -1.0] {
                    if below >= score {
                        continue;
                    }
                    let cut = metric.score_with_locators(&locators, &clamp, below, &mut hint);
                    let cut = cut.unwrap_or(f64::NAN);
                    assert!(cut > below && cut <= score, "{cut} {below} {score}");
                }
                for bound in [score * 0.5, score, score * 1.5, -1.0] {
                    let w3 = [w[0], w[1], w[2]];
                    let want = one_wrench_floor(&w3, applied, bound);
                    assert_eq!(
                        metric.prepared_locators_exceed(&locators, bound, &mut hint),
                        want
                    );
                    assert_eq!(metric.locators_exceed(&[a, b, c], bound, &mut hint), want);
                    assert_eq!(
                        metric.prepared_locators_exceed(&plain, bound, &mut hint),
                        want
                    );
                }
            }
        }
        assert!(scored > 4000 && none > 500, "{scored} scored, {none} none");
    }
}
