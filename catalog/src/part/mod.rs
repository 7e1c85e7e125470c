//! Part files: DXF, SVG and JSON readers and writers, and the one
//! validation every format goes through. Uses only `crate::units` outside
//! this folder; readers use `raw` and `outline`, never each other.

mod dxf;
mod json;
mod outline;
mod raw;
mod svg;
mod validate;

pub use dxf::{read_dxf, write_dxf};
pub use json::{read_json, write_json};
pub use raw::{
    Format, RawPart, ReadOptions, DEFAULT_CHORD_TOLERANCE_MM, DEFAULT_JOIN_TOLERANCE_MM,
};
pub use svg::{read_svg, write_svg};
pub use validate::validate_part;

use fixplan_core::Part;

/// Reads a part file's bytes without validating the polygons.
pub fn read_raw(bytes: &[u8], format: Format, opts: &ReadOptions) -> Result<RawPart, String> {
    if !(opts.chord_tolerance.is_finite() && opts.chord_tolerance > 0.0) {
        return Err(format!(
            "chord tolerance {} must be a positive number",
            opts.chord_tolerance
        ));
    }
    if !(opts.join_tolerance.is_finite() && opts.join_tolerance >= 0.0) {
        return Err(format!(
            "join tolerance {} must be a non-negative number",
            opts.join_tolerance
        ));
    }
    match format {
        Format::Dxf => read_dxf(bytes, opts),
        Format::Svg => read_svg(bytes, opts),
        Format::Json => read_json(bytes, opts),
    }
}

/// Reads and validates a part file's bytes: the part and the warnings of
/// the repairs made, or the first problem found.
pub fn parse_part(
    bytes: &[u8],
    format: Format,
    opts: &ReadOptions,
) -> Result<(Part, Vec<String>), String> {
    let raw = read_raw(bytes, format, opts)?;
    validate_part(raw, opts.units)
}
