//! The crossings far edges add to the cut of a grown line, cut down to the
//! ones that can change its answer.
//!
//! The cut of [`super::curved`] splits a grown edge at its crossings with
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

use super::line::slab;
use super::segment::LineFeature;
use crate::geometry::Aabb;

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
            .filter_map(|b| {
                let (x0, x1) = slab(line.origin.x, line.u.x, b.min.x - reach, b.max.x + reach)?;
                let (y0, y1) = slab(line.origin.y, line.u.y, b.min.y - reach, b.max.y + reach)?;
                let (lo, hi) = (x0.max(y0) - slack, x1.min(y1) + slack);
                (lo <= hi && hi >= 0.0 && lo <= len).then_some((lo, hi))
            })
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
