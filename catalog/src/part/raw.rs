//! What every reader produces and takes: a [`RawPart`] in the catalogue's
//! units, the [`ReadOptions`] it was read with, the [`Format`] of the file.
//! Kept apart from the readers so that they, validation and the manifest
//! can all use these types without using each other.

use crate::units::LengthUnit;
use fixplan_core::Units;
use std::fmt;
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

/// A part as read from a file, in catalogue units, not yet validated: what
/// every reader hands to the one validation, so formats cannot disagree
/// about what a valid part is.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RawPart {
    /// The part's outer outline, in file order.
    pub outline: Vec<[f64; 2]>,
    /// Regions that must stay free of fixture elements.
    pub access: Vec<Vec<[f64; 2]>>,
    /// What the reader ignored or assumed, for the user to check.
    pub warnings: Vec<String>,
}

/// A part file format, known by its extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// AutoCAD DXF, ASCII (R12 to current).
    Dxf,
    /// SVG 1.1 geometry.
    Svg,
    /// The `part` / `access` fields of SPEC Appendix A.
    Json,
}

impl Format {
    /// The format a file name says, so a directory can hold notes and
    /// images next to its parts; `None` for anything else.
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

/// Which polygon of a part a message is about; part of every reader's and
/// the validation's messages so the user knows where to look.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PolygonRole {
    /// The part's outline.
    Outline,
    /// Access constraint number `.0` (from 0, in file order).
    Access(usize),
}

impl fmt::Display for PolygonRole {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PolygonRole::Outline => f.write_str("outline"),
            PolygonRole::Access(i) => write!(f, "access constraint {i}"),
        }
    }
}
