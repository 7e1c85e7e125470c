//! The inputs of SPEC section 1 and the case file of Appendix A.
//!
//! These types are the contract between the catalogue readers, the CLI and the
//! enumeration: everything is in the catalogue's length unit here; the
//! enumeration converts to lattice units itself (see [`crate::prepare()`]).

use serde::{Deserialize, Serialize};

/// A point as it appears in files: `[x, y]`.
pub type Point = [f64; 2];

/// Length unit of a catalogue or case. Only used for defaults and labels: the
/// numbers are never converted inside the core.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Units {
    #[default]
    Mm,
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

    pub fn label(self) -> &'static str {
        match self {
            Units::Mm => "mm",
            Units::In => "in",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Pattern {
    Square,
    Alternating,
}

/// The kind of hole a module needs on an alternating plate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum HoleKind {
    Dowel,
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
    pub offset: [i64; 2],
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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Clamp {
    pub mount_holes: Vec<MountHole>,
    pub axis_offset: f64,
    pub travel: [f64; 2],
    pub body: Vec<Point>,
    pub plunger: Vec<Point>,
}

/// A modular fixture kit: plate, locators and clamp (SPEC section 1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Kit {
    pub spacing: f64,
    pub cols: u32,
    pub rows: u32,
    pub pattern: Pattern,
    pub locator_radius: f64,
    pub clamp: Clamp,
}

/// Enumeration parameters; `None` means SPEC's default for the unit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Params {
    #[serde(default = "default_angle")]
    pub max_clamp_angle_deg: f64,
    #[serde(default)]
    pub edge_trim: Option<f64>,
    #[serde(default)]
    pub min_clearance: Option<f64>,
    #[serde(default = "default_grid_step")]
    pub grid_step: u32,
    #[serde(default = "default_top_k")]
    pub top_k: usize,
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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct Part {
    pub outline: Vec<Point>,
    #[serde(default)]
    pub access: Vec<Vec<Point>>,
}

/// A single-part case file (SPEC Appendix A).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Case {
    #[serde(default)]
    pub units: Units,
    pub part: Vec<Point>,
    #[serde(default)]
    pub access: Vec<Vec<Point>>,
    pub kit: Kit,
    #[serde(default)]
    pub params: Params,
}

impl Case {
    pub fn part(&self) -> Part {
        Part {
            outline: self.part.clone(),
            access: self.access.clone(),
        }
    }
}
