//! Validation of the inputs against SPEC sections 1 and 7 (kit, parameters)
//! and the error every preparation step reports, so the catalogue, the CLI
//! and [`crate::prepare()`] refuse the same inputs with the same messages.

use crate::geometry::polygon::{validate_polygon, PolygonError};
use crate::input::{HoleKind, Kit, Params, Pattern, Units};
use crate::outline::{HoleError, OutlineError};
use thiserror::Error;

/// Why a part or kit cannot be enumerated. Messages name the place, so a
/// catalogue report can point at the offending input.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum PrepareError {
    /// The outline breaks SPEC sections 1 and 8.1 (too few points,
    /// self-crossing...).
    #[error("part outline: {0}")]
    Outline(OutlineError),
    /// A hole breaks SPEC 9.1 (the message names it by its input index).
    #[error("part: {0}")]
    Hole(HoleError),
    /// Access constraint `index` breaks SPEC section 1.
    #[error("access constraint {index}: {source}")]
    Access {
        /// Position of the region in the part's `access` list.
        index: usize,
        /// What is wrong with it.
        source: PolygonError,
    },
    /// Lattice coordinates would come near integer overflow.
    #[error(
        "part is {extent:.3e} lattice spacings across; fixplan handles parts up to {limit:.0e}"
    )]
    TooLarge {
        /// Largest absolute coordinate, lattice units.
        extent: f64,
        /// `MAX_EXTENT` (a million lattice spacings).
        limit: f64,
    },
    /// The kit breaks SPEC section 1.
    #[error("kit: {0}")]
    Kit(String),
    /// An enumeration parameter is out of range.
    #[error("params: {0}")]
    Params(String),
    /// [`crate::PreparedPart::with_kit`] was given a kit or parameters that change
    /// the part's geometry, so only a fresh [`crate::prepare()`] gives the right part.
    #[error("cannot reuse the prepared part: the new kit or parameters change its {0}")]
    OtherGeometry(&'static str),
}

/// Largest coordinate, in lattice units, that a part may have.
pub const MAX_EXTENT: f64 = 1e6;

fn finite_pos(x: f64) -> bool {
    x.is_finite() && x > 0.0
}

/// Checks a kit against SPEC section 1 (locator size against the lattice,
/// travel order, clamp polygons).
pub fn validate_kit(kit: &Kit) -> Result<(), PrepareError> {
    let err = |m: String| Err(PrepareError::Kit(m));
    if !finite_pos(kit.spacing) {
        return err(format!("spacing {} must be a positive number", kit.spacing));
    }
    if kit.cols < 1 || kit.rows < 1 {
        return err(format!(
            "plate of {} x {} holes is empty",
            kit.cols, kit.rows
        ));
    }
    let r = kit.locator_radius;
    if !finite_pos(r) {
        return err(format!("locator_radius {r} must be a positive number"));
    }
    let limit = match kit.pattern {
        Pattern::Square => kit.spacing / 2.0,
        Pattern::Alternating => kit.spacing * std::f64::consts::SQRT_2 / 2.0,
    };
    if r >= limit {
        return err(format!(
            "locator_radius {r} is too large for a {:?} lattice of spacing {} (must be below {limit:.6})",
            kit.pattern, kit.spacing
        ));
    }
    validate_clamp(kit)
}

/// The clamp half of [`validate_kit`].
fn validate_clamp(kit: &Kit) -> Result<(), PrepareError> {
    let err = |m: String| Err(PrepareError::Kit(m));
    let c = &kit.clamp;
    if c.mount_holes.is_empty() {
        return err("clamp has no mount_holes".into());
    }
    if c.mount_holes[0].offset != [0, 0] {
        return err(format!(
            "clamp mount hole 0 is at {:?}; the clamp frame's origin is mount hole 0, so it must be [0, 0]",
            c.mount_holes[0].offset
        ));
    }
    if kit.pattern == Pattern::Square {
        // Nothing to check: every hole takes any module.
    } else if let Some(h) = c.mount_holes.iter().find(|h| h.kind == HoleKind::Any) {
        return err(format!(
            "clamp mount hole {:?} has no hole kind; an alternating plate needs \"dowel\" or \"tapped\"",
            h.offset
        ));
    }
    if !c.axis_offset.is_finite() {
        return err("clamp axis_offset is not a finite number".into());
    }
    let [t0, t1] = c.travel;
    if !t0.is_finite() || !t1.is_finite() {
        return err("clamp travel has a non-finite bound".into());
    }
    if t0 > t1 {
        return err(format!("clamp travel min {t0} is above max {t1}"));
    }
    for (name, poly) in [("body", &c.body), ("plunger", &c.plunger)] {
        if let Err(e) = validate_polygon(poly) {
            return err(format!("clamp {name} polygon {e}"));
        }
    }
    Ok(())
}

/// Checks the enumeration parameters (angle range, non-negative lengths,
/// grid step, finite wrenches).
pub fn validate_params(p: &Params, units: Units) -> Result<(), PrepareError> {
    let err = |m: String| Err(PrepareError::Params(m));
    let a = p.max_clamp_angle_deg;
    if !(a.is_finite() && a > 0.0 && a <= 90.0) {
        return err(format!("max_clamp_angle_deg {a} must be in (0, 90]"));
    }
    let t = p.edge_trim_or_default(units);
    if !(t.is_finite() && t >= 0.0) {
        return err(format!("edge_trim {t} must be a non-negative number"));
    }
    let c = p.min_clearance_or_default(units);
    if !(c.is_finite() && c >= 0.0) {
        return err(format!("min_clearance {c} must be a non-negative number"));
    }
    check_grid_step(p.grid_step)?;
    if let Some(ws) = &p.wrenches {
        if ws.is_empty() {
            return err("wrenches is an empty list (use null for the default metric)".into());
        }
        if let Some(i) = ws.iter().position(|w| w.iter().any(|x| !x.is_finite())) {
            return err(format!("wrench {i} has a non-finite component"));
        }
    }
    Ok(())
}

/// Step 0 would put every locator on the origin (and divide by zero).
pub(crate) fn check_grid_step(step: u32) -> Result<(), PrepareError> {
    if step < 1 {
        return Err(PrepareError::Params("grid_step must be at least 1".into()));
    }
    Ok(())
}
