//! Solving one part: the shard planner and its cost model, the grid-step
//! search and good-enough stop, and the embedded solve of a part.
//! Uses the core, catalog and worker crates only; knows nothing of files,
//! messages or the cluster.

pub mod budget;
pub mod enumerate;
pub mod guard;
pub mod search;
pub mod shards;
pub mod solve;

pub use guard::solve_guarded;
pub use search::{SearchError, SearchInfo, SearchOptions, StepSummary};
pub use solve::{part_params, solve_part, JobContext, Solved, Timing};
