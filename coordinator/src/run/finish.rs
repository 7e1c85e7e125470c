//! Parts finished by the worker that solved them ([`fixplan_worker::finish`]):
//! what the coordinator sends with a whole part ([`context`]), what the
//! worker makes of it ([`RunFinisher`], the very [`part_outcome`] the
//! coordinator would run, compressed), and how the coordinator takes it
//! back ([`outcome`]). The coordinator then copies the chunk: its own work
//! per part is a check and a copy, so one coordinator serves many more
//! workers. The fixtures and scene messages are byte for byte what the
//! coordinator would have made; the part message's timing is the worker's.

use super::outcome::{part_outcome, OutcomeError, PartOutcome};
use crate::job::{JobContext, SearchOptions, Solved, Timing};
use crate::output::PartChunk;
use fixplan_catalog::CatalogPart;
use fixplan_core::{PartialResult, PreparedPart, Status};
use fixplan_worker::finish::Finisher;
use fixplan_worker::part_input::PartInput;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// What a worker needs to finish a part besides its input and result:
/// its place and entry in the catalogue.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct FinishContext {
    index: usize,
    id: String,
    file: Option<String>,
    warnings: Vec<String>,
    quantity: f64,
}

/// A part as its worker finished it: what the progress display counts and
/// the chunk to copy.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct FinishedPart {
    index: usize,
    id: String,
    status: Status,
    error: Option<String>,
    admissible: Option<u64>,
    kept: usize,
    chunk: PartChunk,
}

/// What the worker of part `index` (`cp`) is sent to finish it; `None` for
/// a part that cannot be read (it never leaves the coordinator).
pub fn context(index: usize, cp: &CatalogPart) -> Option<Vec<u8>> {
    cp.part.as_ref().ok()?;
    let c = FinishContext {
        index,
        id: cp.id.clone(),
        file: cp.file.as_ref().map(|f| f.display().to_string()),
        warnings: cp.warnings.clone(),
        quantity: cp.quantity,
    };
    postcard::to_allocvec(&c).ok()
}

/// Why a worker's finished part is not taken.
#[derive(Debug, thiserror::Error)]
pub enum FinishedError {
    /// Not a finished part of this version.
    #[error("malformed: {0}")]
    Malformed(#[from] postcard::Error),
    /// A finished part, of another part.
    #[error("it is part #{got_index} {got_id:?}, not this one")]
    OtherPart {
        /// Its index.
        got_index: usize,
        /// Its id.
        got_id: String,
    },
}

/// The outcome of part `index` (`cp`) from its worker's bytes.
pub fn outcome(bytes: &[u8], index: usize, cp: &CatalogPart) -> Result<PartOutcome, FinishedError> {
    let f: FinishedPart = postcard::from_bytes(bytes)?;
    if f.index != index || f.id != cp.id {
        return Err(FinishedError::OtherPart {
            got_index: f.index,
            got_id: f.id,
        });
    }
    Ok(PartOutcome {
        chunk: f.chunk,
        id: f.id,
        status: f.status,
        error: f.error,
        admissible: f.admissible,
        kept: f.kept,
        steps: None,
        stopped_at: None,
    })
}

/// The finisher of `fixplan worker` (and of the simulated workers of
/// `fixplan bench-coordinator`).
#[derive(Debug, Default, Clone, Copy)]
pub struct RunFinisher;

impl RunFinisher {
    fn finished(
        input: &PartInput,
        prep: &PreparedPart,
        result: &PartialResult,
        micros: u64,
        context: &[u8],
    ) -> Result<FinishedPart, String> {
        let c: FinishContext = postcard::from_bytes(context).map_err(|e| e.to_string())?;
        let cp = CatalogPart {
            id: c.id,
            file: c.file.map(PathBuf::from),
            part: Ok(input.part.clone()),
            warnings: c.warnings,
            quantity: c.quantity,
            top_k: None,
            wrenches: None,
        };
        let search = SearchOptions::default();
        let ctx = JobContext {
            kit: &input.kit,
            params: &input.params,
            units: input.units,
            shard_size: None,
            search: &search,
        };
        // As the coordinator closes a part: its shards merged (one here).
        let merged = fixplan_core::merge(prep.top_k(), vec![result.clone()]);
        let solved = Solved {
            result: fixplan_core::report(prep, &merged),
            timing: Timing {
                enumerate_ms: micros as f64 * 1e-3,
                shards: 1,
                ..Timing::default()
            },
            search: Default::default(),
        };
        let o =
            part_outcome(&ctx, c.index, &cp, solved).map_err(|e: OutcomeError| e.to_string())?;
        Ok(FinishedPart {
            index: c.index,
            id: o.id,
            status: o.status,
            error: o.error,
            admissible: o.admissible,
            kept: o.kept,
            chunk: o.chunk,
        })
    }
}

impl Finisher for RunFinisher {
    fn finish(
        &self,
        input: &PartInput,
        prep: &PreparedPart,
        result: &PartialResult,
        micros: u64,
        context: &[u8],
    ) -> Result<Vec<u8>, String> {
        let f = RunFinisher::finished(input, prep, result, micros, context)?;
        postcard::to_allocvec(&f).map_err(|e| e.to_string())
    }
}
