//! Solving one part: the shard planner and its cost model, the grid-step
//! search and good-enough stop, and the embedded solve of a part.
//! Uses the core, catalog and worker crates only; knows nothing of files,
//! messages or the cluster.

pub mod budget;
pub mod enumerate;
pub mod guard;
pub mod search;
pub mod shards;
pub mod solve_part;
pub mod threads;

pub use guard::solve_guarded;
pub use search::{SearchError, SearchInfo, SearchOptions, StepSummary};
pub use solve_part::{part_params, solve_part, JobContext, SolveTiming, Solved};
