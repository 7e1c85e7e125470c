//! Safe repairs before validation, then core's own validation.
//!
//! CAD exports routinely repeat the closing vertex, leave zero-length edges
//! where two entities meet, or split one straight edge into several LINEs.
//! Those are fixed here (with a warning) because the fix cannot change the
//! shape. Anything else that SPEC 1 forbids is left for
//! [`fixplan_core::polygon::validate_polygon`] to report, so the catalogue
//! and the solver never disagree about what a valid polygon is.

use super::outline::{dist, fmt_pt, scale_of, P};
use super::raw::RawPart;
use fixplan_core::polygon::{validate_polygon, PolygonError};
use fixplan_core::{Part, Units};

/// Repairs and validates the outline and every access constraint.
pub fn validate_part(raw: RawPart, units: Units) -> Result<(Part, Vec<String>), String> {
    let mut warnings = raw.warnings;
    let unit = units.label();
    let outline = clean_and_validate(&raw.outline, "outline", unit, &mut warnings)?;
    let mut access = Vec::with_capacity(raw.access.len());
    for (i, a) in raw.access.iter().enumerate() {
        access.push(clean_and_validate(
            a,
            &format!("access constraint {i}"),
            unit,
            &mut warnings,
        )?);
    }
    Ok((Part { outline, access }, warnings))
}

/// Relative size under which two consecutive vertices are the same point.
const DUP_REL: f64 = 1e-9;
/// Relative distance under which a vertex lies on the line through its
/// neighbours; loose enough for coordinates written with 7 significant
/// digits, far below any real feature.
const COLLINEAR_REL: f64 = 1e-7;

/// Repairs what is safe to repair, then validates. `what` names the polygon
/// ("outline", "access constraint 2"); `unit` labels coordinates.
pub(crate) fn clean_and_validate(
    pts: &[P],
    what: &str,
    unit: &str,
    warnings: &mut Vec<String>,
) -> Result<Vec<P>, String> {
    if let Some(i) = pts
        .iter()
        .position(|p| !p[0].is_finite() || !p[1].is_finite())
    {
        return Err(format!(
            "{what}: vertex {i} has a non-finite coordinate ({}, {})",
            pts[i][0], pts[i][1]
        ));
    }
    let scale = scale_of(pts).max(f64::MIN_POSITIVE);
    let mut idx: Vec<usize> = (0..pts.len()).collect();

    // Consecutive duplicates (zero-length edges), including a repeated
    // closing vertex.
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

    // Vertices in the middle of a straight run: merging the two edges keeps
    // the shape and gives the enumeration one segment instead of two
    // trimmed halves.
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

    let cleaned: Vec<P> = idx.iter().map(|&i| pts[i]).collect();
    validate_polygon(&cleaned).map_err(|e| format!("{what}: {}", polygon_message(&e, unit)))?;
    Ok(cleaned)
}

/// Core's message, with the unit after coordinates so that "(12.5, 3)"
/// cannot be misread in an inch catalogue.
pub(crate) fn polygon_message(e: &PolygonError, unit: &str) -> String {
    match e {
        PolygonError::RepeatedVertex { .. } | PolygonError::SelfIntersection { .. } => {
            format!("{e} {unit}")
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
        let out = clean_and_validate(&sq, "outline", "mm", &mut w).unwrap();
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
        let e = clean_and_validate(&bow, "outline", "mm", &mut w).unwrap_err();
        assert_eq!(e, "outline: edge 0 crosses edge 2 at (1, 1) mm");
    }
}
