//! Integer rounding of floats without libm: on the baseline x86-64 target
//! (no SSE4.1) `f64::ceil` and `f64::floor` are calls, and the sweeps'
//! row scans and the clamp's line loops round once per region, row or
//! setup. Each function gives the same value as the libm one for every
//! input, NaN, infinities and out-of-range values included.

/// `x.ceil() as i64`: the cast saturates and maps NaN to 0 either way.
#[inline(always)]
pub(crate) fn ceil_i64(x: f64) -> i64 {
    let t = x as i64;
    if (t as f64) < x {
        t.saturating_add(1)
    } else {
        t
    }
}

/// `x.floor() as i64`, see [`ceil_i64`].
#[inline(always)]
pub(crate) fn floor_i64(x: f64) -> i64 {
    let t = x as i64;
    if (t as f64) > x {
        t.saturating_sub(1)
    } else {
        t
    }
}

/// `x.ceil()` by [`ceil_i64`], the same value for every `x` (up to the
/// sign of a zero): from `2^52` on every `f64` is an integer.
#[inline(always)]
pub(crate) fn ceil(x: f64) -> f64 {
    if x.abs() < 4_503_599_627_370_496.0 {
        ceil_i64(x) as f64
    } else {
        x
    }
}

#[cfg(test)]
mod tests {
    use super::{ceil, ceil_i64, floor_i64};

    /// Against the libm ones at the places casts and rounding differ:
    /// halves, integers, signed zeros, the edges of exact integers and of
    /// `i64`, infinities and NaN.
    #[test]
    fn rounding_without_libm_matches_std() {
        let mut xs = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            2.5e-300,
            -2.5e-300,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MAX,
            f64::MIN,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            i64::MAX as f64,
            i64::MIN as f64,
            2f64.powi(63) * 2.0,
            2f64.powi(52) - 0.5,
            -(2f64.powi(52) - 0.5),
            2f64.powi(53) + 2.0,
            9.3e18,
            -9.3e18,
        ];
        let mut rng = crate::test_rng::Xorshift::new(0x51_7cc1_b727_220a);
        for i in 0..20_000 {
            let x = rng.signed_unit() * 10f64.powi(i % 22 - 3);
            xs.extend([x, x.round(), x.round() + 0.5, x.round() - 0.5]);
        }
        for x in xs {
            assert_eq!(ceil_i64(x), x.ceil() as i64, "ceil {x:e}");
            assert_eq!(floor_i64(x), x.floor() as i64, "floor {x:e}");
            let (ours, std) = (ceil(x), x.ceil());
            assert!(ours == std || (ours.is_nan() && std.is_nan()), "{x:e}");
        }
    }
}
