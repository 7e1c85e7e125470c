//! What the cut of one grown edge is made against, and the steps of it
//! that are the same whatever the feature: the crossings with access
//! regions, the order of the cuts, and the test of each piece's middle.

use crate::geometry::{boundary_distance2, point_in_polygon, V2};
use crate::outline::{Edge, Outline};
use crate::segments::cuts::edge_cuts;
use crate::segments::segment::Feature;

/// The cut of the grown edge `edge`: its neighbours and the access
/// regions it must keep `rho` away from.
#[derive(Debug, Clone, Copy)]
pub(crate) struct EdgeCut<'a> {
    /// Index of the edge whose grown feature is cut.
    pub(crate) edge: usize,
    /// Length of the grown feature: `s` runs over `0..=len`.
    pub(crate) len: f64,
    /// The part region the edge belongs to.
    pub(crate) outline: &'a Outline,
    /// The edges (increasing) a point of the grown edge can be closer
    /// than `rho` to.
    pub(crate) near: &'a [usize],
    /// Filled access regions.
    pub(crate) access: &'a [Vec<V2>],
    /// The clearance, `r - eps`.
    pub(crate) rho: f64,
    /// Rounding allowance of the box tests that chose `near`.
    pub(crate) slack: f64,
}

impl EdgeCut<'_> {
    /// The pieces of `f` between `cuts` (the crossings with the other
    /// edges' curves) and the access regions' crossings that lie too
    /// close: `near_edge(s, p)` says whether the point `p` at `s` is
    /// closer than `rho` to another edge; the access regions are tested
    /// here.
    pub(super) fn removed_where(
        &self,
        f: &Feature,
        mut cuts: Vec<f64>,
        mut near_edge: impl FnMut(f64, V2) -> bool,
    ) -> Vec<(f64, f64)> {
        let (access, len, rho) = (self.access, self.len, self.rho);
        for poly in access {
            for k in 0..poly.len() {
                let e = Edge::Line {
                    a: poly[k],
                    b: poly[(k + 1) % poly.len()],
                };
                edge_cuts(f, &e, rho, &mut cuts);
            }
        }
        cuts.retain(|s| *s >= 0.0 && *s <= len);
        cuts.sort_by(f64::total_cmp);
        cuts.dedup();
        let near_access = |p: V2| {
            access
                .iter()
                .any(|poly| point_in_polygon(p, poly) || boundary_distance2(p, poly).sqrt() < rho)
        };
        let mut too_close = |s: f64| {
            let p = f.point(s);
            near_edge(s, p) || near_access(p)
        };
        cuts.windows(2)
            .filter(|w| w[1] > w[0] && too_close(0.5 * (w[0] + w[1])))
            .map(|w| (w[0], w[1]))
            .collect()
    }
}
