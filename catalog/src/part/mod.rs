//! Part files: DXF, SVG and JSON readers and writers, and the one
//! validation every format goes through. Uses only `crate::units` outside
//! this folder; readers use `raw` and `outline`, never each other.

mod dxf;
mod json;
mod outline;
mod raw;
mod svg;
mod validate;

pub use dxf::{read_dxf, read_dxf_parts, write_dxf, DxfError, OpenCause};
pub use json::{read_json, write_json, JsonError};
pub use outline::OutlinePickError;
pub(crate) use outline::{flatten_vertices, keep_holes};
pub use raw::{
    ArcMode, Format, HoleMode, LayerFilter, LimitExceeded, Limits, PolygonRole, RawPart,
    ReadOptions, DEFAULT_CHORD_TOLERANCE_MM, DEFAULT_JOIN_TOLERANCE_MM,
};
pub use svg::{
    read_svg, read_svg_parts, write_svg, ElementProblem, PathError, SvgError, TransformError,
};
pub use validate::{validate_part, InvalidPolygon, PolygonProblem};

use fixplan_core::Part;

/// Why a part file's bytes do not give a [`RawPart`]: the options, or the
/// format's own reader.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReadError {
    /// [`ReadOptions::chord_tolerance`] is not a positive number.
    #[error("chord tolerance {0} must be a positive number")]
    ChordTolerance(f64),
    /// [`ReadOptions::join_tolerance`] is negative or not a number.
    #[error("join tolerance {0} must be a non-negative number")]
    JoinTolerance(f64),
    /// The file is larger than [`Limits::file_bytes`].
    #[error(transparent)]
    Limit(#[from] LimitExceeded),
    /// The DXF reader's finding.
    #[error(transparent)]
    Dxf(#[from] DxfError),
    /// The SVG reader's finding.
    #[error(transparent)]
    Svg(#[from] SvgError),
    /// The JSON reader's finding.
    #[error(transparent)]
    Json(#[from] JsonError),
}

/// Why a part file's bytes do not give a valid part: unreadable, or read
/// but not an outline SPEC accepts.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParseError {
    /// The file could not be read as its format.
    #[error(transparent)]
    Read(#[from] ReadError),
    /// The file was read; a polygon in it is invalid.
    #[error(transparent)]
    Invalid(#[from] InvalidPolygon),
}

/// Reads a part file's bytes without validating the polygons, for callers
/// that add polygons of their own (a manifest entry's `access`) before
/// [`validate_part`].
pub fn read_raw(bytes: &[u8], format: Format, opts: &ReadOptions) -> Result<RawPart, ReadError> {
    check_options(bytes, opts)?;
    Ok(match format {
        Format::Dxf => read_dxf(bytes, opts)?,
        Format::Svg => read_svg(bytes, opts)?,
        Format::Json => read_json(bytes, opts)?,
    })
}

/// Tolerances that make sense, and a file within [`Limits::file_bytes`],
/// before any reader looks at the bytes.
fn check_options(bytes: &[u8], opts: &ReadOptions) -> Result<(), ReadError> {
    if !(opts.chord_tolerance.is_finite() && opts.chord_tolerance > 0.0) {
        return Err(ReadError::ChordTolerance(opts.chord_tolerance));
    }
    if !(opts.join_tolerance.is_finite() && opts.join_tolerance >= 0.0) {
        return Err(ReadError::JoinTolerance(opts.join_tolerance));
    }
    let len = u64::try_from(bytes.len()).unwrap_or(u64::MAX);
    Ok(opts.limits.check_file_bytes(len)?)
}

/// [`read_raw`] for a file that may be a sheet: with
/// [`ReadOptions::sheet`], every outer loop of a DXF or SVG drawing as a
/// part of its own, in the order [`read_dxf_parts`] gives; otherwise (and
/// for JSON, which holds one part) the one part.
pub fn read_parts(
    bytes: &[u8],
    format: Format,
    opts: &ReadOptions,
) -> Result<Vec<RawPart>, ReadError> {
    if !opts.sheet {
        return Ok(vec![read_raw(bytes, format, opts)?]);
    }
    check_options(bytes, opts)?;
    Ok(match format {
        Format::Dxf => read_dxf_parts(bytes, opts)?,
        Format::Svg => read_svg_parts(bytes, opts)?,
        Format::Json => vec![read_json(bytes, opts)?],
    })
}

/// Reads and validates a part file's bytes: the part and the warnings of
/// the repairs made, or the first problem found.
pub fn parse_part(
    bytes: &[u8],
    format: Format,
    opts: &ReadOptions,
) -> Result<(Part, Vec<String>), ParseError> {
    let raw = read_raw(bytes, format, opts)?;
    Ok(validate_part(raw, opts.units)?)
}
