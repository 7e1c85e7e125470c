//! The lattice points of a region covered by grown quadrilaterals, row
//! by row and each once: what every kind of sweep hands the setup search.

use super::pieces::Quad;
use crate::geometry::rounding::{ceil, ceil_i64};
use crate::geometry::V2;

/// A horizontal run of the plate, `y` a lattice row, `x` in `[lo, hi]`:
/// what [`scan_spans`], the reference of [`scan_quads`], sorts.
#[cfg(test)]
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
/// `|y - row| <= margin`, widened by the margin). The tests' reference:
/// the scan keeps runs.
#[cfg(test)]
pub(super) fn quad_spans(quad: &Quad, grid_step: i64, out: &mut Vec<Span>) {
    quad_rows(quad, grid_step, |y, lo, hi| out.push(Span { y, lo, hi }));
}

/// Pushes, for every row of `quad_spans`, the lattice points of its
/// span as a [`Run`], when it holds any: most spans of small parts lie
/// between two lattice columns, and what the scan needs of a span is only
/// its lattice points, so it is rounded once here and never stored,
/// sorted or rounded again when empty.
fn quad_runs(quad: &Quad, grid_step: i64, out: &mut Vec<Run>) {
    quad_rows(quad, grid_step, |y, lo, hi| {
        if let Some(run) = Run::of_span(y, lo, hi, grid_step) {
            out.push(run);
        }
    });
}

/// Calls `row(y, lo, hi)` for every span of `quad_spans`, in order:
/// the one computation behind spans and runs, so both list the same
/// lattice points.
#[inline(always)]
fn quad_rows(quad: &Quad, grid_step: i64, mut row: impl FnMut(i64, f64, f64)) {
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
    let [p0, p1, p2, p3] = quad.pts;
    // Spelled out, not mapped from index pairs: the map was a call per
    // quadrilateral, a fifth of the cost of a one-row one.
    let pairs = [
        StripPair::of(p0, p1),
        StripPair::of(p0, p2),
        StripPair::of(p0, p3),
        StripPair::of(p1, p2),
        StripPair::of(p1, p3),
        StripPair::of(p2, p3),
    ];
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
            row(y, lo - e, hi + e);
        }
        y += grid_step;
    }
}

/// The lattice points of one row of a region: `x` the multiples of the
/// grid step in `[x0, x1]`, on row `y`. Field order is the scan's order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(super) struct Run {
    y: i64,
    x0: i64,
    x1: i64,
}

impl Run {
    /// The lattice points of the span `[lo, hi]` of row `y`, exactly those
    /// the span scan visits (`scan_spans`: from `ceil(lo / g) g` while
    /// `x as f64 <= hi`); `None` when there are none.
    #[inline(always)]
    fn of_span(y: i64, lo: f64, hi: f64, grid_step: i64) -> Option<Run> {
        let gf = grid_step as f64;
        let x0 = ceil_i64(lo / gf) * grid_step;
        // The scan's loop test (false for a NaN `hi` too); then the last
        // multiple at or below `hi` by that test, step by step: a run
        // holds a point or two.
        ((x0 as f64) <= hi).then(|| {
            let mut x1 = x0;
            while ((x1 + grid_step) as f64) <= hi {
                x1 += grid_step;
            }
            Run { y, x0, x1 }
        })
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
    #[inline(always)]
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
    pub(super) runs: Vec<Run>,
}

/// Every lattice point (multiples of `grid_step`) of the union of `quads`, row
/// by row and `x` ascending, each once: the points of `scan_spans`, in
/// its order, from the non-empty spans only.
pub(super) fn scan_quads(
    quads: &[Quad],
    grid_step: i64,
    runs: &mut Vec<Run>,
    mut visit: impl FnMut([i64; 2]),
) {
    runs.clear();
    for quad in quads {
        quad_runs(quad, grid_step, runs);
    }
    runs.sort_unstable();
    let mut row = i64::MIN;
    let mut next_x = i64::MIN;
    for r in runs.iter() {
        if r.y != row {
            row = r.y;
            next_x = i64::MIN;
        }
        let mut x = r.x0.max(next_x);
        while x <= r.x1 {
            visit([x, r.y]);
            x += grid_step;
        }
        next_x = next_x.max(x);
    }
}

/// [`scan_quads`] from every span, empty or not, as it was before runs:
/// the reference the runs are tested against.
#[cfg(test)]
pub(super) fn scan_spans(
    quads: &[Quad],
    grid_step: i64,
    spans: &mut Vec<Span>,
    visit: impl FnMut([i64; 2]),
) {
    spans.clear();
    for quad in quads {
        quad_spans(quad, grid_step, spans);
    }
    scan_span_list(spans, grid_step, visit);
}

/// The lattice points of `spans` as [`scan_spans`] lists them.
#[cfg(test)]
pub(super) fn scan_span_list(spans: &mut [Span], grid_step: i64, mut visit: impl FnMut([i64; 2])) {
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

/// The `x` of the run of the span `[lo, hi]`, none when it has none.
#[cfg(test)]
pub(super) fn run_points(lo: f64, hi: f64, grid_step: i64) -> Vec<i64> {
    Run::of_span(0, lo, hi, grid_step)
        .map(|run| (run.x0..=run.x1).step_by(grid_step as usize).collect())
        .unwrap_or_default()
}
