//! Trust but verify: the checks a shard result must pass before it is
//! merged. Every result gets the shape checks; for the results the
//! [`VerifyPolicy`] picks, every fixture that would enter the part's top-k
//! is re-derived from the part the coordinator holds (its locator setup
//! enumerated again and the clamp placed again), which recomputes form
//! closure, admissibility and score; the fixture must come out identical.

use fixplan_core::admissibility::Scratch;
use fixplan_core::clamp::Accumulator;
use fixplan_core::combinations::combination_at;
use fixplan_core::{Fixture, PartialResult, PreparedPart};
use std::cmp::Ordering;
use std::ops::Range;

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
    Sample { one_in: u64 },
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
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "all" => Ok(VerifyPolicy::All),
            "sample" => Ok(VerifyPolicy::default()),
            _ => s
                .strip_prefix("1/")
                .and_then(|n| n.parse::<u64>().ok())
                .filter(|&n| n >= 1)
                .map(|one_in| VerifyPolicy::Sample { one_in })
                .ok_or_else(|| format!("unknown verification {s:?} (all, sample, or 1/N)")),
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

fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Whether `f` is exactly what the enumeration gives for its segments,
/// locators, clamp segment and rotation (core's own code path, restricted to
/// that clamp side, so the check costs a fraction of the enumeration).
pub fn rederive(prep: &PreparedPart, f: &Fixture) -> bool {
    let n = prep.segments().len();
    let [a, b, c] = f.segments;
    if !(a <= b && b <= c && c < n && a != c) || f.locators[0] != [0, 0] {
        return false;
    }
    let mut acc = Accumulator::new(0);
    let mut scratch = Scratch::default();
    prep.setups_for_locators(f.segments, f.locators[1], f.locators[2], |s| {
        prep.process_setup_for_clamp(s, &mut acc, &mut scratch, f.clamp_segment, f.rotation)
    });
    acc.top.into_sorted().iter().any(|g| g == f)
}

/// Whether `f` would enter a top-k that holds `top` (sorted, best first).
pub fn enters(top: &[Fixture], top_k: usize, f: &Fixture) -> bool {
    top_k == 0
        || top.len() < top_k
        || top
            .get(top_k - 1)
            .is_some_and(|w| f.rank_cmp(w) == Ordering::Less)
}

/// The checks of the fixture list that hold for any shard: at most
/// `top_k`, no more than the admissible count, in rank order, finite
/// scores.
fn check_list(top_k: usize, res: &PartialResult) -> Result<(), String> {
    if top_k != 0 && res.fixtures.len() > top_k {
        return Err(format!("{} fixtures, top_k is {top_k}", res.fixtures.len()));
    }
    if (res.fixtures.len() as u64) > res.counts.admissible {
        return Err(format!(
            "{} fixtures but {} admissible",
            res.fixtures.len(),
            res.counts.admissible
        ));
    }
    if res
        .fixtures
        .windows(2)
        .any(|w| w[0].rank_cmp(&w[1]) != Ordering::Less)
    {
        return Err("fixtures not in rank order".into());
    }
    match res.fixtures.iter().position(|f| !f.score.is_finite()) {
        Some(i) => Err(format!("fixture {i} has score {}", res.fixtures[i].score)),
        None => Ok(()),
    }
}

/// The checks that need no prepared part, for a part sent whole and not
/// re-derived: the result must cover `range` (the whole part, or its
/// prefix up to a `--good-enough` hit) with counts consistent with its own
/// segment count, and hold fixtures of that part.
pub fn check_shape(top_k: usize, range: &Range<u64>, res: &PartialResult) -> Result<(), String> {
    let n = res.counts.segments;
    let count = fixplan_core::combinations::combination_count(n as usize);
    let want = range.end.min(count).saturating_sub(range.start);
    if res.range != *range || res.counts.combinations != want {
        return Err(format!(
            "result for combinations {:?} ({} of {n} segments), expected {range:?}",
            res.range, res.counts.combinations
        ));
    }
    check_list(top_k, res)?;
    for (i, f) in res.fixtures.iter().enumerate() {
        let [a, b, c] = f.segments;
        if !(a <= b && b <= c && (c as u64) < n && a != c) || f.clamp_segment as u64 >= n {
            return Err(format!(
                "fixture {i} on segments {:?}, not of the part",
                f.segments
            ));
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
) -> Result<(), String> {
    let best = res.fixtures.first().map(|f| f.score);
    match (good_enough, hit) {
        (None, None) => Ok(()),
        (None, Some(h)) => Err(format!("stopped at {h} without --good-enough")),
        (Some(_), Some(h)) if !shard.contains(&h) => {
            Err(format!("stopped at {h}, outside the shard {shard:?}"))
        }
        (Some(g), Some(h)) if best.is_none_or(|b| b > g) => Err(format!(
            "stopped at {h} but no fixture scores {g} or better"
        )),
        (Some(g), None) if best.is_some_and(|b| b <= g) => Err(format!(
            "a fixture scores {} (good enough: {g}) but the shard did not stop",
            best.unwrap_or(g)
        )),
        _ => Ok(()),
    }
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
) -> Result<usize, String> {
    let count = prep.combination_count();
    if res.range != *range {
        return Err(format!(
            "result for combinations {:?}, shard is {range:?}",
            res.range
        ));
    }
    let want = range.end.min(count).saturating_sub(range.start);
    if res.counts.combinations != want || res.counts.segments != prep.segments().len() as u64 {
        return Err(format!(
            "counts {} combinations / {} segments, expected {want} / {}",
            res.counts.combinations,
            res.counts.segments,
            prep.segments().len()
        ));
    }
    check_list(prep.top_k(), res)?;
    let n = prep.segments().len();
    let (first, last) = match (
        combination_at(n, range.start),
        combination_at(n, want.saturating_sub(1) + range.start),
    ) {
        (Some(a), Some(b)) => (a, b),
        _ if res.fixtures.is_empty() => return Ok(0),
        _ => return Err("fixtures in an empty shard".into()),
    };
    let mut checked = 0;
    for (i, f) in res.fixtures.iter().enumerate() {
        if f.segments < first || f.segments > last {
            return Err(format!(
                "fixture {i} on segments {:?}, outside the shard",
                f.segments
            ));
        }
        if deep && enters(top, prep.top_k(), f) {
            if !rederive(prep, f) {
                return Err(format!(
                    "fixture {i} (segments {:?}, locators {:?}, score {}) does not check out: \
                     form closure, clamp or score differ from the part's own enumeration",
                    f.segments, f.locators, f.score
                ));
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
        let part = Part {
            outline: vec![[0.0, 0.0], [120.0, 0.0], [120.0, 70.0], [0.0, 70.0]],
            access: vec![],
        };
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
        let (res, hit) = prep.enumerate_until(all.clone(), g);
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
}
