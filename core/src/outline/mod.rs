//! Part outlines made of line segments and circular arcs (SPEC 8.1).
//!
//! A polygon is the special case with every bulge zero, and for it every
//! function here gives exactly what [`crate::geometry::polygon`] and
//! [`crate::geometry`] give (same errors, same floating-point numbers), so
//! arc-free parts keep their results when the enumeration moves to
//! outlines.
//!
//! The true region is the polygon of the vertices with, for each arc, the
//! circular segment between arc and chord added (the arc bulges out of the
//! polygon) or removed (it bulges in). Areas and moments follow from
//! Green's theorem edge by edge; point location is the polygon's even-odd
//! test toggled once per circular segment containing the point.

mod clearance;
mod edge;
mod mass;
mod validate;
mod vertex;

#[cfg(test)]
mod tests;

pub use edge::{ccw_of_cw_outline, edges_of, tangents_smooth, Edge, GrownEdge};
pub use mass::{mass_properties, MassProperties};
pub use validate::{validate_outline, OutlineError};
pub use vertex::Vertex;

use crate::geometry::arc::{CircArc, Closest};
use crate::geometry::{point_in_polygon, V2};

/// A validated outline, counter-clockwise, with its edges.
#[derive(Debug, Clone, PartialEq)]
pub struct Outline {
    vertices: Vec<Vertex>,
    edges: Vec<Edge>,
    /// The vertex positions, kept because point location runs in the
    /// clearance tests of every candidate fixture.
    points: Vec<V2>,
    /// Whether an edge is an arc: asked once per clamp placement, where
    /// polygons take their own faster path.
    has_arcs: bool,
}

impl Outline {
    /// Validates `vertices` (SPEC 8.1) and normalises them to
    /// counter-clockwise.
    pub fn new(vertices: &[Vertex]) -> Result<Outline, OutlineError> {
        let vertices = validate_outline(vertices)?;
        let edges = edges_of(&vertices);
        let points = vertices.iter().map(Vertex::point).collect();
        let has_arcs = edges.iter().any(Edge::is_arc);
        Ok(Outline {
            vertices,
            edges,
            points,
            has_arcs,
        })
    }

    /// An outline from polygon points (all edges straight).
    pub fn from_polygon(points: &[[f64; 2]]) -> Result<Outline, OutlineError> {
        let v: Vec<Vertex> = points.iter().map(|&p| Vertex::from(p)).collect();
        Outline::new(&v)
    }

    /// The counter-clockwise vertices (what a result file would list).
    pub fn vertices(&self) -> &[Vertex] {
        &self.vertices
    }

    /// The edges, edge `i` leaving vertex `i`.
    pub fn edges(&self) -> &[Edge] {
        &self.edges
    }

    /// The vertex positions: the polygon itself when there are no arcs.
    pub fn points(&self) -> &[V2] {
        &self.points
    }

    /// Whether any edge is an arc.
    pub fn has_arcs(&self) -> bool {
        self.has_arcs
    }

    /// Area, centroid and polar moment of the true region (SPEC 6, 8.1).
    pub fn mass_properties(&self) -> MassProperties {
        mass_properties(&self.vertices)
    }

    /// Even-odd point location in the true region (boundary points may go
    /// either way; combine with [`Outline::boundary_distance`] where the
    /// boundary matters).
    pub fn contains(&self, p: V2) -> bool {
        let mut inside = point_in_polygon(p, &self.points);
        for e in &self.edges {
            if let Edge::Arc(arc) = e {
                inside ^= arc.segment_contains(p);
            }
        }
        inside
    }

    /// Nearest boundary point to `p` (first `p`, second the boundary point).
    pub fn closest_boundary_point(&self, p: V2) -> Closest {
        let mut best = Closest {
            distance: f64::INFINITY,
            p,
            q: p,
        };
        for e in &self.edges {
            let c = e.closest_to_point(p);
            if c.distance < best.distance {
                best = c;
            }
        }
        best
    }

    /// Distance from `p` to the boundary.
    pub fn boundary_distance(&self, p: V2) -> f64 {
        self.closest_boundary_point(p).distance
    }

    /// Distance from `p` to the true region (0 inside).
    pub fn distance(&self, p: V2) -> f64 {
        if self.contains(p) {
            0.0
        } else {
            self.boundary_distance(p)
        }
    }

    /// Whether vertex `i` is a smooth joint (SPEC 8.2): the edges meeting
    /// there are tangent, pointing on, and at least one is an arc.
    pub fn smooth_joint(&self, i: usize) -> bool {
        let n = self.edges.len();
        let (e_in, e_out) = (&self.edges[(i + n - 1) % n], &self.edges[i % n]);
        (e_in.is_arc() || e_out.is_arc())
            && tangents_smooth(e_in.tangent_end(), e_out.tangent_start())
    }

    /// A polygon through every vertex whose chords stay within
    /// `chord_error` of the arcs (at most 2^20 chords per arc), for
    /// drawings and for checking the exact functions against polygons.
    pub fn flatten(&self, chord_error: f64) -> Vec<V2> {
        let mut out = Vec::new();
        for e in &self.edges {
            out.push(e.start());
            if let Edge::Arc(arc) = e {
                let k = arc_pieces(arc, chord_error);
                out.extend((1..k).map(|i| arc.point_at(i as f64 / k as f64)));
            }
        }
        out
    }
}

/// Chords needed so that each deviates from the arc by at most `err`:
/// a chord of angle `a` deviates by `R (1 - cos(a / 2))`.
fn arc_pieces(arc: &CircArc, err: f64) -> usize {
    let ratio = (1.0 - err / arc.radius).max(-1.0);
    let max_angle = 2.0 * ratio.acos();
    let k = (arc.sweep.abs() / max_angle).ceil();
    if k.is_finite() {
        k.clamp(1.0, (1u32 << 20) as f64) as usize
    } else {
        1 << 20
    }
}
