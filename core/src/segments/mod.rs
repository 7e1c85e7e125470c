//! Usable segments: the pieces of the grown part's true boundary (SPEC
//! sections 2 and 8.2) where a locator or the clamp tip can touch the part,
//! straight where the part edge is straight and circular where it is an
//! arc.
//!
//! Polygons go through `line`, the code fixplan had before arcs, so their
//! segments do not change by a bit; outlines with arcs go through
//! `curved`, which cuts every grown edge, line or arc, at the points where
//! its distance to the part or an access region crosses `r`.

mod curved;
mod cuts;
mod far;
mod line;
mod pairs;
mod segment;
mod walls;

#[cfg(test)]
mod tests;

pub use pairs::PairBounds;
pub(crate) use pairs::PairTable;
pub use segment::{arc_inward_normal, Feature, LineFeature, Segment, SegmentKind};

use crate::geometry::V2;
use crate::outline::Outline;

/// The segments of a part region (CCW outline, CW holes) with access
/// constraints (SPEC 2, 8.2 and 9.3), all in lattice units: grow by `r`,
/// keep the true boundary, keep away from access regions, trim `trim` at
/// both ends except at smooth joints. Numbered by (edge, position), edges
/// over the loops as SPEC 9.2 numbers them.
pub fn usable_segments(outline: &Outline, access: &[Vec<V2>], r: f64, trim: f64) -> Vec<Segment> {
    if !outline.is_polygon() {
        curved::outline_segments(outline, access, r, trim)
    } else {
        line::polygon_segments(outline.points(), access, r, trim)
    }
}
