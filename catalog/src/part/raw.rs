//! What every reader produces and takes: a [`RawPart`] in the catalogue's
//! units, the [`ReadOptions`] it was read with, the [`Format`] of the file.
//! Kept apart from the readers so that they, validation and the manifest
//! can all use these types without using each other.

use crate::units::LengthUnit;
use fixplan_core::{Units, Vertex};
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
#[derive(Debug, Clone, PartialEq)]
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
    /// Every outer loop of the file is a part of its own (a sheet of
    /// nested parts), read with [`read_parts`](super::read_parts);
    /// otherwise a second outer loop is an error.
    pub sheet: bool,
    /// Which layers of a DXF drawing are read.
    pub layers: LayerFilter,
    /// How much work and memory one file may cost.
    pub limits: Limits,
    /// Whether loops inside the outline are the part's holes (SPEC 9) or
    /// dropped with a warning, as before holes were supported.
    pub holes: HoleMode,
}

/// Layers of a DXF drawing to read, for drawings whose borders,
/// dimensions, title blocks and construction lines are on layers of their
/// own. Names match without regard to case or surrounding spaces.
/// Access/keepout layers are read unless `ignore` names them.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LayerFilter {
    /// Only these layers (empty: all).
    pub read: Vec<String>,
    /// Never these layers.
    pub ignore: Vec<String>,
}

impl LayerFilter {
    /// A layer's name as the filter compares it: trimmed, ASCII case
    /// folded (for sets of names; [`LayerFilter::reads`] compares without
    /// allocating, to the same effect).
    pub fn key(layer: &str) -> String {
        layer.trim().to_ascii_lowercase()
    }

    /// Whether `ignore` names `layer`: nothing on it is read, not even the
    /// blocks an INSERT on it places.
    pub fn ignores(&self, layer: &str) -> bool {
        names(&self.ignore, layer)
    }

    /// Whether an entity on `layer` is read; `access` says the layer holds
    /// access constraints, which `read` does not need to name.
    pub fn reads(&self, layer: &str, access: bool) -> bool {
        !self.ignores(layer) && (access || self.read.is_empty() || names(&self.read, layer))
    }
}

/// Whether `list` names `layer`, as [`LayerFilter::key`] compares.
fn names(list: &[String], layer: &str) -> bool {
    list.iter()
        .any(|l| l.trim().eq_ignore_ascii_case(layer.trim()))
}

/// Bounds on what one part file may cost to read, whatever it holds: a
/// file over any of them is refused with a message naming the limit and
/// the manifest key that raises it (`[limits]`, the field's name).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// Largest file, bytes (`file_bytes`).
    pub file_bytes: u64,
    /// Most entities of a DXF drawing, those of exploded blocks included
    /// (`entities`).
    pub entities: usize,
    /// Most vertices of all loops and pieces together, curves flattened
    /// (`vertices`).
    pub vertices: usize,
    /// Deepest nesting of DXF block references (`block_depth`).
    pub block_depth: usize,
    /// Most straight pieces one SPLINE is flattened into (`spline_pieces`).
    pub spline_pieces: usize,
}

impl Limits {
    /// The keys of a manifest's `[limits]` table, as [`Limits::set`] takes
    /// them.
    pub const KEYS: [&'static str; 5] = [
        "file_bytes",
        "entities",
        "vertices",
        "block_depth",
        "spline_pieces",
    ];

    /// Sets the limit named `key` (one of [`Limits::KEYS`]); `false` for
    /// an unknown key.
    pub fn set(&mut self, key: &str, value: u64) -> bool {
        let v = usize::try_from(value).unwrap_or(usize::MAX);
        match key {
            "file_bytes" => self.file_bytes = value,
            "entities" => self.entities = v,
            "vertices" => self.vertices = v,
            "block_depth" => self.block_depth = v,
            "spline_pieces" => self.spline_pieces = v,
            _ => return false,
        }
        true
    }

    /// A file of `len` bytes within [`Limits::file_bytes`], or the limit it
    /// goes over.
    pub fn check_file_bytes(&self, len: u64) -> Result<(), LimitExceeded> {
        if len <= self.file_bytes {
            return Ok(());
        }
        Err(LimitExceeded {
            what: format!("the file's {len} bytes"),
            limit: self.file_bytes,
            key: "file_bytes",
        })
    }
}

impl Default for Limits {
    /// Generous for any real part drawing (the largest sheets seen have a
    /// few ten thousand entities), small enough that a hostile file costs
    /// seconds and a few hundred MB at most.
    fn default() -> Limits {
        Limits {
            file_bytes: 64 << 20,
            entities: 200_000,
            vertices: 2_000_000,
            block_depth: 16,
            spline_pieces: 100_000,
        }
    }
}

/// A limit of [`Limits`] that a file goes over.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{what} is over the limit of {limit}; if the file is what you mean, raise it with `{key} = ...` in the manifest's [limits] table")]
pub struct LimitExceeded {
    /// What was counted, e.g. "the file's 70000000 bytes".
    pub what: String,
    /// The limit.
    pub limit: u64,
    /// Its key in [`Limits::KEYS`].
    pub key: &'static str,
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
    pub fn parse(text: &str) -> Option<ArcMode> {
        match text.trim().to_ascii_lowercase().as_str() {
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
    fn fmt(&self, formatter: &mut fmt::Formatter<'_>) -> fmt::Result {
        formatter.write_str(self.name())
    }
}

impl std::str::FromStr for ArcMode {
    type Err = String;

    fn from_str(text: &str) -> Result<ArcMode, String> {
        ArcMode::parse(text).ok_or_else(|| {
            format!("unknown arcs mode \"{text}\" (expected \"exact\" or \"flatten\")")
        })
    }
}

/// What the readers make of loops inside a part's outline: its holes
/// (SPEC 9: bores and windows a locator may stand in, material a clamp
/// need not clear), or nothing, as fixplan read parts before holes (for
/// comparison: the part then is its solid outline).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum HoleMode {
    /// Loops directly inside the outline are the part's holes.
    #[default]
    Keep,
    /// Every loop inside the outline is dropped with a warning.
    Ignore,
}

impl HoleMode {
    /// The values a manifest's `holes` and the `--holes` flag take.
    pub const NAMES: [&'static str; 2] = ["keep", "ignore"];

    /// `"keep"` or `"ignore"` (any case); `None` for anything else.
    pub fn parse(text: &str) -> Option<HoleMode> {
        match text.trim().to_ascii_lowercase().as_str() {
            "keep" => Some(HoleMode::Keep),
            "ignore" => Some(HoleMode::Ignore),
            _ => None,
        }
    }

    /// The name [`HoleMode::parse`] reads.
    pub fn name(self) -> &'static str {
        match self {
            HoleMode::Keep => "keep",
            HoleMode::Ignore => "ignore",
        }
    }
}

impl fmt::Display for HoleMode {
    fn fmt(&self, formatter: &mut fmt::Formatter<'_>) -> fmt::Result {
        formatter.write_str(self.name())
    }
}

impl std::str::FromStr for HoleMode {
    type Err = String;

    fn from_str(text: &str) -> Result<HoleMode, String> {
        HoleMode::parse(text).ok_or_else(|| {
            format!("unknown holes mode \"{text}\" (expected \"keep\" or \"ignore\")")
        })
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
            sheet: false,
            layers: LayerFilter::default(),
            limits: Limits::default(),
            holes: HoleMode::Keep,
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
    /// The part's holes (SPEC 9): loops directly inside the outline, in
    /// file order, unless [`HoleMode::Ignore`] dropped them.
    pub holes: Vec<Vec<Vertex>>,
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
    /// Hole number `.0` (from 0, in file order, as SPEC 9 numbers them).
    Hole(usize),
}

impl fmt::Display for PolygonRole {
    fn fmt(&self, formatter: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PolygonRole::Outline => formatter.write_str("outline"),
            PolygonRole::Access(i) => write!(formatter, "access constraint {i}"),
            PolygonRole::Hole(i) => write!(formatter, "hole {i}"),
        }
    }
}
