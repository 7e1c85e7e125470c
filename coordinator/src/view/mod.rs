//! What people look at: the Foxglove scene of a part, SVG pictures of
//! fixtures with an HTML gallery, and the tables and JSON lines of `show`
//! and `export`. Uses `output` (messages, the results reader) and core.
//!
//! [`draw`] places a fixture on the plate, [`outline`] reads outlines of
//! lines and arcs for drawing; [`scene`] (Foxglove) and
//! [`picture`] (SVG, with [`svg`]) draw it; [`render`] writes the pictures
//! and the gallery; [`show`] prints tables and JSON lines.

pub mod draw;
pub mod outline;
pub mod picture;
pub mod render;
pub mod scene;
pub mod show;
pub mod svg;

#[cfg(test)]
mod tests;
