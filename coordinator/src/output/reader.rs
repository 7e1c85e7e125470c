//! Reading a results file back, complete or cut short by a kill: the run
//! message, then each part's messages in catalogue order. Every chunk is
//! checked before its part is handed out (lengths, decompression, CRC,
//! one decodable message on each part channel, the part's place), so a
//! damaged part is never read as a sound one: what is damaged is listed,
//! with its byte offset, in [`Contents::damage`].

use super::channels::{PART_CHANNELS, RUN_CHANNEL};
use super::messages::*;
use super::records::{self, op, ChunkRecord, Flaw, Record, Step, MAGIC};
use super::writer::PartMessages;
use std::path::Path;

/// Why a results file cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum ResultsFileError {
    /// The file system refused.
    #[error("{path}: cannot read: {source}")]
    Io {
        /// The file.
        path: String,
        /// What the system said.
        #[source]
        source: std::io::Error,
    },
    /// Not MCAP, or not written by fixplan, or its run message is
    /// damaged: `--resume` starts afresh.
    #[error("{path}: not a fixplan results file: {message}")]
    Format {
        /// The file.
        path: String,
        /// What is wrong with it.
        message: String,
    },
    /// Parts of the file are damaged (the sound ones were read).
    #[error("{path}: damaged: {damage}")]
    Damaged {
        /// The file.
        path: String,
        /// Each damaged place: part and byte offset.
        damage: String,
    },
}

/// A results file read into memory.
pub struct ResultsFile {
    /// Where it was read from, for messages.
    pub path: String,
    bytes: Vec<u8>,
}

/// A damaged place of a results file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Damage {
    /// Byte offset of the damaged record.
    pub offset: u64,
    /// The catalogue index of the part it held, when known, or of the
    /// last sound part before it (`after`).
    pub part: PartPlace,
    /// What is wrong.
    pub message: String,
}

/// Which part a damaged record belongs to, as far as can be told.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PartPlace {
    /// Part `#n` of the catalogue.
    Part(usize),
    /// The record after part `#n` (its own place is unreadable).
    After(usize),
    /// Before any part.
    First,
    /// Outside the parts' records (summary, indexes).
    NoPart,
}

impl std::fmt::Display for Damage {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.part {
            PartPlace::Part(n) => write!(formatter, "part #{n}")?,
            PartPlace::After(n) => write!(formatter, "the part after #{n}")?,
            PartPlace::First => write!(formatter, "the first part")?,
            PartPlace::NoPart => write!(formatter, "outside the parts")?,
        }
        write!(formatter, " at byte {}: {}", self.offset, self.message)
    }
}

/// What a results file holds.
#[derive(Debug)]
pub struct Contents {
    /// The run message (what was run).
    pub run: RunMsg,
    /// Indices of the sound parts, in file order.
    pub parts: Vec<usize>,
    /// False when the file has no footer (an interrupted run).
    pub complete: bool,
    /// Where an interrupted run's file is cut short, if it is.
    pub truncated: Option<String>,
    /// Damaged places, in file order (empty for a sound file).
    pub damage: Vec<Damage>,
}

impl Contents {
    /// Fails, naming the file and each damaged part and offset, when
    /// anything was damaged.
    pub fn sound(&self, path: &str) -> Result<(), ResultsFileError> {
        if self.damage.is_empty() {
            return Ok(());
        }
        let damage = self
            .damage
            .iter()
            .map(Damage::to_string)
            .collect::<Vec<_>>()
            .join("; ");
        Err(ResultsFileError::Damaged {
            path: path.to_string(),
            damage,
        })
    }
}

impl ResultsFile {
    /// Reads the whole file (results files are small: a few kB a part).
    pub fn open(path: &Path) -> Result<ResultsFile, ResultsFileError> {
        let io = |source| ResultsFileError::Io {
            path: path.display().to_string(),
            source,
        };
        let meta = std::fs::metadata(path).map_err(io)?;
        if !meta.is_file() {
            return Err(io(std::io::Error::other("not a regular file")));
        }
        let bytes = std::fs::read(path).map_err(io)?;
        Ok(ResultsFile::from_bytes(path.display().to_string(), bytes))
    }

    /// A file already in memory, named `path` in messages.
    pub fn from_bytes(path: String, bytes: Vec<u8>) -> ResultsFile {
        ResultsFile { path, bytes }
    }

    fn format_err(&self, message: impl Into<String>) -> ResultsFileError {
        ResultsFileError::Format {
            path: self.path.clone(),
            message: message.into(),
        }
    }

    /// Walks the records; calls `on_part` for each sound part, in order,
    /// until it returns false. Damaged parts are skipped and listed in
    /// [`Contents::damage`]; the walk stops where the records cannot be
    /// followed any further (a length past the end, a cut).
    pub fn for_each_part(
        &self,
        mut on_part: impl FnMut(&RunMsg, PartMessages) -> bool,
    ) -> Result<Contents, ResultsFileError> {
        if !self.bytes.starts_with(MAGIC) {
            return Err(self.format_err("it does not start with the MCAP magic"));
        }
        let mut walk = RecordWalk {
            footer: records::footer(&self.bytes),
            run: None,
            last: None,
            damaged_since: 0,
            parts: Vec::new(),
            damage: Vec::new(),
            truncated: None,
            keep_going: true,
        };
        let mut pos = MAGIC.len();
        loop {
            match records::record_at(&self.bytes, pos) {
                Step::End => break,
                Step::Short {
                    offset,
                    opcode,
                    needs,
                    has,
                } => {
                    walk.short(&self.bytes, offset, opcode, needs, has);
                    break;
                }
                Step::Record(r) => {
                    pos = r.offset + 9 + r.body.len();
                    if r.opcode == op::DATA_END {
                        walk.data_end(&self.bytes, r, pos);
                        break;
                    }
                    walk.record(r, &mut on_part)
                        .map_err(|m| self.format_err(m))?;
                }
            }
        }
        let complete = walk.footer.is_some();
        let run = walk.run.ok_or_else(|| match walk.damage.first() {
            Some(d) => self.format_err(format!("no readable {TOPIC_RUN} message ({d})")),
            None => self.format_err(format!("no {TOPIC_RUN} message")),
        })?;
        Ok(Contents {
            run,
            parts: walk.parts,
            complete,
            truncated: walk.truncated,
            damage: walk.damage,
        })
    }
}

/// The state of a walk through a file's data section.
struct RecordWalk {
    footer: Option<records::Footer>,
    run: Option<RunMsg>,
    /// The last sound part.
    last: Option<usize>,
    /// Damaged chunks since it (each presumably one part).
    damaged_since: usize,
    parts: Vec<usize>,
    damage: Vec<Damage>,
    truncated: Option<String>,
    keep_going: bool,
}

impl RecordWalk {
    /// Where a damaged record of unknown part lies.
    fn place(&self) -> PartPlace {
        match self.last {
            Some(n) => PartPlace::After(n),
            None => PartPlace::First,
        }
    }

    fn flaw(&mut self, part: PartPlace, flaw: Flaw) {
        self.damage.push(Damage {
            offset: flaw.offset,
            part,
            message: flaw.message,
        });
    }

    /// One whole record of the data section. Fails only when the run
    /// message is unreadable (nothing else can be trusted then).
    fn record(
        &mut self,
        mcap_record: Record<'_>,
        on_part: &mut dyn FnMut(&RunMsg, PartMessages) -> bool,
    ) -> Result<(), String> {
        match mcap_record.opcode {
            op::HEADER | op::SCHEMA | op::CHANNEL | op::MESSAGE_INDEX | op::METADATA => Ok(()),
            op::CHUNK => self.chunk(mcap_record, on_part),
            other => {
                let place = self.place();
                self.flaw(
                    place,
                    Flaw::at(
                        mcap_record.offset,
                        format!("unexpected record {other:#04x}"),
                    ),
                );
                self.damaged_since += 1;
                Ok(())
            }
        }
    }

    fn chunk(
        &mut self,
        record: Record<'_>,
        on_part: &mut dyn FnMut(&RunMsg, PartMessages) -> bool,
    ) -> Result<(), String> {
        let read = ChunkRecord::parse(record.body).and_then(|c| {
            let records = c.records()?;
            Ok((c, records))
        });
        let (chunk, data) = match read {
            Ok(x) => x,
            Err(message) => {
                let index = ChunkRecord::parse(record.body)
                    .ok()
                    .and_then(|c| self.claimed(&c));
                return self.damaged_chunk(record.offset, index, message);
            }
        };
        let messages = match records::messages(&data) {
            Ok(m) => m,
            Err(message) => return self.damaged_chunk(record.offset, None, message),
        };
        if messages.len() == 1 && messages[0].channel == RUN_CHANNEL.id {
            if self.run.is_some() {
                let place = self.place();
                self.flaw(place, Flaw::at(record.offset, "a second run message"));
                return Ok(());
            }
            let run = serde_json::from_slice(messages[0].data)
                .map_err(|e| format!("{TOPIC_RUN} at byte {}: {e}", record.offset))?;
            self.run = Some(run);
            return Ok(());
        }
        let Some(run) = self.run.as_ref() else {
            return Err(format!(
                "a part's chunk at byte {} comes before the {TOPIC_RUN} message",
                record.offset
            ));
        };
        match part_of(run, &chunk, &messages) {
            Ok(m) => {
                self.part(record.offset, m, on_part);
                Ok(())
            }
            Err((index, message)) => self.damaged_chunk(record.offset, index, message),
        }
    }

    /// The part a damaged chunk's head names, when that is the part
    /// expected next (a damaged head could name any).
    fn claimed(&self, chunk: &ChunkRecord<'_>) -> Option<usize> {
        let time = chunk.start_time;
        if !time.is_multiple_of(NS_PER_PART) || chunk.end_time != time {
            return None;
        }
        let index = usize::try_from(time / NS_PER_PART).ok()?;
        let expected = match self.last {
            Some(last) => index == last + 1 + self.damaged_since,
            None => self.run.as_ref().is_some_and(|r| index < r.catalog.parts),
        };
        expected.then_some(index)
    }

    fn damaged_chunk(
        &mut self,
        offset: usize,
        index: Option<usize>,
        message: String,
    ) -> Result<(), String> {
        if self.run.is_none() {
            return Err(format!(
                "the {TOPIC_RUN} chunk at byte {offset} is damaged: {message}"
            ));
        }
        let place = index.map_or(self.place(), PartPlace::Part);
        self.flaw(place, Flaw::at(offset, message));
        self.damaged_since += 1;
        Ok(())
    }

    /// A sound part: handed out when it comes where it should.
    fn part(
        &mut self,
        offset: usize,
        messages: PartMessages,
        on_part: &mut dyn FnMut(&RunMsg, PartMessages) -> bool,
    ) {
        let index = messages.index;
        if let Some(last) = self.last {
            if index <= last {
                self.flaw(
                    PartPlace::Part(index),
                    Flaw::at(offset, format!("part #{index} comes after part #{last}")),
                );
                return;
            }
            let expected = last + 1 + self.damaged_since;
            if index > expected {
                let missing = format!("parts #{}..#{} are missing", last + 1, index - 1);
                self.flaw(PartPlace::Part(index), Flaw::at(offset, missing));
            }
        }
        self.last = Some(index);
        self.damaged_since = 0;
        self.parts.push(index);
        if let (true, Some(run)) = (self.keep_going, self.run.as_ref()) {
            self.keep_going = on_part(run, messages);
        }
    }

    /// A record that runs past the end: a killed run's last bytes, or a
    /// damaged length.
    fn short(
        &mut self,
        bytes: &[u8],
        offset: usize,
        opcode: Option<u8>,
        needs: Option<u64>,
        has: usize,
    ) {
        let what = match needs {
            Some(n) => format!("a record at byte {offset} needs {n} bytes where {has} are left"),
            None => format!("a record at byte {offset} is cut inside its head"),
        };
        let known = opcode.is_some_and(|o| {
            [
                op::HEADER,
                op::SCHEMA,
                op::CHANNEL,
                op::CHUNK,
                op::MESSAGE_INDEX,
                op::METADATA,
                op::DATA_END,
            ]
            .contains(&o)
        });
        let consistent = opcode != Some(op::CHUNK) || chunk_length_fits(&bytes[offset..], needs);
        if self.footer.is_none() && known && consistent {
            self.truncated = Some(what);
        } else {
            let place = self.place();
            self.flaw(
                place,
                Flaw::at(offset, format!("{what}: the records after it are lost")),
            );
        }
    }

    /// The end of the data section of a complete file: its CRC, then the
    /// summary's.
    fn data_end(&mut self, bytes: &[u8], record: Record<'_>, summary_start: usize) {
        if !self.damage.is_empty() {
            return;
        }
        let crc = crc32fast::hash(&bytes[..record.offset]);
        match records::data_end_crc(record.body) {
            Ok(want) if want == 0 || want == crc => {}
            Ok(want) => self.flaw(
                PartPlace::NoPart,
                Flaw::at(
                    record.offset,
                    format!("the data section has CRC {crc:#010x}, not the {want:#010x} written (damage outside the parts' chunks)"),
                ),
            ),
            Err(m) => self.flaw(PartPlace::NoPart, Flaw::at(record.offset, m)),
        }
        match self.footer {
            Some(footer) => {
                if let Some(flaw) = records::summary_flaw(bytes, &footer, summary_start) {
                    self.flaw(PartPlace::NoPart, flaw);
                }
            }
            None => {
                self.truncated = Some(format!(
                    "the file ends inside its summary (byte {summary_start} on)"
                ))
            }
        }
    }
}

/// Whether a chunk cut short at the end of the file has a head that
/// agrees with its record's length (a kill), rather than a damaged one.
fn chunk_length_fits(record: &[u8], needs: Option<u64>) -> bool {
    let (Some(needs), Some(head)) = (needs, record.get(9..)) else {
        return true;
    };
    let mut f = records::Fields::of(head);
    let compressed = (|| {
        f.take(28, "chunk head")?;
        let n = f.u32("compression")?;
        if n != 4 {
            return Err(String::new());
        }
        f.take(4, "compression")?;
        f.u64("compressed size")
    })();
    match compressed {
        Ok(size) => size.checked_add(9 + 44) == Some(needs),
        Err(e) => e.contains("left"),
    }
}

/// The part a chunk holds, checked: one message on each part channel in
/// order, all at the chunk's time, each decodable, the part message
/// naming the chunk's place and the fixtures the same part. On failure,
/// the part's index if it could be told and what is wrong.
fn part_of(
    run: &RunMsg,
    chunk: &ChunkRecord<'_>,
    messages: &[records::MessageRecord<'_>],
) -> Result<PartMessages, (Option<usize>, String)> {
    let time = chunk.start_time;
    let index = (time.is_multiple_of(NS_PER_PART) && chunk.end_time == time)
        .then_some(time / NS_PER_PART)
        .and_then(|i| usize::try_from(i).ok())
        .filter(|&i| i < run.catalog.parts);
    let Some(index) = index else {
        return Err((None, format!("chunk log time {time} is no part's place")));
    };
    let fail = |m: String| (Some(index), m);
    let channels: Vec<u16> = messages.iter().map(|m| m.channel).collect();
    if !channels
        .iter()
        .eq(PART_CHANNELS.iter().map(|c| &c.channel.id))
    {
        return Err(fail(format!("its messages are on channels {channels:?}")));
    }
    if let Some(m) = messages.iter().find(|m| m.log_time != time) {
        return Err(fail(format!(
            "a message is logged at {}, not {time}",
            m.log_time
        )));
    }
    for (m, c) in messages.iter().zip(&PART_CHANNELS) {
        if let Err(e) = serde_json::from_slice::<serde::de::IgnoredAny>(m.data) {
            return Err(fail(format!("{}: {e}", c.channel.topic)));
        }
    }
    let data: [Vec<u8>; PART_CHANNELS.len()] = std::array::from_fn(|i| messages[i].data.to_vec());
    let parts = PartMessages::read(index, data);
    // Only the fields that place the part: a sound file's fixtures may
    // hold values its full types do not read back (a non-finite score is
    // written as null), and they are copied as they are.
    let head = |topic: &str| -> Result<Placed, (Option<usize>, String)> {
        let data = parts.get(topic).unwrap_or_default();
        serde_json::from_slice(data).map_err(|e| fail(format!("{topic}: {e}")))
    };
    let part = head(TOPIC_PART)?;
    let fixtures = head(TOPIC_FIXTURES)?;
    if part.index != Some(index) {
        return Err(fail(format!(
            "its part message is of part #{:?}",
            part.index
        )));
    }
    if part.id.is_none() || fixtures.part != part.id {
        return Err(fail(format!(
            "its fixtures are of part {:?}, not {:?}",
            fixtures.part, part.id
        )));
    }
    Ok(parts)
}

/// What places a part's messages: its index and id (part message), the
/// part id (fixtures message).
#[derive(serde::Deserialize)]
struct Placed {
    #[serde(default)]
    index: Option<usize>,
    #[serde(default)]
    id: Option<String>,
    #[serde(default)]
    part: Option<String>,
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
    pub fn decode(messages: &PartMessages) -> Result<PartRecord, serde_json::Error> {
        Ok(PartRecord {
            part: messages.decode()?,
            fixtures: messages.decode()?,
        })
    }
}

/// Calls `visit` on each sound part of the results file at `path`, its
/// messages decoded by `decode`, in file order; stops at the first error,
/// a message that does not decode named by file and part. Fails, after
/// the sound parts, when the file is damaged. Every reader of parts
/// (`show`, `render`, `export`) goes through it, so their errors read
/// alike.
pub fn for_each_decoded<T>(
    path: &Path,
    decode: impl Fn(&PartMessages) -> serde_json::Result<T>,
    mut visit: impl FnMut(&RunMsg, T) -> anyhow::Result<()>,
) -> anyhow::Result<Contents> {
    let file = ResultsFile::open(path)?;
    let mut err = None;
    let contents = file.for_each_part(|run, m| {
        let outcome = decode(&m)
            .map_err(|e| anyhow::anyhow!("{}: part #{}: {e}", path.display(), m.index))
            .and_then(|decoded| visit(run, decoded));
        match outcome {
            Ok(()) => true,
            Err(e) => {
                err = Some(e);
                false
            }
        }
    })?;
    if let Some(e) = err {
        return Err(e);
    }
    contents.sound(&file.path)?;
    Ok(contents)
}

/// Calls `on_record` on each sound part of the results file at `path` (only the
/// part `part` when given), decoded, in file order; stops at the first
/// error. Fails when `part` names no part of the file, and, after the
/// sound parts, when the file is damaged. `show` and `render` share it.
pub fn for_each_record(
    path: &Path,
    part: Option<&str>,
    mut on_record: impl FnMut(&RunMsg, &PartRecord) -> anyhow::Result<()>,
) -> anyhow::Result<Contents> {
    let mut found = false;
    let contents = for_each_decoded(path, PartRecord::decode, |run, record| {
        if part.is_some_and(|p| p != record.part.id) {
            return Ok(());
        }
        found = true;
        on_record(run, &record)
    })?;
    if let Some(p) = part {
        if !found {
            anyhow::bail!("{}: no part {p:?}", path.display());
        }
    }
    Ok(contents)
}
