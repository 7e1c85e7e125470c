//! The pieces of a grown edge that lie too close to the part or an access
//! region (SPEC 8.2 and 9.3), removed before the segments are trimmed.
//!
//! The grown edge is cut at its crossings with the level curves of the
//! other edges ([`super::cuts`]) and each piece is tested at its middle.
//! How far crossings are cut down and which edges a middle is tested
//! against depend on the feature, chosen here once, in
//! [`removed_pieces`]: `line` (far crossings kept only where they can move
//! a piece's end, [`far`]; middles tested against the edges whose boxes
//! reach them) and `arc` (every level curve that can reach the arc; middles
//! tested against every near edge). What both share is in `shared`.

mod arc;
mod far;
mod line;
mod shared;

pub(super) use shared::EdgeCut;

use super::segment::Feature;

/// The open parameter intervals of the grown edge `cut.edge` (the whole
/// feature `f`) that lie closer than `cut.rho` to another edge or to a
/// filled access region: the dispatcher of the cut, by the feature's kind.
pub(super) fn removed_pieces(f: &Feature, cut: &EdgeCut) -> Vec<(f64, f64)> {
    match f {
        Feature::Line(line) => line::removed_pieces(f, line, cut),
        Feature::Arc(_) => arc::removed_pieces(f, cut),
    }
}
