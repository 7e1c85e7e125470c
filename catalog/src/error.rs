//! Errors of loading a catalogue or a kit as a whole. A part's own problem
//! is not one of these: it stays with the part (see
//! [`CatalogPart::part`](crate::CatalogPart::part)) so the others go on.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum CatalogError {
    #[error("{path}: {message}")]
    Invalid { path: PathBuf, message: String },
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}
