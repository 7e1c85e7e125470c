//! The JSON messages of a results file, one type per MCAP channel, and
//! what a part's messages are made from ([`PartContent`]). Which channel
//! carries which message is [`super::channels`]; the JSON Schemas are
//! generated from these types ([`super::schemas`]); the layout is
//! documented in the README ("The results file (MCAP)").
//!
//! The messages are the file's own types, not core's: each is built by an
//! explicit conversion from the solved part ([`PartMessage::of`]) out of
//! the fields of [`super::fields`] and [`super::fixture_fields`], so a
//! rename in core changes neither a file nor the wire, and every schema
//! is one the viewers' JSON-schema parser reads.

use super::fields::{
    CountsField, HoleLoopField, KitField, ParamsField, PolygonField, SegmentKindName, StatusName,
    UnitsName, VertexField, WrenchField,
};
use super::fixture_fields::FixtureField;
pub use crate::job::SolveTiming;
use crate::job::{SearchInfo, StepSummary};
use fixplan_catalog::{Catalog, CatalogPart};
use fixplan_core::{Kit, Params, Point, SolveResult, Units, Vertex};
use schemars::JsonSchema;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::path::Path;

/// Channel of the run message, once at the start of a file.
pub const TOPIC_RUN: &str = "/fixplan/run";
/// Channel of the part messages, one per part in catalogue order.
pub const TOPIC_PART: &str = "/fixplan/part";
/// Channel of the ranked fixtures, one message per part.
pub const TOPIC_FIXTURES: &str = "/fixplan/fixtures";
/// Channel of the Foxglove scene of each part's best fixture.
pub const TOPIC_SCENE: &str = "/fixplan/scene";

/// Schema name of [`RunMsg`].
pub const SCHEMA_RUN: &str = "fixplan.Run";
/// Schema name of [`PartMsg`].
pub const SCHEMA_PART: &str = "fixplan.Part";
/// Schema name of [`FixturesMsg`].
pub const SCHEMA_FIXTURES: &str = "fixplan.Fixtures";
/// Foxglove recognises the scene only under this exact name.
pub const SCHEMA_SCENE: &str = "foxglove.SceneUpdate";

/// Name of the MCAP metadata record that repeats the run message's kit and
/// catalogue as strings, for tools that list a file's metadata.
pub const METADATA_RUN: &str = "fixplan.run";

/// Nanoseconds of log time per part: part `i` is logged at `i` seconds, so
/// Foxglove's timeline steps through the catalogue one part per second.
pub const NS_PER_PART: u64 = 1_000_000_000;

/// A JSON message of a results file: the topic of its channel and the
/// name of the schema generated from it.
pub trait Message: Serialize + DeserializeOwned + JsonSchema {
    /// Its channel.
    const TOPIC: &'static str;
    /// Its schema's name (and title).
    const SCHEMA: &'static str;
}

/// A JSON message each part has one of, made from the solved part.
pub trait PartMessage: Message {
    /// The message of `part`.
    fn of(part: &PartContent) -> Self;
}

/// Everything a part's messages are made from: its place and entry in
/// the catalogue, the run's unit and kit, the outline and access regions
/// as read, and what solving it found.
#[derive(Clone, Copy)]
pub struct PartContent<'a> {
    /// Position in the catalogue: the messages' log time and sequence.
    pub index: usize,
    /// The catalogue entry.
    pub entry: &'a CatalogPart,
    /// The catalogue's unit.
    pub units: Units,
    /// The run's kit.
    pub kit: &'a Kit,
    /// The outline (as read, for an invalid part; empty if nothing was).
    pub outline: &'a [Vertex],
    /// Its holes (SPEC 9), as the outline.
    pub holes: &'a [Vec<Vertex>],
    /// Access regions.
    pub access: &'a [Vec<Point>],
    /// The part's result.
    pub result: &'a SolveResult,
    /// How long it took.
    pub timing: SolveTiming,
    /// `--grid-steps` summaries and the `--good-enough` stop.
    pub search: &'a SearchInfo,
}

/// `/fixplan/run`: what was run, once at the start of the file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RunMsg {
    /// `fixplan`.
    pub tool: String,
    /// The fixplan version that wrote the file: a resumed run must be the
    /// same version.
    pub version: String,
    /// The catalogue, with a digest of its content.
    pub catalog: CatalogInfo,
    /// The kit's name (built-in) or file.
    pub kit_name: String,
    /// The kit, in the catalogue's unit.
    pub kit: KitField,
    /// Parameters of the run (the kit's, with `--top-k` applied); a part's
    /// own `top_k` / `wrenches` in the catalogue override them.
    pub params: ParamsField,
    /// `--grid-steps` (coarse to fine; `params.grid_step` is the finest).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grid_steps: Option<Vec<u32>>,
    /// `--good-enough` threshold.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub good_enough: Option<f64>,
    /// The per-part budgets: which parts are `over_budget` depends on
    /// them, so a run resumed with other budgets is another run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub budgets: Option<BudgetsField>,
}

/// A run of the built-in `metric-25` kit with default parameters over an
/// in-memory catalogue, for tests that need a run message and no files.
#[cfg(test)]
pub(crate) fn test_run_msg(catalog_name: &str, parts: usize, digest: &str) -> RunMsg {
    let (kit, _) = fixplan_catalog::kit::builtin_kit("metric-25").unwrap();
    RunMsg {
        tool: "fixplan".into(),
        version: "test".into(),
        catalog: CatalogInfo {
            name: catalog_name.into(),
            source: "mem".into(),
            units: UnitsName::Mm,
            parts,
            digest: digest.into(),
        },
        kit_name: "metric-25".into(),
        kit: (&kit).into(),
        params: (&Params::default()).into(),
        grid_steps: None,
        good_enough: None,
        budgets: None,
    }
}

/// The budgets of a run (`/fixplan/run` field `budgets`); absent ones
/// are not limited.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BudgetsField {
    /// `--part-budget`: segment combinations x segments.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cost: Option<u64>,
    /// `--part-setups`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub setups: Option<u64>,
    /// `--part-fixtures`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fixtures: Option<u64>,
    /// `--part-seconds` (wall clock).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seconds: Option<f64>,
}

impl BudgetsField {
    /// The budgets of a search, `None` when there is none.
    pub fn of(search: &crate::job::SearchOptions) -> Option<BudgetsField> {
        let b = BudgetsField {
            cost: search.part_budget,
            setups: search.part_setups,
            fixtures: search.part_fixtures,
            seconds: search.part_seconds,
        };
        let any = b.cost.is_some() || b.setups.is_some() || b.fixtures.is_some();
        (any || b.seconds.is_some()).then_some(b)
    }
}

/// The catalogue a run or study read: enough to tell two runs apart.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CatalogInfo {
    /// The manifest's name (or the directory's).
    pub name: String,
    /// Where it was read from, as given on the command line.
    pub source: String,
    /// The catalogue's unit: every length of the file is in it.
    pub units: UnitsName,
    /// Parts in the catalogue, valid or not.
    pub parts: usize,
    /// `sha256:` of the catalogue content (ids, outlines, access, overrides).
    pub digest: String,
}

impl CatalogInfo {
    /// What the run and study channels say of `catalog`, read from `source`.
    pub fn of(catalog: &Catalog, source: &Path) -> CatalogInfo {
        CatalogInfo {
            name: catalog.name.clone(),
            source: source.display().to_string(),
            units: catalog.units.into(),
            parts: catalog.parts.len(),
            digest: catalog_digest(catalog),
        }
    }
}

/// `sha256:` of the catalogue's content, independent of where it lives:
/// what tells `--resume` that a file was written from the same parts.
/// Each entry is hashed as one JSON line of the file's own field types
/// (so a rename in core leaves it alone), written into a reused buffer.
pub fn catalog_digest(catalog: &Catalog) -> String {
    /// A part's geometry as hashed; `holes` absent when there are none,
    /// so a file of parts without holes written before holes resumes.
    #[derive(Serialize)]
    struct HashedShape {
        outline: Vec<VertexField>,
        #[serde(skip_serializing_if = "Vec::is_empty")]
        holes: Vec<HoleLoopField>,
        access: Vec<PolygonField>,
    }
    /// One catalogue entry as hashed.
    #[derive(Serialize)]
    struct Entry<'a> {
        id: &'a str,
        part: Result<HashedShape, String>,
        quantity: f64,
        top_k: Option<usize>,
        wrenches: Option<Vec<WrenchField>>,
    }
    let mut h = Sha256::new();
    h.update(format!("units={}\n", UnitsName::from(catalog.units).text()));
    let mut line = Vec::with_capacity(4096);
    for p in &catalog.parts {
        let entry = Entry {
            id: &p.id,
            part: match &p.part {
                Ok(part) => Ok(HashedShape {
                    outline: part.outline.iter().map(VertexField::from).collect(),
                    holes: part.holes.iter().map(HoleLoopField::from).collect(),
                    access: part.access.iter().map(PolygonField::from).collect(),
                }),
                Err(e) => Err(e.to_string()),
            },
            quantity: p.quantity,
            top_k: p.top_k,
            wrenches: p
                .wrenches
                .as_ref()
                .map(|ws| ws.iter().map(WrenchField::from).collect()),
        };
        // Writing into a hash cannot fail; a part that cannot be written
        // as JSON (never) is hashed by its error.
        line.clear();
        if let Err(e) = serde_json::to_writer(&mut line, &entry) {
            line.clear();
            line.extend_from_slice(e.to_string().as_bytes());
        }
        line.push(b'\n');
        h.update(&line);
    }
    let d = h.finalize();
    let hex: String = d.iter().map(|b| format!("{b:02x}")).collect();
    format!("sha256:{hex}")
}

impl Message for RunMsg {
    const TOPIC: &'static str = TOPIC_RUN;
    const SCHEMA: &'static str = SCHEMA_RUN;
}

impl RunMsg {
    /// Whether a file written by `other` can be continued by this run:
    /// everything equal except where the catalogue was read from.
    pub fn same_run(&self, other: &RunMsg) -> bool {
        let mut a = other.clone();
        a.catalog.source = self.catalog.source.clone();
        &a == self
    }

    /// The run's kit, as core takes it.
    pub fn kit(&self) -> Kit {
        Kit::from(&self.kit)
    }

    /// The run's parameters, as core takes them.
    pub fn params(&self) -> Params {
        Params::from(&self.params)
    }

    /// The catalogue's unit.
    pub fn units(&self) -> Units {
        self.catalog.units.into()
    }
}

/// Wall-clock timings: the only fields that differ between runs.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TimingField {
    /// Validating and preparing the part, milliseconds.
    pub prepare_ms: f64,
    /// Enumerating its shards (all grid steps), milliseconds.
    pub enumerate_ms: f64,
    /// Shards it was cut into.
    pub shards: usize,
}

impl From<&SolveTiming> for TimingField {
    fn from(timing: &SolveTiming) -> TimingField {
        TimingField {
            prepare_ms: timing.prepare_ms,
            enumerate_ms: timing.enumerate_ms,
            shards: timing.shards,
        }
    }
}

/// One grid step of a `--grid-steps` part.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StepField {
    /// The step: locators 2 and 3 at multiples of it from locator 1.
    pub grid_step: u32,
    /// What the enumeration went through at this step.
    pub counts: CountsField,
    /// Fixtures kept (top-k) at this step.
    pub fixtures: usize,
    /// Score of the best fixture at this step.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub best_score: Option<f64>,
    /// The best fixture at this step.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub best: Option<FixtureField>,
    /// Admissible fixtures this step added to the previous one; absent in
    /// top-k mode, which does not count them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub added: Option<u64>,
    /// How much this step lowered the best score; absent for the first
    /// step or when either step holds nothing.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub improved_by: Option<f64>,
    /// `--good-enough`: the combination index where this step stopped.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stopped_at: Option<u64>,
    /// Wall time of this step, milliseconds.
    pub enumerate_ms: f64,
}

impl From<&StepSummary> for StepField {
    fn from(summary: &StepSummary) -> StepField {
        StepField {
            grid_step: summary.grid_step,
            counts: CountsField::from(&summary.counts),
            fixtures: summary.fixtures,
            best_score: summary.best_score,
            best: summary.best.as_ref().map(FixtureField::from),
            added: summary.added,
            improved_by: summary.improved_by,
            stopped_at: summary.stopped_at,
            enumerate_ms: summary.enumerate_ms,
        }
    }
}

/// `/fixplan/part`: one per part, in catalogue order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PartMsg {
    /// Position in the catalogue (0-based).
    pub index: usize,
    /// Catalogue id.
    pub id: String,
    /// The part's file, if it has one (inline outlines have none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// `ok`, `no_fixture` or `invalid`.
    pub status: StatusName,
    /// Why the part is invalid, naming the part and the place.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// Repairs made while reading the part.
    #[serde(default)]
    pub warnings: Vec<String>,
    /// The catalogue's unit.
    pub units: UnitsName,
    /// Parts per year, for kit studies.
    pub quantity: f64,
    /// Part frame, catalogue units, as given (empty if it could not be read).
    pub outline: Vec<VertexField>,
    /// Holes cut through the part (SPEC 9), as given, in order (hole `k`
    /// is the `k`-th); absent for a part without holes.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub holes: Vec<HoleLoopField>,
    /// Access regions (part frame, catalogue units).
    #[serde(default)]
    pub access: Vec<PolygonField>,
    /// What the enumeration went through; absent for an invalid part.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub counts: Option<CountsField>,
    /// Fixtures kept in the ranking (top-k).
    pub fixtures: usize,
    /// Score of the best fixture (lower is better); absent without one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub best_score: Option<f64>,
    /// Wall-clock timings (the only fields that differ between runs).
    pub timing: TimingField,
    /// `--grid-steps`: one summary per grid step, coarse to fine (counts,
    /// best fixture, what the step added). Absent in plain runs.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refine: Option<Vec<StepField>>,
    /// `"good_enough"` when `--good-enough` stopped the part early.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stopped: Option<String>,
    /// The combination index where it stopped (combinations `0..=index`
    /// were enumerated).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stopped_at: Option<u64>,
}

/// `PartMsg::stopped` of a part stopped by `--good-enough`.
pub const STOPPED_GOOD_ENOUGH: &str = "good_enough";

impl Message for PartMsg {
    const TOPIC: &'static str = TOPIC_PART;
    const SCHEMA: &'static str = SCHEMA_PART;
}

impl PartMessage for PartMsg {
    fn of(content: &PartContent) -> PartMsg {
        let (result, search) = (content.result, content.search);
        PartMsg {
            index: content.index,
            id: content.entry.id.clone(),
            file: content.entry.file.as_ref().map(|f| f.display().to_string()),
            status: result.status.into(),
            error: result.error.clone(),
            warnings: content.entry.warnings.clone(),
            units: content.units.into(),
            quantity: content.entry.quantity,
            outline: content.outline.iter().map(VertexField::from).collect(),
            holes: content.holes.iter().map(HoleLoopField::from).collect(),
            access: content.access.iter().map(PolygonField::from).collect(),
            counts: result.counts.as_ref().map(CountsField::from),
            fixtures: result.fixtures.len(),
            best_score: result.fixtures.first().map(|f| f.score),
            timing: TimingField::from(&content.timing),
            refine: (search.steps.as_ref()).map(|s| s.iter().map(StepField::from).collect()),
            stopped: search.stopped_at.map(|_| STOPPED_GOOD_ENOUGH.to_string()),
            stopped_at: search.stopped_at,
        }
    }
}

impl PartMsg {
    /// The outline, as core takes it.
    pub fn outline(&self) -> Vec<Vertex> {
        self.outline.iter().map(Vertex::from).collect()
    }

    /// The holes, as core takes them.
    pub fn holes(&self) -> Vec<Vec<Vertex>> {
        self.holes.iter().map(Vec::from).collect()
    }

    /// The access regions, as core takes them.
    pub fn access(&self) -> Vec<Vec<Point>> {
        let region = |r: &PolygonField| r.points.iter().map(Point::from).collect();
        self.access.iter().map(region).collect()
    }

    /// The catalogue's unit.
    pub fn units(&self) -> Units {
        self.units.into()
    }
}

/// `/fixplan/fixtures`: the part's status, counts and ranked fixtures
/// (with contacts and plate placement per fixture). `fixplan export
/// --json` turns it back into SPEC Appendix A's result format
/// ([`FixturesMsg::export_line`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FixturesMsg {
    /// Catalogue id of the part.
    pub part: String,
    /// Outcome.
    pub status: StatusName,
    /// Why the part is invalid.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// Counts; absent for an invalid part.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub counts: Option<CountsField>,
    /// The kind of every segment, in segment order, so that a fixture's
    /// segment indices say whether it touches lines or arcs; empty for an
    /// invalid part.
    #[serde(default)]
    pub segment_kinds: Vec<SegmentKindName>,
    /// The loop of every segment, in segment order (SPEC 9.6): 0 the
    /// outline, `k + 1` hole `k`; absent for a part without holes, whose
    /// message keeps its bytes.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub segment_loops: Vec<usize>,
    /// The top-k, best first.
    #[serde(default)]
    pub fixtures: Vec<FixtureField>,
}

impl Message for FixturesMsg {
    const TOPIC: &'static str = TOPIC_FIXTURES;
    const SCHEMA: &'static str = SCHEMA_FIXTURES;
}

impl PartMessage for FixturesMsg {
    fn of(content: &PartContent) -> FixturesMsg {
        FixturesMsg::of_result(&content.entry.id, content.result)
    }
}

/// One line of `fixplan export --json`: `{"part": ID, ...}` then the
/// result in SPEC Appendix A's format, which is core's.
#[derive(Serialize)]
struct ExportLine<'a> {
    part: &'a str,
    #[serde(flatten)]
    result: &'a SolveResult,
}

impl FixturesMsg {
    /// The message of part `id`'s result.
    pub fn of_result(id: &str, result: &SolveResult) -> FixturesMsg {
        FixturesMsg {
            part: id.to_string(),
            status: result.status.into(),
            error: result.error.clone(),
            counts: result.counts.as_ref().map(CountsField::from),
            segment_kinds: result.segment_kinds.iter().map(|&k| k.into()).collect(),
            segment_loops: result.segment_loops.clone(),
            fixtures: result.fixtures.iter().map(FixtureField::from).collect(),
        }
    }

    /// The result, as core makes it.
    pub fn result(&self) -> SolveResult {
        SolveResult {
            status: self.status.into(),
            error: self.error.clone(),
            counts: self.counts.as_ref().map(Into::into),
            segment_kinds: self.segment_kinds.iter().map(|&k| k.into()).collect(),
            segment_loops: self.segment_loops.clone(),
            fixtures: self.fixtures.iter().map(Into::into).collect(),
        }
    }

    /// The part's line of `fixplan export --json` (without the newline):
    /// SPEC Appendix A's result, `{"part": ID, "status": ...}`.
    pub fn export_line(&self) -> serde_json::Result<Vec<u8>> {
        serde_json::to_vec(&ExportLine {
            part: &self.part,
            result: &self.result(),
        })
    }
}

/// The JSON of each message, pinned from literals: field names, order and
/// forms are the file format, which nothing outside this module may move.
/// Each message is made from core's types by its conversion, as a run
/// makes it, and converted back where a reader needs core's types.
#[cfg(test)]
mod tests {
    use super::*;
    use crate::job::StepSummary;
    use fixplan_core::{
        Clamp, ClampReport, ContactReport, Counts, FixtureReport, HoleKind, MountHole, Part,
        Pattern, PlacementReport, PoseReport, SegmentKind, Status,
    };

    fn json<T: Serialize>(message: &T) -> String {
        serde_json::to_string(message).expect("json")
    }

    /// Exact counts of a small part, as a full enumeration gives them.
    fn exact_counts() -> Counts {
        Counts {
            segments: 3,
            combinations: 10,
            setups: 4,
            candidates: 2,
            admissible: 1,
            exact: true,
        }
    }

    fn kit() -> Kit {
        Kit {
            spacing: 25.0,
            cols: 4,
            rows: 3,
            pattern: Pattern::Alternating,
            locator_radius: 5.5,
            clamp: Clamp {
                mount_holes: vec![
                    MountHole {
                        offset: [0, 0],
                        kind: HoleKind::Any,
                    },
                    MountHole {
                        offset: [1, 0],
                        kind: HoleKind::Tapped,
                    },
                ],
                axis_offset: 1.5,
                travel: [2.0, 9.25],
                body: vec![[0.0, 0.0], [1.0, 0.5]],
                plunger: vec![[0.0, -0.5]],
            },
        }
    }

    fn fixture() -> FixtureReport {
        FixtureReport {
            rank: 1,
            score: 0.25,
            segments: [0, 1, 2],
            locators: [[0, 0], [2, 0], [0, 1]],
            pose: PoseReport {
                x: 1.0,
                y: 2.0,
                theta_deg: 90.0,
            },
            clamp: ClampReport {
                segment: 1,
                rotation_deg: 180,
                mount: [3, 1],
                extension: 4.5,
                contact: [5.0, 6.0],
            },
            borderline: false,
            contacts: vec![ContactReport {
                point: [1.0, 0.0],
                normal: [0.0, 1.0],
            }],
            placement: PlacementReport {
                rotation_deg: 90,
                locators: [[1, 1], [3, 1], [1, 2]],
                clamp_holes: vec![[4, 2], [5, 2]],
            },
        }
    }

    /// A score that overflowed is written `null` (JSON has no infinity)
    /// and read back as the infinity it was, as `--full-counts --top-k 0`
    /// keeps such fixtures (the sample catalogue's part #25 has some).
    #[test]
    fn an_infinite_score_is_read_back() {
        let mut f = fixture();
        f.score = f64::INFINITY;
        let result = SolveResult {
            status: Status::Ok,
            error: None,
            counts: Some(exact_counts()),
            segment_kinds: vec![SegmentKind::Line],
            segment_loops: Vec::new(),
            fixtures: vec![fixture(), f],
        };
        let written = FixturesMsg::of_result("p", &result);
        let text = json(&written);
        assert!(text.contains("\"score\":null"), "{text}");
        let read = serde_json::from_slice::<FixturesMsg>(text.as_bytes()).unwrap();
        assert_eq!(read.result(), result);
    }

    /// Numbers of 17 significant digits, which serde_json's parse without
    /// `float_roundtrip` (the workspace turns it on) misses by an ulp
    /// (54.286548683761524 is one), come back as the f64s written: export
    /// gives back core's bytes.
    #[test]
    fn fixtures_are_read_back_exactly() {
        let mut f = fixture();
        f.clamp.contact = [54.286548683761524, 92.99240966070201];
        f.score = 1.1407774087193523;
        f.pose.x = -55.54457980741133;
        f.contacts[0].normal = [0.6328716297238466, 0.774256740552307];
        let result = SolveResult {
            status: Status::Ok,
            error: Some("\u{e9}\"\\\n".into()),
            counts: Some(exact_counts()),
            segment_kinds: vec![SegmentKind::Arc],
            segment_loops: Vec::new(),
            fixtures: vec![f],
        };
        let written = FixturesMsg::of_result("p\u{1f600}", &result);
        let read = serde_json::from_slice::<FixturesMsg>(json(&written).as_bytes()).unwrap();
        assert_eq!(read, written);
        assert_eq!(read.result(), result);
        let line = read.export_line().unwrap();
        let core = serde_json::to_vec(&ExportLine {
            part: "p\u{1f600}",
            result: &result,
        })
        .unwrap();
        assert_eq!(
            String::from_utf8(line).unwrap(),
            String::from_utf8(core).unwrap()
        );
    }

    #[test]
    fn the_run_message_keeps_its_json() {
        let params = Params {
            max_clamp_angle_deg: 45.0,
            edge_trim: Some(0.5),
            min_clearance: None,
            grid_step: 2,
            top_k: 10,
            full_counts: false,
            wrenches: Some(vec![[1.0, 0.0, -2.0]]),
        };
        let run = RunMsg {
            tool: "fixplan".into(),
            version: "0.0.0".into(),
            catalog: CatalogInfo {
                name: "cat".into(),
                source: "dir".into(),
                units: Units::In.into(),
                parts: 2,
                digest: "sha256:00".into(),
            },
            kit_name: "kit".into(),
            kit: (&kit()).into(),
            params: (&params).into(),
            grid_steps: Some(vec![4, 2]),
            good_enough: None,
            budgets: None,
        };
        assert_eq!(
            json(&run),
            r#"{"tool":"fixplan","version":"0.0.0","catalog":{"name":"cat","source":"dir","units":"in","parts":2,"digest":"sha256:00"},"kit_name":"kit","kit":{"spacing":25.0,"cols":4,"rows":3,"pattern":"alternating","locator_radius":5.5,"clamp":{"mount_holes":[{"i":0,"j":0,"kind":"any"},{"i":1,"j":0,"kind":"tapped"}],"axis_offset":1.5,"travel":{"min":2.0,"max":9.25},"body":[{"x":0.0,"y":0.0},{"x":1.0,"y":0.5}],"plunger":[{"x":0.0,"y":-0.5}]}},"params":{"max_clamp_angle_deg":45.0,"edge_trim":0.5,"grid_step":2,"top_k":10,"full_counts":false,"wrenches":[{"force_x":1.0,"force_y":0.0,"torque":-2.0}]},"grid_steps":[4,2]}"#
        );
        assert_eq!(
            (run.kit(), run.params(), run.units()),
            (kit(), params, Units::In)
        );
        let read: RunMsg = serde_json::from_str(&json(&run)).unwrap();
        assert_eq!(read, run);
    }

    #[test]
    fn the_part_message_keeps_its_json() {
        let outline = vec![
            Vertex::new(0.0, 0.0, 0.0),
            Vertex::new(10.0, 0.0, 0.5),
            Vertex::new(0.0, 5.0, 0.0),
        ];
        let access = vec![vec![[1.0, 1.0], [2.0, 1.0], [1.0, 2.0]]];
        let entry = CatalogPart {
            id: "p".into(),
            file: Some("p.dxf".into()),
            part: Ok(Part {
                outline: outline.clone(),
                holes: Vec::new(),
                access: access.clone(),
            }),
            warnings: vec!["w".into()],
            quantity: 2.5,
            top_k: None,
            wrenches: None,
        };
        let mut counts = exact_counts();
        (counts.admissible, counts.exact) = (0, false);
        let result = SolveResult {
            status: Status::Ok,
            error: None,
            counts: Some(counts),
            segment_kinds: vec![SegmentKind::Line; 3],
            segment_loops: Vec::new(),
            fixtures: vec![fixture()],
        };
        let search = SearchInfo {
            steps: Some(vec![StepSummary {
                grid_step: 2,
                counts: exact_counts(),
                fixtures: 1,
                best_score: Some(0.25),
                best: None,
                added: Some(1),
                improved_by: None,
                stopped_at: None,
                enumerate_ms: 1.0,
            }]),
            stopped_at: Some(7),
            shards: 2,
        };
        let kit = kit();
        let content = PartContent {
            index: 3,
            entry: &entry,
            units: Units::Mm,
            kit: &kit,
            outline: &outline,
            holes: &[],
            access: &access,
            result: &result,
            timing: SolveTiming {
                prepare_ms: 0.5,
                enumerate_ms: 1.0,
                shards: 2,
            },
            search: &search,
        };
        let part = PartMsg::of(&content);
        assert_eq!(
            json(&part),
            r#"{"index":3,"id":"p","file":"p.dxf","status":"ok","warnings":["w"],"units":"mm","quantity":2.5,"outline":[{"x":0.0,"y":0.0},{"x":10.0,"y":0.0,"bulge":0.5},{"x":0.0,"y":5.0}],"access":[{"points":[{"x":1.0,"y":1.0},{"x":2.0,"y":1.0},{"x":1.0,"y":2.0}]}],"counts":{"segments":3,"combinations":10,"setups":4,"candidates":2,"exact":false},"fixtures":1,"best_score":0.25,"timing":{"prepare_ms":0.5,"enumerate_ms":1.0,"shards":2},"refine":[{"grid_step":2,"counts":{"segments":3,"combinations":10,"setups":4,"candidates":2,"admissible":1,"exact":true},"fixtures":1,"best_score":0.25,"added":1,"enumerate_ms":1.0}],"stopped":"good_enough","stopped_at":7}"#
        );
        assert_eq!(
            (part.outline(), part.access()),
            (outline.clone(), access.clone())
        );
        let read: PartMsg = serde_json::from_str(&json(&part)).unwrap();
        assert_eq!(read, part);
        // With holes (SPEC 9): after the outline, in order, arcs kept.
        let holes = vec![
            vec![Vertex::new(2.0, 1.0, 1.0), Vertex::new(3.0, 1.0, 1.0)],
            vec![
                Vertex::new(5.0, 1.0, 0.0),
                Vertex::new(6.0, 1.0, 0.0),
                Vertex::new(5.0, 2.0, 0.0),
            ],
        ];
        let holed = PartMsg::of(&PartContent {
            holes: &holes,
            ..content
        });
        let text = json(&holed);
        let want = r#""outline":[{"x":0.0,"y":0.0},{"x":10.0,"y":0.0,"bulge":0.5},{"x":0.0,"y":5.0}],"holes":[{"vertices":[{"x":2.0,"y":1.0,"bulge":1.0},{"x":3.0,"y":1.0,"bulge":1.0}]},{"vertices":[{"x":5.0,"y":1.0},{"x":6.0,"y":1.0},{"x":5.0,"y":2.0}]}],"access""#;
        assert!(text.contains(want), "{text}");
        assert_eq!(holed.holes(), holes);
        let read: PartMsg = serde_json::from_str(&text).unwrap();
        assert_eq!(read, holed);
    }

    /// The fixtures message, and the line `fixplan export --json` makes of
    /// it: SPEC Appendix A's result, byte for byte what it always was.
    #[test]
    fn the_fixtures_message_keeps_its_json_and_exports_appendix_a() {
        let result = SolveResult {
            status: Status::Ok,
            error: None,
            counts: Some(exact_counts()),
            segment_kinds: vec![SegmentKind::Line, SegmentKind::Arc, SegmentKind::Line],
            segment_loops: Vec::new(),
            fixtures: vec![fixture()],
        };
        let fixtures = FixturesMsg::of_result("p", &result);
        assert_eq!(
            json(&fixtures),
            r#"{"part":"p","status":"ok","counts":{"segments":3,"combinations":10,"setups":4,"candidates":2,"admissible":1,"exact":true},"segment_kinds":["line","arc","line"],"fixtures":[{"rank":1,"score":0.25,"segments":[0,1,2],"locators":[{"i":0,"j":0},{"i":2,"j":0},{"i":0,"j":1}],"pose":{"x":1.0,"y":2.0,"theta_deg":90.0},"clamp":{"segment":1,"rotation_deg":180,"mount":{"i":3,"j":1},"extension":4.5,"contact":{"x":5.0,"y":6.0}},"borderline":false,"contacts":[{"point":{"x":1.0,"y":0.0},"normal":{"x":0.0,"y":1.0}}],"placement":{"rotation_deg":90,"locators":[{"i":1,"j":1},{"i":3,"j":1},{"i":1,"j":2}],"clamp_holes":[{"i":4,"j":2},{"i":5,"j":2}]}}]}"#
        );
        assert_eq!(fixtures.result(), result);
        assert_eq!(
            String::from_utf8(fixtures.export_line().unwrap()).unwrap(),
            r#"{"part":"p","status":"ok","counts":{"segments":3,"combinations":10,"setups":4,"candidates":2,"admissible":1},"segment_kinds":["line","arc","line"],"fixtures":[{"rank":1,"score":0.25,"segments":[0,1,2],"locators":[[0,0],[2,0],[0,1]],"pose":{"x":1.0,"y":2.0,"theta_deg":90.0},"clamp":{"segment":1,"rotation_deg":180,"mount":[3,1],"extension":4.5,"contact":[5.0,6.0]},"borderline":false,"contacts":[{"point":[1.0,0.0],"normal":[0.0,1.0]}],"placement":{"rotation_deg":90,"locators":[[1,1],[3,1],[1,2]],"clamp_holes":[[4,2],[5,2]]}}]}"#
        );
        let read = serde_json::from_slice::<FixturesMsg>(json(&fixtures).as_bytes()).unwrap();
        assert_eq!(read, fixtures);
        // A part with holes lists the loop of every segment (SPEC 9.6),
        // in the message and in the exported result.
        let holed = SolveResult {
            segment_loops: vec![0, 1, 0],
            ..result.clone()
        };
        let m = FixturesMsg::of_result("h", &holed);
        let text = json(&m);
        assert!(
            text.contains(
                r#""segment_kinds":["line","arc","line"],"segment_loops":[0,1,0],"fixtures""#
            ),
            "{text}"
        );
        assert_eq!(m.result(), holed);
        let line = String::from_utf8(m.export_line().unwrap()).unwrap();
        assert!(line.contains(r#""segment_loops":[0,1,0]"#), "{line}");
        let invalid = FixturesMsg::of_result("q", &SolveResult::invalid("q: open outline"));
        assert_eq!(
            json(&invalid),
            r#"{"part":"q","status":"invalid","error":"q: open outline","segment_kinds":[],"fixtures":[]}"#
        );
        assert_eq!(
            String::from_utf8(invalid.export_line().unwrap()).unwrap(),
            r#"{"part":"q","status":"invalid","error":"q: open outline","fixtures":[]}"#
        );
    }
}
