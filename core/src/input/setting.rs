//! The kit and the parameters in lattice units: what they decide on their
//! own whatever the part (plate, clamp, angle, clearance, grid step,
//! top-k), converted once so the setup and mount searches never convert.

use crate::geometry::polygon::validate_polygon;
use crate::geometry::{v2, V2};
use crate::input::validate::{validate_kit, validate_params, PrepareError};
use crate::input::{Kit, MountHole, Params, Pattern, Units};

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

/// What the kit and the parameters decide on their own, whatever the part:
/// plate, clamp, angle, clearance, grid step and top-k. Split from the
/// geometry so [`crate::PreparedPart::with_kit`] can swap it without re-deriving
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
pub(crate) fn top_k_mode(top_k: usize, full_counts: bool) -> bool {
    top_k > 0 && !full_counts
}

impl Setting {
    /// Validates the kit and the parameters (in that order, as [`crate::prepare()`]
    /// reports them) and converts them to lattice units.
    pub(crate) fn new(kit: &Kit, params: &Params, units: Units) -> Result<Setting, PrepareError> {
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

/// Divides points by the lattice spacing.
pub(crate) fn scale(pts: &[[f64; 2]], l: f64) -> Vec<[f64; 2]> {
    pts.iter().map(|p| [p[0] / l, p[1] / l]).collect()
}
