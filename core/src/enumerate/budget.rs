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
//!
//! A fixture cap bounds the memory a part holds: with `top_k = 0` every
//! admissible fixture is kept (millions for a big part on a big plate).
//! The fixtures a piece keeps are admissible fixtures of its own range,
//! so any piece's count, and the sum over pieces, is at most the part's;
//! once it is beyond the cap, so is the part (when the cap bites at all:
//! `top_k` 0 or above it), however the range was cut.

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
    /// Fixtures kept at most, when that can bite ([`fixture_cap`]).
    fixtures: Option<u64>,
    /// Wall-clock instant after which the part stops.
    deadline: Option<Instant>,
    /// Setups seen by the combinations done or stopped so far.
    seen: AtomicU64,
    /// Fixtures kept by the combinations done or stopped so far.
    kept: AtomicU64,
}

/// The fixture cap that applies to a part keeping its best `top_k` (0:
/// all): none when `top_k` is within the cap, since the part never
/// keeps more than `top_k`.
pub fn fixture_cap(cap: Option<u64>, top_k: usize) -> Option<u64> {
    cap.filter(|&n| top_k == 0 || top_k as u64 > n)
}

/// Which budget stopped an enumeration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BudgetHalt {
    /// More setups than the budget: the same verdict on every machine.
    Setups(u64),
    /// More fixtures kept than the cap: the same verdict on every machine.
    Fixtures(u64),
    /// Past the deadline (wall clock: not deterministic).
    Deadline,
}

impl WorkBudget {
    /// At most `setups` setups (none: no limit), until `deadline`.
    pub fn new(setups: Option<u64>, deadline: Option<Instant>) -> WorkBudget {
        WorkBudget {
            setups,
            fixtures: None,
            deadline,
            seen: AtomicU64::new(0),
            kept: AtomicU64::new(0),
        }
    }

    /// With at most `cap` fixtures kept by a part keeping its best
    /// `top_k` (the cap is dropped when `top_k` is within it).
    pub fn with_fixtures(self, cap: Option<u64>, top_k: usize) -> WorkBudget {
        WorkBudget {
            fixtures: fixture_cap(cap, top_k),
            ..self
        }
    }

    /// Whether there is anything to check.
    pub fn is_limited(&self) -> bool {
        self.setups.is_some() || self.fixtures.is_some() || self.deadline.is_some()
    }

    /// The fixture cap, if it applies.
    pub fn fixtures(&self) -> Option<u64> {
        self.fixtures
    }

    /// The setup budget, if any.
    pub fn setups(&self) -> Option<u64> {
        self.setups
    }

    /// Setups counted on the shared counter so far.
    pub(crate) fn seen(&self) -> u64 {
        self.seen.load(Ordering::Relaxed)
    }

    /// Fixtures counted on the shared counter so far.
    pub(crate) fn kept(&self) -> u64 {
        self.kept.load(Ordering::Relaxed)
    }

    /// Adds a combination's setups and kept fixtures to the shared
    /// counters.
    pub(crate) fn add(&self, setups: u64, kept: u64) {
        self.seen.fetch_add(setups, Ordering::Relaxed);
        self.kept.fetch_add(kept, Ordering::Relaxed);
    }

    /// Whether `kept` fixtures (a count the caller knows to be at most
    /// the part's) are beyond the cap.
    pub(crate) fn over_fixtures(&self, kept: u64) -> Option<BudgetHalt> {
        self.fixtures
            .filter(|&cap| kept > cap)
            .map(BudgetHalt::Fixtures)
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
    /// whether its merged result (all of it, no piece having stopped),
    /// with `setups` setups and `kept` fixtures, has more setups than the
    /// budget or keeps more fixtures than the cap.
    pub fn verdict(
        &self,
        halted: Option<BudgetHalt>,
        setups: u64,
        kept: usize,
    ) -> Option<BudgetHalt> {
        halted
            .or_else(|| self.setups.filter(|&b| setups > b).map(BudgetHalt::Setups))
            .or_else(|| self.over_fixtures(kept as u64))
    }
}

/// One piece's spending against a [`WorkBudget`], combination by
/// combination: what it adds to the shared counters, or with
/// `good_enough` (pieces after the first hit are dropped, so the setups
/// and fixtures of dropped pieces must not stop a kept one) what it
/// counts on its own.
pub(crate) struct Spending<'a> {
    budget: &'a WorkBudget,
    /// Counting on the shared counters.
    shared: bool,
    /// Setups and fixtures counted when the combination started.
    base: (u64, u64),
    /// The piece's own setups and fixtures before this combination.
    own: (u64, u64),
    /// Setups of this combination so far.
    seen: u64,
    /// Fixtures the piece kept when this combination started.
    kept_at_start: usize,
}

impl<'a> Spending<'a> {
    /// A piece spending `budget`, on its own when not `shared`.
    pub(crate) fn new(budget: &'a WorkBudget, shared: bool) -> Spending<'a> {
        Spending {
            budget,
            shared,
            base: (0, 0),
            own: (0, 0),
            seen: 0,
            kept_at_start: 0,
        }
    }

    /// A combination starts with the piece keeping `kept` fixtures:
    /// whether the budget is spent already.
    pub(crate) fn start(&mut self, kept: usize) -> Option<BudgetHalt> {
        self.base = if self.shared {
            (self.budget.seen(), self.budget.kept())
        } else {
            self.own
        };
        self.seen = 0;
        self.kept_at_start = kept;
        self.budget
            .halt(self.base.0, true)
            .or_else(|| self.budget.over_fixtures(self.base.1))
    }

    /// One more setup: whether it is beyond the budget (checked only
    /// when there is a budget: a bare enumeration pays one addition).
    pub(crate) fn setup(&mut self) -> Option<BudgetHalt> {
        self.seen += 1;
        if !self.budget.is_limited() {
            return None;
        }
        self.budget.halt(self.base.0 + self.seen, false)
    }

    /// The piece now keeps `kept` fixtures: whether that is beyond the
    /// cap.
    pub(crate) fn kept(&self, kept: usize) -> Option<BudgetHalt> {
        self.budget.fixtures?;
        let added = kept.saturating_sub(self.kept_at_start) as u64;
        self.budget.over_fixtures(self.base.1 + added)
    }

    /// The combination ends with the piece keeping `kept` fixtures: its
    /// setups and fixtures are counted.
    pub(crate) fn end(&mut self, kept: usize) {
        let added = kept.saturating_sub(self.kept_at_start) as u64;
        self.own.0 += self.seen;
        self.own.1 += added;
        if self.shared && self.budget.is_limited() {
            self.budget.add(self.seen, added);
        }
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
        assert_eq!(b.verdict(None, 10, 0), None);
        assert_eq!(b.verdict(None, 11, 0), Some(BudgetHalt::Setups(10)));
        assert_eq!(
            b.verdict(Some(BudgetHalt::Deadline), 0, 0),
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

    /// The cap bites only when the part may keep more than it: `top_k`
    /// 0 (all) or above the cap; a count at the cap is within it.
    #[test]
    fn the_fixture_cap_applies_when_top_k_can_exceed_it() {
        assert_eq!(fixture_cap(Some(5), 0), Some(5));
        assert_eq!(fixture_cap(Some(5), 6), Some(5));
        assert_eq!(fixture_cap(Some(5), 5), None);
        assert_eq!(fixture_cap(Some(5), 1), None);
        assert_eq!(fixture_cap(None, 0), None);
        let b = WorkBudget::new(None, None).with_fixtures(Some(5), 0);
        assert!(b.is_limited());
        assert_eq!(b.verdict(None, u64::MAX, 5), None);
        assert_eq!(b.verdict(None, 0, 6), Some(BudgetHalt::Fixtures(5)));
        let within = WorkBudget::new(None, None).with_fixtures(Some(5), 3);
        assert!(!within.is_limited());
        assert_eq!(within.verdict(None, 0, 6), None);
    }

    /// Shared pieces add to one count; a piece on its own
    /// (`good_enough`) counts only itself.
    #[test]
    fn pieces_spend_the_shared_counters_or_their_own() {
        let b = WorkBudget::new(Some(100), None).with_fixtures(Some(4), 0);
        let mut first = Spending::new(&b, true);
        assert_eq!(first.start(0), None);
        assert_eq!(first.setup(), None);
        assert_eq!(first.kept(3), None);
        first.end(3);
        let mut second = Spending::new(&b, true);
        assert_eq!(second.start(0), None);
        assert_eq!(second.kept(1), None, "3 + 1 is at the cap");
        assert_eq!(second.kept(2), Some(BudgetHalt::Fixtures(4)));
        let mut alone = Spending::new(&b, false);
        assert_eq!(alone.start(0), None);
        assert_eq!(alone.kept(4), None, "its own 4 only");
        alone.end(4);
        assert_eq!(alone.start(4), None);
        assert_eq!(alone.kept(5), Some(BudgetHalt::Fixtures(4)));
        second.end(2);
        let mut third = Spending::new(&b, true);
        assert_eq!(third.start(0), Some(BudgetHalt::Fixtures(4)));
    }
}
