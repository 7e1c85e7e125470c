//! The fields the results and study files' messages are made of: names
//! (units, status, hole kinds...), points, the kit, the parameters and the
//! counts, each its own type built by an explicit conversion from core's
//! and back. Core can rename a field or a variant without moving a byte
//! of a file: the compiler then points here, where the file's name stays.
//!
//! Every type takes the form the viewers' JSON-schema parser reads
//! (Foxglove Studio and Lichtblick, `parseJsonSchema` of `mcap-support`):
//! objects with named fields, one JSON type per field, points as `{x, y}`
//! objects rather than arrays of arrays, names as strings whose schema
//! lists the values in a `pattern` (that parser refuses string `oneOf`s).

use fixplan_core::SegmentKind;
use fixplan_core::Vertex;
use fixplan_core::{
    Clamp, Counts, HoleKind, Kit, MountHole, Params, Pattern, Point, Status, Units,
};
use schemars::{JsonSchema, Schema, SchemaGenerator};
use serde::{Deserialize, Serialize};
use std::borrow::Cow;

/// The schema of a name taking one of `values`: a string matching exactly
/// one of them (a `pattern`, since the viewers' parser refuses `oneOf`
/// alternatives that are strings).
pub fn choice_schema(values: &[&str]) -> Schema {
    let pattern = format!("^({})$", values.join("|"));
    schemars::json_schema!({
        "type": "string",
        "pattern": pattern,
    })
}

/// A name of the files standing for a core enum: its own variants, each
/// written as the string given, converted from and to the core enum
/// variant named after `=>`, with the schema of [`choice_schema`].
macro_rules! file_name_enum {
    ($(#[$doc:meta])* $name:ident for $core:ident {
        $($(#[$variant_doc:meta])* $variant:ident = $text:literal => $core_variant:ident),+ $(,)?
    }) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
        pub enum $name {
            $($(#[$variant_doc])* #[serde(rename = $text)] $variant),+
        }

        impl $name {
            /// How the files write it.
            pub fn text(self) -> &'static str {
                match self {
                    $($name::$variant => $text),+
                }
            }
        }

        impl From<$core> for $name {
            fn from(value: $core) -> $name {
                match value {
                    $($core::$core_variant => $name::$variant),+
                }
            }
        }

        impl From<$name> for $core {
            fn from(value: $name) -> $core {
                match value {
                    $($name::$variant => $core::$core_variant),+
                }
            }
        }

        impl JsonSchema for $name {
            fn schema_name() -> Cow<'static, str> {
                stringify!($name).into()
            }

            fn json_schema(_: &mut SchemaGenerator) -> Schema {
                choice_schema(&[$($text),+])
            }
        }
    };
}

file_name_enum! {
    /// The catalogue's length unit.
    UnitsName for Units {
        /// Millimetres.
        Mm = "mm" => Mm,
        /// Inches.
        In = "in" => In,
    }
}

file_name_enum! {
    /// A part's outcome.
    StatusName for Status {
        /// At least one admissible fixture.
        Ok = "ok" => Ok,
        /// A valid part no fixture of the kit holds.
        NoFixture = "no_fixture" => NoFixture,
        /// The input cannot be enumerated.
        Invalid = "invalid" => Invalid,
        /// The solver failed on the part (a bug, not the input's fault).
        Failed = "failed" => Failed,
        /// The part's estimated work is beyond the run's budget.
        OverBudget = "over_budget" => OverBudget,
    }
}

file_name_enum! {
    /// The plate's hole layout.
    PatternName for Pattern {
        /// Every hole takes any module.
        Square = "square" => Square,
        /// Checkerboard of dowel and tapped holes.
        Alternating = "alternating" => Alternating,
    }
}

file_name_enum! {
    /// The hole a clamp mount hole needs on an alternating plate.
    HoleKindName for HoleKind {
        /// A dowel hole.
        Dowel = "dowel" => Dowel,
        /// A tapped hole.
        Tapped = "tapped" => Tapped,
        /// Either kind.
        Any = "any" => Any,
    }
}

file_name_enum! {
    /// What a segment lies on.
    SegmentKindName for SegmentKind {
        /// A straight edge.
        Line = "line" => Line,
        /// A circular arc.
        Arc = "arc" => Arc,
    }
}

/// A point `{x, y}`, in the catalogue's unit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PointField {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
}

impl From<&Point> for PointField {
    fn from(point: &Point) -> PointField {
        PointField {
            x: point[0],
            y: point[1],
        }
    }
}

impl From<&PointField> for Point {
    fn from(point: &PointField) -> Point {
        [point.x, point.y]
    }
}

/// The points `{x, y}` of a list of core points.
pub fn point_fields(points: &[Point]) -> Vec<PointField> {
    points.iter().map(PointField::from).collect()
}

/// The core points of a list of `{x, y}` points.
pub fn points_of(points: &[PointField]) -> Vec<Point> {
    points.iter().map(Point::from).collect()
}

/// An outline vertex `{x, y, bulge}`; `bulge` (DXF's: the edge to the
/// next vertex is an arc of included angle `4 atan(bulge)`) is absent for
/// a straight edge.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct VertexField {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// Bulge of the edge leaving the vertex; absent when straight.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bulge: Option<f64>,
}

impl From<&Vertex> for VertexField {
    fn from(vertex: &Vertex) -> VertexField {
        VertexField {
            x: vertex.x,
            y: vertex.y,
            bulge: vertex.is_arc().then_some(vertex.bulge),
        }
    }
}

impl From<&VertexField> for Vertex {
    fn from(vertex: &VertexField) -> Vertex {
        Vertex::new(vertex.x, vertex.y, vertex.bulge.unwrap_or(0.0))
    }
}

/// A closed polygon of points (an access region).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PolygonField {
    /// Its vertices, in order.
    pub points: Vec<PointField>,
}

impl From<&Vec<Point>> for PolygonField {
    fn from(points: &Vec<Point>) -> PolygonField {
        PolygonField {
            points: point_fields(points),
        }
    }
}

/// A hole cut through a part (SPEC 9): a closed loop of outline vertices,
/// in an object because the viewers' schema parser reads no list of
/// lists.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct HoleLoopField {
    /// Its vertices, in order, as given.
    pub vertices: Vec<VertexField>,
}

impl From<&Vec<Vertex>> for HoleLoopField {
    fn from(hole_loop: &Vec<Vertex>) -> HoleLoopField {
        HoleLoopField {
            vertices: hole_loop.iter().map(VertexField::from).collect(),
        }
    }
}

impl From<&HoleLoopField> for Vec<Vertex> {
    fn from(hole_loop: &HoleLoopField) -> Vec<Vertex> {
        hole_loop.vertices.iter().map(Vertex::from).collect()
    }
}

/// A plate hole or lattice offset `{i, j}` (column, row).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct HoleField {
    /// Column.
    pub i: i64,
    /// Row.
    pub j: i64,
}

impl From<&[i64; 2]> for HoleField {
    fn from(hole: &[i64; 2]) -> HoleField {
        HoleField {
            i: hole[0],
            j: hole[1],
        }
    }
}

impl From<&HoleField> for [i64; 2] {
    fn from(hole: &HoleField) -> [i64; 2] {
        [hole.i, hole.j]
    }
}

/// A clamp mount hole: its lattice offset from mount hole 0 (clamp frame)
/// and the hole it needs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MountHoleField {
    /// Column offset.
    pub i: i64,
    /// Row offset.
    pub j: i64,
    /// The hole kind it needs on an alternating plate.
    pub kind: HoleKindName,
}

/// The kit's clamp, in its own frame (origin at mount hole 0, `+x` the
/// push direction).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ClampField {
    /// Holes it is bolted to.
    pub mount_holes: Vec<MountHoleField>,
    /// `y0`: the plunger axis is the line `y = y0`.
    pub axis_offset: f64,
    /// Shortest and longest plunger extension.
    pub travel: TravelField,
    /// Space the clamp body takes.
    pub body: Vec<PointField>,
    /// The plunger shaft at extension 0.
    pub plunger: Vec<PointField>,
}

/// The plunger's travel.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TravelField {
    /// Shortest extension.
    pub min: f64,
    /// Longest extension.
    pub max: f64,
}

/// A modular fixture kit, in the catalogue's unit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct KitField {
    /// Hole spacing.
    pub spacing: f64,
    /// Holes across.
    pub cols: u32,
    /// Holes down.
    pub rows: u32,
    /// Hole layout.
    pub pattern: PatternName,
    /// Radius of the locators and of the clamp tip.
    pub locator_radius: f64,
    /// The clamp.
    pub clamp: ClampField,
}

impl From<&Kit> for KitField {
    fn from(kit: &Kit) -> KitField {
        let clamp = &kit.clamp;
        KitField {
            spacing: kit.spacing,
            cols: kit.cols,
            rows: kit.rows,
            pattern: kit.pattern.into(),
            locator_radius: kit.locator_radius,
            clamp: ClampField {
                mount_holes: clamp
                    .mount_holes
                    .iter()
                    .map(|h| MountHoleField {
                        i: h.offset[0],
                        j: h.offset[1],
                        kind: h.kind.into(),
                    })
                    .collect(),
                axis_offset: clamp.axis_offset,
                travel: TravelField {
                    min: clamp.travel[0],
                    max: clamp.travel[1],
                },
                body: point_fields(&clamp.body),
                plunger: point_fields(&clamp.plunger),
            },
        }
    }
}

impl From<&KitField> for Kit {
    fn from(kit: &KitField) -> Kit {
        let clamp = &kit.clamp;
        Kit {
            spacing: kit.spacing,
            cols: kit.cols,
            rows: kit.rows,
            pattern: kit.pattern.into(),
            locator_radius: kit.locator_radius,
            clamp: Clamp {
                mount_holes: clamp
                    .mount_holes
                    .iter()
                    .map(|h| MountHole {
                        offset: [h.i, h.j],
                        kind: h.kind.into(),
                    })
                    .collect(),
                axis_offset: clamp.axis_offset,
                travel: [clamp.travel.min, clamp.travel.max],
                body: points_of(&clamp.body),
                plunger: points_of(&clamp.plunger),
            },
        }
    }
}

/// An expected wrench (part frame, torque about its origin).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WrenchField {
    /// Force along x.
    pub force_x: f64,
    /// Force along y.
    pub force_y: f64,
    /// Torque about the part's origin.
    pub torque: f64,
}

impl From<&[f64; 3]> for WrenchField {
    fn from(wrench: &[f64; 3]) -> WrenchField {
        WrenchField {
            force_x: wrench[0],
            force_y: wrench[1],
            torque: wrench[2],
        }
    }
}

/// The enumeration parameters of a run or a study's kit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ParamsField {
    /// Largest angle between the push direction and the contact normal.
    pub max_clamp_angle_deg: f64,
    /// How much every usable segment is shortened at both ends; absent for
    /// the unit's default.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub edge_trim: Option<f64>,
    /// Smallest gap between the clamp and the part, locators or access
    /// regions; absent for the unit's default.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_clearance: Option<f64>,
    /// Locators 2 and 3 only at multiples of this from locator 1.
    pub grid_step: u32,
    /// Fixtures kept per part (0 keeps all).
    pub top_k: usize,
    /// Whether every candidate was checked (exact admissible count).
    pub full_counts: bool,
    /// Expected wrenches; absent for the default metric.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wrenches: Option<Vec<WrenchField>>,
}

impl From<&Params> for ParamsField {
    fn from(params: &Params) -> ParamsField {
        ParamsField {
            max_clamp_angle_deg: params.max_clamp_angle_deg,
            edge_trim: params.edge_trim,
            min_clearance: params.min_clearance,
            grid_step: params.grid_step,
            top_k: params.top_k,
            full_counts: params.full_counts,
            wrenches: (params.wrenches.as_ref())
                .map(|ws| ws.iter().map(WrenchField::from).collect()),
        }
    }
}

impl From<&ParamsField> for Params {
    fn from(params: &ParamsField) -> Params {
        Params {
            max_clamp_angle_deg: params.max_clamp_angle_deg,
            edge_trim: params.edge_trim,
            min_clearance: params.min_clearance,
            grid_step: params.grid_step,
            top_k: params.top_k,
            full_counts: params.full_counts,
            wrenches: params.wrenches.as_ref().map(|ws| {
                ws.iter()
                    .map(|w| [w.force_x, w.force_y, w.torque])
                    .collect()
            }),
        }
    }
}

/// What the enumeration of a part went through.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CountsField {
    /// Usable segments.
    pub segments: u64,
    /// Segment combinations enumerated.
    pub combinations: u64,
    /// Locator setups found.
    pub setups: u64,
    /// Candidate fixtures (setup and clamp contact in form closure).
    pub candidates: u64,
    /// Candidates with an admissible clamp mount; absent when not counted
    /// (`exact` false: top-k mode checked mounts only for candidates that
    /// could enter the top-k).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub admissible: Option<u64>,
    /// Whether `admissible` was counted.
    pub exact: bool,
}

impl From<&Counts> for CountsField {
    fn from(counts: &Counts) -> CountsField {
        CountsField {
            segments: counts.segments,
            combinations: counts.combinations,
            setups: counts.setups,
            candidates: counts.candidates,
            admissible: counts.admissible(),
            exact: counts.exact,
        }
    }
}

impl From<&CountsField> for Counts {
    fn from(counts: &CountsField) -> Counts {
        Counts {
            segments: counts.segments,
            combinations: counts.combinations,
            setups: counts.setups,
            candidates: counts.candidates,
            admissible: counts.admissible.filter(|_| counts.exact).unwrap_or(0),
            exact: counts.exact,
        }
    }
}
