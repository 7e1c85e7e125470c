//! Errors of loading a catalogue: [`CatalogError`] when the catalogue or
//! kit as a whole cannot be used, [`PartError`] for one part, which stays
//! with that part (see [`CatalogPart::part`](crate::CatalogPart::part)) so
//! that the others go on.

use crate::part::{InvalidPolygon, ReadError};
use fixplan_core::Part;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Why a catalogue or a kit cannot be loaded at all.
#[derive(Debug, thiserror::Error)]
pub enum CatalogError {
    /// The manifest or kit file says something unusable.
    #[error("{path}: {message}")]
    Invalid {
        /// The manifest or kit file (a kit name for a built-in kit).
        path: PathBuf,
        /// What is wrong, for the user.
        message: String,
    },
    /// The manifest, kit file or directory cannot be read.
    #[error("{path}: {source}")]
    Io {
        /// What could not be read.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
}

/// Why one catalogue part cannot be used. Its message names the part, and
/// its file when it has one ("bracket-7 (parts/bracket-7.dxf): ..."), so it
/// can be shown as it is among the results of the other parts.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{}: {kind}", part_name(.id, .file.as_deref()))]
pub struct PartError {
    /// The part's catalogue id (`part #N` for an entry without a readable
    /// id).
    pub id: String,
    /// The part's file as the manifest gives it, if the entry names one.
    pub file: Option<PathBuf>,
    /// What is wrong.
    pub kind: PartErrorKind,
}

impl PartError {
    /// The outline and access regions as read, when they were read but are
    /// not valid: what a picture of the invalid part shows.
    pub fn read(&self) -> Option<&Part> {
        match &self.kind {
            PartErrorKind::Invalid { read, .. } => Some(read),
            _ => None,
        }
    }
}

/// What is wrong with a catalogue part.
#[derive(Debug, Clone, thiserror::Error)]
pub enum PartErrorKind {
    /// The `[[part]]` table does not fit the manifest's schema (entry
    /// number from 1; TOML's message).
    #[error("manifest entry {entry}: {message}")]
    ManifestEntry {
        /// The entry, from 1 in manifest order.
        entry: usize,
        /// TOML's description of the mismatch.
        message: String,
    },
    /// The entry's fields contradict each other or are out of range.
    #[error(transparent)]
    Entry(#[from] EntryProblem),
    /// The file's extension is not one of a part format.
    #[error("unknown file type (expected .dxf, .svg or .json)")]
    UnknownFileType,
    /// The file cannot be read (missing, a directory, no permission).
    #[error("cannot read {}: {error}", .path.display())]
    Unreadable {
        /// The file, as opened (joined to the manifest's directory).
        path: PathBuf,
        /// The system's reason; shared so that the error stays `Clone`.
        error: Arc<std::io::Error>,
    },
    /// The path is not a regular file (a directory, a FIFO, a device); it
    /// is refused before it is opened, since reading a FIFO or a device
    /// may never end.
    #[error("cannot read {}: it is {kind}, not a regular file", .path.display())]
    NotAFile {
        /// The path, as opened (joined to the manifest's directory).
        path: PathBuf,
        /// What it is instead.
        kind: &'static str,
    },
    /// The file cannot be read as its format.
    #[error(transparent)]
    Read(#[from] ReadError),
    /// A polygon of the part is not one SPEC accepts.
    #[error("{problem}")]
    Invalid {
        /// What is wrong, and where.
        problem: InvalidPolygon,
        /// The outline and access regions as read (catalogue units), so
        /// that pictures and scenes can show what the error is about.
        read: Box<Part>,
    },
}

/// A manifest entry that cannot be used as written.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EntryProblem {
    /// The id is empty or blank.
    #[error("empty id")]
    EmptyId,
    /// An earlier entry has the same id; the first one stands. Entries
    /// from 1.
    #[error("duplicate id: entry {entry} has the same id as entry {first}")]
    DuplicateId {
        /// This entry.
        entry: usize,
        /// The entry that has the id first.
        first: usize,
    },
    /// Both `file` and `outline`.
    #[error("give either file or outline, not both")]
    FileAndOutline,
    /// Neither `file` nor `outline`.
    #[error("no file and no outline")]
    NoFileNorOutline,
    /// `holes` beside `file`: a file's holes are the loops it draws.
    #[error(
        "holes go with an inline outline; a file's holes are the loops drawn inside its outline"
    )]
    HolesWithFile,
    /// A negative or non-finite `quantity`.
    #[error("quantity {0} must be a non-negative number")]
    Quantity(f64),
    /// `wrenches = []`, which would leave the metric nothing to rate.
    #[error("wrenches is an empty list (leave it out for the default metric)")]
    EmptyWrenches,
    /// Wrench number `.0` (from 0) has a NaN or infinite component.
    #[error("wrench {0} has a non-finite component")]
    NonFiniteWrench(usize),
    /// A zero, negative or non-finite `chord_tolerance`.
    #[error("chord_tolerance {0} must be a positive number")]
    ChordTolerance(f64),
    /// A `units` no reader knows.
    #[error("unknown units \"{0}\"")]
    UnknownUnits(String),
}

/// How messages about a part name it: its id, and its file in parentheses
/// when it has one.
pub(crate) fn part_name(id: &str, file: Option<&Path>) -> String {
    match file {
        Some(f) => format!("{id} ({})", f.display()),
        None => id.to_string(),
    }
}
