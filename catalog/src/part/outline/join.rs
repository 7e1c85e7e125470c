//! Joining the open pieces of a drawing (LINEs, ARCs, open polylines, SVG
//! subpaths) end to end into closed loops, arcs kept, and describing what
//! would not close so that a message can tell a gap from a stray line.

use super::curves::{dist, P};
use fixplan_core::Vertex;
use std::collections::HashMap;

/// A piece read backwards: the points reversed, each bulge negated and
/// moved with its edge (the edge `v(k) -> v(k+1)` becomes `v(k+1) -> v(k)`),
/// the new last vertex (an open end) straight.
pub(crate) fn reversed(vertices: &[Vertex]) -> Vec<Vertex> {
    let n = vertices.len();
    (0..n)
        .map(|k| {
            let p = vertices[n - 1 - k];
            let b = if k + 1 < n {
                -vertices[n - 2 - k].bulge
            } else {
                0.0
            };
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

pub(crate) fn pt(vertex: Vertex) -> P {
    [vertex.x, vertex.y]
}

/// A chain that could not be closed.
#[derive(Debug, Clone)]
pub(crate) struct OpenChain {
    pub labels: Vec<String>,
    pub start: P,
    pub end: P,
    /// Joining its own ends would make a loop (it has more than one edge,
    /// or an arc): a chain that nearly closes has a gap between them.
    pub closable: bool,
}

/// The free ends of the pieces by grid cell, so that joining many pieces
/// looks only at the ends near a point instead of at every piece (a sheet
/// of parts has tens of thousands of LINEs).
struct Ends {
    cell: f64,
    grid: HashMap<(i64, i64), Vec<(usize, bool)>>,
}

impl Ends {
    fn new(pieces: &[Piece], tol: f64) -> Ends {
        // Cells no smaller than the tolerance, so a match is always in one
        // of the 3 x 3 cells around a point.
        let cell = if tol > 0.0 && tol.is_finite() {
            tol
        } else {
            1.0
        };
        let mut ends = Ends {
            cell,
            grid: HashMap::new(),
        };
        for (j, pc) in pieces.iter().enumerate() {
            if let (Some(s), Some(e)) = (pc.pts.first(), pc.pts.last()) {
                for (p, is_end) in [(pt(*s), false), (pt(*e), true)] {
                    let key = ends.key(p);
                    ends.grid.entry(key).or_default().push((j, is_end));
                }
            }
        }
        ends
    }

    fn key(&self, p: P) -> (i64, i64) {
        // `as` saturates (and maps NaN to 0): far-off or broken points share
        // edge cells, which only costs time.
        (
            (p[0] / self.cell).floor() as i64,
            (p[1] / self.cell).floor() as i64,
        )
    }

    /// The piece ends in the cells around `p`, in piece order.
    fn near(&self, p: P) -> Vec<(usize, bool)> {
        let (kx, ky) = self.key(p);
        let mut out = Vec::new();
        for dx in -1..=1i64 {
            for dy in -1..=1i64 {
                if let Some(v) = self
                    .grid
                    .get(&(kx.saturating_add(dx), ky.saturating_add(dy)))
                {
                    out.extend_from_slice(v);
                }
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    }
}

/// Joins pieces end to end (either direction, nearest free end within
/// `tol`) into closed loops, arcs kept: a piece joined backwards is
/// [`reversed`]. Returned loops do not repeat their first point.
pub(crate) fn join_pieces(pieces: Vec<Piece>, tol: f64) -> (Vec<Vec<Vertex>>, Vec<OpenChain>) {
    let ends = Ends::new(&pieces, tol);
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
            match nearest_free(&pieces, &used, &ends, first, last, tol) {
                Some((j, at_end, rev)) => {
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
                        closable: chain.len() > 2 || chain.iter().any(Vertex::is_arc),
                    });
                    break;
                }
            }
        }
    }
    (loops, open)
}

/// The unused piece with the free end nearest the chain's last point, then
/// its first (ties: the piece first in file order), within `tol`: the
/// piece, whether it joins at the chain's end, and whether backwards.
fn nearest_free(
    pieces: &[Piece],
    used: &[bool],
    ends: &Ends,
    first: P,
    last: P,
    tol: f64,
) -> Option<(usize, bool, bool)> {
    let mut cands = ends.near(last);
    cands.extend(ends.near(first));
    cands.sort_unstable();
    cands.dedup_by_key(|c| c.0);
    let mut best: Option<(f64, usize, bool, bool)> = None;
    for (j, _) in cands {
        let pc = &pieces[j];
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
    best.map(|(_, j, at_end, rev)| (j, at_end, rev))
}

/// The free end nearest to `p` among the chains' ends other than chain
/// `skip`'s end `p` itself (its other end counts when the chain is
/// [`OpenChain::closable`]): the distance, the point and the first label
/// of its chain.
pub(crate) fn nearest_other_end(open: &[OpenChain], skip: usize, p: P) -> Option<(f64, P, &str)> {
    let mut best: Option<(f64, P, &str)> = None;
    for (i, c) in open.iter().enumerate() {
        for q in [c.start, c.end] {
            if i == skip && (q == p || !c.closable) {
                continue;
            }
            let d = dist(p, q);
            let label = c.labels.first().map(String::as_str).unwrap_or("");
            if d.is_finite() && best.is_none_or(|b| d < b.0) {
                best = Some((d, q, label));
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::super::curves::{bulge_points, circle_loop, exact_arc, exact_circle, straight};
    use super::super::region::{contains, loop_area};
    use super::*;
    use fixplan_core::parts::v2;

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
        assert!(contains(&loops[0], v2(0.0, 0.5)));
        assert!(!contains(&loops[0], v2(0.0, -0.5)));
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
