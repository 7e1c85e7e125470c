//! The forms the results file gives the core values its messages carry
//! (kit, parameters, outline, counts, fixtures...), declared here and
//! converted from and to core's types: a field renamed or a doc comment
//! reworded in the core changes neither the file's messages nor their
//! schemas. Their JSON, field names and order, and doc comments (the
//! schemas' descriptions) are those core's types had when results files
//! were first written this way; `tests` pins them.
//!
//! A file is only ever read back by fixplan from what fixplan wrote, so
//! each form reads exactly the form it writes (a catalogue's or case's
//! looser input forms are the core's business).

#[cfg(doc)]
use fixplan_core::Counts;
use schemars::JsonSchema;
use serde::de::{self, SeqAccess, Visitor};
use serde::ser::SerializeTuple;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// Length unit of a catalogue or case. Only used for defaults and labels: the
/// numbers are never converted inside the core.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum UnitsForm {
    /// Millimetres: the default, and the unit SPEC's defaults are given in.
    Mm,
    /// Inches: SPEC's defaults are converted (edge trim 0.04 in).
    In,
}

/// Hole layout of the plate: decides which lattice points a locator may
/// take and which hole kinds a clamp's mount holes need.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum PatternForm {
    /// Every hole takes any module.
    Square,
    /// Checkerboard: `(i, j)` is a dowel hole when `i + j` is even, tapped
    /// otherwise; locators go in dowel holes only.
    Alternating,
}

/// The kind of hole a module needs on an alternating plate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum HoleKindForm {
    /// A hole with `i + j` even; locators and dowel pins go here.
    Dowel,
    /// A hole with `i + j` odd; clamp bolts go here.
    Tapped,
    /// Fits either kind (only meaningful on square plates, or for modules
    /// that do not care).
    Any,
}

/// A clamp mount hole, written `[i, j, kind]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct MountHoleForm(pub i64, pub i64, pub HoleKindForm);

impl JsonSchema for MountHoleForm {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "MountHole".into()
    }

    fn json_schema(generator: &mut schemars::SchemaGenerator) -> schemars::Schema {
        let kind = generator.subschema_for::<HoleKindForm>();
        schemars::json_schema!({
            "description": "A clamp mount hole: lattice offset (i, j) and hole kind",
            "type": "array",
            "prefixItems": [{"type": "integer"}, {"type": "integer"}, kind],
            "items": false,
            "minItems": 3,
            "maxItems": 3
        })
    }
}

/// The sliding clamp, in its own frame: origin at mount hole 0, `+x` the push
/// direction.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ClampForm {
    /// Holes it is bolted to; hole 0 must be `[0, 0]`, the frame's origin.
    pub mount_holes: Vec<MountHoleForm>,
    /// `y0`: the plunger axis is the line `y = y0`.
    pub axis_offset: f64,
    /// `[t_min, t_max]`: the plunger tip centre is at `(t, y0)` for `t` in
    /// this range; the mount search tries the shortest extension first.
    pub travel: [f64; 2],
    /// Space the clamp body takes (handle sweep included), which must keep
    /// `min_clearance` from the part, locators and access regions.
    pub body: Vec<[f64; 2]>,
    /// The plunger shaft at `t = 0` (tip circle excluded); it moves by
    /// `(t, 0)` with the extension.
    pub plunger: Vec<[f64; 2]>,
}

/// A modular fixture kit: plate, locators and clamp (SPEC section 1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct KitForm {
    /// Hole spacing `l`: the lattice unit everything is converted to.
    pub spacing: f64,
    /// Holes across; a fixture must fit on `cols x rows` holes.
    pub cols: u32,
    /// Holes down.
    pub rows: u32,
    /// Hole layout.
    pub pattern: PatternForm,
    /// Radius of the round locators and of the clamp tip; must stay below
    /// half the spacing (square) or `l sqrt(2) / 2` (alternating) so
    /// neighbouring locators fit.
    pub locator_radius: f64,
    /// The one clamp of the kit.
    pub clamp: ClampForm,
}

/// Enumeration parameters; `None` means SPEC's default for the unit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ParamsForm {
    /// Largest angle between the push direction and the inward contact
    /// normal, in `(0, 90]`; 90 is the complete, heuristic-free setting,
    /// smaller angles keep clamps that do not slip.
    #[serde(default = "default_angle")]
    pub max_clamp_angle_deg: f64,
    /// Shortens every usable segment at both ends, keeping contacts off
    /// corners that real parts round or chamfer.
    #[serde(default)]
    pub edge_trim: Option<f64>,
    /// Smallest gap between clamp body or plunger and the part, the
    /// locators or the access regions.
    #[serde(default)]
    pub min_clearance: Option<f64>,
    /// Locators 2 and 3 only at multiples of this from locator 1: a coarse
    /// step finds a subset of the fixtures, much faster.
    #[serde(default = "default_grid_step")]
    pub grid_step: u32,
    /// Fixtures kept per part, best first; 0 keeps all.
    #[serde(default = "default_top_k")]
    pub top_k: usize,
    /// Check every candidate so that the admissible count is exact. Off
    /// (the default), a part with `top_k > 0` checks the clamp mount only
    /// of candidates that could still enter its top-k: the same fixtures,
    /// several times faster on big parts, but the admissible count is
    /// then unknown (`counts_exact: false`). Ignored when `top_k` is 0.
    #[serde(default)]
    pub full_counts: bool,
    /// Expected wrenches `[F_x, F_y, tau]` (part frame, tau about its origin);
    /// `None` selects the default metric of SPEC section 6.
    #[serde(default)]
    pub wrenches: Option<Vec<[f64; 3]>>,
}

/// The defaults the schema states (the core's defaults when the file
/// format was fixed; a run always writes every field).
fn default_angle() -> f64 {
    45.0
}
fn default_grid_step() -> u32 {
    1
}
fn default_top_k() -> usize {
    10
}

/// An outline vertex, written `[x, y]` for a straight edge or
/// `[x, y, bulge]` for an arc.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VertexForm {
    /// x coordinate.
    pub x: f64,
    /// y coordinate.
    pub y: f64,
    /// Bulge of the edge from this vertex to the next (0: straight).
    pub bulge: f64,
}

impl Serialize for VertexForm {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let arc = self.bulge != 0.0;
        let mut t = s.serialize_tuple(if arc { 3 } else { 2 })?;
        t.serialize_element(&self.x)?;
        t.serialize_element(&self.y)?;
        if arc {
            t.serialize_element(&self.bulge)?;
        }
        t.end()
    }
}

impl<'de> Deserialize<'de> for VertexForm {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_seq(VertexVisitor)
    }
}

struct VertexVisitor;

impl<'de> Visitor<'de> for VertexVisitor {
    type Value = VertexForm;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a vertex [x, y] or [x, y, bulge]")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<VertexForm, A::Error> {
        let x = seq
            .next_element()?
            .ok_or_else(|| de::Error::invalid_length(0, &self))?;
        let y = seq
            .next_element()?
            .ok_or_else(|| de::Error::invalid_length(1, &self))?;
        let bulge = seq.next_element()?.unwrap_or(0.0);
        if seq.next_element::<de::IgnoredAny>()?.is_some() {
            return Err(de::Error::invalid_length(4, &self));
        }
        Ok(VertexForm { x, y, bulge })
    }
}

impl JsonSchema for VertexForm {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "Vertex".into()
    }

    fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        schemars::json_schema!({
            "description": "An outline vertex [x, y], or [x, y, bulge] when the edge to the next vertex is a circular arc of included angle 4 atan(bulge), counter-clockwise when positive",
            "type": "array",
            "items": {"type": "number"},
            "minItems": 2,
            "maxItems": 3
        })
    }
}

/// A part's outcome (SPEC section 7): `no_fixture` is a real answer about
/// the kit, `invalid` a problem with the input.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum StatusForm {
    /// At least one admissible fixture.
    Ok,
    /// A valid part that no fixture of this kit holds.
    NoFixture,
    /// The input cannot be enumerated; `error` says why and where.
    Invalid,
}

/// [`Counts`] as JSON shows them (results, MCAP messages): the full-count
/// form is the one SPEC Appendix A shows, unchanged; top-k mode leaves
/// `admissible` out and says so.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename = "Counts")]
pub struct CountsForm {
    /// Usable segments of the part (SPEC 2).
    pub segments: u64,
    /// Segment combinations enumerated (SPEC 3).
    pub combinations: u64,
    /// Locator setups found (SPEC 3).
    pub setups: u64,
    /// Candidate fixtures: setup plus a clamp contact in form closure
    /// (SPEC 4).
    pub candidates: u64,
    /// Candidates with a clamp mount that passes every test (SPEC 4).
    /// Absent when `counts_exact` is false: the top-k mode searched mounts
    /// only for candidates that could enter the top-k, so all that is
    /// known is that it lies between the number of fixtures and
    /// `candidates`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub admissible: Option<u64>,
    /// False in top-k mode (`full_counts` off, `top_k > 0`), when
    /// `admissible` was not counted; absent (true) with full counts.
    #[serde(default = "yes", skip_serializing_if = "is_yes")]
    pub counts_exact: bool,
}

fn yes() -> bool {
    true
}

fn is_yes(b: &bool) -> bool {
    *b
}

/// The kind of a segment, as results list it (SPEC 8.6).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum SegmentKindForm {
    /// On a straight part edge.
    Line,
    /// On a circular arc of the part.
    Arc,
}

/// The part's pose in the canonical plate frame, in the catalogue unit and
/// degrees so it can be read without knowing the lattice.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct PoseForm {
    /// Translation x.
    pub x: f64,
    /// Translation y.
    pub y: f64,
    /// Rotation, in `[0, 360)`.
    pub theta_deg: f64,
}

/// The clamp of a fixture (SPEC Appendix A).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ClampPlacedForm {
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
pub struct ContactForm {
    /// Centre of the locator or tip, catalogue unit.
    pub point: [f64; 2],
    /// Inward unit normal.
    pub normal: [f64; 2],
}

/// Where each module goes on the physical plate: `[column, row]` of holes,
/// hole `[0, 0]` being a dowel hole on an alternating plate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct PlacementForm {
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
pub struct FixtureForm {
    /// 1 for the best.
    pub rank: usize,
    /// The metric's value, lower is better.
    pub score: f64,
    /// Segments touched by locators 1-3.
    pub segments: [usize; 3],
    /// Locator lattice points, canonical frame (`L1 = [0, 0]`).
    pub locators: [[i64; 2]; 3],
    /// Where the part sits.
    pub pose: PoseForm,
    /// Where the clamp sits and pushes.
    pub clamp: ClampPlacedForm,
    /// Within `1e-6` of a decision boundary: implementations may disagree.
    pub borderline: bool,
    /// Locators 1-3 then the clamp.
    pub contacts: Vec<ContactForm>,
    /// Where the modules go on the physical plate.
    pub placement: PlacementForm,
}

/// One part's answer (SPEC Appendix A), what `fixplan solve` prints and a
/// catalogue run stores per part.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ResultForm {
    /// Outcome.
    pub status: StatusForm,
    /// Why the part is invalid.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// Counts; absent for an invalid part.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub counts: Option<CountsForm>,
    /// The kind of every segment, in segment order (SPEC 8.6), so that a
    /// fixture's segment indices say whether it touches lines or arcs;
    /// absent for an invalid part.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub segment_kinds: Vec<SegmentKindForm>,
    /// The top-k, best first.
    #[serde(default)]
    pub fixtures: Vec<FixtureForm>,
}

/// Wall-clock timings: the only fields of a results file that differ from
/// one run to the next.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
pub struct TimingForm {
    /// Validating and preparing the part.
    pub prepare_ms: f64,
    /// Enumerating its shards (all grid steps).
    pub enumerate_ms: f64,
    /// Shards it was cut into.
    pub shards: usize,
}

/// One grid step of a part (`/fixplan/part` field `refine`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct StepForm {
    /// The step: locators 2 and 3 at multiples of it from locator 1.
    pub grid_step: u32,
    /// SPEC counts at this step.
    pub counts: CountsForm,
    /// Fixtures kept (top-k) at this step.
    pub fixtures: usize,
    /// Score of the best fixture at this step.
    pub best_score: Option<f64>,
    /// The best fixture at this step.
    pub best: Option<FixtureForm>,
    /// Admissible fixtures this step added to the previous (coarser) one;
    /// `null` in top-k mode, which does not count them (`--full-counts`).
    pub added: Option<u64>,
    /// How much this step lowered the best score (previous best - this best;
    /// absent for the first step or when either step holds nothing).
    pub improved_by: Option<f64>,
    /// `--good-enough`: the combination index where this step stopped.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stopped_at: Option<u64>,
    /// Wall time of this step.
    pub enumerate_ms: f64,
}
