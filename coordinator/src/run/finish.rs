//! Parts finished by the worker that solved them ([`fixplan_worker::finish`]):
//! what the coordinator sends with a whole part ([`context`]), what the
//! worker makes of it ([`RunFinisher`], the very [`part_outcome`](super::outcome::part_outcome) the
//! coordinator would run, compressed), and how the coordinator takes it
//! back ([`outcome`]). The coordinator then copies the chunk: its own work
//! per part is a check and a copy, so one coordinator serves many more
//! workers. The fixtures and scene messages are byte for byte what the
//! coordinator would have made; the part message's timing is the worker's.

use super::outcome::{part_outcome_packed, PartOutcome};
use crate::job::{SearchInfo, SolveTiming, Solved};
use crate::output::messages::NS_PER_PART;
use crate::output::{PartChunk, PartMessages};
use bytes::Bytes;
use fixplan_catalog::CatalogPart;
use fixplan_core::Status;
use fixplan_worker::finish::{FinishInputs, Finisher};
use fixplan_worker::protocol::FinishError;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// What a worker needs to finish a part besides its input and result:
/// its place and its whole entry in the catalogue (the part itself is the
/// input's).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct FinishContext {
    index: usize,
    id: String,
    file: Option<String>,
    warnings: Vec<String>,
    quantity: f64,
    top_k: Option<usize>,
    wrenches: Option<Vec<[f64; 3]>>,
}

impl FinishContext {
    /// The context of part `index` (`cp`); `None` for a part that cannot
    /// be read.
    fn of(index: usize, cp: &CatalogPart) -> Option<FinishContext> {
        cp.part.as_ref().ok()?;
        Some(FinishContext {
            index,
            id: cp.id.clone(),
            file: cp.file.as_ref().map(|f| f.display().to_string()),
            warnings: cp.warnings.clone(),
            quantity: cp.quantity,
            top_k: cp.top_k,
            wrenches: cp.wrenches.clone(),
        })
    }

    /// The catalogue entry back, with the part the worker was sent.
    fn entry(self, part: &fixplan_core::Part) -> CatalogPart {
        CatalogPart {
            id: self.id,
            file: self.file.map(PathBuf::from),
            part: Ok(part.clone()),
            warnings: self.warnings,
            quantity: self.quantity,
            top_k: self.top_k,
            wrenches: self.wrenches,
        }
    }
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

impl FinishedPart {
    /// The wire form: the postcard head, then the chunk's compressed
    /// records raw, so that the coordinator writes them from the buffer
    /// they arrived in.
    fn to_bytes(&self) -> Result<Vec<u8>, postcard::Error> {
        let raw = &self.chunk.compressed;
        let mut v = postcard::to_extend(self, Vec::with_capacity(256 + raw.len()))?;
        v.extend_from_slice(raw);
        Ok(v)
    }

    /// Reads [`FinishedPart::to_bytes`]; the chunk's bytes are a view of
    /// `bytes`.
    fn from_bytes(bytes: Bytes) -> Result<FinishedPart, postcard::Error> {
        let (mut f, raw) = postcard::take_from_bytes::<FinishedPart>(&bytes)?;
        f.chunk.compressed = bytes.slice_ref(raw);
        Ok(f)
    }
}

/// What the worker of part `index` (`cp`) is sent to finish it; `None` for
/// a part that cannot be read (it never leaves the coordinator).
pub fn context(index: usize, cp: &CatalogPart) -> Option<Vec<u8>> {
    postcard::to_allocvec(&FinishContext::of(index, cp)?).ok()
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
    /// Its chunk has not the shape of a part's ([`PartChunk::fits`]).
    #[error("its chunk: {0}")]
    BadChunk(String),
}

/// The outcome of part `index` (`cp`) from its worker's bytes.
pub fn outcome(bytes: Bytes, index: usize, cp: &CatalogPart) -> Result<PartOutcome, FinishedError> {
    let f = FinishedPart::from_bytes(bytes)?;
    if f.index != index || f.id != cp.id {
        return Err(FinishedError::OtherPart {
            got_index: f.index,
            got_id: f.id,
        });
    }
    f.chunk
        .fits(index as u64 * NS_PER_PART)
        .map_err(FinishedError::BadChunk)?;
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
    /// The finished part, its chunk made by `pack`: the very
    /// [`part_outcome_packed`] the coordinator runs on a part it merged.
    fn finished(
        inputs: &FinishInputs,
        pack: impl FnOnce(&PartMessages) -> std::io::Result<PartChunk>,
    ) -> Result<FinishedPart, FinishError> {
        let context: FinishContext = postcard::from_bytes(inputs.context)
            .map_err(|e| FinishError::Context(e.to_string()))?;
        let index = context.index;
        let entry = context.entry(&inputs.input.part);
        // As the coordinator closes a part: its shards merged (one here),
        // numbered from 0 as the embedded run numbers a whole part (a
        // worker's whole shard is labelled with an open range).
        let mut whole = inputs.result.clone();
        whole.range = 0..inputs.result.counts.combinations;
        let merged = fixplan_core::merge(inputs.prep.top_k(), vec![whole]);
        let solved = Solved {
            result: fixplan_core::report(inputs.prep, &merged),
            timing: SolveTiming {
                enumerate_ms: inputs.micros as f64 * 1e-3,
                shards: 1,
                ..SolveTiming::default()
            },
            search: SearchInfo::default(),
        };
        let (kit, units) = (&inputs.input.kit, inputs.input.units);
        let o = part_outcome_packed(kit, units, index, &entry, solved, pack)
            .map_err(|e| FinishError::Messages(e.to_string()))?;
        Ok(FinishedPart {
            index,
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
    fn finish(&self, inputs: &FinishInputs) -> Result<Vec<u8>, FinishError> {
        let f = RunFinisher::finished(inputs, |m| m.chunk())?;
        f.to_bytes().map_err(|e| FinishError::Encode(e.to_string()))
    }

    fn check(&self, inputs: &FinishInputs, theirs: &[u8]) -> Result<(), FinishError> {
        // Laid out, not compressed: the check compares what the chunks hold.
        let ours = RunFinisher::finished(inputs, |m| Ok(m.unpacked_chunk()))?;
        let theirs = FinishedPart::from_bytes(Bytes::copy_from_slice(theirs))
            .map_err(|e| FinishError::Malformed(e.to_string()))?;
        same_part(&ours, &theirs)
    }
}

/// Whether `theirs` holds what `ours` describes: every field, and a chunk
/// with the same records ([`PartChunk::holds_same`]).
fn same_part(ours: &FinishedPart, theirs: &FinishedPart) -> Result<(), FinishError> {
    let head = |f: &FinishedPart| {
        (
            f.index,
            f.id.clone(),
            f.status,
            f.error.clone(),
            f.admissible,
            f.kept,
        )
    };
    if head(ours) != head(theirs) {
        return Err(FinishError::Summary {
            theirs: format!("{:?}", head(theirs)),
            ours: format!("{:?}", head(ours)),
        });
    }
    ours.chunk
        .holds_same(&theirs.chunk)
        .map_err(FinishError::Records)
}

#[cfg(test)]
mod tests {
    use super::*;
    use fixplan_catalog::kit::{builtin_kit, METRIC_25};
    use fixplan_core::{Params, Part, PartialResult, PreparedPart};
    use fixplan_worker::part_input::PartInput;

    /// A rectangle's pieces, as a worker finishes it.
    struct Rectangle {
        input: PartInput,
        prep: PreparedPart,
        result: PartialResult,
        context: Vec<u8>,
    }

    impl Rectangle {
        fn new() -> Rectangle {
            let (kit, units) = builtin_kit(METRIC_25).expect("kit");
            let input = PartInput {
                part: Part::polygon(&[[0.0, 0.0], [120.0, 0.0], [120.0, 60.0], [0.0, 60.0]]),
                kit,
                params: Params::default(),
                units,
            };
            let prep = input.prepare().expect("prepare");
            let result = prep.enumerate_all();
            let cp = CatalogPart {
                id: "rect".into(),
                file: None,
                part: Ok(input.part.clone()),
                warnings: vec![],
                quantity: 1.0,
                top_k: Some(4),
                wrenches: None,
            };
            let context = context(3, &cp).expect("context");
            Rectangle {
                input,
                prep,
                result,
                context,
            }
        }

        fn inputs<'a>(&'a self, result: &'a PartialResult, micros: u64) -> FinishInputs<'a> {
            FinishInputs {
                input: &self.input,
                prep: &self.prep,
                result,
                micros,
                context: &self.context,
            }
        }

        fn finish(&self, result: &PartialResult, micros: u64) -> Vec<u8> {
            RunFinisher
                .finish(&self.inputs(result, micros))
                .expect("finish")
        }
    }

    #[test]
    fn a_finished_part_is_the_same_only_as_its_own_result() {
        let rect = Rectangle::new();
        let ours = rect.finish(&rect.result, 1500);
        let check = |theirs: &[u8]| RunFinisher.check(&rect.inputs(&rect.result, 1500), theirs);
        assert_eq!(check(&ours), Ok(()));
        let decode =
            |b: &[u8]| FinishedPart::from_bytes(Bytes::copy_from_slice(b)).expect("decode");
        let part = decode(&ours);
        assert_eq!(
            part.to_bytes().expect("encode"),
            ours,
            "the wire form reads back"
        );
        assert_eq!((part.index, part.id.as_str()), (3, "rect"));
        assert!(part.kept > 0, "a rectangle has fixtures");
        // Another timing: another part message, told apart.
        let later = rect.finish(&rect.result, 2500);
        assert!(matches!(check(&later), Err(FinishError::Records(_))));
        // A result with its best fixture dropped.
        let mut fewer = rect.result.clone();
        fewer.fixtures.remove(0);
        let forged = rect.finish(&fewer, 1500);
        assert!(matches!(
            check(&forged),
            Err(FinishError::Summary { .. } | FinishError::Records(_))
        ));
        // The same header over other compressed bytes.
        let mut swapped = decode(&ours);
        swapped.chunk.compressed = decode(&forged).chunk.compressed;
        let swapped = swapped.to_bytes().expect("encode");
        assert!(check(&swapped).is_err());
        assert!(matches!(check(b"junk"), Err(FinishError::Malformed(_))));
        // A context this version cannot read.
        let junk = FinishInputs {
            context: b"junk",
            ..rect.inputs(&rect.result, 1500)
        };
        assert!(matches!(
            RunFinisher.finish(&junk),
            Err(FinishError::Context(_))
        ));
    }

    #[test]
    fn the_context_carries_the_whole_entry() {
        let rect = Rectangle::new();
        let context: FinishContext = postcard::from_bytes(&rect.context).expect("context");
        let entry = context.entry(&rect.input.part);
        assert_eq!(entry.top_k, Some(4));
        assert_eq!(entry.part.as_ref().ok(), Some(&rect.input.part));
    }

    #[test]
    fn the_coordinator_reads_back_what_a_worker_finished() {
        let rect = Rectangle::new();
        let bytes = Bytes::from(rect.finish(&rect.result, 1500));
        let cp = CatalogPart {
            id: "rect".into(),
            file: None,
            part: Ok(Part::polygon(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])),
            warnings: vec![],
            quantity: 1.0,
            top_k: None,
            wrenches: None,
        };
        let o = outcome(bytes.clone(), 3, &cp).expect("outcome");
        assert_eq!(o.status, Status::Ok);
        assert!(matches!(
            outcome(bytes.clone(), 4, &cp),
            Err(FinishedError::OtherPart { got_index: 3, .. })
        ));
        let mut bad = FinishedPart::from_bytes(bytes).expect("decode");
        bad.chunk.compressed.truncate(3);
        let bad = bad.to_bytes().expect("encode");
        assert!(matches!(
            outcome(bad.into(), 3, &cp),
            Err(FinishedError::BadChunk(_))
        ));
    }
}
