//! Fixtures, their canonical order, and top-k that merges the same however
//! the work was split (SPEC section 6, "Ranking").

use crate::checks::plate::Placement;
use serde::{Deserialize, Serialize};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// One admissible fixture in lattice units, canonical frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Fixture {
    /// The metric's value, lower is better: the first ranking key.
    pub score: f64,
    /// Segments touched by locators 1-3 (`a <= b <= c`).
    pub segments: [usize; 3],
    /// `L1 = (0, 0)`, `L2` in `Q`, `L3`.
    pub locators: [[i64; 2]; 3],
    /// Part pose: plate point = `R(theta) p + t`, theta in `[0, 2 pi)`.
    pub theta: f64,
    /// See `theta`; lattice units.
    pub t: [f64; 2],
    /// Segment the clamp tip touches.
    pub clamp_segment: usize,
    /// Quarter turns of the clamp frame.
    pub rotation: u8,
    /// Lattice point of clamp mount hole 0.
    pub mount: [i64; 2],
    /// Plunger extension `t`, lattice units: the shortest that passes.
    pub extension: f64,
    /// Clamp tip centre (on the grown segment).
    pub contact: [f64; 2],
    /// Inward normals at locators 1-3 and the clamp.
    pub normals: [[f64; 2]; 4],
    /// Some decision was within `BORDERLINE` (1e-6) of its
    /// boundary: another implementation may rightly disagree on it.
    pub borderline: bool,
    /// Where it goes on the physical plate.
    pub placement: Placement,
}

impl Fixture {
    /// SPEC's canonical key `(a, b, c, L2, L3, theta, x, y, clamp segment,
    /// k, m)`.
    pub fn key_cmp(&self, other: &Fixture) -> Ordering {
        self.segments
            .cmp(&other.segments)
            .then(self.locators[1].cmp(&other.locators[1]))
            .then(self.locators[2].cmp(&other.locators[2]))
            .then(self.theta.total_cmp(&other.theta))
            .then(self.t[0].total_cmp(&other.t[0]))
            .then(self.t[1].total_cmp(&other.t[1]))
            .then(self.clamp_segment.cmp(&other.clamp_segment))
            .then(self.rotation.cmp(&other.rotation))
            .then(self.mount.cmp(&other.mount))
    }

    /// Ascending score, then the canonical key.
    pub fn rank_cmp(&self, other: &Fixture) -> Ordering {
        self.score
            .total_cmp(&other.score)
            .then_with(|| self.key_cmp(other))
    }
}

/// Heap entry ordered by rank (worst on top of the max-heap).
#[derive(Debug, Clone)]
struct Ranked(Fixture);

impl PartialEq for Ranked {
    fn eq(&self, other: &Self) -> bool {
        self.0.rank_cmp(&other.0) == Ordering::Equal
    }
}
impl Eq for Ranked {}
impl PartialOrd for Ranked {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Ranked {
    fn cmp(&self, other: &Self) -> Ordering {
        self.0.rank_cmp(&other.0)
    }
}

/// The best `k` fixtures seen (all when `k == 0`).
#[derive(Debug, Clone, Default)]
pub struct TopK {
    k: usize,
    held: Held,
}

/// The fixtures a [`TopK`] holds: all of them in the order seen (a full
/// enumeration ranks them once at the end), or the best `k` in a heap
/// whose top is the k-th.
#[derive(Debug, Clone)]
enum Held {
    /// `k == 0`.
    All(Vec<Fixture>),
    /// `k > 0`.
    Best(BinaryHeap<Ranked>),
}

impl Default for Held {
    fn default() -> Self {
        Held::All(Vec::new())
    }
}

impl TopK {
    /// Empty, keeping the best `k` (0: all).
    pub fn new(k: usize) -> Self {
        let held = match k {
            0 => Held::All(Vec::new()),
            _ => Held::Best(BinaryHeap::new()),
        };
        TopK { k, held }
    }

    /// Offers a fixture; it stays only while among the best `k`, so memory
    /// is bounded by `k` however many fixtures a part has.
    pub fn push(&mut self, f: Fixture) {
        if !self.could_enter(&f) {
            return;
        }
        match &mut self.held {
            Held::All(all) => all.push(f),
            Held::Best(heap) => {
                if heap.len() >= self.k {
                    heap.pop();
                }
                heap.push(Ranked(f));
            }
        }
    }

    /// Fixtures held: a part's fixture cap counts them (each an
    /// admissible fixture of what was seen).
    pub fn len(&self) -> usize {
        match &self.held {
            Held::All(all) => all.len(),
            Held::Best(heap) => heap.len(),
        }
    }

    /// Whether none is held.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The score above which nothing can enter: the k-th fixture's once
    /// `k` are held, infinity before (and when keeping all).
    pub fn score_bound(&self) -> f64 {
        self.kth().map_or(f64::INFINITY, |w| w.score)
    }

    /// Whether `f` would enter now ([`Self::push`] keeps it). A fixture
    /// that would not can never be among the best `k` of anything that
    /// contains what was seen: the k-th only gets better.
    pub fn could_enter(&self, f: &Fixture) -> bool {
        self.kth().is_none_or(|w| f.rank_cmp(w) == Ordering::Less)
    }

    /// The worst fixture held, once there are `k` (`None` when keeping
    /// all).
    fn kth(&self) -> Option<&Fixture> {
        match &self.held {
            Held::Best(heap) if heap.len() >= self.k => heap.peek().map(|r| &r.0),
            _ => None,
        }
    }

    /// Sorted best first.
    pub fn into_sorted(self) -> Vec<Fixture> {
        match self.held {
            Held::All(all) => sorted_by_rank(all),
            Held::Best(heap) => sorted_by_rank(heap.into_iter().map(|r| r.0).collect()),
        }
    }
}

/// `score`'s place in [`f64::total_cmp`]'s order, as an integer (the
/// transformation `total_cmp` itself makes).
fn total_order_key(score: f64) -> i64 {
    let bits = score.to_bits() as i64;
    bits ^ (((bits >> 63) as u64) >> 1) as i64
}

/// `fixtures` sorted best first, as `sort_by(Fixture::rank_cmp)` sorts
/// them (a stable sort: the same order, ties included). A fixture is a
/// few hundred bytes, so the sort moves their indices and each fixture
/// moves once: sorting the 3,874 fixtures of `housing-57`'s full
/// enumeration by moving them cost 4% of it. The scores, the first key,
/// sit beside the indices, so most comparisons read no fixture.
fn sorted_by_rank(fixtures: Vec<Fixture>) -> Vec<Fixture> {
    let mut order: Vec<(i64, usize)> = fixtures
        .iter()
        .enumerate()
        .map(|(i, f)| (total_order_key(f.score), i))
        .collect();
    order.sort_by(|a, b| {
        a.0.cmp(&b.0)
            .then_with(|| fixtures[a.1].key_cmp(&fixtures[b.1]))
    });
    let mut slots: Vec<Option<Fixture>> = fixtures.into_iter().map(Some).collect();
    order.iter().filter_map(|&(_, i)| slots[i].take()).collect()
}

/// Merges ranked lists into the best `k` (all when `k == 0`), sorted.
pub fn merge_ranked(mut lists: Vec<Vec<Fixture>>, k: usize) -> Vec<Fixture> {
    // A whole part's one list (the common case in a cluster run) is sorted
    // in place rather than copied.
    let all: Vec<Fixture> = match lists.len() {
        1 => lists.pop().unwrap_or_default(),
        _ => lists.drain(..).flatten().collect(),
    };
    let mut all = sorted_by_rank(all);
    if k != 0 {
        all.truncate(k);
    }
    all
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fixture whose score and key come from small ranges, so that
    /// scores tie often and whole keys sometimes; `extension` (no key)
    /// tells tied fixtures apart.
    fn fixture(rng: &mut crate::test_rng::Xorshift, serial: usize) -> Fixture {
        let mut pick = |n: f64| (rng.signed_unit().abs() * n) as i64;
        Fixture {
            score: pick(4.0) as f64 * 0.5,
            segments: [0, pick(2.0) as usize, 2],
            locators: [[0, 0], [1, pick(2.0)], [pick(2.0), 3]],
            theta: pick(2.0) as f64,
            t: [0.0, 0.0],
            clamp_segment: 1,
            rotation: pick(2.0) as u8,
            mount: [pick(2.0), 0],
            extension: serial as f64,
            contact: [0.0, 0.0],
            normals: [[0.0, 1.0]; 4],
            borderline: false,
            placement: Placement {
                rotation: 0,
                offset: [0, 0],
            },
        }
    }

    #[test]
    fn sorting_by_index_keeps_the_stable_sorts_order() {
        let mut rng = crate::test_rng::Xorshift::new(0x5EED_F1C7);
        for len in [0, 1, 2, 7, 30, 300] {
            let fixtures: Vec<Fixture> = (0..len).map(|i| fixture(&mut rng, i)).collect();
            let mut expected = fixtures.clone();
            expected.sort_by(Fixture::rank_cmp);
            let got = sorted_by_rank(fixtures);
            let serials = |v: &[Fixture]| v.iter().map(|f| f.extension).collect::<Vec<_>>();
            assert_eq!(serials(&got), serials(&expected), "{len} fixtures");
            let ties = expected
                .windows(2)
                .filter(|w| w[0].rank_cmp(&w[1]) == Ordering::Equal)
                .count();
            assert!(len < 300 || ties > 0, "no whole-key ties to keep in order");
        }
    }

    /// Keeping all and keeping the best `k` hold the first `k` of the
    /// same order.
    #[test]
    fn top_k_is_the_head_of_keeping_all() {
        let mut rng = crate::test_rng::Xorshift::new(0x70b_4ead);
        let fixtures: Vec<Fixture> = (0..200).map(|i| fixture(&mut rng, i)).collect();
        let mut all = TopK::new(0);
        fixtures.iter().for_each(|f| all.push(f.clone()));
        assert_eq!(all.len(), 200);
        assert_eq!(all.score_bound(), f64::INFINITY);
        let all = all.into_sorted();
        for k in [1, 7, 199, 200, 300] {
            let mut top = TopK::new(k);
            fixtures.iter().for_each(|f| top.push(f.clone()));
            assert_eq!(top.len(), k.min(200));
            let top = top.into_sorted();
            // Whole-key ties may come in either order.
            let n = k.min(200);
            assert!(
                top.iter()
                    .zip(&all[..n])
                    .all(|(a, b)| a.rank_cmp(b) == Ordering::Equal),
                "k {k}"
            );
        }
    }

    #[test]
    fn merging_keeps_the_best_k_in_rank_order() {
        let mut rng = crate::test_rng::Xorshift::new(0xA115_5047);
        let lists: Vec<Vec<Fixture>> = (0..3)
            .map(|l| {
                let mut top = TopK::new(0);
                (0..40).for_each(|i| top.push(fixture(&mut rng, 100 * l + i)));
                top.into_sorted()
            })
            .collect();
        let mut all: Vec<Fixture> = lists.iter().flatten().cloned().collect();
        all.sort_by(Fixture::rank_cmp);
        let merged = merge_ranked(lists, 25);
        let serials = |v: &[Fixture]| v.iter().map(|f| f.extension).collect::<Vec<_>>();
        assert_eq!(serials(&merged), serials(&all[..25]));
    }
}
