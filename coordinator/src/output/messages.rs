//! The JSON messages of a results file, one type per MCAP channel, and
//! what a part's messages are made from ([`PartContent`]). Which channel
//! carries which message is [`super::channels`]; the JSON Schemas are
//! generated from these types ([`super::schemas`]); the layout is
//! documented in the README ("The results file (MCAP)").

use crate::job::SearchInfo;
pub use crate::job::SolveTiming;
use fixplan_catalog::{Catalog, CatalogPart};
use fixplan_core::outline::Vertex;
use fixplan_core::{Counts, Kit, Params, Point, SolveResult, Status, Units};
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
    pub kit: Kit,
    /// Parameters of the run (the kit's, with `--top-k` applied); a part's
    /// own `top_k` / `wrenches` in the catalogue override them.
    pub params: Params,
    /// `--grid-steps` (coarse to fine; `params.grid_step` is the finest).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grid_steps: Option<Vec<u32>>,
    /// `--good-enough` threshold.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub good_enough: Option<f64>,
}

/// The catalogue a run or study read: enough to tell two runs apart.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct CatalogInfo {
    /// The manifest's name (or the directory's).
    pub name: String,
    /// Where it was read from, as given on the command line.
    pub source: String,
    /// The catalogue's unit: every length of the file is in it.
    pub units: Units,
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
            units: catalog.units,
            parts: catalog.parts.len(),
            digest: catalog_digest(catalog),
        }
    }
}

/// `sha256:` of the catalogue's content, independent of where it lives:
/// what tells `--resume` that a file was written from the same parts.
/// Each entry is hashed as one JSON line, written into a reused buffer
/// (building JSON values first cost the coordinator more per part than
/// copying its results; writing each token into the hash cost more than
/// hashing the line).
pub fn catalog_digest(c: &Catalog) -> String {
    /// One catalogue entry as hashed.
    #[derive(Serialize)]
    struct Entry<'a> {
        id: &'a str,
        part: Result<&'a fixplan_core::Part, String>,
        quantity: f64,
        top_k: Option<usize>,
        wrenches: &'a Option<Vec<[f64; 3]>>,
    }
    let mut h = Sha256::new();
    h.update(format!("units={:?}\n", c.units));
    let mut line = Vec::with_capacity(4096);
    for p in &c.parts {
        let entry = Entry {
            id: &p.id,
            part: p.part.as_ref().map_err(|e| e.to_string()),
            quantity: p.quantity,
            top_k: p.top_k,
            wrenches: &p.wrenches,
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
}

/// `/fixplan/part`: one per part, in catalogue order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct PartMsg {
    /// Position in the catalogue (0-based).
    pub index: usize,
    /// Catalogue id.
    pub id: String,
    /// The part's file, if it has one (inline outlines have none).
    #[serde(default)]
    pub file: Option<String>,
    /// `ok`, `no_fixture` or `invalid`.
    pub status: Status,
    /// Why the part is invalid, naming the part and the place.
    #[serde(default)]
    pub error: Option<String>,
    /// Repairs made while reading the part.
    #[serde(default)]
    pub warnings: Vec<String>,
    /// The catalogue's unit.
    pub units: Units,
    /// Parts per year, for kit studies.
    pub quantity: f64,
    /// Part frame, catalogue units, as given (empty if it could not be read).
    pub outline: Vec<Vertex>,
    /// Access regions (part frame, catalogue units).
    #[serde(default)]
    pub access: Vec<Vec<Point>>,
    /// SPEC section 4 counts; absent for an invalid part.
    #[serde(default)]
    pub counts: Option<Counts>,
    /// Fixtures kept in the ranking (top-k).
    pub fixtures: usize,
    /// Score of the best fixture (lower is better).
    #[serde(default)]
    pub best_score: Option<f64>,
    /// Wall-clock timings (the only fields that differ between runs).
    pub timing: SolveTiming,
    /// `--grid-steps`: one summary per grid step, coarse to fine (counts,
    /// best fixture, what the step added). Absent in plain runs.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refine: Option<Vec<crate::job::StepSummary>>,
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
    fn of(p: &PartContent) -> PartMsg {
        let (result, search) = (p.result, p.search);
        PartMsg {
            index: p.index,
            id: p.entry.id.clone(),
            file: p.entry.file.as_ref().map(|f| f.display().to_string()),
            status: result.status,
            error: result.error.clone(),
            warnings: p.entry.warnings.clone(),
            units: p.units,
            quantity: p.entry.quantity,
            outline: p.outline.to_vec(),
            access: p.access.to_vec(),
            counts: result.counts,
            fixtures: result.fixtures.len(),
            best_score: result.fixtures.first().map(|f| f.score),
            timing: p.timing,
            refine: search.steps.clone(),
            stopped: search.stopped_at.map(|_| STOPPED_GOOD_ENOUGH.to_string()),
            stopped_at: search.stopped_at,
        }
    }
}

/// `/fixplan/fixtures`: `{"part": ID, ...}` plus the result format of SPEC
/// Appendix A (with contacts and plate placement per fixture). Exactly one
/// line of `fixplan export --json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct FixturesMsg {
    /// Catalogue id of the part.
    pub part: String,
    /// Status, counts and ranked fixtures.
    #[serde(flatten)]
    pub result: SolveResult,
}

impl Message for FixturesMsg {
    const TOPIC: &'static str = TOPIC_FIXTURES;
    const SCHEMA: &'static str = SCHEMA_FIXTURES;
}

impl PartMessage for FixturesMsg {
    fn of(p: &PartContent) -> FixturesMsg {
        FixturesMsg {
            part: p.entry.id.clone(),
            result: p.result.clone(),
        }
    }
}

/// The JSON of each message, pinned from literals: field names, order and
/// forms are the file format, which nothing outside this module may move.
#[cfg(test)]
mod tests {
    use super::*;
    use fixplan_core::report::{
        ClampReport, ContactReport, FixtureReport, PlacementReport, PoseReport,
    };
    use fixplan_core::segments::SegmentKind;
    use fixplan_core::{Clamp, HoleKind, MountHole, Pattern};

    fn json<T: Serialize>(m: &T) -> String {
        serde_json::to_string(m).expect("json")
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

    #[test]
    fn the_run_message_keeps_its_json() {
        let run = RunMsg {
            tool: "fixplan".into(),
            version: "0.0.0".into(),
            catalog: CatalogInfo {
                name: "cat".into(),
                source: "dir".into(),
                units: Units::In,
                parts: 2,
                digest: "sha256:00".into(),
            },
            kit_name: "kit".into(),
            kit: Kit {
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
            },
            params: Params {
                max_clamp_angle_deg: 45.0,
                edge_trim: Some(0.5),
                min_clearance: None,
                grid_step: 2,
                top_k: 10,
                full_counts: false,
                wrenches: Some(vec![[1.0, 0.0, -2.0]]),
            },
            grid_steps: Some(vec![4, 2]),
            good_enough: None,
        };
        assert_eq!(
            json(&run),
            r#"{"tool":"fixplan","version":"0.0.0","catalog":{"name":"cat","source":"dir","units":"in","parts":2,"digest":"sha256:00"},"kit_name":"kit","kit":{"spacing":25.0,"cols":4,"rows":3,"pattern":"alternating","locator_radius":5.5,"clamp":{"mount_holes":[[0,0,"any"],[1,0,"tapped"]],"axis_offset":1.5,"travel":[2.0,9.25],"body":[[0.0,0.0],[1.0,0.5]],"plunger":[[0.0,-0.5]]}},"params":{"max_clamp_angle_deg":45.0,"edge_trim":0.5,"min_clearance":null,"grid_step":2,"top_k":10,"full_counts":false,"wrenches":[[1.0,0.0,-2.0]]},"grid_steps":[4,2]}"#
        );
    }

    #[test]
    fn the_part_message_keeps_its_json() {
        let part = PartMsg {
            index: 3,
            id: "p".into(),
            file: Some("p.dxf".into()),
            status: Status::Ok,
            error: None,
            warnings: vec!["w".into()],
            units: Units::Mm,
            quantity: 2.5,
            outline: vec![
                Vertex::new(0.0, 0.0, 0.0),
                Vertex::new(10.0, 0.0, 0.5),
                Vertex::new(0.0, 5.0, 0.0),
            ],
            access: vec![vec![[1.0, 1.0], [2.0, 1.0], [1.0, 2.0]]],
            counts: Some(Counts {
                segments: 3,
                combinations: 10,
                setups: 4,
                candidates: 2,
                admissible: 0,
                exact: false,
            }),
            fixtures: 1,
            best_score: Some(0.25),
            timing: SolveTiming {
                prepare_ms: 0.5,
                enumerate_ms: 1.0,
                shards: 2,
            },
            refine: Some(vec![crate::job::StepSummary {
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
            stopped: Some(STOPPED_GOOD_ENOUGH.into()),
            stopped_at: Some(7),
        };
        assert_eq!(
            json(&part),
            r#"{"index":3,"id":"p","file":"p.dxf","status":"ok","error":null,"warnings":["w"],"units":"mm","quantity":2.5,"outline":[[0.0,0.0],[10.0,0.0,0.5],[0.0,5.0]],"access":[[[1.0,1.0],[2.0,1.0],[1.0,2.0]]],"counts":{"segments":3,"combinations":10,"setups":4,"candidates":2,"counts_exact":false},"fixtures":1,"best_score":0.25,"timing":{"prepare_ms":0.5,"enumerate_ms":1.0,"shards":2},"refine":[{"grid_step":2,"counts":{"segments":3,"combinations":10,"setups":4,"candidates":2,"admissible":1},"fixtures":1,"best_score":0.25,"best":null,"added":1,"improved_by":null,"enumerate_ms":1.0}],"stopped":"good_enough","stopped_at":7}"#
        );
    }

    #[test]
    fn the_fixtures_message_keeps_its_json() {
        let fixture = FixtureReport {
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
        };
        let fixtures = FixturesMsg {
            part: "p".into(),
            result: SolveResult {
                status: Status::Ok,
                error: None,
                counts: Some(exact_counts()),
                segment_kinds: vec![SegmentKind::Line, SegmentKind::Arc, SegmentKind::Line],
                fixtures: vec![fixture],
            },
        };
        assert_eq!(
            json(&fixtures),
            r#"{"part":"p","status":"ok","counts":{"segments":3,"combinations":10,"setups":4,"candidates":2,"admissible":1},"segment_kinds":["line","arc","line"],"fixtures":[{"rank":1,"score":0.25,"segments":[0,1,2],"locators":[[0,0],[2,0],[0,1]],"pose":{"x":1.0,"y":2.0,"theta_deg":90.0},"clamp":{"segment":1,"rotation_deg":180,"mount":[3,1],"extension":4.5,"contact":[5.0,6.0]},"borderline":false,"contacts":[{"point":[1.0,0.0],"normal":[0.0,1.0]}],"placement":{"rotation_deg":90,"locators":[[1,1],[3,1],[1,2]],"clamp_holes":[[4,2],[5,2]]}}]}"#
        );
        let invalid = FixturesMsg {
            part: "q".into(),
            result: SolveResult::invalid("q: open outline"),
        };
        assert_eq!(
            json(&invalid),
            r#"{"part":"q","status":"invalid","error":"q: open outline","fixtures":[]}"#
        );
    }
}
