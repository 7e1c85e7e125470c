//! One part file (DXF, SVG or JSON) to a validated [`Part`].
//!
//! Readers produce a [`RawPart`] already in the catalogue's units; one
//! validation step ([`validate_part`]) then applies the same rules to every
//! format, so a part means the same thing whatever tool drew it.

use crate::clean::clean_and_validate;
use crate::units::LengthUnit;
use fixplan_core::{Part, Units};
use std::path::Path;

/// Default chord error for flattening arcs: 0.05 mm is well inside the
/// tolerance of the cast or sawn blanks that modular fixtures hold, while a
/// 50 mm radius still flattens to about 50 edges.
pub const DEFAULT_CHORD_TOLERANCE_MM: f64 = 0.05;
/// Default gap allowed where two DXF entities should meet: CAD snapping is
/// exact to far better than this, hand-edited or converted files often not.
pub const DEFAULT_JOIN_TOLERANCE_MM: f64 = 0.01;

/// How to read one part file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReadOptions {
    /// The catalogue's units: the part comes back in these.
    pub units: Units,
    /// Units of a file that does not say (DXF `$INSUNITS` unitless, SVG
    /// without physical size, JSON without `units`).
    pub fallback: LengthUnit,
    /// Largest distance between a curve and its chords, catalogue units.
    pub chord_tolerance: f64,
    /// Largest gap closed when joining DXF entities, catalogue units.
    pub join_tolerance: f64,
}

impl ReadOptions {
    /// Defaults for a catalogue in `units`, files assumed in the same units.
    pub fn new(units: Units) -> Self {
        ReadOptions {
            units,
            fallback: units.into(),
            chord_tolerance: DEFAULT_CHORD_TOLERANCE_MM / units.mm_per_unit(),
            join_tolerance: DEFAULT_JOIN_TOLERANCE_MM / units.mm_per_unit(),
        }
    }
}

/// A part as read from a file, in catalogue units, not yet validated.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RawPart {
    pub outline: Vec<[f64; 2]>,
    pub access: Vec<Vec<[f64; 2]>>,
    pub warnings: Vec<String>,
}

/// A part file format, known by its extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Dxf,
    Svg,
    Json,
}

impl Format {
    pub fn from_path(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "dxf" => Some(Format::Dxf),
            "svg" => Some(Format::Svg),
            "json" => Some(Format::Json),
            _ => None,
        }
    }
}

/// Reads a part file's bytes without validating the polygons.
pub fn read_raw(bytes: &[u8], format: Format, opts: &ReadOptions) -> Result<RawPart, String> {
    if !(opts.chord_tolerance.is_finite() && opts.chord_tolerance > 0.0) {
        return Err(format!(
            "chord tolerance {} must be a positive number",
            opts.chord_tolerance
        ));
    }
    if !(opts.join_tolerance.is_finite() && opts.join_tolerance >= 0.0) {
        return Err(format!(
            "join tolerance {} must be a non-negative number",
            opts.join_tolerance
        ));
    }
    match format {
        Format::Dxf => crate::dxf_io::read_dxf(bytes, opts),
        Format::Svg => crate::svg_io::read_svg(bytes, opts),
        Format::Json => crate::json_io::read_json(bytes, opts),
    }
}

/// Reads and validates a part file's bytes: the part and the warnings of
/// the repairs made, or the first problem found.
pub fn parse_part(
    bytes: &[u8],
    format: Format,
    opts: &ReadOptions,
) -> Result<(Part, Vec<String>), String> {
    let raw = read_raw(bytes, format, opts)?;
    validate_part(raw, opts.units)
}

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
