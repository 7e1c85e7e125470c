//! The lattice points of a region covered by grown quadrilaterals, row
//! by row and each once: what every kind of sweep hands the setup search.

use super::pieces::Quad;
use crate::geometry::rounding::{ceil, ceil_i64};
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
    if (y as f64) > y_max {
        return;
    }
    let p = &quad.pts;
    let pairs =
        [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)].map(|(i, j)| StripPair::of(p[i], p[j]));
    while (y as f64) <= y_max {
        let (s_lo, s_hi) = (y as f64 - e, y as f64 + e);
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for pair in &pairs {
            if let Some((x0, x1)) = pair.clip(s_lo, s_hi) {
                lo = lo.min(x0);
                hi = hi.max(x1);
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

/// Segment `a b` of a quadrilateral (two of its corners) with what
/// [`StripPair::clip`] needs of it that does not change from row to row,
/// worked out once per quadrilateral: the same operations on the same
/// values as clipping from the corners each row, so the same spans.
#[derive(Debug, Clone, Copy)]
struct StripPair {
    a: V2,
    dx: f64,
    dy: f64,
    /// `dy` too small to divide by: the segment is horizontal.
    flat: bool,
}

impl StripPair {
    fn of(a: V2, b: V2) -> StripPair {
        let dy = b.y - a.y;
        StripPair {
            a,
            dx: b.x - a.x,
            dy,
            flat: dy.abs() < 1e-300,
        }
    }

    /// The x range of the part of the segment with `y` in `[y0, y1]`.
    #[inline(always)]
    fn clip(&self, y0: f64, y1: f64) -> Option<(f64, f64)> {
        let (a, dy) = (self.a, self.dy);
        let (t0, t1) = if self.flat {
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
        let (xa, xb) = (a.x + self.dx * t0, a.x + self.dx * t1);
        Some((xa.min(xb), xa.max(xb)))
    }
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
