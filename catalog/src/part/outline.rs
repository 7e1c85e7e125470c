//! What the drawing readers share: exact arcs as bulge vertices, curve
//! flattening, joining pieces into loops (arcs kept), choosing the outline
//! among the loops, and numbers for messages. Points are plain `[f64; 2]`
//! as files hold them; outlines are core's [`Vertex`] lists (a point and
//! the bulge of the edge leaving it); areas and point location come from
//! `fixplan_core` so that the true region, arcs included, decides.

use super::raw::RawPart;
use fixplan_core::geometry::{point_in_polygon, signed_area, v2, V2};
use fixplan_core::outline::{edges_of, mass_properties, Edge, Vertex};
use fixplan_core::Units;

pub(crate) type P = [f64; 2];

/// No curve is cut into more pieces than this, whatever the tolerance: a
/// tiny tolerance on a huge radius (or a hostile file) must not exhaust
/// memory, and a coarser outline is still a valid outline.
pub(crate) const MAX_ARC_PIECES: usize = 1024;

/// Numbers in messages: at most six decimals, no trailing zeros, so that
/// "(12.5, 3)" reads like the user's drawing rather than like a float dump.
pub(crate) fn fmt(x: f64) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    let r = (x * 1e6).round() / 1e6;
    let r = if r == 0.0 { 0.0 } else { r };
    format!("{r}")
}

pub(crate) fn fmt_pt(p: P) -> String {
    format!("({}, {})", fmt(p[0]), fmt(p[1]))
}

pub(crate) fn dist(a: P, b: P) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Largest absolute coordinate, the scale for relative tolerances.
pub(crate) fn scale_of(p: &[P]) -> f64 {
    p.iter()
        .fold(0.0f64, |m, q| m.max(q[0].abs()).max(q[1].abs()))
}

/// How many chords keep a circular arc of radius `r` and sweep `sweep`
/// (radians, any sign) within `tol` of the true curve.
pub(crate) fn arc_pieces(r: f64, sweep: f64, tol: f64) -> usize {
    let r = r.abs();
    let sweep = sweep.abs();
    if !(r.is_finite() && sweep.is_finite() && tol.is_finite()) || r == 0.0 || sweep == 0.0 {
        return 1;
    }
    // Sagitta of a chord spanning angle a is r (1 - cos(a/2)).
    let step = if tol >= r {
        std::f64::consts::PI
    } else {
        2.0 * (1.0 - tol / r).acos()
    };
    let n = if step > 0.0 {
        (sweep / step).ceil()
    } else {
        f64::INFINITY
    };
    if n.is_finite() {
        (n as usize).clamp(1, MAX_ARC_PIECES)
    } else {
        MAX_ARC_PIECES
    }
}

/// Points of a circular arc from angle `a0` sweeping `sweep` radians (CCW
/// when positive), start excluded, end included.
pub(crate) fn arc_points(c: P, r: f64, a0: f64, sweep: f64, tol: f64, min: usize) -> Vec<P> {
    let n = arc_pieces(r, sweep, tol).max(min).min(MAX_ARC_PIECES);
    (1..=n)
        .map(|k| {
            let a = a0 + sweep * k as f64 / n as f64;
            [c[0] + r * a.cos(), c[1] + r * a.sin()]
        })
        .collect()
}

/// A full circle as a closed loop (at least 3 vertices, so that a tiny
/// circle still reaches validation and is reported by size, not shape).
pub(crate) fn circle_loop(c: P, r: f64, tol: f64) -> Vec<P> {
    let mut pts = arc_points(c, r, 0.0, std::f64::consts::TAU, tol, 3);
    pts.pop();
    pts.insert(0, [c[0] + r, c[1]]);
    pts
}

/// Vertices with straight edges.
pub(crate) fn straight(pts: Vec<P>) -> Vec<Vertex> {
    pts.into_iter().map(Vertex::from).collect()
}

/// The positions of vertices, dropping bulges (for access constraints,
/// which are polygons and are always flattened before this).
pub(crate) fn positions(v: &[Vertex]) -> Vec<P> {
    v.iter().map(|q| [q.x, q.y]).collect()
}

/// An exact circular arc of centre `c` and radius `r` from angle `a0`
/// sweeping `sweep` radians (CCW when positive), both ends included, the
/// end with bulge 0: one bulge vertex, or two half arcs for a full turn
/// (a bulge of `tan(pi / 2)` is no number).
pub(crate) fn exact_arc(c: P, r: f64, a0: f64, sweep: f64) -> Vec<Vertex> {
    let at = |a: f64| Vertex::new(c[0] + r * a.cos(), c[1] + r * a.sin(), 0.0);
    let pieces = if sweep.abs() >= std::f64::consts::TAU - 1e-9 {
        2
    } else {
        1
    };
    let bulge = (sweep / pieces as f64 / 4.0).tan();
    let mut v: Vec<Vertex> = (0..pieces)
        .map(|k| Vertex {
            bulge,
            ..at(a0 + sweep * k as f64 / pieces as f64)
        })
        .collect();
    v.push(at(a0 + sweep));
    v
}

/// A full circle as a closed loop of two half arcs (bulge 1 on both
/// vertices, SPEC 8.1), starting at angle 0.
pub(crate) fn exact_circle(c: P, r: f64) -> Vec<Vertex> {
    vec![
        Vertex::new(c[0] + r, c[1], 1.0),
        Vertex::new(c[0] - r, c[1], 1.0),
    ]
}

/// Interior points of a DXF bulge edge from `p` to `q` (bulge = tan of a
/// quarter of the included angle, positive CCW), endpoints excluded.
pub(crate) fn bulge_points(p: P, q: P, bulge: f64, tol: f64) -> Vec<P> {
    if !bulge.is_finite() || bulge.abs() < 1e-12 {
        return Vec::new();
    }
    let chord = [q[0] - p[0], q[1] - p[1]];
    let c = chord[0].hypot(chord[1]);
    if c == 0.0 || !c.is_finite() {
        return Vec::new();
    }
    let theta = 4.0 * bulge.atan();
    // The centre sits on the chord's bisector, (1 - b^2) / (4 b) chord
    // lengths to the left of p -> q.
    let k = (1.0 - bulge * bulge) / (4.0 * bulge);
    let center = [
        (p[0] + q[0]) / 2.0 - chord[1] * k,
        (p[1] + q[1]) / 2.0 + chord[0] * k,
    ];
    let r = dist(center, p);
    let a0 = (p[1] - center[1]).atan2(p[0] - center[0]);
    let mut pts = arc_points(center, r, a0, theta, tol, 1);
    pts.pop();
    pts
}

/// Vertices with bulges flattened into chords within `tol`; `closed` adds
/// the closing edge's arc. What the DXF reader always did with polyline
/// bulges, so `arcs = "flatten"` gives the polygons of before.
pub(crate) fn flatten_vertices(verts: &[Vertex], closed: bool, tol: f64) -> Vec<Vertex> {
    let mut pts = Vec::with_capacity(verts.len());
    let n = verts.len();
    for i in 0..n {
        let v = verts[i];
        let p = [v.x, v.y];
        pts.push(p);
        if i + 1 < n {
            pts.extend(bulge_points(
                p,
                [verts[i + 1].x, verts[i + 1].y],
                v.bulge,
                tol,
            ));
        } else if closed && n > 1 {
            pts.extend(bulge_points(p, [verts[0].x, verts[0].y], v.bulge, tol));
        }
    }
    straight(pts)
}

/// A piece read backwards: the points reversed, each bulge negated and
/// moved with its edge (the edge `v(k) -> v(k+1)` becomes `v(k+1) -> v(k)`),
/// the new last vertex (an open end) straight.
pub(crate) fn reversed(v: &[Vertex]) -> Vec<Vertex> {
    let n = v.len();
    (0..n)
        .map(|k| {
            let p = v[n - 1 - k];
            let b = if k + 1 < n { -v[n - 2 - k].bulge } else { 0.0 };
            Vertex::new(p.x, p.y, if b == 0.0 { 0.0 } else { b })
        })
        .collect()
}

/// An open piece of a drawing (a LINE, an ARC, an open polyline) waiting to
/// be joined, with a label for error messages. The last vertex's bulge is
/// not an edge and is kept 0.
#[derive(Debug, Clone)]
pub(crate) struct Piece {
    pub pts: Vec<Vertex>,
    pub label: String,
}

fn pt(v: Vertex) -> P {
    [v.x, v.y]
}

/// A chain that could not be closed.
#[derive(Debug, Clone)]
pub(crate) struct OpenChain {
    pub labels: Vec<String>,
    pub start: P,
    pub end: P,
}

/// Joins pieces end to end (either direction, nearest free end within
/// `tol`) into closed loops, arcs kept: a piece joined backwards is
/// [`reversed`]. Returned loops do not repeat their first point.
pub(crate) fn join_pieces(pieces: Vec<Piece>, tol: f64) -> (Vec<Vec<Vertex>>, Vec<OpenChain>) {
    let mut used = vec![false; pieces.len()];
    let mut loops = Vec::new();
    let mut open = Vec::new();
    for i in 0..pieces.len() {
        if used[i] || pieces[i].pts.is_empty() {
            continue;
        }
        used[i] = true;
        let mut chain = pieces[i].pts.clone();
        let mut labels = vec![pieces[i].label.clone()];
        loop {
            let first = pt(chain[0]);
            let last = pt(chain[chain.len() - 1]);
            if chain.len() > 2 && dist(first, last) <= tol {
                chain.pop();
                loops.push(chain);
                break;
            }
            // Nearest free end to our last point, then to our first.
            let mut best: Option<(f64, usize, bool, bool)> = None;
            for (j, pc) in pieces.iter().enumerate() {
                if used[j] || pc.pts.is_empty() {
                    continue;
                }
                let (s, e) = (pt(pc.pts[0]), pt(pc.pts[pc.pts.len() - 1]));
                for (d, at_end, rev) in [
                    (dist(last, s), true, false),
                    (dist(last, e), true, true),
                    (dist(first, e), false, false),
                    (dist(first, s), false, true),
                ] {
                    if d <= tol && best.is_none_or(|b| d < b.0) {
                        best = Some((d, j, at_end, rev));
                    }
                }
            }
            match best {
                Some((_, j, at_end, rev)) => {
                    used[j] = true;
                    labels.push(pieces[j].label.clone());
                    let mut pts = if rev {
                        reversed(&pieces[j].pts)
                    } else {
                        pieces[j].pts.clone()
                    };
                    if at_end {
                        // The joint keeps the chain's point and takes the
                        // bulge of the piece's first edge.
                        let k = chain.len() - 1;
                        chain[k].bulge = pts[0].bulge;
                        chain.extend_from_slice(&pts[1..]);
                    } else {
                        pts.pop();
                        pts.extend_from_slice(&chain);
                        chain = pts;
                    }
                }
                None => {
                    open.push(OpenChain {
                        labels,
                        start: pt(chain[0]),
                        end: pt(chain[chain.len() - 1]),
                    });
                    break;
                }
            }
        }
    }
    (loops, open)
}

/// Unsigned area of the true region (arcs included: a circle is two
/// vertices) for choosing the largest loop; an overflowing loop counts as
/// the largest rather than as NaN, so the choice stays total.
fn loop_area(p: &[Vertex]) -> f64 {
    let a = if p.iter().any(Vertex::is_arc) {
        mass_properties(p).area.abs()
    } else {
        signed_area(&p.iter().map(Vertex::point).collect::<Vec<_>>()).abs()
    };
    if a.is_finite() {
        a
    } else {
        f64::INFINITY
    }
}

/// Even-odd test of `q` against the true region of `outline` (the polygon
/// of its vertices toggled by each arc's circular segment), enough to tell
/// a hole from a second outline; an empty loop contains nothing (core's
/// test needs a vertex).
fn inside(q: Vertex, outline: &[Vertex]) -> bool {
    if outline.is_empty() {
        return false;
    }
    let p = v2(q.x, q.y);
    let poly: Vec<V2> = outline.iter().map(Vertex::point).collect();
    let mut inside = point_in_polygon(p, &poly);
    for e in edges_of(outline) {
        if let Edge::Arc(arc) = e {
            inside ^= arc.segment_contains(p);
        }
    }
    inside
}

/// Why the loops of a drawing do not make one part.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OutlineError {
    /// No closed loop at all, or only access loops: nothing to hold.
    #[error("no closed loop: {}", if *.only_access { "only access/keepout loops, no part outline" } else { "the file has no closed outline" })]
    NoClosedLoop {
        /// The drawing has access/keepout loops, just no outline.
        only_access: bool,
    },
    /// A loop outside the largest one: two parts in one file, and which one
    /// is meant cannot be guessed.
    #[error("more than one outline: {label} near {} {} lies outside the largest loop; put one part per file", fmt_pt(*.near), .units.label())]
    MoreThanOne {
        /// The other loop, as the reader names it.
        label: String,
        /// Its first point, catalogue units.
        near: [f64; 2],
        /// The catalogue's units.
        units: Units,
    },
}

/// The largest loop is the part; smaller loops inside it are features the
/// planar method does not use; loops outside it mean the file holds more
/// than one part, which is ambiguous.
pub(crate) fn pick_outline(
    mut loops: Vec<(Vec<Vertex>, String)>,
    access: Vec<Vec<P>>,
    mut warnings: Vec<String>,
    units: Units,
) -> Result<RawPart, OutlineError> {
    if loops.is_empty() {
        return Err(OutlineError::NoClosedLoop {
            only_access: !access.is_empty(),
        });
    }
    let unit = units.label();
    let areas: Vec<f64> = loops.iter().map(|(l, _)| loop_area(l)).collect();
    let outer_i = (0..loops.len())
        .max_by(|&i, &j| areas[i].total_cmp(&areas[j]))
        .unwrap_or(0);
    let outer = &loops[outer_i].0;
    for (i, (l, label)) in loops.iter().enumerate() {
        if i == outer_i || l.is_empty() {
            continue;
        }
        if inside(l[0], outer) {
            warnings.push(format!(
                "{label} near {} {unit} is a loop inside the outline (a hole or pocket); ignored: fixtures hold the outer outline only",
                fmt_pt(pt(l[0]))
            ));
        } else {
            return Err(OutlineError::MoreThanOne {
                label: label.clone(),
                near: pt(l[0]),
                units,
            });
        }
    }
    let outer = loops.swap_remove(outer_i).0;
    Ok(RawPart {
        outline: outer,
        access,
        warnings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chord_error_is_respected() {
        let tol = 0.05;
        let pts = circle_loop([0.0, 0.0], 30.0, tol);
        let n = pts.len();
        for i in 0..n {
            let (a, b) = (pts[i], pts[(i + 1) % n]);
            let m = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
            assert!(30.0 - dist(m, [0.0, 0.0]) <= tol + 1e-9);
        }
    }

    #[test]
    fn pieces_join_in_any_direction() {
        let pc = |a: P, b: P| Piece {
            pts: straight(vec![a, b]),
            label: "LINE".into(),
        };
        let (loops, open) = join_pieces(
            vec![
                pc([0.0, 0.0], [1.0, 0.0]),
                pc([1.0, 1.0], [1.0, 0.0]),
                pc([0.0, 1.0], [0.0, 0.0]),
                pc([1.0, 1.0], [0.0, 1.0]),
            ],
            1e-6,
        );
        assert!(open.is_empty());
        assert_eq!(loops.len(), 1);
        assert_eq!(loops[0].len(), 4);
        assert!((loop_area(&loops[0]) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn bulge_one_is_a_half_circle() {
        let pts = bulge_points([1.0, 0.0], [-1.0, 0.0], 1.0, 0.01);
        assert!(!pts.is_empty());
        for p in &pts {
            assert!((dist(*p, [0.0, 0.0]) - 1.0).abs() < 1e-12);
            assert!(p[1] > 0.0, "CCW from (1,0) to (-1,0) passes above");
        }
    }

    #[test]
    fn reversed_pieces_keep_their_arcs() {
        // A half circle from (1, 0) over the top to (-1, 0), then a line back;
        // the arc drawn backwards (clockwise from (-1, 0)) must give the
        // same loop.
        let arc = exact_arc([0.0, 0.0], 1.0, 0.0, std::f64::consts::PI);
        assert_eq!(arc.len(), 2);
        assert!((arc[0].bulge - 1.0).abs() < 1e-15);
        let back = reversed(&arc);
        assert!((back[0].bulge + 1.0).abs() < 1e-15 && back[1].bulge == 0.0);
        let line = Piece {
            pts: straight(vec![[-1.0, 0.0], [1.0, 0.0]]),
            label: "LINE".into(),
        };
        let (loops, open) = join_pieces(
            vec![
                line,
                Piece {
                    pts: back,
                    label: "ARC".into(),
                },
            ],
            1e-9,
        );
        assert!(open.is_empty());
        let area = loop_area(&loops[0]);
        assert!((area - std::f64::consts::FRAC_PI_2).abs() < 1e-12, "{area}");
        assert!(inside(Vertex::new(0.0, 0.5, 0.0), &loops[0]));
        assert!(!inside(Vertex::new(0.0, -0.5, 0.0), &loops[0]));
    }

    #[test]
    fn full_turns_are_two_half_arcs() {
        let c = exact_arc([0.0, 0.0], 2.0, 0.0, std::f64::consts::TAU);
        assert_eq!(c.len(), 3);
        assert!((c[0].bulge - 1.0).abs() < 1e-12 && (c[1].bulge - 1.0).abs() < 1e-12);
        let area = loop_area(&exact_circle([0.0, 0.0], 2.0));
        assert!((area - 4.0 * std::f64::consts::PI).abs() < 1e-12);
    }
}
