//! What a solved part becomes in the results file: its messages (one on
//! each part channel) in one compressed chunk, and the summary the
//! progress display shows.

use crate::job::{JobContext, Solved};
use crate::output::messages::PartContent;
use crate::output::{PartChunk, PartMessages};
use fixplan_catalog::CatalogPart;
use fixplan_core::{Kit, Status, Units};

/// Why a part's messages could not be made.
#[derive(Debug, thiserror::Error)]
pub enum OutcomeError {
    /// A message could not be serialised.
    #[error("JSON: {0}")]
    Json(#[from] serde_json::Error),
    /// Its chunk could not be compressed.
    #[error("compressing: {0}")]
    Compress(#[from] std::io::Error),
}

/// A part ready to be written: its chunk and what the progress display
/// and summary count.
#[derive(Debug, Clone)]
pub struct PartOutcome {
    /// The part's messages, serialised and compressed once, copied into
    /// the file.
    pub chunk: PartChunk,
    /// Catalogue id.
    pub id: String,
    /// `ok`, `no_fixture` or `invalid`.
    pub status: Status,
    /// Why the part is invalid.
    pub error: Option<String>,
    /// Admissible fixtures found; `None` when not counted (top-k mode).
    pub admissible: Option<u64>,
    /// Fixtures kept in the ranking.
    pub kept: usize,
    /// `--grid-steps`: what each step found.
    pub steps: Option<Vec<crate::job::StepSummary>>,
    /// `--good-enough`: the combination index where the part stopped.
    pub stopped_at: Option<u64>,
}

/// The messages and summary of part `index`, solved in this process or by
/// the workers of a cluster alike.
pub fn part_outcome(
    ctx: &JobContext,
    index: usize,
    cp: &CatalogPart,
    solved: Solved,
) -> Result<PartOutcome, OutcomeError> {
    part_outcome_packed(ctx.kit, ctx.units, index, cp, solved, |m| m.chunk())
}

/// [`part_outcome`] from the kit and unit alone (what a worker finishing
/// the part holds), its chunk made by `pack` (compressed, or only
/// described: [`PartMessages::unpacked_chunk`]).
pub fn part_outcome_packed(
    kit: &Kit,
    units: Units,
    index: usize,
    cp: &CatalogPart,
    solved: Solved,
    pack: impl FnOnce(&PartMessages) -> std::io::Result<PartChunk>,
) -> Result<PartOutcome, OutcomeError> {
    let Solved {
        result,
        timing,
        search,
    } = solved;
    // What was read of an invalid part, if anything: the picture shows
    // what is wrong.
    let read = match &cp.part {
        Ok(p) => Some(p),
        Err(e) => e.read(),
    };
    let messages = PartMessages::encode(&PartContent {
        index,
        entry: cp,
        units,
        kit,
        outline: read.map_or(&[], |p| &p.outline),
        holes: read.map_or(&[], |p| &p.holes),
        access: read.map_or(&[], |p| &p.access),
        result: &result,
        timing,
        search: &search,
    })?;
    Ok(PartOutcome {
        chunk: pack(&messages)?,
        id: cp.id.clone(),
        status: result.status,
        admissible: admissible_found(result.status, result.counts),
        kept: result.fixtures.len(),
        error: result.error,
        steps: search.steps,
        stopped_at: search.stopped_at,
    })
}

/// The admissible fixtures of a part, as far as they were counted: none
/// for a part without counts (invalid) or without fixtures, unknown for a
/// part with fixtures solved in top-k mode.
pub fn admissible_found(status: Status, counts: Option<fixplan_core::Counts>) -> Option<u64> {
    match counts {
        Some(c) if status == Status::Ok => c.admissible(),
        _ => Some(0),
    }
}
