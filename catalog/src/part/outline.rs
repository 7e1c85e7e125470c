//! What the drawing readers share: curve flattening, joining pieces into
//! loops, choosing the outline among the loops, and numbers for messages.
//! Everything here works on plain `[f64; 2]` points because that is what
//! files hold and what [`fixplan_core::Part`] stores; areas and
//! point-in-polygon come from `fixplan_core::geometry`.

use super::raw::RawPart;
use fixplan_core::geometry::{point_in_polygon, signed_area, v2, V2};
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

fn to_v2(p: &[P]) -> Vec<V2> {
    p.iter().map(|q| v2(q[0], q[1])).collect()
}

/// Unsigned area for choosing the largest loop; an overflowing loop counts
/// as the largest rather than as NaN, so the choice stays total.
fn loop_area(p: &[P]) -> f64 {
    let a = signed_area(&to_v2(p)).abs();
    if a.is_finite() {
        a
    } else {
        f64::INFINITY
    }
}

/// Even-odd test of `q` against `poly`, enough to tell a hole from a second
/// outline; an empty polygon contains nothing (core's test needs a vertex).
fn inside(q: P, poly: &[V2]) -> bool {
    !poly.is_empty() && point_in_polygon(v2(q[0], q[1]), poly)
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
    mut loops: Vec<(Vec<P>, String)>,
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
    let outer = to_v2(&loops[outer_i].0);
    for (i, (l, label)) in loops.iter().enumerate() {
        if i == outer_i || l.is_empty() {
            continue;
        }
        if inside(l[0], &outer) {
            warnings.push(format!(
                "{label} near {} {unit} is a loop inside the outline (a hole or pocket); ignored: fixtures hold the outer outline only",
                fmt_pt(l[0])
            ));
        } else {
            return Err(OutlineError::MoreThanOne {
                label: label.clone(),
                near: l[0],
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
        assert!((loop_area(&loops[0]) - 1.0).abs() < 1e-12);
    }
}
