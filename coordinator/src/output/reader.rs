//! Reading a results file back, complete or cut short by a kill: the run
//! message, then each part's messages grouped in catalogue order.

use super::channels::{part_slot, PART_CHANNELS};
use super::messages::*;
use super::writer::PartMessages;
use mcap::read::Options;
use mcap::MessageStream;
use std::path::Path;

/// Why a results file cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// The file system refused.
    #[error("{path}: cannot read: {source}")]
    Io {
        /// The file.
        path: String,
        /// What the system said.
        #[source]
        source: std::io::Error,
    },
    /// Not MCAP, or not written by fixplan: `--resume` starts afresh.
    #[error("{path}: not a fixplan results file: {message}")]
    Format {
        /// The file.
        path: String,
        /// What is wrong with it.
        message: String,
    },
}

/// A results file read into memory.
pub struct ResultsFile {
    /// Where it was read from, for messages.
    pub path: String,
    bytes: Vec<u8>,
}

/// What a results file holds.
pub struct Contents {
    /// The run message (what was run).
    pub run: RunMsg,
    /// Indices of the parts whose messages (one on each part channel) are
    /// all present, in file order.
    pub parts: Vec<usize>,
    /// False when the file has no summary (an interrupted run).
    pub complete: bool,
    /// Why reading stopped early, if it did (a truncated chunk).
    pub truncated: Option<String>,
}

impl ResultsFile {
    /// Reads the whole file (results files are small: a few kB a part).
    pub fn open(path: &Path) -> Result<ResultsFile, ReadError> {
        let bytes = std::fs::read(path).map_err(|source| ReadError::Io {
            path: path.display().to_string(),
            source,
        })?;
        Ok(ResultsFile {
            path: path.display().to_string(),
            bytes,
        })
    }

    fn format_err(&self, message: impl Into<String>) -> ReadError {
        ReadError::Format {
            path: self.path.clone(),
            message: message.into(),
        }
    }

    /// Streams the messages; calls `on_part` for each part whose messages
    /// are complete, in order. Stops quietly at a truncated record.
    pub fn for_each_part(
        &self,
        mut on_part: impl FnMut(&RunMsg, PartMessages) -> bool,
    ) -> Result<Contents, ReadError> {
        let complete = matches!(mcap::Summary::read(&self.bytes), Ok(Some(_)));
        let stream = MessageStream::new_with_options(&self.bytes, Options::IgnoreEndMagic.into())
            .map_err(|e| self.format_err(e.to_string()))?;
        let mut run: Option<RunMsg> = None;
        let mut cur: Option<Gathered> = None;
        let mut truncated = None;
        let mut parts = Vec::new();
        let mut keep_going = true;
        let flush = |cur: &mut Option<Gathered>,
                     run: &Option<RunMsg>,
                     parts: &mut Vec<usize>,
                     keep_going: &mut bool,
                     on_part: &mut dyn FnMut(&RunMsg, PartMessages) -> bool| {
            if let (Some(m), Some(run)) = (cur.take().and_then(Gathered::complete), run) {
                parts.push(m.index);
                if *keep_going {
                    *keep_going = on_part(run, m);
                }
            }
        };
        for msg in stream {
            let msg = match msg {
                Ok(m) => m,
                Err(e) => {
                    truncated = Some(e.to_string());
                    break;
                }
            };
            let topic = msg.channel.topic.as_str();
            if topic == TOPIC_RUN {
                let r: RunMsg = serde_json::from_slice(&msg.data)
                    .map_err(|e| self.format_err(format!("{TOPIC_RUN}: {e}")))?;
                run = Some(r);
                continue;
            }
            let Some(slot) = part_slot(topic) else {
                continue;
            };
            let index = (msg.log_time / NS_PER_PART) as usize;
            if cur.as_ref().map(|c| c.index) != Some(index) {
                flush(&mut cur, &run, &mut parts, &mut keep_going, &mut on_part);
                cur = Some(Gathered {
                    index,
                    messages: Default::default(),
                });
            }
            if let Some(c) = cur.as_mut() {
                c.messages[slot] = Some(msg.data.into_owned());
            }
        }
        flush(&mut cur, &run, &mut parts, &mut keep_going, &mut on_part);
        let run = run.ok_or_else(|| self.format_err(format!("no {TOPIC_RUN} message")))?;
        Ok(Contents {
            run,
            parts,
            complete,
            truncated,
        })
    }
}

/// The messages of one part read so far, by their place in
/// [`PART_CHANNELS`].
struct Gathered {
    index: usize,
    messages: [Option<Vec<u8>>; PART_CHANNELS.len()],
}

impl Gathered {
    /// The part's messages, if there is one on every part channel.
    fn complete(self) -> Option<PartMessages> {
        if self.messages.iter().any(Option::is_none) {
            return None;
        }
        let messages = self.messages.map(Option::unwrap_or_default);
        Some(PartMessages::read(self.index, messages))
    }
}

/// The decoded messages of one part.
pub struct PartRecord {
    /// The part message.
    pub part: PartMsg,
    /// Its ranked fixtures.
    pub fixtures: FixturesMsg,
}

impl PartRecord {
    /// Decodes the part and fixtures messages (the scene is for viewers).
    pub fn decode(m: &PartMessages) -> Result<PartRecord, serde_json::Error> {
        Ok(PartRecord {
            part: m.decode()?,
            fixtures: m.decode()?,
        })
    }
}

/// Calls `f` on each part of the results file at `path` (only the part
/// `part` when given), decoded, in file order; stops at the first error.
/// Fails when `part` names no part of the file. `show` and `render` share it.
pub fn for_each_record(
    path: &Path,
    part: Option<&str>,
    mut f: impl FnMut(&RunMsg, &PartRecord) -> anyhow::Result<()>,
) -> anyhow::Result<Contents> {
    let file = ResultsFile::open(path)?;
    let mut err = None;
    let mut found = false;
    let contents = file.for_each_part(|run, m| {
        let rec = match PartRecord::decode(&m) {
            Ok(r) => r,
            Err(e) => {
                err = Some(anyhow::anyhow!("part {}: {e}", m.index));
                return false;
            }
        };
        if part.is_some_and(|p| p != rec.part.id) {
            return true;
        }
        found = true;
        if let Err(e) = f(run, &rec) {
            err = Some(e);
            return false;
        }
        true
    })?;
    if let Some(e) = err {
        return Err(e);
    }
    if let Some(p) = part {
        if !found {
            anyhow::bail!("{}: no part {p:?}", path.display());
        }
    }
    Ok(contents)
}
