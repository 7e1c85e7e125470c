//! A ranked fixture as the results file writes it: core's
//! [`FixtureReport`] converted field by field, lattice holes as `{i, j}`
//! and points as `{x, y}` (see [`super::fields`] for why), and back.

use super::fields::{HoleField, PointField};
use fixplan_core::FixtureReport;
use fixplan_core::{ClampReport, ContactReport, PlacementReport, PoseReport};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// Where the part sits, canonical plate frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PoseField {
    /// Translation x.
    pub x: f64,
    /// Translation y.
    pub y: f64,
    /// Rotation, degrees in `[0, 360)`.
    pub theta_deg: f64,
}

/// Where the clamp sits and pushes, canonical plate frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ClampPlacementField {
    /// The segment its tip touches.
    pub segment: usize,
    /// Push direction: 0, 90, 180 or 270 degrees.
    pub rotation_deg: u32,
    /// Lattice point of mount hole 0.
    pub mount: HoleField,
    /// Plunger extension.
    pub extension: f64,
    /// Tip centre.
    pub contact: PointField,
}

/// One contact: the locator's (or tip's) centre and the inward normal.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ContactField {
    /// Centre of the locator or tip.
    pub point: PointField,
    /// Inward unit normal.
    pub normal: PointField,
}

/// Where the modules go on the physical plate (`i` column, `j` row).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PlacementField {
    /// Rotation applied to the canonical frame (0 or 90 degrees).
    pub rotation_deg: u32,
    /// Holes of locators 1-3.
    pub locators: [HoleField; 3],
    /// Holes of the clamp's mount holes, in the kit's order.
    pub clamp_holes: Vec<HoleField>,
}

/// A score, `null` read as infinity (what serde_json writes for it).
fn score_or_infinity<'de, D: serde::Deserializer<'de>>(deserializer: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(deserializer)?.unwrap_or(f64::INFINITY))
}

/// One ranked fixture.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FixtureField {
    /// 1 for the best.
    pub rank: usize,
    /// The metric's value, lower is better.
    // JSON has no infinity: a score that overflowed (the only non-finite
    // one the metric gives, which ignores NaN) is written `null` and read
    // back as infinity. (A plain comment: the doc is the schema's text.)
    #[serde(deserialize_with = "score_or_infinity")]
    pub score: f64,
    /// Segments touched by locators 1-3.
    pub segments: [usize; 3],
    /// Locator lattice points, canonical frame (locator 1 at `{0, 0}`).
    pub locators: [HoleField; 3],
    /// Where the part sits.
    pub pose: PoseField,
    /// Where the clamp sits and pushes.
    pub clamp: ClampPlacementField,
    /// Within `1e-6` of a decision boundary.
    pub borderline: bool,
    /// Locators 1-3 then the clamp.
    pub contacts: Vec<ContactField>,
    /// Where the modules go on the physical plate.
    pub placement: PlacementField,
}

fn holes3(holes: &[[i64; 2]; 3]) -> [HoleField; 3] {
    holes.each_ref().map(HoleField::from)
}

fn lattice3(holes: &[HoleField; 3]) -> [[i64; 2]; 3] {
    holes.each_ref().map(<[i64; 2]>::from)
}

impl From<&FixtureReport> for FixtureField {
    fn from(fixture: &FixtureReport) -> FixtureField {
        FixtureField {
            rank: fixture.rank,
            score: fixture.score,
            segments: fixture.segments,
            locators: holes3(&fixture.locators),
            pose: PoseField {
                x: fixture.pose.x,
                y: fixture.pose.y,
                theta_deg: fixture.pose.theta_deg,
            },
            clamp: ClampPlacementField {
                segment: fixture.clamp.segment,
                rotation_deg: fixture.clamp.rotation_deg,
                mount: HoleField::from(&fixture.clamp.mount),
                extension: fixture.clamp.extension,
                contact: PointField::from(&fixture.clamp.contact),
            },
            borderline: fixture.borderline,
            contacts: fixture
                .contacts
                .iter()
                .map(|c| ContactField {
                    point: PointField::from(&c.point),
                    normal: PointField::from(&c.normal),
                })
                .collect(),
            placement: PlacementField {
                rotation_deg: fixture.placement.rotation_deg,
                locators: holes3(&fixture.placement.locators),
                clamp_holes: fixture
                    .placement
                    .clamp_holes
                    .iter()
                    .map(HoleField::from)
                    .collect(),
            },
        }
    }
}

impl From<&FixtureField> for FixtureReport {
    fn from(fixture: &FixtureField) -> FixtureReport {
        FixtureReport {
            rank: fixture.rank,
            score: fixture.score,
            segments: fixture.segments,
            locators: lattice3(&fixture.locators),
            pose: PoseReport {
                x: fixture.pose.x,
                y: fixture.pose.y,
                theta_deg: fixture.pose.theta_deg,
            },
            clamp: ClampReport {
                segment: fixture.clamp.segment,
                rotation_deg: fixture.clamp.rotation_deg,
                mount: (&fixture.clamp.mount).into(),
                extension: fixture.clamp.extension,
                contact: (&fixture.clamp.contact).into(),
            },
            borderline: fixture.borderline,
            contacts: fixture
                .contacts
                .iter()
                .map(|c| ContactReport {
                    point: (&c.point).into(),
                    normal: (&c.normal).into(),
                })
                .collect(),
            placement: PlacementReport {
                rotation_deg: fixture.placement.rotation_deg,
                locators: lattice3(&fixture.placement.locators),
                clamp_holes: fixture
                    .placement
                    .clamp_holes
                    .iter()
                    .map(<[i64; 2]>::from)
                    .collect(),
            },
        }
    }
}
