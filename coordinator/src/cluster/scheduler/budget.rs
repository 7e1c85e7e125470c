//! Work budgets in the cluster (`--part-setups`, `--part-seconds`), with
//! the embedded run's verdicts: a part beyond them is `over_budget` and
//! never holds the workers longer.
//!
//! Setups: every task carries the budget, and a task that sees more
//! setups than it stops ([`TaskError::OverBudget`]); since a task's
//! setups are at most its part's, that part is over whatever the shard
//! cut. A part whose tasks all stay within is checked on its merged
//! setups when it closes. So the same parts are over budget whatever the
//! workers, the shard size or the threads, as in `fixplan run`. With
//! `--good-enough` a shard past the part's stop does not count (the
//! embedded run never enumerates it), and the stop is only known when
//! the part closes: such a shard's verdict waits until then.
//!
//! Seconds: by the coordinator's clock, from the part's first task
//! handed out (each grid step is a part of its own here). A task gets
//! what is left and stops when it runs out; a shard not handed out by
//! then is not handed out at all.

use super::errors::PartFailure;
use super::state::{fail_part, PartSlot, Settings, ShardStatus, ShardWork, State};
use fixplan_worker::protocol::{BudgetStop, TaskBudget};
use std::time::Instant;

/// What a task of `part` may spend, handed out at `now`; the stop when
/// the part's time is up already (a [`fail`]).
pub(super) fn task_budget(
    part: &mut PartSlot,
    settings: &Settings,
    now: Instant,
) -> Result<TaskBudget, BudgetStop> {
    let millis = match settings.part_seconds {
        None => None,
        Some(seconds) => {
            let started = *part.started.get_or_insert(now);
            let left = seconds - now.duration_since(started).as_secs_f64();
            if left <= 0.0 {
                return Err(BudgetStop::Deadline);
            }
            Some((left * 1e3).ceil() as u64)
        }
    };
    Ok(TaskBudget {
        setups: settings.part_setups,
        millis,
    })
}

/// Part `p` is over budget: no shard of it goes out again.
pub(super) fn fail(st: &mut State, p: usize, stop: BudgetStop) {
    fail_part(st, p, PartFailure::OverBudget(stop));
}

/// Shard `id` of part `p` stopped on its budget. Without `--good-enough`
/// the part is over at once; with it, a setups stop counts only if the
/// shard is not past the part's stop, known when the part closes: the
/// shard is done, and true says the part may be ready to close.
#[must_use]
pub(super) fn shard_over(
    st: &mut State,
    settings: &Settings,
    (p, id): (usize, u64),
    stop: BudgetStop,
) -> bool {
    let deferred = settings.good_enough.is_some() && matches!(stop, BudgetStop::Setups(_));
    if !deferred {
        fail(st, p, stop);
        return false;
    }
    let start = match &st.shards[id as usize].work {
        ShardWork::Combinations(range) => range.start,
        ShardWork::Finishing(_) => 0,
    };
    st.shards[id as usize].status = ShardStatus::Done;
    let part = &mut st.parts[p];
    part.over = Some(part.over.map_or(start, |s| s.min(start)));
    true
}

/// When part `p` closes with `setups` merged: whether it is over budget,
/// for a shard of it not past its stop that stopped, or for the setups of
/// all of them.
pub(super) fn over_at_close(
    part: &PartSlot,
    settings: &Settings,
    setups: u64,
) -> Option<BudgetStop> {
    let budget = settings.part_setups?;
    let shard_over = part
        .over
        .is_some_and(|start| part.stop.is_none_or(|stop| start <= stop));
    (shard_over || setups > budget).then_some(BudgetStop::Setups(budget))
}
