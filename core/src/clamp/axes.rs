//! The clamp's four push directions read off coordinates: `rot90(k, (1, 0))`
//! is a unit axis vector, so a dot product with it is one coordinate of the
//! other vector, up to sign. The clamp search's per-(segment, rotation)
//! tests take it that way instead of multiplying by a zero and a one that
//! a rotation index only known at run time hides from the compiler.

use crate::geometry::V2;

/// `rot90(k, (1, 0)) . v` (push direction `d_k`); `along(k + 1, v)` is
/// `rot90(k, (0, 1)) . v` (axis line normal `e_k`). Equal to the dot
/// product but for the sign of a zero (the product with the zero
/// coordinate only adds a zero, and the sign of `1 * x` is `x`'s): callers
/// compare the value, or add it to a non-zero number, where the two agree.
#[inline(always)]
pub(super) fn along(k: u8, v: V2) -> f64 {
    match k & 3 {
        0 => v.x,
        1 => v.y,
        2 => -v.x,
        _ => -v.y,
    }
}

#[cfg(test)]
mod tests {
    use super::along;
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
}
