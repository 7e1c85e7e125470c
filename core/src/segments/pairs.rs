//! Distance bounds between every two segments: the annuli that prune the
//! lattice points a second or third locator can take (SPEC 3), computed
//! once per part, on its first enumeration.

use super::segment::{distance_range, Segment};
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
    /// The distance range between the points of `a` and those of `b`.
    pub(crate) fn between(a: &Segment, b: &Segment) -> PairBounds {
        let (dmin, dmax) = distance_range(a, b);
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
