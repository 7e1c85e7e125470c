//! DXF part outlines, read with the `dxf` crate and written by hand.
//!
//! What a part drawing means here: closed loops made of LWPOLYLINE,
//! POLYLINE (with bulge arcs), CIRCLE, ELLIPSE, or chains of LINE and ARC
//! entities that meet end to end. The loop with the largest area is the
//! part; loops on a layer named `ACCESS` or `KEEPOUT` (any case) are access
//! constraints; other loops inside the part (holes, pockets) are ignored
//! with a warning, because the method of Brost & Goldberg holds a part by
//! its outer silhouette only. Paper-space entities (title blocks) and
//! annotations are skipped.

use super::outline::{
    arc_pieces, arc_points, circle_loop, dist, fmt, fmt_pt, join_pieces, pick_outline, Piece,
    MAX_ARC_PIECES, P,
};
use super::raw::{RawPart, ReadOptions};
use crate::units::LengthUnit;
use dxf::entities::EntityType;
use dxf::enums::Units as DxfUnits;
use dxf::Drawing;
use fixplan_core::{Part, Units};

fn is_access_layer(layer: &str) -> bool {
    let l = layer.trim();
    l.eq_ignore_ascii_case("access") || l.eq_ignore_ascii_case("keepout")
}

/// `$INSUNITS` as a length unit; `None` when the drawing says "unitless"
/// (then the catalogue's fallback applies).
fn drawing_units(u: DxfUnits) -> Result<Option<LengthUnit>, String> {
    Ok(Some(match u {
        DxfUnits::Unitless => return Ok(None),
        DxfUnits::Millimeters => LengthUnit::Mm,
        DxfUnits::Centimeters => LengthUnit::Cm,
        DxfUnits::Meters => LengthUnit::M,
        DxfUnits::Inches => LengthUnit::In,
        DxfUnits::Feet => LengthUnit::Ft,
        other => {
            return Err(format!(
                "unknown units: $INSUNITS is {other:?}; supported are mm, cm, m, in and ft (or unitless, with the catalogue's units)"
            ))
        }
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

fn flip_all(pts: &mut [P], flip: bool) {
    if flip {
        for p in pts {
            p[0] = -p[0];
        }
    }
}

/// Interior points of a DXF bulge segment from `p` to `q` (bulge = tan of a
/// quarter of the included angle, positive CCW), endpoints excluded.
fn bulge_points(p: P, q: P, bulge: f64, tol: f64) -> Vec<P> {
    if !bulge.is_finite() || bulge.abs() < 1e-12 {
        return Vec::new();
    }
    let chord = [q[0] - p[0], q[1] - p[1]];
    let c = chord[0].hypot(chord[1]);
    if c == 0.0 || !c.is_finite() {
        return Vec::new();
    }
    let theta = 4.0 * bulge.atan();
    // The centre sits on the chord's bisector, (1 - b^2) / (4 b) chord
    // lengths to the left of p -> q.
    let k = (1.0 - bulge * bulge) / (4.0 * bulge);
    let center = [
        (p[0] + q[0]) / 2.0 - chord[1] * k,
        (p[1] + q[1]) / 2.0 + chord[0] * k,
    ];
    let r = dist(center, p);
    let a0 = (p[1] - center[1]).atan2(p[0] - center[0]);
    let mut pts = arc_points(center, r, a0, theta, tol, 1);
    pts.pop();
    pts
}

/// Vertices with bulges to points; `closed` adds the closing segment's arc.
fn bulged_polyline(verts: &[(P, f64)], closed: bool, tol: f64) -> Vec<P> {
    let mut pts = Vec::with_capacity(verts.len());
    let n = verts.len();
    for i in 0..n {
        let (p, b) = verts[i];
        pts.push(p);
        if i + 1 < n {
            pts.extend(bulge_points(p, verts[i + 1].0, b, tol));
        } else if closed && n > 1 {
            pts.extend(bulge_points(p, verts[0].0, b, tol));
        }
    }
    pts
}

/// Reads a DXF drawing into a part in `opts.units`, unvalidated.
pub fn read_dxf(bytes: &[u8], opts: &ReadOptions) -> Result<RawPart, String> {
    // The dxf crate is not written for hostile input; a panic inside it must
    // become this part's error, not the catalogue's end.
    let loaded = std::panic::catch_unwind(|| {
        let mut cursor = std::io::Cursor::new(bytes);
        Drawing::load(&mut cursor)
    });
    let drawing = match loaded {
        Ok(Ok(d)) => d,
        Ok(Err(e)) => return Err(format!("not a readable DXF file: {e}")),
        Err(_) => return Err("not a readable DXF file (the DXF reader failed on it)".into()),
    };
    let src = drawing_units(drawing.header.default_drawing_units)?.unwrap_or(opts.fallback);
    let factor = src.factor_to(opts.units);
    // Tolerances are given in catalogue units; the geometry is still in
    // file units here.
    let tol = opts.chord_tolerance / factor;
    let join_tol = opts.join_tolerance / factor;
    let mut warnings = Vec::new();

    let mut part_pieces = Vec::new();
    let mut access_pieces = Vec::new();
    let mut part_loops: Vec<(Vec<P>, String)> = Vec::new();
    let mut access_loops: Vec<(Vec<P>, String)> = Vec::new();

    for (k, e) in drawing.entities().enumerate() {
        if e.common.is_in_paper_space {
            continue;
        }
        let layer = e.common.layer.clone();
        let access = is_access_layer(&layer);
        let kind = entity_name(&e.specific);
        let label = format!("{kind} #{} on layer {layer}", k + 1);
        let mut closed: Option<Vec<P>> = None;
        let mut open: Option<Vec<P>> = None;
        match &e.specific {
            EntityType::Line(l) => {
                open = Some(vec![[l.p1.x, l.p1.y], [l.p2.x, l.p2.y]]);
            }
            EntityType::Arc(a) => {
                let Some(flip) = ocs_flip(a.normal.x, a.normal.y, a.normal.z) else {
                    warnings.push(format!("{label} is not in the XY plane; ignored"));
                    continue;
                };
                let c = [a.center.x, a.center.y];
                let a0 = a.start_angle.to_radians();
                let mut sweep = (a.end_angle - a.start_angle).rem_euclid(360.0).to_radians();
                if sweep == 0.0 {
                    sweep = std::f64::consts::TAU;
                }
                let mut pts = vec![[c[0] + a.radius * a0.cos(), c[1] + a.radius * a0.sin()]];
                pts.extend(arc_points(c, a.radius, a0, sweep, tol, 1));
                flip_all(&mut pts, flip);
                open = Some(pts);
            }
            EntityType::Circle(c) => {
                let Some(flip) = ocs_flip(c.normal.x, c.normal.y, c.normal.z) else {
                    warnings.push(format!("{label} is not in the XY plane; ignored"));
                    continue;
                };
                let mut pts = circle_loop([c.center.x, c.center.y], c.radius, tol);
                flip_all(&mut pts, flip);
                closed = Some(pts);
            }
            EntityType::Ellipse(el) => {
                let Some(flip) = ocs_flip(el.normal.x, el.normal.y, el.normal.z) else {
                    warnings.push(format!("{label} is not in the XY plane; ignored"));
                    continue;
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
                let n = arc_pieces(rmax, sweep, tol).max(if full { 3 } else { 1 });
                let n = n.min(MAX_ARC_PIECES);
                let at = |t: f64| {
                    [
                        el.center.x + maj[0] * t.cos() + min[0] * t.sin(),
                        el.center.y + maj[1] * t.cos() + min[1] * t.sin(),
                    ]
                };
                let mut pts: Vec<P> = (0..=n)
                    .map(|i| at(t0 + sweep * i as f64 / n as f64))
                    .collect();
                flip_all(&mut pts, flip);
                if full {
                    pts.pop();
                    closed = Some(pts);
                } else {
                    open = Some(pts);
                }
            }
            EntityType::LwPolyline(pl) => {
                let Some(flip) = ocs_flip(
                    pl.extrusion_direction.x,
                    pl.extrusion_direction.y,
                    pl.extrusion_direction.z,
                ) else {
                    warnings.push(format!("{label} is not in the XY plane; ignored"));
                    continue;
                };
                let verts: Vec<(P, f64)> =
                    pl.vertices.iter().map(|v| ([v.x, v.y], v.bulge)).collect();
                let is_closed = pl.flags & 1 == 1;
                let mut pts = bulged_polyline(&verts, is_closed, tol);
                flip_all(&mut pts, flip);
                if is_closed {
                    closed = Some(pts);
                } else {
                    open = Some(pts);
                }
            }
            EntityType::Polyline(pl) => {
                // 8: 3D polyline, 16: 3D mesh, 64: polyface mesh.
                if pl.flags & (8 | 16 | 64) != 0 {
                    warnings.push(format!("{label} is a 3D polyline or mesh; ignored"));
                    continue;
                }
                let Some(flip) = ocs_flip(pl.normal.x, pl.normal.y, pl.normal.z) else {
                    warnings.push(format!("{label} is not in the XY plane; ignored"));
                    continue;
                };
                // Vertex flag 16 marks spline frame control points, which
                // are not on the curve.
                let verts: Vec<(P, f64)> = pl
                    .vertices()
                    .filter(|v| v.flags & 16 == 0)
                    .map(|v| ([v.location.x, v.location.y], v.bulge))
                    .collect();
                let is_closed = pl.flags & 1 == 1;
                let mut pts = bulged_polyline(&verts, is_closed, tol);
                flip_all(&mut pts, flip);
                if is_closed {
                    closed = Some(pts);
                } else {
                    open = Some(pts);
                }
            }
            EntityType::Spline(_) | EntityType::Insert(_) => {
                warnings.push(format!(
                    "{label} is not supported (explode or convert it to polylines); ignored"
                ));
                continue;
            }
            // Text, dimensions, points and the like are annotations.
            _ => continue,
        }
        if let Some(pts) = closed {
            if access {
                access_loops.push((pts, label));
            } else {
                part_loops.push((pts, label));
            }
        } else if let Some(pts) = open {
            if pts.len() < 2 {
                continue;
            }
            let piece = Piece { pts, label };
            if access {
                access_pieces.push(piece);
            } else {
                part_pieces.push(piece);
            }
        }
    }

    let unit = opts.units.label();
    let src_label = src.label();
    for (pieces, dest) in [
        (part_pieces, &mut part_loops),
        (access_pieces, &mut access_loops),
    ] {
        let (loops, open) = join_pieces(pieces, join_tol);
        if let Some(o) = open.first() {
            let ends = format!(
                "{} and {}",
                fmt_pt([o.start[0] * factor, o.start[1] * factor]),
                fmt_pt([o.end[0] * factor, o.end[1] * factor])
            );
            let what = if o.labels.len() == 1 {
                o.labels[0].clone()
            } else {
                format!("{} entities from {}", o.labels.len(), o.labels[0])
            };
            return Err(format!(
                "open loop: {what} end at {ends} {unit} with nothing within {} {src_label} to join (a gap in the outline?)",
                fmt(join_tol)
            ));
        }
        dest.extend(
            loops
                .into_iter()
                .map(|l| (l, "joined LINE/ARC chain".to_string())),
        );
    }

    let scale = |pts: Vec<P>| -> Vec<P> {
        pts.into_iter()
            .map(|p| [p[0] * factor, p[1] * factor])
            .collect()
    };
    let part_loops: Vec<(Vec<P>, String)> =
        part_loops.into_iter().map(|(p, l)| (scale(p), l)).collect();
    let access: Vec<Vec<P>> = access_loops.into_iter().map(|(p, _)| scale(p)).collect();
    pick_outline(part_loops, access, warnings, unit)
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
/// layer `PART` for the outline and one on layer `ACCESS` per access
/// constraint, `$INSUNITS` set from `units`. Numbers are written in Rust's
/// shortest round-trip form, so reading the file back gives the same part.
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
    let polys =
        std::iter::once(("PART", &part.outline)).chain(part.access.iter().map(|a| ("ACCESS", a)));
    for (handle, (layer, pts)) in (0x100..).zip(polys) {
        pair(0, "LWPOLYLINE");
        pair(5, &format!("{handle:X}"));
        pair(100, "AcDbEntity");
        pair(8, layer);
        pair(100, "AcDbPolyline");
        pair(90, &pts.len().to_string());
        pair(70, "1");
        for p in pts.iter() {
            pair(10, &format!("{:?}", p[0]));
            pair(20, &format!("{:?}", p[1]));
        }
    }
    pair(0, "ENDSEC");
    pair(0, "EOF");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bulge_one_is_a_half_circle() {
        let pts = bulge_points([1.0, 0.0], [-1.0, 0.0], 1.0, 0.01);
        assert!(!pts.is_empty());
        for p in &pts {
            assert!((dist(*p, [0.0, 0.0]) - 1.0).abs() < 1e-12);
            assert!(p[1] > 0.0, "CCW from (1,0) to (-1,0) passes above");
        }
    }
}
