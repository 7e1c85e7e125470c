//! Distance bounds between every two segments: the annuli that prune the
//! lattice points a second or third locator can take (SPEC 3), computed
//! once per part, on its first enumeration.
//!
//! The bound of a pair is computed by the code of its feature pair, chosen
//! once in [`PairBounds::between`]: `line_line` (exact, from end points:
//! the code of polygons), `line_arc` (exact) and `arc_arc` (sampled, with
//! a Lipschitz slack). A new feature kind adds its pairs there. What a
//! pair reads of each of its segments (end points, arc piece, the sampled
//! points of an arc) is worked out once per segment ([`Sides`]), not once
//! per pair: a small part with arcs spent most of its table in the sines
//! and cosines of the same arc samples, recomputed for every other arc.

mod arc_arc;
mod farthest;
mod line_arc;
mod line_line;

use super::segment::{Feature, Segment};
use crate::geometry::arc::CircArc;
use crate::geometry::V2;
use std::sync::{Arc, OnceLock};

/// Distance range between the points of two segments: the annulus that
/// prunes the lattice points a second or third locator can take.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairBounds {
    /// Smallest distance.
    pub dmin: f64,
    /// Largest distance.
    pub dmax: f64,
}

impl PairBounds {
    /// The distance range between the points of `a` and those of `b` (the
    /// tests' pair by pair; the table reads each segment once).
    #[cfg(test)]
    pub(crate) fn between(a: &Segment, b: &Segment) -> PairBounds {
        Sides::of(a).bounds(&Sides::of(b))
    }
}

/// What the bounds of a pair read of one of its segments, by the same
/// calls as reading it pair by pair (so the same numbers, to the bit).
#[derive(Debug, Clone)]
pub(super) struct Sides {
    /// [`Segment::start`].
    start: V2,
    /// [`Segment::end`].
    end: V2,
    /// The arc piece and its sampled points; `None` on a line.
    arc: Option<(CircArc, Vec<V2>)>,
}

impl Sides {
    /// The sides of `segment`.
    fn of(segment: &Segment) -> Sides {
        let arc = match &segment.feature {
            Feature::Line(_) => None,
            Feature::Arc(arc) => {
                let piece = segment.piece_of_arc(arc);
                let samples = arc_arc::samples(&piece);
                Some((piece, samples))
            }
        };
        Sides {
            start: segment.start(),
            end: segment.end(),
            arc,
        }
    }

    /// The bounds of the pair (this segment, `other`): the dispatcher of
    /// the bounds, by feature pair.
    fn bounds(&self, other: &Sides) -> PairBounds {
        let (dmin, dmax) = match (&self.arc, &other.arc) {
            (None, None) => {
                line_line::distance_range([self.start, self.end], [other.start, other.end])
            }
            (Some((arc, _)), None) => line_arc::distance_range([other.start, other.end], arc),
            (None, Some((arc, _))) => line_arc::distance_range([self.start, self.end], arc),
            (Some((p, samples)), Some((q, _))) => arc_arc::distance_range(p, samples, q),
        };
        PairBounds { dmin, dmax }
    }
}

/// Every ordered pair's [`PairBounds`], `a * n + b`, computed on first use:
/// they are about half of a part's preparation (n^2 segment distances), and
/// a coordinator prepares the parts it cuts into shards only to count their
/// combinations and finish their results, which needs no bounds. Shared by
/// clones, so a study's kits compute them once.
#[derive(Debug, Clone, Default)]
pub(crate) struct PairTable(Arc<OnceLock<Vec<PairBounds>>>);

impl PairTable {
    /// The table of `segments` (the segments this table belongs to: the
    /// first call fixes it).
    #[inline]
    pub(crate) fn of(&self, segments: &[Segment]) -> &[PairBounds] {
        self.0.get_or_init(|| pair_bounds(segments))
    }
}

/// Distance ranges between every ordered pair of segments.
fn pair_bounds(segments: &[Segment]) -> Vec<PairBounds> {
    let sides: Vec<Sides> = segments.iter().map(Sides::of).collect();
    let mut pair = Vec::with_capacity(segments.len() * segments.len());
    for a in &sides {
        for b in &sides {
            pair.push(a.bounds(b));
        }
    }
    pair
}
