//! The results file: one message type per MCAP channel, their JSON
//! Schemas, finished chunks and the MCAP file written from them, the writer (chunk per
//! part, resumable) and the reader.
//! Uses `job` (the types a part's messages carry) and the core crate.

pub mod chunk;
pub mod mcap_file;
pub mod messages;
pub mod reader;
pub mod schemas;
pub mod writer;

pub use chunk::PartChunk;
pub use reader::{PartRecord, ReadError, ResultsFile};
pub use writer::{PartMessages, ResultsWriter};
