//! SVG part outlines: a small reader on top of `roxmltree` (path data,
//! transforms and their number syntax in the files of this folder), and a
//! writer. Uses `super::raw` and `super::outline`, nothing else of `part`.
//!
//! **Coordinates.** SVG's y axis points down, fixplan's (like DXF's and the
//! paper's) points up. A point at user coordinates `(x, y)`, after every
//! `transform` of its element and enclosing groups has been applied, becomes
//! the part point `(x, -y)` (times the unit scale below). The flip mirrors
//! nothing about the part as seen on screen: what is drawn at the top of
//! the SVG is at the top of the part, and the SVG origin (top-left corner
//! of the default viewport) is the part origin. No translation is applied,
//! so SVG parts usually have negative y coordinates; fixplan does not care
//! where the part frame's origin is.
//!
//! **Units.** If the root `<svg>` has a `width` in `mm`, `cm` or `in` and a
//! `viewBox`, one user unit is `width / viewBox-width` of that unit (this is
//! what Inkscape and most CAD exports write). A physical `width` without a
//! `viewBox` means user units are CSS pixels (1/96 in). Without a physical
//! width (no `width`, `%`, `px` or a bare number), user units are taken to
//! be the catalogue's fallback unit, because drawings made for fixplan by
//! hand or by script rarely mean pixels.
//!
//! **What is read.** `polygon`, `polyline`, `path` (M, L, H, V, C, S, Q, T,
//! A, Z, absolute and relative, curves flattened to the chord tolerance),
//! `rect`, `circle` and `ellipse`, with `translate`, `scale`, `rotate`,
//! `skewX`, `skewY` and `matrix` transforms on elements and groups.
//!
//! **Arcs.** An `A` command with equal radii, a `<circle>`, an
//! `<ellipse>` with `rx = ry` and the corners of a `<rect>` with
//! `rx = ry` are exact circular arcs (bulge vertices, SPEC
//! 8.1; a circle is two half arcs) when the element's whole transform is a
//! similarity (uniform scale, rotation, translation, possibly a reflection,
//! which turns arcs the other way, as does the y flip below). Elliptical
//! arcs, arcs under a skew or non-uniform scale, Bézier curves, access
//! shapes and everything with [`ArcMode::Flatten`](super::raw::ArcMode)
//! are flattened within the chord tolerance. A path may carry
//! `data-fixplan-bulges` (what [`write_svg`] writes: one bulge per vertex
//! of its outline, in part coordinates); a bulge computed from an `A`
//! command within `1e-9` (relative) of the one written there is taken as
//! written, so that a written part reads back bit for bit. Elements
//! whose `class` contains `access` or `keepout`, or whose `id` starts with
//! one of those words (any case), are access constraints, and so is all
//! inside a group marked that way. The largest closed shape is the part;
//! smaller ones inside it are ignored with a warning. `<defs>`, `<use>`,
//! text and styles are not geometry here.

mod lexer;
mod path;
mod transform;

pub use path::PathError;
pub use transform::TransformError;

use super::outline::{arc_pieces, fmt_pt, pick_outline, positions, OutlineError, P};
use super::raw::{RawPart, ReadOptions};
use crate::units::LengthUnit;
use fixplan_core::outline::Vertex;
use fixplan_core::{Part, Units};
use lexer::Lexer;
use path::{parse_path, Sub};
use transform::{parse_transform, Affine};

/// Why an SVG file does not give a part.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SvgError {
    /// The bytes are not UTF-8.
    #[error("not a readable SVG file: {0}")]
    NotUtf8(std::str::Utf8Error),
    /// Not well-formed XML; the parser's message says where.
    #[error("not a readable SVG file: {0}")]
    NotXml(roxmltree::Error),
    /// XML whose root element (named here) is not `<svg>`.
    #[error("not an SVG file: the root element is <{0}>")]
    NotSvg(String),
    /// A physical `width` with a `viewBox` that gives no scale.
    #[error("root <svg> has a viewBox that is not four numbers with a positive width")]
    BadViewBox,
    /// The root `<svg>`'s own `transform`.
    #[error(transparent)]
    RootTransform(TransformError),
    /// A problem in an element's `transform` or path data, with the
    /// element (`<path id="...">`, or its tag and line).
    #[error("{element}: {problem}")]
    InElement {
        /// The element, as messages name it.
        element: String,
        /// What is wrong in it.
        problem: ElementProblem,
    },
    /// A `points` attribute that is not numbers; the whole attribute.
    #[error("bad points list \"{0}\"")]
    BadPoints(String),
    /// A `points` attribute with an x but no y; the whole attribute.
    #[error("odd number of coordinates in \"{0}\"")]
    OddPoints(String),
    /// A length with a unit or percentage where only user units make sense.
    #[error("<{element}> {attribute}=\"{value}\": only plain numbers are supported here")]
    Length {
        /// The element's tag.
        element: String,
        /// The attribute's name.
        attribute: String,
        /// What it says.
        value: String,
    },
    /// More than 10 000 groups: a guard against hostile files.
    #[error("too many nested elements")]
    TooManyElements,
    /// A shape that does not close; the ends are in user units because
    /// that is what the file's author sees.
    #[error("open loop: {element} (subpath {subpath}) runs from {} to {} in SVG user units and is not closed (add Z)", fmt_pt(*.from), fmt_pt(*.to))]
    OpenSubpath {
        /// The element, as messages name it.
        element: String,
        /// Which subpath of it, from 0.
        subpath: usize,
        /// Its first point, user units.
        from: [f64; 2],
        /// Its last point, user units.
        to: [f64; 2],
    },
    /// The shapes found do not make one part.
    #[error(transparent)]
    Outline(#[from] OutlineError),
}

/// What is wrong inside one element.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ElementProblem {
    /// Its `transform` attribute.
    #[error(transparent)]
    Transform(TransformError),
    /// Its path data.
    #[error(transparent)]
    Path(PathError),
}

fn in_element(node: roxmltree::Node, problem: ElementProblem) -> SvgError {
    SvgError::InElement {
        element: describe(node),
        problem,
    }
}

fn points_attr(s: &str) -> Result<Vec<P>, SvgError> {
    let mut lx = Lexer::new(s);
    let mut v = Vec::new();
    while !lx.at_end() {
        let x = lx
            .number()
            .ok_or_else(|| SvgError::BadPoints(s.to_string()))?;
        let y = lx
            .number()
            .ok_or_else(|| SvgError::OddPoints(s.to_string()))?;
        v.push([x, y]);
    }
    Ok(v)
}

/// A length attribute in user units: a bare number or `px`.
fn length_attr(node: roxmltree::Node, name: &str, default: f64) -> Result<f64, SvgError> {
    match node.attribute(name) {
        None => Ok(default),
        Some(s) => {
            let t = s.trim().trim_end_matches("px");
            // `nan` and `inf` parse as floats but are no SVG length.
            match t.trim().parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => Err(SvgError::Length {
                    element: node.tag_name().name().to_string(),
                    attribute: name.to_string(),
                    value: s.to_string(),
                }),
            }
        }
    }
}

fn marked_access(node: roxmltree::Node) -> bool {
    let class_hit = node.attribute("class").is_some_and(|c| {
        c.split_ascii_whitespace()
            .any(|t| t.eq_ignore_ascii_case("access") || t.eq_ignore_ascii_case("keepout"))
    });
    let id_hit = node.attribute("id").is_some_and(|id| {
        let id = id.to_ascii_lowercase();
        id.starts_with("access") || id.starts_with("keepout")
    });
    class_hit || id_hit
}

/// What the walk through the document has found so far, in user units
/// after transforms.
struct Walk {
    tol: f64,
    /// Circular arcs may stay exact (`arcs = "exact"`).
    exact: bool,
    loops: Vec<(Vec<Vertex>, String)>,
    access: Vec<Vec<P>>,
    warnings: Vec<String>,
    depth_guard: usize,
}

fn describe(node: roxmltree::Node) -> String {
    match node.attribute("id") {
        Some(id) => format!("<{} id=\"{id}\">", node.tag_name().name()),
        None => format!(
            "<{}> at line {}",
            node.tag_name().name(),
            node.document().text_pos_at(node.range().start).row
        ),
    }
}

/// Elements whose children are walked, not drawn.
fn is_container(name: &str) -> bool {
    matches!(name, "g" | "a" | "switch" | "svg")
}

fn walk(node: roxmltree::Node, ctm: Affine, access: bool, w: &mut Walk) -> Result<(), SvgError> {
    w.depth_guard += 1;
    if w.depth_guard > 10_000 {
        return Err(SvgError::TooManyElements);
    }
    for child in node.children().filter(|n| n.is_element()) {
        if child.attribute("display") == Some("none") {
            continue;
        }
        let ctm = match child.attribute("transform") {
            Some(t) => ctm.mul(
                parse_transform(t).map_err(|e| in_element(child, ElementProblem::Transform(e)))?,
            ),
            None => ctm,
        };
        let access = access || marked_access(child);
        if is_container(child.tag_name().name()) {
            walk(child, ctm, access, w)?;
            continue;
        }
        let tol = w.tol / ctm.max_scale();
        let exact = w.exact && !access && ctm.is_similarity();
        if let Some(subs) = element_subpaths(child, tol, exact, &mut w.warnings)? {
            w.add(child, subs, ctm, access)?;
        }
    }
    Ok(())
}

/// The subpaths a drawing element draws, in its user units (circular arcs
/// exact when `exact`); `None` for elements that are not geometry here
/// (with a warning for those a user may have meant as geometry).
fn element_subpaths(
    el: roxmltree::Node,
    tol: f64,
    exact: bool,
    warnings: &mut Vec<String>,
) -> Result<Option<Vec<Sub>>, SvgError> {
    let name = el.tag_name().name();
    let subs = match name {
        "polygon" | "polyline" => vec![Sub {
            pts: points_attr(el.attribute("points").unwrap_or(""))?
                .into_iter()
                .map(Vertex::from)
                .collect(),
            closed: name == "polygon",
        }],
        "path" => parse_path(el.attribute("d").unwrap_or(""), tol, exact)
            .map_err(|e| in_element(el, ElementProblem::Path(e)))?,
        "rect" => rect(el, tol, exact)?,
        "circle" | "ellipse" => vec![ellipse(el, tol, exact)?],
        "use" => {
            warnings.push(format!(
                "{} (a reference) is not supported; ignored",
                describe(el)
            ));
            return Ok(None);
        }
        "line" => {
            warnings.push(format!(
                "{} is a single line, not a shape; ignored",
                describe(el)
            ));
            return Ok(None);
        }
        _ => return Ok(None),
    };
    Ok(Some(subs))
}

/// A `<rect>`, with rounded corners (`rx`, `ry`) read as the path SVG
/// defines for them, so that round corners are exact circular arcs like
/// any `A` command (a rounded rectangle is how drawing programs write a
/// filleted plate). As in SVG: a radius given alone serves for both, and
/// each is at most half the side it rounds.
fn rect(el: roxmltree::Node, tol: f64, exact: bool) -> Result<Vec<Sub>, SvgError> {
    let x = length_attr(el, "x", 0.0)?;
    let y = length_attr(el, "y", 0.0)?;
    let wd = length_attr(el, "width", 0.0)?;
    let ht = length_attr(el, "height", 0.0)?;
    let given = |name| el.attribute(name).is_some();
    let (rx, ry) = match (given("rx"), given("ry")) {
        (false, false) => (0.0, 0.0),
        (true, false) => {
            let r = length_attr(el, "rx", 0.0)?;
            (r, r)
        }
        (false, true) => {
            let r = length_attr(el, "ry", 0.0)?;
            (r, r)
        }
        (true, true) => (length_attr(el, "rx", 0.0)?, length_attr(el, "ry", 0.0)?),
    };
    // A negative size (an error in SVG) is taken as the same rectangle
    // drawn from its other corner, as without rounded corners.
    let (x, wd) = if wd < 0.0 { (x + wd, -wd) } else { (x, wd) };
    let (y, ht) = if ht < 0.0 { (y + ht, -ht) } else { (y, ht) };
    let (rx, ry) = (rx.abs().min(wd / 2.0), ry.abs().min(ht / 2.0));
    if rx <= 0.0 || ry <= 0.0 {
        return Ok(vec![Sub {
            pts: [[x, y], [x + wd, y], [x + wd, y + ht], [x, y + ht]]
                .into_iter()
                .map(Vertex::from)
                .collect(),
            closed: true,
        }]);
    }
    // Sides of zero length (a radius of half the side) are left out, so
    // that no vertex is doubled.
    let side = |cmd: char, to: f64, len: f64| {
        if len > 0.0 {
            format!("{cmd} {to} ")
        } else {
            String::new()
        }
    };
    let corner = |to_x: f64, to_y: f64| format!("A {rx} {ry} 0 0 1 {to_x} {to_y} ");
    let d = format!(
        "M {} {y} {}{}{}{}{}{}{}{}Z",
        x + rx,
        side('H', x + wd - rx, wd - 2.0 * rx),
        corner(x + wd, y + ry),
        side('V', y + ht - ry, ht - 2.0 * ry),
        corner(x + wd - rx, y + ht),
        side('H', x + rx, wd - 2.0 * rx),
        corner(x, y + ht - ry),
        side('V', y + ry, ht - 2.0 * ry),
        corner(x + rx, y),
    );
    parse_path(&d, tol, exact).map_err(|e| in_element(el, ElementProblem::Path(e)))
}

/// A `<circle>` or `<ellipse>` as a closed polygon within `tol`, or, when
/// `exact` and the radii are equal, as two half arcs.
fn ellipse(el: roxmltree::Node, tol: f64, exact: bool) -> Result<Sub, SvgError> {
    let cx = length_attr(el, "cx", 0.0)?;
    let cy = length_attr(el, "cy", 0.0)?;
    let (rx, ry) = if el.tag_name().name() == "circle" {
        let r = length_attr(el, "r", 0.0)?;
        (r, r)
    } else {
        (length_attr(el, "rx", 0.0)?, length_attr(el, "ry", 0.0)?)
    };
    if exact && rx.abs() == ry.abs() {
        let r = rx.abs();
        let pts = vec![Vertex::new(cx + r, cy, 1.0), Vertex::new(cx - r, cy, 1.0)];
        return Ok(Sub { pts, closed: true });
    }
    let n = arc_pieces(rx.abs().max(ry.abs()), std::f64::consts::TAU, tol).max(3);
    let pts = (0..n)
        .map(|k| {
            let t = std::f64::consts::TAU * k as f64 / n as f64;
            Vertex::new(cx + rx * t.cos(), cy + ry * t.sin(), 0.0)
        })
        .collect();
    Ok(Sub { pts, closed: true })
}

impl Walk {
    /// Adds an element's subpaths as loops (or access loops), transformed;
    /// every one must be closed.
    fn add(
        &mut self,
        el: roxmltree::Node,
        subs: Vec<Sub>,
        ctm: Affine,
        access: bool,
    ) -> Result<(), SvgError> {
        let mirror = ctm.mirrors();
        let mut loops = Vec::new();
        for (k, sub) in subs.into_iter().enumerate() {
            let mut pts = sub.pts;
            let at = |i: usize| pts.get(i).map(|v: &Vertex| [v.x, v.y]);
            let closes = pts.len() > 2 && at(0) == at(pts.len() - 1);
            if !sub.closed && !closes {
                return Err(SvgError::OpenSubpath {
                    element: describe(el),
                    subpath: k,
                    from: at(0).unwrap_or_default(),
                    to: pts.last().map(|v| [v.x, v.y]).unwrap_or_default(),
                });
            }
            if closes {
                pts.pop();
            }
            let pts: Vec<Vertex> = pts
                .into_iter()
                .map(|v| {
                    let [x, y] = ctm.apply([v.x, v.y]);
                    let b = if mirror && v.bulge != 0.0 {
                        -v.bulge
                    } else {
                        v.bulge
                    };
                    Vertex::new(x, y, b)
                })
                .collect();
            if access {
                self.access.push(positions(&pts));
            } else {
                loops.push((pts, describe(el)));
            }
        }
        if let (Some(b), [(pts, _)]) = (written_bulges(el), &mut loops[..]) {
            take_written_bulges(pts, &b);
        }
        self.loops.extend(loops);
        Ok(())
    }
}

/// The `data-fixplan-bulges` of an element, if it is a list of numbers.
fn written_bulges(el: roxmltree::Node) -> Option<Vec<f64>> {
    let s = el.attribute("data-fixplan-bulges")?;
    let mut lx = Lexer::new(s);
    let mut v = Vec::new();
    while !lx.at_end() {
        v.push(lx.number()?);
    }
    Some(v)
}

/// Bulges in user coordinates (before the y flip) taken as written when
/// the computed ones agree within `1e-9` (relative): `written` is in part
/// coordinates, one per vertex.
fn take_written_bulges(pts: &mut [Vertex], written: &[f64]) {
    if pts.len() != written.len() {
        return;
    }
    for (v, &w) in pts.iter_mut().zip(written) {
        let user = -w;
        if v.bulge != 0.0 && (v.bulge - user).abs() <= 1e-9 * user.abs().max(1.0) {
            v.bulge = user;
        }
    }
}

fn split_length(s: &str) -> Option<(f64, &str)> {
    let s = s.trim();
    let end = s
        .find(|c: char| c.is_ascii_alphabetic() || c == '%')
        .unwrap_or(s.len());
    let v = s[..end].trim().parse::<f64>().ok()?;
    Some((v, s[end..].trim()))
}

/// Factor from user units to catalogue units.
fn user_unit(root: roxmltree::Node, opts: &ReadOptions) -> Result<f64, SvgError> {
    let physical = root
        .attribute("width")
        .and_then(split_length)
        .and_then(|(v, u)| {
            LengthUnit::parse(u)
                .filter(|u| matches!(u, LengthUnit::Mm | LengthUnit::Cm | LengthUnit::In))
                .map(|u| (v, u))
        });
    let Some((w, unit)) = physical else {
        return Ok(opts.fallback.factor_to(opts.units));
    };
    let to_cat = unit.factor_to(opts.units);
    let vb: Option<Vec<f64>> = root.attribute("viewBox").map(|s| {
        let mut lx = Lexer::new(s);
        std::iter::from_fn(|| lx.number()).collect()
    });
    match vb.as_deref() {
        Some([_, _, vw, _]) if *vw > 0.0 && vw.is_finite() && w.is_finite() && w > 0.0 => {
            Ok(w / vw * to_cat)
        }
        Some(_) => Err(SvgError::BadViewBox),
        // CSS pixels: 96 per inch.
        None => Ok(LengthUnit::In.factor_to(opts.units) / 96.0),
    }
}

/// Reads an SVG drawing into a part in `opts.units`, unvalidated: the
/// reader finds the shapes, [`validate_part`](super::validate_part) judges
/// them the same way for every format.
pub fn read_svg(bytes: &[u8], opts: &ReadOptions) -> Result<RawPart, SvgError> {
    let text = std::str::from_utf8(bytes).map_err(SvgError::NotUtf8)?;
    let doc = roxmltree::Document::parse(text).map_err(SvgError::NotXml)?;
    let root = doc.root_element();
    if root.tag_name().name() != "svg" {
        return Err(SvgError::NotSvg(root.tag_name().name().to_string()));
    }
    let k = user_unit(root, opts)?;
    let mut w = Walk {
        tol: opts.chord_tolerance / k,
        exact: !opts.arcs.flatten(),
        loops: Vec::new(),
        access: Vec::new(),
        warnings: Vec::new(),
        depth_guard: 0,
    };
    let access = marked_access(root);
    let ctm = match root.attribute("transform") {
        Some(t) => parse_transform(t).map_err(SvgError::RootTransform)?,
        None => Affine::ID,
    };
    walk(root, ctm, access, &mut w)?;
    // User units down to part units up: (x, y) -> (x, -y), then scale; the
    // flip turns every arc the other way.
    let map = |pts: Vec<P>| -> Vec<P> { pts.into_iter().map(|p| [p[0] * k, -p[1] * k]).collect() };
    let map_v = |pts: Vec<Vertex>| -> Vec<Vertex> {
        pts.into_iter()
            .map(|v| {
                Vertex::new(
                    v.x * k,
                    -v.y * k,
                    if v.bulge == 0.0 { 0.0 } else { -v.bulge },
                )
            })
            .collect()
    };
    let loops = w.loops.into_iter().map(|(p, l)| (map_v(p), l)).collect();
    let access = w.access.into_iter().map(map).collect();
    Ok(pick_outline(loops, access, w.warnings, opts.units)?)
}

/// Writes a part as SVG with a physical size in `units`, so that any SVG
/// tool shows it at scale and [`read_svg`] reads back the same numbers:
/// the outline is `<path id="outline">` (arcs as `A` commands, their
/// bulges also in `data-fixplan-bulges` so they read back bit for bit),
/// access constraints are paths of class `access`, and part y is written
/// as SVG `-y`.
pub fn write_svg(part: &Part, units: Units) -> String {
    let outline = positions(&part.outline);
    let all = outline.iter().chain(part.access.iter().flatten());
    let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
    for p in all {
        if p[0].is_finite() && p[1].is_finite() {
            x0 = x0.min(p[0]);
            x1 = x1.max(p[0]);
            y0 = y0.min(-p[1]);
            y1 = y1.max(-p[1]);
        }
    }
    if x0 > x1 || y0 > y1 {
        (x0, y0, x1, y1) = (0.0, 0.0, 1.0, 1.0);
    }
    let (w, h) = ((x1 - x0).max(1e-9), (y1 - y0).max(1e-9));
    let u = units.label();
    let mut s = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w:?}{u}\" height=\"{h:?}{u}\" viewBox=\"{x0:?} {y0:?} {w:?} {h:?}\">\n"
    );
    let bulges = if part.outline.iter().any(Vertex::is_arc) {
        let list: Vec<String> = part
            .outline
            .iter()
            .map(|v| format!("{:?}", v.bulge))
            .collect();
        format!(" data-fixplan-bulges=\"{}\"", list.join(" "))
    } else {
        String::new()
    };
    s.push_str(&format!(
        "  <path id=\"outline\" fill=\"#ddd\" stroke=\"black\"{bulges} d=\"{}\"/>\n",
        path_data(&part.outline)
    ));
    for a in &part.access {
        let a: Vec<Vertex> = a.iter().map(|&p| Vertex::from(p)).collect();
        s.push_str(&format!(
            "  <path class=\"access\" fill=\"none\" stroke=\"red\" d=\"{}\"/>\n",
            path_data(&a)
        ));
    }
    s.push_str("</svg>\n");
    s
}

/// A closed outline as path data in SVG coordinates (y negated): `L` for
/// straight edges, `A` for arcs (radius from the bulge, large-arc when
/// `|b| > 1`, and the sweep flag, SVG's positive-angle direction in its
/// y-down coordinates, for a clockwise part arc, `b < 0`).
fn path_data(pts: &[Vertex]) -> String {
    let mut d = String::new();
    let n = pts.len();
    for (i, p) in pts.iter().enumerate() {
        if i == 0 {
            d.push_str(&format!("M {:?},{:?}", p.x, -p.y));
        }
        let q = pts[(i + 1) % n];
        if i + 1 == n && !p.is_arc() {
            break;
        }
        if p.is_arc() {
            let chord = (q.x - p.x).hypot(q.y - p.y);
            let b = p.bulge.abs();
            let r = chord * (1.0 / b + b) / 4.0;
            let large = u8::from(b > 1.0);
            let sweep = u8::from(p.bulge < 0.0);
            d.push_str(&format!(
                " A {r:?},{r:?} 0 {large} {sweep} {:?},{:?}",
                q.x, -q.y
            ));
        } else {
            d.push_str(&format!(" L {:?},{:?}", q.x, -q.y));
        }
    }
    d.push_str(" Z");
    d
}
