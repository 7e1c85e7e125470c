//! An MCAP file written from finished chunks ([`PartChunk`]). The `mcap`
//! crate's writer compresses the messages it is given itself; a results
//! file's chunks are compressed where their parts were solved, so this
//! writer only lays records out: the crate's own record types (encoded
//! with `binrw`, as the crate does) in the order and with the indexes,
//! statistics and checksums its writer produces. Files are read back with
//! the crate's reader.

use super::chunk::PartChunk;
use super::records::MAGIC;
use binrw::BinWrite;
use mcap::records::{
    op, Channel, ChunkHeader, ChunkIndex, DataEnd, Footer, Header, MessageIndex, MessageIndexEntry,
    Metadata, MetadataIndex, SchemaHeader, Statistics, SummaryOffset,
};
use std::collections::BTreeMap;
use std::io::{Cursor, Write};

/// An MCAP file being written, chunk by chunk.
pub struct McapFile<W: Write> {
    out: W,
    /// Bytes written so far: the next record's offset.
    pos: u64,
    /// CRC of the data section so far, then of the summary section.
    crc: crc32fast::Hasher,
    schemas: Vec<(SchemaHeader, Vec<u8>)>,
    channels: Vec<Channel>,
    chunk_indexes: Vec<ChunkIndex>,
    metadata_indexes: Vec<MetadataIndex>,
    stats: Statistics,
}

/// A record body as the `mcap` crate encodes it.
fn body<T>(record: &T) -> std::io::Result<Vec<u8>>
where
    T: BinWrite,
    for<'a> T::Args<'a>: Default,
{
    let mut c = Cursor::new(Vec::with_capacity(64));
    record.write_le(&mut c).map_err(std::io::Error::other)?;
    Ok(c.into_inner())
}

impl<W: Write> McapFile<W> {
    /// Starts a file: magic and header.
    pub fn new(out: W, profile: &str, library: &str) -> std::io::Result<McapFile<W>> {
        let mut f = McapFile {
            out,
            pos: 0,
            crc: crc32fast::Hasher::new(),
            schemas: Vec::new(),
            channels: Vec::new(),
            chunk_indexes: Vec::new(),
            metadata_indexes: Vec::new(),
            stats: Statistics::default(),
        };
        f.put(MAGIC)?;
        let header = Header {
            profile: profile.into(),
            library: library.into(),
        };
        f.record(op::HEADER, &body(&header)?)?;
        Ok(f)
    }

    fn put(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        self.out.write_all(bytes)?;
        self.crc.update(bytes);
        self.pos += bytes.len() as u64;
        Ok(())
    }

    fn record(&mut self, opcode: u8, body: &[u8]) -> std::io::Result<()> {
        self.record_parts(opcode, &[body])
    }

    /// A record whose body is `parts` one after the other.
    fn record_parts(&mut self, opcode: u8, parts: &[&[u8]]) -> std::io::Result<()> {
        let len: usize = parts.iter().map(|p| p.len()).sum();
        let mut head = [0u8; 9];
        head[0] = opcode;
        head[1..].copy_from_slice(&(len as u64).to_le_bytes());
        self.put(&head)?;
        for p in parts {
            self.put(p)?;
        }
        Ok(())
    }

    fn schema_record(&mut self, header: &SchemaHeader, data: &[u8]) -> std::io::Result<()> {
        let h = body(header)?;
        self.record_parts(op::SCHEMA, &[&h, &(data.len() as u32).to_le_bytes(), data])
    }

    /// Adds a schema (written at once, and again in the summary).
    pub fn schema(
        &mut self,
        id: u16,
        name: &str,
        encoding: &str,
        data: &[u8],
    ) -> std::io::Result<()> {
        let header = SchemaHeader {
            id,
            name: name.into(),
            encoding: encoding.into(),
        };
        self.schema_record(&header, data)?;
        self.schemas.push((header, data.to_vec()));
        Ok(())
    }

    /// Adds a channel (written at once, and again in the summary).
    pub fn channel(&mut self, channel: Channel) -> std::io::Result<()> {
        self.record(op::CHANNEL, &body(&channel)?)?;
        self.channels.push(channel);
        Ok(())
    }

    /// Writes a metadata record.
    pub fn metadata(&mut self, metadata: &Metadata) -> std::io::Result<()> {
        let offset = self.pos;
        self.record(op::METADATA, &body(metadata)?)?;
        self.metadata_indexes.push(MetadataIndex {
            offset,
            length: self.pos - offset,
            name: metadata.name.clone(),
        });
        self.stats.metadata_count += 1;
        Ok(())
    }

    /// Writes a chunk and its message indexes.
    pub fn chunk(&mut self, chunk: &PartChunk) -> std::io::Result<()> {
        let start = self.pos;
        let header = ChunkHeader {
            message_start_time: chunk.log_time,
            message_end_time: chunk.log_time,
            uncompressed_size: chunk.uncompressed_size,
            uncompressed_crc: chunk.uncompressed_crc,
            compression: "zstd".into(),
            compressed_size: chunk.compressed.len() as u64,
        };
        self.record_parts(op::CHUNK, &[&body(&header)?, &chunk.compressed])?;
        let chunk_length = self.pos - start;
        let mut by_channel: BTreeMap<u16, Vec<MessageIndexEntry>> = BTreeMap::new();
        for &(channel, offset) in &chunk.offsets {
            by_channel
                .entry(channel)
                .or_default()
                .push(MessageIndexEntry {
                    log_time: chunk.log_time,
                    offset,
                });
            *self
                .stats
                .channel_message_counts
                .entry(channel)
                .or_default() += 1;
        }
        let index_start = self.pos;
        let mut message_index_offsets = BTreeMap::new();
        for (channel_id, records) in by_channel {
            message_index_offsets.insert(channel_id, self.pos);
            let index = MessageIndex {
                channel_id,
                records,
            };
            self.record(op::MESSAGE_INDEX, &body(&index)?)?;
        }
        let n = chunk.offsets.len() as u64;
        let s = &mut self.stats;
        if n > 0 {
            if s.message_count == 0 {
                (s.message_start_time, s.message_end_time) = (chunk.log_time, chunk.log_time);
            }
            s.message_start_time = s.message_start_time.min(chunk.log_time);
            s.message_end_time = s.message_end_time.max(chunk.log_time);
        }
        s.message_count += n;
        s.chunk_count += 1;
        self.chunk_indexes.push(ChunkIndex {
            message_start_time: chunk.log_time,
            message_end_time: chunk.log_time,
            chunk_start_offset: start,
            chunk_length,
            message_index_offsets,
            message_index_length: self.pos - index_start,
            compression: "zstd".into(),
            compressed_size: chunk.compressed.len() as u64,
            uncompressed_size: chunk.uncompressed_size,
        });
        Ok(())
    }

    /// Hands what was written so far to the underlying writer's flush.
    pub fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
    }

    /// A summary group: the records `write` makes, and its offset record.
    fn group(
        &mut self,
        opcode: u8,
        offsets: &mut Vec<SummaryOffset>,
        write: impl FnOnce(&mut Self) -> std::io::Result<()>,
    ) -> std::io::Result<()> {
        let group_start = self.pos;
        write(self)?;
        if self.pos > group_start {
            offsets.push(SummaryOffset {
                group_opcode: opcode,
                group_start,
                group_length: self.pos - group_start,
            });
        }
        Ok(())
    }

    /// Ends the data section, writes the summary (schemas, channels,
    /// statistics, chunk and metadata indexes), its offsets, the footer
    /// and the closing magic; returns the underlying writer.
    pub fn finish(mut self) -> std::io::Result<W> {
        let data_section_crc = std::mem::take(&mut self.crc).finalize();
        self.record(op::DATA_END, &body(&DataEnd { data_section_crc })?)?;
        self.crc = crc32fast::Hasher::new();
        let summary_start = self.pos;
        let mut offsets = Vec::new();
        let schemas = std::mem::take(&mut self.schemas);
        self.group(op::SCHEMA, &mut offsets, |f| {
            schemas.iter().try_for_each(|(h, d)| f.schema_record(h, d))
        })?;
        let channels = std::mem::take(&mut self.channels);
        self.group(op::CHANNEL, &mut offsets, |f| {
            channels
                .iter()
                .try_for_each(|c| f.record(op::CHANNEL, &body(c)?))
        })?;
        self.stats.schema_count = schemas.len() as u16;
        self.stats.channel_count = channels.len() as u32;
        let stats = std::mem::take(&mut self.stats);
        self.group(op::STATISTICS, &mut offsets, |f| {
            f.record(op::STATISTICS, &body(&stats)?)
        })?;
        let chunks = std::mem::take(&mut self.chunk_indexes);
        self.group(op::CHUNK_INDEX, &mut offsets, |f| {
            chunks
                .iter()
                .try_for_each(|c| f.record(op::CHUNK_INDEX, &body(c)?))
        })?;
        let metadata = std::mem::take(&mut self.metadata_indexes);
        self.group(op::METADATA_INDEX, &mut offsets, |f| {
            metadata
                .iter()
                .try_for_each(|m| f.record(op::METADATA_INDEX, &body(m)?))
        })?;
        let summary_offset_start = self.pos;
        for o in &offsets {
            self.record(op::SUMMARY_OFFSET, &body(o)?)?;
        }
        // The footer's CRC covers the summary up to and including its own
        // first two fields.
        let mut footer = Footer {
            summary_start,
            summary_offset_start,
            summary_crc: 0,
        };
        let mut head = vec![op::FOOTER];
        head.extend_from_slice(&20u64.to_le_bytes());
        head.extend_from_slice(&summary_start.to_le_bytes());
        head.extend_from_slice(&summary_offset_start.to_le_bytes());
        let mut crc = std::mem::take(&mut self.crc);
        crc.update(&head);
        footer.summary_crc = crc.finalize();
        self.record(op::FOOTER, &body(&footer)?)?;
        self.put(MAGIC)?;
        self.out.flush()?;
        Ok(self.out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A message as read back: channel, log time, data.
    type Sent = (u16, u64, Vec<u8>);

    /// A file of `parts` chunks of three messages, and what each holds.
    fn file(parts: u64) -> (Vec<u8>, Vec<Sent>) {
        let mut f = McapFile::new(Vec::new(), "", "test").expect("header");
        for id in 1..=3u16 {
            f.schema(id, &format!("s{id}"), "jsonschema", b"{}")
                .expect("schema");
            f.channel(Channel {
                id,
                schema_id: id,
                topic: format!("/t{id}"),
                message_encoding: "json".into(),
                metadata: BTreeMap::new(),
            })
            .expect("channel");
        }
        f.metadata(&Metadata {
            name: "m".into(),
            metadata: BTreeMap::from([("k".into(), "v".into())]),
        })
        .expect("metadata");
        let mut sent = Vec::new();
        for p in 0..parts {
            let t = p * 1_000;
            let datas: Vec<Vec<u8>> = (1..=3u16)
                .map(|c| format!("{{\"part\":{p},\"channel\":{c}}}").into_bytes())
                .collect();
            let msgs: Vec<(u16, u32, &[u8])> = datas
                .iter()
                .zip(1u16..)
                .map(|(d, c)| (c, p as u32, d.as_slice()))
                .collect();
            f.chunk(&PartChunk::encode(t, &msgs).expect("chunk"))
                .expect("write");
            sent.extend(datas.into_iter().zip(1u16..).map(|(d, c)| (c, t, d)));
        }
        (f.finish().expect("finish"), sent)
    }

    #[test]
    fn the_mcap_crate_reads_what_it_writes_streamed_and_indexed() {
        let (bytes, sent) = file(5);
        // Streamed, with every CRC checked.
        let streamed: Vec<Sent> = mcap::MessageStream::new(&bytes)
            .expect("stream")
            .map(|m| {
                let m = m.expect("message");
                (m.channel.id, m.log_time, m.data.into_owned())
            })
            .collect();
        assert_eq!(streamed, sent);
        // Through the summary: statistics, chunk and message indexes.
        let summary = mcap::Summary::read(&bytes).expect("summary").expect("some");
        let stats = summary.stats.as_ref().expect("statistics");
        assert_eq!(stats.message_count, 15);
        assert_eq!(stats.chunk_count, 5);
        assert_eq!((stats.schema_count, stats.channel_count), (3, 3));
        assert_eq!(
            (stats.message_start_time, stats.message_end_time),
            (0, 4_000)
        );
        assert_eq!(stats.channel_message_counts.get(&2), Some(&5));
        assert_eq!(stats.metadata_count, 1);
        assert_eq!(summary.chunk_indexes.len(), 5);
        let mut indexed = Vec::new();
        for ci in &summary.chunk_indexes {
            let idx = summary.read_message_indexes(&bytes, ci).expect("indexes");
            let mut entries: Vec<_> = idx
                .into_iter()
                .flat_map(|(c, es)| es.into_iter().map(move |e| (c.id, e)))
                .collect();
            entries.sort_by_key(|(c, _)| *c);
            for (c, e) in entries {
                let m = summary.seek_message(&bytes, ci, &e).expect("seek");
                assert_eq!(m.channel.id, c);
                indexed.push((c, m.log_time, m.data.into_owned()));
            }
        }
        assert_eq!(indexed, sent);
        let meta = &summary.metadata_indexes[0];
        let m = mcap::read::metadata(&bytes, meta).expect("metadata");
        assert_eq!(m.metadata.get("k").map(String::as_str), Some("v"));
    }

    #[test]
    fn a_damaged_chunk_fails_its_crc() {
        let (mut bytes, _) = file(2);
        // The last byte of the first chunk's compressed records.
        let summary = mcap::Summary::read(&bytes).expect("summary").expect("some");
        let ci = &summary.chunk_indexes[0];
        let at = (ci.chunk_start_offset + ci.chunk_length - 1) as usize;
        bytes[at] ^= 0xFF;
        let all_ok = mcap::MessageStream::new(&bytes)
            .expect("stream")
            .all(|m| m.is_ok());
        assert!(!all_ok, "a flipped byte must not read back quietly");
    }
}
