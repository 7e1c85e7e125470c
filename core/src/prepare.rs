//! A part made ready for enumeration: validated, in lattice units, with its
//! segments and per-pair bounds computed once. A prepared part is what a
//! worker caches (by digest) and what every shard of the part shares.

use crate::geometry::{v2, Aabb, V2};
use crate::input::{HoleKind, Kit, MountHole, Params, Part, Pattern, Units};
use crate::locator_sweep::SweptSegment;
use crate::metric::{MaxForceMetric, Metric, WrenchListMetric};
use crate::outline::{Edge, Outline, OutlineError, Vertex};
use crate::polygon::{validate_polygon, PolygonError};
use crate::segments::{distance_range, usable_segments, Segment};
use std::sync::{Arc, OnceLock};
use thiserror::Error;

/// Why a part or kit cannot be enumerated. Messages name the place, so a
/// catalogue report can point at the offending input.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum PrepareError {
    /// The outline breaks SPEC sections 1 and 8.1 (too few points,
    /// self-crossing...).
    #[error("part outline: {0}")]
    Outline(OutlineError),
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
        /// [`MAX_EXTENT`].
        limit: f64,
    },
    /// The kit breaks SPEC section 1.
    #[error("kit: {0}")]
    Kit(String),
    /// An enumeration parameter is out of range.
    #[error("params: {0}")]
    Params(String),
    /// [`PreparedPart::with_kit`] was given a kit or parameters that change
    /// the part's geometry, so only a fresh [`prepare`] gives the right part.
    #[error("cannot reuse the prepared part: the new kit or parameters change its {0}")]
    OtherGeometry(&'static str),
}

/// Largest coordinate, in lattice units, that a part may have.
pub const MAX_EXTENT: f64 = 1e6;

/// The clamp in lattice units, so the mount search works on the lattice
/// without converting per candidate.
#[derive(Debug, Clone)]
pub(crate) struct ClampGeom {
    /// Mount holes in the clamp frame; hole 0 is the frame's origin.
    pub(crate) holes: Vec<MountHole>,
    /// The plunger axis is the line `y = y0` in the clamp frame.
    pub(crate) y0: f64,
    /// Travel: the tip centre is at `(t, y0)`, `t_min <= t <= t_max`.
    pub(crate) t_min: f64,
    /// See `t_min`.
    pub(crate) t_max: f64,
    /// CCW polygon of the fixed body, clamp frame.
    pub(crate) body: Vec<V2>,
    /// CCW polygon of the plunger at extension 0, clamp frame.
    pub(crate) plunger: Vec<V2>,
}

/// Distance range between the points of two segments: the annulus that
/// prunes the lattice points a second or third locator can take.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairBounds {
    /// Smallest distance.
    pub dmin: f64,
    /// Largest distance.
    pub dmax: f64,
}

/// What the kit and the parameters decide on their own, whatever the part:
/// plate, clamp, angle, clearance, grid step and top-k. Split from the
/// geometry so [`PreparedPart::with_kit`] can swap it without re-deriving
/// segments.
#[derive(Debug, Clone)]
pub(crate) struct Setting {
    pub(crate) pattern: Pattern,
    pub(crate) cols: i64,
    pub(crate) rows: i64,
    pub(crate) clamp: ClampGeom,
    pub(crate) cos_max_angle: f64,
    /// Lattice units.
    pub(crate) min_clearance: f64,
    pub(crate) grid_step: i64,
    pub(crate) top_k: usize,
    /// Top-k mode: skip the mount search of candidates that cannot enter
    /// the top-k (`top_k > 0` and no `full_counts`).
    pub(crate) prune_to_top_k: bool,
}

/// The default whenever a top-k is asked for: the fixtures do not need
/// the admissible count, and counting it takes a mount search per
/// candidate, most of a big part's time.
fn top_k_mode(top_k: usize, full_counts: bool) -> bool {
    top_k > 0 && !full_counts
}

impl Setting {
    /// Validates the kit and the parameters (in that order, as [`prepare`]
    /// reports them) and converts them to lattice units.
    fn new(kit: &Kit, params: &Params, units: Units) -> Result<Setting, PrepareError> {
        validate_kit(kit)?;
        validate_params(params, units)?;
        let l = kit.spacing;
        let c = &kit.clamp;
        let clamp_poly = |pts: &[[f64; 2]]| -> Vec<V2> {
            // Already validated; normalise to CCW.
            validate_polygon(&scale(pts, l))
                .unwrap_or_else(|_| pts.iter().map(|p| v2(p[0] / l, p[1] / l)).collect())
        };
        Ok(Setting {
            pattern: kit.pattern,
            cols: kit.cols as i64,
            rows: kit.rows as i64,
            clamp: ClampGeom {
                holes: c.mount_holes.clone(),
                y0: c.axis_offset / l,
                t_min: c.travel[0] / l,
                t_max: c.travel[1] / l,
                body: clamp_poly(&c.body),
                plunger: clamp_poly(&c.plunger),
            },
            cos_max_angle: params.max_clamp_angle_deg.to_radians().cos(),
            min_clearance: params.min_clearance_or_default(units) / l,
            grid_step: params.grid_step as i64,
            top_k: params.top_k,
            prune_to_top_k: top_k_mode(params.top_k, params.full_counts),
        })
    }
}

/// A part ready for enumeration: the part, kit and parameters validated and
/// converted to lattice units, with everything that does not depend on the
/// combination range computed once (usable segments, their pair bounds, the
/// metric).
///
/// It exists so that work on one part is split without repeating that
/// preparation: a worker caches it by the digest of its inputs, and every
/// shard of the part enumerates a range of combinations against the same
/// value ([`Self::enumerate_range`]). [`prepare`] is deterministic, so a
/// worker and the coordinator that prepare the same inputs hold the same
/// part bit for bit.
///
/// It depends on the part (outline and access regions), on the kit's
/// spacing and locator radius, on the edge trim and on the wrenches (the
/// geometry), and on the rest of the kit and parameters (plate, clamp,
/// angle, clearance, grid step, top-k: the setting). A study or a
/// coarse-to-fine search changes only the setting: [`Self::with_kit`] and
/// [`Self::with_grid_step`] give the part [`prepare`] would without
/// deriving the geometry again.
#[derive(Debug, Clone)]
pub struct PreparedPart {
    /// Catalogue units per lattice unit.
    pub(crate) spacing: f64,
    /// Locator (and clamp tip) radius, lattice units.
    pub(crate) r: f64,
    /// Edge trim, lattice units (kept to check [`Self::with_kit`]).
    pub(crate) trim: f64,
    /// `params.wrenches` (kept to check [`Self::with_kit`]).
    pub(crate) wrenches: Option<Vec<[f64; 3]>>,
    /// CCW outline, lattice units.
    pub(crate) outline: Outline,
    /// Bounding box of the outline (part frame), arcs included.
    pub(crate) outline_box: Aabb,
    pub(crate) access: Vec<Vec<V2>>,
    pub(crate) segments: Vec<Segment>,
    pub(crate) metric: Arc<dyn Metric>,
    /// `pair[a * n + b]`: distance range between segments a and b, computed
    /// on the first enumeration: they are about half of `prepare` (n^2
    /// segment distances), and a coordinator prepares the parts it cuts
    /// into shards only to count their combinations and finish their
    /// results, which needs no bounds. Shared by clones, so a study's
    /// kits computes them once.
    pub(crate) pair: Arc<OnceLock<Vec<PairBounds>>>,
    /// Each segment as the setup sweep uses it, so that choosing a
    /// combination's pivot costs no trig per combination.
    pub(crate) swept: Vec<SweptSegment>,
    pub(crate) setting: Setting,
}

fn finite_pos(x: f64) -> bool {
    x.is_finite() && x > 0.0
}

/// Divides points by the lattice spacing.
fn scale(pts: &[[f64; 2]], l: f64) -> Vec<[f64; 2]> {
    pts.iter().map(|p| [p[0] / l, p[1] / l]).collect()
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
fn check_grid_step(step: u32) -> Result<(), PrepareError> {
    if step < 1 {
        return Err(PrepareError::Params("grid_step must be at least 1".into()));
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
    let setting = Setting::new(kit, params, units)?;
    let l = kit.spacing;
    let (outline, access) = lattice_polygons(part, l)?;
    let r = kit.locator_radius / l;
    let trim = params.edge_trim_or_default(units) / l;
    let segments = usable_segments(&outline, &access, r, trim);
    let swept = segments.iter().map(SweptSegment::of).collect();
    let metric = metric(params.wrenches.as_deref(), &outline, l);
    Ok(PreparedPart {
        spacing: l,
        r,
        trim,
        wrenches: params.wrenches.clone(),
        outline_box: outline.aabb(),
        outline,
        access,
        segments,
        metric,
        pair: Arc::default(),
        swept,
        setting,
    })
}

/// The outline and access regions, validated and CCW in lattice units.
fn lattice_polygons(part: &Part, l: f64) -> Result<(Outline, Vec<Vec<V2>>), PrepareError> {
    // Validate in the user's unit so error coordinates are the user's.
    Outline::new(&part.outline).map_err(PrepareError::Outline)?;
    // A bulge is an angle: scaling leaves it as it is.
    let scaled: Vec<Vertex> = part
        .outline
        .iter()
        .map(|v| Vertex::new(v.x / l, v.y / l, v.bulge))
        .collect();
    let outline = Outline::new(&scaled).map_err(PrepareError::Outline)?;
    let mut access = Vec::with_capacity(part.access.len());
    for (index, a) in part.access.iter().enumerate() {
        let at = |source| PrepareError::Access { index, source };
        validate_polygon(a).map_err(at)?;
        access.push(validate_polygon(&scale(a, l)).map_err(at)?);
    }
    // Lattice coordinates are enumerated as integers: keep them far from
    // overflow (a part 10^6 spacings across is 25 km on a 25 mm plate).
    // An arc reaches beyond its end points (a bulge of 1e9 on a 10 mm
    // chord is a circle of radius 2.5e9 mm): its whole circle counts.
    let arcs = outline.edges().iter().filter_map(|e| match e {
        Edge::Arc(arc) => Some(arc.center.x.abs().max(arc.center.y.abs()) + arc.radius),
        Edge::Line { .. } => None,
    });
    let extent = outline
        .points()
        .iter()
        .chain(access.iter().flatten())
        .fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()));
    let extent = arcs.fold(extent, f64::max);
    if extent > MAX_EXTENT {
        return Err(PrepareError::TooLarge {
            extent,
            limit: MAX_EXTENT,
        });
    }
    Ok((outline, access))
}

/// Distance ranges between every ordered pair of segments.
fn pair_bounds(segments: &[Segment]) -> Vec<PairBounds> {
    let mut pair = Vec::with_capacity(segments.len() * segments.len());
    for a in segments {
        for b in segments {
            let (dmin, dmax) = distance_range(a, b);
            pair.push(PairBounds { dmin, dmax });
        }
    }
    pair
}

/// The user's wrenches, or SPEC 6's default about the true region's
/// centroid (SPEC 8.1: arcs included).
fn metric(wrenches: Option<&[[f64; 3]]>, outline: &Outline, l: f64) -> Arc<dyn Metric> {
    match wrenches {
        Some(ws) => Arc::new(WrenchListMetric::new(ws, l)),
        None => {
            let mass = outline.mass_properties();
            Arc::new(MaxForceMetric::new(
                mass.centroid,
                mass.radius_of_gyration(),
            ))
        }
    }
}

/// Bitwise float equality: `-0.0` and `0.0` can round differently later,
/// and the study's cache key tells them apart too.
fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits()
}

impl PreparedPart {
    /// `prepare(part, kit, params, units)` for the part this was prepared
    /// from, reusing its segments, pair bounds and metric: only the
    /// setting (plate, clamp, angle, clearance, grid step, top-k) is
    /// converted again. A study solves one part with many kits this way.
    ///
    /// Precondition: `kit` and `params` keep the geometry, that is the
    /// same spacing, locator radius, edge trim (after defaults) and
    /// wrenches, bit for bit. This is checked, not assumed: otherwise the
    /// answer is [`PrepareError::OtherGeometry`] (after the kit and
    /// parameter errors a [`prepare`] would report first).
    pub fn with_kit(
        &self,
        kit: &Kit,
        params: &Params,
        units: Units,
    ) -> Result<PreparedPart, PrepareError> {
        let setting = Setting::new(kit, params, units)?;
        let l = kit.spacing;
        let wrenches_same = match (&self.wrenches, &params.wrenches) {
            (None, None) => true,
            (Some(a), Some(b)) => {
                a.len() == b.len()
                    && a.iter()
                        .flatten()
                        .zip(b.iter().flatten())
                        .all(|(x, y)| same(*x, *y))
            }
            _ => false,
        };
        let differs = [
            (!same(l, self.spacing), "lattice spacing"),
            (!same(kit.locator_radius / l, self.r), "locator radius"),
            (
                !same(params.edge_trim_or_default(units) / l, self.trim),
                "edge trim",
            ),
            (!wrenches_same, "wrenches"),
        ];
        if let Some((_, what)) = differs.iter().find(|d| d.0) {
            return Err(PrepareError::OtherGeometry(what));
        }
        Ok(PreparedPart {
            setting,
            ..self.clone()
        })
    }

    /// The part with locators 2 and 3 on multiples of `step`: what
    /// [`prepare`] gives with `params.grid_step = step`, for a coarse-to-fine
    /// search that runs several steps on one part. Step 0 is refused as
    /// [`validate_params`] refuses it.
    pub fn with_grid_step(&self, step: u32) -> Result<PreparedPart, PrepareError> {
        check_grid_step(step)?;
        let mut p = self.clone();
        p.setting.grid_step = step as i64;
        Ok(p)
    }

    /// The part keeping the best `top_k` (0: all), in top-k mode unless
    /// `full_counts`: what [`prepare`] gives with those parameters, for a
    /// bench that measures both modes on one part.
    pub fn with_top_k(&self, top_k: usize, full_counts: bool) -> PreparedPart {
        let mut p = self.clone();
        p.setting.top_k = top_k;
        p.setting.prune_to_top_k = top_k_mode(top_k, full_counts);
        p
    }

    /// Distance range between segments `a` and `b` (pruning bound).
    #[inline]
    pub fn pair(&self, a: usize, b: usize) -> PairBounds {
        self.pair_table()[a * self.segments.len() + b]
    }

    /// Every pair's [`Self::pair`], `a * n + b`: for loops that look up
    /// many pairs and should check only once that they are computed.
    #[inline]
    pub(crate) fn pair_table(&self) -> &[PairBounds] {
        self.pair.get_or_init(|| pair_bounds(&self.segments))
    }

    /// The usable segments (SPEC section 2), in the order that numbers
    /// combinations and fixtures: a fixture's segment indices point here.
    #[inline]
    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }

    /// The CCW outline in lattice units, the frame of the segments and of
    /// the part contacts a metric scores.
    #[inline]
    pub fn outline(&self) -> &Outline {
        &self.outline
    }

    /// Locator (and clamp tip) radius in lattice units: the distance from
    /// the part edge to the grown edge the segments lie on.
    #[inline]
    pub fn locator_radius(&self) -> f64 {
        self.r
    }

    /// Cosine of the largest angle between the plunger axis and a clamped
    /// edge's inward normal.
    #[inline]
    pub fn cos_max_angle(&self) -> f64 {
        self.setting.cos_max_angle
    }

    /// How many fixtures a result keeps (0: all); merging shards needs it.
    #[inline]
    pub fn top_k(&self) -> usize {
        self.setting.top_k
    }

    /// Whether results count admissible fixtures: not in top-k mode
    /// (`top_k > 0` without `full_counts`), which skips the mount search
    /// of candidates that cannot enter the top-k.
    #[inline]
    pub fn counts_exact(&self) -> bool {
        !self.setting.prune_to_top_k
    }

    /// The grid step locators 2 and 3 are enumerated at.
    #[inline]
    pub fn grid_step(&self) -> u32 {
        self.setting.grid_step as u32
    }
}
