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
//!
//! A part with holes (SPEC 9) is the same type: the outline's loop and
//! every hole's, clockwise, one after the other in the edge list, so each
//! stage asks the part region what it asked the outline. Without holes
//! every answer is computed as before, bit for bit.

mod clearance;
mod edge;
mod holes;
mod mass;
mod validate;
mod vertex;

#[cfg(test)]
mod tests;

use edge::loop_contains;
pub use edge::{ccw_of_cw_outline, edges_of, tangents_smooth, Edge, GrownEdge};
pub use holes::{validate_holes, HoleError};
pub use mass::{mass_properties, MassProperties};
pub use validate::{validate_outline, OutlineError};
pub use vertex::Vertex;

use crate::geometry::arc::{CircArc, Closest};
use crate::geometry::{Aabb, V2};
use std::ops::Range;

/// A validated outline, counter-clockwise, with its edges, and the part's
/// holes (SPEC 9), clockwise, whose edges follow the outline's.
#[derive(Debug, Clone, PartialEq)]
pub struct Outline {
    vertices: Vec<Vertex>,
    /// Every loop's edges: the outline's, then hole 0's, hole 1's...
    /// (SPEC 9.2's numbering).
    edges: Vec<Edge>,
    /// The vertex positions, kept because point location runs in the
    /// clearance tests of every candidate fixture.
    points: Vec<V2>,
    /// The box of every edge, in edge order: the segment code asks which
    /// edges come near a grown edge once per edge.
    boxes: Vec<Aabb>,
    /// Whether an edge of the outline is an arc.
    has_arcs: bool,
    /// The holes, clockwise (SPEC 9.2).
    holes: Vec<Hole>,
    /// The holes by the left side of their boxes, and the widest box:
    /// a clamp polygon's clearance looks only at the holes whose boxes
    /// can come near its own.
    by_left: HoleIndex,
}

/// Holes ordered by `aabb.min.x`, for a sweep over an x range.
#[derive(Debug, Clone, PartialEq, Default)]
struct HoleIndex {
    /// Hole numbers, by increasing `aabb.min.x`.
    order: Vec<usize>,
    /// Their `aabb.min.x`, in that order.
    left: Vec<f64>,
    /// The largest box width.
    widest: f64,
}

impl HoleIndex {
    fn of(holes: &[Hole]) -> HoleIndex {
        let mut order: Vec<usize> = (0..holes.len()).collect();
        order.sort_by(|&a, &b| holes[a].aabb.min.x.total_cmp(&holes[b].aabb.min.x));
        HoleIndex {
            left: order.iter().map(|&k| holes[k].aabb.min.x).collect(),
            widest: holes
                .iter()
                .fold(0.0, |w, h| f64::max(w, h.aabb.max.x - h.aabb.min.x)),
            order,
        }
    }
}

/// A hole of the part region: its clockwise loop, where its edges sit in
/// the region's edge list, and its box (most clearance and point location
/// tests are decided by the box alone when a part has many small holes).
#[derive(Debug, Clone, PartialEq)]
struct Hole {
    vertices: Vec<Vertex>,
    points: Vec<V2>,
    edges: Range<usize>,
    aabb: Aabb,
}

impl Outline {
    /// Validates `vertices` (SPEC 8.1) and normalises them to
    /// counter-clockwise.
    pub fn new(vertices: &[Vertex]) -> Result<Outline, OutlineError> {
        Ok(Outline::from_ccw(validate_outline(vertices)?))
    }

    /// The part region of this outline with `holes`, each already
    /// validated against it ([`validate_holes`]) and clockwise.
    pub fn with_holes(mut self, holes: Vec<Vec<Vertex>>) -> Outline {
        self.holes.clear();
        self.edges.truncate(self.vertices.len());
        self.boxes.truncate(self.vertices.len());
        for vertices in holes {
            let start = self.edges.len();
            self.edges.extend(edges_of(&vertices));
            let edges = start..self.edges.len();
            self.boxes
                .extend(self.edges[edges.clone()].iter().map(Edge::aabb));
            let aabb = union_of(&self.boxes[edges.clone()]);
            let points = vertices.iter().map(Vertex::point).collect();
            self.holes.push(Hole {
                vertices,
                points,
                edges,
                aabb,
            });
        }
        self.by_left = HoleIndex::of(&self.holes);
        self
    }

    /// The outline of vertices already validated and counter-clockwise.
    fn from_ccw(vertices: Vec<Vertex>) -> Outline {
        let edges = edges_of(&vertices);
        let points = vertices.iter().map(Vertex::point).collect();
        let has_arcs = edges.iter().any(Edge::is_arc);
        let boxes = edges.iter().map(Edge::aabb).collect();
        Outline {
            vertices,
            boxes,
            edges,
            points,
            has_arcs,
            holes: Vec::new(),
            by_left: HoleIndex::default(),
        }
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

    /// The edges of every loop, numbered as SPEC 9.2 says: the outline's
    /// (edge `i` leaving vertex `i`), then each hole's in its clockwise
    /// order.
    pub fn edges(&self) -> &[Edge] {
        &self.edges
    }

    /// The box of every edge of [`Self::edges`].
    pub fn edge_boxes(&self) -> &[Aabb] {
        &self.boxes
    }

    /// The outline's own edges (the first ones of [`Self::edges`]).
    pub fn outline_edges(&self) -> &[Edge] {
        &self.edges[..self.vertices.len()]
    }

    /// The holes' clockwise vertices, in input order.
    pub fn holes(&self) -> impl ExactSizeIterator<Item = &[Vertex]> + '_ {
        self.holes.iter().map(|h| h.vertices.as_slice())
    }

    /// Whether the part has holes.
    pub fn has_holes(&self) -> bool {
        !self.holes.is_empty()
    }

    /// The edges of every loop: the outline's, then each hole's in input
    /// order (SPEC 9.2's numbering).
    pub fn loop_edges(&self) -> impl Iterator<Item = Range<usize>> + '_ {
        std::iter::once(0..self.vertices.len()).chain(self.holes.iter().map(|h| h.edges.clone()))
    }

    /// Pushes onto `out`, in edge order, every edge but `skip` whose box
    /// comes within `reach` of `near`: the outline's edges one by one, a
    /// hole's only when the hole's box does, so that a part's many small
    /// holes cost a box test each. Any edge that has a point within
    /// `reach` of a point in `near` is listed.
    pub fn edges_near(&self, near: &Aabb, reach: f64, skip: usize, out: &mut Vec<usize>) {
        out.clear();
        let mut consider = |range: Range<usize>| {
            for j in range {
                if j != skip && self.boxes[j].gap(near) <= reach {
                    out.push(j);
                }
            }
        };
        consider(0..self.vertices.len());
        for h in &self.holes {
            if h.aabb.gap(near) <= reach {
                consider(h.edges.clone());
            }
        }
    }

    /// The loop edge `i` belongs to: 0 for the outline, `k + 1` for hole
    /// `k` (SPEC 9.6's `segment_loops`).
    pub fn loop_of_edge(&self, i: usize) -> usize {
        // Holes follow one another in the edge list: the loop is the
        // number of holes starting at or before `i`.
        self.holes.partition_point(|h| h.edges.start <= i)
    }

    /// The edges of the loop that edge `i` belongs to.
    fn loop_edges_of(&self, i: usize) -> Range<usize> {
        match self.loop_of_edge(i) {
            0 => 0..self.vertices.len(),
            k => self.holes[k - 1].edges.clone(),
        }
    }

    /// The edge after edge `i` in its loop: its end is that edge's start.
    pub fn next_in_loop(&self, i: usize) -> usize {
        let range = self.loop_edges_of(i);
        if i + 1 == range.end {
            range.start
        } else {
            i + 1
        }
    }

    /// The edge before edge `i` in its loop.
    fn previous_in_loop(&self, i: usize) -> usize {
        let range = self.loop_edges_of(i);
        if i == range.start {
            range.end - 1
        } else {
            i - 1
        }
    }

    /// Whether the part is a plain polygon: no arc, no hole. Stages take
    /// their polygon code, the code fixplan had before arcs, for it.
    pub fn is_polygon(&self) -> bool {
        !self.has_arcs && self.holes.is_empty()
    }

    /// The vertex positions: the polygon itself when there are no arcs.
    pub fn points(&self) -> &[V2] {
        &self.points
    }

    /// Whether any edge of the outline is an arc.
    pub fn has_arcs(&self) -> bool {
        self.has_arcs
    }

    /// Area, centroid and polar moment of the true region (SPEC 6, 8.1),
    /// holes removed (SPEC 9.5).
    pub fn mass_properties(&self) -> MassProperties {
        let outline = mass_properties(&self.vertices);
        if self.holes.is_empty() {
            return outline;
        }
        let loops: Vec<MassProperties> = std::iter::once(outline)
            .chain(self.holes.iter().map(|h| mass_properties(&h.vertices)))
            .collect();
        mass::combined(&loops)
    }

    /// Even-odd point location in the true region, outside every hole
    /// (boundary points may go either way; combine with
    /// [`Outline::boundary_distance`] where the boundary matters).
    pub fn contains(&self, p: V2) -> bool {
        let inside = loop_contains(p, &self.points, self.outline_edges());
        inside
            && !self.holes.iter().any(|h| {
                let b = &h.aabb;
                p.x >= b.min.x
                    && p.x <= b.max.x
                    && p.y >= b.min.y
                    && p.y <= b.max.y
                    && loop_contains(p, &h.points, &self.edges[h.edges.clone()])
            })
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

    /// Whether the start of edge `i` is a smooth joint (SPEC 8.2): the
    /// edges meeting there (the one before in the same loop, SPEC 9.3) are
    /// tangent, pointing on, and at least one is an arc.
    pub fn smooth_joint(&self, i: usize) -> bool {
        let (e_in, e_out) = (&self.edges[self.previous_in_loop(i)], &self.edges[i]);
        (e_in.is_arc() || e_out.is_arc())
            && tangents_smooth(e_in.tangent_end(), e_out.tangent_start())
    }

    /// A polygon through every vertex of the outline whose chords stay
    /// within `chord_error` of the arcs (at most 2^20 chords per arc), for
    /// drawings and for checking the exact functions against polygons.
    pub fn flatten(&self, chord_error: f64) -> Vec<V2> {
        flatten_edges(self.outline_edges(), chord_error)
    }

    /// [`Self::flatten`] of hole `k`'s clockwise loop.
    pub fn flatten_hole(&self, k: usize, chord_error: f64) -> Vec<V2> {
        flatten_edges(&self.edges[self.holes[k].edges.clone()], chord_error)
    }
}

/// The box around `boxes` (a loop's edges').
fn union_of(boxes: &[Aabb]) -> Aabb {
    let mut b = Aabb::of(&[]);
    for eb in boxes {
        b.min = b.min.inf(&eb.min);
        b.max = b.max.sup(&eb.max);
    }
    b
}

/// The polygon of [`Outline::flatten`] for one loop's edges.
fn flatten_edges(edges: &[Edge], chord_error: f64) -> Vec<V2> {
    let mut out = Vec::new();
    for e in edges {
        out.push(e.start());
        if let Edge::Arc(arc) = e {
            let k = arc_pieces(arc, chord_error);
            out.extend((1..k).map(|i| arc.point_at(i as f64 / k as f64)));
        }
    }
    out
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
