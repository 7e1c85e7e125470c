//! Where locator 3 can be once locators 1 and 2 touch their segments
//! (issue 15's pruning, SPEC 3 allows any pruning that keeps the set).
//!
//! Two segments of a combination are the pivot: with `L1` at the origin
//! on the first and `L2` on the second, the part has one degree of freedom
//! left, and over the angles at which both contacts stay on their
//! segments the third segment sweeps a region of the plate; `L3` must be a
//! lattice point of that region. Every sweep covers it by quadrilaterals
//! grown by a margin (`pieces`), whose lattice points are listed row by
//! row (`scan`); how the part moves depends on the kinds of the two pivot
//! segments, so each pair of kinds that pivots has its own file: `lines`
//! (two lines, the polygons' path: exact angle bands) and `line_arc` (a
//! line, then an arc).
//!
//! This file is the stage's dispatcher, as parry's query dispatcher is for
//! shapes: the one place that looks at a segment's feature
//! ([`SweptSegment::of`]) and at a pair's ([`PivotPair::of`], which also
//! says which pairs a combination prefers to pivot on). A new kind of
//! feature is one arm in each, and a file for each pair it pivots in.

mod line_arc;
mod lines;
mod pieces;
mod scan;
#[cfg(test)]
mod tests;

pub use line_arc::{ArcPoint, LineArcSweep};
pub use lines::{LineSweep, LinesPoint};
pub use pieces::Quad;
pub use scan::SweepScratch;

use crate::geometry::angle_set::AngleSet;
use crate::geometry::V2;
use crate::segments::{Feature, Segment};
use line_arc::ArcPiece;
use pieces::{LinePiece, ThirdPiece};
use scan::scan_quads;

/// What the sweep needs of one segment, worked out once per part: a
/// combination only borrows these, so choosing its pivot costs no trig
/// and no copy of the arc's chord points.
#[derive(Debug, Clone, Copy)]
pub struct SweptSegment {
    pivot: PivotPiece,
    third: ThirdPiece,
}

/// A segment as one of the two a sweep pivots on, by its feature.
#[derive(Debug, Clone, Copy)]
enum PivotPiece {
    /// A grown line.
    Line(LinePiece),
    /// A grown arc.
    Arc(ArcPiece),
    /// A feature no sweep pivots on (an arc of no radius): only swept.
    Unusable,
}

impl SweptSegment {
    /// The segment as a pivot and as a third segment: the stage's one
    /// choice by a single feature.
    pub fn of(seg: &Segment) -> SweptSegment {
        match &seg.feature {
            Feature::Line(line) => SweptSegment {
                pivot: PivotPiece::Line(LinePiece::of(seg, *line)),
                third: ThirdPiece::straight(seg),
            },
            Feature::Arc(arc) => SweptSegment {
                pivot: ArcPiece::of(seg, arc).map_or(PivotPiece::Unusable, PivotPiece::Arc),
                third: ThirdPiece::chords(seg, arc),
            },
        }
    }

    /// The segment's line, when it lies on one.
    fn as_line(&self) -> Option<&LinePiece> {
        match &self.pivot {
            PivotPiece::Line(line) => Some(line),
            _ => None,
        }
    }

    /// The segment as the sweep's third segment.
    fn third(&self) -> &ThirdPiece {
        &self.third
    }
}

/// Two segments a sweep pivots on, `L1` on the first and `L2` on the
/// second, by the kinds of their features.
#[derive(Debug, Clone, Copy)]
pub(crate) enum PivotPair<'s> {
    /// Two lines ([`LineSweep`]).
    Lines(&'s LinePiece, &'s LinePiece),
    /// A line, then an arc ([`LineArcSweep`]).
    LineArc(&'s LinePiece, &'s ArcPiece),
}

impl<'s> PivotPair<'s> {
    /// The stage's one choice by a pair of features: the pair `first`,
    /// `second` as a pivot, `None` when no sweep pivots on them in this
    /// order (an arc first, two arcs).
    pub(crate) fn of(first: &'s SweptSegment, second: &'s SweptSegment) -> Option<PivotPair<'s>> {
        match (&first.pivot, &second.pivot) {
            (PivotPiece::Line(a), PivotPiece::Line(b)) => Some(PivotPair::Lines(a, b)),
            (PivotPiece::Line(line), PivotPiece::Arc(arc)) => Some(PivotPair::LineArc(line, arc)),
            _ => None,
        }
    }

    /// Which kind of pair a combination pivots on when it has several
    /// (lowest first): two lines, whose angle bands are exact, before a
    /// line and an arc, so that an arc is only swept (chords), never
    /// solved for at every lattice point of its annuli, when it can be.
    pub(crate) fn preference(&self) -> u8 {
        match self {
            PivotPair::Lines(..) => 0,
            PivotPair::LineArc(..) => 1,
        }
    }

    /// Whether [`LocatorSweep::new`] refuses this pair whatever the third
    /// segment (nearly parallel lines), so the caller must take another
    /// pivot or the annuli.
    pub(crate) fn refused(&self) -> bool {
        match self {
            PivotPair::Lines(a, b) => lines::refuses(a, b),
            PivotPair::LineArc(..) => false,
        }
    }

    /// Whether the two segments play the same part, so that the pair in
    /// the other order finds the same setups and need not be tried.
    pub(crate) fn symmetric(&self) -> bool {
        matches!(self, PivotPair::Lines(..))
    }
}

/// The sweep of one combination, by the kind of its pivot: two lines
/// (exact angle sets, the common case) or a line and an arc.
#[derive(Debug, Clone, Copy)]
pub enum LocatorSweep<'s> {
    /// Pivot on two lines.
    Lines(LineSweep<'s>),
    /// Pivot on a line (locator 1) and an arc (locator 2).
    LineArc(LineArcSweep<'s>),
}

/// What the region of `L3` needs of `L2` beyond the third segment, by the
/// kind of sweep; shared by every combination with the same pivot pair.
#[derive(Debug, Clone)]
// The pivot cache keeps points by value in one vector: boxing the lines'
// points (the common kind, which carry their angles' trig) would cost an
// allocation per point.
#[allow(clippy::large_enum_variant)]
pub enum PivotPoint {
    /// See [`LinesPoint`].
    Lines(LinesPoint),
    /// See [`ArcPoint`] (boxed: more than twice the size of the other).
    LineArc(Box<ArcPoint>),
}

impl<'s> LocatorSweep<'s> {
    /// The sweep pivoting on `segs[0]` then `segs[1]` with `segs[2]` third;
    /// `None` when no sweep applies (`PivotPair::of`: an arc first, two
    /// arcs) or it refuses (nearly parallel lines). `dmax_ac` bounds the
    /// distance between points of `segs[0]` and `segs[2]`.
    pub fn new(
        segs: [&'s SweptSegment; 3],
        same_ab: bool,
        dmax_ac: f64,
    ) -> Option<LocatorSweep<'s>> {
        match PivotPair::of(segs[0], segs[1])? {
            PivotPair::Lines(a, b) => {
                let third = segs[2];
                LineSweep::new([a, b], third.third(), third.as_line(), same_ab, dmax_ac)
                    .map(LocatorSweep::Lines)
            }
            PivotPair::LineArc(line, arc) => Some(LocatorSweep::LineArc(LineArcSweep::new(
                line,
                arc,
                segs[2].third(),
                dmax_ac,
            ))),
        }
    }

    /// What the region needs of `L2 = l2`; `None` when no angle keeps both
    /// pivot contacts on their segments.
    pub fn pivot_point(&self, l2: V2) -> Option<PivotPoint> {
        match self {
            LocatorSweep::Lines(sweep) => sweep.pivot_point(l2).map(PivotPoint::Lines),
            LocatorSweep::LineArc(sweep) => sweep
                .pivot_point(l2)
                .map(|point| PivotPoint::LineArc(Box::new(point))),
        }
    }

    /// Calls `visit` once for every lattice point (multiples of `grid_step`) of the
    /// region of `L3` for the pivot point's `L2`, row by row, with (a
    /// superset of) the angles at which the pivot's contacts stay on their
    /// segments, for the pose solver to look only there; `false` (and no call)
    /// when the region needs too many pieces and the caller should scan
    /// the annuli instead.
    pub fn for_each_third_locator(
        &self,
        pt: &PivotPoint,
        grid_step: i64,
        scratch: &mut SweepScratch,
        mut visit: impl FnMut([i64; 2], Option<&AngleSet>),
    ) -> bool {
        let SweepScratch { quads, runs } = scratch;
        quads.clear();
        if !self.region(pt, quads) {
            return false;
        }
        let angles = pt.angles();
        scan_quads(quads, grid_step, runs, |l3| visit(l3, Some(angles)));
        true
    }

    /// The region of `L3` for a pivot point, as quadrilaterals grown by
    /// their margins pushed onto `out`; `false` when it needs too many
    /// pieces.
    pub fn region(&self, pt: &PivotPoint, out: &mut Vec<Quad>) -> bool {
        match (self, pt) {
            (LocatorSweep::Lines(sweep), PivotPoint::Lines(point)) => sweep.region(point, out),
            (LocatorSweep::LineArc(sweep), PivotPoint::LineArc(point)) => sweep.region(point, out),
            // A point of another kind of pivot: nothing is known, so the
            // caller scans the annuli (never happens: points are kept per
            // pivot pair, whose kind is fixed).
            _ => false,
        }
    }
}

impl PivotPoint {
    /// A superset of the angles that keep both pivot contacts on their
    /// segments, for the pose solver to look only there.
    fn angles(&self) -> &AngleSet {
        match self {
            PivotPoint::Lines(point) => &point.angles,
            PivotPoint::LineArc(point) => &point.angles,
        }
    }

    /// Whether the angle `theta` keeps both pivot contacts on their
    /// segments (up to the slack), for the soundness tests.
    #[cfg(test)]
    fn contains_angle(&self, theta: f64) -> bool {
        match self {
            PivotPoint::Lines(point) => point.angles.contains(theta),
            PivotPoint::LineArc(point) => point.contains_angle(theta),
        }
    }
}
