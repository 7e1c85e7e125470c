//! The JSON messages of a results file, one type per MCAP channel. Their
//! JSON Schemas are in [`super::schemas`]; the layout is documented in the
//! README ("MCAP layout").

pub use crate::job::Timing;
use fixplan_catalog::Catalog;
use fixplan_core::outline::Vertex;
use fixplan_core::{Counts, Kit, Params, Point, SolveResult, Status, Units};
use schemars::JsonSchema;
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
    pub timing: Timing,
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
