//! JSON parts: the `part` / `access` fields of SPEC Appendix A.
//!
//! A whole case file is accepted (its kit and parameters are ignored here:
//! the catalogue's kit applies), and so is core's own `Part` serialisation
//! (`outline` instead of `part`), so a part exported by fixplan reads back.
//! An optional `units` field says what the numbers are in.

use super::raw::{RawPart, ReadOptions};
use crate::units::LengthUnit;
use fixplan_core::{Part, Units};
use serde_json::Value;

fn point(v: &Value, what: &str, i: usize) -> Result<[f64; 2], String> {
    match v.as_array().map(|a| a.as_slice()) {
        Some([x, y]) => match (x.as_f64(), y.as_f64()) {
            (Some(x), Some(y)) => Ok([x, y]),
            _ => Err(format!("{what}: vertex {i} is not a pair of numbers: {v}")),
        },
        _ => Err(format!("{what}: vertex {i} is not an [x, y] pair: {v}")),
    }
}

fn polygon(v: &Value, what: &str) -> Result<Vec<[f64; 2]>, String> {
    let arr = v
        .as_array()
        .ok_or_else(|| format!("{what} is not a list of [x, y] points"))?;
    arr.iter()
        .enumerate()
        .map(|(i, p)| point(p, what, i))
        .collect()
}

pub fn read_json(bytes: &[u8], opts: &ReadOptions) -> Result<RawPart, String> {
    let v: Value =
        serde_json::from_slice(bytes).map_err(|e| format!("not a readable JSON file: {e}"))?;
    let obj = v
        .as_object()
        .ok_or("not a part: expected an object with a \"part\" field")?;
    let src = match obj.get("units") {
        None | Some(Value::Null) => opts.fallback,
        Some(Value::String(s)) => {
            LengthUnit::parse(s).ok_or_else(|| format!("unknown units \"{s}\""))?
        }
        Some(other) => return Err(format!("unknown units {other}")),
    };
    let outline = obj
        .get("part")
        .or_else(|| obj.get("outline"))
        .ok_or("no \"part\" field (the outline as a list of [x, y] points)")?;
    let mut outline = polygon(outline, "outline")?;
    let mut access = Vec::new();
    match obj.get("access") {
        None | Some(Value::Null) => {}
        Some(Value::Array(list)) => {
            for (i, a) in list.iter().enumerate() {
                access.push(polygon(a, &format!("access constraint {i}"))?);
            }
        }
        Some(_) => return Err("\"access\" is not a list of polygons".into()),
    }
    let f = src.factor_to(opts.units);
    if f != 1.0 {
        for p in outline.iter_mut().chain(access.iter_mut().flatten()) {
            p[0] *= f;
            p[1] *= f;
        }
    }
    Ok(RawPart {
        outline,
        access,
        warnings: Vec::new(),
    })
}

/// Writes a part in the Appendix A field names, with its units.
pub fn write_json(part: &Part, units: Units) -> String {
    let v = serde_json::json!({
        "units": units,
        "part": part.outline,
        "access": part.access,
    });
    // Serialising plain numbers and strings cannot fail; if a future
    // serde_json disagreed, an empty object is still valid JSON.
    serde_json::to_string_pretty(&v).unwrap_or_else(|_| "{}".into())
}
