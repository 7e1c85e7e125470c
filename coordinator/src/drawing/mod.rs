//! The geometry every picture of a fixture is drawn from (plate holes,
//! the part in its pose, locators, clamp, contacts and the holes they
//! stand in; outlines with arcs
//! flattened for drawing), in plate coordinates and free of any output
//! format: the Foxglove scene of the results file (`output::scene`) and
//! the SVG pictures of `view` both draw from it, so it sits below both.

pub(crate) mod draw;
pub(crate) mod hole_contacts;
pub(crate) mod outline;
