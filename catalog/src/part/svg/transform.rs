//! `transform` attributes: SVG's affine maps and their parser.

use super::lexer::Lexer;

/// Why a `transform` attribute cannot be used.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TransformError {
    /// Parentheses missing or unbalanced; the whole attribute.
    #[error("bad transform \"{0}\"")]
    Syntax(String),
    /// An argument that is not a number; the whole attribute.
    #[error("bad number in transform \"{0}\"")]
    BadNumber(String),
    /// A name or argument count SVG does not define, e.g. `rotate(1 2)`;
    /// the transform in question.
    #[error("unsupported transform \"{0}\"")]
    Unsupported(String),
}

/// Affine map `(x, y) -> (a x + c y + e, b x + d y + f)`, SVG's order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Affine([f64; 6]);

impl Affine {
    /// The identity: no transform.
    pub(super) const ID: Affine = Affine([1.0, 0.0, 0.0, 1.0, 0.0, 0.0]);

    /// `self` then `o` applied first (SVG nesting: parent * child).
    pub(super) fn mul(self, o: Affine) -> Affine {
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

    /// The image of `p`.
    pub(super) fn apply(self, p: [f64; 2]) -> [f64; 2] {
        let [a, b, c, d, e, f] = self.0;
        [a * p[0] + c * p[1] + e, b * p[0] + d * p[1] + f]
    }

    /// Whether the map keeps circles circles: a uniform scale, a rotation,
    /// a translation and possibly a reflection (columns orthogonal and of
    /// equal length, to a relative `1e-9`).
    pub(super) fn is_similarity(self) -> bool {
        let [a, b, c, d, _, _] = self.0;
        let (p, q) = (a * a + b * b, c * c + d * d);
        let tol = 1e-9 * p.max(q);
        p > 0.0
            && p.is_finite()
            && q.is_finite()
            && (p - q).abs() <= tol
            && (a * c + b * d).abs() <= tol
    }

    /// Whether the map mirrors (negative determinant), which turns every
    /// arc the other way.
    pub(super) fn mirrors(self) -> bool {
        let [a, b, c, d, _, _] = self.0;
        a * d - b * c < 0.0
    }

    /// Largest stretch of the map, to keep chord errors within tolerance
    /// after scaling.
    pub(super) fn max_scale(self) -> f64 {
        let [a, b, c, d, _, _] = self.0;
        let s = a.hypot(b).max(c.hypot(d));
        if s.is_finite() && s > 0.0 {
            s
        } else {
            1.0
        }
    }
}

/// A `transform` attribute as one map (its transforms composed left to
/// right, as SVG applies them right to left).
pub(super) fn parse_transform(s: &str) -> Result<Affine, TransformError> {
    let mut m = Affine::ID;
    let mut rest = s.trim();
    while !rest.is_empty() {
        let open = rest
            .find('(')
            .ok_or_else(|| TransformError::Syntax(s.to_string()))?;
        let close = rest[open..]
            .find(')')
            .map(|c| c + open)
            .ok_or_else(|| TransformError::Syntax(s.to_string()))?;
        let name = rest[..open].trim().trim_start_matches(',').trim();
        let mut lx = Lexer::new(&rest[open + 1..close]);
        let mut args = Vec::new();
        while !lx.at_end() {
            args.push(
                lx.number()
                    .ok_or_else(|| TransformError::BadNumber(s.to_string()))?,
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
            _ => return Err(TransformError::Unsupported(rest[..=close].to_string())),
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
