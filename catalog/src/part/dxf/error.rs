//! Why a DXF file gives no part, in words that say what to do.

use super::super::outline::{fmt, fmt_pt, OutlinePickError};
use super::super::raw::LimitExceeded;
use crate::units::LengthUnit;
use fixplan_core::Units;

/// Why a DXF file does not give a part.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DxfError {
    /// The `dxf` crate could not parse the file; its message says where.
    #[error("not a readable DXF file: {0}")]
    Unreadable(String),
    /// The `dxf` crate panicked on the file (it is not written for hostile
    /// input); the panic is caught so it stays this part's problem.
    #[error("not a readable DXF file (the DXF reader failed on it)")]
    ReaderFailed,
    /// `$INSUNITS` names a unit other than mm, cm, m, in or ft (its name in
    /// the `dxf` crate).
    #[error("unknown units: $INSUNITS is {0}; supported are mm, cm, m, in and ft (or unitless, with the catalogue's units)")]
    UnknownUnits(String),
    /// Entities whose chain does not close; the ends are given, and what
    /// is near them: another end beyond the join tolerance (a gap), an
    /// entity the reader could not use, or nothing (a stray line).
    #[error("open loop: {} end at {} and {} {} with nothing within {} {} to join: {cause}",
        chain_name(*.entities, .first), fmt_pt(*.start), fmt_pt(*.end), .units.label(), fmt(*.gap), .gap_unit.label())]
    OpenLoop {
        /// How many entities the chain has.
        entities: usize,
        /// The chain's first entity, e.g. `LINE #3 on layer 0`.
        first: String,
        /// One free end, catalogue units.
        start: [f64; 2],
        /// The other free end, catalogue units.
        end: [f64; 2],
        /// The catalogue's units.
        units: Units,
        /// The join tolerance, in the file's units.
        gap: f64,
        /// The file's units.
        gap_unit: LengthUnit,
        /// What lies near the ends (boxed: errors travel by value).
        cause: Box<OpenCause>,
    },
    /// The file goes over one of the reader's [`Limits`](crate::part::Limits).
    #[error(transparent)]
    Limit(#[from] LimitExceeded),
    /// The loops found do not make one part.
    #[error(transparent)]
    Outline(#[from] OutlinePickError),
}

/// What lies near the free ends of a chain that does not close.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OpenCause {
    /// Another free end, farther than the join tolerance but close: a gap
    /// in the outline.
    #[error("the nearest other free end, of {other}, is {} {} away at {} (a gap in the outline: close it in the drawing)", fmt(*.distance), .units.label(), fmt_pt(*.at))]
    Gap {
        /// The entity whose end it is.
        other: String,
        /// How far, catalogue units.
        distance: f64,
        /// Where, catalogue units.
        at: [f64; 2],
        /// The catalogue's units.
        units: Units,
    },
    /// An entity this reader cannot use ends there (the warnings say why).
    #[error("it runs into {0}, which is not read (see the warnings); convert that entity to lines, arcs or polylines")]
    Unread(String),
    /// Nothing ends near: a line on its own.
    #[error("no other entity ends near it{}; if it is a centre, construction or dimension line, put it on a layer of its own and leave that out with ignore_layers", if *.unread > 0 { format!(" ({} entities were not read, see the warnings)", .unread) } else { String::new() })]
    Stray {
        /// How many entities of the layer were not read.
        unread: usize,
    },
}

/// "LINE #1 on layer 0", or "3 entities from LINE #1 on layer 0".
fn chain_name(entities: usize, first: &str) -> String {
    if entities == 1 {
        first.to_string()
    } else {
        format!("{entities} entities from {first}")
    }
}
