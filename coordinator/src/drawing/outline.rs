//! Part outlines of lines and circular arcs (SPEC 8.1) as the views draw
//! them: vertex positions, the bounding box with the arcs' extents, rigid
//! motions, and line strips fine enough for viewers without an arc
//! primitive.
//!
//! Everything here reads the outline as it is listed, without validating
//! or normalising it: an invalid part's picture shows what was read. For an
//! outline without arcs each function gives exactly the vertex positions,
//! so polygon pictures and scenes keep their bytes.

use fixplan_core::parts::{edges_of, Edge};
use fixplan_core::{Point, Vertex};

/// Whether any edge of `outline` is drawn as an arc (a bulge on a
/// zero-length or non-finite chord is drawn as a straight edge, as core
/// builds it).
pub fn has_arcs(outline: &[Vertex]) -> bool {
    edges_of(outline).iter().any(Edge::is_arc)
}

/// The vertex positions (the polygon itself when there are no arcs).
pub fn vertex_points(outline: &[Vertex]) -> Vec<Point> {
    outline.iter().map(|v| [v.x, v.y]).collect()
}

/// The outline moved by `motion`, a rotation and translation: positions
/// move, bulges stay (a rigid motion without reflection keeps each arc's
/// included angle and turning sense).
pub fn moved(outline: &[Vertex], motion: impl Fn(&Point) -> Point) -> Vec<Vertex> {
    outline
        .iter()
        .map(|v| {
            let p = motion(&[v.x, v.y]);
            Vertex::new(p[0], p[1], v.bulge)
        })
        .collect()
}

/// Points whose bounding box is the outline's: the vertices, then for each
/// arc the corners of its own box (its circle's extreme points in the
/// span).
pub fn extent_points(outline: &[Vertex]) -> Vec<Point> {
    let mut pts = vertex_points(outline);
    for e in edges_of(outline) {
        if let Edge::Arc(arc) = e {
            let b = arc.aabb();
            pts.push([b.min.x, b.min.y]);
            pts.push([b.max.x, b.max.y]);
        }
    }
    pts
}

/// Largest turn of one chord of a flattened arc: 5 degrees keeps a circle
/// round at any zoom (72 chords) and each chord within `1e-3 R` of it.
pub const MAX_CHORD_TURN: f64 = 5.0 * std::f64::consts::PI / 180.0;

/// A closed line strip (the first point not repeated) through every vertex,
/// each arc cut into chords that turn at most [`MAX_CHORD_TURN`] and stay
/// within `chord_error` of it.
pub fn flattened(outline: &[Vertex], chord_error: f64) -> Vec<Point> {
    let mut out = Vec::with_capacity(outline.len());
    for e in edges_of(outline) {
        let a = e.start();
        out.push([a.x, a.y]);
        if let Edge::Arc(arc) = e {
            let by_error = 2.0 * (1.0 - chord_error / arc.radius).clamp(-1.0, 1.0).acos();
            let turn = if by_error > 0.0 {
                by_error.min(MAX_CHORD_TURN)
            } else {
                MAX_CHORD_TURN
            };
            // At most 4096 chords an arc, whatever the numbers say.
            let k = (arc.sweep.abs() / turn).ceil().clamp(1.0, 4096.0) as usize;
            out.extend((1..k).map(|i| {
                let p = arc.point_at(i as f64 / k as f64);
                [p.x, p.y]
            }));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plate() -> Vec<Vertex> {
        vec![
            Vertex::new(0.0, 0.0, 0.0),
            Vertex::new(60.0, 0.0, 1.0),
            Vertex::new(60.0, 40.0, 0.0),
            Vertex::new(0.0, 40.0, 0.0),
        ]
    }

    #[test]
    fn polygons_are_their_vertices() {
        let sq: Vec<Vertex> = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0]]
            .into_iter()
            .map(Vertex::from)
            .collect();
        assert!(!has_arcs(&sq));
        assert_eq!(flattened(&sq, 1e-3), vertex_points(&sq));
        assert_eq!(extent_points(&sq), vertex_points(&sq));
    }

    #[test]
    fn arcs_extend_the_box_and_flatten_onto_their_circle() {
        let p = plate();
        assert!(has_arcs(&p));
        let right = extent_points(&p).iter().map(|q| q[0]).fold(0.0, f64::max);
        assert!((right - 80.0).abs() < 1e-9, "{right}");
        let strip = flattened(&p, 0.06);
        // 180 degrees, at most 5 degrees a chord: 36 chords (37 if rounding
        // puts the sweep a hair over), all inner points on the circle.
        let inner = strip.len() - 4;
        assert!(inner == 35 || inner == 36, "{}", strip.len());
        assert_eq!(strip[1], [60.0, 0.0]);
        assert_eq!(strip[2 + inner], [60.0, 40.0]);
        for q in &strip[2..2 + inner] {
            let r = ((q[0] - 60.0).powi(2) + (q[1] - 20.0).powi(2)).sqrt();
            assert!((r - 20.0).abs() < 1e-9 && q[0] > 60.0, "{q:?}");
        }
    }

    #[test]
    fn moving_keeps_bulges() {
        let m = moved(&plate(), |p| [-p[1] + 5.0, p[0]]);
        assert_eq!(m[1], Vertex::new(5.0, 60.0, 1.0));
        assert_eq!(m[0].bulge, 0.0);
    }
}
