//! Growing a part edge into the feature its segments lie on (SPEC 2 step
//! 1 and 8.2), with the range of its parameter: the one place where the
//! outline's kinds of grown edge become the segments' kinds of feature.

use super::segment::{Feature, LineFeature};
use crate::geometry::EPS;
use crate::outline::{Edge, GrownEdge};

/// The whole grown edge of `edge` for a locator of radius `r` as a
/// segment feature (`s` from 0) and its length (the range of `s`); `None`
/// when the edge grows to nothing (a concave arc no wider than `r`). A
/// grown line is the edge moved along its normal, so it keeps the edge's
/// length.
pub(super) fn grown_feature(edge: &Edge, r: f64) -> Option<(Feature, f64)> {
    Some(match edge.grown(r, EPS)? {
        GrownEdge::Line { a, b, normal } => {
            let u = (b - a).normalize();
            (Feature::Line(LineFeature::new(a, u, normal)), edge.length())
        }
        GrownEdge::Arc(arc) => (Feature::Arc(arc), arc.length()),
    })
}
