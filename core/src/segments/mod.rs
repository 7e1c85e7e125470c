//! Usable segments: the pieces of the grown part's true boundary (SPEC
//! sections 2 and 8.2) where a locator or the clamp tip can touch the part,
//! straight where the part edge is straight and circular where it is an
//! arc.
//!
//! Polygons go through `polygon`, the code fixplan had before arcs, so
//! their segments do not change by a bit; outlines with arcs or holes go
//! through `curved`, which cuts every grown edge, line or arc, at the
//! points where its distance to the part or an access region crosses `r`.
//!
//! Where the code differs between lines and arcs, the choice is made once
//! per operation, in a dispatcher that names the files of the feature
//! kinds (or pairs of kinds), as parry's query dispatcher does:
//! - [`usable_segments`]: the polygon fast path or the general cut;
//! - `grow::grown_feature`: a part edge grown into a segment feature, and
//!   the range of its parameter;
//! - `pieces::removed_pieces`: the cut of a grown feature by the other
//!   edges (`pieces/line.rs`, `pieces/arc.rs`);
//! - `cuts::crossings`: where a grown feature meets a level curve of a
//!   neighbour edge, by pair (`cuts/line_line.rs`, `cuts/line_circle.rs`,
//!   `cuts/arc_line.rs`, `cuts/arc_circle.rs`); the level curves of an
//!   edge, by its kind, in `cuts::far_edge_cuts`;
//! - [`PairBounds`]: the distance bounds of two segments, by pair
//!   (`pairs/line_line.rs`, `pairs/line_arc.rs`, `pairs/arc_arc.rs`).
//!
//! A segment's one-line accessors (point, parameter, inward normal, kind,
//! arc piece) are matches beside [`Feature`] in `segment.rs`. A new
//! feature kind is a `Feature` variant, its arm in each of those, and a
//! file per pair; `walls` and `curved` use features only through them.

mod curved;
mod cuts;
mod grow;
mod pairs;
mod pieces;
mod polygon;
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
        polygon::polygon_segments(outline.points(), access, r, trim)
    }
}
