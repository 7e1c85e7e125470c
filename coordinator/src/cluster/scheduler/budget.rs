//! Work budgets in the cluster (`--part-setups`, `--part-fixtures`,
//! `--part-seconds`), with the embedded run's verdicts: a part beyond
//! them is `over_budget` and never holds the workers longer.
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
//! Fixtures: the same, on the fixtures a part keeps (when its top-k can
//! exceed the cap). A shard's fixtures are admissible fixtures of its
//! part, so the results held for a part are also counted as they come
//! in: past the cap, the part is over at once and its results dropped,
//! so that the coordinator never holds much more than the cap.
//!
//! Seconds: by the coordinator's clock, from the part's first task
//! handed out (each grid step is a part of its own here). A task gets
//! what is left and stops when it runs out; a shard not handed out by
//! then is not handed out at all.

use super::errors::PartFailure;
use super::state::{fail_part, PartSlot, Settings, ShardStatus, ShardWork, State};
use fixplan_core::{fixture_cap, PartialResult};
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
        fixtures: settings.part_fixtures,
        millis,
    })
}

/// Part `p` is over budget: no shard of it goes out again, and the
/// results held for it are dropped.
pub(super) fn fail(st: &mut State, p: usize, stop: BudgetStop) {
    let part = &mut st.parts[p];
    part.partials = Vec::new();
    part.top = Vec::new();
    fail_part(st, p, PartFailure::OverBudget(stop));
}

/// The results held for part `p` keep more fixtures than the cap (they
/// are admissible fixtures of disjoint ranges, so the part keeps at
/// least as many): it is over at once, unless `--good-enough` may drop
/// some of them (a shard past the part's stop), which only its close
/// tells. True when the part was failed.
pub(super) fn held_over(st: &mut State, settings: &Settings, p: usize) -> bool {
    let part = &st.parts[p];
    let Some(cap) = fixture_cap(settings.part_fixtures, part.top_k()) else {
        return false;
    };
    let held: usize = part.partials.iter().map(|h| h.result.fixtures.len()).sum();
    let over = settings.good_enough.is_none() && held as u64 > cap;
    if over {
        fail(st, p, BudgetStop::Fixtures(cap));
    }
    over
}

/// Shard `id` of part `p` stopped on its budget. Without `--good-enough`
/// the part is over at once; with it, a setups or fixtures stop counts
/// only if the shard is not past the part's stop, known when the part
/// closes: the shard is done, and true says the part may be ready to
/// close.
#[must_use]
pub(super) fn shard_over(
    st: &mut State,
    settings: &Settings,
    (p, id): (usize, u64),
    stop: BudgetStop,
) -> bool {
    let deferred = settings.good_enough.is_some()
        && matches!(stop, BudgetStop::Setups(_) | BudgetStop::Fixtures(_));
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
    // The earliest such shard speaks for the part, as the embedded run's
    // first stopped piece in combination order does.
    part.over = Some(part.over.filter(|o| o.0 <= start).unwrap_or((start, stop)));
    true
}

/// When part `p` closes with `merged`: whether it is over budget, for a
/// shard of it not past its stop that stopped, or for the setups or the
/// kept fixtures of all of them.
pub(super) fn over_at_close(
    part: &PartSlot,
    settings: &Settings,
    merged: &PartialResult,
) -> Option<BudgetStop> {
    let shard_over = part
        .over
        .filter(|&(start, _)| part.stop.is_none_or(|stop| start <= stop))
        .map(|(_, stop)| stop);
    let setups = settings
        .part_setups
        .filter(|&budget| merged.counts.setups > budget)
        .map(BudgetStop::Setups);
    let fixtures = fixture_cap(settings.part_fixtures, part.top_k())
        .filter(|&cap| merged.fixtures.len() as u64 > cap)
        .map(BudgetStop::Fixtures);
    shard_over.or(setups).or(fixtures)
}
