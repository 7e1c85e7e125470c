//! Writing a results file: MCAP, zstd chunks, summary and indexes. A chunk
//! holds whole parts (three messages each: part, fixtures, scene), a few
//! of them ([`CHUNK_BYTES`], [`CHUNK_PARTS`]), and is flushed when closed,
//! so a run killed at any moment leaves a file whose complete chunks hold
//! whole parts; `--resume` reads them back.

use super::messages::*;
use super::schemas::{fixtures_schema, part_schema, run_schema, scene_schema};
use mcap::records::{MessageHeader, Metadata};
use mcap::{Compression, WriteOptions, Writer};
use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;

/// Why a results file could not be written.
#[derive(Debug, thiserror::Error)]
pub enum OutError {
    /// The MCAP writer failed (usually the disk).
    #[error("MCAP: {0}")]
    Mcap(#[from] mcap::McapError),
    /// A message could not be serialised.
    #[error("JSON: {0}")]
    Json(#[from] serde_json::Error),
}

/// The three messages of one part, already serialised.
#[derive(Debug, Clone, PartialEq)]
pub struct PartMessages {
    /// Position of the part in the catalogue: its log time.
    pub index: usize,
    /// `/fixplan/part` message.
    pub part: Vec<u8>,
    /// `/fixplan/fixtures` message.
    pub fixtures: Vec<u8>,
    /// `/fixplan/scene` message.
    pub scene: Vec<u8>,
}

/// A chunk is closed once its parts' fixtures and scene messages hold this
/// many bytes. A chunk per part made zstd's per-chunk start (tables,
/// headers, indexes) and the flush most of the coordinator's cost of
/// writing; a few parts together also compress better (their scenes share
/// the plate). Counted on those two channels only, whose bytes do not
/// depend on timing, so chunks close at the same parts in every run.
pub const CHUNK_BYTES: usize = 256 * 1024;

/// At most this many parts in a chunk: what a run killed at the wrong
/// moment has to redo at most, when parts are small.
pub const CHUNK_PARTS: usize = 16;

/// A results file being written, whole parts per flushed chunk, so a run
/// killed at any moment leaves whole parts behind.
pub struct ResultsWriter {
    w: Writer<BufWriter<File>>,
    run: u16,
    part: u16,
    fixtures: u16,
    scene: u16,
    /// Parts in the open chunk, and their fixtures and scene bytes.
    open: (usize, usize),
}

/// The write options of every results file, embedded or distributed
/// (deterministic: single-threaded zstd, chunks closed only by
/// [`ResultsWriter`] at part boundaries).
pub fn write_options() -> WriteOptions {
    WriteOptions::new()
        .compression(Some(Compression::Zstd))
        .chunk_size(None)
        .compression_threads(0)
        .compression_level(1)
        .profile("")
        .library(format!("fixplan {}", env!("CARGO_PKG_VERSION")))
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
        ("catalog_units".to_string(), c.units.label().to_string()),
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
        let mut w = write_options().create(BufWriter::new(file))?;
        let none = BTreeMap::new();
        let chan = |w: &mut Writer<_>, name: &str, schema: Vec<u8>, topic: &str| {
            let s = w.add_schema(name, "jsonschema", &schema)?;
            w.add_channel(s, topic, "json", &none)
        };
        let run_ch = chan(&mut w, SCHEMA_RUN, run_schema(), TOPIC_RUN)?;
        let part = chan(&mut w, SCHEMA_PART, part_schema(), TOPIC_PART)?;
        let fixtures = chan(&mut w, SCHEMA_FIXTURES, fixtures_schema(), TOPIC_FIXTURES)?;
        let scene = chan(&mut w, SCHEMA_SCENE, scene_schema(), TOPIC_SCENE)?;
        let mut out = ResultsWriter {
            w,
            run: run_ch,
            part,
            fixtures,
            scene,
            open: (0, 0),
        };
        let data = serde_json::to_vec(run)?;
        out.message(out.run, 0, 0, &data)?;
        out.w.flush()?;
        // After the flush: no chunk is open, so the chunks stay as they were.
        out.w.write_metadata(&run_metadata(run)?)?;
        Ok(out)
    }

    fn message(
        &mut self,
        channel: u16,
        seq: u32,
        log_time: u64,
        data: &[u8],
    ) -> Result<(), OutError> {
        let header = MessageHeader {
            channel_id: channel,
            sequence: seq,
            log_time,
            publish_time: log_time,
        };
        self.w.write_to_known_channel(&header, data)?;
        Ok(())
    }

    /// Writes one part's messages into the open chunk, and closes and
    /// flushes the chunk once it is full ([`CHUNK_BYTES`], [`CHUNK_PARTS`]).
    pub fn write_part(&mut self, m: &PartMessages) -> Result<(), OutError> {
        let t = m.index as u64 * NS_PER_PART;
        let seq = m.index as u32;
        self.message(self.part, seq, t, &m.part)?;
        self.message(self.fixtures, seq, t, &m.fixtures)?;
        self.message(self.scene, seq, t, &m.scene)?;
        let (parts, bytes) = self.open;
        self.open = (parts + 1, bytes + m.fixtures.len() + m.scene.len());
        if self.open.0 >= CHUNK_PARTS || self.open.1 >= CHUNK_BYTES {
            self.w.flush()?;
            self.open = (0, 0);
        }
        Ok(())
    }

    /// Writes the summary and indexes; the file is complete after this.
    pub fn finish(mut self) -> Result<File, OutError> {
        self.w.finish()?;
        let buf = self.w.into_inner();
        buf.into_inner()
            .map_err(|e| OutError::Mcap(mcap::McapError::Io(e.into_error())))
    }
}
