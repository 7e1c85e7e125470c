//! What the clamp search's filters read of each segment, worked out once
//! per part (the prepared part holds the table): a setup then only adds
//! its pose's share.

use super::arc_reach::ArcReach;
use crate::geometry::{EPS, V2};
use crate::segments::{Feature, Segment};

/// What the clamp search's filters read of one segment, worked out once
/// per part so that a setup does not redo it.
#[derive(Debug, Clone, Copy)]
pub(crate) enum SegmentReach {
    /// A line: what its force cone test reads.
    Line(LineReach),
    /// An arc: its piece of the circle.
    Arc(ArcReach),
}

impl SegmentReach {
    /// The reach of a segment.
    pub(crate) fn of(seg: &Segment) -> SegmentReach {
        match &seg.feature {
            Feature::Line(line) => {
                let (s_lo, s_hi) = (seg.s0 + EPS, seg.s1 - EPS);
                SegmentReach::Line(LineReach {
                    n: line.n,
                    own: 1.5
                        * (line.origin.x.abs() + line.origin.y.abs() + s_lo.abs().max(s_hi.abs())),
                })
            }
            Feature::Arc(arc) => SegmentReach::Arc(ArcReach::on(seg, arc)),
        }
    }
}

/// What a setup's force cone test reads of a line segment, next to each
/// other so that the many lines the test drops cost a few loads.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LineReach {
    /// The line's outward normal (part frame), as the cone unposed takes it.
    pub(crate) n: V2,
    /// `1.5 (|origin|_1 + max(|s0 + eps|, |s1 - eps|))`, the part's share
    /// of the bound on its contacts' `|tau|` that the line candidates'
    /// search gives the force cone.
    pub(crate) own: f64,
}
