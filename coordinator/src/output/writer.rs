//! Writing a results file: MCAP, one zstd chunk per part (a message on
//! each of [`PART_CHANNELS`]), summary and indexes. Chunks come finished
//! ([`PartChunk`]: made by a worker, or by the solving thread of an
//! embedded run), so writing a part is a copy. The file is flushed every
//! few parts ([`FLUSH_BYTES`], [`FLUSH_PARTS`]), so a run killed at any
//! moment leaves a file whose complete chunks hold whole parts;
//! `--resume` reads them back.

use super::channels::{all_channels, part_slot, PART_CHANNELS, RUN_CHANNEL};
use super::chunk::PartChunk;
use super::mcap_file::McapFile;
use super::messages::*;
use mcap::records::{Channel, Metadata};
use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;

/// Why a results file could not be written.
#[derive(Debug, thiserror::Error)]
pub enum OutError {
    /// Writing failed (usually the disk), or a chunk could not be
    /// compressed.
    #[error("writing the results file: {0}")]
    Io(#[from] std::io::Error),
    /// A message could not be serialised.
    #[error("JSON: {0}")]
    Json(#[from] serde_json::Error),
}

/// The messages of one part, already serialised: one on each of
/// [`PART_CHANNELS`], in its order.
#[derive(Debug, Clone, PartialEq)]
pub struct PartMessages {
    /// Position of the part in the catalogue: its log time.
    pub index: usize,
    messages: [Vec<u8>; PART_CHANNELS.len()],
}

impl PartMessages {
    /// The messages of `part`, each made by its channel's encoder.
    pub fn encode(part: &PartContent) -> serde_json::Result<PartMessages> {
        let mut messages: [Vec<u8>; PART_CHANNELS.len()] = Default::default();
        for (m, c) in messages.iter_mut().zip(&PART_CHANNELS) {
            *m = (c.encode)(part)?;
        }
        Ok(PartMessages {
            index: part.index,
            messages,
        })
    }

    /// The messages of part `index` as read from a file, in the order of
    /// [`PART_CHANNELS`].
    pub fn read(index: usize, messages: [Vec<u8>; PART_CHANNELS.len()]) -> PartMessages {
        PartMessages { index, messages }
    }

    /// The message on channel `topic`, if it is a part channel.
    pub fn get(&self, topic: &str) -> Option<&[u8]> {
        part_slot(topic).map(|i| self.messages[i].as_slice())
    }

    /// The message `M`, decoded.
    pub fn decode<M: Message>(&self) -> serde_json::Result<M> {
        match self.get(M::TOPIC) {
            Some(data) => serde_json::from_slice(data),
            None => Err(serde::de::Error::custom(format!(
                "{} is not a part channel",
                M::TOPIC
            ))),
        }
    }

    /// The part's chunk (compressed here: on the solving thread, or the
    /// worker, never the writer's).
    pub fn chunk(&self) -> std::io::Result<PartChunk> {
        PartChunk::encode(self.log_time(), &self.records())
    }

    /// [`PartMessages::chunk`] uncompressed ([`PartChunk::unpacked`]).
    pub fn unpacked_chunk(&self) -> PartChunk {
        PartChunk::unpacked(self.log_time(), &self.records())
    }

    fn log_time(&self) -> u64 {
        self.index as u64 * NS_PER_PART
    }

    fn records(&self) -> [(u16, u32, &[u8]); PART_CHANNELS.len()] {
        let seq = self.index as u32;
        std::array::from_fn(|i| (PART_CHANNELS[i].channel.id, seq, &self.messages[i][..]))
    }
}

/// The file is flushed once this many compressed bytes were written since
/// the last flush...
pub const FLUSH_BYTES: usize = 256 * 1024;

/// ... or this many parts: what a run killed at the wrong moment has to
/// redo at most, when parts are small.
pub const FLUSH_PARTS: usize = 16;

/// A results file being written, a chunk per part, so a run killed at
/// any moment leaves whole parts behind.
pub struct ResultsWriter {
    w: McapFile<BufWriter<File>>,
    /// Parts and bytes written since the last flush.
    unflushed: (usize, usize),
}

/// The library string of every results file.
fn library() -> String {
    format!("fixplan {}", env!("CARGO_PKG_VERSION"))
}

/// The [`METADATA_RUN`] record of `run`: tool, version, kit name, kit and
/// parameters (JSON), and the catalogue's name, source, unit, part count
/// and digest.
pub fn run_metadata(run: &RunMsg) -> Result<Metadata, OutError> {
    let c = &run.catalog;
    let mut m = BTreeMap::from([
        ("tool".to_string(), run.tool.clone()),
        ("version".to_string(), run.version.clone()),
        ("kit_name".to_string(), run.kit_name.clone()),
        ("kit".to_string(), serde_json::to_string(&run.kit)?),
        ("params".to_string(), serde_json::to_string(&run.params)?),
        ("catalog_name".to_string(), c.name.clone()),
        ("catalog_source".to_string(), c.source.clone()),
        ("catalog_units".to_string(), c.units.text().to_string()),
        ("catalog_parts".to_string(), c.parts.to_string()),
        ("catalog_digest".to_string(), c.digest.clone()),
    ]);
    if let Some(steps) = &run.grid_steps {
        m.insert("grid_steps".into(), serde_json::to_string(steps)?);
    }
    if let Some(g) = run.good_enough {
        m.insert("good_enough".into(), g.to_string());
    }
    Ok(Metadata {
        name: METADATA_RUN.to_string(),
        metadata: m,
    })
}

impl ResultsWriter {
    /// Starts a file: schemas, channels, the `/fixplan/run` message and the
    /// [`METADATA_RUN`] metadata record.
    pub fn create(file: File, run: &RunMsg) -> Result<ResultsWriter, OutError> {
        let mut w = McapFile::new(BufWriter::with_capacity(FLUSH_BYTES, file), "", &library())?;
        for c in all_channels() {
            w.schema(c.id, c.schema_name, "jsonschema", &(c.schema)())?;
            w.channel(Channel {
                id: c.id,
                schema_id: c.id,
                topic: c.topic.into(),
                message_encoding: "json".into(),
                metadata: BTreeMap::new(),
            })?;
        }
        let data = serde_json::to_vec(run)?;
        w.chunk(&PartChunk::encode(0, &[(RUN_CHANNEL.id, 0, &data)])?)?;
        w.metadata(&run_metadata(run)?)?;
        w.flush()?;
        Ok(ResultsWriter {
            w,
            unflushed: (0, 0),
        })
    }

    /// Writes one part's messages (compressing them here: resumed and
    /// merged files; a run writes finished chunks, [`Self::write_chunk`]).
    pub fn write_part(&mut self, messages: &PartMessages) -> Result<(), OutError> {
        self.write_chunk(&messages.chunk()?)
    }

    /// Writes one part's chunk, and flushes the file every few parts.
    pub fn write_chunk(&mut self, chunk: &PartChunk) -> Result<(), OutError> {
        self.w.chunk(chunk)?;
        let (parts, bytes) = self.unflushed;
        self.unflushed = (parts + 1, bytes + chunk.compressed.len());
        if self.unflushed.0 >= FLUSH_PARTS || self.unflushed.1 >= FLUSH_BYTES {
            self.w.flush()?;
            self.unflushed = (0, 0);
        }
        Ok(())
    }

    /// Writes the summary and indexes; the file is complete after this.
    pub fn finish(self) -> Result<File, OutError> {
        let buf = self.w.finish()?;
        buf.into_inner().map_err(|e| OutError::Io(e.into_error()))
    }
}
