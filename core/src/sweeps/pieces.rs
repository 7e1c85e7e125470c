//! The shapes the sweeps are made of: the pivot's line, the third segment
//! as chords, and the grown quadrilaterals that cover a region. Shared by
//! every kind of sweep; which one a segment gets is chosen in
//! [`super::SweptSegment::of`].

use crate::geometry::arc::GrownArc;
use crate::geometry::V2;
use crate::segments::{LineFeature, Segment};

/// Contact-parameter slack of the angle sets (lattice units). The pose
/// solver's contacts and the sinusoids here are the same quantities
/// computed two ways; near a tangent (double) root the solver snaps the
/// angle and its contacts move by up to about `EPS` over the determinant,
/// so the slack is far above both that and rounding.
pub(super) const S_SLACK: f64 = 1e-6;

/// Added to every quadrilateral's margin: covers rounding in the poses
/// (lattice units).
pub(super) const QUAD_SLACK: f64 = 1e-6;

/// A convex region of the plate: the hull of four points grown by `margin`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quad {
    /// Corners, any order.
    pub pts: [V2; 4],
    /// How far outside the hull points may still lie.
    pub margin: f64,
}

/// A segment on a grown line with its contact range.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LinePiece {
    pub(super) line: LineFeature,
    pub(super) s0: f64,
    pub(super) s1: f64,
    /// Angle of `u`.
    pub(super) direction: f64,
}

impl LinePiece {
    /// Segment `seg`, which lies on `line`.
    pub(super) fn of(seg: &Segment, line: LineFeature) -> LinePiece {
        LinePiece {
            line,
            s0: seg.s0,
            s1: seg.s1,
            direction: line.u.y.atan2(line.u.x),
        }
    }

    pub(super) fn point(&self, s: f64) -> V2 {
        self.line.origin + self.line.u * s
    }
}

/// Most chords an arc of segment `c` is cut into (a quarter of a quarter
/// turn each at most, for a whole circle).
pub(super) const MAX_CHORDS: usize = 8;

/// Segment `c` as a polyline within `margin` of it: itself for a line;
/// chords of at most an eighth of a turn for an arc, within their sagitta.
/// The sweep of a set grown by `margin` is the sweep grown by `margin`
/// (the motion is rigid), so chords serve arcs soundly.
#[derive(Debug, Clone, Copy)]
pub(super) struct ThirdPiece {
    pts: [V2; MAX_CHORDS + 1],
    chords: usize,
    pub(super) margin: f64,
    /// Whether the segment is an arc: its sweep is covered more finely
    /// (see `lines::ARC_THIRD_TARGET_MARGIN`).
    pub(super) curved: bool,
}

impl ThirdPiece {
    /// A line segment: itself, one chord.
    pub(super) fn straight(seg: &Segment) -> ThirdPiece {
        ThirdPiece::of_chords(seg, 1, 0.0, false)
    }

    /// A segment of `arc`: chords of at most an eighth of a turn, within
    /// their sagitta.
    pub(super) fn chords(seg: &Segment, arc: &GrownArc) -> ThirdPiece {
        let len = seg.s1 - seg.s0;
        let eighth = arc.radius * std::f64::consts::FRAC_PI_4;
        let count = ((len / eighth).ceil() as usize).clamp(1, MAX_CHORDS);
        let half_angle = len / count as f64 / arc.radius / 2.0;
        let sagitta = arc.radius * (1.0 - half_angle.cos()) + 1e-9;
        ThirdPiece::of_chords(seg, count, sagitta, true)
    }

    /// `chords` equal pieces of `seg` (by its parameter), `margin` from it.
    fn of_chords(seg: &Segment, chords: usize, margin: f64, curved: bool) -> ThirdPiece {
        let mut pts = [V2::zeros(); MAX_CHORDS + 1];
        for (j, p) in pts.iter_mut().enumerate().take(chords + 1) {
            let s = if j == chords {
                seg.s1
            } else {
                seg.s0 + (seg.s1 - seg.s0) * j as f64 / chords as f64
            };
            *p = seg.point(s);
        }
        ThirdPiece {
            pts,
            chords,
            margin,
            curved,
        }
    }

    /// How many chord points the segment has: 2 for a line.
    pub(super) fn point_count(&self) -> usize {
        self.chords + 1
    }

    /// Pushes the quadrilaterals of every chord between two placements of
    /// the chord points (slices of at least [`ThirdPiece::point_count`]).
    pub(super) fn push_quads(&self, from: &[V2], to: &[V2], margin: f64, out: &mut Vec<Quad>) {
        for j in 0..self.chords {
            out.push(Quad {
                pts: [from[j], from[j + 1], to[j], to[j + 1]],
                margin: margin + self.margin,
            });
        }
    }

    /// The chord points under `map`, into `out` (at least
    /// [`ThirdPiece::point_count`] long).
    #[inline]
    pub(super) fn map_into(&self, map: impl Fn(V2) -> V2, out: &mut [V2]) {
        for (o, p) in out.iter_mut().zip(&self.pts).take(self.chords + 1) {
            *o = map(*p);
        }
    }
}
