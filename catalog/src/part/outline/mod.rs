//! What the drawing readers share: exact arcs as bulge vertices, curve
//! flattening ([`curves`]), the affine maps of transforms and block
//! references ([`affine`]), joining pieces into loops, arcs kept
//! ([`join`]), the true region of a loop ([`region`]), and choosing the
//! outline among the loops ([`pick`]). Points are plain `[f64; 2]` as
//! files hold them; outlines are core's [`Vertex`](fixplan_core::Vertex)
//! lists (a point and the bulge of the edge leaving it).

mod affine;
mod curves;
mod join;
mod pick;
mod region;

pub(crate) use affine::Affine;
pub(crate) use curves::{
    arc_pieces, arc_points, circle_loop, dist, exact_arc, exact_circle, flatten_vertices, fmt,
    fmt_pt, positions, scale_of, straight, MAX_ARC_PIECES, P,
};
pub(crate) use join::{join_pieces, nearest_other_end, reversed, OpenChain, Piece};
pub use pick::OutlinePickError;
pub(crate) use pick::{keep_holes, pick_outline, pick_outlines};
