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
    /// Solving the part failed (a panic in the solver: a bug, not the
    /// input's fault); `error` says where. The run goes on.
    Failed,
    /// The part's estimated work is beyond the run's budget
    /// (`--part-budget`); `error` gives the estimate and the budget.
    OverBudget,
}

/// The per-part counts of SPEC section 4.
///
/// In top-k mode (`top_k > 0` without `full_counts`) only the candidates
/// that could enter the top-k get a mount search, so the admissible count
/// is not known: `exact` is false and `admissible` is 0 here and absent
/// from the JSON, which says `"counts_exact": false` instead. What is
/// known then: segments, combinations, setups and candidates are exact,
/// and the admissible count lies between the number of fixtures reported
/// and `candidates`. Nothing order-dependent is kept, so the result is the
/// same bytes however the work was split.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Counts {
    /// Usable segments of the part (SPEC 2).
    pub segments: u64,
    /// Segment combinations enumerated (SPEC 3).
    pub combinations: u64,
    /// Locator setups found (SPEC 3).
    pub setups: u64,
    /// Candidate fixtures: setup plus a clamp contact in form closure (SPEC 4).
    pub candidates: u64,
    /// Candidates with a clamp mount that passes every test (SPEC 4); 0
    /// when not `exact`.
    pub admissible: u64,
    /// Whether `admissible` was counted (full counts).
    pub exact: bool,
}

impl Default for Counts {
    fn default() -> Self {
        Counts {
            segments: 0,
            combinations: 0,
            setups: 0,
            candidates: 0,
            admissible: 0,
            exact: true,
        }
    }
}

impl Counts {
    /// Counts of disjoint pieces of one part's combination range add up;
    /// `segments` is a property of the part, not of the piece.
    pub fn add(&mut self, other: &Counts) {
        self.segments = self.segments.max(other.segments);
        self.combinations += other.combinations;
        self.setups += other.setups;
        self.candidates += other.candidates;
        self.admissible += other.admissible;
        self.exact &= other.exact;
    }

    /// The admissible count, when it was counted.
    pub fn admissible(&self) -> Option<u64> {
        self.exact.then_some(self.admissible)
    }
}

/// [`Counts`] as JSON shows them (results, MCAP messages): the full-count
/// form is the one SPEC Appendix A shows, unchanged; top-k mode leaves
/// `admissible` out and says so.
#[derive(Serialize, Deserialize, JsonSchema)]
#[serde(rename = "Counts")]
struct CountsJson {
    /// Usable segments of the part (SPEC 2).
    segments: u64,
    /// Segment combinations enumerated (SPEC 3).
    combinations: u64,
    /// Locator setups found (SPEC 3).
    setups: u64,
    /// Candidate fixtures: setup plus a clamp contact in form closure
    /// (SPEC 4).
    candidates: u64,
    /// Candidates with a clamp mount that passes every test (SPEC 4).
    /// Absent when `counts_exact` is false: the top-k mode searched mounts
    /// only for candidates that could enter the top-k, so all that is
    /// known is that it lies between the number of fixtures and
    /// `candidates`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    admissible: Option<u64>,
    /// False in top-k mode (`full_counts` off, `top_k > 0`), when
    /// `admissible` was not counted; absent (true) with full counts.
    #[serde(default = "yes", skip_serializing_if = "is_yes")]
    counts_exact: bool,
}

fn yes() -> bool {
    true
}

fn is_yes(b: &bool) -> bool {
    *b
}

/// [`Counts`] between processes (postcard): every field, always, since a
/// binary format cannot skip one.
#[derive(Serialize, Deserialize)]
struct CountsWire(u64, u64, u64, u64, u64, bool);

impl Serialize for Counts {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let c = *self;
        if s.is_human_readable() {
            CountsJson {
                segments: c.segments,
                combinations: c.combinations,
                setups: c.setups,
                candidates: c.candidates,
                admissible: c.admissible(),
                counts_exact: c.exact,
            }
            .serialize(s)
        } else {
            CountsWire(
                c.segments,
                c.combinations,
                c.setups,
                c.candidates,
                c.admissible,
                c.exact,
            )
            .serialize(s)
        }
    }
}

impl<'de> Deserialize<'de> for Counts {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        if d.is_human_readable() {
            let j = CountsJson::deserialize(d)?;
            Ok(Counts {
                segments: j.segments,
                combinations: j.combinations,
                setups: j.setups,
                candidates: j.candidates,
                admissible: j.admissible.filter(|_| j.counts_exact).unwrap_or(0),
                exact: j.counts_exact,
            })
        } else {
            let CountsWire(segments, combinations, setups, candidates, admissible, exact) =
                CountsWire::deserialize(d)?;
            Ok(Counts {
                segments,
                combinations,
                setups,
                candidates,
                admissible,
                exact,
            })
        }
    }
}

impl JsonSchema for Counts {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        CountsJson::schema_name()
    }

    fn json_schema(generator: &mut schemars::SchemaGenerator) -> schemars::Schema {
        CountsJson::json_schema(generator)
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
    /// The loop of every segment, in segment order (SPEC 9.6): 0 the
    /// outline, `k + 1` hole `k` of the input. Only parts with holes have
    /// it, so results of parts without holes keep their bytes.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub segment_loops: Vec<usize>,
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
            segment_loops: Vec::new(),
            fixtures: Vec::new(),
        }
    }

    /// [`SolveResult::invalid`] with another status: a part the run gave
    /// up on ([`Status::Failed`], [`Status::OverBudget`]), `message` saying
    /// why.
    pub fn gave_up(status: Status, message: impl Into<String>) -> SolveResult {
        SolveResult {
            status,
            ..SolveResult::invalid(message)
        }
    }
}
