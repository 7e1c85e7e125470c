//! What an enumeration produces: fixtures in their canonical order and the
//! top-k that merges the same however the work was split ([`ranking`]),
//! and the counts and reported form of a result ([`report`]).

pub(crate) mod ranking;
pub(crate) mod report;
