//! DXF part outlines, read with the `dxf` crate and written by hand.
//!
//! What a part drawing means here: closed loops made of LWPOLYLINE,
//! POLYLINE (with bulge arcs), CIRCLE, ELLIPSE, SPLINE, or chains of LINE,
//! ARC, SPLINE and open polyline entities that meet end to end, in model
//! space or in blocks placed by INSERT (see [`walk`]).
//!
//! **Arcs.** Bulges (group code 42), ARC and CIRCLE entities, and
//! ELLIPSEs whose axes are equal stay exact circular arcs: bulge vertices
//! (SPEC 8.1), a CIRCLE two half arcs (bulge 1 on both vertices), and a
//! LINE/ARC chain joined backwards has its bulges negated and moved with
//! their edges. Other ELLIPSEs and SPLINEs are flattened within the chord
//! tolerance, and so is everything with
//! [`ArcMode::Flatten`](super::raw::ArcMode) (as this reader did before
//! arcs, polygon for polygon), every access loop (access constraints
//! being polygons), and arcs in a block inserted with unequal x and y
//! scales (they are elliptic there). The loop with the largest area is the
//! part; loops on a layer named `ACCESS` or `KEEPOUT` (any case) are access
//! constraints; the loops directly inside the part are its holes (SPEC 9:
//! bores, windows, slots), in the order of the drawing, and loops inside a
//! hole (a counterbore's drawn step, text) are ignored with a warning
//! (`holes = "ignore"` drops every hole with a warning, as fixplan did
//! before holes). Paper-space entities (title blocks) and
//! annotations are skipped. `docs/cad-files.md` lists entity by entity
//! what is read.

mod entities;
mod error;
mod spline;
mod transform;
mod walk;
mod write;

pub use error::{DxfError, OpenCause};
pub use write::write_dxf;

use super::outline::{join_pieces, nearest_other_end, pick_outline, pick_outlines, positions, P};
use super::raw::{RawPart, ReadOptions};
use crate::units::LengthUnit;
use dxf::enums::Units as DxfUnits;
use dxf::Drawing;
use fixplan_core::{Units, Vertex};
use walk::{DxfFindings, DxfWalk, Layer};

/// `$INSUNITS` as a length unit; `None` when the drawing says "unitless"
/// (then the catalogue's fallback applies).
fn drawing_units(units: DxfUnits) -> Result<Option<LengthUnit>, DxfError> {
    Ok(Some(match units {
        DxfUnits::Unitless => return Ok(None),
        DxfUnits::Millimeters => LengthUnit::Mm,
        DxfUnits::Centimeters => LengthUnit::Cm,
        DxfUnits::Meters => LengthUnit::M,
        DxfUnits::Inches => LengthUnit::In,
        DxfUnits::Feet => LengthUnit::Ft,
        other => return Err(DxfError::UnknownUnits(format!("{other:?}"))),
    }))
}

/// Parses the drawing; the `dxf` crate is not written for hostile input,
/// so a panic inside it must become this part's error, not the
/// catalogue's end.
fn load_drawing(bytes: &[u8]) -> Result<Drawing, DxfError> {
    let loaded = std::panic::catch_unwind(|| {
        let mut cursor = std::io::Cursor::new(bytes);
        Drawing::load(&mut cursor)
    });
    match loaded {
        Ok(Ok(d)) => Ok(d),
        Ok(Err(e)) => Err(DxfError::Unreadable(e.to_string())),
        Err(_) => Err(DxfError::ReaderFailed),
    }
}

/// Units of a drawing and the factor from them to catalogue units.
#[derive(Clone, Copy)]
struct Scale {
    file: LengthUnit,
    factor: f64,
    units: Units,
}

impl Scale {
    fn pt(self, p: P) -> P {
        [p[0] * self.factor, p[1] * self.factor]
    }

    fn vertex(self, vertex: Vertex) -> Vertex {
        Vertex::new(vertex.x * self.factor, vertex.y * self.factor, vertex.bulge)
    }
}

/// How far from an open end another end still counts as "near" (a gap
/// rather than a stray line): a hundred join tolerances, or 2% of the
/// drawing's size, whichever is larger (file units).
fn near_radius(layer: &Layer, join_tol: f64) -> f64 {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    let pts = layer
        .pieces
        .iter()
        .flat_map(|p| p.pts.iter())
        .chain(layer.loops.iter().flat_map(|l| l.0.iter()));
    for v in pts {
        lo = [lo[0].min(v.x), lo[1].min(v.y)];
        hi = [hi[0].max(v.x), hi[1].max(v.y)];
    }
    let size = (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
    let size = if size.is_finite() { size } else { 0.0 };
    (100.0 * join_tol).max(0.02 * size)
}

/// A layer's loops in catalogue units: its closed entities, then its
/// pieces joined within `join_tol` (file units); a chain that does not
/// close is an error, because the outline would be a guess.
fn close_layer(
    layer: Layer,
    join_tol: f64,
    scale: Scale,
) -> Result<Vec<(Vec<Vertex>, String)>, DxfError> {
    let near = near_radius(&layer, join_tol);
    let Layer {
        mut loops,
        pieces,
        ignored,
    } = layer;
    let (joined, open) = join_pieces(pieces, join_tol);
    if let Some(o) = open.first() {
        let ends = [o.start, o.end];
        let touch = (10.0 * join_tol).max(1e-9 * near);
        let unread = ignored.iter().find(|(_, pts)| {
            pts.iter()
                .any(|p| ends.iter().any(|e| super::outline::dist(*p, *e) <= touch))
        });
        let gap = ends
            .iter()
            .filter_map(|&e| nearest_other_end(&open, 0, e))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        let cause = match (unread, gap) {
            (Some((label, _)), _) => OpenCause::Unread(label.clone()),
            (None, Some((d, at, other))) if d <= near => OpenCause::Gap {
                other: other.to_string(),
                distance: d * scale.factor,
                at: scale.pt(at),
                units: scale.units,
            },
            _ => OpenCause::Stray {
                unread: ignored.len(),
            },
        };
        return Err(DxfError::OpenLoop {
            entities: o.labels.len(),
            first: o.labels.first().cloned().unwrap_or_default(),
            start: scale.pt(o.start),
            end: scale.pt(o.end),
            units: scale.units,
            gap: join_tol,
            gap_unit: scale.file,
            cause: Box::new(cause),
        });
    }
    loops.extend(
        joined
            .into_iter()
            .map(|l| (l, "joined LINE/ARC chain".to_string())),
    );
    Ok(loops
        .into_iter()
        .map(|(pts, label)| (pts.into_iter().map(|v| scale.vertex(v)).collect(), label))
        .collect())
}

/// The loops of a drawing in catalogue units, the access polygons, and the
/// reader's warnings.
type Loops = (Vec<(Vec<Vertex>, String)>, Vec<Vec<P>>, Vec<String>);

fn read_loops(bytes: &[u8], opts: &ReadOptions) -> Result<Loops, DxfError> {
    let drawing = load_drawing(bytes)?;
    let file = drawing_units(drawing.header.default_drawing_units)?.unwrap_or(opts.fallback);
    let scale = Scale {
        file,
        factor: file.factor_to(opts.units),
        units: opts.units,
    };
    // Tolerances are given in catalogue units; the geometry is still in
    // file units here.
    let tol = opts.chord_tolerance / scale.factor;
    let join_tol = opts.join_tolerance / scale.factor;
    let mut walk = DxfWalk::new(&drawing, opts, tol, join_tol);
    walk.run(&drawing)?;
    let DxfFindings {
        part,
        access,
        warnings,
    } = walk.found;
    let part_loops = close_layer(part, join_tol, scale)?;
    let access = close_layer(access, join_tol, scale)?
        .into_iter()
        .map(|(pts, _)| positions(&pts))
        .collect();
    Ok((part_loops, access, warnings))
}

/// Reads a DXF drawing into a part in `opts.units`, unvalidated: the
/// reader finds the loops, [`validate_part`](super::validate_part) judges
/// them the same way for every format. A second outer loop is an error
/// (see [`read_dxf_parts`] for sheets).
pub fn read_dxf(bytes: &[u8], opts: &ReadOptions) -> Result<RawPart, DxfError> {
    let (loops, access, warnings) = read_loops(bytes, opts)?;
    Ok(pick_outline(
        loops, access, warnings, opts.units, opts.holes,
    )?)
}

/// Reads a DXF sheet: every outer loop a part, in sheet order (by the
/// bottom edge of its bounding box, then the left edge), each with the
/// loops inside it and the access loops that start inside it.
pub fn read_dxf_parts(bytes: &[u8], opts: &ReadOptions) -> Result<Vec<RawPart>, DxfError> {
    let (loops, access, warnings) = read_loops(bytes, opts)?;
    Ok(pick_outlines(
        loops, access, warnings, opts.units, opts.holes,
    )?)
}
