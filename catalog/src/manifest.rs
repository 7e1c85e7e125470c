//! Catalogues: a `catalog.toml` manifest or a plain directory of part
//! files, each part read and validated on its own (through `crate::part`)
//! so that one broken part never stops the others.

use crate::error::{part_name, CatalogError, EntryProblem, PartError, PartErrorKind};
use crate::part::{
    flatten_vertices, read_raw, validate_part, ArcMode, Format, RawPart, ReadOptions,
};
use crate::units::{self, LengthUnit};
use fixplan_core::outline::Vertex;
use fixplan_core::{Part, Units};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A catalogue, its parts in manifest order (directory: sorted by file name).
#[derive(Debug, Clone)]
pub struct Catalog {
    /// The manifest's `name`, else the directory's name: what reports and
    /// results files call the catalogue.
    pub name: String,
    /// The units every part (and the kit) is in.
    pub units: Units,
    /// Where it was read from (manifest file or directory).
    pub source: PathBuf,
    /// Every entry, valid or not, so that results can report each one.
    pub parts: Vec<CatalogPart>,
}

/// One catalogue entry, read and validated independently of the others.
#[derive(Debug, Clone)]
pub struct CatalogPart {
    /// The id results and reports use (a directory part: its file stem).
    pub id: String,
    /// The file it came from, if any (inline outlines have none).
    pub file: Option<PathBuf>,
    /// The part in the catalogue's units, or why it cannot be used.
    pub part: Result<Part, PartError>,
    /// Warnings from repairs that were safe to make (e.g. a repeated vertex
    /// dropped), each naming the part and the place.
    pub warnings: Vec<String>,
    /// Parts per year, for kit studies (default 1).
    pub quantity: f64,
    /// Fixtures to keep for this part, overriding the run's `top_k`.
    pub top_k: Option<usize>,
    /// Expected wrenches for this part's quality metric, overriding the
    /// kit's.
    pub wrenches: Option<Vec<[f64; 3]>>,
}

impl CatalogPart {
    /// The entry with the outcome of reading it; warnings get the part's
    /// name, as every message about a part does. Quantity and overrides are
    /// the defaults.
    fn new(
        id: String,
        file: Option<PathBuf>,
        read: Result<(Part, Vec<String>), PartErrorKind>,
    ) -> CatalogPart {
        let (part, warnings) = match read {
            Ok((part, warnings)) => {
                let name = part_name(&id, file.as_deref());
                let warnings = warnings
                    .into_iter()
                    .map(|w| format!("{name}: {w}"))
                    .collect();
                (Ok(part), warnings)
            }
            Err(kind) => {
                let e = PartError {
                    id: id.clone(),
                    file: file.clone(),
                    kind,
                };
                (Err(e), Vec::new())
            }
        };
        CatalogPart {
            id,
            file,
            part,
            warnings,
            quantity: 1.0,
            top_k: None,
            wrenches: None,
        }
    }
}

/// Choices a caller can make when loading a catalogue.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LoadOptions {
    /// Units of a plain directory (a manifest states its own); default mm.
    pub units: Option<Units>,
    /// Largest distance between an arc and its chords, in the catalogue's
    /// units. Overrides the manifest's `chord_tolerance`; default 0.05 mm.
    pub chord_tolerance: Option<f64>,
    /// Largest gap closed when joining DXF entities into loops, catalogue
    /// units; default 0.01 mm.
    pub join_tolerance: Option<f64>,
    /// Circular arcs exact or flattened within the chord tolerance.
    /// Overrides the manifest's `arcs`; default exact.
    pub arcs: Option<ArcMode>,
}

/// The manifest's file name, looked for when a directory is given.
pub const MANIFEST: &str = "catalog.toml";

/// Loads a catalogue from a manifest (`catalog.toml`) or a directory.
/// Errors here concern the catalogue as a whole; a broken part is reported
/// in its [`CatalogPart::part`].
pub fn load_catalog(path: &Path) -> Result<Catalog, CatalogError> {
    load_catalog_with(path, &LoadOptions::default())
}

/// [`load_catalog`] with explicit tolerances and directory units.
pub fn load_catalog_with(path: &Path, opts: &LoadOptions) -> Result<Catalog, CatalogError> {
    if path.is_dir() {
        let manifest = path.join(MANIFEST);
        if manifest.is_file() {
            load_manifest(&manifest, opts)
        } else {
            load_directory(path, opts)
        }
    } else if path.is_file() {
        load_manifest(path, opts)
    } else {
        Err(CatalogError::Io {
            path: path.to_path_buf(),
            source: std::io::Error::new(std::io::ErrorKind::NotFound, "no such file or directory"),
        })
    }
}

fn invalid(path: &Path, message: impl Into<String>) -> CatalogError {
    CatalogError::Invalid {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

/// The read options of a catalogue: the caller's choices, else the
/// manifest's (`manifest` is the default [`Header`] for a directory).
fn read_options(units: Units, opts: &LoadOptions, manifest: &Header) -> ReadOptions {
    let mut r = ReadOptions::new(units);
    if let Some(t) = opts.chord_tolerance.or(manifest.chord_tolerance) {
        r.chord_tolerance = t;
    }
    if let Some(t) = opts.join_tolerance {
        r.join_tolerance = t;
    }
    r.arcs = opts.arcs.or(manifest.arcs).unwrap_or_default();
    r
}

fn dir_name(p: &Path) -> String {
    p.canonicalize()
        .ok()
        .and_then(|c| c.file_name().map(|s| s.to_string_lossy().into_owned()))
        .unwrap_or_else(|| p.display().to_string())
}

fn load_directory(dir: &Path, opts: &LoadOptions) -> Result<Catalog, CatalogError> {
    let units = opts.units.unwrap_or(Units::Mm);
    let ropts = read_options(units, opts, &Header::default());
    let entries = std::fs::read_dir(dir).map_err(|source| CatalogError::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && Format::from_path(p).is_some())
        .collect();
    files.sort();
    let parts = files
        .into_iter()
        .map(|f| {
            let id = f
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            let name = f
                .file_name()
                .map(PathBuf::from)
                .unwrap_or_else(|| f.clone());
            CatalogPart::new(id, Some(name), read_file_part(&f, &ropts, &[]))
        })
        .collect();
    Ok(Catalog {
        name: dir_name(dir),
        units,
        source: dir.to_path_buf(),
        parts,
    })
}

/// Reads a part file, adds the entry's own access polygons, validates.
fn read_file_part(
    path: &Path,
    ropts: &ReadOptions,
    extra_access: &[Vec<[f64; 2]>],
) -> Result<(Part, Vec<String>), PartErrorKind> {
    let format = Format::from_path(path).ok_or(PartErrorKind::UnknownFileType)?;
    let bytes = std::fs::read(path).map_err(|e| PartErrorKind::Unreadable {
        path: path.to_path_buf(),
        error: Arc::new(e),
    })?;
    let mut raw = read_raw(&bytes, format, ropts)?;
    raw.access.extend(extra_access.iter().cloned());
    validated(raw, ropts.units)
}

/// [`validate_part`], keeping what was read in the error.
fn validated(raw: RawPart, units: Units) -> Result<(Part, Vec<String>), PartErrorKind> {
    let read = Part {
        outline: raw.outline.clone(),
        access: raw.access.clone(),
    };
    validate_part(raw, units).map_err(|problem| PartErrorKind::Invalid {
        problem,
        read: Box::new(read),
    })
}

/// Validates an entry's inline outline (`[x, y]` or `[x, y, bulge]`
/// vertices, arcs flattened with [`ArcMode::Flatten`]) and access
/// polygons, given in the entry's units (`ropts.fallback`), else the
/// catalogue's.
fn inline_part(
    outline: &[Vertex],
    access: &[Vec<[f64; 2]>],
    ropts: &ReadOptions,
) -> Result<(Part, Vec<String>), PartErrorKind> {
    let k = ropts.fallback.factor_to(ropts.units);
    let sc = |p: &[[f64; 2]]| p.iter().map(|q| [q[0] * k, q[1] * k]).collect();
    let mut outline: Vec<Vertex> = outline
        .iter()
        .map(|v| Vertex::new(v.x * k, v.y * k, v.bulge))
        .collect();
    if ropts.arcs.flatten() {
        outline = flatten_vertices(&outline, true, ropts.chord_tolerance);
    }
    let raw = RawPart {
        outline,
        access: access.iter().map(|a| sc(a)).collect(),
        warnings: Vec::new(),
    };
    validated(raw, ropts.units)
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Entry {
    id: String,
    #[serde(default)]
    file: Option<PathBuf>,
    #[serde(default)]
    outline: Option<Vec<Vertex>>,
    #[serde(default)]
    access: Vec<Vec<[f64; 2]>>,
    #[serde(default)]
    quantity: Option<f64>,
    #[serde(default)]
    top_k: Option<usize>,
    #[serde(default)]
    wrenches: Option<Vec<[f64; 3]>>,
    #[serde(default)]
    units: Option<String>,
    #[serde(default)]
    chord_tolerance: Option<f64>,
}

/// Where an entry's polygons come from.
enum Geometry<'a> {
    File(&'a Path),
    Outline(&'a [Vertex]),
}

/// The manifest's top-level fields.
#[derive(Default)]
struct Header {
    name: String,
    units: Units,
    chord_tolerance: Option<f64>,
    arcs: Option<ArcMode>,
    entries: Vec<toml::Value>,
}

fn load_manifest(path: &Path, opts: &LoadOptions) -> Result<Catalog, CatalogError> {
    let text = std::fs::read_to_string(path).map_err(|source| CatalogError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let mut table: toml::Table = text
        .parse()
        .map_err(|e: toml::de::Error| invalid(path, format!("not a readable manifest: {e}")))?;
    let base = path.parent().unwrap_or(Path::new("."));
    let header = read_header(&mut table, path, base)?;
    let ctx = EntryContext {
        base,
        ropts: read_options(header.units, opts, &header),
        chord_tolerance_given: opts.chord_tolerance.is_some(),
    };
    let mut seen = HashMap::new();
    let parts = header
        .entries
        .into_iter()
        .enumerate()
        .map(|(i, v)| load_entry(i, v, &ctx, &mut seen))
        .collect();
    Ok(Catalog {
        name: header.name,
        units: header.units,
        source: path.to_path_buf(),
        parts,
    })
}

/// Takes the top-level fields out of the manifest; anything left over is
/// an unknown field.
fn read_header(table: &mut toml::Table, path: &Path, base: &Path) -> Result<Header, CatalogError> {
    let name = match table.remove("name") {
        Some(toml::Value::String(s)) => s,
        None => dir_name(base),
        Some(v) => return Err(invalid(path, format!("name {v} is not a string"))),
    };
    let units = match table.remove("units") {
        Some(toml::Value::String(s)) => {
            units::parse_units(&s).map_err(|e| invalid(path, e.to_string()))?
        }
        None => return Err(invalid(path, "no units: say units = \"mm\" or \"in\"")),
        Some(v) => return Err(invalid(path, format!("unknown units {v}"))),
    };
    let chord_tolerance = match table.remove("chord_tolerance") {
        None => None,
        Some(v) => Some(positive(&v).ok_or_else(|| {
            invalid(
                path,
                format!("chord_tolerance {v} must be a positive number"),
            )
        })?),
    };
    let arcs = match table.remove("arcs") {
        None => None,
        Some(toml::Value::String(s)) => Some(ArcMode::parse(&s).ok_or_else(|| {
            invalid(
                path,
                format!("arcs = \"{s}\": expected \"exact\" (arcs kept, the default) or \"flatten\" (arcs cut into chords within chord_tolerance)"),
            )
        })?),
        Some(v) => {
            return Err(invalid(
                path,
                format!("arcs {v} is not a string: expected \"exact\" or \"flatten\""),
            ))
        }
    };
    let entries = match table.remove("part") {
        None => Vec::new(),
        Some(toml::Value::Array(a)) => a,
        Some(_) => return Err(invalid(path, "part must be an array of tables ([[part]])")),
    };
    if let Some(k) = table.keys().next() {
        return Err(invalid(
            path,
            format!("unknown manifest field \"{k}\" (expected name, units, chord_tolerance, arcs, part)"),
        ));
    }
    Ok(Header {
        name,
        units,
        chord_tolerance,
        arcs,
        entries,
    })
}

/// A positive finite number, integer or float.
fn positive(v: &toml::Value) -> Option<f64> {
    v.as_float()
        .or(v.as_integer().map(|i| i as f64))
        .filter(|t| t.is_finite() && *t > 0.0)
}

/// What every entry of a manifest is read with.
struct EntryContext<'a> {
    /// The manifest's directory, which entry files are relative to.
    base: &'a Path,
    /// The catalogue's read options.
    ropts: ReadOptions,
    /// The caller fixed the chord tolerance: entries may not change it.
    chord_tolerance_given: bool,
}

/// Entry `i` (from 0) of the manifest as a catalogue part; `seen` holds
/// the ids of the entries before it.
fn load_entry(
    i: usize,
    v: toml::Value,
    ctx: &EntryContext,
    seen: &mut HashMap<String, usize>,
) -> CatalogPart {
    let fallback_id = v
        .get("id")
        .and_then(|x| x.as_str())
        .map(str::to_string)
        .unwrap_or_else(|| format!("part #{}", i + 1));
    let entry: Entry = match v.try_into() {
        Ok(e) => e,
        Err(e) => {
            let kind = PartErrorKind::ManifestEntry {
                entry: i + 1,
                message: e.message().to_string(),
            };
            return CatalogPart::new(fallback_id, None, Err(kind));
        }
    };
    let checked = check_entry(&entry, seen, i);
    let quantity = match checked {
        Ok(_) => entry.quantity.unwrap_or(1.0),
        Err(_) => 1.0,
    };
    let read = checked
        .map_err(PartErrorKind::from)
        .and_then(|geometry| read_entry(&entry, geometry, ctx));
    let mut cp = CatalogPart::new(entry.id.clone(), entry.file.clone(), read);
    cp.quantity = quantity;
    cp.top_k = entry.top_k;
    cp.wrenches = entry.wrenches;
    cp
}

/// Reads an entry that passed [`check_entry`].
fn read_entry(
    entry: &Entry,
    geometry: Geometry,
    ctx: &EntryContext,
) -> Result<(Part, Vec<String>), PartErrorKind> {
    let mut ropts = ctx.ropts;
    if let Some(t) = entry.chord_tolerance.filter(|_| !ctx.chord_tolerance_given) {
        ropts.chord_tolerance = t;
    }
    if let Some(u) = &entry.units {
        ropts.fallback =
            LengthUnit::parse(u).ok_or_else(|| EntryProblem::UnknownUnits(u.clone()))?;
    }
    match geometry {
        Geometry::File(f) => read_file_part(&ctx.base.join(f), &ropts, &entry.access),
        Geometry::Outline(outline) => inline_part(outline, &entry.access, &ropts),
    }
}

/// The entry's fields on their own and against the ids `seen` before it
/// (entry `i` from 0); the id is recorded unless it is empty or taken.
fn check_entry<'e>(
    e: &'e Entry,
    seen: &mut HashMap<String, usize>,
    i: usize,
) -> Result<Geometry<'e>, EntryProblem> {
    if e.id.trim().is_empty() {
        return Err(EntryProblem::EmptyId);
    }
    if let Some(first) = seen.get(&e.id) {
        return Err(EntryProblem::DuplicateId {
            entry: i + 1,
            first: first + 1,
        });
    }
    seen.insert(e.id.clone(), i);
    let geometry = match (&e.file, &e.outline) {
        (Some(_), Some(_)) => return Err(EntryProblem::FileAndOutline),
        (None, None) => return Err(EntryProblem::NoFileNorOutline),
        (Some(f), None) => Geometry::File(f),
        (None, Some(o)) => Geometry::Outline(o),
    };
    if let Some(q) = e.quantity.filter(|q| !(q.is_finite() && *q >= 0.0)) {
        return Err(EntryProblem::Quantity(q));
    }
    if let Some(ws) = &e.wrenches {
        if ws.is_empty() {
            return Err(EntryProblem::EmptyWrenches);
        }
        if let Some(k) = ws.iter().position(|w| w.iter().any(|x| !x.is_finite())) {
            return Err(EntryProblem::NonFiniteWrench(k));
        }
    }
    if let Some(t) = e.chord_tolerance.filter(|t| !(t.is_finite() && *t > 0.0)) {
        return Err(EntryProblem::ChordTolerance(t));
    }
    Ok(geometry)
}
