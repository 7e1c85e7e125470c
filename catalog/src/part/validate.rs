//! Safe repairs before validation, then core's own validation.
//!
//! CAD exports routinely repeat the closing vertex, leave zero-length edges
//! where two entities meet, or split one straight edge into several LINEs.
//! Those are fixed here (with a warning) because the fix cannot change the
//! shape. Anything else that SPEC 1 forbids is left for
//! [`fixplan_core::polygon::validate_polygon`] to report, so the catalogue
//! and the solver never disagree about what a valid polygon is.

use super::outline::{dist, fmt_pt, scale_of, P};
use super::raw::{PolygonRole, RawPart};
use fixplan_core::polygon::{validate_polygon, PolygonError};
use fixplan_core::{Part, Units};

/// Why a polygon of a part cannot be used, naming the polygon so a part
/// with several access constraints says which one is wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{polygon}: {problem}")]
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
}

/// Repairs and validates the outline and every access constraint: the part
/// and the warnings of the repairs (the reader's first), or the first
/// problem found.
pub fn validate_part(raw: RawPart, units: Units) -> Result<(Part, Vec<String>), InvalidPolygon> {
    let mut warnings = raw.warnings;
    let outline = clean_and_validate(&raw.outline, PolygonRole::Outline, units, &mut warnings)?;
    let mut access = Vec::with_capacity(raw.access.len());
    for (i, a) in raw.access.iter().enumerate() {
        access.push(clean_and_validate(
            a,
            PolygonRole::Access(i),
            units,
            &mut warnings,
        )?);
    }
    let outline = outline.into_iter().map(Into::into).collect();
    Ok((Part { outline, access }, warnings))
}

/// Relative size under which two consecutive vertices are the same point.
const DUP_REL: f64 = 1e-9;
/// Relative distance under which a vertex lies on the line through its
/// neighbours; loose enough for coordinates written with 7 significant
/// digits, far below any real feature.
const COLLINEAR_REL: f64 = 1e-7;

/// Repairs what is safe to repair, then validates. `what` names the polygon
/// in messages; `units` labels coordinates.
fn clean_and_validate(
    pts: &[P],
    what: PolygonRole,
    units: Units,
    warnings: &mut Vec<String>,
) -> Result<Vec<P>, InvalidPolygon> {
    let invalid = |problem| InvalidPolygon {
        polygon: what,
        problem,
    };
    if let Some(i) = pts
        .iter()
        .position(|p| !p[0].is_finite() || !p[1].is_finite())
    {
        return Err(invalid(PolygonProblem::NonFinite {
            vertex: i,
            x: pts[i][0],
            y: pts[i][1],
        }));
    }
    let unit = units.label();
    let scale = scale_of(pts).max(f64::MIN_POSITIVE);
    let mut idx = (0..pts.len()).collect();
    drop_repeated_vertices(pts, &mut idx, scale, what, unit, warnings);
    merge_collinear_vertices(pts, &mut idx, scale, what, unit, warnings);
    let cleaned: Vec<P> = idx.iter().map(|&i| pts[i]).collect();
    validate_polygon(&cleaned).map_err(|error| invalid(PolygonProblem::Core { error, units }))?;
    Ok(cleaned)
}

/// Drops consecutive duplicates (zero-length edges), including a repeated
/// closing vertex, from the indices `idx` into `pts`.
fn drop_repeated_vertices(
    pts: &[P],
    idx: &mut Vec<usize>,
    scale: f64,
    what: PolygonRole,
    unit: &str,
    warnings: &mut Vec<String>,
) {
    let mut k = 0;
    while idx.len() > 1 && k < idx.len() {
        let wraps = k + 1 == idx.len();
        let (a, b) = (idx[k], idx[(k + 1) % idx.len()]);
        if dist(pts[a], pts[b]) <= DUP_REL * scale {
            // Keep the earlier vertex, and vertex 0 on the closing edge, so
            // that v0 stays v0.
            let (kept, dropped, at) = if wraps { (b, a, k) } else { (a, b, k + 1) };
            warnings.push(format!(
                "{what}: vertex {dropped} repeats vertex {kept} at {} {unit} (zero-length edge); dropped",
                fmt_pt(pts[kept])
            ));
            idx.remove(at);
        } else {
            k += 1;
        }
    }
}

/// Drops vertices in the middle of a straight run: merging the two edges
/// keeps the shape and gives the enumeration one segment instead of two
/// trimmed halves.
fn merge_collinear_vertices(
    pts: &[P],
    idx: &mut Vec<usize>,
    scale: f64,
    what: PolygonRole,
    unit: &str,
    warnings: &mut Vec<String>,
) {
    let mut changed = true;
    while changed && idx.len() > 3 {
        changed = false;
        let m = idx.len();
        for k in 0..m {
            let (a, b, c) = (
                pts[idx[(k + m - 1) % m]],
                pts[idx[k]],
                pts[idx[(k + 1) % m]],
            );
            let u = [c[0] - a[0], c[1] - a[1]];
            let len = u[0].hypot(u[1]);
            if len == 0.0 {
                continue;
            }
            let off = ((b[0] - a[0]) * u[1] - (b[1] - a[1]) * u[0]).abs() / len;
            let along = (b[0] - a[0]) * u[0] + (b[1] - a[1]) * u[1];
            if off <= COLLINEAR_REL * scale && along > 0.0 && along < len * len {
                warnings.push(format!(
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

/// Core's message, with the unit after coordinates so that "(12.5, 3)"
/// cannot be misread in an inch catalogue.
fn polygon_message(e: &PolygonError, units: Units) -> String {
    match e {
        PolygonError::RepeatedVertex { .. } | PolygonError::SelfIntersection { .. } => {
            format!("{e} {}", units.label())
        }
        PolygonError::ZeroArea => "has zero area (all its vertices lie on one line)".into(),
        _ => e.to_string(),
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
        let bow = [[0.0, 0.0], [2.0, 2.0], [2.0, 0.0], [0.0, 2.0]];
        let e = clean_and_validate(&bow, PolygonRole::Outline, Units::Mm, &mut w).unwrap_err();
        assert_eq!(e.to_string(), "outline: edge 0 crosses edge 2 at (1, 1) mm");
    }
}
