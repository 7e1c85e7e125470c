//! Catalogues: a `catalog.toml` manifest or a plain directory of part
//! files, each part read and validated on its own (through `crate::part`)
//! so that one broken part never stops the others.

use crate::error::{part_name, CatalogError, EntryProblem, PartError, PartErrorKind};
use crate::part::{
    flatten_vertices, keep_holes, read_parts, validate_part, ArcMode, Format, HoleMode,
    LayerFilter, Limits, RawPart, ReadError, ReadOptions,
};
use crate::units::{self, LengthUnit};
use fixplan_core::{Part, Units, Vertex};
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
    /// Every file is a sheet: each outer loop a part of its own (`id#1`,
    /// `id#2`, ...). Overrides the manifest's `sheet` and its entries'.
    pub sheet: Option<bool>,
    /// Holes kept (SPEC 9) or dropped with a warning, for comparison.
    /// Overrides the manifest's `holes`; default kept.
    pub holes: Option<HoleMode>,
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
    if let Some(t) = opts.join_tolerance.or(manifest.join_tolerance) {
        r.join_tolerance = t;
    }
    r.arcs = opts.arcs.or(manifest.arcs).unwrap_or_default();
    r.sheet = opts.sheet.or(manifest.sheet).unwrap_or(false);
    r.holes = opts.holes.or(manifest.holes).unwrap_or_default();
    r.layers = manifest.layers.clone();
    r.limits = manifest.limits;
    r
}

fn dir_name(path: &Path) -> String {
    path.canonicalize()
        .ok()
        .and_then(|c| c.file_name().map(|s| s.to_string_lossy().into_owned()))
        .unwrap_or_else(|| path.display().to_string())
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
        // Every name of a part format is a part: anything but a
        // directory is read, so a FIFO or a device is refused with its
        // name (reading refuses it before opening) instead of skipped.
        .filter(|p| !p.is_dir() && Format::from_path(p).is_some())
        .collect();
    files.sort();
    let parts = files
        .into_iter()
        .flat_map(|f| {
            let id = f
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            let name = f
                .file_name()
                .map(PathBuf::from)
                .unwrap_or_else(|| f.clone());
            file_parts(
                id,
                Some(name),
                read_file_parts(&f, &ropts, &[]),
                ropts.sheet,
            )
        })
        .collect();
    Ok(Catalog {
        name: dir_name(dir),
        units,
        source: dir.to_path_buf(),
        parts,
    })
}

/// What reading one file gave: one part, the parts of a sheet (each read
/// and validated on its own), or why the file gives none.
type FileParts = Result<Vec<Result<(Part, Vec<String>), PartErrorKind>>, PartErrorKind>;

/// The catalogue parts of a file: `id` for one part, `id#1`, `id#2`, ...
/// for a file read as a sheet (even a sheet of one part, so that ids do
/// not change with the number of parts found).
fn file_parts(id: String, file: Option<PathBuf>, read: FileParts, sheet: bool) -> Vec<CatalogPart> {
    match read {
        Err(kind) => vec![CatalogPart::new(id, file, Err(kind))],
        Ok(parts) if !sheet => parts
            .into_iter()
            .map(|p| CatalogPart::new(id.clone(), file.clone(), p))
            .collect(),
        Ok(parts) => parts
            .into_iter()
            .enumerate()
            .map(|(i, p)| CatalogPart::new(format!("{id}#{}", i + 1), file.clone(), p))
            .collect(),
    }
}

/// A file's bytes, refusing anything but a regular file before opening it
/// (a FIFO would block the reader, a device never end) and anything over
/// [`Limits::file_bytes`], whose read is bounded even if the file grows.
fn file_bytes(path: &Path, limits: &Limits) -> Result<Vec<u8>, PartErrorKind> {
    let unreadable = |e: std::io::Error| PartErrorKind::Unreadable {
        path: path.to_path_buf(),
        error: Arc::new(e),
    };
    let meta = std::fs::metadata(path).map_err(unreadable)?;
    if !meta.is_file() {
        return Err(PartErrorKind::NotAFile {
            path: path.to_path_buf(),
            kind: file_kind(&meta),
        });
    }
    let within = |len: u64| {
        limits
            .check_file_bytes(len)
            .map_err(|e| PartErrorKind::Read(ReadError::Limit(e)))
    };
    within(meta.len())?;
    let mut bytes = Vec::new();
    let file = std::fs::File::open(path).map_err(unreadable)?;
    std::io::Read::read_to_end(
        &mut std::io::Read::take(file, limits.file_bytes.saturating_add(1)),
        &mut bytes,
    )
    .map_err(unreadable)?;
    within(u64::try_from(bytes.len()).unwrap_or(u64::MAX))?;
    Ok(bytes)
}

/// What a path that is not a regular file is, for the message.
fn file_kind(meta: &std::fs::Metadata) -> &'static str {
    let t = meta.file_type();
    if t.is_dir() {
        return "a directory";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if t.is_socket() {
            return "a socket";
        }
        if t.is_block_device() || t.is_char_device() {
            return "a device";
        }
    }
    "not a regular file"
}

/// Reads a part file (a sheet: its parts), adds the entry's own access
/// polygons to each, validates each.
fn read_file_parts(path: &Path, ropts: &ReadOptions, extra_access: &[Vec<[f64; 2]>]) -> FileParts {
    let format = Format::from_path(path).ok_or(PartErrorKind::UnknownFileType)?;
    let bytes = file_bytes(path, &ropts.limits)?;
    let raws = read_parts(&bytes, format, ropts)?;
    Ok(raws
        .into_iter()
        .map(|mut raw| {
            raw.access.extend(extra_access.iter().cloned());
            validated(raw, ropts.units)
        })
        .collect())
}

/// [`validate_part`], keeping what was read in the error.
fn validated(raw: RawPart, units: Units) -> Result<(Part, Vec<String>), PartErrorKind> {
    let read = Part {
        outline: raw.outline.clone(),
        holes: raw.holes.clone(),
        access: raw.access.clone(),
    };
    validate_part(raw, units).map_err(|problem| PartErrorKind::Invalid {
        problem,
        read: Box::new(read),
    })
}

/// Validates an entry's inline outline and holes (`[x, y]` or
/// `[x, y, bulge]` vertices, arcs flattened with [`ArcMode::Flatten`],
/// holes dropped with [`HoleMode::Ignore`]) and access polygons, given in
/// the entry's units (`ropts.fallback`), else the catalogue's.
fn inline_part(
    outline: &[Vertex],
    holes: &[Vec<Vertex>],
    access: &[Vec<[f64; 2]>],
    ropts: &ReadOptions,
) -> Result<(Part, Vec<String>), PartErrorKind> {
    let k = ropts.fallback.factor_to(ropts.units);
    let sc = |p: &[[f64; 2]]| p.iter().map(|q| [q[0] * k, q[1] * k]).collect();
    let scaled = |l: &[Vertex]| {
        let l: Vec<Vertex> = l
            .iter()
            .map(|v| Vertex::new(v.x * k, v.y * k, v.bulge))
            .collect();
        if ropts.arcs.flatten() {
            flatten_vertices(&l, true, ropts.chord_tolerance)
        } else {
            l
        }
    };
    let mut warnings = Vec::new();
    let named = holes
        .iter()
        .enumerate()
        .map(|(k, h)| (scaled(h), format!("hole {k}")))
        .collect();
    let holes = keep_holes(ropts.holes, named, &mut warnings, ropts.units);
    let raw = RawPart {
        outline: scaled(outline),
        access: access.iter().map(|a| sc(a)).collect(),
        warnings,
        holes,
    };
    validated(raw, ropts.units)
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct ManifestEntry {
    id: String,
    #[serde(default)]
    file: Option<PathBuf>,
    #[serde(default)]
    outline: Option<Vec<Vertex>>,
    #[serde(default)]
    holes: Vec<Vec<Vertex>>,
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
    #[serde(default)]
    sheet: Option<bool>,
    #[serde(default)]
    layers: Option<Vec<String>>,
    #[serde(default)]
    ignore_layers: Option<Vec<String>>,
}

/// Where an entry's polygons come from: a file, or an inline outline and
/// its holes.
enum Geometry<'a> {
    File(&'a Path),
    Outline(&'a [Vertex], &'a [Vec<Vertex>]),
}

/// The manifest's top-level fields.
#[derive(Default)]
struct Header {
    name: String,
    units: Units,
    chord_tolerance: Option<f64>,
    join_tolerance: Option<f64>,
    arcs: Option<ArcMode>,
    sheet: Option<bool>,
    holes: Option<HoleMode>,
    layers: LayerFilter,
    limits: Limits,
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
        sheet_given: opts.sheet.is_some(),
    };
    let mut seen = HashMap::new();
    let parts = header
        .entries
        .into_iter()
        .enumerate()
        .flat_map(|(i, v)| load_entry(i, v, &ctx, &mut seen))
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
    let join_tolerance = match table.remove("join_tolerance") {
        None => None,
        Some(v) => Some(
            v.as_float()
                .or(v.as_integer().map(|i| i as f64))
                .filter(|t| t.is_finite() && *t >= 0.0)
                .ok_or_else(|| {
                    invalid(
                        path,
                        format!("join_tolerance {v} must be a non-negative number"),
                    )
                })?,
        ),
    };
    let sheet = match table.remove("sheet") {
        None => None,
        Some(toml::Value::Boolean(b)) => Some(b),
        Some(v) => return Err(invalid(path, format!("sheet {v} must be true or false"))),
    };
    let holes = read_holes(table.remove("holes"), path)?;
    let layers = LayerFilter {
        read: string_list(table.remove("layers"), "layers").map_err(|m| invalid(path, m))?,
        ignore: string_list(table.remove("ignore_layers"), "ignore_layers")
            .map_err(|m| invalid(path, m))?,
    };
    let limits = match table.remove("limits") {
        None => Limits::default(),
        Some(toml::Value::Table(t)) => read_limits(t).map_err(|m| invalid(path, m))?,
        Some(v) => {
            return Err(invalid(
                path,
                format!("limits {v} must be a table ([limits])"),
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
            format!("unknown manifest field \"{k}\" (expected name, units, chord_tolerance, join_tolerance, arcs, sheet, holes, layers, ignore_layers, limits, part)"),
        ));
    }
    Ok(Header {
        name,
        units,
        chord_tolerance,
        join_tolerance,
        arcs,
        sheet,
        holes,
        layers,
        limits,
        entries,
    })
}

/// The manifest's `holes`: `"keep"` or `"ignore"`.
fn read_holes(value: Option<toml::Value>, path: &Path) -> Result<Option<HoleMode>, CatalogError> {
    let Some(value) = value else { return Ok(None) };
    value.as_str().and_then(HoleMode::parse).map(Some).ok_or_else(|| {
        invalid(
            path,
            format!("holes = {value}: expected \"keep\" (loops inside a part are its holes, the default) or \"ignore\" (dropped with a warning, as before holes)"),
        )
    })
}

/// A list of strings (layer names), or why not.
fn string_list(value: Option<toml::Value>, key: &str) -> Result<Vec<String>, String> {
    match value {
        None => Ok(Vec::new()),
        Some(toml::Value::Array(a)) => a
            .into_iter()
            .map(|x| match x {
                toml::Value::String(s) => Ok(s),
                other => Err(format!("{key}: {other} is not a layer name (a string)")),
            })
            .collect(),
        Some(value) => Err(format!("{key} {value} must be a list of layer names")),
    }
}

/// The `[limits]` table: each key one of [`Limits::KEYS`], a positive
/// integer.
fn read_limits(table: toml::Table) -> Result<Limits, String> {
    let mut limits = Limits::default();
    for (k, v) in table {
        let n = v
            .as_integer()
            .and_then(|i| u64::try_from(i).ok())
            .filter(|&i| i > 0)
            .ok_or_else(|| format!("limits.{k} = {v} must be a positive integer"))?;
        if !limits.set(&k, n) {
            return Err(format!(
                "unknown limit \"{k}\" (expected one of {})",
                Limits::KEYS.join(", ")
            ));
        }
    }
    Ok(limits)
}

/// A positive finite number, integer or float.
fn positive(value: &toml::Value) -> Option<f64> {
    value
        .as_float()
        .or(value.as_integer().map(|i| i as f64))
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
    /// The caller fixed `sheet`: entries may not change it.
    sheet_given: bool,
}

/// Entry `index` (from 0) of the manifest as catalogue parts (one, or those
/// of a sheet); `seen` holds the ids of the entries before it.
fn load_entry(
    index: usize,
    value: toml::Value,
    ctx: &EntryContext,
    seen: &mut HashMap<String, usize>,
) -> Vec<CatalogPart> {
    let fallback_id = value
        .get("id")
        .and_then(|x| x.as_str())
        .map(str::to_string)
        .unwrap_or_else(|| format!("part #{}", index + 1));
    let entry: ManifestEntry = match value.try_into() {
        Ok(e) => e,
        Err(e) => {
            let kind = PartErrorKind::ManifestEntry {
                entry: index + 1,
                message: e.message().to_string(),
            };
            return vec![CatalogPart::new(fallback_id, None, Err(kind))];
        }
    };
    let checked = check_entry(&entry, seen, index);
    let quantity = match checked {
        Ok(_) => entry.quantity.unwrap_or(1.0),
        Err(_) => 1.0,
    };
    let ropts = entry_options(&entry, ctx);
    let sheet = entry.file.is_some() && ropts.as_ref().is_ok_and(|r| r.sheet);
    let read = checked
        .map_err(PartErrorKind::from)
        .and_then(|geometry| read_entry(&entry, geometry, ctx, ropts?));
    let mut parts = file_parts(entry.id.clone(), entry.file.clone(), read, sheet);
    for cp in &mut parts {
        cp.quantity = quantity;
        cp.top_k = entry.top_k;
        cp.wrenches.clone_from(&entry.wrenches);
    }
    parts
}

/// The catalogue's read options with the entry's own choices.
fn entry_options(entry: &ManifestEntry, ctx: &EntryContext) -> Result<ReadOptions, PartErrorKind> {
    let mut ropts = ctx.ropts.clone();
    if let Some(t) = entry.chord_tolerance.filter(|_| !ctx.chord_tolerance_given) {
        ropts.chord_tolerance = t;
    }
    if let Some(u) = &entry.units {
        ropts.fallback =
            LengthUnit::parse(u).ok_or_else(|| EntryProblem::UnknownUnits(u.clone()))?;
    }
    if let Some(s) = entry.sheet.filter(|_| !ctx.sheet_given) {
        ropts.sheet = s;
    }
    if let Some(l) = &entry.layers {
        ropts.layers.read.clone_from(l);
    }
    if let Some(l) = &entry.ignore_layers {
        ropts.layers.ignore.clone_from(l);
    }
    Ok(ropts)
}

/// Reads an entry that passed [`check_entry`].
fn read_entry(
    entry: &ManifestEntry,
    geometry: Geometry,
    ctx: &EntryContext,
    ropts: ReadOptions,
) -> FileParts {
    match geometry {
        Geometry::File(f) => read_file_parts(&ctx.base.join(f), &ropts, &entry.access),
        Geometry::Outline(outline, holes) => {
            Ok(vec![inline_part(outline, holes, &entry.access, &ropts)])
        }
    }
}

/// The entry's fields on their own and against the ids `seen` before it
/// (entry `index` from 0); the id is recorded unless it is empty or taken.
fn check_entry<'e>(
    listed: &'e ManifestEntry,
    seen: &mut HashMap<String, usize>,
    index: usize,
) -> Result<Geometry<'e>, EntryProblem> {
    if listed.id.trim().is_empty() {
        return Err(EntryProblem::EmptyId);
    }
    if let Some(first) = seen.get(&listed.id) {
        return Err(EntryProblem::DuplicateId {
            entry: index + 1,
            first: first + 1,
        });
    }
    seen.insert(listed.id.clone(), index);
    let geometry = match (&listed.file, &listed.outline) {
        (Some(_), Some(_)) => return Err(EntryProblem::FileAndOutline),
        (None, None) => return Err(EntryProblem::NoFileNorOutline),
        (Some(_), None) if !listed.holes.is_empty() => return Err(EntryProblem::HolesWithFile),
        (Some(f), None) => Geometry::File(f),
        (None, Some(o)) => Geometry::Outline(o, &listed.holes),
    };
    if let Some(q) = listed.quantity.filter(|q| !(q.is_finite() && *q >= 0.0)) {
        return Err(EntryProblem::Quantity(q));
    }
    if let Some(ws) = &listed.wrenches {
        if ws.is_empty() {
            return Err(EntryProblem::EmptyWrenches);
        }
        if let Some(k) = ws.iter().position(|w| w.iter().any(|x| !x.is_finite())) {
            return Err(EntryProblem::NonFiniteWrench(k));
        }
    }
    if let Some(t) = listed
        .chord_tolerance
        .filter(|t| !(t.is_finite() && *t > 0.0))
    {
        return Err(EntryProblem::ChordTolerance(t));
    }
    Ok(geometry)
}
