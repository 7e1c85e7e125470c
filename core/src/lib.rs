//! fixplan-core: the complete fixture enumeration of Brost & Goldberg (1996)
//! as specified by SPEC.md, pure (no I/O) and deterministic.
//!
//! Pipeline: [`prepare()`] a part (segments, pair bounds) once, then
//! [`PreparedPart::enumerate_range`] any range of segment combinations into a
//! [`PartialResult`], and [`merge`] the pieces. [`solve()`] does all of it for
//! one part and returns the result format of SPEC Appendix A.

pub mod admissibility;
pub mod angle_set;
pub mod arc;
pub mod clamp;
pub mod combinations;
pub mod contact_pose;
pub mod enumerate;
pub mod form_closure;
pub mod geometry;
pub mod input;
pub mod locator_sweep;
pub mod metric;
pub mod outline;
pub mod plate;
pub mod polygon;
pub mod pose;
pub mod prepare;
pub mod ranking;
pub mod report;
pub mod segments;
pub mod setups;
pub mod solve;
#[cfg(test)]
mod test_rng;

pub use enumerate::{merge, PartialResult};
pub use input::{Case, Clamp, HoleKind, Kit, MountHole, Params, Part, Pattern, Point, Units};
pub use prepare::{prepare, PrepareError, PreparedPart};
pub use ranking::Fixture;
pub use report::{Counts, FixtureReport, SolveResult, Status};
pub use solve::{report, solve, solve_case};
