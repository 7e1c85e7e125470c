//! Solving one part: the shard planner and its cost model, the grid-step
//! search and good-enough stop, and the embedded solve of a part.
//! Uses the core, catalog and worker crates only; knows nothing of files,
//! messages or the cluster.

pub(crate) mod budget;
pub(crate) mod enumerate;
pub(crate) mod guard;
pub(crate) mod search;
pub(crate) mod shards;
pub(crate) mod solve_part;
pub(crate) mod threads;

pub use guard::solve_guarded;
pub use search::{SearchInfo, SearchOptions, StepSummary};
pub use solve_part::{part_params, JobContext, SolveTiming, Solved};
