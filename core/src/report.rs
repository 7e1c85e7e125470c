//! The result format of SPEC Appendix A (plus the per-contact details and the
//! plate placement that section 5 asks for), in the catalogue's unit.

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    Ok,
    NoFixture,
    Invalid,
}

/// The per-part counts of SPEC section 4.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct Counts {
    pub segments: u64,
    pub combinations: u64,
    pub setups: u64,
    pub candidates: u64,
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

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PoseReport {
    pub x: f64,
    pub y: f64,
    pub theta_deg: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ClampReport {
    pub segment: usize,
    pub rotation_deg: u32,
    pub mount: [i64; 2],
    pub extension: f64,
    pub contact: [f64; 2],
}

/// One contact: where the locator (or clamp tip) centre touches, and the
/// inward normal it pushes along, in the canonical plate frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ContactReport {
    pub point: [f64; 2],
    pub normal: [f64; 2],
}

/// Where each module goes on the physical plate: `[column, row]` of holes,
/// hole `[0, 0]` being a dowel hole on an alternating plate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlacementReport {
    /// Rotation applied to the canonical frame (0 or 90 degrees).
    pub rotation_deg: u32,
    pub locators: [[i64; 2]; 3],
    pub clamp_holes: Vec<[i64; 2]>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FixtureReport {
    pub rank: usize,
    pub score: f64,
    pub segments: [usize; 3],
    pub locators: [[i64; 2]; 3],
    pub pose: PoseReport,
    pub clamp: ClampReport,
    pub borderline: bool,
    /// Locators 1-3 then the clamp.
    pub contacts: Vec<ContactReport>,
    pub placement: PlacementReport,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SolveResult {
    pub status: Status,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub counts: Option<Counts>,
    #[serde(default)]
    pub fixtures: Vec<FixtureReport>,
}

impl SolveResult {
    pub fn invalid(message: impl Into<String>) -> SolveResult {
        SolveResult {
            status: Status::Invalid,
            error: Some(message.into()),
            counts: None,
            fixtures: Vec::new(),
        }
    }
}
