//! The whole enumeration of a part: [`prepare`] it once, number its
//! segment [`combinations`], run any range of them through the stages
//! ([`shards`]) and give the result in the reported form ([`whole_part`]).

pub(crate) mod budget;
#[cfg(test)]
mod clamp_filters;
pub(crate) mod combinations;
pub(crate) mod prepare;
pub(crate) mod shards;
pub(crate) mod whole_part;
