//! The results file: its channels (one list), one message type per
//! channel (the file's own types, made of [`fields`]), their JSON
//! Schemas, finished chunks and the MCAP file written from them, the
//! writer (chunk per part, resumable) and the reader.
//! The Foxglove scene is one of its messages ([`scene`]). Uses `job` (the
//! types a part's messages carry), `drawing` (what the scene draws) and
//! the core crate.

pub mod channels;
pub mod chunk;
pub mod fields;
pub mod fixture_fields;
pub mod mcap_file;
pub mod messages;
pub mod reader;
pub mod records;
pub mod scene;
pub mod schemas;
pub mod writer;

pub use chunk::PartChunk;
pub use reader::{PartRecord, ResultsFile, ResultsFileError};
pub use writer::{PartMessages, ResultsWriter};
