//! Reading part catalogues and kits into validated fixplan inputs.
//!
//! Interface agreed with the `fixplan run` command (coordinator crate):
//! - [`load_catalog`]: a `catalog.toml` manifest or a plain directory;
//! - [`load_kit`]: a built-in kit name or a kit TOML file;
//! - every part comes back on its own, valid or with its error, so one broken
//!   part never stops the others.
//!
//! A manifest:
//!
//! ```toml
//! name = "sample"
//! units = "mm"               # "mm" or "in": every part is converted to it
//! chord_tolerance = 0.2      # optional, catalogue units (default 0.05 mm)
//! arcs = "exact"             # optional: "exact" (default) or "flatten"
//!
//! [[part]]
//! id = "bracket-7"
//! file = "parts/bracket-7.dxf"   # DXF, SVG or JSON, relative to the manifest
//! quantity = 1200                # parts per year (default 1)
//! top_k = 5                      # optional per-part overrides
//! wrenches = [[0.0, -200.0, 0.0]]
//!
//! [[part]]
//! id = "plate"
//! outline = [[0, 0], [80, 0], [80, 50, 1], [0, 50]]   # [x, y, bulge]: an arc
//! access = [[[10, 40], [30, 40], [30, 60], [10, 60]]]
//! ```
//!
//! **Arcs.** Circular arcs (DXF bulges, ARC and CIRCLE entities, SVG `A`
//! commands with equal radii under a similarity transform, SVG circles,
//! `[x, y, bulge]` vertices) are read as exact arcs, SPEC section 8.
//! `arcs = "flatten"` (or [`LoadOptions::arcs`], the command line's
//! `--arcs flatten`) cuts them into chords within the chord tolerance as
//! fixplan did before arcs, for comparison. Ellipses, splines and Bézier
//! curves are always flattened within the chord tolerance (an ellipse with
//! equal axes is a circle and exact); access constraints are polygons.
//!
//! An entry may also give `units` (the file's units when the file does not
//! say) and `chord_tolerance`; `access` polygons of an entry with a `file`
//! are added to those found in the file.

mod error;
pub mod kit;
pub mod kit_limits;
mod manifest;
pub mod part;
pub mod units;

pub use error::{CatalogError, EntryProblem, PartError, PartErrorKind};
pub use kit::{builtin_kit_names, load_kit, KitSpec};
pub use manifest::{load_catalog, load_catalog_with, Catalog, CatalogPart, LoadOptions, MANIFEST};
pub use part::{
    parse_part, read_dxf, read_dxf_parts, read_json, read_parts, read_raw, read_svg,
    read_svg_parts, validate_part, write_dxf, write_json, write_svg, ArcMode, DxfError, Format,
    HoleMode, InvalidPolygon, JsonError, LayerFilter, LimitExceeded, Limits, OpenCause, ParseError,
    PolygonProblem, PolygonRole, RawPart, ReadError, ReadOptions, SvgError,
};
pub use units::LengthUnit;
