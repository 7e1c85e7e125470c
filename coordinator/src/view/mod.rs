//! What people look at: the Foxglove scene of a part, SVG pictures of
//! fixtures with an HTML gallery, and the tables and JSON lines of `show`
//! and `export`. Uses `output` (messages, the results reader) and core.

pub mod draw;
pub mod render;
pub mod scene;
pub mod show;
pub mod svg;
