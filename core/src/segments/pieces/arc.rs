//! The cut of a grown arc: every curve of a near edge, and of a far edge
//! the curves that run on past it (a far edge's end-point circles cannot
//! reach the arc: their crossings with its circle lie off the arc and
//! would be dropped); each piece's middle is tested against every near
//! edge.

use super::shared::EdgeCut;
use crate::segments::cuts::{edge_cuts, far_edge_cuts};
use crate::segments::segment::Feature;

/// The open parameter intervals of the grown arc `f` that lie too close
/// to another edge or an access region.
pub(super) fn removed_pieces(f: &Feature, cut: &EdgeCut) -> Vec<(f64, f64)> {
    let edges = cut.outline.edges();
    let (near, rho) = (cut.near, cut.rho);
    let mut cuts = vec![0.0, cut.len];
    let mut near_iter = near.iter().peekable();
    for (j, e) in edges.iter().enumerate() {
        if near_iter.next_if_eq(&&j).is_some() {
            edge_cuts(f, e, rho, &mut cuts);
        } else if j != cut.edge {
            far_edge_cuts(f, e, rho, &mut cuts);
        }
    }
    cut.removed_where(f, cuts, |_, p| {
        near.iter().any(|&j| edges[j].distance(p) < rho)
    })
}
