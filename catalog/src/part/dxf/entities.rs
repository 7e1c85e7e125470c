//! What one DXF entity adds to a drawing, in its block's coordinates
//! (file units): a closed loop, an open piece to join, geometry this
//! reader cannot use, or nothing (annotations). Entities drawn in a
//! mirrored object coordinate system (extrusion (0, 0, -1)) are mirrored
//! here; block transforms are applied by the caller.

use super::super::outline::{
    arc_pieces, arc_points, circle_loop, exact_arc, exact_circle, flatten_vertices, straight,
    MAX_ARC_PIECES, P,
};
use super::super::raw::LimitExceeded;
use super::spline::{self, SplineProblem};
use dxf::entities::EntityType;
use fixplan_core::Vertex;

/// Entities are drawn in their object coordinate system; for the usual
/// extrusion (0, 0, 1) that is the world, for (0, 0, -1) (mirrored
/// entities, common in files from some CAM tools) x is flipped. Anything
/// tilted out of the plane is not a planar outline.
pub(super) fn ocs_flip(nx: f64, ny: f64, nz: f64) -> Option<bool> {
    if nx.abs() > 1e-9 || ny.abs() > 1e-9 || nz == 0.0 || !nz.is_finite() {
        None
    } else {
        Some(nz < 0.0)
    }
}

/// Mirrors x (and so the turning direction of every arc) when `flip`.
pub(super) fn flip_all(pts: &mut [Vertex], flip: bool) {
    if flip {
        for p in pts {
            p.x = -p.x;
            if p.bulge != 0.0 {
                p.bulge = -p.bulge;
            }
        }
    }
}

/// What one entity adds to the drawing.
pub(super) enum EntityShape {
    /// A loop on its own (closed polyline, circle, full ellipse).
    Closed(Vec<Vertex>),
    /// A piece to be joined with others (line, arc, open polyline, spline).
    Open(Vec<Vertex>),
    /// Geometry this reader cannot use: the reason ends the warning; the
    /// points it is known to pass through (its ends, its vertices) let an
    /// open loop that ends on it name it.
    Ignored(&'static str, Vec<P>),
    /// Over one of the reader's limits.
    Limit(LimitExceeded),
    /// Not geometry (text, dimensions, points...).
    Nothing,
}

const NOT_PLANAR: EntityShape = EntityShape::Ignored("is not in the XY plane", Vec::new());

/// How curves are read: chords within `tol` (file units) when `flatten`,
/// else exact arcs (and chords for what is not circular); a spline gets at
/// most `spline_pieces` chords.
#[derive(Clone, Copy)]
pub(super) struct Curves {
    pub tol: f64,
    pub flatten: bool,
    pub spline_pieces: usize,
}

/// The shape of an entity other than an INSERT (which the caller
/// explodes).
pub(super) fn entity_shape(entity: &EntityType, curves: Curves) -> EntityShape {
    match entity {
        EntityType::Line(l) => {
            EntityShape::Open(straight(vec![[l.p1.x, l.p1.y], [l.p2.x, l.p2.y]]))
        }
        EntityType::Arc(a) => arc_shape(a, curves),
        EntityType::Circle(c) => circle_shape(c, curves),
        EntityType::Ellipse(el) => ellipse_shape(el, curves),
        EntityType::LwPolyline(pl) => lwpolyline_shape(pl, curves),
        EntityType::Polyline(pl) => polyline_shape(pl, curves),
        EntityType::Spline(s) => spline_shape(s, curves),
        EntityType::Solid(_)
        | EntityType::Trace(_)
        | EntityType::Face3D(_)
        | EntityType::Solid3D(_)
        | EntityType::Region(_)
        | EntityType::Body(_)
        | EntityType::MLine(_)
        | EntityType::ProxyEntity(_)
        | EntityType::Helix(_)
        | EntityType::Shape(_) => EntityShape::Ignored(
            "is not supported (explode it into lines, arcs and polylines)",
            Vec::new(),
        ),
        // Text, dimensions, points, construction lines, images and the like
        // are annotations.
        _ => EntityShape::Nothing,
    }
}

/// A SPLINE flattened within the chord tolerance; it lies in the XY plane
/// when its control points all have one z (SPLINE points are world
/// coordinates, so its normal does not mirror it).
fn spline_shape(curve: &dxf::entities::Spline, curves: Curves) -> EntityShape {
    let ends: Vec<P> = [curve.control_points.first(), curve.control_points.last()]
        .into_iter()
        .chain([curve.fit_points.first(), curve.fit_points.last()])
        .flatten()
        .map(|p| [p.x, p.y])
        .collect();
    let z0 = curve
        .control_points
        .first()
        .or(curve.fit_points.first())
        .map_or(0.0, |p| p.z);
    let planar = curve
        .control_points
        .iter()
        .chain(&curve.fit_points)
        .all(|p| (p.z - z0).abs() <= 1e-9 * (1.0 + z0.abs()));
    if !planar {
        return EntityShape::Ignored("is not in the XY plane", ends);
    }
    let ctrl: Vec<[f64; 2]> = curve.control_points.iter().map(|p| [p.x, p.y]).collect();
    match spline::flatten(
        curve.degree_of_curve,
        &curve.knot_values,
        &curve.weight_values,
        &ctrl,
        curves.tol,
        curves.spline_pieces,
    ) {
        Ok(pts) => EntityShape::Open(straight(pts)),
        Err(SplineProblem::Unusable(why)) => EntityShape::Ignored(why, ends),
        Err(SplineProblem::Limit(l)) => EntityShape::Limit(l),
    }
}

/// A circular arc from angle `a0` (radians) sweeping `sweep` about `centre`:
/// one or two bulge vertices, or chords.
fn circular(centre: P, radius: f64, a0: f64, sweep: f64, curves: Curves) -> Vec<Vertex> {
    if curves.flatten {
        let mut pts = vec![[centre[0] + radius * a0.cos(), centre[1] + radius * a0.sin()]];
        pts.extend(arc_points(centre, radius, a0, sweep, curves.tol, 1));
        straight(pts)
    } else {
        exact_arc(centre, radius, a0, sweep)
    }
}

fn arc_shape(arc: &dxf::entities::Arc, curves: Curves) -> EntityShape {
    let Some(flip) = ocs_flip(arc.normal.x, arc.normal.y, arc.normal.z) else {
        return NOT_PLANAR;
    };
    let c = [arc.center.x, arc.center.y];
    let a0 = arc.start_angle.to_radians();
    let mut sweep = (arc.end_angle - arc.start_angle)
        .rem_euclid(360.0)
        .to_radians();
    if sweep == 0.0 {
        sweep = std::f64::consts::TAU;
    }
    let mut pts = circular(c, arc.radius, a0, sweep, curves);
    flip_all(&mut pts, flip);
    EntityShape::Open(pts)
}

/// A circle as a closed loop: two half arcs, or chords.
fn circle_loop_of(centre: P, radius: f64, curves: Curves) -> Vec<Vertex> {
    if curves.flatten {
        straight(circle_loop(centre, radius, curves.tol))
    } else {
        exact_circle(centre, radius)
    }
}

fn circle_shape(circle: &dxf::entities::Circle, curves: Curves) -> EntityShape {
    let Some(flip) = ocs_flip(circle.normal.x, circle.normal.y, circle.normal.z) else {
        return NOT_PLANAR;
    };
    let mut pts = circle_loop_of([circle.center.x, circle.center.y], circle.radius, curves);
    flip_all(&mut pts, flip);
    EntityShape::Closed(pts)
}

fn ellipse_shape(el: &dxf::entities::Ellipse, curves: Curves) -> EntityShape {
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
            EntityShape::Closed(pts)
        } else {
            EntityShape::Open(pts)
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
        EntityShape::Closed(pts)
    } else {
        EntityShape::Open(pts)
    }
}

/// A polyline's vertices as a closed loop or an open piece, by its flag:
/// the bulges kept (an open polyline's last one is no edge), or flattened.
fn polyline_points(verts: &[(P, f64)], closed: bool, flip: bool, curves: Curves) -> EntityShape {
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
        EntityShape::Closed(pts)
    } else {
        EntityShape::Open(pts)
    }
}

fn lwpolyline_shape(pl: &dxf::entities::LwPolyline, curves: Curves) -> EntityShape {
    let d = &pl.extrusion_direction;
    let Some(flip) = ocs_flip(d.x, d.y, d.z) else {
        return NOT_PLANAR;
    };
    let verts: Vec<(P, f64)> = pl.vertices.iter().map(|v| ([v.x, v.y], v.bulge)).collect();
    polyline_points(&verts, pl.flags & 1 == 1, flip, curves)
}

fn polyline_shape(pl: &dxf::entities::Polyline, curves: Curves) -> EntityShape {
    // 8: 3D polyline, 16: 3D mesh, 64: polyface mesh.
    if pl.flags & (8 | 16 | 64) != 0 {
        let pts = pl
            .vertices()
            .map(|v| [v.location.x, v.location.y])
            .collect();
        return EntityShape::Ignored("is a 3D polyline or mesh", pts);
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

/// The DXF type name of an entity, for messages.
pub(super) fn entity_name(kind: &EntityType) -> &'static str {
    match kind {
        EntityType::Line(_) => "LINE",
        EntityType::Arc(_) => "ARC",
        EntityType::Circle(_) => "CIRCLE",
        EntityType::Ellipse(_) => "ELLIPSE",
        EntityType::LwPolyline(_) => "LWPOLYLINE",
        EntityType::Polyline(_) => "POLYLINE",
        EntityType::Spline(_) => "SPLINE",
        EntityType::Insert(_) => "INSERT",
        EntityType::Solid(_) => "SOLID",
        EntityType::Trace(_) => "TRACE",
        EntityType::Face3D(_) => "3DFACE",
        EntityType::Solid3D(_) => "3DSOLID",
        EntityType::Region(_) => "REGION",
        EntityType::Body(_) => "BODY",
        EntityType::MLine(_) => "MLINE",
        EntityType::ProxyEntity(_) => "ACAD_PROXY_ENTITY",
        EntityType::Helix(_) => "HELIX",
        EntityType::Shape(_) => "SHAPE",
        _ => "entity",
    }
}
