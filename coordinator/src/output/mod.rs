//! The results file: its channels (one list), one message type per
//! channel (the file's own types, made of [`fields`]), their JSON
//! Schemas, finished chunks and the MCAP file written from them, the
//! writer (chunk per part, resumable) and the reader.
//! The Foxglove scene is one of its messages ([`scene`]). Uses `job` (the
//! types a part's messages carry), `drawing` (what the scene draws) and
//! the core crate.

pub(crate) mod channels;
pub(crate) mod chunk;
pub(crate) mod fields;
pub(crate) mod fixture_fields;
pub(crate) mod mcap_file;
pub(crate) mod messages;
pub(crate) mod reader;
pub(crate) mod records;
pub(crate) mod scene;
pub(crate) mod schemas;
pub(crate) mod writer;

pub use chunk::PartChunk;
pub use reader::{PartRecord, ResultsFile, ResultsFileError};
pub use writer::{PartMessages, ResultsWriter};
