//! Hole walls that offer no segment, recognised at the cost of their own
//! loop (SPEC 9.3: most bolt holes are smaller than a locator).
//!
//! The cut of [`super::curved`] tests every piece of a grown edge between
//! crossings with the level curves of every edge of the part, a cost that
//! grows with the square of the edge count when a part has many holes.
//! A grown hole wall whose every point lies well within `rho` of another
//! edge of its own hole, but for stretches shorter than the trims, offers
//! nothing whatever the other edges add: proving that needs only the
//! hole's own edges. The proof is kept exact with a margin, so the answer is the full
//! cut's answer bit for bit, and where the margin is not met the full cut
//! decides. Most walls of small holes are shown covered at a few sample
//! points first, which costs a handful of distances and no allocation.

use super::cuts::edge_cuts;
use super::segment::Feature;
use crate::geometry::{Aabb, EPS};
use crate::outline::Edge;
use std::ops::Range;

/// Margin of the proof, relative to the coordinates' size: far above the
/// rounding of a distance (`1e-15` of it) and far below any hole's size.
const MARGIN_REL: f64 = 1e-7;

/// How the full cut trims a piece of edge `i` (SPEC 2 and 8.2): `trim`
/// at both ends, none at an end of the edge that is a smooth joint.
#[derive(Debug, Clone, Copy)]
pub(super) struct Trim {
    /// The edge trim, lattice units.
    pub(super) trim: f64,
    /// Whether the edge's start is a smooth joint.
    pub(super) smooth_start: bool,
    /// Whether its end is.
    pub(super) smooth_end: bool,
}

/// Whether the grown edge `f` (parameters `0..=len`) of edge `i` offers
/// no segment because of the other edges of its loop alone (`own`,
/// indices into `edges`): every point lies closer than `rho` to one of
/// them, with a margin rounding cannot eat, except on stretches too short
/// to survive the trim. Then the full cut, which tests the same edges
/// among others, finds no segment either.
///
/// Why it is exact: with `rho1 = rho - margin`, the distance from the
/// grown edge to the loop crosses `rho1` only at the cuts computed here,
/// so between two cuts it stays on one side of `rho1`; a piece whose
/// middle lies closer than `rho1 - margin` is closer than `rho1` all
/// along, up to rounding near its ends, so closer than `rho - margin / 2`,
/// and the full cut removes every point of it. What the full cut keeps
/// lies in the other pieces (its ends are where the distance reaches
/// `rho`, inside them, up to rounding), so a run of them shorter than the
/// trims, by a margin, holds no segment.
pub(super) fn offers_nothing(
    f: &Feature,
    len: f64,
    i: usize,
    edges: &[Edge],
    own: Range<usize>,
    rho: f64,
    trim: Trim,
) -> bool {
    let margin = MARGIN_REL * (1.0 + size_of(f, len));
    let rho1 = rho - margin;
    if rho1 - margin <= 0.0 {
        return false;
    }
    let others = || own.clone().filter(move |&j| j != i).map(|j| &edges[j]);
    if covered_at_samples(f, len, others, rho1 - margin) {
        return true;
    }
    let mut cuts = vec![0.0, len];
    for e in others() {
        edge_cuts(f, e, rho1, &mut cuts);
    }
    cuts.retain(|s| *s >= 0.0 && *s <= len);
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    // A run of pieces not shown covered, as (start, end).
    let mut run: Option<(f64, f64)> = None;
    let too_short = |(a, b): (f64, f64)| {
        let t0 = if a <= margin && trim.smooth_start {
            0.0
        } else {
            trim.trim
        };
        let t1 = if b >= len - margin && trim.smooth_end {
            0.0
        } else {
            trim.trim
        };
        (b - a) + 3.0 * margin - t0 - t1 <= EPS
    };
    for w in cuts.windows(2) {
        let p = f.point(0.5 * (w[0] + w[1]));
        if others().any(|e| e.distance(p) < rho1 - margin) {
            if !run.take().is_none_or(too_short) {
                return false;
            }
        } else {
            run = Some(run.map_or((w[0], w[1]), |(a, _)| (a, w[1])));
        }
    }
    run.is_none_or(too_short)
}

/// Most walls of small holes (a switch cutout, a bolt hole's flats) lie
/// well within `bound` of their hole's other edges all along: shown on a
/// few points, without cutting or sorting, then nothing else is asked.
const MAX_SAMPLE_STEPS: usize = 16;

/// Whether every point of the grown edge `f` (parameters `0..=len`) lies
/// closer than `bound` to one of `others`, shown at `n + 1` evenly spaced
/// points: the distance to a set moves no faster than the point, and `s`
/// is arc length (a grown line's `u` is a unit vector, an arc's chord is
/// shorter than its arc), so every point lies within `len / 2n` of a
/// sample and its distance exceeds the sample's by no more. `false` says
/// only that the samples do not show it (too far apart, or a point is not
/// covered); the full proof then decides.
fn covered_at_samples<'e, I>(f: &Feature, len: f64, others: impl Fn() -> I, bound: f64) -> bool
where
    I: Iterator<Item = &'e Edge>,
{
    // Steps of half the bound leave room for distances up to 3/4 of it.
    let steps = (len / (0.5 * bound)).ceil();
    if steps.is_nan() || steps > MAX_SAMPLE_STEPS as f64 {
        return false;
    }
    let steps = (steps as usize).max(1);
    let slack = 0.5 * len / steps as f64;
    (0..=steps).all(|k| {
        let p = f.point(len * k as f64 / steps as f64);
        others().any(|e| e.distance(p) + slack < bound)
    })
}

/// The largest coordinate of the grown edge's ends and middle, for the
/// margin's scale.
fn size_of(f: &Feature, len: f64) -> f64 {
    let b = Aabb::of(&[f.point(0.0), f.point(0.5 * len), f.point(len)]);
    [b.min.x, b.min.y, b.max.x, b.max.y]
        .iter()
        .fold(0.0f64, |m, x| m.max(x.abs()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::outline::{edges_of, Vertex};
    use crate::segments::grow::grown_feature;

    /// The walls of a rectangle hole `w` by `h` (clockwise, as holes are
    /// kept), grown by `r` into it, and whether the samples show each
    /// covered.
    fn sampled(w: f64, h: f64, r: f64) -> Vec<bool> {
        let hole: Vec<Vertex> = [[0.0, 0.0], [0.0, h], [w, h], [w, 0.0]]
            .iter()
            .map(|&[x, y]| Vertex::new(x, y, 0.0))
            .collect();
        let edges = edges_of(&hole);
        let rho = r - EPS;
        (0..edges.len())
            .map(|i| {
                let Some((f, len)) = grown_feature(&edges[i], r) else {
                    panic!("a straight wall grows");
                };
                let others = || (0..edges.len()).filter(move |&j| j != i).map(|j| &edges[j]);
                covered_at_samples(&f, len, others, rho)
            })
            .collect()
    }

    #[test]
    fn a_switch_cutout_is_covered_on_samples_and_a_window_is_not() {
        // aek64's cutouts in lattice units (11.7 x 9.5 mm, r 6 mm, 25 mm).
        assert_eq!(sampled(0.468, 0.381, 0.24), vec![true; 4]);
        // A window a locator fits in: its walls are not covered.
        assert_eq!(sampled(2.0, 1.5, 0.24), vec![false; 4]);
        // A slot narrower than a locator: covered all round.
        assert_eq!(sampled(1.5, 0.3, 0.24), vec![true; 4]);
    }
}
