//! What a worker needs to prepare a part itself: outline, holes, access regions,
//! kit, parameters and unit, in a binary wire form that crosses processes
//! bit for bit. `prepare` is deterministic, so a worker that prepares the
//! same input holds the same [`PreparedPart`] as the coordinator.

use crate::protocol::{Digest, TaskError};
use fixplan_core::{
    prepare, Clamp, HoleKind, Kit, MountHole, Params, Part, Pattern, PrepareError, PreparedPart,
    Units, Vertex,
};
use serde::{Deserialize, Serialize};
use sha2::{Digest as _, Sha256};
use std::borrow::Cow;
use thiserror::Error;

/// One part of a distributed run.
#[derive(Debug, Clone, PartialEq)]
pub struct PartInput {
    /// The outline, holes and access regions, as the catalogue gave them.
    pub part: Part,
    /// The kit, in the catalogue's unit: the worker builds its own lattice.
    pub kit: Kit,
    /// The parameters after the catalogue's per-part overrides.
    pub params: Params,
    /// The unit of `part` and `kit`, which scales the tolerances.
    pub units: Units,
}

/// Why a part input cannot cross the wire: postcard's error, which names
/// what it could not encode or read.
#[derive(Debug, Error)]
pub enum InputError {
    /// The coordinator cannot encode the input (a value postcard refuses).
    #[error("part input: {0}")]
    Encode(postcard::Error),
    /// The bytes are not a part input of this protocol version.
    #[error("part input: {0}")]
    Decode(postcard::Error),
}

/// Why a worker has no prepared part for an assignment: the shard fails
/// with this text and the part becomes `invalid` (see
/// [`crate::protocol::TaskFailed`]).
#[derive(Debug, Error)]
pub enum WireInputError {
    /// The assignment is for a part this worker has not been sent.
    #[error("the coordinator sent no input for an unknown part")]
    Missing,
    /// The input was damaged or belongs to another part.
    #[error("part input does not match its digest")]
    DigestMismatch,
    /// The input could not be read.
    #[error(transparent)]
    Input(#[from] InputError),
    /// The input was read but the part or kit is unusable.
    #[error(transparent)]
    Prepare(#[from] PrepareError),
}

// `Kit`'s serde form reads mount holes in several spellings (untagged),
// which a binary format cannot; the wire form spells them one way. The
// wire structs borrow what they can from the input they encode (the
// coordinator encodes every part of a catalogue) and own what they decode.
#[derive(Serialize, Deserialize)]
struct WireClamp<'a> {
    mount_holes: Vec<(i64, i64, HoleKind)>,
    axis_offset: f64,
    travel: [f64; 2],
    body: Cow<'a, [[f64; 2]]>,
    plunger: Cow<'a, [[f64; 2]]>,
}

#[derive(Serialize, Deserialize)]
struct WireKit<'a> {
    spacing: f64,
    cols: u32,
    rows: u32,
    pattern: Pattern,
    locator_radius: f64,
    clamp: WireClamp<'a>,
}

/// The part with every vertex as `(x, y, bulge)`: a vertex's file form
/// (`[x, y]` or `[x, y, b]`) has a varying length, which postcard's
/// tuples cannot carry. Holes in the catalogue's order, which numbers
/// their edges and segments (SPEC 9.2).
#[derive(Serialize, Deserialize)]
struct WirePart<'a> {
    outline: Vec<(f64, f64, f64)>,
    holes: Vec<Vec<(f64, f64, f64)>>,
    access: Cow<'a, [Vec<[f64; 2]>]>,
}

/// A loop's vertices in their wire form.
fn wire_loop(l: &[Vertex]) -> Vec<(f64, f64, f64)> {
    l.iter().map(|v| (v.x, v.y, v.bulge)).collect()
}

/// A loop's vertices from their wire form.
fn loop_of_wire(l: &[(f64, f64, f64)]) -> Vec<Vertex> {
    l.iter().map(|&(x, y, b)| Vertex::new(x, y, b)).collect()
}

#[derive(Serialize, Deserialize)]
struct WireInput<'a> {
    part: WirePart<'a>,
    kit: WireKit<'a>,
    params: Cow<'a, Params>,
    units: Units,
}

impl PartInput {
    /// The wire bytes (postcard).
    pub fn encode(&self) -> Result<Vec<u8>, InputError> {
        let k = &self.kit;
        let w = WireInput {
            part: WirePart {
                outline: wire_loop(&self.part.outline),
                holes: self.part.holes.iter().map(|h| wire_loop(h)).collect(),
                access: Cow::Borrowed(&self.part.access),
            },
            kit: WireKit {
                spacing: k.spacing,
                cols: k.cols,
                rows: k.rows,
                pattern: k.pattern,
                locator_radius: k.locator_radius,
                clamp: WireClamp {
                    mount_holes: k
                        .clamp
                        .mount_holes
                        .iter()
                        .map(|h| (h.offset[0], h.offset[1], h.kind))
                        .collect(),
                    axis_offset: k.clamp.axis_offset,
                    travel: k.clamp.travel,
                    body: Cow::Borrowed(&k.clamp.body),
                    plunger: Cow::Borrowed(&k.clamp.plunger),
                },
            },
            params: Cow::Borrowed(&self.params),
            units: self.units,
        };
        // Borrowing the input and sizing the buffer up front: clones and a
        // buffer grown from empty were most of the encoding's cost (the
        // coordinator encodes every part of a catalogue).
        let hole_vertices: usize = self.part.holes.iter().map(Vec::len).sum();
        let size = 256 + 32 * (self.part.outline.len() + hole_vertices + self.kit.clamp.body.len());
        postcard::to_extend(&w, Vec::with_capacity(size)).map_err(InputError::Encode)
    }

    /// Reads the wire bytes of [`PartInput::encode`].
    pub fn decode(bytes: &[u8]) -> Result<PartInput, InputError> {
        let w: WireInput = postcard::from_bytes(bytes).map_err(InputError::Decode)?;
        let c = w.kit.clamp;
        Ok(PartInput {
            part: Part {
                outline: loop_of_wire(&w.part.outline),
                holes: w.part.holes.iter().map(|h| loop_of_wire(h)).collect(),
                access: w.part.access.into_owned(),
            },
            kit: Kit {
                spacing: w.kit.spacing,
                cols: w.kit.cols,
                rows: w.kit.rows,
                pattern: w.kit.pattern,
                locator_radius: w.kit.locator_radius,
                clamp: Clamp {
                    mount_holes: c
                        .mount_holes
                        .into_iter()
                        .map(|(i, j, kind)| MountHole {
                            offset: [i, j],
                            kind,
                        })
                        .collect(),
                    axis_offset: c.axis_offset,
                    travel: c.travel,
                    body: c.body.into_owned(),
                    plunger: c.plunger.into_owned(),
                },
            },
            params: w.params.into_owned(),
            units: w.units,
        })
    }

    /// Prepares the part as the coordinator does: the same input gives the
    /// same [`PreparedPart`], so shards from any worker merge.
    pub fn prepare(&self) -> Result<PreparedPart, PrepareError> {
        prepare(&self.part, &self.kit, &self.params, self.units)
    }

    /// Prepares the part of an assignment from the wire input that came with
    /// it, after checking it against the `expected` digest the shards of
    /// the part are named by.
    pub fn prepare_wire(
        expected: &Digest,
        input: Option<&[u8]>,
    ) -> Result<PreparedPart, WireInputError> {
        Ok(PartInput::prepare_wire_kept(expected, input)?.1)
    }

    /// [`PartInput::prepare_wire`], keeping the input read from the wire
    /// (what a worker finishing whole parts needs besides the prepared part).
    pub fn prepare_wire_kept(
        expected: &Digest,
        input: Option<&[u8]>,
    ) -> Result<(PartInput, PreparedPart), WireInputError> {
        let bytes = input.ok_or(WireInputError::Missing)?;
        if digest(bytes) != *expected {
            return Err(WireInputError::DigestMismatch);
        }
        let input = PartInput::decode(bytes)?;
        let prep = input.prepare()?;
        Ok((input, prep))
    }
}

/// SHA-256 of wire bytes.
pub fn digest(bytes: &[u8]) -> Digest {
    Sha256::digest(bytes).into()
}

/// A digest in hex, for logs.
pub fn short_hex(digest: &Digest) -> String {
    digest[..6].iter().map(|b| format!("{b:02x}")).collect()
}

/// The input of the `rectangle-mm` bench case, for tests.
impl From<&WireInputError> for TaskError {
    fn from(error: &WireInputError) -> TaskError {
        match error {
            WireInputError::Missing => TaskError::MissingInput,
            WireInputError::DigestMismatch => TaskError::DigestMismatch,
            WireInputError::Input(error) => TaskError::UnreadableInput(error.to_string()),
            WireInputError::Prepare(error) => TaskError::Unprepared(error.to_string()),
        }
    }
}

#[cfg(test)]
pub(crate) fn sample_input() -> PartInput {
    let case: fixplan_core::Case =
        serde_json::from_str(include_str!("../../examples/cases/rectangle-mm.json"))
            .expect("the bench case reads");
    PartInput {
        part: case.part(),
        kit: case.kit.clone(),
        params: case.params.clone(),
        units: case.units,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wire_round_trip_is_exact() {
        let case: fixplan_core::Case =
            serde_json::from_str(include_str!("../../examples/cases/rectangle-mm.json")).unwrap();
        let mut params = case.params.clone();
        params.wrenches = Some(vec![[0.1, 1.0 / 3.0, -7.25e-3]]);
        let mut part = case.part();
        // An arc (SPEC 8.1): a vertex with a bulge crosses the wire too.
        part.outline[1].bulge = -0.375;
        // Holes (SPEC 9), in order, a round one and a square one.
        part.holes = vec![
            vec![Vertex::new(20.0, 20.0, 1.0), Vertex::new(30.0, 20.0, 1.0)],
            vec![[5.0, 5.0], [5.0, 9.0], [9.0, 9.0], [9.0, 5.0]]
                .into_iter()
                .map(Vertex::from)
                .collect(),
        ];
        let input = PartInput {
            part,
            kit: case.kit.clone(),
            params,
            units: case.units,
        };
        let b = input.encode().unwrap();
        let back = PartInput::decode(&b).unwrap();
        assert_eq!(back, input);
        assert_eq!(back.encode().unwrap(), b);
        assert!(PartInput::decode(&b[..b.len() / 2]).is_err());
    }

    #[test]
    fn wire_inputs_are_checked_before_they_are_prepared() {
        let b = sample_input().encode().unwrap();
        let d = digest(&b);
        assert!(PartInput::prepare_wire(&d, Some(&b)).is_ok());
        let text = |r: Result<PreparedPart, WireInputError>| r.err().map(|e| e.to_string());
        assert_eq!(
            text(PartInput::prepare_wire(&d, None)).as_deref(),
            Some("the coordinator sent no input for an unknown part")
        );
        assert_eq!(
            text(PartInput::prepare_wire(&[0; 32], Some(&b))).as_deref(),
            Some("part input does not match its digest")
        );
        let cut = &b[..b.len() / 2];
        let e = text(PartInput::prepare_wire(&digest(cut), Some(cut))).unwrap();
        assert!(e.starts_with("part input: "), "{e}");
    }
}
