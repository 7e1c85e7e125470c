//! The crossings far edges add to the cut of a grown line, cut down to the
//! ones that can change its answer.
//!
//! The cut of [`crate::segments::curved`] splits a grown edge at its crossings with
//! the level curves of every edge of the part. An edge farther than `rho`
//! from the grown edge never makes a piece too close, but the lines along
//! it run on and cross the grown line: a part with many holes gives every
//! outline edge hundreds of such crossings, each a piece to sort and test.
//!
//! Only the pieces whose middle lies in a *zone*, where some near edge or
//! access region comes within `rho` (box tests, with slack), can be
//! removed; every other piece is kept. Keeping the far crossings inside
//! the zones and, in each gap between zones, the first and the last, leaves
//! every piece whose middle lies in a zone exactly as it was (its ends are
//! consecutive crossings, and neither can be a dropped one: a dropped
//! crossing lies strictly between two kept ones of its gap, so a piece it
//! bounds lies in the gap). The pieces it merges lie in a gap and are kept
//! either way, so the removed pieces, and the segments, are the same bit
//! for bit.

use crate::geometry::Aabb;
use crate::segments::polygon::slab;
use crate::segments::segment::LineFeature;

/// The zones of a grown line, merged and in order of `s`.
pub(super) struct NearZones {
    zones: Vec<(f64, f64)>,
}

impl NearZones {
    /// The zones of the grown line `line` (parameters `0..=len`) where a
    /// point can lie within `reach` of a box of `boxes`. `slack` widens
    /// each zone, for the rounding of the box clip.
    pub(super) fn of(
        line: &LineFeature,
        len: f64,
        boxes: impl Iterator<Item = Aabb>,
        reach: f64,
        slack: f64,
    ) -> NearZones {
        let mut zones: Vec<(f64, f64)> = boxes
            .filter_map(|b| box_span(line, &b, reach, slack))
            .filter(|&(lo, hi)| hi >= 0.0 && lo <= len)
            .collect();
        zones.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut merged: Vec<(f64, f64)> = Vec::with_capacity(zones.len());
        for (lo, hi) in zones {
            match merged.last_mut() {
                Some(last) if lo <= last.1 => last.1 = last.1.max(hi),
                _ => merged.push((lo, hi)),
            }
        }
        NearZones { zones: merged }
    }

    /// Adds to `cuts` the crossings of `far` in `0..=len` that can bound a
    /// piece whose middle lies in a zone: those inside a zone, and the
    /// smallest and largest of each gap before, between and after them.
    pub(super) fn add_far_cuts(&self, far: &[f64], len: f64, cuts: &mut Vec<f64>) {
        let gaps = self.zones.len() + 1;
        let mut first = vec![f64::INFINITY; gaps];
        let mut last = vec![f64::NEG_INFINITY; gaps];
        for &c in far {
            if !(c >= 0.0 && c <= len) {
                continue;
            }
            // The first zone that does not end before c.
            let k = self.zones.partition_point(|z| z.1 < c);
            if k < self.zones.len() && self.zones[k].0 <= c {
                cuts.push(c);
            } else {
                first[k] = first[k].min(c);
                last[k] = last[k].max(c);
            }
        }
        for (lo, hi) in first.into_iter().zip(last) {
            if lo <= hi {
                cuts.extend([lo, hi]);
            }
        }
    }
}

/// The parameters of the grown line `line` (an interval, maybe unbounded)
/// where a point can lie within `reach` of the box `b`, widened by `slack`
/// for the rounding of the clip; `None` if there are none.
fn box_span(line: &LineFeature, b: &Aabb, reach: f64, slack: f64) -> Option<(f64, f64)> {
    let (x0, x1) = slab(line.origin.x, line.u.x, b.min.x - reach, b.max.x + reach)?;
    let (y0, y1) = slab(line.origin.y, line.u.y, b.min.y - reach, b.max.y + reach)?;
    let (lo, hi) = (x0.max(y0) - slack, x1.min(y1) + slack);
    (lo <= hi).then_some((lo, hi))
}

/// The near edges of a grown line by the stretch of it their boxes can
/// come within reach of ([`box_span`]), for testing a piece's middle
/// against the few edges near it rather than against every near edge: a
/// long outline edge beside a row of holes has hundreds of pieces and of
/// near edges. An edge closer than the reach to a point has its box
/// closer too, so it is among those listed at that point, and the answer
/// of "is any edge too close" is the same.
pub(super) struct EdgeSpans {
    /// `(lo, hi, edge)`, by increasing `lo`.
    spans: Vec<(f64, f64, usize)>,
    /// How many of `spans` have been taken in.
    taken: usize,
    /// The edges taken in whose span has not ended before the last `s`,
    /// as `(hi, edge)`.
    active: Vec<(f64, usize)>,
}

impl EdgeSpans {
    /// The spans of the edges `near` (indices into `boxes`) on `line`.
    pub(super) fn of(
        line: &LineFeature,
        near: &[usize],
        boxes: &[Aabb],
        reach: f64,
        slack: f64,
    ) -> EdgeSpans {
        let mut spans: Vec<(f64, f64, usize)> = near
            .iter()
            .filter_map(|&j| box_span(line, &boxes[j], reach, slack).map(|(lo, hi)| (lo, hi, j)))
            .collect();
        spans.sort_by(|a, b| a.0.total_cmp(&b.0));
        EdgeSpans {
            spans,
            taken: 0,
            active: Vec::new(),
        }
    }

    /// The edges whose span holds `s`, and maybe a few more. `s` must not
    /// decrease from one call to the next.
    pub(super) fn at(&mut self, s: f64) -> impl Iterator<Item = usize> + '_ {
        while let Some(&(lo, hi, j)) = self.spans.get(self.taken) {
            if lo > s {
                break;
            }
            self.active.push((hi, j));
            self.taken += 1;
        }
        self.active.retain(|&(hi, _)| hi >= s);
        self.active.iter().map(|&(_, j)| j)
    }
}
