//! Kits: TOML files with the fields of SPEC section 1, and built-in kits.
//!
//! A kit file is flat: the [`Kit`] fields at the top level, a `[clamp]`
//! table, an optional `[params]` table (SPEC defaults for anything left
//! out), optional `name` and `units` (`mm` or `in`, default `mm`):
//!
//! ```toml
//! name = "shop-plate"
//! units = "mm"
//! spacing = 25.0
//! cols = 20
//! rows = 20
//! pattern = "square"
//! locator_radius = 6.0
//! [clamp]
//! mount_holes = [[0, 0], [1, 0]]
//! axis_offset = 0.0
//! travel = [60.0, 92.0]
//! body = [[-16, -16], [50, -16], [50, 16], [-16, 16]]
//! plunger = [[-70, -5], [-6, -5], [-6, 5], [-70, 5]]
//! [params]
//! max_clamp_angle_deg = 45
//! top_k = 10
//! ```

use crate::error::CatalogError;
use crate::kit_limits::check_kit_sizes;
use crate::units::parse_units;
use fixplan_core::{validate_kit, Clamp, HoleKind, Kit, MountHole, Params, Pattern, Units};
use std::path::Path;

/// The kit of Brost & Goldberg's examples (1996, section VII: "an 18 x 18
/// array of alternating dowel/threaded holes, with a spacing of 0.75 in.
/// The fixel radius is 0.25 in"). The paper draws its toggle clamp without
/// dimensions; ours is the one of the repository's benchmark cases
/// (`bench/housing-57.json`): bolted to a dowel hole and the tapped hole
/// next to it, a 1.6 x 0.8 in body footprint (handle sweep included), a
/// 0.24 in plunger and 1.25 in of travel.
pub const PAPER_INCH: &str = "paper-inch";

/// A metric kit with the proportions of common 25 mm-pitch modular
/// fixturing systems: a 500 x 500 mm plate (20 x 20 holes) whose holes all
/// take both bolts and pins (square pattern), round locating pins of 12 mm
/// diameter (the usual pin size for a 25 mm grid), and a push-type toggle
/// clamp of the size usually mounted on such plates: 66 x 32 mm footprint
/// over two holes, an M10 spindle (plunger 10 mm wide) and 32 mm of stroke.
/// Figures are rounded typical catalogue values, not one vendor's part.
pub const METRIC_25: &str = "metric-25";

const BUILTIN: &[&str] = &[PAPER_INCH, METRIC_25];

/// Names of the built-in kits, for help texts and for the error of an
/// unknown kit name.
pub fn builtin_kit_names() -> &'static [&'static str] {
    BUILTIN
}

/// A kit with its enumeration parameters (defaults filled in), all lengths
/// in the catalogue's units, so that it can be used with any part of the
/// catalogue as it is.
#[derive(Debug, Clone)]
pub struct KitSpec {
    /// The kit file's `name`, else its file stem, or the built-in name:
    /// what results and study tables call the kit.
    pub name: String,
    /// Plate, locators and clamp.
    pub kit: Kit,
    /// Enumeration parameters, SPEC defaults filled in for the units.
    pub params: Params,
}

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<[f64; 2]> {
    vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
}

/// A built-in kit in its native units, the ones its figures were chosen
/// in, so it can be written out or scaled without rounding twice.
pub fn builtin_kit(name: &str) -> Option<(Kit, Units)> {
    match name {
        PAPER_INCH => Some((
            Kit {
                spacing: 0.75,
                cols: 18,
                rows: 18,
                pattern: Pattern::Alternating,
                locator_radius: 0.25,
                clamp: Clamp {
                    mount_holes: vec![
                        MountHole {
                            offset: [0, 0],
                            kind: HoleKind::Dowel,
                        },
                        MountHole {
                            offset: [1, 0],
                            kind: HoleKind::Tapped,
                        },
                    ],
                    axis_offset: 0.0,
                    travel: [1.5, 2.75],
                    body: rect(-0.4, -0.4, 1.2, 0.4),
                    plunger: rect(-2.5, -0.12, -0.25, 0.12),
                },
            },
            Units::In,
        )),
        METRIC_25 => Some((
            Kit {
                spacing: 25.0,
                cols: 20,
                rows: 20,
                pattern: Pattern::Square,
                locator_radius: 6.0,
                clamp: Clamp {
                    mount_holes: vec![
                        MountHole {
                            offset: [0, 0],
                            kind: HoleKind::Any,
                        },
                        MountHole {
                            offset: [1, 0],
                            kind: HoleKind::Any,
                        },
                    ],
                    axis_offset: 0.0,
                    travel: [60.0, 92.0],
                    body: rect(-16.0, -16.0, 50.0, 16.0),
                    plunger: rect(-70.0, -5.0, -6.0, 5.0),
                },
            },
            Units::Mm,
        )),
        _ => None,
    }
}

/// Scales every length of a kit and its parameters by `factor` (one unit to
/// another). Torques in expected wrenches are force x length and scale too.
pub fn scale_kit(kit: &Kit, params: &Params, factor: f64) -> (Kit, Params) {
    let pts = |v: &[[f64; 2]]| v.iter().map(|p| [p[0] * factor, p[1] * factor]).collect();
    let kit = Kit {
        spacing: kit.spacing * factor,
        cols: kit.cols,
        rows: kit.rows,
        pattern: kit.pattern,
        locator_radius: kit.locator_radius * factor,
        clamp: Clamp {
            mount_holes: kit.clamp.mount_holes.clone(),
            axis_offset: kit.clamp.axis_offset * factor,
            travel: [kit.clamp.travel[0] * factor, kit.clamp.travel[1] * factor],
            body: pts(&kit.clamp.body),
            plunger: pts(&kit.clamp.plunger),
        },
    };
    let params = Params {
        edge_trim: params.edge_trim.map(|x| x * factor),
        min_clearance: params.min_clearance.map(|x| x * factor),
        wrenches: params
            .wrenches
            .as_ref()
            .map(|ws| ws.iter().map(|w| [w[0], w[1], w[2] * factor]).collect()),
        ..params.clone()
    };
    (kit, params)
}

fn invalid(path: &Path, message: String) -> CatalogError {
    CatalogError::Invalid {
        path: path.to_path_buf(),
        message,
    }
}

/// Parses a kit TOML text: the kit, its parameters (as written), its
/// native units and its name if given.
pub fn parse_kit_toml(
    text: &str,
    path: &Path,
) -> Result<(Kit, Params, Units, Option<String>), CatalogError> {
    let mut table: toml::Table = text
        .parse()
        .map_err(|e: toml::de::Error| invalid(path, format!("not a readable kit TOML: {e}")))?;
    let name = match table.remove("name") {
        None => None,
        Some(toml::Value::String(s)) => Some(s),
        Some(v) => return Err(invalid(path, format!("kit name {v} is not a string"))),
    };
    let units = match table.remove("units") {
        None => Units::Mm,
        Some(toml::Value::String(s)) => {
            parse_units(&s).map_err(|e| invalid(path, e.to_string()))?
        }
        Some(v) => return Err(invalid(path, format!("unknown units {v}"))),
    };
    let params: Params = match table.remove("params") {
        None => Params::default(),
        Some(v) => v
            .try_into()
            .map_err(|e: toml::de::Error| invalid(path, format!("[params]: {}", e.message())))?,
    };
    let kit: Kit = toml::Value::Table(table)
        .try_into()
        .map_err(|e: toml::de::Error| invalid(path, format!("kit: {}", e.message())))?;
    Ok((kit, params, units, name))
}

/// Writes a kit and its parameters as a kit TOML that [`parse_kit_toml`]
/// reads back.
pub fn write_kit_toml(name: &str, kit: &Kit, params: &Params, units: Units) -> String {
    let mut t = toml::Table::new();
    t.insert("name".into(), toml::Value::String(name.into()));
    t.insert("units".into(), toml::Value::String(units.label().into()));
    if let Ok(toml::Value::Table(k)) = toml::Value::try_from(kit) {
        t.extend(k);
    }
    if let Ok(p) = toml::Value::try_from(params) {
        t.insert("params".into(), p);
    }
    toml::to_string(&t).unwrap_or_default()
}

/// Fills SPEC's defaults (for the target units) into the parameters and
/// checks kit and parameters with core's own rules, so a kit that loads
/// here is a kit the solver accepts.
fn finish(
    name: String,
    kit: Kit,
    params: Params,
    units: Units,
    path: &Path,
) -> Result<KitSpec, CatalogError> {
    check_kit_sizes(&kit).map_err(|e| invalid(path, format!("kit {name}: {e}")))?;
    validate_kit(&kit).map_err(|e| invalid(path, format!("kit {name}: {e}")))?;
    let params = Params {
        edge_trim: Some(params.edge_trim_or_default(units)),
        min_clearance: Some(params.min_clearance_or_default(units)),
        ..params
    };
    fixplan_core::validate_params(&params, units)
        .map_err(|e| invalid(path, format!("kit {name}: {e}")))?;
    Ok(KitSpec { name, kit, params })
}

/// A built-in kit by name, or a kit TOML file; lengths converted to `units`
/// (the catalogue's), and checked with core's rules so that a kit that
/// loads is one the solver accepts.
pub fn load_kit(name_or_path: &str, units: Units) -> Result<KitSpec, CatalogError> {
    if let Some((kit, native)) = builtin_kit(name_or_path) {
        let f = native.mm_per_unit() / units.mm_per_unit();
        let (kit, params) = scale_kit(&kit, &Params::default(), f);
        return finish(
            name_or_path.to_string(),
            kit,
            params,
            units,
            Path::new(name_or_path),
        );
    }
    let path = Path::new(name_or_path);
    if !path.is_file() {
        return Err(invalid(
            path,
            format!(
                "no such kit: not a built-in kit ({}) and not a kit file",
                BUILTIN.join(", ")
            ),
        ));
    }
    let text = std::fs::read_to_string(path).map_err(|source| CatalogError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let (kit, params, native, name) = parse_kit_toml(&text, path)?;
    let name = name.unwrap_or_else(|| {
        path.file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| name_or_path.to_string())
    });
    let f = native.mm_per_unit() / units.mm_per_unit();
    let (kit, params) = scale_kit(&kit, &params, f);
    finish(name, kit, params, units, path)
}
