//! The study as an MCAP file: `/fixplan/study` (one message per kit) and
//! `/fixplan/study_summary`, JSON with their schemas, with the message clock of a results file, written by the `mcap` crate's
//! writer (a study is one small file, written at the end).

use super::messages::{
    study_schema, summary_schema, StudyKitMsg, StudyReport, StudySummaryMsg, SCHEMA_STUDY,
    SCHEMA_STUDY_SUMMARY, TOPIC_STUDY, TOPIC_STUDY_SUMMARY,
};
use crate::output::messages::NS_PER_PART;
use anyhow::{Context, Result};
use mcap::records::MessageHeader;
use std::collections::BTreeMap;
use std::path::Path;

/// Deterministic options: single-threaded zstd, one chunk.
fn write_options() -> mcap::WriteOptions {
    mcap::WriteOptions::new()
        .compression(Some(mcap::Compression::Zstd))
        .chunk_size(None)
        .compression_threads(0)
        .compression_level(1)
        .profile("")
        .library(format!("fixplan {}", env!("CARGO_PKG_VERSION")))
}

/// Writes the study to `path`, for Foxglove or for [`read_mcap`].
pub fn write_mcap(path: &Path, rep: &StudyReport) -> Result<()> {
    let file = std::fs::File::create(path)
        .with_context(|| format!("{}: cannot create", path.display()))?;
    let mut w = write_options().create(std::io::BufWriter::new(file))?;
    let none = BTreeMap::new();
    let s1 = w.add_schema(
        SCHEMA_STUDY,
        "jsonschema",
        &serde_json::to_vec_pretty(&study_schema())?,
    )?;
    let c1 = w.add_channel(s1, TOPIC_STUDY, "json", &none)?;
    let s2 = w.add_schema(
        SCHEMA_STUDY_SUMMARY,
        "jsonschema",
        &serde_json::to_vec_pretty(&summary_schema())?,
    )?;
    let c2 = w.add_channel(s2, TOPIC_STUDY_SUMMARY, "json", &none)?;
    for k in &rep.kits {
        let t = k.index as u64 * NS_PER_PART;
        w.write_to_known_channel(
            &MessageHeader {
                channel_id: c1,
                sequence: k.index as u32,
                log_time: t,
                publish_time: t,
            },
            &serde_json::to_vec(k)?,
        )?;
    }
    let t = rep.kits.len() as u64 * NS_PER_PART;
    w.write_to_known_channel(
        &MessageHeader {
            channel_id: c2,
            sequence: 0,
            log_time: t,
            publish_time: t,
        },
        &serde_json::to_vec(&rep.summary)?,
    )?;
    w.finish()?;
    Ok(())
}

/// Reads a study file back (tests, scripts comparing kits): its kits'
/// messages and its summary, if it has one.
pub fn read_mcap(path: &Path) -> Result<(Vec<StudyKitMsg>, Option<StudySummaryMsg>)> {
    let bytes = std::fs::read(path).with_context(|| format!("{}: cannot read", path.display()))?;
    let mut kits = Vec::new();
    let mut summary = None;
    for m in mcap::MessageStream::new(&bytes)? {
        let m = m?;
        match m.channel.topic.as_str() {
            TOPIC_STUDY => kits.push(serde_json::from_slice(&m.data)?),
            TOPIC_STUDY_SUMMARY => summary = Some(serde_json::from_slice(&m.data)?),
            _ => {}
        }
    }
    Ok((kits, summary))
}
