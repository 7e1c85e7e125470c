//! Which applied wrenches can be the farthest along a direction: the
//! locator floor ([`super::max_force_floor_exceeds`]) asks, for each row
//! `r` of `W^-1`, whether some applied wrench `p` has `-(r . p)` above a
//! bound, and the answer is decided by the few wrenches farthest along
//! `-r`. The directions are cut into the cells of a cube map; each cell
//! keeps the wrenches that can be the farthest along some direction of
//! the cell ("candidates"), and a bound on how far along any direction of
//! the cell every other wrench reaches. A setup then tells its floor from
//! a handful of wrenches instead of the blocks of all 256 of the sphere:
//! a candidate above the bound answers yes with the very number the
//! blocks would compute, and the bound on the others answers no when it
//! is below the bound of the test; otherwise the blocks decide.

use super::lanes::{self, fmax, Solve};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::OnceLock;

/// Cells per side of a cube face: a cell spans at most about 0.25 rad,
/// so some nine wrenches of the 256-direction sphere are candidates of a
/// cell (fifteen at most).
const SIDE: usize = 8;

/// Margin, relative to the largest `|p|`, on every bound worked out when
/// a cell is built (its sines, cosines and products round by a few
/// `1e-16`).
const BUILD_MARGIN: f64 = 1e-9;

/// How far, in radians, each cell's cap of directions reaches beyond the
/// cell's corners: a direction computed from a row lands in the cell of
/// its computed ratios, within a few ulps of the cell of its exact ones.
const CAP_MARGIN: f64 = 1e-6;

/// Questions a cell leaves to the blocks before it is built: a cell of
/// the sphere costs some 18,000 instructions to build, the blocks some
/// 300 to 2,000 a question, so a run that asks the floor only now and
/// then (a small part) builds no cell, and one that asks it a hundred
/// thousand times pays a few questions a cell.
const BUILD_AFTER: u32 = 8;

/// The cells of the cube map of directions, each built once
/// [`BUILD_AFTER`] questions have landed in it.
#[derive(Debug, Clone)]
pub(crate) struct Directions {
    /// The applied wrenches.
    wrenches: Vec<[f64; 3]>,
    /// Each wrench's length and direction (zero: no direction).
    polar: Vec<(f64, [f64; 3])>,
    /// [`BUILD_MARGIN`] times the largest length.
    margin: f64,
    /// `6 * SIDE * SIDE` cells: face (axis, then sign), then `a`, then `b`.
    cells: Vec<OnceLock<Cell>>,
    /// Questions each cell was asked before it was built.
    asked: Vec<Asked>,
}

/// A count of questions, shared by the threads (which cells get built
/// when depends on them; no answer does).
#[derive(Debug, Default)]
struct Asked(AtomicU32);

impl Clone for Asked {
    fn clone(&self) -> Self {
        Asked(AtomicU32::new(self.0.load(Ordering::Relaxed)))
    }
}

/// One cell of [`Directions`].
#[derive(Debug, Clone)]
struct Cell {
    /// The wrenches that can be the farthest along a direction of the
    /// cell, farthest reach first (the ones most likely to answer yes
    /// come first).
    candidates: Vec<[f64; 3]>,
    /// At least `u . p` for every unit direction `u` of the cell and
    /// every applied wrench `p` that is not a candidate; never negative.
    others: f64,
}

/// The unit vector along `v`.
fn unit(v: [f64; 3]) -> [f64; 3] {
    let length = dot(v, v).sqrt();
    v.map(|x| x / length)
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The face axes: the face's own axis `k`, then the two others in
/// order.
fn axes(k: usize) -> (usize, usize) {
    ((k + 1) % 3, (k + 2) % 3)
}

/// The direction through point `(a, b)` of face `face` (not unit).
fn on_face(face: usize, a: f64, b: f64) -> [f64; 3] {
    let k = face / 2;
    let (k1, k2) = axes(k);
    let mut v = [0.0; 3];
    v[k] = if face.is_multiple_of(2) { 1.0 } else { -1.0 };
    v[k1] = a;
    v[k2] = b;
    v
}

/// A cell's edge, from `-1` to `1` in `SIDE` steps.
fn edge(i: usize) -> f64 {
    -1.0 + 2.0 * i as f64 / SIDE as f64
}

impl Directions {
    /// The cells for these applied wrenches; `None` when a coordinate is
    /// not finite or there are none (the blocks then decide everything).
    pub(crate) fn new(wrenches: &[[f64; 3]]) -> Option<Directions> {
        if wrenches.is_empty() || wrenches.iter().flatten().any(|x| !x.is_finite()) {
            return None;
        }
        let polar: Vec<(f64, [f64; 3])> = wrenches
            .iter()
            .map(|&p| {
                let length = dot(p, p).sqrt();
                let along = if length > 0.0 {
                    p.map(|x| x / length)
                } else {
                    [0.0; 3]
                };
                (length, along)
            })
            .collect();
        let max_norm = polar.iter().map(|w| w.0).fold(0.0, f64::max);
        Some(Directions {
            wrenches: wrenches.to_vec(),
            polar,
            margin: BUILD_MARGIN * max_norm,
            cells: (0..6 * SIDE * SIDE).map(|_| OnceLock::new()).collect(),
            asked: (0..6 * SIDE * SIDE).map(|_| Asked::default()).collect(),
        })
    }

    /// Cell `index`: its cap of directions (around the direction through
    /// its middle, holding its corners: the cell is convex on the face
    /// plane, and so is the cap's trace there, so the corners settle
    /// it), then each wrench's reach over the cap; the candidates are
    /// those whose upper reach is not below the best lower one.
    fn build(&self, index: usize) -> Cell {
        let (face, ia, ib) = (index / (SIDE * SIDE), index / SIDE % SIDE, index % SIDE);
        let (a0, a1, b0, b1) = (edge(ia), edge(ia + 1), edge(ib), edge(ib + 1));
        let centre = unit(on_face(face, 0.5 * (a0 + a1), 0.5 * (b0 + b1)));
        let corners = [(a0, b0), (a0, b1), (a1, b0), (a1, b1)];
        let cos = corners
            .iter()
            .map(|&(a, b)| dot(centre, unit(on_face(face, a, b))))
            .fold(1.0, f64::min);
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        // Widened by CAP_MARGIN: cos(rho + d) >= cos - d sin - d^2.
        let cos = cos - CAP_MARGIN * sin - CAP_MARGIN;
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let reach: Vec<(f64, f64)> = self
            .polar
            .iter()
            .map(|&(length, along)| cap_reach(dot(centre, along), cos, sin, length))
            .collect();
        let lowest_best = reach.iter().map(|r| r.0).fold(f64::NEG_INFINITY, f64::max);
        let margin = self.margin;
        let mut kept: Vec<(f64, [f64; 3])> = Vec::new();
        let mut others = 0.0f64;
        for (&(_, upper), &p) in reach.iter().zip(&self.wrenches) {
            if upper + margin >= lowest_best - margin {
                kept.push((upper, p));
            } else {
                others = others.max(upper + margin);
            }
        }
        kept.sort_by(|x, y| y.0.total_cmp(&x.0));
        Cell {
            candidates: kept.into_iter().map(|(_, p)| p).collect(),
            others,
        }
    }

    /// The cell of direction `v` (any length, not zero, finite): its
    /// largest coordinate picks the face, the ratios of the other two to
    /// it the cell. `None` while the cell is not built and has been
    /// asked fewer than [`BUILD_AFTER`] times.
    #[inline(always)]
    fn cell(&self, v: [f64; 3]) -> Option<&Cell> {
        let magnitude = v.map(f64::abs);
        let k = if magnitude[0] >= magnitude[1] && magnitude[0] >= magnitude[2] {
            0
        } else if magnitude[1] >= magnitude[2] {
            1
        } else {
            2
        };
        let (k1, k2) = axes(k);
        let face = 2 * k + usize::from(v[k] < 0.0);
        // `(x / |v_k| + 1) SIDE / 2`, rounded a few ulps off (the caps'
        // margin); a tiny negative goes to 0 as `as` saturates.
        let half = 0.5 * SIDE as f64;
        let scale = half / magnitude[k];
        let index = |x: f64| ((x * scale + half) as usize).min(SIDE - 1);
        let cell = (face * SIDE + index(v[k1])) * SIDE + index(v[k2]);
        if let Some(built) = self.cells[cell].get() {
            return Some(built);
        }
        if self.asked[cell].0.fetch_add(1, Ordering::Relaxed) < BUILD_AFTER {
            return None;
        }
        Some(self.cells[cell].get_or_init(|| self.build(cell)))
    }

    /// The floor test of one row `r` of `W^-1` (`norm` its computed
    /// length, finite and not zero): `Some(true)` when some applied
    /// wrench `p` has `-(r . p)`, computed as the blocks compute it, above
    /// `bound`; `Some(false)` when none has; `None` when the cell cannot
    /// tell (or is not built yet).
    ///
    /// A candidate above `bound` is such a wrench. Every other wrench
    /// has `-(r . p) = |r| (u . p)` with `u = -r / |r|` in the cell's cap,
    /// so at most `|r| others` exactly, and as computed (three products
    /// and two sums) within `3.01 eps |r| |p|` of it; `norm` is within
    /// `3 eps` of `|r|`, so `norm * (others + 1e-12 max_norm)`, rounded,
    /// is above all of them (`others` is at most `max_norm` and a hair, the
    /// margin far above the few `eps` the rounding takes).
    #[inline(always)]
    pub(crate) fn row_exceeds(
        &self,
        r: &[f64; 3],
        norm: f64,
        max_norm: f64,
        bound: f64,
    ) -> Option<bool> {
        let cell = self.cell(r.map(|x| -x))?;
        for p in &cell.candidates {
            if -(r[0] * p[0] + r[1] * p[1] + r[2] * p[2]) > bound {
                return Some(true);
            }
        }
        (norm * (cell.others + 1e-12 * max_norm) <= bound).then_some(false)
    }
}

/// Relative margin, on the largest length of a functional of
/// [`Directions::largest_force`] times the largest `|p|`, for the
/// roundings of the functionals and of each wrench's force (some
/// `10 eps` of that product).
const FORCE_ROUNDING: f64 = 1e-12;

impl Directions {
    /// The largest contact force over the applied wrenches (each computed
    /// as [`lanes::force`], so as the blocks compute it), when the cells
    /// can tell it; `None` when they cannot (a cell not built, a margin
    /// too thin, a number not finite), and the blocks must.
    ///
    /// With `y = W^-1 p` and `mu` extended by `y_3 = 0`, `mu_3 = 1`, the
    /// force is `max_i (lambda0_i + s mu_i)` for `s = max_j y_j / mu_j`
    /// (`mu > 0`), that is the largest of `v_ij . p` over the twelve
    /// functionals `v_ij = (mu_i / mu_j) r_j - r_i` (`i != j`, `r_3 = 0`;
    /// `i = j` gives the 0 the force starts from). So the largest force
    /// is the largest reach of some `v_ij`: each functional's cell gives
    /// its candidates' reach `v_ij . p` (a dot product) and bounds every
    /// other wrench's by `|v_ij|` times the cell's `others`; a functional
    /// whose length times `max_norm` is short of the largest reach so far
    /// needs no cell. Only the candidates that reach within the rounding
    /// margin of the largest reach can hold the largest force: theirs are
    /// computed as the blocks compute them. Every other wrench's exact
    /// force is below the largest of the bounds (of the cells, of the
    /// functionals left out, the margin under the largest reach), its
    /// computed force within the margin of that; when all that is at
    /// most the largest computed force, the maximum over all wrenches is
    /// that force, the same bits (a maximum does not depend on the order
    /// of its terms).
    pub(crate) fn largest_force(&self, solve: &Solve, max_norm: f64) -> Option<f64> {
        let slack = FORCE_ROUNDING * row_scale(solve) * max_norm;
        if !slack.is_finite() {
            return None;
        }
        let whole = max_norm * (1.0 + FORCE_ROUNDING);
        let mut asked: [Option<(&Cell, [f64; 3])>; 12] = [None; 12];
        // The largest reach of a candidate, and a bound on every reach no
        // cell lists.
        let (mut top, mut rest) = (0.0f64, 0.0f64);
        let functionals = functionals(solve);
        // The longest first: its reach leaves most of the others out.
        let longest = (1..12).fold(0, |b, k| {
            if functionals[k].1 > functionals[b].1 {
                k
            } else {
                b
            }
        });
        let order = std::iter::once(longest).chain((0..12).filter(|&k| k != longest));
        for (k, slot) in order.zip(&mut asked) {
            let (v, length) = functionals[k];
            if length * whole + 3.0 * slack <= top {
                rest = rest.max(length * whole);
                continue;
            }
            if length.is_nan() || length <= 0.0 {
                return None;
            }
            let cell = self.cell(v)?;
            for &p in &cell.candidates {
                top = top.max(dot(v, p));
            }
            rest = rest.max(length * (cell.others + FORCE_ROUNDING * max_norm));
            *slot = Some((cell, v));
        }
        let near = top - 3.0 * slack;
        let mut best = 0.0f64;
        for &(cell, v) in asked.iter().flatten() {
            for &p in &cell.candidates {
                if dot(v, p) >= near {
                    best = fmax(best, lanes::force(solve, p));
                }
            }
        }
        (rest + slack <= best && top - slack <= best).then_some(best)
    }
}

/// The twelve functionals `v_ij` of [`Directions::largest_force`] with
/// their lengths.
fn functionals(solve: &Solve) -> [([f64; 3], f64); 12] {
    let row = |i: usize| if i < 3 { solve.rows[i] } else { [0.0; 3] };
    let mu = |i: usize| if i < 3 { solve.mu[i] } else { 1.0 };
    let mut out = [([0.0; 3], 0.0); 12];
    let pairs = (0..4).flat_map(|i| (0..4).filter(move |&j| j != i).map(move |j| (i, j)));
    for (slot, (i, j)) in out.iter_mut().zip(pairs) {
        let ratio = mu(i) / mu(j);
        let v = std::array::from_fn(|k| ratio * row(j)[k] - row(i)[k]);
        *slot = (v, dot(v, v).sqrt());
    }
    out
}

/// `max_i mu_i max_j |r_j| / mu_j + max_i |r_i|` (with `mu_3 = 1`): a
/// bound on every `|v_ij|` and on each term `y_i`, `s mu_i` of a force,
/// over `|p|`, the scale of their roundings.
fn row_scale(solve: &Solve) -> f64 {
    let norms = solve.rows.map(|r| dot(r, r).sqrt());
    let largest_mu = solve.mu.iter().copied().fold(1.0, f64::max);
    let per_mu = (0..3).map(|j| norms[j] / solve.mu[j]).fold(0.0, f64::max);
    largest_mu * per_mu + norms.into_iter().fold(0.0, f64::max)
}

/// For a cap of directions of cosine radius `cos` (sine `sin`, at most
/// a quarter turn) and a wrench of length `length` whose direction makes
/// cosine `t` with the cap's centre: a lower and an upper bound of
/// `u . p` over the directions `u` of the cap (the caller widens both by
/// its margin for their rounding). With `theta` the angle of `t`, the
/// extremes are `length cos(theta -+ rho)` (the upper `length` when
/// `theta <= rho`); beyond a quarter turn (`t < 0`), where `theta + rho`
/// may pass a half turn, they are taken as `-length` and `length sin`
/// (`t cos <= 0`), which saves a square root on half the sphere.
fn cap_reach(t: f64, cos: f64, sin: f64, length: f64) -> (f64, f64) {
    if t < 0.0 {
        return (-length, length * sin);
    }
    let t = t.min(1.0);
    let across = (1.0 - t * t).sqrt();
    let lower = length * (t * cos - across * sin);
    if t >= cos {
        return (lower, length);
    }
    (lower, length * (t * cos + across * sin))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every direction of a fine sample lands in a cell whose bound on
    /// the others holds for it, and whose candidates hold the farthest
    /// wrench along it; the cells keep few candidates on a sphere.
    #[test]
    fn cells_bound_every_direction_they_take() {
        let mut rng = crate::test_rng::Xorshift::new(0xd1ec_7105);
        let mut rnd = || rng.signed_unit();
        let sphere: Vec<[f64; 3]> = (0..256).map(|_| unit([rnd(), rnd(), rnd()])).collect();
        let scattered: Vec<[f64; 3]> = (0..40).map(|_| [rnd(), 2.0 * rnd(), 0.5 * rnd()]).collect();
        for wrenches in [&sphere, &scattered] {
            let cells = Directions::new(wrenches).unwrap();
            for _ in 0..20_000 {
                // Now and then on a face's edge or corner.
                let mut v = [rnd(), rnd(), rnd()];
                if rnd() > 0.8 {
                    v[1] = v[0].abs().copysign(v[1]);
                }
                if rnd() > 0.9 {
                    v[2] = v[0].abs().copysign(v[2]);
                }
                let u = unit(v);
                let cell = (0..=BUILD_AFTER).find_map(|_| cells.cell(v)).unwrap();
                let run = &cell.candidates;
                let best = wrenches.iter().map(|&p| dot(u, p)).fold(f64::MIN, f64::max);
                let best_candidate = run.iter().map(|&p| dot(u, p)).fold(f64::MIN, f64::max);
                assert_eq!(best.to_bits(), best_candidate.to_bits(), "{v:?}");
                for p in wrenches.iter().filter(|p| !run.contains(p)) {
                    assert!(dot(u, *p) <= cell.others, "{v:?} {p:?}");
                }
            }
        }
        // Some 25 on this random sphere, 15 on the metric's Fibonacci one.
        let cells = Directions::new(&sphere).unwrap();
        let most = (0..cells.cells.len())
            .map(|i| cells.build(i).candidates.len())
            .max()
            .unwrap();
        assert!(most <= 32, "{most}");
        assert!(Directions::new(&[]).is_none());
        assert!(Directions::new(&[[0.0, f64::NAN, 1.0]]).is_none());
    }

    /// The largest force through the cells is the blocks' one, bit for
    /// bit, whenever the cells tell it, on unit directions and scattered
    /// wrenches, over rows of many scales and `mu` of many spreads, and
    /// rows that nearly tie (two functionals of the same length); most
    /// scores are told.
    #[test]
    fn largest_force_through_the_cells_matches_the_blocks() {
        let mut rng = crate::test_rng::Xorshift::new(0x5c0e_ce11);
        let mut rnd = || rng.signed_unit();
        let sphere: Vec<[f64; 3]> = (0..256).map(|_| unit([rnd(), rnd(), rnd()])).collect();
        let scattered: Vec<[f64; 3]> = (0..77).map(|_| [rnd(), rnd(), 3.0 * rnd()]).collect();
        let (mut asked, mut told) = (0, 0);
        for wrenches in [&sphere, &scattered] {
            let cells = Directions::new(wrenches).unwrap();
            let blocks = lanes::blocks(wrenches);
            let max_norm = wrenches
                .iter()
                .map(|&p| dot(p, p).sqrt())
                .fold(0.0, f64::max);
            for round in 0..6_000 {
                let scale = 10f64.powf(3.0 * rnd());
                let mut rows: [[f64; 3]; 3] =
                    std::array::from_fn(|_| [scale * rnd(), scale * rnd(), scale * rnd()]);
                let spread = 10f64.powf(2.0 * rnd());
                let mu = [rnd().abs(), spread * rnd().abs(), rnd().abs()];
                if round % 3 == 0 {
                    // v_30 = r_0 / mu_0 and v_03 = -r_0 tie when mu_0 = 1,
                    // and r_1 a rounding off -r_0 ties more.
                    rows[1] = rows[0].map(|x| -x * (1.0 + 1e-15 * rnd()));
                }
                let solve = Solve { rows, mu };
                let full = lanes::largest_force(&solve, &blocks, f64::INFINITY, &mut 0);
                asked += 1;
                // Cells are built after a few questions: ask until built.
                let fresh = (0..=BUILD_AFTER).find_map(|_| cells.largest_force(&solve, max_norm));
                if let Some(got) = fresh {
                    assert_eq!(got.to_bits(), full.to_bits(), "{solve:?}");
                    told += 1;
                }
            }
        }
        assert!(told * 10 > asked * 8, "{told} of {asked}");
    }
}
