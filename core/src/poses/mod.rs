//! The part poses that put three locators on three segments (SPEC 3 and
//! 8.4): on three grown lines, the closed form of [`pose`]; with an arc,
//! the trigonometric elimination of [`contact_pose`], which falls back on
//! the closed form when every contact is a line.

pub(crate) mod contact_pose;
pub(crate) mod pose;
