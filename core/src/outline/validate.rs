//! Validation of outlines on their true curves (SPEC 8.1 and 7).
//!
//! Arc-free outlines go through [`validate_polygon`] unchanged, so their
//! errors and messages are exactly the polygon ones. With arcs, crossings
//! are decided with a tolerance of `1e-9` times the outline's extent:
//! tangent joints (a fillet meeting its line) compute their second
//! intersection a few ulps from the shared vertex, and two edges that come
//! closer than that are touching for any practical purpose.

use super::edge::{ccw_of_cw_outline, edges_of, Edge};
use super::mass::general;
use super::vertex::Vertex;
use crate::geometry::arc::{same_circle, CircArc};
use crate::geometry::polygon::{validate_polygon, PolygonError};
use crate::geometry::{point_segment_dist2, V2};
use thiserror::Error;

/// Crossing tolerance relative to the outline's extent.
pub(super) const TOUCH_REL: f64 = 1e-9;

/// Why an outline is invalid. Problems that polygons also have (too few
/// vertices without arcs, non-finite coordinates, repeated vertices,
/// crossings, zero area) are [`PolygonError`]s with their usual messages,
/// so catalogue reports treat both alike.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum OutlineError {
    /// A problem polygons share, worded as for polygons.
    #[error(transparent)]
    Polygon(#[from] PolygonError),
    /// An outline with an arc and fewer than 2 vertices.
    #[error("has {0} vertices; an outline with arcs needs at least 2")]
    TooFewArcVertices(usize),
    /// A bulge that is not a finite number.
    #[error("vertex {index} has bulge {bulge}; a bulge must be a finite number")]
    BadBulge {
        /// The vertex whose outgoing edge it is.
        index: usize,
        /// The bulge as read.
        bulge: f64,
    },
    /// A finite, non-zero bulge whose arc has no finite radius (too close
    /// to 0: a straight edge is written with bulge 0; or so large the
    /// circle overflows).
    #[error("vertex {index} has bulge {bulge:e}, which draws no arc of finite radius; write 0 for a straight edge")]
    NoArc {
        /// The vertex whose outgoing edge it is.
        index: usize,
        /// The bulge as read.
        bulge: f64,
    },
}

/// Checks SPEC 8.1's conditions on the true curves and returns the outline
/// counter-clockwise (orientation = sign of the true area).
pub fn validate_outline(vertices: &[Vertex]) -> Result<Vec<Vertex>, OutlineError> {
    if !vertices.iter().any(Vertex::is_arc) {
        let pts: Vec<[f64; 2]> = vertices.iter().map(|v| [v.x, v.y]).collect();
        let ccw = validate_polygon(&pts)?;
        return Ok(ccw.iter().map(|p| Vertex::new(p.x, p.y, 0.0)).collect());
    }
    let n = vertices.len();
    if n < 2 {
        return Err(OutlineError::TooFewArcVertices(n));
    }
    for (index, v) in vertices.iter().enumerate() {
        if !v.x.is_finite() || !v.y.is_finite() {
            return Err(PolygonError::NonFinite { index }.into());
        }
        if !v.bulge.is_finite() {
            return Err(OutlineError::BadBulge {
                index,
                bulge: v.bulge,
            });
        }
    }
    repeated_vertex(vertices)?;
    let edges = edges_of(vertices);
    if let Some(index) = (0..n).find(|&i| vertices[i].is_arc() && !edges[i].is_arc()) {
        return Err(OutlineError::NoArc {
            index,
            bulge: vertices[index].bulge,
        });
    }
    let (scale, extent) = sizes(vertices);
    if let Some((first, second, p)) = first_crossing(&edges, TOUCH_REL * extent) {
        return Err(PolygonError::SelfIntersection {
            first,
            second,
            x: p.x,
            y: p.y,
        }
        .into());
    }
    let area = general(vertices).area;
    if area.abs() <= 1e-12 * scale * scale || area == 0.0 {
        return Err(PolygonError::ZeroArea.into());
    }
    Ok(if area < 0.0 {
        ccw_of_cw_outline(vertices)
    } else {
        vertices.to_vec()
    })
}

/// Any two equal vertices, as for polygons (a repeated vertex that is not
/// consecutive would also be two edges touching).
fn repeated_vertex(vertices: &[Vertex]) -> Result<(), PolygonError> {
    for (i, p) in vertices.iter().enumerate() {
        for (j, q) in vertices.iter().enumerate().skip(i + 1) {
            if p.point() == q.point() {
                return Err(PolygonError::RepeatedVertex {
                    first: i,
                    second: j,
                    x: p.x,
                    y: p.y,
                });
            }
        }
    }
    Ok(())
}

/// Largest absolute coordinate (the polygon code's zero-area scale) and
/// the larger side of the vertices' bounding box (for crossings, so that
/// moving a part does not change its validity).
pub(super) fn sizes(vertices: &[Vertex]) -> (f64, f64) {
    let scale = vertices
        .iter()
        .fold(0.0f64, |m, v| m.max(v.x.abs()).max(v.y.abs()));
    let pts: Vec<V2> = vertices.iter().map(Vertex::point).collect();
    let bb = crate::geometry::Aabb::of(&pts);
    let extent = (bb.max.x - bb.min.x).max(bb.max.y - bb.min.y);
    (scale, extent)
}

/// First pair of edges `(i, j)`, `i < j`, that meet where they should not:
/// non-adjacent edges anywhere (within `tol`), adjacent ones away from the
/// vertices they share (both vertices when there are only two edges).
fn first_crossing(edges: &[Edge], tol: f64) -> Option<(usize, usize, V2)> {
    let n = edges.len();
    for i in 0..n {
        for j in i + 1..n {
            let mut shared = Vec::with_capacity(2);
            if j == i + 1 {
                shared.push(edges[i].end());
            }
            if i == 0 && j == n - 1 {
                shared.push(edges[0].start());
            }
            let hit = if shared.is_empty() {
                let c = edges[i].closest(&edges[j]);
                (c.distance <= tol).then_some(c.p)
            } else {
                adjacent_overlap(&edges[i], &edges[j], &shared, tol)
            };
            if let Some(p) = hit {
                return Some((i, j, p));
            }
        }
    }
    None
}

/// A point where two edges sharing the vertices `shared` meet elsewhere:
/// the second meeting point of their line and circle or of their two
/// circles when it lies on both edges, an arc on the same circle running
/// back over its neighbour, or two lines folding back on each other.
///
/// The second point is the reflection of the shared vertex (across the
/// line of centres, or along the line), not a fresh intersection: that
/// keeps the known point exact, where a general circle-circle
/// intersection with a nearly straight arc (radius 5e4 on a part of size
/// 30) lands 4e-8 off it and looks like a separate crossing.
fn adjacent_overlap(e: &Edge, f: &Edge, shared: &[V2], tol: f64) -> Option<V2> {
    let s = shared[0];
    let away = |p: &V2| shared.iter().all(|s| (p - s).norm() > tol);
    let on = |edge: &Edge, p: V2| match edge {
        Edge::Line { a, b } => point_segment_dist2(p, *a, *b).sqrt() <= tol,
        Edge::Arc(arc) => arc.contains_on_circle(p, tol),
    };
    let second = match (e, f) {
        // Two lines (only one shared vertex then: an outline with arcs has
        // more than two lines' worth of edges) overlap when the far end of
        // one lies on the other.
        (Edge::Line { a, b }, Edge::Line { a: c, b: d }) => {
            return [*a, *b, *c, *d]
                .into_iter()
                .find(|&p| away(&p) && on(e, p) && on(f, p));
        }
        (Edge::Line { a, b }, Edge::Arc(arc)) | (Edge::Arc(arc), Edge::Line { a, b }) => {
            let u = (b - a).normalize();
            s - u * (2.0 * u.dot(&(s - arc.center)))
        }
        (Edge::Arc(p), Edge::Arc(q)) => {
            if same_circle(p, q, tol) {
                return overlap_on_circle(p, q, tol).filter(|x| away(x));
            }
            let axis = (q.center - p.center).normalize();
            let foot = p.center + axis * (s - p.center).dot(&axis);
            foot * 2.0 - s
        }
    };
    (away(&second) && on(e, second) && on(f, second)).then_some(second)
}

/// For two arcs of one circle: an end point or midpoint of either lying
/// strictly inside the other (more than `tol` from its ends). Two closed
/// arcs share more than end points exactly when one of these six points
/// does.
fn overlap_on_circle(p: &CircArc, q: &CircArc, tol: f64) -> Option<V2> {
    let inside = |arc: &CircArc, x: V2| arc.contains_on_circle(x, -tol);
    [p.a, p.b, p.midpoint()]
        .into_iter()
        .find(|&x| inside(q, x))
        .or_else(|| [q.a, q.b, q.midpoint()].into_iter().find(|&x| inside(p, x)))
}
