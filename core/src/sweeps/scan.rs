//! The lattice points of a region covered by grown quadrilaterals, row
//! by row and each once: what every kind of sweep hands the setup search.

use super::pieces::Quad;
use crate::geometry::V2;

/// A horizontal run of the plate, `y` a lattice row, `x` in `[lo, hi]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Span {
    /// Row.
    pub y: i64,
    /// Smallest x.
    pub lo: f64,
    /// Largest x.
    pub hi: f64,
}

/// Pushes, for every lattice row (multiple of `grid_step`) that `quad`
/// reaches, the x range of `quad` on that row (a superset: the hull clipped to the strip
/// `|y - row| <= margin`, widened by the margin).
pub fn quad_spans(quad: &Quad, grid_step: i64, out: &mut Vec<Span>) {
    let e = quad.margin;
    let gf = grid_step as f64;
    let (xs, ys) = (quad.pts.map(|p| p.x), quad.pts.map(|p| p.y));
    let x_min = xs.iter().copied().fold(f64::INFINITY, f64::min) - e;
    let x_max = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max) + e;
    // Most regions are slivers between lattice columns or rows.
    if ceil(x_min / gf) * gf > x_max {
        return;
    }
    let y_min = ys.iter().copied().fold(f64::INFINITY, f64::min) - e;
    let y_max = ys.iter().copied().fold(f64::NEG_INFINITY, f64::max) + e;
    let mut y = ceil_i64(y_min / gf) * grid_step;
    while (y as f64) <= y_max {
        let (s_lo, s_hi) = (y as f64 - e, y as f64 + e);
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for i in 0..4 {
            for j in i + 1..4 {
                if let Some((x0, x1)) = clip_to_strip(quad.pts[i], quad.pts[j], s_lo, s_hi) {
                    lo = lo.min(x0);
                    hi = hi.max(x1);
                }
            }
        }
        if lo <= hi {
            out.push(Span {
                y,
                lo: lo - e,
                hi: hi + e,
            });
        }
        y += grid_step;
    }
}

/// `x.ceil() as i64` without libm's `ceil`, a call on the baseline x86-64
/// target (the spans take one per quadrilateral and per row): the same
/// value for every `x`, infinities and NaN included, as the cast
/// saturates either way.
#[inline(always)]
fn ceil_i64(x: f64) -> i64 {
    let t = x as i64;
    if (t as f64) < x {
        t.saturating_add(1)
    } else {
        t
    }
}

/// `x.ceil()` by [`ceil_i64`], the same value for every `x` (up to the
/// sign of a zero): from `2^52` on every `f64` is an integer.
#[inline(always)]
fn ceil(x: f64) -> f64 {
    if x.abs() < 4_503_599_627_370_496.0 {
        ceil_i64(x) as f64
    } else {
        x
    }
}

/// The x range of the part of segment `a b` with `y` in `[y0, y1]`.
fn clip_to_strip(a: V2, b: V2, y0: f64, y1: f64) -> Option<(f64, f64)> {
    let dy = b.y - a.y;
    let (t0, t1) = if dy.abs() < 1e-300 {
        if a.y < y0 || a.y > y1 {
            return None;
        }
        (0.0, 1.0)
    } else {
        let (ta, tb) = ((y0 - a.y) / dy, (y1 - a.y) / dy);
        (ta.min(tb).max(0.0), ta.max(tb).min(1.0))
    };
    if t0 > t1 {
        return None;
    }
    let (xa, xb) = (a.x + (b.x - a.x) * t0, a.x + (b.x - a.x) * t1);
    Some((xa.min(xb), xa.max(xb)))
}

/// Buffers of [`super::LocatorSweep::for_each_third_locator`], reused across `L2`.
#[derive(Debug, Default)]
pub struct SweepScratch {
    pub(super) quads: Vec<Quad>,
    pub(super) spans: Vec<Span>,
}

/// Every lattice point (multiples of `grid_step`) of the union of `quads`, row
/// by row, each once.
pub(super) fn scan_quads(
    quads: &[Quad],
    grid_step: i64,
    spans: &mut Vec<Span>,
    mut visit: impl FnMut([i64; 2]),
) {
    spans.clear();
    for quad in quads {
        quad_spans(quad, grid_step, spans);
    }
    spans.sort_unstable_by(|a, b| a.y.cmp(&b.y).then(a.lo.total_cmp(&b.lo)));
    let gf = grid_step as f64;
    let mut row = i64::MIN;
    let mut next_x = i64::MIN;
    for s in spans.iter() {
        if s.y != row {
            row = s.y;
            next_x = i64::MIN;
        }
        let mut x = (ceil_i64(s.lo / gf) * grid_step).max(next_x);
        while (x as f64) <= s.hi {
            visit([x, s.y]);
            x += grid_step;
        }
        next_x = next_x.max(x);
    }
}

#[cfg(test)]
mod tests {
    use super::{ceil, ceil_i64};

    #[test]
    fn ceil_without_libm_matches_std() {
        let mut values = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            2.5e-300,
            -2.5e-300,
            4_503_599_627_370_495.5,
            -4_503_599_627_370_495.5,
            9.3e18,
            -9.3e18,
            1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        let mut rng = crate::test_rng::Xorshift::new(7);
        values.extend((0..2000).map(|k| rng.signed_unit() * 10f64.powi(k % 20 - 4)));
        for x in values {
            assert_eq!(ceil_i64(x), x.ceil() as i64, "{x}");
            let (ours, std) = (ceil(x), x.ceil());
            assert!(ours == std || (ours.is_nan() && std.is_nan()), "{x}");
        }
    }
}
