//! The sharding API: enumerate a range of combination indices into a partial
//! result, and merge partial results. Any split of the range merges to the
//! same bytes as one run, because counts add and the ranking is a total
//! order on fixtures that are each computed from their own inputs only.

use crate::checks::admissibility::{Scratch, Timing};
use crate::clamp::{Accumulator, ClampSearch, Work};
use crate::enumerate::budget::{BudgetHalt, Spending, WorkBudget};
use crate::enumerate::combinations::{combination_count, combinations_in};
use crate::results::ranking::{merge_ranked, Fixture};
use crate::results::report::Counts;
use crate::setups::{SearchStats, SetupScratch, SetupSearch};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::ops::Range;

/// Counts and top-k of a piece of one part's combination space.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PartialResult {
    /// The combination indices covered, so a merge can tell pieces apart
    /// and a coordinator can check a shard did the work it was given.
    pub range: Range<u64>,
    /// SPEC section 4's counts over the range.
    pub counts: Counts,
    /// Best first; at most `top_k` (all when `top_k == 0`).
    pub fixtures: Vec<Fixture>,
}

/// Where one enumeration spent its work (not part of the result: timings
/// vary from run to run).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Profile {
    /// How much the pruning let through.
    pub search: SearchStats,
    /// Time per stage (zero unless asked for).
    pub timing: Timing,
    /// What the top-k mode skipped.
    pub work: Work,
    /// Wall time of the whole enumeration, nanoseconds.
    pub total_ns: u64,
}

impl Profile {
    /// Sums the profiles of pieces of work (threads, shards).
    pub fn add(&mut self, other: &Profile) {
        self.search.add(&other.search);
        self.timing.add(&other.timing);
        self.work.add(&other.work);
        self.total_ns += other.total_ns;
    }
}

/// Combinations per rayon task: small enough to balance, large enough that
/// the merge is cheap.
const CHUNK: u64 = 32;

/// The stages one piece of enumeration runs, borrowed from a prepared
/// part: the setup search of each combination, then the clamp search of
/// each setup.
#[derive(Clone, Copy)]
pub(crate) struct Stages<'a> {
    /// Locator setups of a combination.
    pub(crate) setups: SetupSearch<'a>,
    /// Clamp candidates, mounts and scores of a setup.
    pub(crate) clamp: ClampSearch<'a>,
}

impl Stages<'_> {
    /// Size of the combination space.
    fn combination_count(&self) -> u64 {
        combination_count(self.setups.segments.len())
    }

    /// Whether results count admissible fixtures (not in top-k mode).
    fn counts_exact(&self) -> bool {
        !self.clamp.setting.prune_to_top_k
    }

    /// Where a piece of work collects its fixtures: in top-k mode it skips
    /// the mount search of candidates that cannot enter its own top-k.
    /// Each piece then still holds the exact top-k of its range, and the
    /// top-k of a union is the top-k of the pieces' top-ks, so any split
    /// merges to the full enumeration's top-k.
    fn accumulator(&self) -> Accumulator {
        let setting = self.clamp.setting;
        if setting.prune_to_top_k {
            Accumulator::top_k_mode(setting.top_k)
        } else {
            Accumulator::new(setting.top_k)
        }
    }

    /// `range` (clipped to the part) cut into rayon tasks of [`CHUNK`]
    /// combinations: fixed cuts, so no result depends on the thread count.
    /// In top-k mode a piece's result is its range's exact top-k whatever
    /// the cuts, so the pieces are made as few as the threads allow: each
    /// starts with an empty top-k that lets every candidate through, and
    /// small pieces would search mounts for most of them.
    fn chunks(&self, range: &Range<u64>) -> Vec<Range<u64>> {
        let end = range.end.min(self.combination_count()).max(range.start);
        let size = if self.clamp.setting.prune_to_top_k {
            let pieces = 4 * rayon::current_num_threads() as u64;
            (end - range.start).div_ceil(pieces).max(CHUNK)
        } else {
            CHUNK
        };
        (range.start..end)
            .step_by(size as usize)
            .map(|s| s..(s + size).min(end))
            .collect()
    }

    /// Enumerates `range` in order on this thread, stopping after the
    /// first combination that admits a fixture scoring `good_enough` or
    /// better; `timed` adds clock reads to the inner loop. Returns the
    /// result of the combinations done, where the work went and the
    /// index of the combination that stopped it.
    pub(crate) fn enumerate_serial(
        &self,
        range: Range<u64>,
        options: &EnumerateOptions,
    ) -> RangePiece {
        let (timed, good_enough) = (options.timed, options.good_enough);
        let unlimited = WorkBudget::default();
        // With good_enough, pieces after the first hit are dropped, so a
        // piece counts only its own spending ([`Spending`]).
        let mut spending =
            Spending::new(options.budget.unwrap_or(&unlimited), good_enough.is_none());
        let mut halted = None;
        let clock = std::time::Instant::now();
        let mut acc = self.accumulator();
        let mut scratch = Scratch::default();
        scratch.timing = timed.then(Timing::default);
        let mut setup_scratch = SetupScratch::default();
        let mut search = SearchStats::default();
        let n = self.setups.segments.len();
        let end = range.end.min(self.combination_count());
        let mut hit = None;
        let mut done_to = end;
        for (index, combo) in combinations_in(n, range.start..end) {
            halted = spending.start(acc.top.len());
            if halted.is_some() {
                done_to = index;
                break;
            }
            acc.counts.combinations += 1;
            let s = self
                .setups
                .setups_of_combination(combo, &mut setup_scratch, |s| {
                    // The setup search cannot be left half-way: past the
                    // budget it runs on, but without the clamp search
                    // that costs most of a setup's time.
                    if halted.is_some() {
                        return;
                    }
                    halted = spending.setup();
                    if halted.is_none() {
                        self.clamp.process_setup(s, &mut acc, &mut scratch);
                        halted = spending.kept(acc.top.len());
                    }
                });
            spending.end(acc.top.len());
            search.add(&s);
            if halted.is_some() {
                done_to = index + 1;
                break;
            }
            if good_enough.is_some_and(|g| acc.best_score <= g) {
                hit = Some(index);
                done_to = index + 1;
                break;
            }
        }
        acc.counts.segments = n as u64;
        let profile = Profile {
            search,
            timing: scratch.timing.unwrap_or_default(),
            work: acc.work,
            total_ns: clock.elapsed().as_nanos() as u64,
        };
        let res = PartialResult {
            range: if hit.is_some() || halted.is_some() {
                range.start..done_to
            } else {
                range
            },
            counts: acc.counts,
            fixtures: acc.top.into_sorted(),
        };
        RangePiece {
            result: res,
            profile,
            hit,
            halted,
        }
    }

    /// Enumerates `range` as `options` say: on the rayon pool (same result
    /// as on one thread: fixed chunks, merged in order) or on this thread,
    /// to its end or to the first good-enough fixture. With `good_enough`,
    /// the result is the enumeration of the shortest prefix of `range` (in
    /// combination order) that admits a fixture scoring that or better;
    /// the prefix, hence the result, does not depend on threads or
    /// chunking: chunks run concurrently, the first hit in index order wins
    /// and later chunks are dropped.
    pub(crate) fn enumerate(&self, range: Range<u64>, options: EnumerateOptions) -> Enumeration {
        if options.this_thread {
            let piece = self.enumerate_serial(range, &options);
            return Enumeration {
                result: piece.result,
                stopped_at: piece.hit,
                profile: piece.profile,
                halted: piece.halted,
            };
        }
        use std::sync::atomic::{AtomicU64, Ordering};
        let first_hit = AtomicU64::new(u64::MAX);
        let chunks = self.chunks(&range);
        let parts: Vec<RangePiece> = chunks
            .into_par_iter()
            .filter_map(|r| {
                // A chunk wholly after a known hit cannot matter.
                if r.start > first_hit.load(Ordering::Relaxed) {
                    return None;
                }
                let piece = self.enumerate_serial(r, &options);
                if let Some(h) = piece.hit {
                    first_hit.fetch_min(h, Ordering::Relaxed);
                }
                Some(piece)
            })
            .collect();
        let stop = parts.iter().filter_map(|p| p.hit).min();
        let mut profile = Profile::default();
        let mut kept = Vec::with_capacity(parts.len());
        let mut halted = None;
        for piece in parts {
            if stop.is_none_or(|s| piece.result.range.start <= s) {
                profile.add(&piece.profile);
                halted = halted.or(piece.halted);
                kept.push(piece.result);
            }
        }
        let mut result = merge(self.clamp.setting.top_k, kept);
        result.range = range.start..stop.map_or(range.end, |s| s + 1);
        result.counts.segments = self.setups.segments.len() as u64;
        result.counts.exact = self.counts_exact();
        Enumeration {
            result,
            stopped_at: stop,
            profile,
            halted,
        }
    }
}

/// What one piece of enumeration on one thread gives.
pub(crate) struct RangePiece {
    /// Counts and best fixtures of the combinations it did.
    pub(crate) result: PartialResult,
    /// Where its work went.
    pub(crate) profile: Profile,
    /// With `good_enough`: the combination that admitted a good-enough
    /// fixture, its last.
    pub(crate) hit: Option<u64>,
    /// The budget that stopped it, if one did.
    pub(crate) halted: Option<BudgetHalt>,
}

/// How [`crate::PreparedPart::enumerate`] runs a range of combinations.
/// The default: on the rayon pool, every combination, untimed.
#[derive(Debug, Clone, Copy, Default)]
pub struct EnumerateOptions<'a> {
    /// On the calling thread only (a worker's thread, a bench), rather
    /// than on the rayon pool; the result is the same.
    pub this_thread: bool,
    /// `--good-enough`: stop after the first combination, in index order,
    /// that admits a fixture scoring this or better.
    pub good_enough: Option<f64>,
    /// Time each stage for the profile: clock reads in the inner loop.
    pub timed: bool,
    /// Stop once the part's setups or kept fixtures exceed this budget
    /// or its deadline passes ([`Enumeration::halted`] says which); shared by every
    /// range of the part enumerated in this process.
    pub budget: Option<&'a WorkBudget>,
}

impl EnumerateOptions<'_> {
    /// Every combination, on the calling thread.
    pub fn this_thread() -> EnumerateOptions<'static> {
        EnumerateOptions {
            this_thread: true,
            ..EnumerateOptions::default()
        }
    }

    /// On the rayon pool, up to the first fixture scoring `good_enough` or
    /// better.
    pub fn good_enough(good_enough: f64) -> EnumerateOptions<'static> {
        EnumerateOptions {
            good_enough: Some(good_enough),
            ..EnumerateOptions::default()
        }
    }
}

/// What [`crate::PreparedPart::enumerate`] found.
#[derive(Debug, Clone, PartialEq)]
pub struct Enumeration {
    /// Counts and best fixtures of the combinations enumerated.
    pub result: PartialResult,
    /// With `good_enough`, the combination that admitted a good-enough
    /// fixture, the last one enumerated.
    pub stopped_at: Option<u64>,
    /// Where the work went, summed over the pieces that ran (a
    /// measurement: never part of a result).
    pub profile: Profile,
    /// The budget that stopped a piece (the result is then incomplete).
    /// That no piece stopped does not mean the part is within its setup
    /// budget: [`WorkBudget::verdict`] says.
    pub halted: Option<BudgetHalt>,
}

/// Merges partial results of disjoint ranges of one part.
pub fn merge(top_k: usize, parts: Vec<PartialResult>) -> PartialResult {
    let mut counts = Counts::default();
    let mut start = u64::MAX;
    let mut end = 0;
    let mut lists = Vec::with_capacity(parts.len());
    for p in parts {
        counts.add(&p.counts);
        start = start.min(p.range.start);
        end = end.max(p.range.end);
        lists.push(p.fixtures);
    }
    if start > end {
        start = end;
    }
    PartialResult {
        range: start..end,
        counts,
        fixtures: merge_ranked(lists, top_k),
    }
}
