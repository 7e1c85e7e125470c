//! `transform` attributes: their parser into the readers' affine maps
//! ([`Affine`]).

use super::lexer::Lexer;
use crate::part::outline::Affine;

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

/// A `transform` attribute as one map (its transforms composed left to
/// right, as SVG applies them right to left).
pub(super) fn parse_transform(text: &str) -> Result<Affine, TransformError> {
    let mut m = Affine::ID;
    let mut rest = text.trim();
    while !rest.is_empty() {
        let open = rest
            .find('(')
            .ok_or_else(|| TransformError::Syntax(text.to_string()))?;
        let close = rest[open..]
            .find(')')
            .map(|c| c + open)
            .ok_or_else(|| TransformError::Syntax(text.to_string()))?;
        let name = rest[..open].trim().trim_start_matches(',').trim();
        let mut lx = Lexer::new(&rest[open + 1..close]);
        let mut args = Vec::new();
        while !lx.at_end() {
            args.push(
                lx.number()
                    .ok_or_else(|| TransformError::BadNumber(text.to_string()))?,
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
