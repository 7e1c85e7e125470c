//! Trust but verify: the checks a shard result must pass before it is
//! merged. Every result gets the shape checks; for the results the
//! [`VerifyPolicy`] picks, every fixture that would enter the part's top-k
//! is re-derived from the part the coordinator holds (its locator setup
//! enumerated again and the clamp placed again), which recomputes form
//! closure, admissibility and score; the fixture must come out identical.

use fixplan_core::parts::{combination_at, Accumulator, Scratch};
use fixplan_core::{Fixture, PartialResult, PrepareError, PreparedPart};
use fixplan_worker::finish::{FinishInputs, Finisher};
use fixplan_worker::part_input::short_hex;
use fixplan_worker::protocol::Digest;
use fixplan_worker::protocol::FinishError;
use std::cmp::Ordering;
use std::ops::Range;
use thiserror::Error;

/// Why a shard result is not merged. The text goes back to the worker in
/// the reply's notes and into the coordinator's log, so it names the
/// shard's figures as the worker sent them.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum CheckError {
    /// The result answers another part than the shard's (a worker mixing
    /// up its inputs).
    #[error("result for part {}, shard is of part {}", short_hex(.got), short_hex(.want))]
    OtherPart {
        /// Digest of the part the result names.
        got: Digest,
        /// Digest of the shard's part.
        want: Digest,
    },
    /// A part sent whole could not be prepared here for a deep check.
    #[error("the coordinator cannot prepare the part: {0}")]
    CannotPrepare(PrepareError),
    /// More fixtures than a top-k keeps.
    #[error("{len} fixtures, top_k is {top_k}")]
    TooManyFixtures {
        /// Fixtures in the result.
        len: usize,
        /// The part's top-k.
        top_k: usize,
    },
    /// More fixtures than the result says were admissible.
    #[error("{len} fixtures but {admissible} admissible")]
    MoreThanAdmissible {
        /// Fixtures in the result.
        len: usize,
        /// Admissible fixtures it counted.
        admissible: u64,
    },
    /// The fixtures are not best first (the merge relies on the order).
    #[error("fixtures not in rank order")]
    NotInRankOrder,
    /// A score that is NaN or infinite would poison the ranking.
    #[error("fixture {index} has score {score}")]
    ScoreNotFinite {
        /// Position of the fixture in the result.
        index: usize,
        /// Its score.
        score: f64,
    },
    /// A result of a part sent whole that does not cover what it should.
    #[error("result for combinations {range:?} ({combinations} of {segments} segments), expected {expected:?}")]
    WrongCover {
        /// Combinations the result says it covers.
        range: Range<u64>,
        /// Combinations it counted.
        combinations: u64,
        /// Segments it counted.
        segments: u64,
        /// The combinations it should cover.
        expected: Range<u64>,
    },
    /// A fixture on segments the part does not have.
    #[error("fixture {index} on segments {segments:?}, not of the part")]
    NotOfThePart {
        /// Position of the fixture in the result.
        index: usize,
        /// Its segments.
        segments: [usize; 3],
    },
    /// A stop reported for a run without `--good-enough`.
    #[error("stopped at {at} without --good-enough")]
    StopWithoutGoodEnough {
        /// The combination it claims to have stopped at.
        at: u64,
    },
    /// A stop outside the shard it answers.
    #[error("stopped at {at}, outside the shard {shard:?}")]
    StopOutsideShard {
        /// The combination it claims to have stopped at.
        at: u64,
        /// The shard's combinations.
        shard: Range<u64>,
    },
    /// A stop with no fixture good enough to justify it.
    #[error("stopped at {at} but no fixture scores {good_enough} or better")]
    StopWithoutScore {
        /// The combination it claims to have stopped at.
        at: u64,
        /// The `--good-enough` threshold.
        good_enough: f64,
    },
    /// A fixture good enough to stop at, but no stop reported.
    #[error("a fixture scores {score} (good enough: {good_enough}) but the shard did not stop")]
    MissedStop {
        /// The best fixture's score.
        score: f64,
        /// The `--good-enough` threshold.
        good_enough: f64,
    },
    /// A finished part that is not what its (checked) result makes.
    #[error("its finished part differs from the result's: {0}")]
    Finished(FinishError),
    /// An answer of another kind than its task asked for (a finished part
    /// for a shard, an enumeration for a finishing).
    #[error("an answer of another kind than its task")]
    WrongAnswer,
    /// The result covers other combinations than the shard.
    #[error("result for combinations {range:?}, shard is {shard:?}")]
    WrongRange {
        /// Combinations the result says it covers.
        range: Range<u64>,
        /// The shard's combinations.
        shard: Range<u64>,
    },
    /// Counts that the shard and the part do not give.
    #[error("counts {combinations} combinations / {segments} segments, expected {want_combinations} / {want_segments}")]
    WrongCounts {
        /// Combinations the result counted.
        combinations: u64,
        /// Segments the result counted.
        segments: u64,
        /// Combinations of the shard.
        want_combinations: u64,
        /// Segments of the part.
        want_segments: usize,
    },
    /// Fixtures in a shard that has no combination.
    #[error("fixtures in an empty shard")]
    FixturesInEmptyShard,
    /// A fixture on segments of another shard.
    #[error("fixture {index} on segments {segments:?}, outside the shard")]
    OutsideShard {
        /// Position of the fixture in the result.
        index: usize,
        /// Its segments.
        segments: [usize; 3],
    },
    /// A fixture the part's own enumeration does not give: the worker
    /// computes differently (or lies).
    #[error(
        "fixture {index} (segments {segments:?}, locators {locators:?}, score {score}) does not check out: \
         form closure, clamp or score differ from the part's own enumeration"
    )]
    DoesNotCheckOut {
        /// Position of the fixture in the result.
        index: usize,
        /// Its segments.
        segments: [usize; 3],
        /// Its locators.
        locators: [[i64; 2]; 3],
        /// Its score.
        score: f64,
    },
}

/// A `--verify` value that is none of `all`, `sample` or `1/N`.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("unknown verification {0:?} (all, sample, or 1/N)")]
pub struct UnknownPolicy(String);

/// How much of a shard result the coordinator re-derives before merging.
/// Structural checks (range, counts, order, fixtures inside the shard,
/// finite scores) are made on every result whatever the policy.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VerifyPolicy {
    /// Every fixture that would enter its part's top-k, in every result.
    All,
    /// Every such fixture of a worker's results until [`FULL_CHECKS`] of
    /// its fixtures have checked out (a worker built or running
    /// differently shows up there), then of one result in `one_in`, picked
    /// by a hash of the shard id (the same shards whichever worker runs
    /// them).
    Sample {
        /// One result in this many is checked in full, once a worker has
        /// earned trust.
        one_in: u64,
    },
}

/// Fixtures of each worker re-derived before [`VerifyPolicy::Sample`]
/// starts sampling its results.
pub const FULL_CHECKS: u64 = 16;

impl Default for VerifyPolicy {
    fn default() -> Self {
        VerifyPolicy::Sample { one_in: 32 }
    }
}

impl std::str::FromStr for VerifyPolicy {
    type Err = UnknownPolicy;
    fn from_str(text: &str) -> Result<Self, UnknownPolicy> {
        match text {
            "all" => Ok(VerifyPolicy::All),
            "sample" => Ok(VerifyPolicy::default()),
            _ => text
                .strip_prefix("1/")
                .and_then(|n| n.parse::<u64>().ok())
                .filter(|&n| n >= 1)
                .map(|one_in| VerifyPolicy::Sample { one_in })
                .ok_or_else(|| UnknownPolicy(text.to_string())),
        }
    }
}

impl VerifyPolicy {
    /// Whether to re-derive the fixtures of this result.
    pub(crate) fn deep(self, shard_id: u64, rederived_from_worker: u64) -> bool {
        match self {
            VerifyPolicy::All => true,
            VerifyPolicy::Sample { one_in } => {
                rederived_from_worker < FULL_CHECKS
                    || splitmix64(shard_id).is_multiple_of(one_in.max(1))
            }
        }
    }
}

fn splitmix64(seed: u64) -> u64 {
    let mut z = seed.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Whether `f` is exactly what the enumeration gives for its segments,
/// locators, clamp segment and rotation (core's own code path, restricted to
/// that clamp side, so the check costs a fraction of the enumeration).
pub fn rederive(prep: &PreparedPart, fixture: &Fixture) -> bool {
    let n = prep.segments().len();
    let [a, b, c] = fixture.segments;
    if !(a <= b && b <= c && c < n && a != c) || fixture.locators[0] != [0, 0] {
        return false;
    }
    let mut acc = Accumulator::new(0);
    let mut scratch = Scratch::default();
    prep.setups_for_locators(
        fixture.segments,
        fixture.locators[1],
        fixture.locators[2],
        |s| {
            prep.process_setup_for_clamp(
                s,
                &mut acc,
                &mut scratch,
                fixture.clamp_segment,
                fixture.rotation,
            )
        },
    );
    acc.top.into_sorted().iter().any(|g| g == fixture)
}

/// Whether `f` would enter a top-k that holds `top` (sorted, best first).
pub fn enters(top: &[Fixture], top_k: usize, fixture: &Fixture) -> bool {
    top_k == 0
        || top.len() < top_k
        || top
            .get(top_k - 1)
            .is_some_and(|w| fixture.rank_cmp(w) == Ordering::Less)
}

/// The checks of the fixture list that hold for any shard: at most
/// `top_k`, no more than the admissible count, in rank order, finite
/// scores.
fn check_list(top_k: usize, res: &PartialResult) -> Result<(), CheckError> {
    let len = res.fixtures.len();
    if top_k != 0 && len > top_k {
        return Err(CheckError::TooManyFixtures { len, top_k });
    }
    if let Some(admissible) = res.counts.admissible().filter(|&a| (len as u64) > a) {
        return Err(CheckError::MoreThanAdmissible { len, admissible });
    }
    if res
        .fixtures
        .windows(2)
        .any(|w| w[0].rank_cmp(&w[1]) != Ordering::Less)
    {
        return Err(CheckError::NotInRankOrder);
    }
    match res.fixtures.iter().position(|f| !f.score.is_finite()) {
        Some(index) => Err(CheckError::ScoreNotFinite {
            index,
            score: res.fixtures[index].score,
        }),
        None => Ok(()),
    }
}

/// The checks that need no prepared part, for a part sent whole and not
/// re-derived: the result must cover `range` (the whole part, or its
/// prefix up to a `--good-enough` hit) with counts consistent with its own
/// segment count, and hold fixtures of that part.
pub fn check_shape(
    top_k: usize,
    range: &Range<u64>,
    res: &PartialResult,
) -> Result<(), CheckError> {
    let n = res.counts.segments;
    let count = fixplan_core::combination_count(n as usize);
    let want = range.end.min(count).saturating_sub(range.start);
    if res.range != *range || res.counts.combinations != want {
        return Err(CheckError::WrongCover {
            range: res.range.clone(),
            combinations: res.counts.combinations,
            segments: n,
            expected: range.clone(),
        });
    }
    check_list(top_k, res)?;
    for (index, f) in res.fixtures.iter().enumerate() {
        let [a, b, c] = f.segments;
        if !(a <= b && b <= c && (c as u64) < n && a != c) || f.clamp_segment as u64 >= n {
            return Err(CheckError::NotOfThePart {
                index,
                segments: f.segments,
            });
        }
    }
    Ok(())
}

/// `--good-enough`: a shard stops exactly when it admits a fixture scoring
/// the threshold or better, and its best fixture (first, lowest score)
/// tells whether it did.
pub fn check_stop(
    good_enough: Option<f64>,
    shard: &Range<u64>,
    hit: Option<u64>,
    res: &PartialResult,
) -> Result<(), CheckError> {
    let best = res.fixtures.first().map(|f| f.score);
    match (good_enough, hit) {
        (None, None) => Ok(()),
        (None, Some(at)) => Err(CheckError::StopWithoutGoodEnough { at }),
        (Some(_), Some(at)) if !shard.contains(&at) => Err(CheckError::StopOutsideShard {
            at,
            shard: shard.clone(),
        }),
        (Some(good_enough), Some(at)) if best.is_none_or(|b| b > good_enough) => {
            Err(CheckError::StopWithoutScore { at, good_enough })
        }
        (Some(good_enough), None) if best.is_some_and(|b| b <= good_enough) => {
            Err(CheckError::MissedStop {
                score: best.unwrap_or(good_enough),
                good_enough,
            })
        }
        _ => Ok(()),
    }
}

/// Whether the finished part `theirs` a worker sent with a part's result
/// (checked before) is what the coordinator's finisher makes of the same
/// `inputs`: finished here the same way (with the worker's timing) and
/// compared.
pub fn check_finished(
    finisher: &dyn Finisher,
    inputs: &FinishInputs,
    theirs: &[u8],
) -> Result<(), CheckError> {
    finisher.check(inputs, theirs).map_err(CheckError::Finished)
}

/// Checks a shard result against the shard it answers and the part's
/// current top-k; `deep`: also re-derive every fixture that would enter
/// the top-k (see [`VerifyPolicy`]). Returns how many
/// fixtures were re-derived.
pub fn check(
    prep: &PreparedPart,
    range: &Range<u64>,
    res: &PartialResult,
    top: &[Fixture],
    deep: bool,
) -> Result<usize, CheckError> {
    let count = prep.combination_count();
    if res.range != *range {
        return Err(CheckError::WrongRange {
            range: res.range.clone(),
            shard: range.clone(),
        });
    }
    let want = range.end.min(count).saturating_sub(range.start);
    if res.counts.combinations != want || res.counts.segments != prep.segments().len() as u64 {
        return Err(CheckError::WrongCounts {
            combinations: res.counts.combinations,
            segments: res.counts.segments,
            want_combinations: want,
            want_segments: prep.segments().len(),
        });
    }
    check_list(prep.top_k(), res)?;
    let n = prep.segments().len();
    let (first, last) = match (
        combination_at(n, range.start),
        combination_at(n, want.saturating_sub(1) + range.start),
    ) {
        (Some(a), Some(b)) => (a, b),
        _ if res.fixtures.is_empty() => return Ok(0),
        _ => return Err(CheckError::FixturesInEmptyShard),
    };
    let mut checked = 0;
    for (index, f) in res.fixtures.iter().enumerate() {
        if f.segments < first || f.segments > last {
            return Err(CheckError::OutsideShard {
                index,
                segments: f.segments,
            });
        }
        if deep && enters(top, prep.top_k(), f) {
            if !rederive(prep, f) {
                return Err(CheckError::DoesNotCheckOut {
                    index,
                    segments: f.segments,
                    locators: f.locators,
                    score: f.score,
                });
            }
            checked += 1;
        }
    }
    Ok(checked)
}

#[cfg(test)]
mod tests {
    use super::*;
    use fixplan_catalog::kit::{builtin_kit, METRIC_25};
    use fixplan_core::{prepare, Params, Part};

    #[test]
    fn sampling_checks_a_new_worker_in_full_then_one_result_in_n() {
        let p = VerifyPolicy::Sample { one_in: 16 };
        assert!((0..100).all(|id| p.deep(id, 0)));
        assert!((0..100).all(|id| p.deep(id, FULL_CHECKS - 1)));
        let hits = (0..16_000).filter(|&id| p.deep(id, FULL_CHECKS)).count();
        assert!((800..1200).contains(&hits), "{hits}");
        assert!((0..100).all(|id| VerifyPolicy::All.deep(id, 1000)));
        assert_eq!("all".parse(), Ok(VerifyPolicy::All));
        assert_eq!("1/4".parse(), Ok(VerifyPolicy::Sample { one_in: 4 }));
        assert_eq!("sample".parse(), Ok(VerifyPolicy::default()));
        assert!("1/0".parse::<VerifyPolicy>().is_err());
        assert!("most".parse::<VerifyPolicy>().is_err());
    }

    #[test]
    fn a_stop_must_match_the_scores() {
        let (kit, units) = builtin_kit(METRIC_25).expect("built-in kit");
        let part = Part::polygon(&[[0.0, 0.0], [120.0, 0.0], [120.0, 70.0], [0.0, 70.0]]);
        let params = Params {
            top_k: 0,
            ..Params::default()
        };
        let prep = prepare(&part, &kit, &params, units).expect("prepare");
        let all = 0..prep.combination_count();
        let full = prep.enumerate_range(all.clone());
        let mut scores: Vec<f64> = full.fixtures.iter().map(|f| f.score).collect();
        scores.sort_by(f64::total_cmp);
        assert!(scores.len() > 4, "{}", scores.len());
        let g = scores[scores.len() / 2];
        let done = prep.enumerate(all.clone(), fixplan_core::EnumerateOptions::good_enough(g));
        let (res, hit) = (done.result, done.stopped_at);
        let h = hit.expect("the median score is reached");
        assert_eq!(res.counts.combinations, h + 1);
        assert_eq!(check_stop(Some(g), &all, hit, &res), Ok(()));
        // Hiding the stop, claiming one without --good-enough, or outside.
        assert!(check_stop(Some(g), &all, None, &res).is_err());
        assert!(check_stop(None, &all, hit, &res).is_err());
        assert!(check_stop(Some(g), &(0..h), hit, &res).is_err());
        // A threshold nothing reaches: no stop, and a claimed one is false.
        let low = scores[0] - 1.0;
        assert_eq!(check_stop(Some(low), &all, None, &full), Ok(()));
        assert!(check_stop(Some(low), &all, Some(0), &full).is_err());
        assert_eq!(check_stop(None, &all, None, &full), Ok(()));
        // The prefix checks out against the part as a shard of it.
        let prefix = 0..h + 1;
        assert!(check(&prep, &prefix, &res, &[], true).is_ok());
        assert!(check(&prep, &all, &res, &[], false).is_err());
    }

    /// The texts reach workers (reply notes) and logs: they stay as they were.
    #[test]
    fn check_errors_read_as_before() {
        let cases = [
            (
                CheckError::OtherPart {
                    got: [0xab; 32],
                    want: [1; 32],
                },
                "result for part abababababab, shard is of part 010101010101",
            ),
            (
                CheckError::WrongCover {
                    range: 0..3,
                    combinations: 3,
                    segments: 5,
                    expected: 0..4,
                },
                "result for combinations 0..3 (3 of 5 segments), expected 0..4",
            ),
            (
                CheckError::StopWithoutScore {
                    at: 7,
                    good_enough: 0.5,
                },
                "stopped at 7 but no fixture scores 0.5 or better",
            ),
            (
                CheckError::DoesNotCheckOut {
                    index: 0,
                    segments: [0, 2, 3],
                    locators: [[0, 0], [4, 1], [4, 2]],
                    score: 0.25,
                },
                "fixture 0 (segments [0, 2, 3], locators [[0, 0], [4, 1], [4, 2]], score 0.25) \
                 does not check out: form closure, clamp or score differ from the part's own \
                 enumeration",
            ),
        ];
        for (e, text) in cases {
            assert_eq!(e.to_string(), text);
        }
        assert_eq!(
            "most".parse::<VerifyPolicy>().unwrap_err().to_string(),
            "unknown verification \"most\" (all, sample, or 1/N)"
        );
    }
}
