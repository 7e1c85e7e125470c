//! Where a grown edge crosses the level curves at a distance from an
//! edge (SPEC 8.2): circles about end points, lines parallel to straight
//! edges, circles concentric with arcs. Between two consecutive crossings
//! the distance to that edge stays on one side of the level, which is what
//! lets the segment code test one point per piece.
//!
//! The choice of code is made here once: a neighbour edge gives its level
//! curves ([`Level`], by the edge's kind), and [`crossings`] picks the file
//! of the pair (grown feature, level curve): `line_line`, `line_circle`,
//! `arc_line`, `arc_circle`. A new feature kind adds one arm per curve
//! kind there and a file for each.

mod arc_circle;
mod arc_line;
mod line_circle;
mod line_line;

use super::segment::Feature;
use crate::geometry::{v2, V2};
use crate::outline::Edge;

/// A level curve of an edge: the points at one distance from a piece of
/// it (the line along a straight edge moved sideways, a circle about an
/// end point or concentric with an arc).
#[derive(Debug, Clone, Copy)]
enum Level {
    /// The line through `through` along `along` (not necessarily unit).
    Line {
        /// A point of the line.
        through: V2,
        /// Its direction.
        along: V2,
    },
    /// The circle of centre `center` and radius `radius`.
    Circle {
        /// Centre.
        center: V2,
        /// Radius.
        radius: f64,
    },
}

/// Parameters where the grown edge `f` crosses the curves at distance
/// `rho` from edge `edge` (in no particular order).
pub(super) fn edge_cuts(f: &Feature, edge: &Edge, rho: f64, cuts: &mut Vec<f64>) {
    far_edge_cuts(f, edge, rho, cuts);
    let radius = rho;
    for center in [edge.start(), edge.end()] {
        crossings(f, Level::Circle { center, radius }, cuts);
    }
}

/// The crossings of [`edge_cuts`] that can lie on a grown edge farther than
/// `rho` from `edge`: those with the lines along a straight edge and the
/// circles about an arc's centre, which run on past the edge. The circles
/// about its end points cannot reach the grown edge; their crossings with
/// its line or circle fall outside the grown edge and would be dropped.
pub(super) fn far_edge_cuts(f: &Feature, edge: &Edge, rho: f64, cuts: &mut Vec<f64>) {
    match edge {
        Edge::Line { a, b } => {
            let d = b - a;
            let len = d.norm();
            if len > 0.0 {
                let m = v2(-d.y, d.x) / len;
                for through in [a + m * rho, a - m * rho] {
                    crossings(f, Level::Line { through, along: d }, cuts);
                }
            }
        }
        Edge::Arc(arc) => {
            let center = arc.center;
            let radius = arc.radius + rho;
            crossings(f, Level::Circle { center, radius }, cuts);
            let radius = arc.radius - rho;
            if radius > 0.0 {
                crossings(f, Level::Circle { center, radius }, cuts);
            }
        }
    }
}

/// The parameters where `f` meets `level`: the dispatcher of the cut, by
/// the pair (feature kind, curve kind).
#[inline]
fn crossings(f: &Feature, level: Level, cuts: &mut Vec<f64>) {
    match (f, level) {
        (Feature::Line(l), Level::Line { through, along }) => {
            line_line::crossings(l, through, along, cuts)
        }
        (Feature::Line(l), Level::Circle { center, radius }) => {
            line_circle::crossings(l, center, radius, cuts)
        }
        (Feature::Arc(a), Level::Line { through, along }) => {
            arc_line::crossings(a, through, along, cuts)
        }
        (Feature::Arc(a), Level::Circle { center, radius }) => {
            arc_circle::crossings(a, center, radius, cuts)
        }
    }
}
