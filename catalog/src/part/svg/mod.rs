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
//! **Units** (`units.rs`). By SVG's length rules for the root's `width`
//! (or, without one, `height`) and `viewBox`: one user unit is `width /
//! viewBox-width`, in the width's unit (mm, cm, Q, in, pt, pc: physical,
//! no warning; a bare number or px: CSS px, 96 to the inch). A width
//! without a `viewBox` makes user units CSS px. Without a width or height
//! in absolute units (none, `%`) a user unit is one CSS px, as browsers
//! and Inkscape take it. Whenever the file carries no physical unit a
//! warning states the scale taken, and a manifest entry's `units` (seen
//! when it differs from the catalogue's) takes the place of px.
//!
//! **What is read.** `polygon`, `polyline`, `line`, `path` (M, L, H, V, C,
//! S, Q, T, A, Z, absolute and relative, curves flattened to the chord
//! tolerance), `rect`, `circle` and `ellipse`, with `translate`, `scale`,
//! `rotate`, `skewX`, `skewY` and `matrix` transforms on elements and
//! groups; a DOCTYPE with internal entities (`limits.rs` bounds their
//! expansion; external ones are never read). Open subpaths, `<line>`s and
//! open `<polyline>`s are joined end to end within the join tolerance
//! (`join.rs`). Hidden elements (`display:none`) and elements of other
//! namespaces are skipped.
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
//! the closed shapes directly inside it are its holes (SPEC 9), in
//! document order, and shapes inside a hole are ignored with a warning
//! (`holes = "ignore"` drops every hole with a warning). `<defs>`, `<use>`,
//! text and styles are not geometry here.

mod error;
mod join;
mod lexer;
mod limits;
mod path;
mod transform;
mod units;

pub use error::{ElementProblem, SvgError};
pub use path::PathError;
pub use transform::TransformError;

use super::outline::{arc_pieces, pick_outline, pick_outlines, positions, Affine, Piece, P};
use super::raw::{RawPart, ReadOptions};
use fixplan_core::{Part, Units, Vertex};
use lexer::Lexer;
use limits::Budget;
use path::{parse_path, Sub};
use transform::parse_transform;

fn in_element(node: roxmltree::Node, problem: ElementProblem) -> SvgError {
    SvgError::InElement {
        element: describe(node),
        problem,
    }
}

fn points_attr(text: &str) -> Result<Vec<P>, SvgError> {
    let mut lx = Lexer::new(text);
    let mut v = Vec::new();
    while !lx.at_end() {
        let x = lx
            .number()
            .ok_or_else(|| SvgError::BadPoints(text.to_string()))?;
        let y = lx
            .number()
            .ok_or_else(|| SvgError::OddPoints(text.to_string()))?;
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
struct SvgWalk {
    tol: f64,
    /// Circular arcs may stay exact (`arcs = "exact"`).
    exact: bool,
    loops: Vec<(Vec<Vertex>, String)>,
    access: Vec<Vec<P>>,
    /// Open subpaths, `<line>`s and open `<polyline>`s, to be joined end
    /// to end.
    pieces: Vec<Piece>,
    /// The same, of access constraints.
    access_pieces: Vec<Piece>,
    warnings: Vec<String>,
    budget: Budget,
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

const SVG_NS: &str = "http://www.w3.org/2000/svg";

/// Whether an element is hidden: `display="none"`, or `display:none` in
/// its `style` (how Inkscape hides a layer).
fn display_none(node: roxmltree::Node) -> bool {
    node.attribute("display")
        .is_some_and(|d| d.trim() == "none")
        || node.attribute("style").is_some_and(|st| {
            st.split(';').any(|decl| {
                let mut kv = decl.splitn(2, ':');
                kv.next().is_some_and(|k| k.trim() == "display")
                    && kv.next().is_some_and(|v| v.trim() == "none")
            })
        })
}

/// Whether an element is of another namespace than SVG's: Inkscape's and
/// Sodipodi's own elements are no geometry even when named like SVG's.
fn foreign(node: roxmltree::Node) -> bool {
    node.tag_name().namespace().is_some_and(|ns| ns != SVG_NS)
}

/// Walks the drawing in document order without recursion (an explicit
/// stack of child iterators), so that nesting costs heap, not stack, and
/// is bounded by [`limits::MAX_DEPTH`].
fn walk(
    root: roxmltree::Node,
    ctm: Affine,
    access: bool,
    state: &mut SvgWalk,
) -> Result<(), SvgError> {
    let mut stack = vec![(root.children(), ctm, access)];
    while let Some((children, ctm, access)) = stack.last_mut() {
        let (ctm, access) = (*ctm, *access);
        let Some(child) = children.next() else {
            stack.pop();
            continue;
        };
        if !child.is_element() || foreign(child) {
            continue;
        }
        if display_none(child) {
            let name = child.tag_name().name();
            let drawn = matches!(
                name,
                "path" | "rect" | "circle" | "ellipse" | "line" | "polyline" | "polygon"
            );
            if drawn || (is_container(name) && child.children().any(|c| c.is_element())) {
                state.warnings.push(format!(
                    "{} is hidden (display:none, e.g. a hidden layer); not read",
                    describe(child)
                ));
            }
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
            let viewport = ["x", "y", "width", "height", "viewBox"];
            if child.tag_name().name() == "svg" && viewport.iter().any(|a| child.has_attribute(*a))
            {
                state.warnings.push(format!(
                    "{} is a nested viewport; its x, y, width, height and viewBox are not applied (its shapes are read in the outer user units)",
                    describe(child)
                ));
            }
            if stack.len() >= limits::MAX_DEPTH {
                return Err(SvgError::TooBig {
                    what: "levels of nested groups",
                    limit: limits::MAX_DEPTH,
                });
            }
            stack.push((child.children(), ctm, access));
            continue;
        }
        let tol = state.tol / ctm.max_scale();
        let exact = state.exact && !access && ctm.is_similarity();
        if let Some(subs) =
            element_subpaths(child, tol, exact, &mut state.warnings, &mut state.budget)?
        {
            state.add(child, subs, ctm, access);
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
    budget: &mut Budget,
) -> Result<Option<Vec<Sub>>, SvgError> {
    let name = el.tag_name().name();
    let subs = match name {
        "path" => {
            return parse_path(el.attribute("d").unwrap_or(""), tol, exact, budget)
                .map(Some)
                .map_err(|e| in_element(el, ElementProblem::Path(e)))
        }
        "line" => vec![Sub {
            pts: vec![
                Vertex::new(
                    length_attr(el, "x1", 0.0)?,
                    length_attr(el, "y1", 0.0)?,
                    0.0,
                ),
                Vertex::new(
                    length_attr(el, "x2", 0.0)?,
                    length_attr(el, "y2", 0.0)?,
                    0.0,
                ),
            ],
            closed: false,
        }],
        "polygon" | "polyline" => vec![Sub {
            pts: points_attr(el.attribute("points").unwrap_or(""))?
                .into_iter()
                .map(Vertex::from)
                .collect(),
            closed: name == "polygon",
        }],
        "rect" => rect(el, tol, exact, budget)?,
        "circle" | "ellipse" => vec![ellipse(el, tol, exact)?],
        "use" => {
            warnings.push(format!(
                "{} (a reference) is not supported; ignored",
                describe(el)
            ));
            return Ok(None);
        }
        _ => return Ok(None),
    };
    let n = subs.iter().map(|s| s.pts.len()).sum();
    budget.vertices(n)?;
    Ok(Some(subs))
}

/// A `<rect>`, with rounded corners (`rx`, `ry`) read as the path SVG
/// defines for them, so that round corners are exact circular arcs like
/// any `A` command (a rounded rectangle is how drawing programs write a
/// filleted plate). As in SVG: a radius given alone serves for both, and
/// each is at most half the side it rounds.
fn rect(
    el: roxmltree::Node,
    tol: f64,
    exact: bool,
    budget: &mut Budget,
) -> Result<Vec<Sub>, SvgError> {
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
    parse_path(&d, tol, exact, budget).map_err(|e| in_element(el, ElementProblem::Path(e)))
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

impl SvgWalk {
    /// Adds an element's subpaths, transformed: closed ones as loops (or
    /// access loops), open ones as pieces to join.
    fn add(&mut self, el: roxmltree::Node, subs: Vec<Sub>, ctm: Affine, access: bool) {
        let many = subs.len() > 1;
        let mut loops = Vec::new();
        for (k, sub) in subs.into_iter().enumerate() {
            let mut pts = sub.pts;
            let at = |i: usize| pts.get(i).map(|v: &Vertex| [v.x, v.y]);
            let closes = pts.len() > 2 && at(0) == at(pts.len() - 1);
            if closes {
                pts.pop();
            }
            let pts = ctm.vertices(pts);
            if !sub.closed && !closes {
                let label = if many {
                    format!("{} (subpath {k})", describe(el))
                } else {
                    describe(el)
                };
                let piece = Piece { pts, label };
                if access {
                    self.access_pieces.push(piece);
                } else {
                    self.pieces.push(piece);
                }
            } else if access {
                self.access.push(positions(&pts));
            } else {
                loops.push((pts, describe(el)));
            }
        }
        if let (Some(b), [(pts, _)]) = (written_bulges(el), &mut loops[..]) {
            take_written_bulges(pts, &b);
        }
        self.loops.extend(loops);
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

/// Reads an SVG drawing into a part in `opts.units`, unvalidated: the
/// reader finds the shapes, [`validate_part`](super::validate_part) judges
/// them the same way for every format.
pub fn read_svg(bytes: &[u8], opts: &ReadOptions) -> Result<RawPart, SvgError> {
    let d = read_loops(bytes, opts)?;
    let picked = pick_outline(d.loops, d.access, d.warnings, opts.units, opts.holes);
    join::settle_open(picked, d.open, d.k, d.join_tol)
}

/// Reads an SVG sheet: every outer loop a part of its own, in the order
/// `outline::pick_outlines` documents (as for a DXF sheet).
pub fn read_svg_parts(bytes: &[u8], opts: &ReadOptions) -> Result<Vec<RawPart>, SvgError> {
    let d = read_loops(bytes, opts)?;
    let picked = pick_outlines(d.loops, d.access, d.warnings, opts.units, opts.holes);
    join::settle_open_parts(picked, d.open, d.k, d.join_tol)
}

/// What a drawing holds before an outline is picked: closed loops (in
/// part units), access regions, the warnings so far, and the open chains
/// with the scale and join tolerance they are judged by (user units).
struct Drawn {
    loops: Vec<(Vec<Vertex>, String)>,
    access: Vec<Vec<P>>,
    warnings: Vec<String>,
    open: Vec<join::Open>,
    k: f64,
    join_tol: f64,
}

fn read_loops(bytes: &[u8], opts: &ReadOptions) -> Result<Drawn, SvgError> {
    if bytes.len() > limits::MAX_BYTES {
        return Err(SvgError::TooBig {
            what: "bytes in an SVG file",
            limit: limits::MAX_BYTES,
        });
    }
    let text = std::str::from_utf8(bytes).map_err(SvgError::NotUtf8)?;
    limits::prescan(text).map_err(SvgError::from)?;
    // A DOCTYPE is read (most exporters write one); internal entities are
    // expanded by the parser within the prescan's bound, external ones are
    // never fetched (no resolver is given) and referring to one is
    // refused by the prescan.
    let parsing = roxmltree::ParsingOptions {
        allow_dtd: true,
        nodes_limit: u32::try_from(4 * limits::MAX_ELEMENTS).unwrap_or(u32::MAX),
        ..roxmltree::ParsingOptions::default()
    };
    let doc = roxmltree::Document::parse_with_options(text, parsing).map_err(|e| match e {
        roxmltree::Error::NodesLimitReached => SvgError::TooBig {
            what: "XML nodes (elements, text, comments) in the file",
            limit: 4 * limits::MAX_ELEMENTS,
        },
        e => SvgError::NotXml(e),
    })?;
    let root = doc.root_element();
    if root.tag_name().name() != "svg" {
        return Err(SvgError::NotSvg(root.tag_name().name().to_string()));
    }
    let (k, unit_note) = units::user_unit(root, opts)?;
    let mut w = SvgWalk {
        tol: opts.chord_tolerance / k,
        exact: !opts.arcs.flatten(),
        loops: Vec::new(),
        access: Vec::new(),
        pieces: Vec::new(),
        access_pieces: Vec::new(),
        warnings: unit_note.into_iter().collect(),
        budget: Budget::new(),
    };
    let access = marked_access(root);
    let ctm = match root.attribute("transform") {
        Some(t) => parse_transform(t).map_err(SvgError::RootTransform)?,
        None => Affine::ID,
    };
    walk(root, ctm, access, &mut w)?;
    // Pieces join within the join tolerance, which is in catalogue units.
    let join_tol = opts.join_tolerance / k;
    let join_tol = if join_tol.is_finite() { join_tol } else { 0.0 };
    let open = join::join_into(
        &mut w.loops,
        &mut w.access,
        w.pieces,
        w.access_pieces,
        join_tol,
    )?;
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
    Ok(Drawn {
        loops,
        access,
        warnings: w.warnings,
        open,
        k,
        join_tol,
    })
}

/// Writes a part as SVG with a physical size in `units`, so that any SVG
/// tool shows it at scale and [`read_svg`] reads back the same numbers:
/// the outline is `<path id="outline">` (arcs as `A` commands, their
/// bulges also in `data-fixplan-bulges` so they read back bit for bit),
/// each hole a path of class `hole` after it, in order (read back as the
/// holes, in document order), access constraints are paths of class
/// `access`, and part y is written
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
    s.push_str(&loop_path("id=\"outline\" fill=\"#ddd\"", &part.outline));
    for h in &part.holes {
        s.push_str(&loop_path("class=\"hole\" fill=\"white\"", h));
    }
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

/// A `<path>` element of a closed loop of the part, `attrs` first, with
/// `data-fixplan-bulges` when it has arcs (so it reads back bit for bit).
fn loop_path(attrs: &str, vertices: &[Vertex]) -> String {
    let bulges = if vertices.iter().any(Vertex::is_arc) {
        let list: Vec<String> = vertices.iter().map(|v| format!("{:?}", v.bulge)).collect();
        format!(" data-fixplan-bulges=\"{}\"", list.join(" "))
    } else {
        String::new()
    };
    format!(
        "  <path {attrs} stroke=\"black\"{bulges} d=\"{}\"/>\n",
        path_data(vertices)
    )
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
