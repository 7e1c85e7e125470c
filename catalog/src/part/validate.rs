//! Safe repairs before validation, then core's own validation.
//!
//! CAD exports routinely repeat the closing vertex, leave zero-length edges
//! where two entities meet, or split one straight edge into several LINEs.
//! Those are fixed here (with a warning) because the fix cannot change the
//! shape: a dropped duplicate vertex leaves its bulge to the edge that
//! survives, and a vertex is merged away only between two straight edges.
//! Anything else that SPEC 1 and 8.1 forbid is left for
//! [`fixplan_core::parts::validate_outline`] (the outline and each hole,
//! arcs included) and [`fixplan_core::parts::validate_polygon`] (access
//! constraints, which stay polygons) to report, so the catalogue and the
//! solver never disagree about what a valid loop is. Where the holes lie
//! (SPEC 9.1: inside the outline, sharing no point with it or with each
//! other, none inside another) is [`fixplan_core::parts::validate_holes`]'s
//! to judge, for the same reason: a part with a hole in the wrong place is
//! refused when the catalogue is read, with core's message naming the hole
//! and the place, never accepted here and refused by the solver.

use super::outline::{dist, fmt_pt, scale_of, P};
use super::raw::{PolygonRole, RawPart};
use fixplan_core::parts::{
    validate_holes, validate_outline, validate_polygon, HoleError, OutlineError, PolygonError,
};
use fixplan_core::{Part, Units, Vertex};

/// Why a polygon of a part cannot be used, naming the polygon so a part
/// with several access constraints says which one is wrong (core's
/// message on where a hole lies names the hole itself).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}", invalid_message(.polygon, .problem))]
pub struct InvalidPolygon {
    /// The outline or an access constraint.
    pub polygon: PolygonRole,
    /// What is wrong with it.
    pub problem: PolygonProblem,
}

/// What is wrong with a polygon.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PolygonProblem {
    /// A coordinate is NaN or infinite; caught before repairs, which
    /// measure distances and would be meaningless.
    #[error("vertex {vertex} has a non-finite coordinate ({x}, {y})")]
    NonFinite {
        /// The vertex, from 0 in file order.
        vertex: usize,
        /// Its x as read.
        x: f64,
        /// Its y as read.
        y: f64,
    },
    /// What core's validation found after the repairs, with the unit after
    /// coordinates so that "(12.5, 3)" cannot be misread in an inch
    /// catalogue.
    #[error("{}", polygon_message(.error, *.units))]
    Core {
        /// Core's finding.
        error: PolygonError,
        /// The catalogue's units, for the coordinates in the message.
        units: Units,
    },
    /// What core's outline validation found that polygons cannot have (an
    /// outline with arcs and fewer than 2 vertices, a bulge that is no
    /// number); problems polygons share are [`PolygonProblem::Core`].
    #[error("{0}")]
    Arc(OutlineError),
    /// A hole in the wrong place (SPEC 9.1), as core's validation found
    /// it, with the unit after coordinates.
    #[error("{}", hole_message(.error, *.units))]
    Placement {
        /// Core's finding.
        error: HoleError,
        /// The catalogue's units, for the coordinates in the message.
        units: Units,
    },
}

/// `polygon: problem`, except for a hole's placement, which core's
/// message words with the hole's number ("hole 1 lies inside hole 0").
fn invalid_message(polygon: &PolygonRole, problem: &PolygonProblem) -> String {
    match problem {
        PolygonProblem::Placement { .. } => problem.to_string(),
        _ => format!("{polygon}: {problem}"),
    }
}

/// Repairs and validates the outline, every hole and every access
/// constraint: the part and the warnings of the repairs (the reader's
/// first), or the first problem found.
pub fn validate_part(raw: RawPart, units: Units) -> Result<(Part, Vec<String>), InvalidPolygon> {
    let mut warnings = raw.warnings;
    let outline = clean_and_validate(&raw.outline, PolygonRole::Outline, units, &mut warnings)?;
    let mut holes = Vec::with_capacity(raw.holes.len());
    for (k, h) in raw.holes.iter().enumerate() {
        holes.push(clean_and_validate(
            h,
            PolygonRole::Hole(k),
            units,
            &mut warnings,
        )?);
    }
    place_holes(&outline, &holes, units)?;
    let mut access = Vec::with_capacity(raw.access.len());
    for (i, a) in raw.access.iter().enumerate() {
        let a: Vec<Vertex> = a.iter().map(|&p| Vertex::from(p)).collect();
        let cleaned = clean_and_validate(&a, PolygonRole::Access(i), units, &mut warnings)?;
        access.push(cleaned.iter().map(|v| [v.x, v.y]).collect());
    }
    Ok((
        Part {
            outline,
            holes,
            access,
        },
        warnings,
    ))
}

/// Core's judgement of where the holes lie (SPEC 9.1). The holes stay as
/// read (core's clockwise copies are the solver's business), so a part
/// core accepts is the part the file holds.
fn place_holes(
    outline: &[Vertex],
    holes: &[Vec<Vertex>],
    units: Units,
) -> Result<(), InvalidPolygon> {
    if holes.is_empty() {
        return Ok(());
    }
    validate_holes(outline, holes).map(drop).map_err(|error| {
        let hole = match error {
            HoleError::Loop { index, .. }
            | HoleError::MeetsOutline { index, .. }
            | HoleError::Outside { index }
            | HoleError::MeetsHole { index, .. } => index,
            HoleError::Nested { inner, .. } => inner,
        };
        InvalidPolygon {
            polygon: PolygonRole::Hole(hole),
            problem: PolygonProblem::Placement { error, units },
        }
    })
}

/// Relative size under which two consecutive vertices are the same point.
const DUP_REL: f64 = 1e-9;
/// Relative distance under which a vertex lies on the line through its
/// neighbours; loose enough for coordinates written with 7 significant
/// digits, far below any real feature.
const COLLINEAR_REL: f64 = 1e-7;

/// Repairs what is safe to repair, then validates: the outline with
/// [`validate_outline`] (arcs included), an access constraint with
/// [`validate_polygon`]. `what` names the polygon in messages; `units`
/// labels coordinates.
fn clean_and_validate(
    verts: &[Vertex],
    what: PolygonRole,
    units: Units,
    warnings: &mut Vec<String>,
) -> Result<Vec<Vertex>, InvalidPolygon> {
    let invalid = |problem| InvalidPolygon {
        polygon: what,
        problem,
    };
    if let Some(i) = verts
        .iter()
        .position(|p| !p.x.is_finite() || !p.y.is_finite())
    {
        return Err(invalid(PolygonProblem::NonFinite {
            vertex: i,
            x: verts[i].x,
            y: verts[i].y,
        }));
    }
    let pts: Vec<P> = verts.iter().map(|v| [v.x, v.y]).collect();
    let mut bulges: Vec<f64> = verts.iter().map(|v| v.bulge).collect();
    let unit = units.label();
    let scale = scale_of(&pts).max(f64::MIN_POSITIVE);
    let mut idx = (0..pts.len()).collect();
    let mut c = Cleaning {
        pts: &pts,
        bulges: &mut bulges,
        idx: &mut idx,
        scale,
        what,
        unit,
        warnings,
    };
    c.drop_repeated_vertices();
    c.merge_collinear_vertices();
    let cleaned: Vec<Vertex> = idx
        .iter()
        .map(|&i| Vertex::new(pts[i][0], pts[i][1], bulges[i]))
        .collect();
    let core = |error: PolygonError| invalid(PolygonProblem::Core { error, units });
    let checked = match what {
        PolygonRole::Outline | PolygonRole::Hole(_) => {
            validate_outline(&cleaned).map(drop).map_err(|e| match e {
                OutlineError::Polygon(error) => core(error),
                other => invalid(PolygonProblem::Arc(other)),
            })
        }
        PolygonRole::Access(_) => {
            let p: Vec<P> = cleaned.iter().map(|v| [v.x, v.y]).collect();
            validate_polygon(&p).map(drop).map_err(core)
        }
    };
    checked.map(|()| cleaned)
}

/// The repairs of one outline or access constraint: indices `idx` into
/// `pts` of the vertices kept, `bulges[i]` the bulge of the edge leaving
/// `pts[i]` (updated when a repeated vertex hands its edge on).
struct Cleaning<'a> {
    pts: &'a [P],
    bulges: &'a mut [f64],
    idx: &'a mut Vec<usize>,
    scale: f64,
    what: PolygonRole,
    unit: &'a str,
    warnings: &'a mut Vec<String>,
}

impl Cleaning<'_> {
    /// Drops consecutive duplicates (zero-length edges), including a
    /// repeated closing vertex. The zero-length edge goes; the edge leaving
    /// the dropped vertex survives, leaving the kept one with its bulge.
    fn drop_repeated_vertices(&mut self) {
        let (pts, idx) = (self.pts, &mut *self.idx);
        let (what, unit) = (self.what, self.unit);
        let mut k = 0;
        while idx.len() > 1 && k < idx.len() {
            let wraps = k + 1 == idx.len();
            let (a, b) = (idx[k], idx[(k + 1) % idx.len()]);
            if dist(pts[a], pts[b]) <= DUP_REL * self.scale {
                // Keep the earlier vertex, and vertex 0 on the closing edge,
                // so that v0 stays v0.
                let (kept, dropped, at) = if wraps { (b, a, k) } else { (a, b, k + 1) };
                self.warnings.push(format!(
                    "{what}: vertex {dropped} repeats vertex {kept} at {} {unit} (zero-length edge); dropped",
                    fmt_pt(pts[kept])
                ));
                // The zero-length edge leaves a (its bulge goes), b's edge
                // survives: from a when b is dropped; from b itself (kept,
                // vertex 0) when a, the last vertex, is.
                if !wraps {
                    self.bulges[a] = self.bulges[b];
                }
                idx.remove(at);
            } else {
                k += 1;
            }
        }
    }

    /// Drops vertices in the middle of a straight run: merging the two
    /// edges keeps the shape and gives the enumeration one segment instead
    /// of two trimmed halves. A vertex next to an arc is never merged.
    fn merge_collinear_vertices(&mut self) {
        let (pts, idx) = (self.pts, &mut *self.idx);
        let (what, unit) = (self.what, self.unit);
        let mut changed = true;
        while changed && idx.len() > 3 {
            changed = false;
            let m = idx.len();
            for k in 0..m {
                let (ia, ib) = (idx[(k + m - 1) % m], idx[k]);
                if self.bulges[ia] != 0.0 || self.bulges[ib] != 0.0 {
                    continue;
                }
                let (a, b, c) = (pts[ia], pts[ib], pts[idx[(k + 1) % m]]);
                let u = [c[0] - a[0], c[1] - a[1]];
                let len = u[0].hypot(u[1]);
                if len == 0.0 {
                    continue;
                }
                let off = ((b[0] - a[0]) * u[1] - (b[1] - a[1]) * u[0]).abs() / len;
                let along = (b[0] - a[0]) * u[0] + (b[1] - a[1]) * u[1];
                if off <= COLLINEAR_REL * self.scale && along > 0.0 && along < len * len {
                    self.warnings.push(format!(
                        "{what}: vertex {} at {} {unit} lies on the straight edge through its neighbours; merged",
                        idx[k],
                        fmt_pt(b)
                    ));
                    idx.remove(k);
                    changed = true;
                    break;
                }
            }
        }
    }
}

/// Core's message on a hole's place, with the unit after the coordinates
/// of the point where two loops meet.
fn hole_message(error: &HoleError, units: Units) -> String {
    match error {
        HoleError::MeetsOutline { .. } | HoleError::MeetsHole { .. } => {
            format!("{error} {}", units.label())
        }
        _ => error.to_string(),
    }
}

/// Core's message, with the unit after coordinates so that "(12.5, 3)"
/// cannot be misread in an inch catalogue.
fn polygon_message(error: &PolygonError, units: Units) -> String {
    match error {
        PolygonError::RepeatedVertex { .. } | PolygonError::SelfIntersection { .. } => {
            format!("{error} {}", units.label())
        }
        PolygonError::ZeroArea => "has zero area (all its vertices lie on one line)".into(),
        _ => error.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repairs_warn_and_keep_shape() {
        let mut w = Vec::new();
        let sq = [
            [0.0, 0.0],
            [5.0, 0.0],
            [10.0, 0.0],
            [10.0, 10.0],
            [10.0, 10.0],
            [0.0, 10.0],
            [0.0, 0.0],
        ];
        let sq: Vec<Vertex> = sq.iter().map(|&p| Vertex::from(p)).collect();
        let out = clean_and_validate(&sq, PolygonRole::Outline, Units::Mm, &mut w).unwrap();
        assert_eq!(
            out,
            vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]]
        );
        assert_eq!(w.len(), 3, "{w:?}");
    }

    #[test]
    fn crossing_names_place_and_unit() {
        let mut w = Vec::new();
        let bow: Vec<Vertex> = [[0.0, 0.0], [2.0, 2.0], [2.0, 0.0], [0.0, 2.0]]
            .iter()
            .map(|&p| Vertex::from(p))
            .collect();
        let e = clean_and_validate(&bow, PolygonRole::Outline, Units::Mm, &mut w).unwrap_err();
        assert_eq!(e.to_string(), "outline: edge 0 crosses edge 2 at (1, 1) mm");
    }

    #[test]
    fn repairs_keep_arcs() {
        let mut w = Vec::new();
        // A slot: two half circles joined by lines, with a repeated vertex
        // after each arc end (its zero-length edge goes, the arc stays on the
        // vertex before), a repeated closing vertex, and a vertex in the
        // middle of a straight side that is merged. (5, 0) lies on the line
        // through (0, 0) and (10, 0) but is next to no arc.
        let v = |x: f64, y: f64, b: f64| Vertex::new(x, y, b);
        let slot = [
            v(0.0, 0.0, 0.0),
            v(5.0, 0.0, 0.0),
            v(10.0, 0.0, 0.0),
            v(10.0, 0.0, 1.0),
            v(10.0, 4.0, 0.0),
            v(0.0, 4.0, 1.0),
            v(0.0, 0.0, 0.0),
        ];
        let out = clean_and_validate(&slot, PolygonRole::Outline, Units::Mm, &mut w).unwrap();
        assert_eq!(
            out,
            vec![
                v(0.0, 0.0, 0.0),
                v(10.0, 0.0, 1.0),
                v(10.0, 4.0, 0.0),
                v(0.0, 4.0, 1.0)
            ],
            "{w:?}"
        );
        // A vertex between a line and an arc is never merged, even when it
        // lies on the line through its neighbours.
        let d = [
            v(0.0, 0.0, 0.0),
            v(10.0, 0.0, 0.5),
            v(20.0, 0.0, 0.0),
            v(20.0, 10.0, 0.0),
            v(0.0, 10.0, 0.0),
        ];
        let mut w = Vec::new();
        let out = clean_and_validate(&d, PolygonRole::Outline, Units::Mm, &mut w).unwrap();
        assert_eq!(out, d.to_vec(), "{w:?}");
        assert!(w.is_empty(), "{w:?}");
    }

    #[test]
    fn arc_problems_are_reported() {
        let mut w = Vec::new();
        let bad = [Vertex::new(0.0, 0.0, f64::NAN), Vertex::new(1.0, 0.0, 1.0)];
        let e = clean_and_validate(&bad, PolygonRole::Outline, Units::Mm, &mut w).unwrap_err();
        assert_eq!(
            e.to_string(),
            "outline: vertex 0 has bulge NaN; a bulge must be a finite number"
        );
    }
}
