//! The edges of an outline, lines and arcs, and what SPEC 8.1 and 8.2 say
//! of them one at a time: lengths, tangents, distances, growing by the
//! locator radius, smooth joints, and the normalisation of a clockwise list.

use super::vertex::Vertex;
use crate::geometry::arc::{
    arc_arc_closest, point_arc_closest, point_segment_closest, segment_arc_closest,
    segment_segment_closest, CircArc, Closest, GrownArc,
};
use crate::geometry::{cross, point_in_polygon, Aabb, V2};

/// Two unit tangents closer than this in `|t_in x t_out|` (and pointing the
/// same way) make a smooth joint (SPEC 8.2).
pub const SMOOTH_JOINT_TOL: f64 = 1e-6;

/// One edge of an outline, from a vertex to the next.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Edge {
    /// A straight edge from `a` to `b`.
    Line {
        /// Start point.
        a: V2,
        /// End point.
        b: V2,
    },
    /// A circular arc (bulge non-zero).
    Arc(CircArc),
}

/// The piece of a grown part edge on which a locator centre can lie (SPEC
/// 2 and 8.2), before the true-boundary, access and trim rules cut it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GrownEdge {
    /// A line edge moved outward by `r` along its `normal`.
    Line {
        /// Start point `v_i + r n`.
        a: V2,
        /// End point `v_(i+1) + r n`.
        b: V2,
        /// Outward unit normal `n = (u.y, -u.x)` of the CCW edge.
        normal: V2,
    },
    /// An arc of radius `rho_e`, parametrised by arc length.
    Arc(GrownArc),
}

impl Edge {
    /// The edge from `a` to `b` with the bulge of its start vertex; a
    /// bulge that makes no arc (zero, or a zero-length chord, which
    /// validation rejects) gives a line.
    pub fn new(a: V2, b: V2, bulge: f64) -> Edge {
        match CircArc::from_bulge(a, b, bulge) {
            Some(arc) => Edge::Arc(arc),
            None => Edge::Line { a, b },
        }
    }

    /// Start point.
    pub fn start(&self) -> V2 {
        match self {
            Edge::Line { a, .. } => *a,
            Edge::Arc(arc) => arc.a,
        }
    }

    /// End point.
    pub fn end(&self) -> V2 {
        match self {
            Edge::Line { b, .. } => *b,
            Edge::Arc(arc) => arc.b,
        }
    }

    /// Whether the edge is an arc.
    pub fn is_arc(&self) -> bool {
        matches!(self, Edge::Arc(_))
    }

    /// Length of the curve.
    pub fn length(&self) -> f64 {
        match self {
            Edge::Line { a, b } => (b - a).norm(),
            Edge::Arc(arc) => arc.length(),
        }
    }

    /// Unit tangent at the start, in the direction of travel.
    pub fn tangent_start(&self) -> V2 {
        match self {
            Edge::Line { a, b } => (b - a).normalize(),
            Edge::Arc(arc) => arc.tangent_start(),
        }
    }

    /// Unit tangent at the end, in the direction of travel.
    pub fn tangent_end(&self) -> V2 {
        match self {
            Edge::Line { a, b } => (b - a).normalize(),
            Edge::Arc(arc) => arc.tangent_end(),
        }
    }

    /// The point at fraction `t` of the way along the edge.
    pub fn point_at(&self, t: f64) -> V2 {
        match self {
            Edge::Line { a, b } => a + (b - a) * t,
            Edge::Arc(arc) => arc.point_at(t),
        }
    }

    /// Closest points of `p` (first) and the edge (second).
    pub fn closest_to_point(&self, p: V2) -> Closest {
        match self {
            Edge::Line { a, b } => point_segment_closest(p, *a, *b),
            Edge::Arc(arc) => point_arc_closest(p, arc),
        }
    }

    /// Distance from `p` to the edge.
    pub fn distance(&self, p: V2) -> f64 {
        self.closest_to_point(p).distance
    }

    /// Closest points of this edge (first) and `other` (second); where
    /// they cross, a crossing point.
    pub fn closest(&self, other: &Edge) -> Closest {
        match (self, other) {
            (Edge::Line { a, b }, Edge::Line { a: c, b: d }) => {
                segment_segment_closest(*a, *b, *c, *d)
            }
            (Edge::Line { a, b }, Edge::Arc(q)) => segment_arc_closest(*a, *b, q),
            (Edge::Arc(p), Edge::Line { a, b }) => segment_arc_closest(*a, *b, p).swapped(),
            (Edge::Arc(p), Edge::Arc(q)) => arc_arc_closest(p, q),
        }
    }

    /// Bounding box of the curve.
    pub fn aabb(&self) -> Aabb {
        match self {
            Edge::Line { a, b } => Aabb::of(&[*a, *b]),
            Edge::Arc(arc) => arc.aabb(),
        }
    }

    /// The grown edge for a locator of radius `r` (SPEC 2 step 1 and 8.2),
    /// for an edge of a counter-clockwise outline; `None` for a concave arc
    /// whose grown radius `R - r` is `<= eps`.
    pub fn grown(&self, r: f64, eps: f64) -> Option<GrownEdge> {
        match self {
            Edge::Line { a, b } => {
                let u = (b - a).normalize();
                let normal = V2::new(u.y, -u.x);
                Some(GrownEdge::Line {
                    a: a + normal * r,
                    b: b + normal * r,
                    normal,
                })
            }
            Edge::Arc(arc) => arc.grown(r, eps).map(GrownEdge::Arc),
        }
    }
}

/// SPEC 8.2's smooth-joint test for the unit tangents of the edge arriving
/// at a vertex and the edge leaving it (the caller checks that one of the
/// two is an arc).
pub fn tangents_smooth(t_in: V2, t_out: V2) -> bool {
    cross(t_in, t_out).abs() <= SMOOTH_JOINT_TOL && t_in.dot(&t_out) > 0.0
}

/// The edges of a vertex list, edge `i` from vertex `i` to `i + 1 (mod n)`.
pub fn edges_of(vertices: &[Vertex]) -> Vec<Edge> {
    let n = vertices.len();
    (0..n)
        .map(|i| {
            let v = vertices[i];
            Edge::new(v.point(), vertices[(i + 1) % n].point(), v.bulge)
        })
        .collect()
}

/// SPEC 8.1's normalisation of a clockwise list: `(v0, v(n-1), ..., v1)`,
/// every edge reversed, so each bulge changes sign and moves with its edge
/// (`v0` gets `-b(n-1)`, `v(n-k)` gets `-b(n-k-1)`). It is its own inverse.
pub fn ccw_of_cw_outline(vertices: &[Vertex]) -> Vec<Vertex> {
    let n = vertices.len();
    (0..n)
        .map(|k| {
            let p = vertices[(n - k) % n];
            let b = vertices[(2 * n - k - 1) % n].bulge;
            Vertex::new(p.x, p.y, if b == 0.0 { 0.0 } else { -b })
        })
        .collect()
}

/// Even-odd location in one loop: its vertex polygon, toggled by every
/// arc's circular segment.
pub(super) fn loop_contains(p: V2, points: &[V2], edges: &[Edge]) -> bool {
    let mut inside = point_in_polygon(p, points);
    for e in edges {
        if let Edge::Arc(arc) = e {
            inside ^= arc.segment_contains(p);
        }
    }
    inside
}
