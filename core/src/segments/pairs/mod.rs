//! Distance bounds between every two segments: the annuli that prune the
//! lattice points a second or third locator can take (SPEC 3), computed
//! once per part, on its first enumeration.
//!
//! The bound of a pair is computed by the code of its feature pair, chosen
//! once in [`PairBounds::between`]: `line_line` (exact, from end points:
//! the code of polygons), `line_arc` (exact) and `arc_arc` (sampled, with
//! a Lipschitz slack). A new feature kind adds its pairs there.

mod arc_arc;
mod farthest;
mod line_arc;
mod line_line;

use super::segment::{Feature, Segment};
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
    /// The distance range between the points of `a` and those of `b`: the
    /// dispatcher of the bounds, by feature pair.
    pub(crate) fn between(a: &Segment, b: &Segment) -> PairBounds {
        let (dmin, dmax) = match (&a.feature, &b.feature) {
            (Feature::Line(_), Feature::Line(_)) => line_line::distance_range(a, b),
            (Feature::Arc(arc), Feature::Line(_)) => {
                line_arc::distance_range(b, &a.piece_of_arc(arc))
            }
            (Feature::Line(_), Feature::Arc(arc)) => {
                line_arc::distance_range(a, &b.piece_of_arc(arc))
            }
            (Feature::Arc(p), Feature::Arc(q)) => {
                arc_arc::distance_range(&a.piece_of_arc(p), &b.piece_of_arc(q))
            }
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
    let mut pair = Vec::with_capacity(segments.len() * segments.len());
    for a in segments {
        for b in segments {
            pair.push(PairBounds::between(a, b));
        }
    }
    pair
}
