//! Catalogues: a `catalog.toml` manifest or a plain directory of part
//! files, each part read and validated on its own (through `crate::part`)
//! so that one broken part never stops the others.

use crate::error::CatalogError;
use crate::part::{read_raw, validate_part, Format, RawPart, ReadOptions};
use crate::units::{self, LengthUnit};
use fixplan_core::{Part, Units};
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

fn read_options(units: Units, opts: &LoadOptions, manifest_tol: Option<f64>) -> ReadOptions {
    let mut r = ReadOptions::new(units);
    if let Some(t) = opts.chord_tolerance.or(manifest_tol) {
        r.chord_tolerance = t;
    }
    if let Some(t) = opts.join_tolerance {
        r.join_tolerance = t;
    }
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
    let ropts = read_options(units, opts, None);
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
            let mut cp = blank_part(id, Some(name));
            read_file_part(&mut cp, &f, &ropts, &[]);
            cp
        })
        .collect();
    Ok(Catalog {
        name: dir_name(dir),
        units,
        source: dir.to_path_buf(),
        parts,
    })
}

fn blank_part(id: String, file: Option<PathBuf>) -> CatalogPart {
    CatalogPart {
        id,
        file,
        part: Err(String::new()),
        warnings: Vec::new(),
        quantity: 1.0,
        top_k: None,
        wrenches: None,
    }
}

/// The prefix of every message about a part: its id and its file.
fn who(cp: &CatalogPart) -> String {
    match &cp.file {
        Some(f) => format!("{} ({})", cp.id, f.display()),
        None => cp.id.clone(),
    }
}

/// Reads, merges extra access polygons, validates; fills `cp.part` and
/// `cp.warnings` with messages that name the part.
fn read_file_part(
    cp: &mut CatalogPart,
    path: &Path,
    ropts: &ReadOptions,
    extra_access: &[Vec<[f64; 2]>],
) {
    let prefix = who(cp);
    let result = (|| {
        let format = Format::from_path(path)
            .ok_or_else(|| "unknown file type (expected .dxf, .svg or .json)".to_string())?;
        let bytes =
            std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        let mut raw = read_raw(&bytes, format, ropts)?;
        raw.access.extend(extra_access.iter().cloned());
        validate_part(raw, ropts.units)
    })();
    finish_part(cp, &prefix, result);
}

fn finish_part(cp: &mut CatalogPart, prefix: &str, result: Result<(Part, Vec<String>), String>) {
    match result {
        Ok((part, warnings)) => {
            cp.warnings
                .extend(warnings.into_iter().map(|w| format!("{prefix}: {w}")));
            cp.part = Ok(part);
        }
        Err(e) => cp.part = Err(format!("{prefix}: {e}")),
    }
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Entry {
    id: String,
    #[serde(default)]
    file: Option<PathBuf>,
    #[serde(default)]
    outline: Option<Vec<[f64; 2]>>,
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

fn load_manifest(path: &Path, opts: &LoadOptions) -> Result<Catalog, CatalogError> {
    let text = std::fs::read_to_string(path).map_err(|source| CatalogError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let mut table: toml::Table = text
        .parse()
        .map_err(|e: toml::de::Error| invalid(path, format!("not a readable manifest: {e}")))?;
    let base = path.parent().unwrap_or(Path::new("."));
    let name = match table.remove("name") {
        Some(toml::Value::String(s)) => s,
        None => dir_name(base),
        Some(v) => return Err(invalid(path, format!("name {v} is not a string"))),
    };
    let units = match table.remove("units") {
        Some(toml::Value::String(s)) => units::parse_units(&s).map_err(|e| invalid(path, e))?,
        None => return Err(invalid(path, "no units: say units = \"mm\" or \"in\"")),
        Some(v) => return Err(invalid(path, format!("unknown units {v}"))),
    };
    let manifest_tol = match table.remove("chord_tolerance") {
        None => None,
        Some(v) => match v.as_float().or(v.as_integer().map(|i| i as f64)) {
            Some(t) if t.is_finite() && t > 0.0 => Some(t),
            _ => {
                return Err(invalid(
                    path,
                    format!("chord_tolerance {v} must be a positive number"),
                ))
            }
        },
    };
    let entries = match table.remove("part") {
        None => Vec::new(),
        Some(toml::Value::Array(a)) => a,
        Some(_) => return Err(invalid(path, "part must be an array of tables ([[part]])")),
    };
    if let Some(k) = table.keys().next() {
        return Err(invalid(
            path,
            format!("unknown manifest field \"{k}\" (expected name, units, chord_tolerance, part)"),
        ));
    }
    let ropts = read_options(units, opts, manifest_tol);
    let mut seen: std::collections::HashMap<String, usize> = Default::default();
    let mut parts = Vec::with_capacity(entries.len());
    for (i, v) in entries.into_iter().enumerate() {
        let fallback_id = v
            .get("id")
            .and_then(|x| x.as_str())
            .map(str::to_string)
            .unwrap_or_else(|| format!("part #{}", i + 1));
        let entry: Entry = match v.try_into() {
            Ok(e) => e,
            Err(e) => {
                let mut cp = blank_part(fallback_id, None);
                cp.part = Err(format!(
                    "{}: manifest entry {}: {}",
                    cp.id,
                    i + 1,
                    e.message()
                ));
                parts.push(cp);
                continue;
            }
        };
        let mut cp = blank_part(entry.id.clone(), entry.file.clone());
        cp.top_k = entry.top_k;
        cp.wrenches = entry.wrenches.clone();
        let prefix = who(&cp);
        let problem = entry_problem(&entry, &mut seen, i);
        if let Some(p) = problem {
            cp.part = Err(format!("{prefix}: {p}"));
            parts.push(cp);
            continue;
        }
        cp.quantity = entry.quantity.unwrap_or(1.0);
        let mut eopts = ropts;
        if let Some(t) = opts
            .chord_tolerance
            .is_none()
            .then_some(entry.chord_tolerance)
            .flatten()
        {
            eopts.chord_tolerance = t;
        }
        if let Some(u) = &entry.units {
            match LengthUnit::parse(u) {
                Some(u) => eopts.fallback = u,
                None => {
                    cp.part = Err(format!("{prefix}: unknown units \"{u}\""));
                    parts.push(cp);
                    continue;
                }
            }
        }
        match (&entry.file, &entry.outline) {
            (Some(f), None) => read_file_part(&mut cp, &base.join(f), &eopts, &entry.access),
            (None, Some(outline)) => {
                // Inline numbers are in the entry's units, else the
                // catalogue's.
                let k = eopts.fallback.factor_to(units);
                let sc = |p: &Vec<[f64; 2]>| p.iter().map(|q| [q[0] * k, q[1] * k]).collect();
                let raw = RawPart {
                    outline: sc(outline),
                    access: entry.access.iter().map(sc).collect(),
                    warnings: Vec::new(),
                };
                finish_part(&mut cp, &prefix, validate_part(raw, units));
            }
            _ => unreachable_entry(&mut cp, &prefix),
        }
        parts.push(cp);
    }
    Ok(Catalog {
        name,
        units,
        source: path.to_path_buf(),
        parts,
    })
}

/// An entry with both or neither of `file` and `outline` was already
/// rejected by [`entry_problem`]; kept as an error rather than a panic.
fn unreachable_entry(cp: &mut CatalogPart, prefix: &str) {
    cp.part = Err(format!("{prefix}: give either file or outline"));
}

fn entry_problem(
    e: &Entry,
    seen: &mut std::collections::HashMap<String, usize>,
    i: usize,
) -> Option<String> {
    if e.id.trim().is_empty() {
        return Some("empty id".into());
    }
    if let Some(first) = seen.get(&e.id) {
        return Some(format!(
            "duplicate id: entry {} has the same id as entry {}",
            i + 1,
            first + 1
        ));
    }
    seen.insert(e.id.clone(), i);
    match (&e.file, &e.outline) {
        (Some(_), Some(_)) => return Some("give either file or outline, not both".into()),
        (None, None) => return Some("no file and no outline".into()),
        _ => {}
    }
    if let Some(q) = e.quantity {
        if !(q.is_finite() && q >= 0.0) {
            return Some(format!("quantity {q} must be a non-negative number"));
        }
    }
    if let Some(ws) = &e.wrenches {
        if ws.is_empty() {
            return Some("wrenches is an empty list (leave it out for the default metric)".into());
        }
        if let Some(k) = ws.iter().position(|w| w.iter().any(|x| !x.is_finite())) {
            return Some(format!("wrench {k} has a non-finite component"));
        }
    }
    if let Some(t) = e.chord_tolerance {
        if !(t.is_finite() && t > 0.0) {
            return Some(format!("chord_tolerance {t} must be a positive number"));
        }
    }
    None
}
