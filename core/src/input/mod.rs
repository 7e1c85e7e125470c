//! The inputs of SPEC section 1 and the case file of Appendix A.
//!
//! These types are the contract between the catalogue readers, the CLI and the
//! enumeration: everything is in the catalogue's length unit here; the
//! enumeration converts to lattice units itself (see [`crate::prepare()`]).

pub(crate) mod setting;
pub(crate) mod validate;

use crate::outline::Vertex;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// A point as it appears in files: `[x, y]`.
pub type Point = [f64; 2];

/// Length unit of a catalogue or case. Only used for defaults and labels: the
/// numbers are never converted inside the core.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Units {
    /// Millimetres: the default, and the unit SPEC's defaults are given in.
    #[default]
    Mm,
    /// Inches: SPEC's defaults are converted (edge trim 0.04 in).
    In,
}

impl Units {
    /// Millimetres per unit, for the defaults SPEC gives in millimetres.
    pub fn mm_per_unit(self) -> f64 {
        match self {
            Units::Mm => 1.0,
            Units::In => 25.4,
        }
    }

    /// How reports and tables write lengths in this unit.
    pub fn label(self) -> &'static str {
        match self {
            Units::Mm => "mm",
            Units::In => "in",
        }
    }
}

/// Hole layout of the plate: decides which lattice points a locator may
/// take and which hole kinds a clamp's mount holes need.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Pattern {
    /// Every hole takes any module.
    Square,
    /// Checkerboard: `(i, j)` is a dowel hole when `i + j` is even, tapped
    /// otherwise; locators go in dowel holes only.
    Alternating,
}

/// The kind of hole a module needs on an alternating plate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum HoleKind {
    /// A hole with `i + j` even; locators and dowel pins go here.
    Dowel,
    /// A hole with `i + j` odd; clamp bolts go here.
    Tapped,
    /// Fits either kind (only meaningful on square plates, or for modules
    /// that do not care).
    Any,
}

impl HoleKind {
    /// Whether a hole at lattice point `(i, j)` of an alternating plate (hole
    /// `(0,0)` a dowel hole) is of this kind.
    pub fn accepts(self, i: i64, j: i64) -> bool {
        let dowel = (i + j).rem_euclid(2) == 0;
        match self {
            HoleKind::Dowel => dowel,
            HoleKind::Tapped => !dowel,
            HoleKind::Any => true,
        }
    }
}

/// A clamp mount hole: a lattice offset in the clamp frame and the hole kind.
/// Written `[i, j, "dowel"]` (or `[i, j]` for [`HoleKind::Any`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MountHole {
    /// Lattice offset from mount hole 0, in the clamp frame.
    pub offset: [i64; 2],
    /// What the hole under it must be on an alternating plate.
    pub kind: HoleKind,
}

impl Serialize for MountHole {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeTuple;
        let mut t = s.serialize_tuple(3)?;
        t.serialize_element(&self.offset[0])?;
        t.serialize_element(&self.offset[1])?;
        t.serialize_element(&self.kind)?;
        t.end()
    }
}

/// The schema of the form [`MountHole`] is written in: `[i, j, kind]`
/// (reading also accepts `[i, j]` and `{offset, kind}`).
impl JsonSchema for MountHole {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "MountHole".into()
    }

    fn json_schema(generator: &mut schemars::SchemaGenerator) -> schemars::Schema {
        let kind = generator.subschema_for::<HoleKind>();
        schemars::json_schema!({
            "description": "A clamp mount hole: lattice offset (i, j) and hole kind",
            "type": "array",
            "prefixItems": [{"type": "integer"}, {"type": "integer"}, kind],
            "items": false,
            "minItems": 3,
            "maxItems": 3
        })
    }
}

impl<'de> Deserialize<'de> for MountHole {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Raw {
            WithKind(i64, i64, HoleKind),
            Plain(i64, i64),
            Table {
                offset: [i64; 2],
                #[serde(default = "any_kind")]
                kind: HoleKind,
            },
        }
        fn any_kind() -> HoleKind {
            HoleKind::Any
        }
        Ok(match Raw::deserialize(d)? {
            Raw::WithKind(i, j, kind) => MountHole {
                offset: [i, j],
                kind,
            },
            Raw::Plain(i, j) => MountHole {
                offset: [i, j],
                kind: HoleKind::Any,
            },
            Raw::Table { offset, kind } => MountHole { offset, kind },
        })
    }
}

/// The sliding clamp, in its own frame: origin at mount hole 0, `+x` the push
/// direction.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Clamp {
    /// Holes it is bolted to; hole 0 must be `[0, 0]`, the frame's origin.
    pub mount_holes: Vec<MountHole>,
    /// `y0`: the plunger axis is the line `y = y0`.
    pub axis_offset: f64,
    /// `[t_min, t_max]`: the plunger tip centre is at `(t, y0)` for `t` in
    /// this range; the mount search tries the shortest extension first.
    pub travel: [f64; 2],
    /// Space the clamp body takes (handle sweep included), which must keep
    /// `min_clearance` from the part, locators and access regions.
    pub body: Vec<Point>,
    /// The plunger shaft at `t = 0` (tip circle excluded); it moves by
    /// `(t, 0)` with the extension.
    pub plunger: Vec<Point>,
}

/// A modular fixture kit: plate, locators and clamp (SPEC section 1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Kit {
    /// Hole spacing `l`: the lattice unit everything is converted to.
    pub spacing: f64,
    /// Holes across; a fixture must fit on `cols x rows` holes.
    pub cols: u32,
    /// Holes down.
    pub rows: u32,
    /// Hole layout.
    pub pattern: Pattern,
    /// Radius of the round locators and of the clamp tip; must stay below
    /// half the spacing (square) or `l sqrt(2) / 2` (alternating) so
    /// neighbouring locators fit.
    pub locator_radius: f64,
    /// The one clamp of the kit.
    pub clamp: Clamp,
}

/// Enumeration parameters; `None` means SPEC's default for the unit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Params {
    /// Largest angle between the push direction and the inward contact
    /// normal, in `(0, 90]`; 90 is the complete, heuristic-free setting,
    /// smaller angles keep clamps that do not slip.
    #[serde(default = "default_angle")]
    pub max_clamp_angle_deg: f64,
    /// Shortens every usable segment at both ends, keeping contacts off
    /// corners that real parts round or chamfer.
    #[serde(default)]
    pub edge_trim: Option<f64>,
    /// Smallest gap between clamp body or plunger and the part, the
    /// locators or the access regions.
    #[serde(default)]
    pub min_clearance: Option<f64>,
    /// Locators 2 and 3 only at multiples of this from locator 1: a coarse
    /// step finds a subset of the fixtures, much faster.
    #[serde(default = "default_grid_step")]
    pub grid_step: u32,
    /// Fixtures kept per part, best first; 0 keeps all.
    #[serde(default = "default_top_k")]
    pub top_k: usize,
    /// Check every candidate so that the admissible count is exact. Off
    /// (the default), a part with `top_k > 0` checks the clamp mount only
    /// of candidates that could still enter its top-k: the same fixtures,
    /// several times faster on big parts, but the admissible count is
    /// then unknown (`counts_exact: false`). Ignored when `top_k` is 0.
    #[serde(default)]
    pub full_counts: bool,
    /// Expected wrenches `[F_x, F_y, tau]` (part frame, tau about its origin);
    /// `None` selects the default metric of SPEC section 6.
    #[serde(default)]
    pub wrenches: Option<Vec<[f64; 3]>>,
}

fn default_angle() -> f64 {
    45.0
}
fn default_grid_step() -> u32 {
    1
}
fn default_top_k() -> usize {
    10
}

impl Default for Params {
    fn default() -> Self {
        Params {
            max_clamp_angle_deg: default_angle(),
            edge_trim: None,
            min_clearance: None,
            grid_step: default_grid_step(),
            top_k: default_top_k(),
            full_counts: false,
            wrenches: None,
        }
    }
}

impl Params {
    /// SPEC: 1 mm, or 0.04 in.
    pub fn edge_trim_or_default(&self, units: Units) -> f64 {
        self.edge_trim.unwrap_or(match units {
            Units::Mm => 1.0,
            Units::In => 0.04,
        })
    }

    /// SPEC: 1 mm (1/25.4 in).
    pub fn min_clearance_or_default(&self, units: Units) -> f64 {
        self.min_clearance.unwrap_or(1.0 / units.mm_per_unit())
    }
}

/// A part: its outline and access constraints, in the catalogue unit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default, JsonSchema)]
pub struct Part {
    /// Simple closed outline of lines and circular arcs (SPEC 8.1), either
    /// orientation (normalised to CCW).
    pub outline: Vec<Vertex>,
    /// Holes cut through the part (SPEC 9.1), each a closed loop of lines
    /// and arcs in either orientation (normalised to clockwise). Absent in
    /// files of parts without holes, so their bytes do not change.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub holes: Vec<Vec<Vertex>>,
    /// Regions no fixture component may touch (machining, markings).
    #[serde(default)]
    pub access: Vec<Vec<Point>>,
}

impl Part {
    /// A part with a straight-edged outline and no access constraints.
    pub fn polygon(points: &[Point]) -> Part {
        Part {
            outline: points.iter().map(|&p| p.into()).collect(),
            holes: Vec::new(),
            access: Vec::new(),
        }
    }
}

/// A single-part case file (SPEC Appendix A).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Case {
    /// Unit of every length in the file.
    #[serde(default)]
    pub units: Units,
    /// The part's outline (flat in the file, as Appendix A writes it);
    /// a vertex may carry a bulge (SPEC 8.1).
    pub part: Vec<Vertex>,
    /// The part's holes (SPEC 9.6), beside `part`; absent means none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub holes: Vec<Vec<Vertex>>,
    /// The part's access constraints.
    #[serde(default)]
    pub access: Vec<Vec<Point>>,
    /// The kit to fixture it with.
    pub kit: Kit,
    /// Enumeration parameters; SPEC's defaults when absent.
    #[serde(default)]
    pub params: Params,
}

impl Case {
    /// The part in the form [`crate::prepare()`] takes.
    pub fn part(&self) -> Part {
        Part {
            outline: self.part.clone(),
            holes: self.holes.clone(),
            access: self.access.clone(),
        }
    }
}
