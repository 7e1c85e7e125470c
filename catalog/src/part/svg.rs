//! SVG part outlines: a small reader on top of `roxmltree`, and a writer.
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
//! `skewX`, `skewY` and `matrix` transforms on elements and groups. Elements
//! whose `class` contains `access` or `keepout`, or whose `id` starts with
//! one of those words (any case), are access constraints, and so is all
//! inside a group marked that way. The largest closed shape is the part;
//! smaller ones inside it are ignored with a warning. `<defs>`, `<use>`,
//! text and styles are not geometry here.

use super::outline::{arc_pieces, fmt, pick_outline, MAX_ARC_PIECES, P};
use super::raw::{RawPart, ReadOptions};
use crate::units::LengthUnit;
use fixplan_core::{Part, Units};

/// Affine map `(x, y) -> (a x + c y + e, b x + d y + f)`, SVG's order.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Affine([f64; 6]);

impl Affine {
    const ID: Affine = Affine([1.0, 0.0, 0.0, 1.0, 0.0, 0.0]);

    /// `self` then `o` applied first (SVG nesting: parent * child).
    fn mul(self, o: Affine) -> Affine {
        let [a, b, c, d, e, f] = self.0;
        let [a2, b2, c2, d2, e2, f2] = o.0;
        Affine([
            a * a2 + c * b2,
            b * a2 + d * b2,
            a * c2 + c * d2,
            b * c2 + d * d2,
            a * e2 + c * f2 + e,
            b * e2 + d * f2 + f,
        ])
    }

    fn apply(self, p: P) -> P {
        let [a, b, c, d, e, f] = self.0;
        [a * p[0] + c * p[1] + e, b * p[0] + d * p[1] + f]
    }

    /// Largest stretch of the map, to keep chord errors within tolerance
    /// after scaling.
    fn max_scale(self) -> f64 {
        let [a, b, c, d, _, _] = self.0;
        let s = a.hypot(b).max(c.hypot(d));
        if s.is_finite() && s > 0.0 {
            s
        } else {
            1.0
        }
    }
}

/// Numbers of SVG attribute micro-syntax: separators are whitespace and
/// commas, a sign or a second '.' starts a new number, arc flags may be
/// written without separators.
struct Lexer<'a> {
    s: &'a [u8],
    i: usize,
}

impl<'a> Lexer<'a> {
    fn new(s: &'a str) -> Self {
        Lexer {
            s: s.as_bytes(),
            i: 0,
        }
    }

    fn skip_sep(&mut self) {
        while self.i < self.s.len()
            && (self.s[self.i].is_ascii_whitespace() || self.s[self.i] == b',')
        {
            self.i += 1;
        }
    }

    fn at_end(&mut self) -> bool {
        self.skip_sep();
        self.i >= self.s.len()
    }

    fn peek(&mut self) -> Option<u8> {
        self.skip_sep();
        self.s.get(self.i).copied()
    }

    fn starts_number(&mut self) -> bool {
        matches!(self.peek(), Some(c) if c.is_ascii_digit() || c == b'-' || c == b'+' || c == b'.')
    }

    fn number(&mut self) -> Option<f64> {
        self.skip_sep();
        let start = self.i;
        let s = self.s;
        let mut j = self.i;
        if j < s.len() && (s[j] == b'-' || s[j] == b'+') {
            j += 1;
        }
        let mut digits = false;
        while j < s.len() && s[j].is_ascii_digit() {
            j += 1;
            digits = true;
        }
        if j < s.len() && s[j] == b'.' {
            j += 1;
            while j < s.len() && s[j].is_ascii_digit() {
                j += 1;
                digits = true;
            }
        }
        if !digits {
            return None;
        }
        if j < s.len() && (s[j] == b'e' || s[j] == b'E') {
            let mut k = j + 1;
            if k < s.len() && (s[k] == b'-' || s[k] == b'+') {
                k += 1;
            }
            if k < s.len() && s[k].is_ascii_digit() {
                while k < s.len() && s[k].is_ascii_digit() {
                    k += 1;
                }
                j = k;
            }
        }
        let text = std::str::from_utf8(&s[start..j]).ok()?;
        let v = text.parse::<f64>().ok()?;
        self.i = j;
        Some(v)
    }

    fn flag(&mut self) -> Option<bool> {
        match self.peek()? {
            b'0' => {
                self.i += 1;
                Some(false)
            }
            b'1' => {
                self.i += 1;
                Some(true)
            }
            _ => None,
        }
    }
}

fn parse_transform(s: &str) -> Result<Affine, String> {
    let mut m = Affine::ID;
    let mut rest = s.trim();
    while !rest.is_empty() {
        let open = rest
            .find('(')
            .ok_or_else(|| format!("bad transform \"{s}\""))?;
        let close = rest[open..]
            .find(')')
            .map(|c| c + open)
            .ok_or_else(|| format!("bad transform \"{s}\""))?;
        let name = rest[..open].trim().trim_start_matches(',').trim();
        let mut lx = Lexer::new(&rest[open + 1..close]);
        let mut args = Vec::new();
        while !lx.at_end() {
            args.push(
                lx.number()
                    .ok_or_else(|| format!("bad number in transform \"{s}\""))?,
            );
        }
        let t = match (name, args.as_slice()) {
            ("matrix", [a, b, c, d, e, f]) => Affine([*a, *b, *c, *d, *e, *f]),
            ("translate", [x]) => Affine([1.0, 0.0, 0.0, 1.0, *x, 0.0]),
            ("translate", [x, y]) => Affine([1.0, 0.0, 0.0, 1.0, *x, *y]),
            ("scale", [x]) => Affine([*x, 0.0, 0.0, *x, 0.0, 0.0]),
            ("scale", [x, y]) => Affine([*x, 0.0, 0.0, *y, 0.0, 0.0]),
            ("rotate", [a]) => rotation(*a),
            ("rotate", [a, cx, cy]) => Affine([1.0, 0.0, 0.0, 1.0, *cx, *cy])
                .mul(rotation(*a))
                .mul(Affine([1.0, 0.0, 0.0, 1.0, -cx, -cy])),
            ("skewX", [a]) => Affine([1.0, 0.0, a.to_radians().tan(), 1.0, 0.0, 0.0]),
            ("skewY", [a]) => Affine([1.0, a.to_radians().tan(), 0.0, 1.0, 0.0, 0.0]),
            _ => return Err(format!("unsupported transform \"{}\"", &rest[..=close])),
        };
        m = m.mul(t);
        rest = rest[close + 1..].trim_start();
    }
    Ok(m)
}

fn rotation(deg: f64) -> Affine {
    let (s, c) = deg.to_radians().sin_cos();
    Affine([c, s, -s, c, 0.0, 0.0])
}

/// A subpath in user units, before transforms.
struct Sub {
    pts: Vec<P>,
    closed: bool,
}

fn cubic(p0: P, p1: P, p2: P, p3: P, tol: f64, out: &mut Vec<P>) {
    // |B''| <= 6 max(|p0 - 2p1 + p2|, |p1 - 2p2 + p3|) and n uniform chords
    // deviate at most |B''|max / (8 n^2).
    let dd = |a: P, b: P, c: P| (a[0] - 2.0 * b[0] + c[0]).hypot(a[1] - 2.0 * b[1] + c[1]);
    let m = dd(p0, p1, p2).max(dd(p1, p2, p3));
    let n = pieces_for(0.75 * m / tol);
    for k in 1..=n {
        let t = k as f64 / n as f64;
        let u = 1.0 - t;
        let (a, b, c, d) = (u * u * u, 3.0 * u * u * t, 3.0 * u * t * t, t * t * t);
        out.push([
            a * p0[0] + b * p1[0] + c * p2[0] + d * p3[0],
            a * p0[1] + b * p1[1] + c * p2[1] + d * p3[1],
        ]);
    }
}

fn quad(p0: P, p1: P, p2: P, tol: f64, out: &mut Vec<P>) {
    let m = (p0[0] - 2.0 * p1[0] + p2[0]).hypot(p0[1] - 2.0 * p1[1] + p2[1]);
    let n = pieces_for(0.25 * m / tol);
    for k in 1..=n {
        let t = k as f64 / n as f64;
        let u = 1.0 - t;
        let (a, b, c) = (u * u, 2.0 * u * t, t * t);
        out.push([
            a * p0[0] + b * p1[0] + c * p2[0],
            a * p0[1] + b * p1[1] + c * p2[1],
        ]);
    }
}

/// `ceil(sqrt(x))`, clamped, for the uniform-subdivision bounds above.
fn pieces_for(x: f64) -> usize {
    let n = x.sqrt().ceil();
    if n.is_finite() && n >= 1.0 {
        (n as usize).min(MAX_ARC_PIECES)
    } else if n.is_nan() || n < 1.0 {
        1
    } else {
        MAX_ARC_PIECES
    }
}

/// SVG elliptical arc (endpoint parameterisation, SVG 1.1 F.6.5).
#[allow(clippy::too_many_arguments)]
fn arc(
    p1: P,
    rx: f64,
    ry: f64,
    phi: f64,
    large: bool,
    sweep: bool,
    p2: P,
    tol: f64,
    out: &mut Vec<P>,
) {
    if p1 == p2 {
        return;
    }
    let (mut rx, mut ry) = (rx.abs(), ry.abs());
    if rx == 0.0 || ry == 0.0 || !rx.is_finite() || !ry.is_finite() {
        out.push(p2);
        return;
    }
    let (s, c) = phi.to_radians().sin_cos();
    let dx2 = (p1[0] - p2[0]) / 2.0;
    let dy2 = (p1[1] - p2[1]) / 2.0;
    let x1 = c * dx2 + s * dy2;
    let y1 = -s * dx2 + c * dy2;
    let lambda = (x1 * x1) / (rx * rx) + (y1 * y1) / (ry * ry);
    if lambda > 1.0 {
        rx *= lambda.sqrt();
        ry *= lambda.sqrt();
    }
    let num = rx * rx * ry * ry - rx * rx * y1 * y1 - ry * ry * x1 * x1;
    let den = rx * rx * y1 * y1 + ry * ry * x1 * x1;
    let mut coef = if den > 0.0 {
        (num / den).max(0.0).sqrt()
    } else {
        0.0
    };
    if large == sweep {
        coef = -coef;
    }
    let cxp = coef * rx * y1 / ry;
    let cyp = -coef * ry * x1 / rx;
    let cx = c * cxp - s * cyp + (p1[0] + p2[0]) / 2.0;
    let cy = s * cxp + c * cyp + (p1[1] + p2[1]) / 2.0;
    let ang = |ux: f64, uy: f64| uy.atan2(ux);
    let t1 = ang((x1 - cxp) / rx, (y1 - cyp) / ry);
    let t2 = ang((-x1 - cxp) / rx, (-y1 - cyp) / ry);
    let mut dt = t2 - t1;
    if sweep && dt < 0.0 {
        dt += std::f64::consts::TAU;
    } else if !sweep && dt > 0.0 {
        dt -= std::f64::consts::TAU;
    }
    let n = arc_pieces(rx.max(ry), dt, tol);
    for k in 1..n {
        let t = t1 + dt * k as f64 / n as f64;
        let (st, ct) = t.sin_cos();
        out.push([
            c * rx * ct - s * ry * st + cx,
            s * rx * ct + c * ry * st + cy,
        ]);
    }
    out.push(p2);
}

fn parse_path(d: &str, tol: f64) -> Result<Vec<Sub>, String> {
    let mut lx = Lexer::new(d);
    let mut subs: Vec<Sub> = Vec::new();
    let mut cur: Vec<P> = Vec::new();
    let mut pos = [0.0, 0.0];
    let mut start = [0.0, 0.0];
    // Reflected control point for S / T, with the command that set it.
    let mut last_ctrl: Option<(u8, P)> = None;
    let mut cmd: Option<u8> = None;
    let bad = |what: &str| format!("bad path data near \"{what}\"");
    let tail = |lx: &Lexer| {
        let s = &lx.s[lx.i.min(lx.s.len())..];
        String::from_utf8_lossy(&s[..s.len().min(20)]).into_owned()
    };
    let flush = |cur: &mut Vec<P>, subs: &mut Vec<Sub>, closed: bool| {
        if cur.len() > 1 || closed {
            subs.push(Sub {
                pts: std::mem::take(cur),
                closed,
            });
        } else {
            cur.clear();
        }
    };
    loop {
        let c = match lx.peek() {
            None => break,
            Some(c) if c.is_ascii_alphabetic() => {
                lx.i += 1;
                c
            }
            Some(_) => match cmd {
                // Repeated parameters reuse the previous command; after a
                // moveto they are linetos.
                Some(b'M') => b'L',
                Some(b'm') => b'l',
                Some(b'Z') | Some(b'z') | None => return Err(bad(&tail(&lx))),
                Some(c) => c,
            },
        };
        cmd = Some(c);
        let rel = c.is_ascii_lowercase();
        let base = if rel { pos } else { [0.0, 0.0] };
        let num = |lx: &mut Lexer| lx.number().ok_or_else(|| bad(&tail(lx)));
        match c.to_ascii_uppercase() {
            b'M' => {
                flush(&mut cur, &mut subs, false);
                let p = [base[0] + num(&mut lx)?, base[1] + num(&mut lx)?];
                pos = p;
                start = p;
                cur.push(p);
                last_ctrl = None;
            }
            b'L' => {
                let p = [base[0] + num(&mut lx)?, base[1] + num(&mut lx)?];
                if cur.is_empty() {
                    cur.push(pos);
                }
                cur.push(p);
                pos = p;
                last_ctrl = None;
            }
            b'H' => {
                let x = num(&mut lx)? + if rel { pos[0] } else { 0.0 };
                if cur.is_empty() {
                    cur.push(pos);
                }
                pos = [x, pos[1]];
                cur.push(pos);
                last_ctrl = None;
            }
            b'V' => {
                let y = num(&mut lx)? + if rel { pos[1] } else { 0.0 };
                if cur.is_empty() {
                    cur.push(pos);
                }
                pos = [pos[0], y];
                cur.push(pos);
                last_ctrl = None;
            }
            b'C' | b'S' => {
                let p1 = if c.eq_ignore_ascii_case(&b'C') {
                    [base[0] + num(&mut lx)?, base[1] + num(&mut lx)?]
                } else {
                    match last_ctrl {
                        Some((b'C', q)) => [2.0 * pos[0] - q[0], 2.0 * pos[1] - q[1]],
                        _ => pos,
                    }
                };
                let p2 = [base[0] + num(&mut lx)?, base[1] + num(&mut lx)?];
                let p3 = [base[0] + num(&mut lx)?, base[1] + num(&mut lx)?];
                if cur.is_empty() {
                    cur.push(pos);
                }
                cubic(pos, p1, p2, p3, tol, &mut cur);
                pos = p3;
                last_ctrl = Some((b'C', p2));
            }
            b'Q' | b'T' => {
                let p1 = if c.eq_ignore_ascii_case(&b'Q') {
                    [base[0] + num(&mut lx)?, base[1] + num(&mut lx)?]
                } else {
                    match last_ctrl {
                        Some((b'Q', q)) => [2.0 * pos[0] - q[0], 2.0 * pos[1] - q[1]],
                        _ => pos,
                    }
                };
                let p2 = [base[0] + num(&mut lx)?, base[1] + num(&mut lx)?];
                if cur.is_empty() {
                    cur.push(pos);
                }
                quad(pos, p1, p2, tol, &mut cur);
                pos = p2;
                last_ctrl = Some((b'Q', p1));
            }
            b'A' => {
                let rx = num(&mut lx)?;
                let ry = num(&mut lx)?;
                let phi = num(&mut lx)?;
                let large = lx.flag().ok_or_else(|| bad(&tail(&lx)))?;
                let sweep = lx.flag().ok_or_else(|| bad(&tail(&lx)))?;
                let p = [base[0] + num(&mut lx)?, base[1] + num(&mut lx)?];
                if cur.is_empty() {
                    cur.push(pos);
                }
                arc(pos, rx, ry, phi, large, sweep, p, tol, &mut cur);
                pos = p;
                last_ctrl = None;
            }
            b'Z' => {
                flush(&mut cur, &mut subs, true);
                pos = start;
                last_ctrl = None;
            }
            _ => return Err(format!("unknown path command '{}'", c as char)),
        }
        if !lx.starts_number()
            && !matches!(lx.peek(), Some(c) if c.is_ascii_alphabetic())
            && !lx.at_end()
        {
            return Err(bad(&tail(&lx)));
        }
    }
    flush(&mut cur, &mut subs, false);
    Ok(subs)
}

fn points_attr(s: &str) -> Result<Vec<P>, String> {
    let mut lx = Lexer::new(s);
    let mut v = Vec::new();
    while !lx.at_end() {
        let x = lx
            .number()
            .ok_or_else(|| format!("bad points list \"{s}\""))?;
        let y = lx
            .number()
            .ok_or_else(|| format!("odd number of coordinates in \"{s}\""))?;
        v.push([x, y]);
    }
    Ok(v)
}

/// A length attribute in user units: a bare number or `px`.
fn length_attr(node: roxmltree::Node, name: &str, default: f64) -> Result<f64, String> {
    match node.attribute(name) {
        None => Ok(default),
        Some(s) => {
            let t = s.trim().trim_end_matches("px");
            t.trim().parse::<f64>().map_err(|_| {
                format!(
                    "<{}> {name}=\"{s}\": only plain numbers are supported here",
                    node.tag_name().name()
                )
            })
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

struct Walk {
    tol: f64,
    loops: Vec<(Vec<P>, String)>,
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

fn walk(node: roxmltree::Node, ctm: Affine, access: bool, w: &mut Walk) -> Result<(), String> {
    w.depth_guard += 1;
    if w.depth_guard > 10_000 {
        return Err("too many nested elements".into());
    }
    for child in node.children().filter(|n| n.is_element()) {
        let name = child.tag_name().name();
        if child.attribute("display") == Some("none") {
            continue;
        }
        let ctm = match child.attribute("transform") {
            Some(t) => {
                ctm.mul(parse_transform(t).map_err(|e| format!("{}: {e}", describe(child)))?)
            }
            None => ctm,
        };
        let access = access || marked_access(child);
        let tol = w.tol / ctm.max_scale();
        let subs: Vec<Sub> = match name {
            "g" | "a" | "switch" | "svg" => {
                walk(child, ctm, access, w)?;
                continue;
            }
            "polygon" => vec![Sub {
                pts: points_attr(child.attribute("points").unwrap_or(""))?,
                closed: true,
            }],
            "polyline" => vec![Sub {
                pts: points_attr(child.attribute("points").unwrap_or(""))?,
                closed: false,
            }],
            "path" => parse_path(child.attribute("d").unwrap_or(""), tol)
                .map_err(|e| format!("{}: {e}", describe(child)))?,
            "rect" => {
                let x = length_attr(child, "x", 0.0)?;
                let y = length_attr(child, "y", 0.0)?;
                let wd = length_attr(child, "width", 0.0)?;
                let ht = length_attr(child, "height", 0.0)?;
                vec![Sub {
                    pts: vec![[x, y], [x + wd, y], [x + wd, y + ht], [x, y + ht]],
                    closed: true,
                }]
            }
            "circle" | "ellipse" => {
                let cx = length_attr(child, "cx", 0.0)?;
                let cy = length_attr(child, "cy", 0.0)?;
                let (rx, ry) = if name == "circle" {
                    let r = length_attr(child, "r", 0.0)?;
                    (r, r)
                } else {
                    (
                        length_attr(child, "rx", 0.0)?,
                        length_attr(child, "ry", 0.0)?,
                    )
                };
                let n = arc_pieces(rx.abs().max(ry.abs()), std::f64::consts::TAU, tol).max(3);
                let pts = (0..n)
                    .map(|k| {
                        let t = std::f64::consts::TAU * k as f64 / n as f64;
                        [cx + rx * t.cos(), cy + ry * t.sin()]
                    })
                    .collect();
                vec![Sub { pts, closed: true }]
            }
            "use" => {
                w.warnings.push(format!(
                    "{} (a reference) is not supported; ignored",
                    describe(child)
                ));
                continue;
            }
            "line" => {
                w.warnings.push(format!(
                    "{} is a single line, not a shape; ignored",
                    describe(child)
                ));
                continue;
            }
            _ => continue,
        };
        for (k, sub) in subs.into_iter().enumerate() {
            let mut pts = sub.pts;
            let closes = pts.len() > 2 && pts.first() == pts.last();
            if !sub.closed && !closes {
                let (s, e) = (
                    pts.first().copied().unwrap_or_default(),
                    pts.last().copied().unwrap_or_default(),
                );
                return Err(format!(
                    "open loop: {} (subpath {k}) runs from ({}, {}) to ({}, {}) in SVG user units and is not closed (add Z)",
                    describe(child),
                    fmt(s[0]),
                    fmt(s[1]),
                    fmt(e[0]),
                    fmt(e[1])
                ));
            }
            if closes {
                pts.pop();
            }
            let pts: Vec<P> = pts.into_iter().map(|p| ctm.apply(p)).collect();
            if access {
                w.access.push(pts);
            } else {
                w.loops.push((pts, describe(child)));
            }
        }
    }
    Ok(())
}

fn split_length(s: &str) -> Option<(f64, &str)> {
    let s = s.trim();
    let end = s
        .find(|c: char| c.is_ascii_alphabetic() || c == '%')
        .unwrap_or(s.len());
    let v = s[..end].trim().parse::<f64>().ok()?;
    Some((v, s[end..].trim()))
}

/// Factor from user units to catalogue units, and the unit used.
fn user_unit(root: roxmltree::Node, opts: &ReadOptions) -> Result<f64, String> {
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
        Some(_) => {
            Err("root <svg> has a viewBox that is not four numbers with a positive width".into())
        }
        // CSS pixels: 96 per inch.
        None => Ok(LengthUnit::In.factor_to(opts.units) / 96.0),
    }
}

pub fn read_svg(bytes: &[u8], opts: &ReadOptions) -> Result<RawPart, String> {
    let text = std::str::from_utf8(bytes).map_err(|e| format!("not a readable SVG file: {e}"))?;
    let doc =
        roxmltree::Document::parse(text).map_err(|e| format!("not a readable SVG file: {e}"))?;
    let root = doc.root_element();
    if root.tag_name().name() != "svg" {
        return Err(format!(
            "not an SVG file: the root element is <{}>",
            root.tag_name().name()
        ));
    }
    let k = user_unit(root, opts)?;
    let mut w = Walk {
        tol: opts.chord_tolerance / k,
        loops: Vec::new(),
        access: Vec::new(),
        warnings: Vec::new(),
        depth_guard: 0,
    };
    let access = marked_access(root);
    let ctm = match root.attribute("transform") {
        Some(t) => parse_transform(t)?,
        None => Affine::ID,
    };
    walk(root, ctm, access, &mut w)?;
    // User units down to part units up: (x, y) -> (x, -y), then scale.
    let map = |pts: Vec<P>| -> Vec<P> { pts.into_iter().map(|p| [p[0] * k, -p[1] * k]).collect() };
    let loops = w.loops.into_iter().map(|(p, l)| (map(p), l)).collect();
    let access = w.access.into_iter().map(map).collect();
    pick_outline(loops, access, w.warnings, opts.units.label())
}

/// Writes a part as SVG with a physical size in `units`, so that any SVG
/// tool shows it at scale and [`read_svg`] reads back the same numbers:
/// the outline is `<path id="outline">`, access constraints are paths of
/// class `access`, and part y is written as SVG `-y`.
pub fn write_svg(part: &Part, units: Units) -> String {
    let all = part.outline.iter().chain(part.access.iter().flatten());
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
    let path = |pts: &[[f64; 2]]| {
        let mut d = String::new();
        for (i, p) in pts.iter().enumerate() {
            d.push_str(if i == 0 { "M " } else { " L " });
            d.push_str(&format!("{:?},{:?}", p[0], -p[1]));
        }
        d.push_str(" Z");
        d
    };
    let mut s = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w:?}{u}\" height=\"{h:?}{u}\" viewBox=\"{x0:?} {y0:?} {w:?} {h:?}\">\n"
    );
    s.push_str(&format!(
        "  <path id=\"outline\" fill=\"#ddd\" stroke=\"black\" d=\"{}\"/>\n",
        path(&part.outline)
    ));
    for a in &part.access {
        s.push_str(&format!(
            "  <path class=\"access\" fill=\"none\" stroke=\"red\" d=\"{}\"/>\n",
            path(a)
        ));
    }
    s.push_str("</svg>\n");
    s
}
