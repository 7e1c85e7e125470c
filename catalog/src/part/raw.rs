//! What every reader produces and takes: a [`RawPart`] in the catalogue's
//! units, the [`ReadOptions`] it was read with, the [`Format`] of the file.
//! Kept apart from the readers so that they, validation and the manifest
//! can all use these types without using each other.

use crate::units::LengthUnit;
use fixplan_core::Units;
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
