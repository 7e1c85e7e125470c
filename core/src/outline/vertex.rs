//! Outline vertices as written in files: `[x, y]` or `[x, y, bulge]`.

use crate::geometry::{v2, V2};
use serde::de::{self, SeqAccess, Visitor};
use serde::ser::SerializeTuple;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// An outline vertex and the bulge of the edge that leaves it (SPEC 8.1).
///
/// `bulge` follows DXF: the edge to the next vertex is a circular arc of
/// included angle `4 atan(bulge)`, counter-clockwise when positive; `0` is a
/// straight edge. Written `[x, y]` when the bulge is zero so that polygon
/// files and results stay byte for byte what they were before arcs.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Vertex {
    /// x coordinate.
    pub x: f64,
    /// y coordinate.
    pub y: f64,
    /// Bulge of the edge from this vertex to the next.
    pub bulge: f64,
}

impl Vertex {
    /// A vertex with the given bulge.
    pub fn new(x: f64, y: f64, bulge: f64) -> Vertex {
        Vertex { x, y, bulge }
    }

    /// The position, for geometry.
    pub fn point(&self) -> V2 {
        v2(self.x, self.y)
    }

    /// Whether the edge leaving this vertex is an arc.
    pub fn is_arc(&self) -> bool {
        self.bulge != 0.0
    }
}

/// `v[0]` and `v[1]` are the coordinates and `v[2]` the bulge, as in the
/// `[x, y, bulge]` a file writes: code written for `[x, y]` points reads
/// vertices unchanged.
impl std::ops::Index<usize> for Vertex {
    type Output = f64;

    fn index(&self, i: usize) -> &f64 {
        match i {
            0 => &self.x,
            1 => &self.y,
            2 => &self.bulge,
            _ => panic!("vertex index {i} out of range (0 = x, 1 = y, 2 = bulge)"),
        }
    }
}

/// A vertex equals a point when it is that point with a straight edge.
impl PartialEq<[f64; 2]> for Vertex {
    fn eq(&self, p: &[f64; 2]) -> bool {
        self.x == p[0] && self.y == p[1] && self.bulge == 0.0
    }
}

impl From<[f64; 2]> for Vertex {
    fn from(p: [f64; 2]) -> Vertex {
        Vertex::new(p[0], p[1], 0.0)
    }
}

impl From<[f64; 3]> for Vertex {
    fn from(p: [f64; 3]) -> Vertex {
        Vertex::new(p[0], p[1], p[2])
    }
}

impl Serialize for Vertex {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let arc = self.is_arc();
        let mut t = s.serialize_tuple(if arc { 3 } else { 2 })?;
        t.serialize_element(&self.x)?;
        t.serialize_element(&self.y)?;
        if arc {
            t.serialize_element(&self.bulge)?;
        }
        t.end()
    }
}

/// The schema of the form a [`Vertex`] is written in: `[x, y]` or
/// `[x, y, bulge]`.
impl schemars::JsonSchema for Vertex {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "Vertex".into()
    }

    fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        schemars::json_schema!({
            "description": "An outline vertex [x, y], or [x, y, bulge] when the edge to the next vertex is a circular arc of included angle 4 atan(bulge), counter-clockwise when positive",
            "type": "array",
            "items": {"type": "number"},
            "minItems": 2,
            "maxItems": 3
        })
    }
}

impl<'de> Deserialize<'de> for Vertex {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_seq(VertexVisitor)
    }
}

struct VertexVisitor;

impl<'de> Visitor<'de> for VertexVisitor {
    type Value = Vertex;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a vertex [x, y] or [x, y, bulge]")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vertex, A::Error> {
        let x = seq
            .next_element()?
            .ok_or_else(|| de::Error::invalid_length(0, &self))?;
        let y = seq
            .next_element()?
            .ok_or_else(|| de::Error::invalid_length(1, &self))?;
        let bulge = seq.next_element()?.unwrap_or(0.0);
        if seq.next_element::<de::IgnoredAny>()?.is_some() {
            return Err(de::Error::invalid_length(4, &self));
        }
        Ok(Vertex::new(x, y, bulge))
    }
}
