//! The max-force metrics' loops over the applied wrenches, laid out for
//! the vector unit: the wrenches in blocks of [`LANES`] (structure of
//! arrays), each lane one wrench going through the very operations, in
//! the very order, of the one-wrench formula, so each wrench's force is
//! the same bits whether the lanes run as SSE2 pairs or AVX quads.
//! Nothing here multiplies and adds in one rounding (no FMA), and a
//! maximum does not depend on the order its terms come in (see
//! [`fmax`]), so the scores are those of a plain loop bit for bit.

// A lane index reads several arrays in step: the loops stay index loops.
#![allow(clippy::needless_range_loop)]

/// Wrenches per block: two AVX registers (four SSE2 ones) per
/// coordinate, independent lanes to keep the divider busy.
pub(crate) const LANES: usize = 8;

/// [`LANES`] applied wrenches, coordinate by coordinate, and a ball
/// holding them all (see [`floor_exceeds_portable`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Block {
    x: [f64; LANES],
    y: [f64; LANES],
    z: [f64; LANES],
    /// The mean of the block's wrenches.
    centre: [f64; 3],
    /// The largest distance from `centre` to a wrench of the block, plus
    /// a margin of `1e-12` times a bound on every `|p|` of the block
    /// (`|centre|` plus that distance) for the roundings; infinite if a
    /// coordinate is not finite (then the block is never skipped).
    reach: f64,
}

/// Applied wrenches in blocks of wrenches close together (see
/// [`grouped`]); the last block is filled up with copies of the last
/// wrench (a maximum over a repeated term is the same).
pub(crate) fn blocks(wrenches: &[[f64; 3]]) -> Vec<Block> {
    let wrenches = grouped(wrenches);
    let Some(last) = wrenches.last() else {
        return Vec::new();
    };
    wrenches
        .chunks(LANES)
        .map(|chunk| {
            let at = |j: usize| chunk.get(j).unwrap_or(last);
            let centre: [f64; 3] = std::array::from_fn(|k| {
                chunk.iter().map(|p| p[k]).sum::<f64>() / chunk.len() as f64
            });
            let distance = chunk
                .iter()
                .map(|p| norm(std::array::from_fn(|k| p[k] - centre[k])))
                .fold(0.0, |a: f64, d| if d > a || d.is_nan() { d } else { a });
            let reach = distance + 1e-12 * (norm(centre) + distance);
            Block {
                x: std::array::from_fn(|j| at(j)[0]),
                y: std::array::from_fn(|j| at(j)[1]),
                z: std::array::from_fn(|j| at(j)[2]),
                centre,
                reach: if reach.is_finite() {
                    reach
                } else {
                    f64::INFINITY
                },
            }
        })
        .collect()
}

/// The euclidean length of `v`.
fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// `wrenches` reordered so that each run of [`LANES`] lies close
/// together (small block balls skip more in the floor): halved along the
/// coordinate of largest spread, again and again, the first half always
/// a whole number of blocks (so only the last block is short). The order
/// changes no maximum and no "exists"; it is fixed (a stable sort by
/// `total_cmp`), so every run sees the same blocks.
fn grouped(wrenches: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let mut out = wrenches.to_vec();
    split(&mut out);
    out
}

/// [`grouped`] of `part`, in place.
fn split(part: &mut [[f64; 3]]) {
    let n = part.len();
    if n <= LANES {
        return;
    }
    let spread = |k: usize| {
        let (low, high) = part
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
                (l.min(p[k]), h.max(p[k]))
            });
        high - low
    };
    let axis = (1..3).fold(0, |best, k| if spread(k) > spread(best) { k } else { best });
    part.sort_by(|a, b| a[axis].total_cmp(&b[axis]));
    let half = (n / 2).div_ceil(LANES) * LANES;
    let (first, second) = part.split_at_mut(half);
    split(first);
    split(second);
}

/// The larger of `a` and `b` as one `maxsd` (`maxpd` in lanes):
/// `f64::max`'s NaN rule costs several instructions, and here the
/// accumulator `a` is never NaN (a NaN `b` is ignored, as `f64::max`
/// would). Accumulators start at `+0.0` and only take values above them,
/// so a `-0.0` never gets in and the largest value is the same bits in
/// whatever order the terms come.
#[inline(always)]
pub(crate) fn fmax(a: f64, b: f64) -> f64 {
    if b > a {
        b
    } else {
        a
    }
}

/// The rows of `W^-1` (the inverse of the locator wrench matrix) and
/// `mu = (-W^-1 w4, 1)` for a fourth wrench, as the loops take them.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Solve {
    /// `rows[i][j]` is `W^-1`'s entry `(i, j)`.
    pub(crate) rows: [[f64; 3]; 3],
    /// The ray direction's first three entries (the fourth is 1).
    pub(crate) mu: [f64; 3],
}

/// `W^-1 p` for each lane's `p`, rows summed left to right as nalgebra's
/// matrix-vector product sums them: `(r0 x + r1 y) + r2 z`.
#[inline(always)]
fn solved(rows: &[[f64; 3]; 3], b: &Block) -> [[f64; LANES]; 3] {
    let mut out = [[0.0; LANES]; 3];
    for (i, row) in rows.iter().enumerate() {
        for j in 0..LANES {
            out[i][j] = row[0] * b.x[j] + row[1] * b.y[j] + row[2] * b.z[j];
        }
    }
    out
}

/// Each lane's largest contact force: the smallest non-negative point of
/// the ray `lambda0 + s mu` with `lambda0 = (-W^-1 p, 0)`, the one-wrench
/// formula's operations in its order.
#[inline(always)]
fn forces(solve: &Solve, b: &Block) -> [f64; LANES] {
    let y = solved(&solve.rows, b);
    let mu = [solve.mu[0], solve.mu[1], solve.mu[2], 1.0];
    let mut out = [0.0; LANES];
    for j in 0..LANES {
        out[j] = force_of_solved([y[0][j], y[1][j], y[2][j]], &mu);
    }
    out
}

/// One wrench's largest contact force, as its lane of [`forces`]
/// computes it (the same operations in the same order: the same bits):
/// for the few wrenches the cells of directions pick
/// ([`super::directions::Directions::largest_force`]).
#[inline(always)]
pub(crate) fn force(solve: &Solve, p: [f64; 3]) -> f64 {
    let r = &solve.rows;
    let y = std::array::from_fn(|i| r[i][0] * p[0] + r[i][1] * p[1] + r[i][2] * p[2]);
    force_of_solved(y, &[solve.mu[0], solve.mu[1], solve.mu[2], 1.0])
}

/// The force of one lane from its `y = W^-1 p` ([`solved`]) and `mu`
/// with its fourth entry 1: the smallest non-negative point of the ray
/// `lambda0 + s mu`, `lambda0 = (-y, 0)`.
#[inline(always)]
fn force_of_solved(y: [f64; 3], mu: &[f64; 4]) -> f64 {
    let l0 = [-y[0], -y[1], -y[2], 0.0];
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

/// The largest force over `blocks`, taken from block `*start` on
/// (wrapping around), stopping at the first block whose largest force
/// is above `bound` (then `*start` is left there and the largest so far
/// returned: above `bound`, at most the full maximum).
#[inline(always)]
fn largest_portable(solve: &Solve, blocks: &[Block], bound: f64, start: &mut usize) -> f64 {
    let first = if *start < blocks.len() { *start } else { 0 };
    let (tail, head) = blocks.split_at(first);
    let mut worst = [0.0f64; LANES];
    for (i, b) in head.iter().chain(tail).enumerate() {
        let f = forces(solve, b);
        for j in 0..LANES {
            worst[j] = fmax(worst[j], f[j]);
        }
        if worst.iter().any(|&w| w > bound) {
            *start = (first + i) % blocks.len();
            break;
        }
    }
    worst.into_iter().fold(0.0, fmax)
}

/// Whether some lane's locator force with the clamp's share at zero
/// (`lambda0_i = -(W^-1 p)_i`) is above `bound`, from block `*start` on;
/// `*start` is left at the block that told. `norms` are the lengths of
/// `rows`.
///
/// A block whose ball cannot pass `bound` is skipped without its lanes:
/// for `p` in the block, `|p - c| <= d` (`c` the centre, `d` the largest
/// distance), so `-(r . p) = -(r . c) - r . (p - c) <= -(r . c) + |r| d`
/// (Cauchy-Schwarz). The lanes compute `-(r . p)` within about
/// `3 eps |r| |p|` of its exact value and `|p| <= |c| + d`; the test's
/// own dot product, norm, product and sum are within a few `eps |r|
/// (|c| + d)` too, so the margin of `1e-12 |r| (|c| + d)` in `reach`
/// covers both: when the test's `-(r . c) + |r| reach` is at most
/// `bound` for every row, no lane's computed `-(r . p)` is above it, and
/// the block would not have told. A NaN or infinite test value is not
/// "at most", so such blocks go through their lanes; infinite `norms`
/// skip nothing.
#[inline(always)]
fn floor_exceeds_portable(
    rows: &[[f64; 3]; 3],
    norms: &[f64; 3],
    blocks: &[Block],
    bound: f64,
    start: &mut usize,
) -> bool {
    let first = if *start < blocks.len() { *start } else { 0 };
    let (tail, head) = blocks.split_at(first);
    for (i, b) in head.iter().chain(tail).enumerate() {
        if cannot_pass(rows, norms, b, bound) {
            continue;
        }
        let y = solved(rows, b);
        let mut above = false;
        for yi in &y {
            for &v in yi {
                above |= -v > bound;
            }
        }
        if above {
            *start = (first + i) % blocks.len();
            return true;
        }
    }
    false
}

/// Whether the ball of block `b` shows that no lane's `-(r . p)` is
/// above `bound` (see [`floor_exceeds_portable`]).
#[inline(always)]
fn cannot_pass(rows: &[[f64; 3]; 3], norms: &[f64; 3], b: &Block, bound: f64) -> bool {
    let c = &b.centre;
    let mut may = false;
    for (row, n) in rows.iter().zip(norms) {
        let reach = -(row[0] * c[0] + row[1] * c[1] + row[2] * c[2]) + n * b.reach;
        may |= reach > bound || !reach.is_finite();
    }
    !may
}

/// [`largest_portable`] compiled for AVX (four lanes a register; no FMA,
/// so the same roundings).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn largest_avx(solve: &Solve, blocks: &[Block], bound: f64, start: &mut usize) -> f64 {
    largest_portable(solve, blocks, bound, start)
}

/// [`floor_exceeds_portable`] compiled for AVX.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn floor_exceeds_avx(
    rows: &[[f64; 3]; 3],
    norms: &[f64; 3],
    blocks: &[Block],
    bound: f64,
    start: &mut usize,
) -> bool {
    floor_exceeds_portable(rows, norms, blocks, bound, start)
}

/// Whether this processor has AVX (detected once, then a load).
#[cfg(target_arch = "x86_64")]
fn has_avx() -> bool {
    std::arch::is_x86_feature_detected!("avx")
}

/// The largest contact force over the applied wrenches in `blocks`, with
/// the early stop above `bound` of [`largest_portable`].
pub(crate) fn largest_force(solve: &Solve, blocks: &[Block], bound: f64, start: &mut usize) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if has_avx() {
        // SAFETY: the processor has AVX, the one feature the function
        // is compiled for.
        return unsafe { largest_avx(solve, blocks, bound, start) };
    }
    largest_portable(solve, blocks, bound, start)
}

/// Whether some applied wrench in `blocks` needs a locator force above
/// `bound` with the clamp's share at zero.
pub(crate) fn floor_exceeds(
    rows: &[[f64; 3]; 3],
    norms: &[f64; 3],
    blocks: &[Block],
    bound: f64,
    start: &mut usize,
) -> bool {
    #[cfg(target_arch = "x86_64")]
    if has_avx() {
        // SAFETY: as in `largest_force`.
        return unsafe { floor_exceeds_avx(rows, norms, blocks, bound, start) };
    }
    floor_exceeds_portable(rows, norms, blocks, bound, start)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The portable loops and the dispatched ones (AVX where the
    /// processor has it) give the same bits and answers, from any start.
    #[test]
    fn portable_and_dispatched_loops_agree() {
        let mut rng = crate::test_rng::Xorshift::new(0x7a11_b10c);
        let mut rnd = || rng.signed_unit();
        let wrenches: Vec<[f64; 3]> = (0..61).map(|_| [rnd(), rnd(), rnd()]).collect();
        let blocks = blocks(&wrenches);
        assert_eq!(blocks.len(), 8);
        for _ in 0..300 {
            let solve = Solve {
                rows: std::array::from_fn(|_| [rnd(), rnd(), rnd()]),
                mu: [rnd().abs(), rnd().abs(), rnd().abs()],
            };
            let norms = solve.rows.map(norm);
            let full = largest_portable(&solve, &blocks, f64::INFINITY, &mut 0);
            for bound in [f64::INFINITY, full, full * 0.5, 0.0] {
                for first in [0, 3, 7, 9] {
                    let (mut a, mut b) = (first, first);
                    let portable = largest_portable(&solve, &blocks, bound, &mut a);
                    let dispatched = largest_force(&solve, &blocks, bound, &mut b);
                    assert_eq!(portable.to_bits(), dispatched.to_bits());
                    assert_eq!(a, b);
                    let (mut a, mut b) = (first, first);
                    assert_eq!(
                        floor_exceeds_portable(&solve.rows, &norms, &blocks, bound, &mut a),
                        floor_exceeds(&solve.rows, &norms, &blocks, bound, &mut b)
                    );
                    assert_eq!(a, b);
                }
            }
        }
    }

    /// One wrench's [`force`] is its lane's, bit for bit: the loop over
    /// a block of that wrench alone (padded with copies) gives it.
    #[test]
    fn one_wrench_force_is_its_lanes() {
        let mut rng = crate::test_rng::Xorshift::new(0x01e_f0ce);
        let mut rnd = || rng.signed_unit();
        for _ in 0..2_000 {
            let scale = 10f64.powf(3.0 * rnd());
            let solve = Solve {
                rows: std::array::from_fn(|_| [scale * rnd(), scale * rnd(), rnd()]),
                mu: [rnd().abs(), 0.01 * rnd().abs(), rnd().abs()],
            };
            let p = [rnd(), rnd(), 2.0 * rnd()];
            let lane = largest_portable(&solve, &blocks(&[p]), f64::INFINITY, &mut 0);
            assert_eq!(force(&solve, p).to_bits(), lane.to_bits());
        }
    }

    /// The floor with its block skipping against the floor through every
    /// lane (infinite norms skip nothing): the same answer and the same
    /// block left in `start`, on unit directions and on scattered wrenches,
    /// at bounds at the floor, a rounding either side of it, and around.
    #[test]
    fn skipping_blocks_never_changes_the_floor() {
        let mut rng = crate::test_rng::Xorshift::new(0x5c1b_b10c);
        let mut rnd = || rng.signed_unit();
        // Unit directions, as the metric's sphere (not taken from the
        // metric: imports flow one way).
        let sphere: Vec<[f64; 3]> = (0..256)
            .map(|_| {
                let p = [rnd(), rnd(), rnd()];
                let length = norm(p);
                p.map(|x| x / length)
            })
            .collect();
        let scattered: Vec<[f64; 3]> = (0..77).map(|_| [rnd(), rnd(), 3.0 * rnd()]).collect();
        let (mut skipped, mut looked, mut told) = (0, 0, 0);
        for wrenches in [&sphere, &scattered] {
            let blocks = blocks(wrenches);
            for _ in 0..400 {
                let scale = 10f64.powf(3.0 * rnd());
                let rows: [[f64; 3]; 3] =
                    std::array::from_fn(|_| [scale * rnd(), scale * rnd(), scale * rnd()]);
                let norms = rows.map(norm);
                let floor = blocks
                    .iter()
                    .flat_map(|b| solved(&rows, b).into_iter().flatten())
                    .fold(0.0, |a, v| fmax(a, -v));
                let up = f64::from_bits(floor.to_bits() + 1);
                let down = f64::from_bits(floor.to_bits() - 1);
                for bound in [
                    floor,
                    up,
                    down,
                    floor * 0.9,
                    floor * 0.99,
                    floor * 1.01,
                    0.0,
                ] {
                    for first in [0, 5, 31] {
                        let (mut a, mut b) = (first, first);
                        let unskipped = [f64::INFINITY; 3];
                        let want =
                            floor_exceeds_portable(&rows, &unskipped, &blocks, bound, &mut a);
                        let got = floor_exceeds(&rows, &norms, &blocks, bound, &mut b);
                        assert_eq!(got, want, "floor {floor}, bound {bound}");
                        assert_eq!(a, b);
                        assert_eq!(want, floor > bound);
                        told += usize::from(want);
                    }
                }
                let skip = |b: &&Block| cannot_pass(&rows, &norms, b, floor);
                skipped += blocks.iter().filter(skip).count();
                looked += blocks.len();
            }
        }
        // The test bites: many answers are yes, and many blocks are skipped.
        assert!(
            told > 1000 && 4 * skipped > looked,
            "{told} told, {skipped} of {looked}"
        );
    }
}
