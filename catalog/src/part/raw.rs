//! What every reader produces and takes: a [`RawPart`] in the catalogue's
//! units, the [`ReadOptions`] it was read with, the [`Format`] of the file.
//! Kept apart from the readers so that they, validation and the manifest
//! can all use these types without using each other.

use crate::units::LengthUnit;
use fixplan_core::outline::Vertex;
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
    /// Circular arcs kept exact (bulge vertices) or flattened into chords.
    pub arcs: ArcMode,
}

/// What the readers make of circular arcs (DXF bulges, ARC and CIRCLE
/// entities, SVG `A` commands with equal radii under a similarity, SVG
/// circles): exact arcs, as SPEC 8 enumerates them, or chords within the
/// chord tolerance, as fixplan read them before arcs were supported (for
/// comparison). Ellipses, splines and Bézier curves are flattened either
/// way; access constraints are always polygons.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ArcMode {
    /// Arcs become bulge vertices (SPEC 8.1).
    #[default]
    Exact,
    /// Arcs become chords within the chord tolerance.
    Flatten,
}

impl ArcMode {
    /// The values a manifest's `arcs` and the `--arcs` flag take.
    pub const NAMES: [&'static str; 2] = ["exact", "flatten"];

    /// `"exact"` or `"flatten"` (any case); `None` for anything else.
    pub fn parse(s: &str) -> Option<ArcMode> {
        match s.trim().to_ascii_lowercase().as_str() {
            "exact" => Some(ArcMode::Exact),
            "flatten" => Some(ArcMode::Flatten),
            _ => None,
        }
    }

    /// The name [`ArcMode::parse`] reads.
    pub fn name(self) -> &'static str {
        match self {
            ArcMode::Exact => "exact",
            ArcMode::Flatten => "flatten",
        }
    }

    /// Whether arcs are flattened.
    pub fn flatten(self) -> bool {
        self == ArcMode::Flatten
    }
}

impl fmt::Display for ArcMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for ArcMode {
    type Err = String;

    fn from_str(s: &str) -> Result<ArcMode, String> {
        ArcMode::parse(s)
            .ok_or_else(|| format!("unknown arcs mode \"{s}\" (expected \"exact\" or \"flatten\")"))
    }
}

impl ReadOptions {
    /// Defaults for a catalogue in `units`, files assumed in the same units.
    pub fn new(units: Units) -> Self {
        ReadOptions {
            units,
            fallback: units.into(),
            chord_tolerance: DEFAULT_CHORD_TOLERANCE_MM / units.mm_per_unit(),
            join_tolerance: DEFAULT_JOIN_TOLERANCE_MM / units.mm_per_unit(),
            arcs: ArcMode::Exact,
        }
    }
}

/// A part as read from a file, in catalogue units, not yet validated: what
/// every reader hands to the one validation, so formats cannot disagree
/// about what a valid part is.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RawPart {
    /// The part's outer outline, in file order; a vertex's bulge makes the
    /// edge to the next vertex an arc (SPEC 8.1).
    pub outline: Vec<Vertex>,
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
