//! Curve flattening, loop joining and the small polygon helpers the readers
//! share. Everything here works on plain `[f64; 2]` points because that is
//! what files hold and what [`fixplan_core::Part`] stores.

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

/// Shoelace area, positive for counter-clockwise.
pub(crate) fn signed_area(p: &[P]) -> f64 {
    let n = p.len();
    let mut s = 0.0;
    for i in 0..n {
        let a = p[i];
        let b = p[(i + 1) % n];
        s += a[0] * b[1] - a[1] * b[0];
    }
    s / 2.0
}

/// Even-odd point-in-polygon test; good enough to tell a hole from a second
/// outline, which is all it is used for.
pub(crate) fn point_in_polygon(q: P, poly: &[P]) -> bool {
    let n = poly.len();
    let mut inside = false;
    let mut j = n.wrapping_sub(1);
    for i in 0..n {
        let (a, b) = (poly[i], poly[j]);
        if (a[1] > q[1]) != (b[1] > q[1]) {
            let x = a[0] + (q[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if q[0] < x {
                inside = !inside;
            }
        }
        j = i;
    }
    inside
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

/// Interior points of a DXF bulge segment from `p` to `q` (bulge = tan of a
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

/// An open piece of a drawing (a LINE, an ARC, an open polyline) waiting to
/// be joined, with a label for error messages.
#[derive(Debug, Clone)]
pub(crate) struct Piece {
    pub pts: Vec<P>,
    pub label: String,
}

/// A chain that could not be closed.
#[derive(Debug, Clone)]
pub(crate) struct OpenChain {
    pub labels: Vec<String>,
    pub start: P,
    pub end: P,
}

/// Joins pieces end to end (either direction, nearest free end within
/// `tol`) into closed loops. Returned loops do not repeat their first point.
pub(crate) fn join_pieces(pieces: Vec<Piece>, tol: f64) -> (Vec<Vec<P>>, Vec<OpenChain>) {
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
            let first = chain[0];
            let last = chain[chain.len() - 1];
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
                let (s, e) = (pc.pts[0], pc.pts[pc.pts.len() - 1]);
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
                    let mut pts = pieces[j].pts.clone();
                    if rev {
                        pts.reverse();
                    }
                    if at_end {
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
                        start: chain[0],
                        end: chain[chain.len() - 1],
                    });
                    break;
                }
            }
        }
    }
    (loops, open)
}

#[cfg(test)]
mod tests {
    use super::*;

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
            pts: vec![a, b],
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
        assert!((signed_area(&loops[0]).abs() - 1.0).abs() < 1e-12);
    }
}
