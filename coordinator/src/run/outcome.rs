//! What a solved part becomes in the results file: its three messages
//! (part, fixtures, scene) in one compressed chunk, and the summary the
//! progress display shows.

use crate::job::{JobContext, Solved};
use crate::output::messages::{FixturesMsg, PartMsg, STOPPED_GOOD_ENOUGH};
use crate::output::{PartChunk, PartMessages};
use crate::view::scene::{scene_json, PartScene};
use fixplan_catalog::CatalogPart;
use fixplan_core::Status;

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
    part_outcome_packed(ctx, index, cp, solved, |m| m.chunk())
}

/// [`part_outcome`] with its chunk made by `pack` (compressed, or only
/// described: [`PartMessages::unpacked_chunk`]).
pub fn part_outcome_packed(
    ctx: &JobContext,
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
    let (outline, access) = match &cp.part {
        Ok(p) => (p.outline.clone(), p.access.clone()),
        // What was read, if anything: the picture shows what is wrong.
        Err(e) => e.read().map_or((Vec::new(), Vec::new()), |p| {
            (p.outline.clone(), p.access.clone())
        }),
    };
    let best = result.fixtures.first();
    let part_msg = PartMsg {
        index,
        id: cp.id.clone(),
        file: cp.file.as_ref().map(|f| f.display().to_string()),
        status: result.status,
        error: result.error.clone(),
        warnings: cp.warnings.clone(),
        units: ctx.units,
        quantity: cp.quantity,
        outline: outline.clone(),
        access: access.clone(),
        counts: result.counts,
        fixtures: result.fixtures.len(),
        best_score: best.map(|f| f.score),
        timing,
        refine: search.steps.clone(),
        stopped: search.stopped_at.map(|_| STOPPED_GOOD_ENOUGH.to_string()),
        stopped_at: search.stopped_at,
    };
    let caption = match &result.error {
        Some(e) => e.clone(),
        None => format!("{}: no fixture", cp.id),
    };
    let shown = best.ok_or(caption.as_str());
    let scene = scene_json(PartScene {
        index,
        id: &cp.id,
        units: ctx.units,
        kit: ctx.kit,
        outline: &outline,
        access: &access,
        best: shown,
    })?;
    let part = serde_json::to_vec(&part_msg)?;
    let (status, error) = (result.status, result.error.clone());
    let admissible = admissible_found(result.status, result.counts);
    let kept = result.fixtures.len();
    let fixtures = serde_json::to_vec(&FixturesMsg {
        part: cp.id.clone(),
        result,
    })?;
    let messages = PartMessages {
        index,
        part,
        fixtures,
        scene,
    };
    Ok(PartOutcome {
        chunk: pack(&messages)?,
        id: cp.id.clone(),
        status,
        error,
        admissible,
        kept,
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
