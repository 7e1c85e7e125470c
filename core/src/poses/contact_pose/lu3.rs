//! Newton's step of the pose polisher: a 3x3 linear solve by LU with
//! partial pivoting, written out for three unknowns.
//!
//! The polisher took nalgebra's general `LU` (`j.lu().solve(&b)`), whose
//! loops over views, strides and permutation sequences cost several times
//! the arithmetic at this size (about 4% of an arc part's enumeration).
//! This is the same algorithm, operation for operation (pivot: the first
//! entry of largest magnitude; a zero pivot column is skipped; multipliers
//! scaled by the pivot's reciprocal; updates `y = -u * l + y`; unit lower
//! then upper triangular substitution, `None` on a zero diagonal), so that
//! every iterate, and so every pose, is the same to the bit: the tests
//! compare it with nalgebra's on random, tied, singular and non-finite
//! matrices.

use nalgebra::{Matrix3, Vector3};

/// `x` with `j x = b`, or `None` when the factorisation has a zero pivot
/// (a singular `j`), exactly as `j.lu().solve(&b)` computes it.
#[inline]
#[allow(clippy::needless_range_loop, clippy::assign_op_pattern)] // nalgebra's loops and operand order, written as they run
pub(super) fn solve(j: &Matrix3<f64>, b: &Vector3<f64>) -> Option<Vector3<f64>> {
    let mut m = [
        [j[(0, 0)], j[(0, 1)], j[(0, 2)]],
        [j[(1, 0)], j[(1, 1)], j[(1, 2)]],
        [j[(2, 0)], j[(2, 1)], j[(2, 2)]],
    ];
    let mut x = [b[0], b[1], b[2]];
    for i in 0..3 {
        let mut piv = i;
        let mut largest = m[i][i].abs();
        for r in i + 1..3 {
            let v = m[r][i].abs();
            if v > largest {
                largest = v;
                piv = r;
            }
        }
        let diag = m[piv][i];
        if diag == 0.0 {
            continue;
        }
        // nalgebra swaps whole rows and applies the recorded swaps to the
        // right-hand side, in order, before substituting: the same swaps
        // in the same order.
        if piv != i {
            m.swap(i, piv);
            x.swap(i, piv);
        }
        let inv = 1.0 / diag;
        for row in m.iter_mut().skip(i + 1) {
            row[i] *= inv;
        }
        for k in i + 1..3 {
            let u = m[i][k];
            for r in i + 1..3 {
                m[r][k] = -u * m[r][i] + m[r][k];
            }
        }
    }
    // Unit lower triangle (nalgebra divides by the unit diagonal, exact).
    for i in 0..2 {
        let coeff = x[i];
        for r in i + 1..3 {
            x[r] = -coeff * m[r][i] + x[r];
        }
    }
    for i in (0..3).rev() {
        let diag = m[i][i];
        if diag == 0.0 {
            return None;
        }
        let coeff = x[i] / diag;
        x[i] = coeff;
        for r in 0..i {
            x[r] = -coeff * m[r][i] + x[r];
        }
    }
    Some(Vector3::new(x[0], x[1], x[2]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bits of each component, every NaN as one: which NaN an
    /// operation on NaNs returns (its sign, its payload) IEEE leaves open
    /// and the compiler may commute, and the polisher drops a step with a
    /// NaN whatever its bits.
    fn bits(v: Option<Vector3<f64>>) -> Option<[u64; 3]> {
        let one = |x: f64| {
            if x.is_nan() {
                f64::NAN.to_bits()
            } else {
                x.to_bits()
            }
        };
        v.map(|v| [one(v[0]), one(v[1]), one(v[2])])
    }

    fn same_as_nalgebra(j: Matrix3<f64>, b: Vector3<f64>) {
        assert_eq!(bits(solve(&j, &b)), bits(j.lu().solve(&b)), "{j:?} {b:?}");
    }

    /// Entries that make ties, zero pivots and non-finite values likely.
    fn entry(pick: u8, value: f64) -> f64 {
        match pick {
            0 => 0.0,
            1 => -0.0,
            2 => 1.0,
            3 => -1.0,
            4 => value * 1e-300,
            5 => f64::INFINITY,
            6 => f64::NAN,
            _ => value,
        }
    }

    #[test]
    fn singular_and_permuted_matrices() {
        let cases = [
            Matrix3::zeros(),
            Matrix3::new(1.0, 2.0, 3.0, 2.0, 4.0, 6.0, 0.0, 1.0, 5.0),
            Matrix3::new(0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0),
            Matrix3::new(0.0, 2.0, 1.0, 0.0, 3.0, 1.0, 0.0, 1.0, 4.0),
            Matrix3::new(1.0, 1.0, 1.0, -1.0, 1.0, 1.0, 1.0, -1.0, 1.0),
        ];
        for j in cases {
            same_as_nalgebra(j, Vector3::new(0.3, -1.7, 2.9));
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig {
            cases: 4000,
            failure_persistence: None,
            ..Default::default()
        })]

        #[test]
        fn same_bits_as_nalgebra_lu(
            values in proptest::array::uniform9(-10.0f64..10.0),
            picks in proptest::array::uniform9(0u8..24),
            rhs in proptest::array::uniform3(-10.0f64..10.0),
            rhs_picks in proptest::array::uniform3(0u8..16),
        ) {
            let j = Matrix3::from_fn(|r, c| entry(picks[3 * r + c], values[3 * r + c]));
            let b = Vector3::new(
                entry(rhs_picks[0], rhs[0]),
                entry(rhs_picks[1], rhs[1]),
                entry(rhs_picks[2], rhs[2]),
            );
            same_as_nalgebra(j, b);
        }
    }
}
