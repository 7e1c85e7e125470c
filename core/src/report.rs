//! The result format of SPEC Appendix A (plus the per-contact details and the
//! plate placement that section 5 asks for), in the catalogue's unit.

use crate::segments::SegmentKind;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// A part's outcome (SPEC section 7): `no_fixture` is a real answer about
/// the kit, `invalid` a problem with the input.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// At least one admissible fixture.
    Ok,
    /// A valid part that no fixture of this kit holds.
    NoFixture,
    /// The input cannot be enumerated; `error` says why and where.
    Invalid,
}

/// The per-part counts of SPEC section 4.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
pub struct Counts {
    /// Usable segments of the part (SPEC 2).
    pub segments: u64,
    /// Segment combinations enumerated (SPEC 3).
    pub combinations: u64,
    /// Locator setups found (SPEC 3).
    pub setups: u64,
    /// Candidate fixtures: setup plus a clamp contact in form closure (SPEC 4).
    pub candidates: u64,
    /// Candidates with a clamp mount that passes every test (SPEC 4).
    pub admissible: u64,
}

impl Counts {
    /// Counts of disjoint pieces of one part's combination range add up;
    /// `segments` is a property of the part, not of the piece.
    pub fn add(&mut self, o: &Counts) {
        self.segments = self.segments.max(o.segments);
        self.combinations += o.combinations;
        self.setups += o.setups;
        self.candidates += o.candidates;
        self.admissible += o.admissible;
    }
}

/// The part's pose in the canonical plate frame, in the catalogue unit and
/// degrees so it can be read without knowing the lattice.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct PoseReport {
    /// Translation x.
    pub x: f64,
    /// Translation y.
    pub y: f64,
    /// Rotation, in `[0, 360)`.
    pub theta_deg: f64,
}

/// The clamp of a fixture (SPEC Appendix A).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ClampReport {
    /// Segment the tip touches.
    pub segment: usize,
    /// Push direction: 0, 90, 180 or 270 degrees.
    pub rotation_deg: u32,
    /// Lattice point of mount hole 0, canonical frame.
    pub mount: [i64; 2],
    /// Plunger extension, catalogue unit.
    pub extension: f64,
    /// Tip centre, catalogue unit.
    pub contact: [f64; 2],
}

/// One contact: where the locator (or clamp tip) centre touches, and the
/// inward normal it pushes along, in the canonical plate frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ContactReport {
    /// Centre of the locator or tip, catalogue unit.
    pub point: [f64; 2],
    /// Inward unit normal.
    pub normal: [f64; 2],
}

/// Where each module goes on the physical plate: `[column, row]` of holes,
/// hole `[0, 0]` being a dowel hole on an alternating plate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct PlacementReport {
    /// Rotation applied to the canonical frame (0 or 90 degrees).
    pub rotation_deg: u32,
    /// Holes of locators 1-3.
    pub locators: [[i64; 2]; 3],
    /// Holes of the clamp's mount holes, in the kit's order.
    pub clamp_holes: Vec<[i64; 2]>,
}

/// One ranked fixture as reported (SPEC Appendix A, plus contacts and
/// placement): lattice indices stay integers, lengths are in the
/// catalogue unit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct FixtureReport {
    /// 1 for the best.
    pub rank: usize,
    /// The metric's value, lower is better.
    pub score: f64,
    /// Segments touched by locators 1-3.
    pub segments: [usize; 3],
    /// Locator lattice points, canonical frame (`L1 = [0, 0]`).
    pub locators: [[i64; 2]; 3],
    /// Where the part sits.
    pub pose: PoseReport,
    /// Where the clamp sits and pushes.
    pub clamp: ClampReport,
    /// Within `1e-6` of a decision boundary: implementations may disagree.
    pub borderline: bool,
    /// Locators 1-3 then the clamp.
    pub contacts: Vec<ContactReport>,
    /// Where the modules go on the physical plate.
    pub placement: PlacementReport,
}

/// One part's answer (SPEC Appendix A), what `fixplan solve` prints and a
/// catalogue run stores per part.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct SolveResult {
    /// Outcome.
    pub status: Status,
    /// Why the part is invalid.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// Counts; absent for an invalid part.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub counts: Option<Counts>,
    /// The kind of every segment, in segment order (SPEC 8.6), so that a
    /// fixture's segment indices say whether it touches lines or arcs;
    /// absent for an invalid part.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub segment_kinds: Vec<SegmentKind>,
    /// The top-k, best first.
    #[serde(default)]
    pub fixtures: Vec<FixtureReport>,
}

impl SolveResult {
    /// The outcome of a part that cannot be enumerated: no counts, no
    /// fixtures, so no consumer mistakes it for `no_fixture`.
    pub fn invalid(message: impl Into<String>) -> SolveResult {
        SolveResult {
            status: Status::Invalid,
            error: Some(message.into()),
            counts: None,
            segment_kinds: Vec::new(),
            fixtures: Vec::new(),
        }
    }
}
