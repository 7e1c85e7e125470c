//! A part's work budget, checked inside the enumeration: a part far
//! bigger than the plate (a catalogue entry in inches read as mm) has
//! millions of setups in a handful of combinations, so a check between
//! combinations or before preparing cannot stop it.
//!
//! The deterministic unit is the setup (SPEC section 4's `setups`
//! count): each combination's setups do not depend on how the range is
//! cut, so "the part has more setups than the budget" is the same verdict
//! whatever the threads, shards or workers, even though how far each
//! piece got when it stopped is not. A deadline is also offered; it is
//! wall-clock time, so its verdict is not deterministic.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// Check the deadline every this many setups (a clock read costs about
/// as much as a few setups' bookkeeping, far less than one clamp search).
const DEADLINE_EVERY: u64 = 64;

/// What one part may spend, shared by every piece and shard of its
/// enumeration (on one machine): they add the setups they see to one
/// counter, so the part stops soon after the budget, not after the
/// budget times the pieces.
#[derive(Debug, Default)]
pub struct WorkBudget {
    /// Setups at most (SPEC's `setups` count over the part).
    setups: Option<u64>,
    /// Wall-clock instant after which the part stops.
    deadline: Option<Instant>,
    /// Setups seen by the combinations done or stopped so far.
    seen: AtomicU64,
}

/// Which budget stopped an enumeration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BudgetHalt {
    /// More setups than the budget: the same verdict on every machine.
    Setups(u64),
    /// Past the deadline (wall clock: not deterministic).
    Deadline,
}

impl WorkBudget {
    /// At most `setups` setups (none: no limit), until `deadline`.
    pub fn new(setups: Option<u64>, deadline: Option<Instant>) -> WorkBudget {
        WorkBudget {
            setups,
            deadline,
            seen: AtomicU64::new(0),
        }
    }

    /// Whether there is anything to check.
    pub fn is_limited(&self) -> bool {
        self.setups.is_some() || self.deadline.is_some()
    }

    /// The setup budget, if any.
    pub fn setups(&self) -> Option<u64> {
        self.setups
    }

    /// Setups counted on the shared counter so far.
    pub(crate) fn seen(&self) -> u64 {
        self.seen.load(Ordering::Relaxed)
    }

    /// Adds a combination's setups to the shared counter.
    pub(crate) fn add(&self, setups: u64) {
        self.seen.fetch_add(setups, Ordering::Relaxed);
    }

    /// Whether `setups` (a count the caller knows to be at most the
    /// part's) is beyond the budget, or, every [`DEADLINE_EVERY`] setups
    /// (`setups` itself when `always`), the deadline has passed.
    pub(crate) fn halt(&self, setups: u64, always: bool) -> Option<BudgetHalt> {
        if let Some(budget) = self.setups.filter(|&b| setups > b) {
            return Some(BudgetHalt::Setups(budget));
        }
        let due = always || setups.is_multiple_of(DEADLINE_EVERY);
        self.deadline
            .filter(|&d| due && Instant::now() >= d)
            .map(|_| BudgetHalt::Deadline)
    }

    /// The verdict on a whole enumeration: the halt a piece met, else
    /// whether the setups it counted (all of them, no piece having
    /// stopped) are beyond the budget.
    pub fn verdict(&self, halted: Option<BudgetHalt>, setups: u64) -> Option<BudgetHalt> {
        halted.or_else(|| self.setups.filter(|&b| setups > b).map(BudgetHalt::Setups))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn halts_past_the_setups_and_the_deadline_only() {
        let none = WorkBudget::default();
        assert!(!none.is_limited());
        assert_eq!(none.halt(u64::MAX, true), None);
        let b = WorkBudget::new(Some(10), None);
        assert_eq!(b.halt(10, true), None);
        assert_eq!(b.halt(11, false), Some(BudgetHalt::Setups(10)));
        assert_eq!(b.verdict(None, 10), None);
        assert_eq!(b.verdict(None, 11), Some(BudgetHalt::Setups(10)));
        assert_eq!(
            b.verdict(Some(BudgetHalt::Deadline), 0),
            Some(BudgetHalt::Deadline)
        );
        let past = Instant::now() - Duration::from_millis(1);
        let d = WorkBudget::new(None, Some(past));
        assert_eq!(d.halt(1, true), Some(BudgetHalt::Deadline));
        assert_eq!(d.halt(1, false), None, "not due between checks");
        assert_eq!(d.halt(DEADLINE_EVERY, false), Some(BudgetHalt::Deadline));
        let later = WorkBudget::new(None, Some(Instant::now() + Duration::from_secs(3600)));
        assert_eq!(later.halt(DEADLINE_EVERY, true), None);
    }
}
