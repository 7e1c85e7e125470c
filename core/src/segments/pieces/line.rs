//! The cut of a grown line: every crossing with a near edge's curves, and
//! of the far edges' crossings only those that can move a piece's end
//! ([`super::far`]: a long outline edge beside a row of holes would
//! otherwise be cut hundreds of times); each piece's middle is tested
//! against the near edges whose boxes reach it.

use super::far::{EdgeSpans, NearZones};
use super::shared::EdgeCut;
use crate::geometry::Aabb;
use crate::segments::cuts::{edge_cuts, far_edge_cuts};
use crate::segments::segment::{Feature, LineFeature};

/// The open parameter intervals of the grown line `line` (the feature
/// `f`) that lie too close to another edge or an access region.
pub(super) fn removed_pieces(f: &Feature, line: &LineFeature, cut: &EdgeCut) -> Vec<(f64, f64)> {
    let edges = cut.outline.edges();
    let (rho, slack) = (cut.rho, cut.slack);
    let cuts = line_cuts(f, line, cut);
    // The pieces come in order of `s`: each middle is tested against the
    // near edges whose boxes can reach it.
    let mut spans = EdgeSpans::of(line, cut.near, cut.outline.edge_boxes(), rho + slack, slack);
    cut.removed_where(f, cuts, |s, p| {
        spans.at(s).any(|j| edges[j].distance(p) < rho)
    })
}

/// The crossings of the grown line with the near edges' curves, and
/// those of the far edges' that can bound a piece in a near zone.
fn line_cuts(f: &Feature, line: &LineFeature, cut: &EdgeCut) -> Vec<f64> {
    let edges = cut.outline.edges();
    let (len, near, rho, slack) = (cut.len, cut.near, cut.rho, cut.slack);
    let mut cuts = vec![0.0, len];
    for &j in near {
        edge_cuts(f, &edges[j], rho, &mut cuts);
    }
    let mut far = Vec::with_capacity(2 * edges.len());
    let mut near_iter = near.iter().peekable();
    for (j, e) in edges.iter().enumerate() {
        if near_iter.next_if_eq(&&j).is_none() && j != cut.edge {
            far_edge_cuts(f, e, rho, &mut far);
        }
    }
    let boxes = near
        .iter()
        .map(|&j| cut.outline.edge_boxes()[j])
        .chain(cut.access.iter().map(|poly| Aabb::of(poly)));
    NearZones::of(line, len, boxes, rho + slack, slack).add_far_cuts(&far, len, &mut cuts);
    cuts
}
