//! A part's messages as one finished MCAP chunk: records laid out,
//! compressed and checksummed wherever the part was solved (a worker, or a
//! solving thread of the embedded run), so that writing the results file
//! is a copy. Compressing was most of the coordinator's work per part.

use super::channels::PART_CHANNELS;
use bytes::Bytes;
use serde::{Deserialize, Serialize};
use std::cell::RefCell;

/// zstd level of every chunk: the fastest, as the MCAP writer used before
/// (the files are small beside the enumeration's time; a worker's CPU is
/// better spent enumerating).
const LEVEL: i32 = 1;

/// MCAP opcode of a message record.
const OP_MESSAGE: u8 = 0x05;

/// One chunk of a results file, ready to be copied into it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PartChunk {
    /// Log time of every message of the chunk (the part's place in the
    /// catalogue, [`super::messages::NS_PER_PART`] apart).
    pub log_time: u64,
    /// The records' bytes before compression.
    pub uncompressed_size: u64,
    /// CRC-32 of those bytes.
    pub uncompressed_crc: u32,
    /// The records, zstd-compressed. Not in the serde form: a finished
    /// part carries them raw after its head (`run::finish`), so that the
    /// coordinator copies them from the buffer they arrived in.
    #[serde(skip)]
    pub compressed: Bytes,
    /// Channel of each message and its record's offset in the
    /// uncompressed records (the chunk's message indexes).
    pub offsets: Vec<(u16, u64)>,
}

thread_local! {
    /// One zstd context per thread: making one per chunk cost as much as
    /// compressing a small part.
    static COMPRESSOR: RefCell<Option<zstd::bulk::Compressor<'static>>> = const { RefCell::new(None) };
}

thread_local! {
    /// One zstd context per thread for the chunks the coordinator checks
    /// (its verification sample): making one per chunk costs a large share
    /// of decompressing a small one.
    static DECOMPRESSOR: RefCell<Option<zstd::bulk::Decompressor<'static>>> = const { RefCell::new(None) };
}

/// The records of a chunk compressed elsewhere, `size` bytes at most.
fn decompress(compressed: &[u8], size: usize) -> std::io::Result<Vec<u8>> {
    DECOMPRESSOR.with(|d| {
        let mut d = d.borrow_mut();
        if d.is_none() {
            *d = Some(zstd::bulk::Decompressor::new()?);
        }
        match d.as_mut() {
            Some(z) => z.decompress(compressed, size),
            None => Err(std::io::Error::other("no zstd context")),
        }
    })
}

fn compress(records: &[u8]) -> std::io::Result<Vec<u8>> {
    COMPRESSOR.with(|c| {
        let mut c = c.borrow_mut();
        if c.is_none() {
            *c = Some(zstd::bulk::Compressor::new(LEVEL)?);
        }
        match c.as_mut() {
            Some(z) => z.compress(records),
            None => Err(std::io::Error::other("no zstd context")),
        }
    })
}

impl PartChunk {
    /// The chunk of `messages` (channel, sequence, data), all logged at
    /// `log_time`, in this order.
    pub fn encode(log_time: u64, messages: &[(u16, u32, &[u8])]) -> std::io::Result<PartChunk> {
        let (records, mut chunk) = PartChunk::laid_out(log_time, messages);
        chunk.compressed = compress(&records)?.into();
        Ok(chunk)
    }

    /// [`PartChunk::encode`] without the compressed bytes (empty): what
    /// the chunk holds by its sizes and CRC, for comparing a chunk made
    /// elsewhere without compressing this one.
    pub fn unpacked(log_time: u64, messages: &[(u16, u32, &[u8])]) -> PartChunk {
        PartChunk::laid_out(log_time, messages).1
    }

    /// Whether `other` holds the records this chunk describes: the same
    /// time, sizes, CRC and offsets, and compressed bytes that decompress
    /// to records of that size and CRC (the compressed bytes themselves may
    /// differ with another zstd build).
    pub fn holds_same(&self, other: &PartChunk) -> Result<(), String> {
        let index = |c: &PartChunk| {
            (
                c.log_time,
                c.uncompressed_size,
                c.uncompressed_crc,
                c.offsets.clone(),
            )
        };
        if index(self) != index(other) {
            return Err("its messages differ (sizes or CRC)".into());
        }
        let records = decompress(&other.compressed, self.uncompressed_size as usize)
            .map_err(|e| format!("its chunk does not decompress: {e}"))?;
        if records.len() as u64 != self.uncompressed_size
            || crc32fast::hash(&records) != self.uncompressed_crc
        {
            return Err("its chunk does not hold its messages".into());
        }
        Ok(())
    }

    /// Whether this chunk, made elsewhere, has the shape of part
    /// `index`'s: its log time, one message on each of [`PART_CHANNELS`] in order
    /// at offsets inside its records, and a zstd frame that declares its
    /// records' size. The coordinator copies unchecked chunks into the
    /// results file; this keeps a worker's bug from making a part
    /// unreadable there or misplacing it on the timeline, at the cost of
    /// reading a frame header (the contents are checked on the sample).
    pub fn fits(&self, log_time: u64) -> Result<(), String> {
        if self.log_time != log_time {
            return Err(format!("its log time is {}, not {log_time}", self.log_time));
        }
        let channels: Vec<u16> = self.offsets.iter().map(|o| o.0).collect();
        if !channels
            .iter()
            .eq(PART_CHANNELS.iter().map(|c| &c.channel.id))
        {
            return Err(format!("its messages are on channels {channels:?}"));
        }
        let starts = self.offsets.iter().map(|o| o.1);
        if self.offsets.first().map(|o| o.1) != Some(0)
            || starts.clone().zip(starts.skip(1)).any(|(a, b)| a >= b)
            || self.offsets.last().map(|o| o.1) >= Some(self.uncompressed_size)
        {
            return Err(format!(
                "its message offsets {:?} do not fit {} bytes",
                self.offsets, self.uncompressed_size
            ));
        }
        match zstd::zstd_safe::get_frame_content_size(&self.compressed) {
            Ok(Some(n)) if n == self.uncompressed_size => Ok(()),
            _ => Err(format!(
                "its compressed bytes are not a zstd frame of {} bytes",
                self.uncompressed_size
            )),
        }
    }

    /// The records of `messages` and the chunk's index of them (nothing
    /// compressed yet).
    fn laid_out(log_time: u64, messages: &[(u16, u32, &[u8])]) -> (Vec<u8>, PartChunk) {
        let size: usize = messages.iter().map(|m| 31 + m.2.len()).sum();
        let mut records = Vec::with_capacity(size);
        let mut offsets = Vec::with_capacity(messages.len());
        for &(channel, sequence, data) in messages {
            offsets.push((channel, records.len() as u64));
            records.push(OP_MESSAGE);
            records.extend_from_slice(&(22 + data.len() as u64).to_le_bytes());
            records.extend_from_slice(&channel.to_le_bytes());
            records.extend_from_slice(&sequence.to_le_bytes());
            records.extend_from_slice(&log_time.to_le_bytes());
            records.extend_from_slice(&log_time.to_le_bytes());
            records.extend_from_slice(data);
        }
        let chunk = PartChunk {
            log_time,
            uncompressed_size: records.len() as u64,
            uncompressed_crc: crc32fast::hash(&records),
            compressed: Bytes::new(),
            offsets,
        };
        (records, chunk)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chunk with a message on every part channel, as a part's.
    fn part_chunk(log_time: u64) -> PartChunk {
        let datas: Vec<String> = PART_CHANNELS
            .iter()
            .map(|c| format!("{{\"topic\":{:?}}}", c.channel.topic))
            .collect();
        let messages: Vec<(u16, u32, &[u8])> = PART_CHANNELS
            .iter()
            .zip(&datas)
            .map(|(c, d)| (c.channel.id, 7, d.as_bytes()))
            .collect();
        PartChunk::encode(log_time, &messages).expect("compress")
    }

    #[test]
    fn a_part_chunk_fits_its_place_and_nothing_else() {
        let ok = part_chunk(7_000);
        assert_eq!(ok.fits(7_000), Ok(()));
        assert!(ok.fits(8_000).unwrap_err().contains("log time"));
        let mut swapped = ok.clone();
        swapped.offsets.swap(0, 1);
        assert!(swapped.fits(7_000).unwrap_err().contains("channels"));
        let mut short = ok.clone();
        short.uncompressed_size = short.offsets[short.offsets.len() - 1].1;
        assert!(short.fits(7_000).unwrap_err().contains("offsets"));
        let mut size = ok.clone();
        size.uncompressed_size += 1;
        assert!(size.fits(7_000).unwrap_err().contains("zstd"));
        let mut junk = ok.clone();
        junk.compressed = Bytes::from_static(b"not zstd");
        assert!(junk.fits(7_000).unwrap_err().contains("zstd"));
        let mut missing = ok;
        missing.offsets.pop();
        assert!(missing.fits(7_000).is_err());
    }

    #[test]
    fn a_chunk_holds_the_records_it_describes() {
        let ok = part_chunk(0);
        assert_eq!(ok.holds_same(&ok), Ok(()));
        let mut other = part_chunk(0);
        other.compressed = part_chunk(1).compressed;
        assert!(ok.holds_same(&other).is_err());
    }
}
