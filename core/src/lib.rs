//! fixplan-core: the complete fixture enumeration of Brost & Goldberg (1996)
//! as specified by SPEC.md, pure (no I/O) and deterministic.
//!
//! [`solve`] enumerates one part end to end. Work split over threads or
//! machines goes through a [`PreparedPart`]: [`prepare()`] a part once,
//! enumerate any range of its segment combinations into a
//! [`PartialResult`] ([`PreparedPart::enumerate_range`]), [`merge`] the
//! pieces and [`report`] the whole.
//!
//! The modules follow the pipeline: `geometry` (points, arcs, angle sets,
//! polygons), `input` (the case, validated and in lattice units),
//! `outline` (lines and arcs of the part), `segments` (where a locator
//! can touch), `poses` (the part touching three locators), `sweeps` (where
//! the third locator can be), `setups` (locator triples and poses),
//! `checks` (form closure, clearance, plate fit), `metric` (the score),
//! `clamp` (candidates and the mount search), `results` (ranking, counts,
//! the reported form) and `enumerate` (preparing, sharding, solving).
//! They are private: [`parts`] opens the pieces that catalogue readers,
//! drawings, tests and benches use.
//!
//! ```
//! use fixplan_core::{solve, Clamp, HoleKind, Kit, MountHole, Params, Part, Pattern, Status, Units};
//!
//! // A 6 x 4 plate of 25 mm on a square lattice, with a two-hole clamp.
//! let kit = Kit {
//!     spacing: 25.0,
//!     cols: 12,
//!     rows: 12,
//!     pattern: Pattern::Square,
//!     locator_radius: 6.0,
//!     clamp: Clamp {
//!         mount_holes: vec![
//!             MountHole { offset: [0, 0], kind: HoleKind::Any },
//!             MountHole { offset: [1, 0], kind: HoleKind::Any },
//!         ],
//!         axis_offset: 0.0,
//!         travel: [35.0, 70.0],
//!         body: vec![[-10.0, -10.0], [30.0, -10.0], [30.0, 10.0], [-10.0, 10.0]],
//!         plunger: vec![[-62.0, -3.0], [-6.0, -3.0], [-6.0, 3.0], [-62.0, 3.0]],
//!     },
//! };
//! let part = Part::polygon(&[[0.0, 0.0], [150.0, 0.0], [150.0, 100.0], [0.0, 100.0]]);
//! let result = solve(&part, &kit, &Params::default(), Units::Mm);
//!
//! assert_eq!(result.status, Status::Ok);
//! let best = &result.fixtures[0];
//! assert_eq!(best.rank, 1);
//! // Three locators and the clamp, each on one of the rectangle's sides.
//! assert_eq!(best.contacts.len(), 4);
//! assert!(best.segments.iter().chain([&best.clamp.segment]).all(|&s| s < 4));
//! ```

mod checks;
mod clamp;
mod enumerate;
mod geometry;
mod input;
mod metric;
mod outline;
mod poses;
mod results;
mod segments;
mod setups;
mod sweeps;
#[cfg(test)]
mod test_rng;

pub mod parts;

pub use enumerate::budget::{fixture_cap, BudgetHalt, WorkBudget};
pub use enumerate::combinations::combination_count;
pub use enumerate::prepare::{prepare, PreparedPart};
pub use enumerate::shards::{merge, EnumerateOptions, Enumeration, PartialResult, Profile};
pub use enumerate::whole_part::{report, solve, solve_case};
pub use input::validate::{validate_kit, validate_params, PrepareError};
pub use input::{Case, Clamp, HoleKind, Kit, MountHole, Params, Part, Pattern, Point, Units};
pub use outline::Vertex;
pub use results::ranking::{merge_ranked, Fixture};
pub use results::report::{
    ClampReport, ContactReport, Counts, FixtureReport, PlacementReport, PoseReport, SolveResult,
    Status,
};
pub use segments::SegmentKind;
