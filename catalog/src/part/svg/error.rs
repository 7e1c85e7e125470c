//! Why an SVG file does not give a part: the reader's errors and the
//! wording of their messages.

use super::limits::{Exceeded, PrescanRefusal};
use super::path::PathError;
use super::transform::TransformError;
use crate::part::outline::{fmt, fmt_pt, OutlinePickError, P};

/// Why an SVG file does not give a part.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SvgError {
    /// The bytes are not UTF-8.
    #[error("not a readable SVG file: {0}")]
    NotUtf8(std::str::Utf8Error),
    /// Not well-formed XML; the parser's message says where.
    #[error("not a readable SVG file: {0}")]
    NotXml(roxmltree::Error),
    /// A bound on what a file may make the reader do (size, elements,
    /// attributes, entity expansion, nesting, path commands, vertices):
    /// what was counted and the bound.
    #[error("SVG file refused: more than {limit} {what}, the SVG reader's fixed limit (a guard against runaway and hostile files; it cannot be raised); simplify the drawing or split it into one file per part")]
    TooBig {
        /// What was counted, e.g. "elements in the file".
        what: &'static str,
        /// The bound.
        limit: usize,
    },
    /// An entity whose replacement text refers back to itself.
    #[error("SVG file refused: entity \"{0}\" refers to itself (directly or through others)")]
    EntityLoop(String),
    /// A reference to an entity declared as an external file or URL.
    #[error("SVG file refused: entity \"{name}\" is the external {kind} \"{uri}\": fixplan reads no file or URL but the part file itself; replace the reference with its text")]
    ExternalEntity {
        /// The entity's name.
        name: String,
        /// `SYSTEM` or `PUBLIC`.
        kind: &'static str,
        /// The file or URL it names.
        uri: String,
    },
    /// XML whose root element (named here) is not `<svg>`.
    #[error("not an SVG file: the root element is <{0}>")]
    NotSvg(String),
    /// A `width` or `height` with a `viewBox` that gives no scale.
    #[error("root <svg> has a viewBox that is not four numbers with a positive width and height")]
    BadViewBox,
    /// `preserveAspectRatio="none"` with a viewBox stretched unevenly:
    /// arcs would be ellipses and the drawing is not at one scale.
    #[error("root <svg> stretches its viewBox unevenly (preserveAspectRatio=\"none\": x by {sx}, y by {sy} mm per user unit); make width/height match the viewBox's proportions")]
    Stretched {
        /// Millimetres per user unit along x.
        sx: f64,
        /// Millimetres per user unit along y.
        sy: f64,
    },
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
    /// Open paths that do not join into a closed loop; points in SVG user
    /// units (after transforms), because that is what the file's author
    /// sees.
    #[error("open loop: {} runs from {} to {} in SVG user units and nothing else ends within {} of its ends to join it: {}", chain_name(*.pieces, .first), fmt_pt(*.from), fmt_pt(*.to), fmt(*.tolerance), why(*.nearest, *.gap, *.access))]
    OpenLoop {
        /// How many open paths the chain has.
        pieces: usize,
        /// Its first path, as messages name elements.
        first: String,
        /// One free end.
        from: [f64; 2],
        /// The other free end.
        to: [f64; 2],
        /// The join tolerance, user units.
        tolerance: f64,
        /// The nearest other free end (of another chain, or the chain's
        /// own other end) and its distance.
        nearest: Option<([f64; 2], f64)>,
        /// Whether that end is near enough, for the chain's size, to be a
        /// gap rather than an open line.
        gap: bool,
        /// Whether it is an access/keepout path.
        access: bool,
    },
    /// The shapes found do not make one part.
    #[error(transparent)]
    Outline(#[from] OutlinePickError),
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

/// The end of an open-loop message: a gap, or an open line.
pub(super) fn why(nearest: Option<(P, f64)>, gap: bool, access: bool) -> String {
    let what = if access {
        "access/keepout path"
    } else {
        "outline"
    };
    match (nearest, gap) {
        (Some((q, d)), true) => format!(
            "a gap of {} to the free end at {}; close the {what} in the drawing (snap the ends together, or end the path with Z)",
            fmt(d),
            fmt_pt(q)
        ),
        (Some((q, d)), false) => format!(
            "no gap: the nearest free end, at {}, is {} away, so this is an open line rather than part of a closed {what}; close it with Z if it is one, or delete it",
            fmt_pt(q),
            fmt(d)
        ),
        (None, _) => format!("an open line, not a closed {what}; close it with Z if it is one, or delete it"),
    }
}

/// "<path id=\"a\">", or "a chain of 3 open paths from <path id=\"a\">".
pub(super) fn chain_name(pieces: usize, first: &str) -> String {
    if pieces == 1 {
        first.to_string()
    } else {
        format!("a chain of {pieces} open paths from {first}")
    }
}

impl From<Exceeded> for SvgError {
    fn from(exceeded: Exceeded) -> Self {
        SvgError::TooBig {
            what: exceeded.what,
            limit: exceeded.limit,
        }
    }
}

impl From<PrescanRefusal> for SvgError {
    fn from(refusal: PrescanRefusal) -> Self {
        match refusal {
            PrescanRefusal::Exceeded(e) => e.into(),
            PrescanRefusal::EntityLoop(name) => SvgError::EntityLoop(name),
            PrescanRefusal::ExternalEntity { name, kind, uri } => {
                SvgError::ExternalEntity { name, kind, uri }
            }
        }
    }
}
