//! What people look at: SVG pictures of fixtures with an HTML gallery,
//! and the tables and JSON lines of `show` and `export`. Uses `output`
//! (messages, the results reader), `drawing` and core.
//!
//! [`crate::drawing`] places a fixture on the plate; [`picture`] (SVG,
//! with [`svg`]) draws it, as `output::scene` does for Foxglove;
//! [`render`] writes the pictures and the gallery; [`show`] prints tables
//! and JSON lines.

pub(crate) mod picture;
pub(crate) mod render;
pub(crate) mod show;
pub(crate) mod svg;

#[cfg(test)]
mod tests;
