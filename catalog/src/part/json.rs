//! JSON parts: the `part` / `holes` / `access` fields of SPEC Appendix A.
//!
//! A whole case file is accepted (its kit and parameters are ignored here:
//! the catalogue's kit applies), and so is core's own `Part` serialisation
//! (`outline` instead of `part`), so a part exported by fixplan reads back.
//! An optional `units` field says what the numbers are in. Outline
//! and hole vertices are `[x, y]` or `[x, y, bulge]` (SPEC 8.1, 9.1); with
//! [`ArcMode::Flatten`](super::raw::ArcMode) the arcs are flattened within
//! the chord tolerance. Access constraints are polygons.

use super::outline::{flatten_vertices, keep_holes};
use super::raw::{PolygonRole, RawPart, ReadOptions};
use crate::units::LengthUnit;
use fixplan_core::{Part, Units, Vertex};
use serde_json::Value;

/// Why a JSON file does not give a part's polygons.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum JsonError {
    /// Not JSON at all; the parser's message says where.
    #[error("not a readable JSON file: {0}")]
    Unreadable(String),
    /// JSON, but not an object.
    #[error("not a part: expected an object with a \"part\" field")]
    NotAnObject,
    /// A `units` string no reader knows.
    #[error("unknown units \"{0}\"")]
    UnknownUnits(String),
    /// A `units` field that is not a string.
    #[error("unknown units {0}")]
    UnitsNotAString(Value),
    /// Neither `part` nor `outline`.
    #[error("no \"part\" field (the outline as a list of [x, y] points)")]
    NoOutline,
    /// A polygon that is not a list.
    #[error("{0} is not a list of [x, y] points")]
    NotAList(PolygonRole),
    /// A vertex that is not a two-element list.
    #[error("{polygon}: vertex {vertex} is not an [x, y] pair: {value}")]
    NotAPair {
        /// The polygon it belongs to.
        polygon: PolygonRole,
        /// Its index, from 0.
        vertex: usize,
        /// What was there instead.
        value: Value,
    },
    /// An outline or hole vertex that is not `[x, y]` or `[x, y, bulge]`.
    #[error("{polygon}: vertex {vertex} is not an [x, y] or [x, y, bulge] list: {value}")]
    NotAVertex {
        /// The outline or the hole.
        polygon: PolygonRole,
        /// Its index, from 0.
        vertex: usize,
        /// What was there instead.
        value: Value,
    },
    /// A two-element vertex with something else than numbers in it.
    #[error("{polygon}: vertex {vertex} is not a pair of numbers: {value}")]
    NotNumbers {
        /// The polygon it belongs to.
        polygon: PolygonRole,
        /// Its index, from 0.
        vertex: usize,
        /// What was there instead.
        value: Value,
    },
    /// An `access` field that is not a list.
    #[error("\"access\" is not a list of polygons")]
    AccessNotAList,
    /// A `holes` field that is not a list.
    #[error("\"holes\" is not a list of loops")]
    HolesNotAList,
}

fn point(value: &Value, polygon: PolygonRole, vertex: usize) -> Result<[f64; 2], JsonError> {
    match value.as_array().map(|a| a.as_slice()) {
        Some([x, y]) => match (x.as_f64(), y.as_f64()) {
            (Some(x), Some(y)) => Ok([x, y]),
            _ => Err(JsonError::NotNumbers {
                polygon,
                vertex,
                value: value.clone(),
            }),
        },
        _ => Err(JsonError::NotAPair {
            polygon,
            vertex,
            value: value.clone(),
        }),
    }
}

/// An outline or hole vertex: a point, or a point and the bulge of its
/// edge.
fn vertex(item: &Value, polygon: PolygonRole, index: usize) -> Result<Vertex, JsonError> {
    match item.as_array().map(|a| a.as_slice()) {
        Some([_, _]) => point(item, polygon, index).map(Vertex::from),
        Some([x, y, b]) => match (x.as_f64(), y.as_f64(), b.as_f64()) {
            (Some(x), Some(y), Some(b)) => Ok(Vertex::new(x, y, b)),
            _ => Err(JsonError::NotNumbers {
                polygon,
                vertex: index,
                value: item.clone(),
            }),
        },
        _ => Err(JsonError::NotAVertex {
            polygon,
            vertex: index,
            value: item.clone(),
        }),
    }
}

/// A loop of outline or hole vertices.
fn vertex_loop(value: &Value, role: PolygonRole) -> Result<Vec<Vertex>, JsonError> {
    let arr = value.as_array().ok_or(JsonError::NotAList(role))?;
    arr.iter()
        .enumerate()
        .map(|(i, v)| vertex(v, role, i))
        .collect()
}

/// The `holes` field: absent, `null` or a list of loops.
fn holes(obj: &serde_json::Map<String, Value>) -> Result<Vec<Vec<Vertex>>, JsonError> {
    match obj.get("holes") {
        None | Some(Value::Null) => Ok(Vec::new()),
        Some(Value::Array(list)) => list
            .iter()
            .enumerate()
            .map(|(k, h)| vertex_loop(h, PolygonRole::Hole(k)))
            .collect(),
        Some(_) => Err(JsonError::HolesNotAList),
    }
}

fn polygon(value: &Value, role: PolygonRole) -> Result<Vec<[f64; 2]>, JsonError> {
    let arr = value.as_array().ok_or(JsonError::NotAList(role))?;
    arr.iter()
        .enumerate()
        .map(|(i, p)| point(p, role, i))
        .collect()
}

/// The file's units: its `units` field, else the catalogue's fallback.
fn file_units(
    obj: &serde_json::Map<String, Value>,
    opts: &ReadOptions,
) -> Result<LengthUnit, JsonError> {
    match obj.get("units") {
        None | Some(Value::Null) => Ok(opts.fallback),
        Some(Value::String(s)) => {
            LengthUnit::parse(s).ok_or_else(|| JsonError::UnknownUnits(s.clone()))
        }
        Some(other) => Err(JsonError::UnitsNotAString(other.clone())),
    }
}

/// Reads a JSON part into `opts.units`, unvalidated, so that
/// [`validate_part`](super::validate_part) judges it the same way as a
/// drawing.
pub fn read_json(bytes: &[u8], opts: &ReadOptions) -> Result<RawPart, JsonError> {
    let v: Value =
        serde_json::from_slice(bytes).map_err(|e| JsonError::Unreadable(e.to_string()))?;
    let obj = v.as_object().ok_or(JsonError::NotAnObject)?;
    let src = file_units(obj, opts)?;
    let outline = obj
        .get("part")
        .or_else(|| obj.get("outline"))
        .ok_or(JsonError::NoOutline)?;
    let mut outline = vertex_loop(outline, PolygonRole::Outline)?;
    let mut holes = holes(obj)?;
    let mut access = Vec::new();
    match obj.get("access") {
        None | Some(Value::Null) => {}
        Some(Value::Array(list)) => {
            for (i, a) in list.iter().enumerate() {
                access.push(polygon(a, PolygonRole::Access(i))?);
            }
        }
        Some(_) => return Err(JsonError::AccessNotAList),
    }
    let f = src.factor_to(opts.units);
    if f != 1.0 {
        for v in outline.iter_mut().chain(holes.iter_mut().flatten()) {
            v.x *= f;
            v.y *= f;
        }
        for p in access.iter_mut().flatten() {
            p[0] *= f;
            p[1] *= f;
        }
    }
    if opts.arcs.flatten() {
        outline = flatten_vertices(&outline, true, opts.chord_tolerance);
        for h in holes.iter_mut() {
            *h = flatten_vertices(h, true, opts.chord_tolerance);
        }
    }
    let mut warnings = Vec::new();
    let named = holes
        .into_iter()
        .enumerate()
        .map(|(k, h)| (h, format!("hole {k}")))
        .collect();
    let holes = keep_holes(opts.holes, named, &mut warnings, opts.units);
    Ok(RawPart {
        outline,
        access,
        warnings,
        holes,
    })
}

/// Writes a part in the Appendix A field names, with its units (arc
/// vertices as `[x, y, bulge]`); `holes` only when it has some, so a part
/// without holes is written as before.
pub fn write_json(part: &Part, units: Units) -> String {
    let mut v = serde_json::json!({
        "units": units,
        "part": part.outline,
        "access": part.access,
    });
    if !part.holes.is_empty() {
        v["holes"] = serde_json::json!(part.holes);
    }
    // Serialising plain numbers and strings cannot fail; if a future
    // serde_json disagreed, an empty object is still valid JSON.
    serde_json::to_string_pretty(&v).unwrap_or_else(|_| "{}".into())
}
