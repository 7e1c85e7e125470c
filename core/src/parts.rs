//! The pieces under the pipeline, for code that works below [`crate::solve`]:
//! catalogue readers and drawings (points, outlines and their checks), a
//! coordinator re-deriving a worker's fixture (the clamp search's
//! accumulator and scratch, combination numbering), and the tests and
//! benches that check each stage against a brute force or an independent
//! library. Solving a case needs none of it.

pub use crate::checks::admissibility::{Scratch, Timing};
pub use crate::checks::form_closure::{positively_spanning, wrench, LocatorWrenches};
pub use crate::clamp::{Accumulator, Work};
pub use crate::enumerate::combinations::{combination_at, combinations_in};
pub use crate::geometry::angle_set::AngleSet;
pub use crate::geometry::polygon::{validate_polygon, PolygonError};
pub use crate::geometry::{
    centroid_and_polar_moment, cross, point_segment_dist2, polygon_clearance,
    polygon_clearance_below, polygon_disk_clearance, rot, rot90, rot_t, signed_area, v2, Aabb, V2,
};
pub use crate::metric::{fibonacci_sphere, MaxForceMetric, Metric, PartContact};
pub use crate::outline::{
    ccw_of_cw_outline, edges_of, mass_properties, validate_holes, validate_outline, Edge,
    HoleError, MassProperties, Outline, OutlineError,
};
pub use crate::poses::contact_pose::{
    scaled_jacobian_det, solve_contact_poses, Circle, Contact, ContactPose, ContactPoses,
};
pub use crate::poses::pose::{solve_poses, Line, Pose};
pub use crate::segments::{Feature, LineFeature, Segment};
pub use crate::setups::{SearchStats, Setup};
pub use crate::sweeps::{LocatorSweep, SweepScratch, SweptSegment};
