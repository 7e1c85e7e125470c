//! The clamp's four push directions read off coordinates: `rot90(k, (1, 0))`
//! is a unit axis vector, so a dot product with it is one coordinate of the
//! other vector, up to sign. The clamp search's per-(segment, rotation)
//! tests take it that way instead of multiplying by a zero and a one that
//! a rotation index only known at run time hides from the compiler.

use crate::geometry::{v2, V2};

/// `rot90(k, (1, 0)) . v` (push direction `d_k`); `along(k + 1, v)` is
/// `rot90(k, (0, 1)) . v` (axis line normal `e_k`). Equal to the dot
/// product but for the sign of a zero (the product with the zero
/// coordinate only adds a zero, and the sign of `1 * x` is `x`'s): callers
/// compare the value, or add it to a non-zero number, where the two agree.
/// Read off an array, not a `match`: the search's loops over rotations
/// then load a value where a jump table branched (and hoist the array
/// when `v` does not change within them).
#[inline(always)]
pub(super) fn along(k: u8, v: V2) -> f64 {
    [v.x, v.y, -v.x, -v.y][usize::from(k & 3)]
}

/// `rot90(k, (1, 0))` and `rot90(k, (0, 1))` for each `k`, zeros' signs
/// included (`rot90` negates a zero coordinate): the same vectors bit for
/// bit, so products with them round the same.
const PUSH: [[f64; 2]; 4] = [[1.0, 0.0], [-0.0, 1.0], [-1.0, -0.0], [0.0, -1.0]];
const ACROSS: [[f64; 2]; 4] = [[0.0, 1.0], [-1.0, 0.0], [-0.0, -1.0], [1.0, -0.0]];

/// The push direction `d_k = rot90(k, (1, 0))`, read off a table.
#[inline(always)]
pub(super) fn push_direction(k: u8) -> V2 {
    let [x, y] = PUSH[usize::from(k & 3)];
    v2(x, y)
}

/// The axis lines' normal `e_k = rot90(k, (0, 1))`, read off a table.
#[inline(always)]
pub(super) fn axis_normal(k: u8) -> V2 {
    let [x, y] = ACROSS[usize::from(k & 3)];
    v2(x, y)
}

#[cfg(test)]
mod tests {
    use super::{along, axis_normal, push_direction};
    use crate::geometry::{rot90, v2};
    use crate::test_rng::Xorshift;

    /// Equal to the dot products with the rotated unit vectors, for every
    /// rotation (and its wrap past 3), zeros and infinities included up to
    /// the sign of a zero.
    #[test]
    fn reads_the_dot_product_with_each_axis() {
        let mut rng = Xorshift::new(0x9e37_79b9_7f4a_7c15);
        let mut vs = vec![v2(0.0, -0.0), v2(-0.0, 3.0), v2(1e300, -1e-300)];
        for _ in 0..1000 {
            vs.push(v2(rng.signed_unit() * 1e3, rng.signed_unit() * 1e-3));
        }
        for v in vs {
            for k in 0..8u8 {
                assert_eq!(along(k, v), rot90(k, v2(1.0, 0.0)).dot(&v), "{k} {v}");
                assert_eq!(along(k + 1, v), rot90(k, v2(0.0, 1.0)).dot(&v), "{k} {v}");
            }
        }
    }

    /// The tables are `rot90` of the unit vectors bit for bit, zeros'
    /// signs included, for every rotation and its wrap past 3.
    #[test]
    fn tables_are_the_rotated_unit_vectors() {
        for k in 0..8u8 {
            for (got, want) in [
                (push_direction(k), rot90(k, v2(1.0, 0.0))),
                (axis_normal(k), rot90(k, v2(0.0, 1.0))),
            ] {
                assert_eq!(got.x.to_bits(), want.x.to_bits(), "{k}");
                assert_eq!(got.y.to_bits(), want.y.to_bits(), "{k}");
            }
        }
    }
}
