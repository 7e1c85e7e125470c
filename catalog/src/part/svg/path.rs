//! Path data (`d` attributes): every command of SVG 1.1 into subpaths in
//! user units; Bézier curves and elliptical arcs flattened to a chord
//! tolerance, circular arcs (`A` with equal radii) kept exact as bulge
//! vertices when the caller asks.

use super::lexer::Lexer;
use super::limits::{Budget, Exceeded};
use crate::part::outline::{arc_pieces, MAX_ARC_PIECES, P};
use fixplan_core::Vertex;

/// Why path data cannot be read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PathError {
    /// A number, flag or command is missing or malformed; up to 20
    /// characters from where reading stopped.
    #[error("bad path data near \"{0}\"")]
    BadData(String),
    /// A letter that is not an SVG path command.
    #[error("unknown path command '{0}'")]
    UnknownCommand(char),
    /// The file's budget of commands or vertices is spent: what was
    /// counted and the bound.
    #[error("more than {limit} {what}, the SVG reader's fixed limit (a guard against runaway and hostile files; it cannot be raised); simplify the drawing or split it into one file per part")]
    TooBig {
        /// What was counted.
        what: &'static str,
        /// The bound.
        limit: usize,
    },
}

impl From<Exceeded> for PathError {
    fn from(exceeded: Exceeded) -> Self {
        PathError::TooBig {
            what: exceeded.what,
            limit: exceeded.limit,
        }
    }
}

/// A subpath in user units, before transforms.
pub(super) struct Sub {
    /// Its vertices, a bulge for each circular arc kept exact (turning
    /// counter-clockwise in user coordinates when positive); a closing
    /// point equal to the first is kept.
    pub(super) pts: Vec<Vertex>,
    /// Ended by `Z` (or a closed element such as `<polygon>`).
    pub(super) closed: bool,
}

/// The state of reading one `d` attribute.
struct PathParser<'a> {
    lx: Lexer<'a>,
    tol: f64,
    /// Circular arcs become bulges rather than chords.
    exact: bool,
    subs: Vec<Sub>,
    /// Vertices of `subs`, all together.
    done: usize,
    /// The subpath being drawn.
    cur: Vec<Vertex>,
    /// The current point.
    pos: P,
    /// Where the current subpath started (for `Z`).
    start: P,
    /// Control point for the reflection of `S` / `T`, with the command
    /// that set it.
    last_ctrl: Option<(u8, P)>,
}

/// Parses path data into subpaths, curves flattened within `tol`, circular
/// arcs exact when `exact`, every command and vertex taken from `budget`.
pub(super) fn parse_path(
    d: &str,
    tol: f64,
    exact: bool,
    budget: &mut Budget,
) -> Result<Vec<Sub>, PathError> {
    let mut p = PathParser {
        lx: Lexer::new(d),
        tol,
        exact,
        subs: Vec::new(),
        done: 0,
        cur: Vec::new(),
        pos: [0.0, 0.0],
        start: [0.0, 0.0],
        last_ctrl: None,
    };
    let mut cmd: Option<u8> = None;
    let mut drawn = 0;
    while let Some(c) = p.next_command(cmd)? {
        cmd = Some(c);
        budget.command()?;
        p.command(c)?;
        p.expect_separator()?;
        let now = p.drawn();
        budget.vertices(now.saturating_sub(drawn))?;
        drawn = now;
    }
    p.flush(false);
    Ok(p.subs)
}

impl PathParser<'_> {
    /// Vertices drawn so far, all subpaths.
    fn drawn(&self) -> usize {
        self.done + self.cur.len()
    }

    fn bad(&self) -> PathError {
        PathError::BadData(self.lx.tail())
    }

    /// The next command letter, or the previous command again when
    /// parameters repeat (after a moveto they are linetos); `None` at the
    /// end.
    fn next_command(&mut self, prev: Option<u8>) -> Result<Option<u8>, PathError> {
        match self.lx.peek() {
            None => Ok(None),
            Some(c) if c.is_ascii_alphabetic() => {
                self.lx.bump();
                Ok(Some(c))
            }
            Some(_) => match prev {
                Some(b'M') => Ok(Some(b'L')),
                Some(b'm') => Ok(Some(b'l')),
                Some(b'Z') | Some(b'z') | None => Err(self.bad()),
                Some(c) => Ok(Some(c)),
            },
        }
    }

    /// After a command's parameters: another number, a command or the end.
    fn expect_separator(&mut self) -> Result<(), PathError> {
        if !self.lx.starts_number()
            && !matches!(self.lx.peek(), Some(c) if c.is_ascii_alphabetic())
            && !self.lx.at_end()
        {
            return Err(self.bad());
        }
        Ok(())
    }

    fn num(&mut self) -> Result<f64, PathError> {
        self.lx.number().ok_or_else(|| self.bad())
    }

    fn flag(&mut self) -> Result<bool, PathError> {
        self.lx.flag().ok_or_else(|| self.bad())
    }

    /// A coordinate pair, offset by `base` (the current point for relative
    /// commands, the origin for absolute ones).
    fn point(&mut self, base: P) -> Result<P, PathError> {
        Ok([base[0] + self.num()?, base[1] + self.num()?])
    }

    /// Ends the current subpath; an open one of a single point draws
    /// nothing and is dropped.
    fn flush(&mut self, closed: bool) {
        if self.cur.len() > 1 || closed {
            self.done += self.cur.len();
            self.subs.push(Sub {
                pts: std::mem::take(&mut self.cur),
                closed,
            });
        } else {
            self.cur.clear();
        }
    }

    /// Starts drawing from the current point if nothing is drawn yet.
    fn begin(&mut self) {
        if self.cur.is_empty() {
            self.cur.push(self.pos.into());
        }
    }

    /// Appends points drawn by a flattened curve.
    fn push_points(&mut self, pts: Vec<P>) {
        self.cur.extend(pts.into_iter().map(Vertex::from));
    }

    /// Reads and draws one command's parameters.
    fn command(&mut self, letter: u8) -> Result<(), PathError> {
        let rel = letter.is_ascii_lowercase();
        let base = if rel { self.pos } else { [0.0, 0.0] };
        match letter.to_ascii_uppercase() {
            b'M' => {
                self.flush(false);
                let p = self.point(base)?;
                self.pos = p;
                self.start = p;
                self.cur.push(p.into());
                self.last_ctrl = None;
            }
            b'L' => {
                let p = self.point(base)?;
                self.line_to(p);
            }
            b'H' => {
                let x = self.num()? + if rel { self.pos[0] } else { 0.0 };
                self.line_to([x, self.pos[1]]);
            }
            b'V' => {
                let y = self.num()? + if rel { self.pos[1] } else { 0.0 };
                self.line_to([self.pos[0], y]);
            }
            b'C' | b'S' => self.cubic_to(letter.eq_ignore_ascii_case(&b'C'), base)?,
            b'Q' | b'T' => self.quad_to(letter.eq_ignore_ascii_case(&b'Q'), base)?,
            b'A' => self.arc_to(base)?,
            b'Z' => {
                self.flush(true);
                self.pos = self.start;
                self.last_ctrl = None;
            }
            _ => return Err(PathError::UnknownCommand(letter as char)),
        }
        Ok(())
    }

    fn line_to(&mut self, p: P) {
        self.begin();
        self.cur.push(p.into());
        self.pos = p;
        self.last_ctrl = None;
    }

    /// The first control point of `S` / `T`: the reflection of the
    /// previous command's last one if it was the same kind of curve
    /// (`kind` is `C` or `Q`), else the current point.
    fn reflected(&self, kind: u8) -> P {
        match self.last_ctrl {
            Some((k, q)) if k == kind => [2.0 * self.pos[0] - q[0], 2.0 * self.pos[1] - q[1]],
            _ => self.pos,
        }
    }

    /// `C` (`explicit`: first control point given) or `S`.
    fn cubic_to(&mut self, explicit: bool, base: P) -> Result<(), PathError> {
        let p1 = if explicit {
            self.point(base)?
        } else {
            self.reflected(b'C')
        };
        let p2 = self.point(base)?;
        let p3 = self.point(base)?;
        self.begin();
        let mut pts = Vec::new();
        cubic(self.pos, p1, p2, p3, self.tol, &mut pts);
        self.push_points(pts);
        self.pos = p3;
        self.last_ctrl = Some((b'C', p2));
        Ok(())
    }

    /// `Q` (`explicit`: control point given) or `T`.
    fn quad_to(&mut self, explicit: bool, base: P) -> Result<(), PathError> {
        let p1 = if explicit {
            self.point(base)?
        } else {
            self.reflected(b'Q')
        };
        let p2 = self.point(base)?;
        self.begin();
        let mut pts = Vec::new();
        quad(self.pos, p1, p2, self.tol, &mut pts);
        self.push_points(pts);
        self.pos = p2;
        self.last_ctrl = Some((b'Q', p1));
        Ok(())
    }

    fn arc_to(&mut self, base: P) -> Result<(), PathError> {
        let shape = ArcShape {
            rx: self.num()?,
            ry: self.num()?,
            phi: self.num()?,
            large: self.flag()?,
            sweep: self.flag()?,
        };
        let p = self.point(base)?;
        self.begin();
        let mut pts = Vec::new();
        let bulge = arc(self.pos, shape, p, self.tol, self.exact, &mut pts);
        if let (Some(b), Some(last)) = (bulge, self.cur.last_mut()) {
            last.bulge = b;
        }
        self.push_points(pts);
        self.pos = p;
        self.last_ctrl = None;
        Ok(())
    }
}

/// Cubic Bézier from `p0` to `p3`, start excluded, within `tol`.
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

/// Quadratic Bézier from `p0` to `p2`, start excluded, within `tol`.
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

/// The shape parameters of an `A` command: radii, x-axis rotation in
/// degrees, large-arc and sweep flags.
struct ArcShape {
    rx: f64,
    ry: f64,
    phi: f64,
    large: bool,
    sweep: bool,
}

/// Radii closer than this (relative) are one circle's.
const EQUAL_RADII_REL: f64 = 1e-9;

/// SVG elliptical arc (endpoint parameterisation, SVG 1.1 F.6.5): points
/// pushed on `out` (start excluded, end included), chords within `tol`. A
/// circular arc (equal radii) with `exact` set pushes only its end and
/// returns the bulge of the edge to it, `tan(sweep / 4)`.
fn arc(p1: P, shape: ArcShape, p2: P, tol: f64, exact: bool, out: &mut Vec<P>) -> Option<f64> {
    let ArcShape {
        rx,
        ry,
        phi,
        large,
        sweep,
    } = shape;
    if p1 == p2 {
        return None;
    }
    let (mut rx, mut ry) = (rx.abs(), ry.abs());
    if rx == 0.0 || ry == 0.0 || !rx.is_finite() || !ry.is_finite() {
        out.push(p2);
        return None;
    }
    let circular = (rx - ry).abs() <= EQUAL_RADII_REL * rx.max(ry);
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
    if exact && circular {
        let bulge = (dt / 4.0).tan();
        if bulge.is_finite() && bulge != 0.0 {
            out.push(p2);
            return Some(bulge);
        }
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
    None
}
