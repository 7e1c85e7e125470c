//! What a study says, message by message: the `/fixplan/study` message of
//! each kit (with a row per part), the `/fixplan/study_summary` message,
//! and their JSON Schemas. The table, the CSV, the chart and the MCAP file
//! are all made from these.

use crate::output::fields::{CountsField, KitField, ParamsField, StatusName};
use crate::output::messages::CatalogInfo;
use crate::output::schemas::schema_of;
use fixplan_core::SolveResult;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// Topic of the per-kit messages: readers look a study file's kits up by it.
pub const TOPIC_STUDY: &str = "/fixplan/study";
/// Topic of the one summary message at the end of a study file.
pub const TOPIC_STUDY_SUMMARY: &str = "/fixplan/study_summary";
/// Schema name of [`TOPIC_STUDY`], as Foxglove and other MCAP tools show it.
pub const SCHEMA_STUDY: &str = "fixplan.StudyKit";
/// Schema name of [`TOPIC_STUDY_SUMMARY`].
pub const SCHEMA_STUDY_SUMMARY: &str = "fixplan.StudySummary";

/// The result of one part with one kit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StudyPartRow {
    /// The part's id in the catalogue, to find it in a run of that kit.
    pub id: String,
    /// Held, no fixture or invalid: what the coverage counts.
    pub status: StatusName,
    /// Why the part is invalid, if it is.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// Parts per year: weighs the part in `held_quantity_pct`.
    pub quantity: f64,
    /// What the enumeration went through (the same on every plate);
    /// absent for an invalid part.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub counts: Option<CountsField>,
    /// Score of the best fixture, for the kit's score percentiles; absent
    /// without a fixture.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub best_score: Option<f64>,
    /// Wall time of prepare + enumeration (0 when shared).
    pub ms: f64,
    /// How the result was obtained without enumerating, if it was.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shared: Option<String>,
}

impl StudyPartRow {
    /// The row of a part solved in `ms` milliseconds.
    pub fn solved(id: &str, quantity: f64, result: &SolveResult, ms: f64) -> StudyPartRow {
        StudyPartRow {
            id: id.to_string(),
            status: result.status.into(),
            error: result.error.clone(),
            quantity,
            counts: result.counts.as_ref().map(CountsField::from),
            best_score: result.fixtures.first().map(|f| f.score),
            ms,
            shared: None,
        }
    }

    /// This row for another kit, obtained without enumerating (`why`).
    pub fn shared_as(&self, why: String) -> StudyPartRow {
        StudyPartRow {
            ms: 0.0,
            shared: Some(why),
            ..self.clone()
        }
    }

    /// Stands for a row the study failed to fill, which its phases rule
    /// out; an invalid row rather than a panic if they ever do not.
    pub fn missing() -> StudyPartRow {
        StudyPartRow {
            id: String::new(),
            status: StatusName::Invalid,
            error: Some("internal error: no result".into()),
            quantity: 0.0,
            counts: None,
            best_score: None,
            ms: 0.0,
            shared: None,
        }
    }
}

/// `/fixplan/study`: one message per kit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StudyKitMsg {
    /// Position in the study (listed kits first, then sweep points): the
    /// message's sequence number and time.
    pub index: usize,
    /// The kit's name; a sweep point's is `BASE{key=value, ...}`.
    pub name: String,
    /// The listed kit it comes from, to group a sweep's points.
    pub base: String,
    /// The sweep point applied, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sweep: Option<String>,
    /// The kit as solved (catalogue units), to redo any of its parts.
    pub kit: KitField,
    /// The parameters as solved (top-k included).
    pub params: ParamsField,
    /// Parts in the catalogue.
    pub parts: usize,
    /// Parts with at least one fixture.
    pub held: usize,
    /// Share of parts held, percent.
    pub held_pct: f64,
    /// Share of parts held weighted by `quantity` (parts per year), percent.
    pub held_quantity_pct: f64,
    /// Median best score over the parts held (mean of the two middle ones
    /// for an even count); absent when none is held.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub median_score: Option<f64>,
    /// 90th percentile (nearest rank) of the best score over the parts
    /// held; absent when none is held.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub p90_score: Option<f64>,
    /// Parts the kit cannot hold.
    pub no_fixture: usize,
    /// Parts that could not be prepared (bad outline, too small for the kit).
    pub invalid: usize,
    /// Sum of the parts' solve times (prepare + enumerate), milliseconds; in
    /// a distributed study, the time between result deliveries.
    pub time_ms: f64,
    /// Parts enumerated for this kit.
    pub enumerated: usize,
    /// Parts whose result was shared (copied without enumerating).
    pub shared: usize,
    /// One row per part, in catalogue order.
    pub results: Vec<StudyPartRow>,
}

/// `/fixplan/study_summary`: once, at the end.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StudySummaryMsg {
    /// `fixplan`, for readers that meet the file alone.
    pub tool: String,
    /// The fixplan version that wrote it: results may change between versions.
    pub version: String,
    /// Which catalogue was studied (name, source, digest).
    pub catalog: CatalogInfo,
    /// The kits' names, in study order.
    pub kits: Vec<String>,
    /// Parts no kit of the study holds, with their status per kit.
    pub unheld: Vec<String>,
    /// Kits times parts: the work without sharing.
    pub part_runs: usize,
    /// Part runs actually enumerated.
    pub enumerated: usize,
    /// Part runs copied from an identical kit.
    pub shared_same_kit: usize,
    /// Part runs copied because a larger plate has no fixture either.
    pub shared_larger_plate: usize,
    /// Distinct prepared geometries (embedded studies).
    pub prepares: usize,
    /// Workers of a distributed study; absent for an embedded one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub workers: Option<usize>,
    /// Wall time of the whole study, milliseconds.
    pub elapsed_ms: f64,
}

/// What a study found.
#[derive(Debug, Clone)]
pub struct StudyReport {
    /// One message per kit, in study order.
    pub kits: Vec<StudyKitMsg>,
    /// Totals over the kits.
    pub summary: StudySummaryMsg,
}

/// The JSON Schema of [`StudyKitMsg`], stored in the MCAP file.
pub fn study_schema() -> serde_json::Value {
    schema_of::<StudyKitMsg>(SCHEMA_STUDY)
}

/// The JSON Schema of [`StudySummaryMsg`], stored in the MCAP file.
pub fn summary_schema() -> serde_json::Value {
    schema_of::<StudySummaryMsg>(SCHEMA_STUDY_SUMMARY)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::schemas::tests::assert_viewer_ready;

    #[test]
    fn study_schemas_are_titled_2020_12_with_properties_everywhere() {
        for (title, v) in [
            (SCHEMA_STUDY, study_schema()),
            (SCHEMA_STUDY_SUMMARY, summary_schema()),
        ] {
            assert_viewer_ready(title, &v);
        }
    }
}
