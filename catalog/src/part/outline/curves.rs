//! Numbers for messages, and circular arcs as the readers make them:
//! exact bulge vertices, or chords within a tolerance.

use fixplan_core::Vertex;

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
pub(crate) fn scale_of(points: &[P]) -> f64 {
    points
        .iter()
        .fold(0.0f64, |m, q| m.max(q[0].abs()).max(q[1].abs()))
}

/// How many chords keep a circular arc of radius `radius` and sweep `sweep`
/// (radians, any sign) within `tol` of the true curve.
pub(crate) fn arc_pieces(radius: f64, sweep: f64, tol: f64) -> usize {
    let radius = radius.abs();
    let sweep = sweep.abs();
    if !(radius.is_finite() && sweep.is_finite() && tol.is_finite())
        || radius == 0.0
        || sweep == 0.0
    {
        return 1;
    }
    // Sagitta of a chord spanning angle a is r (1 - cos(a/2)).
    let step = if tol >= radius {
        std::f64::consts::PI
    } else {
        2.0 * (1.0 - tol / radius).acos()
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
pub(crate) fn arc_points(
    centre: P,
    radius: f64,
    a0: f64,
    sweep: f64,
    tol: f64,
    min: usize,
) -> Vec<P> {
    let n = arc_pieces(radius, sweep, tol).max(min).min(MAX_ARC_PIECES);
    (1..=n)
        .map(|k| {
            let a = a0 + sweep * k as f64 / n as f64;
            [centre[0] + radius * a.cos(), centre[1] + radius * a.sin()]
        })
        .collect()
}

/// A full circle as a closed loop (at least 3 vertices, so that a tiny
/// circle still reaches validation and is reported by size, not shape).
pub(crate) fn circle_loop(centre: P, radius: f64, tol: f64) -> Vec<P> {
    let mut pts = arc_points(centre, radius, 0.0, std::f64::consts::TAU, tol, 3);
    pts.pop();
    pts.insert(0, [centre[0] + radius, centre[1]]);
    pts
}

/// Vertices with straight edges.
pub(crate) fn straight(pts: Vec<P>) -> Vec<Vertex> {
    pts.into_iter().map(Vertex::from).collect()
}

/// The positions of vertices, dropping bulges (for access constraints,
/// which are polygons and are always flattened before this).
pub(crate) fn positions(vertices: &[Vertex]) -> Vec<P> {
    vertices.iter().map(|q| [q.x, q.y]).collect()
}

/// An exact circular arc of centre `centre` and radius `radius` from angle `a0`
/// sweeping `sweep` radians (CCW when positive), both ends included, the
/// end with bulge 0: one bulge vertex, or two half arcs for a full turn
/// (a bulge of `tan(pi / 2)` is no number).
pub(crate) fn exact_arc(centre: P, radius: f64, a0: f64, sweep: f64) -> Vec<Vertex> {
    let at = |a: f64| {
        Vertex::new(
            centre[0] + radius * a.cos(),
            centre[1] + radius * a.sin(),
            0.0,
        )
    };
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
pub(crate) fn exact_circle(centre: P, radius: f64) -> Vec<Vertex> {
    vec![
        Vertex::new(centre[0] + radius, centre[1], 1.0),
        Vertex::new(centre[0] - radius, centre[1], 1.0),
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
