//! Validation and orientation of a part's holes (SPEC 9.1 and 9.2).
//!
//! Each hole must be a valid loop on its own (the outline's rules, SPEC 1
//! and 8.1), lie strictly inside the outline, share no point with the
//! outline or another hole, and lie inside no other hole. Two loops share
//! a point when two of their edges come within the outline's crossing
//! tolerance (`1e-9` times its extent, the tolerance arcs are validated
//! with; polygons are validated exactly, but loops drawn in a CAD system
//! that touch are a few ulps apart, and that is sharing for any practical
//! purpose).
//!
//! Messages name the hole by its index in the input and the place, in the
//! order of the independent reading (`scripts/spec_reference.py`): each
//! hole on its own first, then hole by hole against the outline and the
//! holes before it, coordinates written as C's `%g` does.

use super::edge::{ccw_of_cw_outline, edges_of, loop_contains, Edge};
use super::mass::general;
use super::validate::{sizes, validate_outline, OutlineError, TOUCH_REL};
use super::vertex::Vertex;
use crate::geometry::{cross, Aabb, V2};
use std::cell::OnceCell;
use thiserror::Error;

/// Points tried along each edge when deciding whether a loop that meets
/// another crosses it or only touches it.
const SIDE_SAMPLES: usize = 32;

/// Why a part's holes make it invalid (SPEC 9.1); `index` is the hole's
/// position in the input.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum HoleError {
    /// The hole is not a valid loop on its own.
    #[error("hole {index}: {source}")]
    Loop {
        /// The hole.
        index: usize,
        /// What is wrong with it, worded as for an outline.
        source: OutlineError,
    },
    /// The hole meets the outline.
    #[error("hole {index} {} the outline at ({}, {})", verb(*.crosses), fmt_g(*.x), fmt_g(*.y))]
    MeetsOutline {
        /// The hole.
        index: usize,
        /// Whether it runs out of the outline (else it touches it).
        crosses: bool,
        /// x of a point they share.
        x: f64,
        /// y of a point they share.
        y: f64,
    },
    /// The hole lies outside the outline.
    #[error("hole {index} lies outside the outline")]
    Outside {
        /// The hole.
        index: usize,
    },
    /// The hole meets an earlier hole.
    #[error("hole {index} {} hole {other} at ({}, {})", verb(*.crosses), fmt_g(*.x), fmt_g(*.y))]
    MeetsHole {
        /// The later hole.
        index: usize,
        /// The earlier hole.
        other: usize,
        /// Whether they cross (else they touch).
        crosses: bool,
        /// x of a point they share.
        x: f64,
        /// y of a point they share.
        y: f64,
    },
    /// One hole lies inside another.
    #[error("hole {inner} lies inside hole {outer}")]
    Nested {
        /// The hole inside.
        inner: usize,
        /// The hole around it.
        outer: usize,
    },
}

fn verb(crosses: bool) -> &'static str {
    if crosses {
        "crosses"
    } else {
        "touches"
    }
}

/// `x` as C's `printf("%g")` writes it: six significant digits, trailing
/// zeros dropped, exponent form below 1e-4 and from 1e6.
pub fn fmt_g(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let sci = format!("{x:.5e}");
    let (mantissa, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let trim = |s: &str| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s.to_string()
        }
    };
    if !(-4..6).contains(&exp) {
        let sign = if exp < 0 { '-' } else { '+' };
        format!("{}e{sign}{:02}", trim(mantissa), exp.abs())
    } else {
        let decimals = (5 - exp).max(0) as usize;
        trim(&format!("{x:.decimals$}"))
    }
}

/// Two boxes farther apart than this many times the touching tolerance
/// hold no two points that come within it (distances are rounded by far
/// less), nor one loop inside the other: the pair is not looked at.
const FAR_TOL: f64 = 2.0;

/// One loop as read, and counter-clockwise, for the checks.
struct Loop {
    edges: Vec<Edge>,
    /// Every edge's box, and the loop's: a part's many small holes are
    /// told apart by their boxes before their edges are compared.
    boxes: Vec<Aabb>,
    aabb: Aabb,
    ccw: Vec<Vertex>,
    /// The counter-clockwise points and edges, made when a point is first
    /// located in the loop: the outline's are, a hole's rarely (only when
    /// another hole's box comes near it).
    region: OnceCell<(Vec<V2>, Vec<Edge>)>,
}

impl Loop {
    fn of(vertices: &[Vertex], ccw: Vec<Vertex>) -> Loop {
        let edges = edges_of(vertices);
        let boxes: Vec<Aabb> = edges.iter().map(Edge::aabb).collect();
        let mut aabb = Aabb::of(&[]);
        for b in &boxes {
            aabb.min = aabb.min.inf(&b.min);
            aabb.max = aabb.max.sup(&b.max);
        }
        Loop {
            edges,
            boxes,
            aabb,
            ccw,
            region: OnceCell::new(),
        }
    }

    /// Even-odd location in the loop's region.
    fn contains(&self, p: V2) -> bool {
        let (points, edges) = self.region.get_or_init(|| {
            (
                self.ccw.iter().map(Vertex::point).collect(),
                edges_of(&self.ccw),
            )
        });
        loop_contains(p, points, edges)
    }
}

/// Checks SPEC 9.1's conditions on `holes` against `outline` (both as
/// read, either orientation) and returns each hole clockwise (SPEC 9.2).
/// The outline must be valid ([`validate_outline`]).
pub fn validate_holes(
    outline: &[Vertex],
    holes: &[Vec<Vertex>],
) -> Result<Vec<Vec<Vertex>>, HoleError> {
    let mut loops = Vec::with_capacity(holes.len());
    for (index, hole) in holes.iter().enumerate() {
        let ccw = validate_outline(hole).map_err(|source| HoleError::Loop { index, source })?;
        loops.push(Loop::of(hole, ccw));
    }
    // The outline is valid: only its orientation is wanted.
    let outline_ccw = if general(outline).area < 0.0 {
        ccw_of_cw_outline(outline)
    } else {
        outline.to_vec()
    };
    let outer = Loop::of(outline, outline_ccw);
    let tol = TOUCH_REL * sizes(outline).1;
    for (index, hole) in loops.iter().enumerate() {
        if let Some(p) = contact(hole, &outer, tol) {
            return Err(HoleError::MeetsOutline {
                index,
                crosses: crosses(&hole.edges, &outer, tol),
                x: p.x,
                y: p.y,
            });
        }
        if !inside(hole, &outer) {
            return Err(HoleError::Outside { index });
        }
        for (other, earlier) in loops[..index].iter().enumerate() {
            if hole.aabb.gap(&earlier.aabb) > FAR_TOL * tol {
                // Neither meets nor holds the other.
                continue;
            }
            if let Some(p) = contact(hole, earlier, tol) {
                return Err(HoleError::MeetsHole {
                    index,
                    other,
                    crosses: crosses(&hole.edges, earlier, tol),
                    x: p.x,
                    y: p.y,
                });
            }
            if inside(hole, earlier) {
                return Err(HoleError::Nested {
                    inner: index,
                    outer: other,
                });
            }
            if inside(earlier, hole) {
                return Err(HoleError::Nested {
                    inner: other,
                    outer: index,
                });
            }
        }
    }
    Ok(loops
        .into_iter()
        .map(|l| ccw_of_cw_outline(&l.ccw))
        .collect())
}

/// The first point (edges of `a` in order, then of `b`) where two loops
/// come within `tol`, on `a`. Edges whose boxes lie far apart are not
/// compared: they cannot be the first.
fn contact(a: &Loop, b: &Loop, tol: f64) -> Option<V2> {
    let far = |x: &Aabb, y: &Aabb| x.gap(y) > FAR_TOL * tol;
    if far(&a.aabb, &b.aabb) {
        return None;
    }
    a.edges.iter().zip(&a.boxes).find_map(|(e, eb)| {
        if far(eb, &b.aabb) {
            return None;
        }
        b.edges.iter().zip(&b.boxes).find_map(|(f, fb)| {
            if far(eb, fb) {
                return None;
            }
            let c = e.closest(f);
            (c.distance <= tol).then_some(c.p)
        })
    })
}

/// Whether loop `a`, which meets loop `b`, has points strictly on both
/// sides of it (crosses) rather than on one side only (touches). Decided
/// on points spread along every edge, those within `tol` of `b` left out:
/// a crossing narrower than the spacing of the points reads as touching,
/// which changes the wording of the message, not the verdict.
fn crosses(a: &[Edge], b: &Loop, tol: f64) -> bool {
    let (mut inner, mut outer) = (false, false);
    for e in a {
        for k in 0..SIDE_SAMPLES {
            let p = e.point_at((k as f64 + 0.5) / SIDE_SAMPLES as f64);
            if b.edges.iter().any(|f| f.distance(p) <= tol) {
                continue;
            }
            if b.contains(p) {
                inner = true;
            } else {
                outer = true;
            }
        }
    }
    inner && outer
}

/// Whether loop `a`, which does not meet `b`, lies inside it: decided at
/// a vertex or edge midpoint of `a` off every chord line of `b`'s arcs
/// (even-odd location is ambiguous exactly on a chord, and a round hole's
/// vertex often lies on the centre line of a round outline).
fn inside(a: &Loop, b: &Loop) -> bool {
    let on_chord = |p: V2| {
        b.edges.iter().any(|f| match f {
            Edge::Arc(arc) => cross(arc.b - arc.a, p - arc.a) == 0.0,
            Edge::Line { .. } => false,
        })
    };
    let candidates = a
        .edges
        .iter()
        .map(Edge::start)
        .chain(a.edges.iter().map(|e| e.point_at(0.5)));
    let mut first = None;
    for p in candidates {
        first.get_or_insert(p);
        if !on_chord(p) {
            return b.contains(p);
        }
    }
    first.is_some_and(|p| b.contains(p))
}
