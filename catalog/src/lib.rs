//! Reading part catalogues and kits into validated fixplan inputs.
//!
//! Interface agreed with the `fixplan run` command (coordinator crate):
//! - [`load_catalog`]: a `catalog.toml` manifest or a plain directory;
//! - [`load_kit`]: a built-in kit name or a kit TOML file;
//! - every part comes back on its own, valid or with its error, so one broken
//!   part never stops the others.

use fixplan_core::{Kit, Params, Part, Units};
use std::path::{Path, PathBuf};

/// A catalogue, its parts in manifest order (directory: sorted by file name).
#[derive(Debug, Clone)]
pub struct Catalog {
    pub name: String,
    pub units: Units,
    /// Where it was read from (manifest file or directory).
    pub source: PathBuf,
    pub parts: Vec<CatalogPart>,
}

/// One catalogue entry, read and validated independently of the others.
#[derive(Debug, Clone)]
pub struct CatalogPart {
    pub id: String,
    /// The file it came from, if any (inline outlines have none).
    pub file: Option<PathBuf>,
    /// The part in the catalogue's units, or why it cannot be used.
    pub part: Result<Part, String>,
    /// Warnings from repairs that were safe to make (e.g. a repeated vertex
    /// dropped), each naming the part and the place.
    pub warnings: Vec<String>,
    /// Parts per year, for kit studies (default 1).
    pub quantity: f64,
    /// Per-part overrides.
    pub top_k: Option<usize>,
    pub wrenches: Option<Vec<[f64; 3]>>,
}

#[derive(Debug, thiserror::Error)]
pub enum CatalogError {
    #[error("{path}: {message}")]
    Invalid { path: PathBuf, message: String },
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

/// Loads a catalogue from a manifest (`catalog.toml`) or a directory.
/// Errors here concern the catalogue as a whole; a broken part is reported
/// in its [`CatalogPart::part`].
pub fn load_catalog(_path: &Path) -> Result<Catalog, CatalogError> {
    unimplemented!("catalog helper implements this")
}

/// Names of the built-in kits.
pub fn builtin_kit_names() -> &'static [&'static str] {
    &[]
}

/// A kit with its enumeration parameters (defaults filled in), all lengths
/// in the catalogue's units.
#[derive(Debug, Clone)]
pub struct KitSpec {
    pub name: String,
    pub kit: Kit,
    pub params: Params,
}

/// A built-in kit by name, or a kit TOML file; lengths converted to `units`.
pub fn load_kit(_name_or_path: &str, _units: Units) -> Result<KitSpec, CatalogError> {
    unimplemented!("catalog helper implements this")
}
