//! The records of a results file walked by hand, every length checked
//! against the bytes that are there before anything is sliced or
//! allocated. The `mcap` crate's reader trusts a record's length (a
//! flipped byte made it ask for exabytes, or panic) and hands out a
//! chunk's messages before its CRC is checked; this walk does neither, so
//! a damaged file is told apart from a sound one, byte offset included.
//! Only the records fixplan writes are understood ([`super::mcap_file`]).

use std::io::Read;

/// The MCAP magic, at both ends of a file.
pub const MAGIC: &[u8] = b"\x89MCAP0\r\n";

/// Opcodes of the records a results file holds.
pub(crate) mod op {
    /// Header (first record).
    pub const HEADER: u8 = 0x01;
    /// Footer (last record).
    pub const FOOTER: u8 = 0x02;
    /// Schema.
    pub const SCHEMA: u8 = 0x03;
    /// Channel.
    pub const CHANNEL: u8 = 0x04;
    /// Message (inside chunks only).
    pub const MESSAGE: u8 = 0x05;
    /// Chunk: a part's (or the run's) messages, compressed.
    pub const CHUNK: u8 = 0x06;
    /// Message index (after each chunk).
    pub const MESSAGE_INDEX: u8 = 0x07;
    /// Metadata (the run's).
    pub const METADATA: u8 = 0x0C;
    /// End of the data section, with its CRC.
    pub const DATA_END: u8 = 0x0F;
}

/// A chunk's records may be at most this many times its compressed bytes
/// (plus [`INFLATE_SLACK`]): fixplan's JSON compresses about tenfold, and
/// a damaged size field must not make a reader allocate gigabytes.
pub const MAX_INFLATION: u64 = 64;

/// Bytes every chunk may inflate to whatever its compressed size (small
/// chunks compress worse).
pub const INFLATE_SLACK: u64 = 64 * 1024;

/// What is wrong at one place of a file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Flaw {
    /// Byte offset in the file of the record (or field) at fault.
    pub offset: u64,
    /// What is wrong there.
    pub message: String,
}

impl Flaw {
    /// A flaw at `offset`.
    pub fn at(offset: usize, message: impl Into<String>) -> Flaw {
        Flaw {
            offset: offset as u64,
            message: message.into(),
        }
    }
}

/// A record of the file: its opcode, where it starts and its body.
#[derive(Debug, Clone, Copy)]
pub struct Record<'a> {
    /// Offset of its opcode in the file.
    pub offset: usize,
    /// Its opcode.
    pub opcode: u8,
    /// Its body (length checked against the file).
    pub body: &'a [u8],
}

/// What the walk found after a record.
#[derive(Debug)]
pub enum Step<'a> {
    /// A whole record.
    Record(Record<'a>),
    /// The bytes end (no more records).
    End,
    /// A record that does not fit the bytes left: `needs` bytes from
    /// `offset` where only `has` are there.
    Short {
        /// Where the record starts.
        offset: usize,
        /// Its opcode, if that byte is there.
        opcode: Option<u8>,
        /// What its head says it needs (head included), if the head is there.
        needs: Option<u64>,
        /// Bytes left from `offset`.
        has: usize,
    },
}

/// The record at `pos` of `bytes`.
pub fn record_at(bytes: &[u8], pos: usize) -> Step<'_> {
    let has = bytes.len().saturating_sub(pos);
    if has == 0 {
        return Step::End;
    }
    let opcode = bytes[pos];
    let Some(len) = bytes.get(pos + 1..pos + 9).map(le_u64) else {
        return Step::Short {
            offset: pos,
            opcode: Some(opcode),
            needs: None,
            has,
        };
    };
    match usize::try_from(len).ok().filter(|&l| l <= has - 9) {
        Some(l) => Step::Record(Record {
            offset: pos,
            opcode,
            body: &bytes[pos + 9..pos + 9 + l],
        }),
        None => Step::Short {
            offset: pos,
            opcode: Some(opcode),
            needs: Some(len.saturating_add(9)),
            has,
        },
    }
}

fn le_u64(bytes: &[u8]) -> u64 {
    let mut a = [0u8; 8];
    a.copy_from_slice(&bytes[..8]);
    u64::from_le_bytes(a)
}

/// Reads a record body's fields in order, every length checked.
pub struct Fields<'a> {
    body: &'a [u8],
    pos: usize,
}

impl<'a> Fields<'a> {
    /// The fields of `body`.
    pub fn of(body: &'a [u8]) -> Fields<'a> {
        Fields { body, pos: 0 }
    }

    /// The next `count` bytes.
    pub fn take(&mut self, count: u64, what: &str) -> Result<&'a [u8], String> {
        let left = self.body.len() - self.pos;
        match usize::try_from(count).ok().filter(|&count| count <= left) {
            Some(count) => {
                self.pos += count;
                Ok(&self.body[self.pos - count..self.pos])
            }
            None => Err(format!("{what} needs {count} bytes where {left} are left")),
        }
    }

    /// A little-endian u16.
    pub fn u16(&mut self, what: &str) -> Result<u16, String> {
        let b = self.take(2, what)?;
        Ok(u16::from_le_bytes([b[0], b[1]]))
    }

    /// A little-endian u32.
    pub fn u32(&mut self, what: &str) -> Result<u32, String> {
        let b = self.take(4, what)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    /// A little-endian u64.
    pub fn u64(&mut self, what: &str) -> Result<u64, String> {
        Ok(le_u64(self.take(8, what)?))
    }

    /// A string prefixed by its u32 length.
    pub fn string(&mut self, what: &str) -> Result<&'a str, String> {
        let n = self.u32(what)?;
        let b = self.take(u64::from(n), what)?;
        std::str::from_utf8(b).map_err(|_| format!("{what} is not UTF-8"))
    }

    /// Whatever is left.
    pub fn rest(&mut self) -> &'a [u8] {
        let r = &self.body[self.pos..];
        self.pos = self.body.len();
        r
    }

    /// Whether every byte was read.
    pub fn is_done(&self) -> bool {
        self.pos == self.body.len()
    }
}

/// A chunk record's header and compressed records.
#[derive(Debug, Clone, Copy)]
pub struct ChunkRecord<'a> {
    /// Log time of its first message.
    pub start_time: u64,
    /// Log time of its last message.
    pub end_time: u64,
    /// Size of its records once decompressed.
    pub uncompressed_size: u64,
    /// CRC-32 of those records.
    pub uncompressed_crc: u32,
    /// The compressed records.
    pub compressed: &'a [u8],
}

impl<'a> ChunkRecord<'a> {
    /// Parses a chunk record's body: a zstd chunk whose compressed size is
    /// the rest of the record.
    pub fn parse(body: &'a [u8]) -> Result<ChunkRecord<'a>, String> {
        let mut f = Fields::of(body);
        let start_time = f.u64("chunk start time")?;
        let end_time = f.u64("chunk end time")?;
        let uncompressed_size = f.u64("chunk uncompressed size")?;
        let uncompressed_crc = f.u32("chunk CRC")?;
        let compression = f.string("chunk compression")?;
        if compression != "zstd" {
            return Err(format!("chunk compression {compression:?} is not zstd"));
        }
        let size = f.u64("chunk compressed size")?;
        let compressed = f.take(size, "chunk records")?;
        if !f.is_done() {
            return Err(format!(
                "chunk record is longer than its {size} compressed bytes"
            ));
        }
        Ok(ChunkRecord {
            start_time,
            end_time,
            uncompressed_size,
            uncompressed_crc,
            compressed,
        })
    }

    /// The chunk's records, decompressed and checked against its size and
    /// CRC. Memory grows with what the frame really holds, up to the
    /// declared size, itself bounded by [`MAX_INFLATION`].
    pub fn records(&self) -> Result<Vec<u8>, String> {
        let size = self.uncompressed_size;
        let bound = (self.compressed.len() as u64)
            .saturating_mul(MAX_INFLATION)
            .saturating_add(INFLATE_SLACK);
        if size > bound {
            return Err(format!(
                "chunk says it inflates to {size} bytes, more than {MAX_INFLATION} times its {} compressed bytes",
                self.compressed.len()
            ));
        }
        let decoder = zstd::stream::read::Decoder::with_buffer(self.compressed)
            .map_err(|e| format!("chunk does not decompress: {e}"))?;
        let mut records = Vec::new();
        decoder
            .take(size + 1)
            .read_to_end(&mut records)
            .map_err(|e| format!("chunk does not decompress: {e}"))?;
        if records.len() as u64 != size {
            return Err(format!(
                "chunk decompresses to {} bytes, not the {size} it declares",
                records.len()
            ));
        }
        let crc = crc32fast::hash(&records);
        if crc != self.uncompressed_crc {
            return Err(format!(
                "chunk's records have CRC {crc:#010x}, not the {:#010x} written",
                self.uncompressed_crc
            ));
        }
        Ok(records)
    }
}

/// A message record of a chunk's records.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MessageRecord<'a> {
    /// Its channel.
    pub channel: u16,
    /// Its log time.
    pub log_time: u64,
    /// Its data.
    pub data: &'a [u8],
}

/// The message records of a chunk's `records`, in order; fails on any
/// other record or on a length that does not fit.
pub fn messages(records: &[u8]) -> Result<Vec<MessageRecord<'_>>, String> {
    let mut out = Vec::new();
    let mut pos = 0;
    loop {
        match record_at(records, pos) {
            Step::End => return Ok(out),
            Step::Short { offset, .. } => {
                return Err(format!(
                    "a record at byte {offset} of the chunk's records runs past their end"
                ))
            }
            Step::Record(r) if r.opcode != op::MESSAGE => {
                return Err(format!(
                    "record {:#04x} at byte {} of the chunk's records is not a message",
                    r.opcode, r.offset
                ))
            }
            Step::Record(r) => {
                let mut f = Fields::of(r.body);
                let channel = f.u16("message channel")?;
                f.u32("message sequence")?;
                let log_time = f.u64("message log time")?;
                f.u64("message publish time")?;
                out.push(MessageRecord {
                    channel,
                    log_time,
                    data: f.rest(),
                });
                pos = r.offset + 9 + r.body.len();
            }
        }
    }
}

/// The footer of a complete file: where its summary starts, if the file
/// ends with a footer and the magic. Its CRC is checked by [`summary_flaw`].
#[derive(Debug, Clone, Copy)]
pub struct Footer {
    /// Offset of the footer record.
    pub offset: usize,
    /// Offset of the summary section (0: none).
    pub summary_start: u64,
    /// CRC of the summary section up to the footer's CRC field.
    pub summary_crc: u32,
}

/// Bytes of the footer record (opcode, length, three fields).
const FOOTER_LEN: usize = 1 + 8 + 8 + 8 + 4;

/// The footer, when the file ends with one and the closing magic: a
/// run that finished (a killed run's file ends anywhere).
pub fn footer(bytes: &[u8]) -> Option<Footer> {
    let n = bytes.len();
    if n < MAGIC.len() * 2 + FOOTER_LEN || !bytes.ends_with(MAGIC) {
        return None;
    }
    let offset = n - MAGIC.len() - FOOTER_LEN;
    let Step::Record(r) = record_at(bytes, offset) else {
        return None;
    };
    if r.opcode != op::FOOTER || r.body.len() != FOOTER_LEN - 9 {
        return None;
    }
    let mut f = Fields::of(r.body);
    let summary_start = f.u64("summary start").ok()?;
    f.u64("summary offset start").ok()?;
    let summary_crc = f.u32("summary CRC").ok()?;
    Some(Footer {
        offset,
        summary_start,
        summary_crc,
    })
}

/// What is wrong with a complete file's summary section, if anything: it
/// must start inside the file, right after the data end record, and match
/// the footer's CRC.
pub fn summary_flaw(bytes: &[u8], footer: &Footer, data_end: usize) -> Option<Flaw> {
    let start = footer.summary_start;
    if start != data_end as u64 {
        return Some(Flaw::at(
            footer.offset,
            format!(
                "the footer puts the summary at byte {start}, not after the data (byte {data_end})"
            ),
        ));
    }
    // The CRC covers the summary and the footer up to its CRC field.
    let covered = &bytes[data_end..footer.offset + FOOTER_LEN - 4];
    let crc = crc32fast::hash(covered);
    (footer.summary_crc != 0 && crc != footer.summary_crc).then(|| {
        Flaw::at(
            data_end,
            format!(
                "the summary has CRC {crc:#010x}, not the {:#010x} its footer says",
                footer.summary_crc
            ),
        )
    })
}

/// The data section CRC a data end record holds.
pub fn data_end_crc(body: &[u8]) -> Result<u32, String> {
    let mut f = Fields::of(body);
    let crc = f.u32("data section CRC")?;
    if !f.is_done() {
        return Err("data end record is longer than its CRC".into());
    }
    Ok(crc)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_record_longer_than_the_bytes_is_short_not_sliced() {
        let mut bytes = vec![op::CHUNK];
        bytes.extend_from_slice(&u64::MAX.to_le_bytes());
        bytes.extend_from_slice(b"abc");
        match record_at(&bytes, 0) {
            Step::Short { needs, has, .. } => {
                assert_eq!(needs, Some(u64::MAX));
                assert_eq!(has, 12);
            }
            other => panic!("{other:?}"),
        }
        let mut ok = vec![op::HEADER];
        ok.extend_from_slice(&3u64.to_le_bytes());
        ok.extend_from_slice(b"abc");
        assert!(matches!(record_at(&ok, 0), Step::Record(r) if r.body == b"abc"));
        assert!(matches!(record_at(&ok, ok.len()), Step::End));
        assert!(matches!(record_at(&ok, 4), Step::Short { needs: None, .. }));
    }

    #[test]
    fn fields_refuse_lengths_past_the_body() {
        let mut body = Vec::new();
        body.extend_from_slice(&u32::MAX.to_le_bytes());
        body.extend_from_slice(b"zstd");
        let e = Fields::of(&body).string("compression").unwrap_err();
        assert!(e.contains("4294967295 bytes where 4 are left"), "{e}");
    }

    #[test]
    fn a_chunk_that_claims_to_inflate_hugely_is_refused_before_allocating() {
        let compressed = zstd::bulk::compress(b"hello", 1).unwrap();
        let chunk = ChunkRecord {
            start_time: 0,
            end_time: 0,
            uncompressed_size: 1 << 40,
            uncompressed_crc: crc32fast::hash(b"hello"),
            compressed: &compressed,
        };
        assert!(chunk.records().unwrap_err().contains("inflates"));
        let right = ChunkRecord {
            uncompressed_size: 5,
            ..chunk
        };
        assert_eq!(right.records().unwrap(), b"hello");
        let wrong_crc = ChunkRecord {
            uncompressed_crc: 1,
            ..right
        };
        assert!(wrong_crc.records().unwrap_err().contains("CRC"));
        let wrong_size = ChunkRecord {
            uncompressed_size: 4,
            ..right
        };
        assert!(wrong_size.records().unwrap_err().contains("decompresses"));
    }
}
