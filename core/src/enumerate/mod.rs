//! The whole enumeration of a part: [`prepare`] it once, number its
//! segment [`combinations`], run any range of them through the stages
//! ([`shards`]) and give the result in the reported form ([`solve`]).

pub(crate) mod combinations;
pub(crate) mod prepare;
pub(crate) mod shards;
pub(crate) mod solve;
