//! Open paths joined end to end, as the DXF reader joins LINE and ARC
//! entities: Inkscape and other tools often draw an outline as separate
//! open paths, `<line>`s or `<polyline>`s. What does not close is either
//! stray linework inside the part (ignored with a warning) or an error
//! that says where the ends are and whether they look like a gap.

use super::error::{chain_name, SvgError};
use crate::part::outline::OutlinePickError;
use crate::part::outline::{
    dist, fmt_pt, join_pieces, nearest_other_end, positions, OpenChain, Piece, P,
};
use crate::part::raw::RawPart;
use fixplan_core::Vertex;

/// A free end closer than this share of its chain's size to another free
/// end is called a gap; farther, the chain is an open line.
const GAP_SHARE: f64 = 0.1;

/// A chain that did not close, with its extent.
pub(super) struct Open {
    /// The error it makes, a [`SvgError::OpenLoop`].
    path: SvgError,
    /// Its first path and ends, for the warning when it is ignored.
    first: String,
    pieces: usize,
    ends: [P; 2],
    /// Bounding box, user units: min x, min y, max x, max y.
    bbox: [f64; 4],
}

fn bbox_of<'a>(pts: impl Iterator<Item = &'a Vertex>) -> [f64; 4] {
    pts.fold([f64::MAX, f64::MAX, f64::MIN, f64::MIN], |b, v| {
        [b[0].min(v.x), b[1].min(v.y), b[2].max(v.x), b[3].max(v.y)]
    })
}

/// The chains of `open` as [`Open`]s: each with the pieces' extent and
/// its nearest other free end.
fn describe_open(open: Vec<OpenChain>, pieces: &[Piece], tol: f64, access: bool) -> Vec<Open> {
    open.iter()
        .enumerate()
        .map(|(i, c)| {
            let bbox = bbox_of(
                pieces
                    .iter()
                    .filter(|p| c.labels.contains(&p.label))
                    .flat_map(|p| p.pts.iter()),
            );
            let size = (bbox[2] - bbox[0]).hypot(bbox[3] - bbox[1]);
            // The nearest free end to either end, as the DXF reader finds it
            // (the chain's own other end included when joining the two would
            // make a loop).
            let nearest = [c.start, c.end]
                .into_iter()
                .filter_map(|own| nearest_other_end(&open, i, own))
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .map(|(d, q, _)| (q, d));
            let gap = nearest.is_some_and(|(_, d)| d <= GAP_SHARE * size);
            let first = c.labels.first().cloned().unwrap_or_default();
            Open {
                path: SvgError::OpenLoop {
                    pieces: c.labels.len(),
                    first: first.clone(),
                    from: c.start,
                    to: c.end,
                    tolerance: tol,
                    nearest,
                    gap,
                    access,
                },
                first,
                pieces: c.labels.len(),
                ends: [c.start, c.end],
                bbox,
            }
        })
        .collect()
}

/// Joins the open pieces within `tol` (user units) into loops appended to
/// `loops` and `access`. Access pieces must all close; outline pieces
/// that do not are returned for [`settle_open`].
pub(super) fn join_into(
    loops: &mut Vec<(Vec<Vertex>, String)>,
    access: &mut Vec<Vec<P>>,
    pieces: Vec<Piece>,
    access_pieces: Vec<Piece>,
    tol: f64,
) -> Result<Vec<Open>, SvgError> {
    let pieces: Vec<Piece> = pieces.into_iter().filter(|p| !degenerate(p, tol)).collect();
    let access_pieces: Vec<Piece> = access_pieces
        .into_iter()
        .filter(|p| !degenerate(p, tol))
        .collect();
    let (joined, open) = join_pieces(access_pieces.clone(), tol);
    if let Some(o) = describe_open(open, &access_pieces, tol, true)
        .into_iter()
        .next()
    {
        return Err(o.path);
    }
    access.extend(joined.iter().map(|l| positions(l)));
    let (joined, open) = join_pieces(pieces.clone(), tol);
    for l in joined {
        // Named by the first piece that starts on it, as messages name
        // elements.
        let on_loop = |v: &Vertex| l.iter().any(|q| q.x == v.x && q.y == v.y);
        let first = pieces
            .iter()
            .find(|p| p.pts.first().is_some_and(on_loop))
            .map_or("", |p| p.label.as_str());
        loops.push((l.clone(), format!("open paths joined from {first}")));
    }
    Ok(describe_open(open, &pieces, tol, false))
}

/// A piece all of whose points are one point (`M 5 5 L 5 5`, a `<line>` of
/// length zero): nothing to draw or join.
fn degenerate(piece: &Piece, tol: f64) -> bool {
    piece.pts.first().is_none_or(|a| {
        piece
            .pts
            .iter()
            .all(|b| dist([a.x, a.y], [b.x, b.y]) <= tol)
    })
}

/// The outline picked from the closed loops, given the open chains left:
/// a chain within the outline's extent is linework inside the part (a
/// centre line, a hatch) and is ignored with a warning; any other chain,
/// or chains with no outline at all, is the error (the outline would be a
/// guess). `scale` maps user units to catalogue units as the loops were
/// mapped (y flipped).
pub(super) fn settle_open(
    picked: Result<RawPart, OutlinePickError>,
    open: Vec<Open>,
    scale: f64,
    tol: f64,
) -> Result<RawPart, SvgError> {
    let mut parts = settle_open_parts(picked.map(|raw| vec![raw]), open, scale, tol)?;
    parts
        .pop()
        .ok_or(SvgError::Outline(OutlinePickError::NoClosedLoop {
            only_access: false,
        }))
}

/// [`settle_open`] for a sheet: a chain is linework inside a part when it
/// lies within the extent of one of the parts, and is reported on that one.
pub(super) fn settle_open_parts(
    picked: Result<Vec<RawPart>, OutlinePickError>,
    open: Vec<Open>,
    scale: f64,
    tol: f64,
) -> Result<Vec<RawPart>, SvgError> {
    let Some(first) = open.first() else {
        return Ok(picked?);
    };
    let mut parts = match picked {
        Ok(parts) => parts,
        // The open chain is why there is no outline.
        Err(OutlinePickError::NoClosedLoop { .. }) => return Err(first.path.clone()),
        Err(e) => return Err(e.into()),
    };
    // Each outline's extent back in user units (y flipped back).
    let extents: Vec<[f64; 4]> = parts
        .iter()
        .map(|raw| {
            let user: Vec<Vertex> = raw
                .outline
                .iter()
                .map(|v| Vertex::new(v.x / scale, -v.y / scale, 0.0))
                .collect();
            bbox_of(user.iter())
        })
        .collect();
    for o in open {
        let b = o.bbox;
        let holder = extents.iter().position(|ob| {
            b[0] >= ob[0] - tol && b[1] >= ob[1] - tol && b[2] <= ob[2] + tol && b[3] <= ob[3] + tol
        });
        let Some(holder) = holder else {
            return Err(o.path);
        };
        let raw = &mut parts[holder];
        raw.warnings.push(format!(
            "{} from {} to {} (SVG user units) is open linework inside the outline, not a closed shape; ignored",
            chain_name(o.pieces, &o.first),
            fmt_pt(o.ends[0]),
            fmt_pt(o.ends[1])
        ));
    }
    Ok(parts)
}
