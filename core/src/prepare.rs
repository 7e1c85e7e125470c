//! A part made ready for enumeration: validated, in lattice units, with its
//! segments and per-pair bounds computed once. A prepared part is what a
//! worker caches (by digest) and what every shard of the part shares.

use crate::geometry::{centroid_and_polar_moment, segment_segment_dist2, v2, Aabb, V2};
use crate::input::{HoleKind, Kit, MountHole, Params, Part, Pattern, Units};
use crate::metric::{MaxForceMetric, Metric, WrenchListMetric};
use crate::polygon::{validate_polygon, PolygonError};
use crate::segments::{usable_segments, Segment};
use std::sync::Arc;
use thiserror::Error;

/// Why a part or kit cannot be enumerated. Messages name the place.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum PrepareError {
    #[error("part outline: {0}")]
    Outline(PolygonError),
    #[error("access constraint {index}: {source}")]
    Access { index: usize, source: PolygonError },
    #[error(
        "part is {extent:.3e} lattice spacings across; fixplan handles parts up to {limit:.0e}"
    )]
    TooLarge { extent: f64, limit: f64 },
    #[error("kit: {0}")]
    Kit(String),
    #[error("params: {0}")]
    Params(String),
}

/// Largest coordinate, in lattice units, that a part may have.
pub const MAX_EXTENT: f64 = 1e6;

/// The clamp in lattice units.
#[derive(Debug, Clone)]
pub struct ClampGeom {
    pub holes: Vec<MountHole>,
    pub y0: f64,
    pub t_min: f64,
    pub t_max: f64,
    /// CCW polygons in the clamp frame.
    pub body: Vec<V2>,
    pub plunger: Vec<V2>,
}

/// Distance range between the points of two segments.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairBounds {
    pub dmin: f64,
    pub dmax: f64,
}

#[derive(Debug, Clone)]
pub struct PreparedPart {
    pub units: Units,
    /// Catalogue units per lattice unit.
    pub spacing: f64,
    /// Locator (and clamp tip) radius, lattice units.
    pub r: f64,
    /// CCW outline, lattice units.
    pub part: Vec<V2>,
    pub part_box: Aabb,
    pub access: Vec<Vec<V2>>,
    pub segments: Vec<Segment>,
    pub pattern: Pattern,
    pub cols: i64,
    pub rows: i64,
    pub clamp: ClampGeom,
    pub cos_max_angle: f64,
    pub min_clearance: f64,
    pub grid_step: i64,
    pub top_k: usize,
    pub metric: Arc<dyn Metric>,
    /// `pair[a * n + b]`: distance range between segments a and b.
    pub pair: Vec<PairBounds>,
}

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
    if p.grid_step < 1 {
        return err("grid_step must be at least 1".into());
    }
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

/// Validates and converts a part, kit and parameters into lattice units and
/// computes everything that does not depend on the combination range.
pub fn prepare(
    part: &Part,
    kit: &Kit,
    params: &Params,
    units: Units,
) -> Result<PreparedPart, PrepareError> {
    validate_kit(kit)?;
    validate_params(params, units)?;
    let l = kit.spacing;
    let scale =
        |pts: &[[f64; 2]]| -> Vec<[f64; 2]> { pts.iter().map(|p| [p[0] / l, p[1] / l]).collect() };
    // Validate in the user's unit so error coordinates are the user's.
    validate_polygon(&part.outline).map_err(PrepareError::Outline)?;
    let outline = validate_polygon(&scale(&part.outline)).map_err(PrepareError::Outline)?;
    let mut access = Vec::with_capacity(part.access.len());
    for (index, a) in part.access.iter().enumerate() {
        validate_polygon(a).map_err(|source| PrepareError::Access { index, source })?;
        access.push(
            validate_polygon(&scale(a)).map_err(|source| PrepareError::Access { index, source })?,
        );
    }
    // Lattice coordinates are enumerated as integers: keep them far from
    // overflow (a part 10^6 spacings across is 25 km on a 25 mm plate).
    let extent = outline
        .iter()
        .chain(access.iter().flatten())
        .fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()));
    if extent > MAX_EXTENT {
        return Err(PrepareError::TooLarge {
            extent,
            limit: MAX_EXTENT,
        });
    }
    let r = kit.locator_radius / l;
    let trim = params.edge_trim_or_default(units) / l;
    let segments = usable_segments(&outline, &access, r, trim);
    let n = segments.len();
    let mut pair = Vec::with_capacity(n * n);
    for a in &segments {
        for b in &segments {
            let dmin = segment_segment_dist2(a.start(), a.end(), b.start(), b.end()).sqrt();
            let dmax = [
                (a.start() - b.start()).norm(),
                (a.start() - b.end()).norm(),
                (a.end() - b.start()).norm(),
                (a.end() - b.end()).norm(),
            ]
            .into_iter()
            .fold(0.0, f64::max);
            pair.push(PairBounds { dmin, dmax });
        }
    }
    let c = &kit.clamp;
    let clamp_poly = |pts: &[[f64; 2]]| -> Vec<V2> {
        // Already validated; normalise to CCW.
        validate_polygon(&scale(pts))
            .unwrap_or_else(|_| pts.iter().map(|p| v2(p[0] / l, p[1] / l)).collect())
    };
    let clamp = ClampGeom {
        holes: c.mount_holes.clone(),
        y0: c.axis_offset / l,
        t_min: c.travel[0] / l,
        t_max: c.travel[1] / l,
        body: clamp_poly(&c.body),
        plunger: clamp_poly(&c.plunger),
    };
    let metric: Arc<dyn Metric> = match &params.wrenches {
        Some(ws) => Arc::new(WrenchListMetric::new(ws, l)),
        None => {
            let (centroid, j) = centroid_and_polar_moment(&outline);
            let area = crate::geometry::signed_area(&outline).abs();
            Arc::new(MaxForceMetric::new(centroid, (j / area).sqrt()))
        }
    };
    Ok(PreparedPart {
        units,
        spacing: l,
        r,
        part_box: Aabb::of(&outline),
        part: outline,
        access,
        segments,
        pattern: kit.pattern,
        cols: kit.cols as i64,
        rows: kit.rows as i64,
        clamp,
        cos_max_angle: params.max_clamp_angle_deg.to_radians().cos(),
        min_clearance: params.min_clearance_or_default(units) / l,
        grid_step: params.grid_step as i64,
        top_k: params.top_k,
        metric,
        pair,
    })
}

impl PreparedPart {
    pub fn pair(&self, a: usize, b: usize) -> PairBounds {
        self.pair[a * self.segments.len() + b]
    }
}
