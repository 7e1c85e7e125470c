//! DXF part outlines, read with the `dxf` crate and written by hand.
//!
//! What a part drawing means here: closed loops made of LWPOLYLINE,
//! POLYLINE (with bulge arcs), CIRCLE, ELLIPSE, or chains of LINE and ARC
//! entities that meet end to end.
//!
//! **Arcs.** Bulges (group code 42), ARC and CIRCLE entities, and
//! ELLIPSEs whose axes are equal stay exact circular arcs: bulge vertices
//! (SPEC 8.1), a CIRCLE two half arcs (bulge 1 on both vertices), and a
//! LINE/ARC chain joined backwards has its bulges negated and moved with
//! their edges. Other ELLIPSEs are flattened within the chord tolerance,
//! and so is everything with [`ArcMode::Flatten`](super::raw::ArcMode) (as
//! this reader did before arcs, polygon for polygon) and every access
//! loop, access constraints being polygons. The loop with the largest area is the
//! part; loops on a layer named `ACCESS` or `KEEPOUT` (any case) are access
//! constraints; other loops inside the part (holes, pockets) are ignored
//! with a warning, because the method of Brost & Goldberg holds a part by
//! its outer silhouette only. Paper-space entities (title blocks) and
//! annotations are skipped.

use super::outline::{
    arc_pieces, arc_points, circle_loop, exact_arc, exact_circle, flatten_vertices, fmt, fmt_pt,
    join_pieces, pick_outline, positions, straight, OutlineError, Piece, MAX_ARC_PIECES, P,
};
use super::raw::{RawPart, ReadOptions};
use crate::units::LengthUnit;
use dxf::entities::EntityType;
use dxf::enums::Units as DxfUnits;
use dxf::Drawing;
use fixplan_core::outline::Vertex;
use fixplan_core::{Part, Units};

fn is_access_layer(layer: &str) -> bool {
    let l = layer.trim();
    l.eq_ignore_ascii_case("access") || l.eq_ignore_ascii_case("keepout")
}

/// `$INSUNITS` as a length unit; `None` when the drawing says "unitless"
/// (then the catalogue's fallback applies).
fn drawing_units(u: DxfUnits) -> Result<Option<LengthUnit>, DxfError> {
    Ok(Some(match u {
        DxfUnits::Unitless => return Ok(None),
        DxfUnits::Millimeters => LengthUnit::Mm,
        DxfUnits::Centimeters => LengthUnit::Cm,
        DxfUnits::Meters => LengthUnit::M,
        DxfUnits::Inches => LengthUnit::In,
        DxfUnits::Feet => LengthUnit::Ft,
        other => return Err(DxfError::UnknownUnits(format!("{other:?}"))),
    }))
}

/// Entities are drawn in their object coordinate system; for the usual
/// extrusion (0, 0, 1) that is the world, for (0, 0, -1) (mirrored
/// entities, common in files from some CAM tools) x is flipped. Anything
/// tilted out of the plane is not a planar outline.
fn ocs_flip(nx: f64, ny: f64, nz: f64) -> Option<bool> {
    if nx.abs() > 1e-9 || ny.abs() > 1e-9 || nz == 0.0 || !nz.is_finite() {
        None
    } else {
        Some(nz < 0.0)
    }
}

/// Mirrors x (and so the turning direction of every arc) when `flip`.
fn flip_all(pts: &mut [Vertex], flip: bool) {
    if flip {
        for p in pts {
            p.x = -p.x;
            if p.bulge != 0.0 {
                p.bulge = -p.bulge;
            }
        }
    }
}

/// Why a DXF file does not give a part.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DxfError {
    /// The `dxf` crate could not parse the file; its message says where.
    #[error("not a readable DXF file: {0}")]
    Unreadable(String),
    /// The `dxf` crate panicked on the file (it is not written for hostile
    /// input); the panic is caught so it stays this part's problem.
    #[error("not a readable DXF file (the DXF reader failed on it)")]
    ReaderFailed,
    /// `$INSUNITS` names a unit other than mm, cm, m, in or ft (its name in
    /// the `dxf` crate).
    #[error("unknown units: $INSUNITS is {0}; supported are mm, cm, m, in and ft (or unitless, with the catalogue's units)")]
    UnknownUnits(String),
    /// LINE/ARC entities (or open polylines) whose chain does not close:
    /// usually a gap in the drawing, so the ends are given.
    #[error("open loop: {} end at {} and {} {} with nothing within {} {} to join (a gap in the outline?)",
        chain_name(*.entities, .first), fmt_pt(*.start), fmt_pt(*.end), .units.label(), fmt(*.gap), .gap_unit.label())]
    OpenLoop {
        /// How many entities the chain has.
        entities: usize,
        /// The chain's first entity, e.g. `LINE #3 on layer 0`.
        first: String,
        /// One free end, catalogue units.
        start: [f64; 2],
        /// The other free end, catalogue units.
        end: [f64; 2],
        /// The catalogue's units.
        units: Units,
        /// The join tolerance, in the file's units.
        gap: f64,
        /// The file's units.
        gap_unit: LengthUnit,
    },
    /// The loops found do not make one part.
    #[error(transparent)]
    Outline(#[from] OutlineError),
}

/// "LINE #1 on layer 0", or "3 entities from LINE #1 on layer 0".
fn chain_name(entities: usize, first: &str) -> String {
    if entities == 1 {
        first.to_string()
    } else {
        format!("{entities} entities from {first}")
    }
}

/// What one entity adds to the drawing.
enum Shape {
    /// A loop on its own (closed polyline, circle, full ellipse).
    Closed(Vec<Vertex>),
    /// A piece to be joined with others (line, arc, open polyline).
    Open(Vec<Vertex>),
    /// Geometry this reader cannot use; the reason ends the warning.
    Ignored(&'static str),
    /// Not geometry (text, dimensions, points...).
    Nothing,
}

const NOT_PLANAR: Shape = Shape::Ignored("is not in the XY plane");

/// The loops and pieces of one kind of layer (part or access).
#[derive(Default)]
struct Layer {
    loops: Vec<(Vec<Vertex>, String)>,
    pieces: Vec<Piece>,
}

/// How curves are read: chords within `tol` (file units) when `flatten`,
/// else exact arcs (and chords for what is not circular).
#[derive(Clone, Copy)]
struct Curves {
    tol: f64,
    flatten: bool,
}

/// Everything the entities of a drawing gave, still in file units.
#[derive(Default)]
struct Found {
    part: Layer,
    access: Layer,
    warnings: Vec<String>,
}

impl Found {
    /// Sorts entity number `k` (from 0, all spaces) into its layer; access
    /// loops are always flattened.
    fn add(&mut self, k: usize, e: &dxf::entities::Entity, curves: Curves) {
        if e.common.is_in_paper_space {
            return;
        }
        let layer = &e.common.layer;
        let label = format!("{} #{} on layer {layer}", entity_name(&e.specific), k + 1);
        let (dest, curves) = if is_access_layer(layer) {
            let flat = Curves {
                flatten: true,
                ..curves
            };
            (&mut self.access, flat)
        } else {
            (&mut self.part, curves)
        };
        match entity_shape(&e.specific, curves) {
            Shape::Closed(pts) => dest.loops.push((pts, label)),
            Shape::Open(pts) if pts.len() >= 2 => dest.pieces.push(Piece { pts, label }),
            Shape::Ignored(why) => self.warnings.push(format!("{label} {why}; ignored")),
            Shape::Open(_) | Shape::Nothing => {}
        }
    }
}

fn entity_shape(e: &EntityType, curves: Curves) -> Shape {
    match e {
        EntityType::Line(l) => Shape::Open(straight(vec![[l.p1.x, l.p1.y], [l.p2.x, l.p2.y]])),
        EntityType::Arc(a) => arc_shape(a, curves),
        EntityType::Circle(c) => circle_shape(c, curves),
        EntityType::Ellipse(el) => ellipse_shape(el, curves),
        EntityType::LwPolyline(pl) => lwpolyline_shape(pl, curves),
        EntityType::Polyline(pl) => polyline_shape(pl, curves),
        EntityType::Spline(_) | EntityType::Insert(_) => {
            Shape::Ignored("is not supported (explode or convert it to polylines)")
        }
        // Text, dimensions, points and the like are annotations.
        _ => Shape::Nothing,
    }
}

/// A circular arc from angle `a0` (radians) sweeping `sweep` about `c`:
/// one or two bulge vertices, or chords.
fn circular(c: P, r: f64, a0: f64, sweep: f64, curves: Curves) -> Vec<Vertex> {
    if curves.flatten {
        let mut pts = vec![[c[0] + r * a0.cos(), c[1] + r * a0.sin()]];
        pts.extend(arc_points(c, r, a0, sweep, curves.tol, 1));
        straight(pts)
    } else {
        exact_arc(c, r, a0, sweep)
    }
}

fn arc_shape(a: &dxf::entities::Arc, curves: Curves) -> Shape {
    let Some(flip) = ocs_flip(a.normal.x, a.normal.y, a.normal.z) else {
        return NOT_PLANAR;
    };
    let c = [a.center.x, a.center.y];
    let a0 = a.start_angle.to_radians();
    let mut sweep = (a.end_angle - a.start_angle).rem_euclid(360.0).to_radians();
    if sweep == 0.0 {
        sweep = std::f64::consts::TAU;
    }
    let mut pts = circular(c, a.radius, a0, sweep, curves);
    flip_all(&mut pts, flip);
    Shape::Open(pts)
}

/// A circle as a closed loop: two half arcs, or chords.
fn circle_loop_of(c: P, r: f64, curves: Curves) -> Vec<Vertex> {
    if curves.flatten {
        straight(circle_loop(c, r, curves.tol))
    } else {
        exact_circle(c, r)
    }
}

fn circle_shape(c: &dxf::entities::Circle, curves: Curves) -> Shape {
    let Some(flip) = ocs_flip(c.normal.x, c.normal.y, c.normal.z) else {
        return NOT_PLANAR;
    };
    let mut pts = circle_loop_of([c.center.x, c.center.y], c.radius, curves);
    flip_all(&mut pts, flip);
    Shape::Closed(pts)
}

fn ellipse_shape(el: &dxf::entities::Ellipse, curves: Curves) -> Shape {
    let Some(flip) = ocs_flip(el.normal.x, el.normal.y, el.normal.z) else {
        return NOT_PLANAR;
    };
    let maj = [el.major_axis.x, el.major_axis.y];
    let ratio = el.minor_axis_ratio;
    let min = [-maj[1] * ratio, maj[0] * ratio];
    let rmax = maj[0].hypot(maj[1]);
    let t0 = el.start_parameter;
    let mut sweep = (el.end_parameter - t0).rem_euclid(std::f64::consts::TAU);
    let full = sweep < 1e-12 || (std::f64::consts::TAU - sweep) < 1e-12;
    if full {
        sweep = std::f64::consts::TAU;
    }
    // Equal axes: a circle or a circular arc, exact unless flattening.
    if (ratio - 1.0).abs() <= 1e-12 && !curves.flatten {
        let c = [el.center.x, el.center.y];
        let a0 = maj[1].atan2(maj[0]) + t0;
        let mut pts = if full {
            exact_arc(c, rmax, a0, std::f64::consts::TAU)
        } else {
            circular(c, rmax, a0, sweep, curves)
        };
        if full {
            pts.pop();
        }
        flip_all(&mut pts, flip);
        return if full {
            Shape::Closed(pts)
        } else {
            Shape::Open(pts)
        };
    }
    let tol = curves.tol;
    let n = arc_pieces(rmax, sweep, tol).max(if full { 3 } else { 1 });
    let n = n.min(MAX_ARC_PIECES);
    let at = |t: f64| {
        [
            el.center.x + maj[0] * t.cos() + min[0] * t.sin(),
            el.center.y + maj[1] * t.cos() + min[1] * t.sin(),
        ]
    };
    let mut pts: Vec<Vertex> = (0..=n)
        .map(|i| Vertex::from(at(t0 + sweep * i as f64 / n as f64)))
        .collect();
    flip_all(&mut pts, flip);
    if full {
        pts.pop();
        Shape::Closed(pts)
    } else {
        Shape::Open(pts)
    }
}

/// A polyline's vertices as a closed loop or an open piece, by its flag:
/// the bulges kept (an open polyline's last one is no edge), or flattened.
fn polyline_points(verts: &[(P, f64)], closed: bool, flip: bool, curves: Curves) -> Shape {
    let mut exact: Vec<Vertex> = verts
        .iter()
        .map(|&(p, b)| Vertex::new(p[0], p[1], b))
        .collect();
    if !closed {
        if let Some(last) = exact.last_mut() {
            last.bulge = 0.0;
        }
    }
    // A bulge this small is a straight edge for any drawing (it was never
    // flattened either).
    for v in &mut exact {
        if v.bulge.abs() < 1e-12 {
            v.bulge = 0.0;
        }
    }
    let mut pts = if curves.flatten {
        flatten_vertices(&exact, closed, curves.tol)
    } else {
        exact
    };
    flip_all(&mut pts, flip);
    if closed {
        Shape::Closed(pts)
    } else {
        Shape::Open(pts)
    }
}

fn lwpolyline_shape(pl: &dxf::entities::LwPolyline, curves: Curves) -> Shape {
    let d = &pl.extrusion_direction;
    let Some(flip) = ocs_flip(d.x, d.y, d.z) else {
        return NOT_PLANAR;
    };
    let verts: Vec<(P, f64)> = pl.vertices.iter().map(|v| ([v.x, v.y], v.bulge)).collect();
    polyline_points(&verts, pl.flags & 1 == 1, flip, curves)
}

fn polyline_shape(pl: &dxf::entities::Polyline, curves: Curves) -> Shape {
    // 8: 3D polyline, 16: 3D mesh, 64: polyface mesh.
    if pl.flags & (8 | 16 | 64) != 0 {
        return Shape::Ignored("is a 3D polyline or mesh");
    }
    let Some(flip) = ocs_flip(pl.normal.x, pl.normal.y, pl.normal.z) else {
        return NOT_PLANAR;
    };
    // Vertex flag 16 marks spline frame control points, which are not on
    // the curve.
    let verts: Vec<(P, f64)> = pl
        .vertices()
        .filter(|v| v.flags & 16 == 0)
        .map(|v| ([v.location.x, v.location.y], v.bulge))
        .collect();
    polyline_points(&verts, pl.flags & 1 == 1, flip, curves)
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

    fn vertex(self, v: Vertex) -> Vertex {
        Vertex::new(v.x * self.factor, v.y * self.factor, v.bulge)
    }
}

/// A layer's loops in catalogue units: its closed entities, then its
/// pieces joined within `join_tol` (file units); a chain that does not
/// close is an error, because the outline would be a guess.
fn close_layer(
    layer: Layer,
    join_tol: f64,
    scale: Scale,
) -> Result<Vec<(Vec<Vertex>, String)>, DxfError> {
    let (joined, open) = join_pieces(layer.pieces, join_tol);
    if let Some(o) = open.first() {
        return Err(DxfError::OpenLoop {
            entities: o.labels.len(),
            first: o.labels.first().cloned().unwrap_or_default(),
            start: scale.pt(o.start),
            end: scale.pt(o.end),
            units: scale.units,
            gap: join_tol,
            gap_unit: scale.file,
        });
    }
    let mut loops = layer.loops;
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

/// Reads a DXF drawing into a part in `opts.units`, unvalidated: the
/// reader finds the loops, [`validate_part`](super::validate_part) judges
/// them the same way for every format.
pub fn read_dxf(bytes: &[u8], opts: &ReadOptions) -> Result<RawPart, DxfError> {
    let drawing = load_drawing(bytes)?;
    let file = drawing_units(drawing.header.default_drawing_units)?.unwrap_or(opts.fallback);
    let scale = Scale {
        file,
        factor: file.factor_to(opts.units),
        units: opts.units,
    };
    // Tolerances are given in catalogue units; the geometry is still in
    // file units here.
    let curves = Curves {
        tol: opts.chord_tolerance / scale.factor,
        flatten: opts.arcs.flatten(),
    };
    let join_tol = opts.join_tolerance / scale.factor;
    let mut found = Found::default();
    for (k, e) in drawing.entities().enumerate() {
        found.add(k, e, curves);
    }
    let part_loops = close_layer(found.part, join_tol, scale)?;
    let access = close_layer(found.access, join_tol, scale)?
        .into_iter()
        .map(|(pts, _)| positions(&pts))
        .collect();
    Ok(pick_outline(
        part_loops,
        access,
        found.warnings,
        opts.units,
    )?)
}

fn entity_name(e: &EntityType) -> &'static str {
    match e {
        EntityType::Line(_) => "LINE",
        EntityType::Arc(_) => "ARC",
        EntityType::Circle(_) => "CIRCLE",
        EntityType::Ellipse(_) => "ELLIPSE",
        EntityType::LwPolyline(_) => "LWPOLYLINE",
        EntityType::Polyline(_) => "POLYLINE",
        EntityType::Spline(_) => "SPLINE",
        EntityType::Insert(_) => "INSERT",
        _ => "entity",
    }
}

/// Writes a part as an AutoCAD 2000 (AC1015) DXF: one closed LWPOLYLINE on
/// layer `PART` for the outline (arcs as bulges, group code 42) and one on
/// layer `ACCESS` per access constraint, `$INSUNITS` set from `units`.
/// Numbers are written in Rust's shortest round-trip form, so reading the
/// file back gives the same part.
pub fn write_dxf(part: &Part, units: Units) -> String {
    let insunits = match units {
        Units::Mm => 4,
        Units::In => 1,
    };
    let mut s = String::new();
    let mut pair = |code: i32, value: &str| {
        s.push_str(&format!("{code:>3}\n{value}\n"));
    };
    pair(0, "SECTION");
    pair(2, "HEADER");
    pair(9, "$ACADVER");
    pair(1, "AC1015");
    pair(9, "$INSUNITS");
    pair(70, &insunits.to_string());
    pair(0, "ENDSEC");
    pair(0, "SECTION");
    pair(2, "ENTITIES");
    let access: Vec<Vec<Vertex>> = part.access.iter().map(|a| straight(a.clone())).collect();
    let polys =
        std::iter::once(("PART", &part.outline)).chain(access.iter().map(|a| ("ACCESS", a)));
    for (handle, (layer, pts)) in (0x100..).zip(polys) {
        pair(0, "LWPOLYLINE");
        pair(5, &format!("{handle:X}"));
        pair(100, "AcDbEntity");
        pair(8, layer);
        pair(100, "AcDbPolyline");
        pair(90, &pts.len().to_string());
        pair(70, "1");
        for p in pts.iter() {
            pair(10, &format!("{:?}", p.x));
            pair(20, &format!("{:?}", p.y));
            if p.is_arc() {
                pair(42, &format!("{:?}", p.bulge));
            }
        }
    }
    pair(0, "ENDSEC");
    pair(0, "EOF");
    s
}
