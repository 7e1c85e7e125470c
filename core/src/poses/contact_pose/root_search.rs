//! The root search of trigonometric polynomials: subdivision of the circle
//! with Taylor bounds, proving every interval it discards root-free (why is
//! in [`roots`]).
//!
//! Kept apart from `trig` (the polynomial) so that the search loop, its
//! budget and its polishers read on their own; the interval tests are in
//! `classify` and the fifth-order proofs in `taylor5`.

use super::classify::{classify, Bounds, Class, Ends, Mid, LEAF, START, STEP};
use super::taylor5::{Below, Taylor5};
use super::trig::{bracketed_root, Angles, Trig, Within};

/// The sign-change root of `f` in `[lo, hi]`, if any (the caller knows `f`
/// is monotone there, so there is at most one).
fn monotone_root(poly: &Trig, lo: f64, hi: f64, out: &mut Angles) {
    sign_change_root(poly, (lo, poly.value(lo)), (hi, poly.value(hi)), out);
}

/// The root of `f` in `[a, b]`, where `f` is monotone and takes `fa`, `fb`
/// at the ends: an end where `f` is zero, else the bracketed sign change,
/// if any.
fn sign_change_root(poly: &Trig, (a, fa): (f64, f64), (b, fb): (f64, f64), out: &mut Angles) {
    if fa == 0.0 {
        out.push(a);
    } else if fb == 0.0 {
        out.push(b);
    } else if (fa < 0.0) != (fb < 0.0) {
        let g = |t: f64| {
            let (v, d, _) = poly.eval3(t);
            (v, d)
        };
        out.push(bracketed_root(g, a, b, fa));
    }
}

/// [`monotone_root`] on an interval whose ends' computed values are known
/// to have the signs of `ends`' estimates ([`Ends::computed_signs`]):
/// neither is zero, so the root is the bracketed sign change, found
/// without evaluating the ends (the polisher only reads the sign at `lo`).
fn estimated_root(poly: &Trig, ends: &Ends, lo: f64, hi: f64, out: &mut Angles) {
    if (ends.flo < 0.0) != (ends.fhi < 0.0) {
        let g = |t: f64| {
            let (v, d, _) = poly.eval3(t);
            (v, d)
        };
        out.push(bracketed_root(g, lo, hi, ends.flo));
    }
}

/// `f` is strictly convex or concave on `[lo, hi]`: at most two roots, one
/// on each side of the extremum, and when there is none the extremum itself
/// is a candidate if `|f| <= tol` there (a tangency or a near miss).
fn convex_roots(poly: &Trig, tol: f64, lo: f64, hi: f64, out: &mut Angles) {
    let (flo, dlo, _) = poly.eval3(lo);
    let (fhi, dhi, _) = poly.eval3(hi);
    if dlo != 0.0 && dhi != 0.0 && (dlo < 0.0) == (dhi < 0.0) {
        monotone_root(poly, lo, hi, out);
        return;
    }
    let tc = if dlo == 0.0 {
        lo
    } else if dhi == 0.0 {
        hi
    } else {
        let g = |t: f64| {
            let (_, d, dd) = poly.eval3(t);
            (d, dd)
        };
        bracketed_root(g, lo, hi, dlo)
    };
    let fc = poly.value(tc);
    let before = out.n;
    sign_change_root(poly, (lo, flo), (tc, fc), out);
    sign_change_root(poly, (tc, fc), (hi, fhi), out);
    if out.n == before && fc.abs() <= tol {
        out.push(tc);
    }
}

/// A run of adjacent leaf intervals and its point of smallest `|f|`.
struct Run {
    end: f64,
    best: (f64, f64),
}

impl Run {
    fn add(run: &mut Option<Run>, lo: f64, hi: f64, poly: &Trig, out: &mut Angles) {
        let m = 0.5 * (lo + hi);
        let v = poly.value(m).abs();
        match run {
            Some(r) if lo <= r.end + 1e-12 => {
                r.end = hi;
                if v < r.best.1 {
                    r.best = (m, v);
                }
            }
            _ => {
                Run::flush(run, out);
                *run = Some(Run {
                    end: hi,
                    best: (m, v),
                });
            }
        }
    }

    fn flush(run: &mut Option<Run>, out: &mut Angles) {
        if let Some(r) = run.take() {
            out.push(r.best.0);
        }
    }
}

/// Every root of `f` in `[0, 2 pi)` (in the start intervals `within`
/// allows), plus every local extremum where
/// `|f| <= tol` without a sign change (tangencies and near misses), pushed
/// onto `out`.
///
/// Why nothing is missed: an interval is dropped only when the third-order
/// Taylor bound (with `|f'''| <= sum j^3 (|a_j| + |b_j|)`) proves `|f| > tol`
/// on all of it; a monotone interval has at most one root, found when the
/// ends differ in sign; a convex or concave one has at most two, one on each
/// side of its single extremum; what is left after splitting down to
/// `LEAF`, or what is zero to within rounding throughout, is reported by
/// the point of smallest `|f|` of each connected run. `noise` bounds the error of the coefficients (this
/// adds the error of evaluating them); `tol` widens the band of values
/// counted as zero beyond it, to catch near misses. The work is
/// bounded (`out.overflow` is set if the bound is reached, which takes a
/// polynomial that is zero to within `tol` almost everywhere).
///
/// Near a cluster of roots (a near-multiple root, or a stretch where `f`
/// stays within `tol` of zero) the third-order bound splits down to the
/// leaves; fifth-order bounds ([`Taylor5`]) decide most of those intervals
/// without classifying them, and only where they prove [`classify`]'s
/// answer, so the angles reported are the same to the bit.
pub(super) fn roots(poly: &Trig, tol: f64, noise: f64, within: &Within, out: &mut Angles) {
    let m3 = poly.bound(3);
    if m3 == 0.0 {
        // A constant: no isolated root (zero is a continuum, caught earlier).
        return;
    }
    // Evaluation adds a few ulps of the coefficients' sum: with cos t and
    // sin t within 2 eps (libm's, or `cos_sin_near`'s in `classify`), the
    // recurrence keeps cos jt and sin jt within 3.5 j eps, so f, f' and f''
    // come within about 25 eps of the sums of their terms' magnitudes, well
    // inside the 64 eps allowed below. A coefficient error `noise` moves f'
    // by up to sum 2j noise and f'' by sum 2j^2 noise.
    let b = Bounds::new(poly, m3, tol, noise);
    let saved = *out;
    if search(poly, &b, within, out, true).is_none() {
        *out = saved;
        search(poly, &b, within, out, false);
    }
}

/// Intervals examined per call before the search gives up on a polynomial
/// that is zero to within `tol` almost everywhere.
const BUDGET: usize = 20_000;

/// Intervals a call classifies before [`search`] proves below every
/// `Split` node (with [`Taylor5`]). Before, it proves only below nodes
/// whose second-order Taylor estimate at the midpoint misses zero
/// ([`worth_proving`]): those are mostly proved silent, while a proof
/// below a node that holds a root fails and costs about as much as the
/// classifications it could save; in the long calls of a root cluster,
/// proofs pay everywhere. Callgrind, deck / motor mount sheets: proving
/// below every node after 50 intervals (before) 4,493 / 108.9 M
/// instructions; predicted nodes from the start and every node after 50,
/// 300 or 1,000 intervals, or never: 4,475 / 109.0, 4,475 / 108.9,
/// 4,468 / 108.9, 4,469 / 108.9 M.
const PROVE_AFTER: usize = 1_000;

/// Whether to prove what lies below a node `classify` found `Split`
/// (`mid` its midpoint's values, `width` its width), `classified`
/// intervals into a call that proves after `prove_after` (never when it
/// is `usize::MAX`: the plain search).
fn worth_proving(mid: &Mid, width: f64, classified: usize, prove_after: usize) -> bool {
    if prove_after == usize::MAX {
        return false;
    }
    let h = 0.5 * width;
    let [f0, f1, f2] = mid.f.map(f64::abs);
    classified > prove_after || f0 > h * f1 + 0.5 * h * h * f2
}

/// The subdivision of [`roots`]; the number of intervals classified.
///
/// With `prove`, what the fifth-order bounds of [`Taylor5`] decide below
/// a `Split` node is not classified (below the nodes [`worth_proving`]
/// picks): see [`search_from`].
fn search(
    poly: &Trig,
    b: &Bounds,
    within: &Within,
    out: &mut Angles,
    prove: bool,
) -> Option<usize> {
    let prove_after = if prove { PROVE_AFTER } else { usize::MAX };
    search_from(poly, b, within, out, prove_after)
}

/// [`search`], proving below the nodes [`worth_proving`] picks (all once
/// more than `prove_after` intervals have been classified; none when it
/// is `usize::MAX`): a subtree proved silent is dropped, and nodes proved `Split`
/// are split unexamined (still counted against the budget). Each proof is
/// about its own subtree only, so whenever proving starts the output is
/// the plain search's, except that a dropped subtree's intervals no longer
/// count against the budget: `None` when they might have exhausted it,
/// which would have changed the answer (the caller then searches again
/// without proofs).
fn search_from(
    poly: &Trig,
    b: &Bounds,
    within: &Within,
    out: &mut Angles,
    prove_after: usize,
) -> Option<usize> {
    let mut budget = BUDGET;
    let (mut reserve, mut classified) = (0usize, 0usize);
    let mut run = None;
    let mut stack = [(0.0, 0.0, 0u32); 48];
    for i in 0..START {
        stack[0] = (i as f64 * STEP, (i + 1) as f64 * STEP, 0);
        if !within(stack[0].0, stack[0].1) {
            continue;
        }
        let mut n = 1;
        while n > 0 {
            n -= 1;
            let (lo, hi, known) = stack[n];
            budget = budget.saturating_sub(1);
            let class = if known > 0 {
                Class::Split(None)
            } else {
                classified += 1;
                classify(poly, b, i, lo, hi)
            };
            match class {
                Class::Empty => {}
                Class::Monotone(Some(ends)) if (ends.flo < 0.0) == (ends.fhi < 0.0) => {}
                Class::Monotone(Some(ends)) if ends.computed_signs => {
                    estimated_root(poly, &ends, lo, hi, out);
                }
                Class::Monotone(_) => monotone_root(poly, lo, hi, out),
                Class::Convex => convex_roots(poly, b.tol, lo, hi, out),
                Class::Split(mid) if hi - lo > LEAF && n + 2 <= stack.len() && budget > 0 => {
                    let next = if known > 0 {
                        known - 1
                    } else if let Some(mid) =
                        mid.filter(|mid| worth_proving(mid, hi - lo, classified, prove_after))
                    {
                        match Taylor5::new(poly, b, &mid, hi - lo).below(b, hi - lo) {
                            Below::Silent(nodes) => {
                                reserve += nodes;
                                if BUDGET - budget + reserve >= BUDGET {
                                    return None;
                                }
                                continue;
                            }
                            Below::Split(levels) => levels,
                        }
                    } else {
                        0
                    };
                    // Halves with no wanted angle are dropped unexamined:
                    // the halves kept are split exactly as before.
                    let m = 0.5 * (lo + hi);
                    if within(m, hi) {
                        stack[n] = (m, hi, next);
                        n += 1;
                    }
                    if within(lo, m) {
                        stack[n] = (lo, m, next);
                        n += 1;
                    }
                }
                Class::Split(_) | Class::Flat => {
                    out.overflow |= budget == 0;
                    Run::add(&mut run, lo, hi, poly, out);
                }
            }
        }
    }
    Run::flush(&mut run, out);
    // The plain search examines at most `reserve` more intervals.
    (reserve == 0 || BUDGET - budget + reserve < BUDGET).then_some(classified)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::poses::contact_pose::trig::{circ_dist, sampled, DEG};
    use std::f64::consts::TAU;

    fn found(poly: &Trig, tol: f64) -> Vec<f64> {
        let mut out = Angles::new();
        roots(poly, tol, 0.0, &|_, _| true, &mut out);
        assert!(!out.overflow);
        out.as_slice().to_vec()
    }

    #[test]
    fn simple_roots_to_machine_precision() {
        // cos(4t): eight equispaced roots, the symmetric case that stalls
        // unshifted QR on its companion matrix.
        let mut f = Trig::default();
        f.a[4] = 1.0;
        let r = found(&f, 0.0);
        assert_eq!(r.len(), 8, "{r:?}");
        for (k, t) in r.iter().enumerate() {
            let want = (std::f64::consts::PI / 8.0) * (2 * k + 1) as f64;
            assert!((t - want).abs() < 1e-14, "{t} vs {want}");
        }
    }

    #[test]
    fn double_root_and_near_miss_are_one_candidate() {
        // 1 - cos(t - 1) + delta: double root at t = 1 when delta = 0.
        for delta in [0.0, 1e-16, 1e-13, -1e-16] {
            let mut f = Trig::default();
            f.a[0] = 1.0 + delta;
            f.a[1] = -(1.0f64).cos();
            f.b[1] = -(1.0f64).sin();
            let r = found(&f, 1e-12);
            assert!(!r.is_empty() && r.len() <= 2, "{delta}: {r:?}");
            for t in r {
                assert!((t - 1.0).abs() < 2e-6, "{delta}: {t}");
            }
        }
        // Clearly positive minimum: nothing.
        let mut f = Trig::default();
        f.a[0] = 1.0 + 1e-6;
        f.a[1] = -1.0;
        assert!(found(&f, 1e-12).is_empty());
    }

    #[test]
    fn random_polynomials_agree_with_dense_sign_changes() {
        let mut rng = crate::test_rng::Xorshift::new(0x2545_f491_4f6c_dd1d);
        let mut rnd = || rng.signed_unit();
        for _ in 0..300 {
            let mut f = Trig::default();
            for j in 0..=DEG {
                f.a[j] = rnd();
                if j > 0 {
                    f.b[j] = rnd();
                }
            }
            let r = found(&f, 1e-13);
            let n = 100_000;
            let mut changes = 0;
            let mut prev = f.value(0.0);
            for m in 1..=n {
                let t = TAU * m as f64 / n as f64;
                let v = f.value(t);
                if (v < 0.0) != (prev < 0.0) {
                    changes += 1;
                    assert!(
                        r.iter().any(|&u| circ_dist(u, t) <= TAU / n as f64),
                        "missed a root near {t}: {r:?}"
                    );
                }
                prev = v;
            }
            assert!(r.len() >= changes);
            for &t in &r {
                assert!(f.value(t).abs() < 1e-12, "{t}");
            }
        }
    }

    /// `roots` and the plain search (the subdivision before the
    /// fifth-order proofs, kept as the oracle) on the same input: the same
    /// angles to the bit and the same overflow flag. Returns how many
    /// intervals each classified.
    fn same_as_plain(poly: &Trig, tol: f64, noise: f64, within: &Within) -> (usize, usize) {
        let mut got = Angles::new();
        got.push(1.0);
        let mut want = got;
        roots(poly, tol, noise, within, &mut got);
        let b = Bounds::new(poly, poly.bound(3), tol, noise);
        let plain = search(poly, &b, within, &mut want, false).expect("plain search is complete");
        let bits = |a: &Angles| a.as_slice().iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(
            bits(&got),
            bits(&want),
            "{poly:?} tol {tol:e} noise {noise:e}"
        );
        assert_eq!(got.overflow, want.overflow, "{poly:?}");
        let mut fresh = Angles::new();
        let proved = search(poly, &b, within, &mut fresh, true).unwrap_or(plain);
        // Proving from the first interval on (what `roots` did before
        // waiting for `PROVE_AFTER`), which exercises the proofs on short
        // calls too.
        let mut early = Angles::new();
        early.push(1.0);
        if search_from(poly, &b, within, &mut early, 0).is_some() {
            assert_eq!(bits(&early), bits(&want), "{poly:?} proving early");
            assert_eq!(early.overflow, want.overflow, "{poly:?}");
        }
        (proved, plain)
    }

    fn from_bits(bits: [u64; 12]) -> (Trig, f64, f64) {
        let v = bits.map(f64::from_bits);
        let poly = Trig {
            a: [v[0], v[1], v[2], v[3], v[4]],
            b: [v[5], v[6], v[7], v[8], v[9]],
        };
        (poly, v[10], v[11])
    }

    #[test]
    fn recorded_clusters_are_found_as_before_with_fewer_intervals() {
        // Eliminants of the deck panel of the real-files set, with the
        // tolerances the pose solver passed: a near-sixfold root at 0
        // (F ~ K (1 - cos)^3), a long stretch within `tol` of zero, one
        // that exhausts the budget, and a cluster elsewhere.
        let recorded: [[u64; 12]; 4] = [
            [
                0x4136860f557122c0,
                0xc140e48980abac12,
                0x412b0738cea0594c,
                0xc10204c5db4fba0d,
                0xbdf9840000000000,
                0x0,
                0x3e081eac00000000,
                0xbe049ce000000000,
                0x3de1ef2000000000,
                0xbdaea40000000000,
                0x3f1a754f18409b49,
                0x3e796609d666fd9c,
            ],
            [
                0x418a3253e32ba9b9,
                0x418a47f880b53b60,
                0xc14a7d4ee5401b30,
                0xc150f7af0c541749,
                0xbe30000000000000,
                0x0,
                0x418d3648b4d37924,
                0x417f42569d89d8b7,
                0x4148978d9462fd3a,
                0x3e4c000000000000,
                0x3f72498fcd6fcb8f,
                0x3ee4d3940b262788,
            ],
            [
                0x4163c39a002e8a11,
                0xc1427c838630617d,
                0xc15691c571914250,
                0x411ca203cbd7cac9,
                0xbe111a0000000000,
                0x0,
                0x416d490dbf484497,
                0xc13d38baa0a01275,
                0xc12c36e179830cad,
                0xbe0b400000000000,
                0x3f4608b80f9edeaf,
                0x3eb291cb17b1e6ac,
            ],
            [
                0x41414c9d6e40978a,
                0xc149d5ac190cdfbd,
                0x413464cfa59417f6,
                0xc10a95927fdc3c7b,
                0xbdf7800000000000,
                0x0,
                0xc114e125d6388fb4,
                0x4110a7034cfbcaf2,
                0xc0f0912bafa94049,
                0xbdd6fc0000000000,
                0x3f21a2d39094e842,
                0x3e83667efdb68b01,
            ],
        ];
        let mut saved = 0;
        for bits in recorded {
            let (poly, tol, noise) = from_bits(bits);
            let (proved, plain) = same_as_plain(&poly, tol, noise, &|_, _| true);
            assert!(proved <= plain);
            saved += plain - proved;
            // Part of the circle only, as the setup sweep asks.
            same_as_plain(&poly, tol, noise, &|lo, hi| hi >= 1.0 && lo <= 4.0);
            same_as_plain(&poly, tol, noise, &|lo, _| lo <= 0.2 || lo >= 6.1);
        }
        assert!(saved > 10_000, "{saved}");
    }

    /// `K (1 - cos(t - t0))^power (c + cos(t - t1))` plus a small random
    /// remainder: a near-multiple root at `t0`.
    fn cluster(
        k: f64,
        power: i32,
        (t0, t1, c): (f64, f64, f64),
        remainder: [f64; 9],
        size: f64,
    ) -> Trig {
        let g = |t: f64| {
            let base = k * (1.0 - (t - t0).cos()).powi(power);
            let r = remainder[0]
                + (1..=DEG)
                    .map(|j| {
                        let jt = j as f64 * t;
                        remainder[2 * j - 1] * jt.cos() + remainder[2 * j] * jt.sin()
                    })
                    .sum::<f64>();
            if power <= 3 {
                base * (c + (t - t1).cos()) + size * k * r
            } else {
                base + size * k * r
            }
        };
        Trig::from_samples(&sampled(g))
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(300))]

        #[test]
        fn proved_search_is_the_plain_search_on_clusters(
            k in 1e-3f64..1e8,
            power in 1i32..=4,
            shape in (0.0f64..TAU, 0.0f64..TAU, 1.5f64..3.0),
            at_zero in proptest::bool::ANY,
            remainder in proptest::array::uniform9(-1.0f64..1.0),
            size_exp in -18.0f64..-8.0,
            tol_exp in -14.0f64..-9.0,
            noise_exp in -17.0f64..-12.0,
        ) {
            let shape = if at_zero { (0.0, shape.1, shape.2) } else { shape };
            let poly = cluster(k, power, shape, remainder, 10f64.powf(size_exp));
            let (tol, noise) = (k * 10f64.powf(tol_exp), k * 10f64.powf(noise_exp));
            same_as_plain(&poly, tol, noise, &|_, _| true);
            let (lo, hi) = (shape.0 - 0.3, shape.0 + 0.05);
            same_as_plain(&poly, tol, noise, &|a, b| b >= lo && a <= hi);
        }

        #[test]
        fn proved_search_is_the_plain_search_on_random_polynomials(
            a in proptest::array::uniform5(-1.0f64..1.0),
            b in proptest::array::uniform5(-1.0f64..1.0),
            tol_exp in -14.0f64..-2.0,
        ) {
            let poly = Trig { a, b: [0.0, b[1], b[2], b[3], b[4]] };
            same_as_plain(&poly, 10f64.powf(tol_exp), 1e-15, &|_, _| true);
        }
    }
}
