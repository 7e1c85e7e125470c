//! What keeps one part from stopping a run: a panic anywhere in a part's
//! solve (preparing, enumerating) becomes that part's `failed` result,
//! written and counted like any other, and the run goes on. (The work
//! budget is [`super::budget`], checked inside the solve.)

use super::search::SearchInfo;
use super::solve_part::{solve_part, JobContext, Preparation, SolveTiming, Solved};
use fixplan_catalog::CatalogPart;
use fixplan_core::{SolveResult, Status};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::Instant;

/// [`solve_part`], a panic anywhere in it becoming the part's
/// [`Status::Failed`] result naming the part and the panic.
pub fn solve_guarded(ctx: &JobContext, cp: &CatalogPart, preparation: Preparation) -> Solved {
    let start = Instant::now();
    catch_unwind(AssertUnwindSafe(|| solve_part(ctx, cp, preparation))).unwrap_or_else(|p| {
        let message = format!(
            "{}: the solver failed (a bug, not the part's fault): {}",
            cp.id,
            fixplan_worker::panic_text(p)
        );
        Solved {
            result: SolveResult::gave_up(Status::Failed, message),
            timing: SolveTiming {
                prepare_ms: start.elapsed().as_secs_f64() * 1e3,
                ..SolveTiming::default()
            },
            search: SearchInfo::default(),
        }
    })
}
