//! Locator setups (SPEC section 3): for a segment combination, the lattice
//! points for locators 2 and 3 and the part poses that touch all three.
//!
//! Pruning: two of the three segments are the pivot, one locator at the
//! origin, the other at every lattice point of their annulus (up to
//! quarter turns), and the third locator only in the region the third
//! segment sweeps while the pivot's contacts stay on their segments
//! ([`crate::sweeps`]); poses are worked out only at the angles that keep
//! the pivot's contacts on their segments. Which ordered pairs can pivot,
//! and which kind a combination prefers, the sweeps' dispatcher says
//! ([`PivotPair`]: two lines first, else a line then an arc, so an arc is
//! only swept, never solved for at every point of its annuli); of the
//! preferred kind the pair with the thinnest annulus pivots (the region is
//! built once per lattice point of that annulus, so the pair with the
//! fewest points costs least). Each triple is then moved to SPEC's
//! canonical frame (`L1` at the origin, `L2` in the quadrant `Q`) and
//! solved there by the solver the poses' dispatcher picks
//! ([`TripleContacts`]), so a setup's numbers never depend on which pair
//! pivoted. Without a pivot (no pair pivots, or nearly parallel lines the
//! sweep refuses), `L2` comes from the annulus (a, b) and `L3` from the
//! annuli (a, c) around `L1` and (b, c) around `L2`. Only lattice points
//! and angles that cannot give a setup are skipped, so the set found is
//! exactly SPEC's; the brute-force tests enumerate without pruning.

use crate::geometry::angle_set::{wrap_angle, AngleSet};
use crate::geometry::rounding::floor_i64;
use crate::geometry::{v2, V2};
use crate::input::Pattern;
use crate::poses::pose::Pose;
use crate::poses::TripleContacts;
use crate::segments::{PairBounds, PairTable, Segment};
use crate::sweeps::{ArcPoint, LocatorSweep, PivotPair, PivotPoint, SweepScratch, SweptSegment};
use std::f64::consts::FRAC_PI_2;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};

/// Slack on annulus bounds, far above rounding and far below a lattice step.
const ANNULUS_SLACK: f64 = 1e-7;

/// A locator setup: combination, canonical locators and pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Setup {
    /// Segments touched by locators 1, 2, 3 (indices into the part's
    /// segments).
    pub combo: [usize; 3],
    /// `L1 = (0, 0)`, `L2`, `L3`: the canonical frame puts `L1` at the
    /// origin so a fixture is counted once, not once per plate position.
    pub locators: [[i64; 2]; 3],
    /// The part pose touching all three.
    pub pose: Pose,
    /// Contact parameters of the three locators on their segments.
    pub s: [f64; 3],
    /// Smallest distance of a contact from its segment's ends, minus eps.
    pub margin: f64,
}

/// What the setup search reads of a prepared part: its segments, as they
/// are and as the sweep uses them, their pair bounds, and the lattice
/// locators 2 and 3 may take.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SetupSearch<'a> {
    /// The usable segments, numbered as combinations number them.
    pub(crate) segments: &'a [Segment],
    /// Each segment as the sweep uses it (same order).
    pub(crate) swept: &'a [SweptSegment],
    /// Distance bounds of every two segments, computed on first use.
    pub(crate) pairs: &'a PairTable,
    /// How every ordered pair ranks as a pivot, computed on first use.
    pub(crate) ranks: &'a PivotRanks,
    /// Locators 2 and 3 lie on multiples of this.
    pub(crate) grid_step: i64,
    /// Alternating plates take locators on dowel holes only.
    pub(crate) pattern: Pattern,
}

impl SetupSearch<'_> {
    /// Whether `point` is a lattice offset allowed for locators 2 and 3 (grid step
    /// and, on alternating plates, dowel-hole parity).
    #[inline]
    pub(crate) fn locator_point_allowed(&self, point: [i64; 2]) -> bool {
        point[0].rem_euclid(self.grid_step) == 0
            && point[1].rem_euclid(self.grid_step) == 0
            && (self.pattern == Pattern::Square || (point[0] + point[1]).rem_euclid(2) == 0)
    }

    /// Every pair's distance bounds, `a * n + b`.
    #[inline]
    pub(crate) fn pair_table(&self) -> &[PairBounds] {
        self.pairs.of(self.segments)
    }

    /// Distance bounds of segments `a` and `b`.
    #[inline]
    fn pair(&self, a: usize, b: usize) -> PairBounds {
        self.pair_table()[a * self.segments.len() + b]
    }

    /// Setups of one combination with the given `L2`, `L3` (`L1` = origin),
    /// working out only the poses at angles `allowed` lets through (others
    /// may be reported too; [`Allowed::ALL`]: no pruning, the building
    /// block that pruned and brute-force enumerations share). Returns the
    /// number of pose solutions computed (kept or not), for the pruning
    /// statistics.
    pub(crate) fn setups_for_locators(
        &self,
        combo: [usize; 3],
        l2: [i64; 2],
        l3: [i64; 2],
        allowed: Allowed<'_>,
        mut visit: impl FnMut(&Setup),
    ) -> usize {
        if l3 == [0, 0] || l3 == l2 || l2 == [0, 0] {
            return 0;
        }
        let segs = combo.map(|i| &self.segments[i]);
        let locs_i = [[0, 0], l2, l3];
        let locs = locs_i.map(|p| v2(p[0] as f64, p[1] as f64));
        let contacts = TripleContacts::of(segs.map(|segment| &segment.feature));
        // The sweep places `L3` in its region without the annuli, which
        // cost nothing next to an arc pose solution: about one swept
        // triple in seven of `bracket-arcs` is dropped here.
        if contacts.is_costly() && allowed.angles.is_some() && !self.in_annuli(combo, &locs) {
            return 0;
        }
        contacts.solve_kept_at_angles(
            &locs,
            |theta| allowed.keeps(theta),
            &|lo, hi| allowed.meets(lo, hi),
            &|k, p| segs[k].distance_outside(p),
            |pose, tangential| {
                self.visit_pose(combo, &segs, locs_i, &locs, pose, tangential, &mut visit);
            },
        )
    }

    /// Whether every two locators lie as far apart as some points of the
    /// segments they touch (the annuli, with slack): true of every setup,
    /// as a rigid motion keeps distances.
    fn in_annuli(&self, combo: [usize; 3], locs: &[V2; 3]) -> bool {
        let (table, n) = (self.pair_table(), self.segments.len());
        in_annuli(combo.map(|i| combo.map(|j| table[i * n + j])), locs)
    }

    /// Keeps a pose whose contacts lie strictly inside their segments, in
    /// canonical order on a shared segment. A tangential pose (SPEC 8.4)
    /// counts once and is borderline: its margin is zero.
    #[inline]
    #[allow(clippy::too_many_arguments)] // the setup's parts, unpacked once per lattice pair
    fn visit_pose(
        &self,
        combo: [usize; 3],
        segs: &[&Segment; 3],
        locators: [[i64; 2]; 3],
        locs: &[V2; 3],
        pose: &Pose,
        tangential: bool,
        visit: &mut impl FnMut(&Setup),
    ) {
        let mut s = [0.0; 3];
        let mut margin = if tangential { 0.0 } else { f64::INFINITY };
        for k in 0..3 {
            let p = pose.inverse_apply(locs[k]);
            s[k] = segs[k].param_of(p);
            let m = segs[k].inner_margin(s[k]);
            if m <= 0.0 {
                return;
            }
            margin = margin.min(m);
        }
        // Locators on one segment are numbered along it.
        if (combo[0] == combo[1] && s[0] >= s[1]) || (combo[1] == combo[2] && s[1] >= s[2]) {
            return;
        }
        visit(&Setup {
            combo,
            locators,
            pose: *pose,
            s,
            margin,
        });
    }

    /// Every setup of one combination, pruned by annuli and the swept
    /// region of [`crate::sweeps`], with buffers and pivot points kept
    /// from the combinations this thread did before.
    pub(crate) fn setups_of_combination(
        &self,
        combo: [usize; 3],
        scratch: &mut SetupScratch,
        mut visit: impl FnMut(&Setup),
    ) -> SearchStats {
        let mut stats = SearchStats::default();
        match self.pivot_roles(combo) {
            Some(roles) => self.swept_setups(combo, roles, scratch, &mut stats, &mut visit),
            None => self.annulus_setups(combo, &mut stats, &mut visit),
        }
        stats
    }

    /// The pivot of a combination: of the ordered pairs of its segments a
    /// sweep pivots on and does not refuse ([`PivotRanks`]), those of the
    /// kind preferred ([`PivotPair::preference`]), and of these the one
    /// with the thinnest annulus (the region is built once per lattice
    /// point of that annulus, so the pair with the fewest points costs
    /// least). The roles only: the sweep is built once the pair is known
    /// to have pivot points.
    fn pivot_roles(&self, combo: [usize; 3]) -> Option<[usize; 3]> {
        // ROLES visited by pairs of positions, each pair in both orders:
        // (forward, backward) as indices into ROLES, whose first order
        // wins a tie.
        const PAIRS: [(usize, usize); 3] = [(0, 2), (1, 4), (3, 5)];
        let count = self.segments.len();
        let ranks = self.ranks.of(self.swept, self.pair_table());
        // The least (preference, area, order): the keys order the first
        // two, the order fills their low byte.
        let mut best = NOT_A_PIVOT;
        for (forward, backward) in PAIRS {
            let [p, q, _] = ROLES[forward];
            let (first, second) = (combo[p], combo[q]);
            let rank = &ranks[first * count + second];
            best = best.min(rank.key | forward as u128);
            // A symmetric pair finds the same setups in the other order
            // (symmetry is a property of the unordered pair).
            if !rank.symmetric {
                best = best.min(ranks[second * count + first].key | backward as u128);
            }
        }
        (best != NOT_A_PIVOT).then(|| ROLES[(best & 0xff) as usize])
    }

    /// Setups by the sweep: the pivot's first locator at the origin, its
    /// second at every lattice point `d` of `Q = {i > 0, j >= 0}` in their
    /// annulus that leaves the part some angle, the third segment's
    /// locator in the swept region. The pivot points come from the part's
    /// shared table ([`PivotRanks`]) when it has them or room for them,
    /// else from this thread's [`PivotCache`].
    fn swept_setups(
        &self,
        combo: [usize; 3],
        roles: [usize; 3],
        scratch: &mut SetupScratch,
        stats: &mut SearchStats,
        visit: &mut impl FnMut(&Setup),
    ) {
        let [p, q, r] = roles.map(|k| combo[k]);
        let count = self.segments.len();
        let SetupScratch {
            sweep: buffers,
            pivots,
        } = scratch;
        let shared = self.ranks.points(count, self.grid_step, self.pattern);
        // A pivot pair without pivot points gives no setup whatever the
        // third segment: most combinations of a small part end here,
        // before their sweep is built.
        let known = match shared.and_then(|table| table.get(p, q)) {
            Some(points) => Some(Known::Shared(points)),
            None if shared.is_none_or(SharedPivots::full) => {
                pivots.range(count, p, q).map(Known::Local)
            }
            None => None,
        };
        if known.as_ref().is_some_and(Known::is_empty) {
            return;
        }
        let Some(sweep) = self.sweep(combo, roles) else {
            // Never: the ranks leave out the pairs a sweep refuses.
            return self.annulus_setups(combo, stats, visit);
        };
        let known = known.unwrap_or_else(|| {
            let fresh = &mut pivots.fresh;
            fresh.clear();
            self.pivot_points(&sweep, p, q, fresh);
            match shared.and_then(|table| table.keep(p, q, fresh)) {
                Some(points) => Known::Shared(points),
                None => Known::Local(pivots.insert(count, p, q)),
            }
        });
        let points = match known {
            Known::Shared(points) => points,
            Known::Local(range) => &pivots.points[range],
        };
        let g = self.grid_step;
        for (d, pt) in points {
            let d = *d;
            let listed = sweep.for_each_third_locator(pt, g, buffers, |e, angles| {
                self.solve_placed(combo, roles, d, e, angles, stats, visit)
            });
            if !listed {
                let (pr, qr) = (self.pair(p, r), self.pair(q, r));
                annulus_points(d, pr, qr, g, |e| {
                    self.solve_placed(combo, roles, d, e, None, stats, visit)
                });
            }
        }
    }

    /// The sweep of a combination in the given roles, `None` when it
    /// refuses.
    fn sweep(&self, combo: [usize; 3], roles: [usize; 3]) -> Option<LocatorSweep<'_>> {
        let [p, q, r] = roles.map(|k| combo[k]);
        let swept = [p, q, r].map(|i| &self.swept[i]);
        LocatorSweep::new(swept, p == q, self.pair(p, r).dmax)
    }

    /// The lattice points `d` of `Q` in the annulus of the pivot pair
    /// `(first, second)` at which some angle keeps both contacts on their segments.
    fn pivot_points(
        &self,
        sweep: &LocatorSweep<'_>,
        first: usize,
        second: usize,
        out: &mut Vec<LatticePivot>,
    ) {
        self.quadrant_points(self.pair(first, second), |d| {
            if let Some(pt) = sweep.pivot_point(lattice_point(d)) {
                out.push((d, pt));
            }
        });
    }

    /// Every allowed lattice point (multiples of the grid step) of
    /// `Q = {i > 0, j >= 0}` in the annulus of a pair: where the second
    /// locator can be, up to quarter turns, once the first is at the
    /// origin.
    fn quadrant_points(&self, pair: PairBounds, mut visit: impl FnMut([i64; 2])) {
        let g = self.grid_step;
        let (lo2, hi2) = annulus_sq(pair);
        let imax = floor_i64(pair.dmax) + 1;
        let mut i = g;
        while i <= imax {
            let mut j = 0;
            while j <= imax {
                let d = [i, j];
                let d2 = (i * i + j * j) as f64;
                if d2 > hi2 {
                    break;
                }
                if d2 >= lo2 && self.locator_point_allowed(d) {
                    visit(d);
                }
                j += g;
            }
            i += g;
        }
    }

    /// Solves the triple with the pivot's locators at `0` and `second` and
    /// the third at `third`, after moving it to the canonical frame: `L1` at the
    /// origin, turned by quarter turns (which map the lattice onto itself)
    /// until `L2` lies in `Q`. Each setup has exactly one placement with
    /// `second` in `Q`, so each is solved once. `angles` (pivot frame) lets
    /// three lines work out only the poses the sweep allows.
    #[allow(clippy::too_many_arguments)] // one lattice triple, unpacked
    fn solve_placed(
        &self,
        combo: [usize; 3],
        roles: [usize; 3],
        second: [i64; 2],
        third: [i64; 2],
        angles: Option<&AngleSet>,
        stats: &mut SearchStats,
        visit: &mut impl FnMut(&Setup),
    ) {
        let mut placed = [[0i64; 2]; 3];
        let [p, q, r] = roles;
        (placed[p], placed[q], placed[r]) = ([0, 0], second, third);
        let o = placed[0];
        let (l2, l3) = (sub(placed[1], o), sub(placed[2], o));
        if l2 == [0, 0] {
            return;
        }
        let turns = quarter_turns_into_q(l2);
        let (l2, l3) = (quarter_turn(l2, turns), quarter_turn(l3, turns));
        // `second` was checked; any other L2 is a difference of checked points
        // turned, which keeps grid step and dowel parity, but say so here
        // rather than rely on it.
        if l2 != second && !self.locator_point_allowed(l2) {
            return;
        }
        let allowed = Allowed { angles, turns };
        self.solve_triple(combo, l2, l3, allowed, stats, visit);
    }

    /// Setups when no pair can pivot (no [`PivotPair`]: two or three arcs;
    /// or nearly parallel lines): `L2` in the annulus (a, b), `L3` in the annuli
    /// (a, c) around `L1` and (b, c) around `L2`.
    fn annulus_setups(
        &self,
        combo: [usize; 3],
        stats: &mut SearchStats,
        visit: &mut impl FnMut(&Setup),
    ) {
        let [a, b, c] = combo;
        let (ac, bc) = (self.pair(a, c), self.pair(b, c));
        let g = self.grid_step;
        self.quadrant_points(self.pair(a, b), |l2| {
            annulus_points(l2, ac, bc, g, |l3| {
                self.solve_triple(combo, l2, l3, Allowed::ALL, stats, visit)
            });
        });
    }

    /// Solves one locator triple that survived pruning, with statistics.
    #[inline]
    fn solve_triple(
        &self,
        combo: [usize; 3],
        l2: [i64; 2],
        l3: [i64; 2],
        allowed: Allowed<'_>,
        stats: &mut SearchStats,
        visit: &mut impl FnMut(&Setup),
    ) {
        if l3 != [0, 0] && l3 != l2 && self.locator_point_allowed(l3) {
            stats.locator_triples += 1;
            stats.pose_solutions +=
                self.setups_for_locators(combo, l2, l3, allowed, &mut *visit) as u64;
        }
    }
}

/// The angles a sweep allows for one triple: its angle set (pivot frame,
/// where known) and the quarter turns from the pivot frame to the
/// canonical one, which turn the pose with the plate:
/// `theta = theta_pivot + turns pi / 2`. Poses elsewhere cannot keep the
/// pivot's contacts on their segments, so they need not be worked out.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Allowed<'a> {
    angles: Option<&'a AngleSet>,
    turns: u8,
}

impl Allowed<'_> {
    /// Every angle.
    pub(crate) const ALL: Allowed<'static> = Allowed {
        angles: None,
        turns: 0,
    };

    fn back(&self) -> f64 {
        f64::from(self.turns) * FRAC_PI_2
    }

    /// Whether the canonical angle `theta` is allowed.
    fn keeps(&self, theta: f64) -> bool {
        self.angles.is_none_or(|a| {
            a.contains(if self.turns == 0 {
                theta
            } else {
                wrap_angle(theta - self.back())
            })
        })
    }

    /// Whether some canonical angle of `[lo, hi]` is allowed.
    fn meets(&self, lo: f64, hi: f64) -> bool {
        let back = self.back();
        self.angles.is_none_or(|a| a.meets(lo - back, hi - back))
    }
}

/// Every order of a combination's roles (pivot's first, pivot's second,
/// swept), as positions in the combination: its order says nothing about
/// which is which. A tie between pivots goes to the first order here.
const ROLES: [[usize; 3]; 6] = [
    [0, 1, 2],
    [0, 2, 1],
    [1, 0, 2],
    [1, 2, 0],
    [2, 0, 1],
    [2, 1, 0],
];

/// The key of a [`PivotRank`] of a pair no sweep pivots on in that order:
/// above every other key, whatever order is or-ed into it.
const NOT_A_PIVOT: u128 = u128::MAX;

/// How an ordered pair of segments ranks as a combination's pivot (see
/// `SetupSearch::pivot_roles`): what the ranking reads of a pair, worked
/// out once per part rather than for each of the combinations it is in.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PivotRank {
    /// Ranks pairs by [`PivotPair::preference`], then by the width of the
    /// pair's annulus (`hi^2 - lo^2`), as one integer ([`pivot_key`])
    /// whose low byte is free for the order of the roles that breaks ties;
    /// [`NOT_A_PIVOT`] when no sweep pivots on the pair in this order or
    /// the sweep refuses it (nearly parallel lines).
    key: u128,
    /// [`PivotPair::symmetric`]: the other order finds the same setups.
    symmetric: bool,
}

/// The [`PivotRank::key`] of a pair of kind `preference` whose annulus is
/// `area` wide: the bits of a float that is not negative (an annulus's
/// width, `+0.0` at least, never NaN) order as the float does, so keys
/// order as `(preference, area)` does, lexicographically.
fn pivot_key(preference: u8, area: f64) -> u128 {
    debug_assert!(
        area >= 0.0 && area.is_sign_positive(),
        "annulus width {area}"
    );
    (u128::from(preference) << 72) | (u128::from(area.to_bits()) << 8)
}

/// Every ordered pair's [`PivotRank`], `first * n + second`, and the
/// pivot points of the pairs that pivot ([`SharedPivots`]), computed on
/// first use from the pair bounds and shared by clones (like
/// [`PairTable`]) and by the threads and shards of an enumeration.
#[derive(Debug, Clone, Default)]
pub(crate) struct PivotRanks(Arc<PivotTables>);

/// What [`PivotRanks`] shares.
#[derive(Default)]
struct PivotTables {
    ranks: OnceLock<Vec<PivotRank>>,
    points: OnceLock<SharedPivots>,
}

impl std::fmt::Debug for PivotTables {
    /// The ranks only: the points are a cache, on the lattice of whichever
    /// variant of the part (another grid step or kit) needed them first,
    /// and a variant is the part a fresh `prepare` gives.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PivotTables")
            .field("ranks", &self.ranks)
            .finish_non_exhaustive()
    }
}

impl PivotRanks {
    /// The ranks of the segments `swept`, whose pair bounds are `pairs`
    /// (the first call fixes them).
    #[inline]
    pub(crate) fn of(&self, swept: &[SweptSegment], pairs: &[PairBounds]) -> &[PivotRank] {
        self.0.ranks.get_or_init(|| {
            let mut ranks = Vec::with_capacity(pairs.len());
            for first in swept {
                for second in swept {
                    let (lo, hi) = annulus_sq(pairs[ranks.len()]);
                    // Finite segments are a finite distance apart: the
                    // ranking compares areas as a total order.
                    debug_assert!(!(hi - lo).is_nan(), "pair bounds {:?}", pairs[ranks.len()]);
                    let kind = PivotPair::of(first, second).filter(|kind| !kind.refused());
                    ranks.push(PivotRank {
                        key: kind.map_or(NOT_A_PIVOT, |kind| pivot_key(kind.preference(), hi - lo)),
                        symmetric: kind.is_some_and(|kind| kind.symmetric()),
                    });
                }
            }
            ranks
        })
    }

    /// The pivot points table of a part of `count` segments on the
    /// lattice `(grid_step, pattern)`; `None` on another lattice than the
    /// one the first call fixed (a clone with another grid step or kit),
    /// whose points live in the threads' caches instead.
    #[inline]
    fn points(&self, count: usize, grid_step: i64, pattern: Pattern) -> Option<&SharedPivots> {
        let table = self.0.points.get_or_init(|| SharedPivots {
            grid_step,
            pattern,
            width: count,
            pairs: (0..count * count).map(|_| OnceLock::new()).collect(),
            stored: AtomicUsize::new(0),
        });
        (table.grid_step == grid_step && table.pattern == pattern && table.width == count)
            .then_some(table)
    }
}

/// Most bytes of pivot points [`SharedPivots`] keeps for one part (a line
/// pair's point is about 360 bytes, a line and arc's 1.4 kB more;
/// `housing-57` has 1,043 points, 0.4 MB): a worker keeps the parts of a
/// run prepared, so a huge part's further points go to the threads'
/// bounded caches instead.
const SHARED_PIVOT_BYTES: usize = 8 << 20;

/// The pivot points of every ordered pair of a part's segments on one
/// lattice, worked out once per part: a pair's points do not depend on
/// the third segment nor on which thread or shard needs them, and
/// `gluegun-28` (full counts: chunks of 32 combinations, each with fresh
/// scratch) worked out each pair's about four times over in the threads'
/// caches.
struct SharedPivots {
    /// The lattice the points are on.
    grid_step: i64,
    /// See `grid_step`.
    pattern: Pattern,
    /// The number of segments `pairs` is laid out for.
    width: usize,
    /// Each ordered pair's points, `first * width + second`, once known.
    pairs: Vec<OnceLock<Box<[LatticePivot]>>>,
    /// Bytes kept so far (or about to be), against
    /// [`SHARED_PIVOT_BYTES`].
    stored: AtomicUsize,
}

impl SharedPivots {
    /// The points of `(first, second)`, when known.
    #[inline]
    fn get(&self, first: usize, second: usize) -> Option<&[LatticePivot]> {
        self.pairs[first * self.width + second].get().map(|p| &**p)
    }

    /// Whether the table has no room left for more points.
    fn full(&self) -> bool {
        self.stored.load(Ordering::Relaxed) >= SHARED_PIVOT_BYTES
    }

    /// Takes `points` (leaving it empty) as those of `(first, second)`
    /// when there is room (another thread may have kept the same points
    /// first); `None`, leaving them, when there is not.
    fn keep(
        &self,
        first: usize,
        second: usize,
        points: &mut Vec<LatticePivot>,
    ) -> Option<&[LatticePivot]> {
        let boxed = points
            .iter()
            .filter(|(_, point)| matches!(point, PivotPoint::LineArc(_)))
            .count();
        let bytes = size_of_val(points.as_slice()) + boxed * size_of::<ArcPoint>();
        let before = self.stored.fetch_add(bytes, Ordering::Relaxed);
        if before + bytes > SHARED_PIVOT_BYTES {
            return None;
        }
        let cell = &self.pairs[first * self.width + second];
        Some(cell.get_or_init(|| {
            // Moved in one copy to a list of its exact size: no regrowth,
            // no shrink.
            let mut kept = Vec::with_capacity(points.len());
            kept.append(points);
            kept.into_boxed_slice()
        }))
    }
}

/// Where the pivot points of a pair are: the part's table or this
/// thread's cache.
enum Known<'a> {
    /// In [`SharedPivots`].
    Shared(&'a [LatticePivot]),
    /// In [`PivotCache::points`].
    Local(std::ops::Range<usize>),
}

impl Known<'_> {
    /// Whether the pair has no pivot points.
    fn is_empty(&self) -> bool {
        match self {
            Known::Shared(points) => points.is_empty(),
            Known::Local(range) => range.is_empty(),
        }
    }
}

/// Buffers and pivot points one thread reuses across combinations.
#[derive(Debug, Default)]
pub struct SetupScratch {
    sweep: SweepScratch,
    pivots: PivotCache,
}

/// A lattice point `d` for the pivot's second locator and what the sweep
/// needs of it.
type LatticePivot = ([i64; 2], PivotPoint);

/// Most pivot points kept per thread (about 360 bytes each, 12 MB in all;
/// `housing-57` keeps 1,043, scaled 3x 13,677): beyond, the cache starts
/// over, so a huge part costs time, never unbounded memory.
const PIVOT_CACHE_POINTS: usize = 1 << 15;

/// Pivot points room is made for at once (about 90 kB): small parts need
/// no more.
const PIVOT_CACHE_START: usize = 256;

/// The pivot points of each pivot pair, in one thread, when the part's
/// [`SharedPivots`] has no room for them (or is on another lattice): the
/// same pair pivots many combinations (every third segment whose pairs
/// with it are wider), and its points (two `acos` bands per lattice point
/// of the annulus) do not depend on the third segment.
#[derive(Debug, Default)]
struct PivotCache {
    /// Where each ordered pair's points lie in `points`, `first * width +
    /// second`, [`UNKNOWN`] before they are worked out: a dense table, as
    /// a hash lookup cost about 2% of `gluegun-28`.
    ranges: Vec<(usize, usize)>,
    /// The number of segments `ranges` is laid out for.
    width: usize,
    /// Every pair's points, one after the other: one allocation for all.
    points: Vec<LatticePivot>,
    /// Where a pair's points are worked out before they are kept here or
    /// in [`SharedPivots`], reused so that it grows only at first.
    fresh: Vec<LatticePivot>,
}

/// Marks a pair of [`PivotCache`] whose points are not worked out.
const UNKNOWN: (usize, usize) = (usize::MAX, usize::MAX);

impl PivotCache {
    /// Where the pivot points of `(first, second)` of a part with `count`
    /// segments lie in `points`, when already worked out.
    fn range(
        &mut self,
        count: usize,
        first: usize,
        second: usize,
    ) -> Option<std::ops::Range<usize>> {
        self.lay_out(count);
        let (start, end) = self.ranges[first * count + second];
        ((start, end) != UNKNOWN).then_some(start..end)
    }

    /// Lays the table out for a part of `count` segments, unless it is.
    fn lay_out(&mut self, count: usize) {
        if self.width != count {
            // A scratch's first combination (or another part's).
            self.width = count;
            self.ranges.clear();
            self.ranges.resize(count * count, UNKNOWN);
            self.points.clear();
            // Growing from nothing cost `gluegun-28` about 1% (7 regrowths).
            self.points.reserve(PIVOT_CACHE_START);
        }
    }

    /// Moves the points in `fresh` to `points` as the pivot points of
    /// `(first, second)` of a part with `count` segments and says where
    /// they lie.
    fn insert(&mut self, count: usize, first: usize, second: usize) -> std::ops::Range<usize> {
        self.lay_out(count);
        if self.points.len() > PIVOT_CACHE_POINTS {
            self.ranges.fill(UNKNOWN);
            self.points.clear();
        }
        let start = self.points.len();
        self.points.append(&mut self.fresh);
        let r = start..self.points.len();
        self.ranges[first * self.width + second] = (r.start, r.end);
        r
    }
}

fn sub(point: [i64; 2], origin: [i64; 2]) -> [i64; 2] {
    [point[0] - origin[0], point[1] - origin[1]]
}

/// `point` turned by `turns` quarter turns counterclockwise.
fn quarter_turn(point: [i64; 2], turns: u8) -> [i64; 2] {
    (0..turns).fold(point, |[x, y], _| [-y, x])
}

/// The quarter turns that bring `v != 0` into `Q = {i > 0, j >= 0}`.
fn quarter_turns_into_q([x, y]: [i64; 2]) -> u8 {
    if x > 0 && y >= 0 {
        0
    } else if x >= 0 && y < 0 {
        1
    } else if x < 0 && y <= 0 {
        2
    } else {
        3
    }
}

/// Whether the locators `locs` lie in the annuli `pairs[i][j]` (distance
/// bounds of the segments locators `i` and `j` touch) of every two of
/// them, by the test [`annulus_points`] applies.
fn in_annuli(pairs: [[PairBounds; 3]; 3], locs: &[V2; 3]) -> bool {
    [(0, 1), (0, 2), (1, 2)].iter().all(|&(i, j)| {
        let (lo, hi) = annulus_sq(pairs[i][j]);
        let d2 = (locs[j] - locs[i]).norm_squared();
        d2 >= lo && d2 <= hi
    })
}

/// Calls `visit` for every lattice point (multiples of `grid_step`) within the
/// annulus `ac` around the origin and `bc` around `l2`.
fn annulus_points(
    l2: [i64; 2],
    ac: PairBounds,
    bc: PairBounds,
    grid_step: i64,
    mut visit: impl FnMut([i64; 2]),
) {
    let (lo_a, hi_a) = annulus_sq(ac);
    let (lo_b, hi_b) = annulus_sq(bc);
    let p2 = v2(l2[0] as f64, l2[1] as f64);
    let x_lo = (-ac.dmax).max(p2.x - bc.dmax) - 1.0;
    let x_hi = ac.dmax.min(p2.x + bc.dmax) + 1.0;
    let mut x = floor_i64(x_lo / grid_step as f64) * grid_step;
    while (x as f64) <= x_hi {
        let xf = x as f64;
        // y range from the outer circle around the origin and around L2.
        let ra = hi_a - xf * xf;
        let rb = hi_b - (xf - p2.x) * (xf - p2.x);
        if ra >= 0.0 && rb >= 0.0 {
            let (ya, yb) = (ra.sqrt(), rb.sqrt());
            let y_lo = (-ya).max(p2.y - yb);
            let y_hi = ya.min(p2.y + yb);
            let mut y = floor_i64(y_lo / grid_step as f64) * grid_step;
            while (y as f64) <= y_hi {
                let da = (x * x + y * y) as f64;
                let db = (v2(xf, y as f64) - p2).norm_squared();
                if da >= lo_a && da <= hi_a && db >= lo_b && db <= hi_b {
                    visit([x, y]);
                }
                y += grid_step;
            }
        }
        x += grid_step;
    }
}

/// How much work the pruned search did (for `fixplan bench`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct SearchStats {
    /// `(L2, L3)` pairs that survived pruning and were solved for poses.
    pub locator_triples: u64,
    /// Pose solutions computed (kept as setups or not).
    pub pose_solutions: u64,
}

impl SearchStats {
    /// Sums the statistics of pieces of work (threads, shards).
    pub fn add(&mut self, other: &SearchStats) {
        self.locator_triples += other.locator_triples;
        self.pose_solutions += other.pose_solutions;
    }
}

/// Squared annulus bounds with slack.
fn annulus_sq(pair: PairBounds) -> (f64, f64) {
    let lo = (pair.dmin - ANNULUS_SLACK).max(0.0);
    let hi = pair.dmax + ANNULUS_SLACK;
    (lo * lo, hi * hi)
}

/// Plate position of a lattice point.
#[inline]
pub fn lattice_point(point: [i64; 2]) -> V2 {
    v2(point[0] as f64, point[1] as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::arc::GrownArc;
    use crate::geometry::rot;
    use crate::segments::{Feature, LineFeature};

    /// The segment from `a` to `b`.
    fn line(a: V2, b: V2) -> Segment {
        let len = (b - a).norm();
        let u = (b - a) / len;
        let n = v2(u.y, -u.x);
        Segment {
            edge: 0,
            s0: 0.0,
            s1: len,
            feature: Feature::Line(LineFeature::new(a, u, n)),
        }
    }

    /// An arc of the circle round `center`, contacts on most of it.
    fn arc(center: V2, radius: f64, start_angle: f64, sweep: f64) -> Segment {
        let arc = GrownArc {
            center,
            radius,
            start_angle,
            sweep,
        };
        Segment {
            edge: 0,
            s0: 0.1 * arc.length(),
            s1: 0.9 * arc.length(),
            feature: Feature::Arc(arc),
        }
    }

    /// The distance bounds of every two of three segments.
    fn pairs(segments: [&Segment; 3]) -> [[PairBounds; 3]; 3] {
        segments.map(|a| segments.map(|b| PairBounds::between(a, b)))
    }

    /// `L1` at the origin, `L2 = second`, `L3 = third`.
    fn at(pairs: [[PairBounds; 3]; 3], second: [i64; 2], third: [i64; 2]) -> bool {
        in_annuli(
            pairs,
            &[v2(0.0, 0.0), lattice_point(second), lattice_point(third)],
        )
    }

    #[test]
    fn annuli_reject_distances_no_segments_have() {
        // p along the x axis, q and r parallel to it 2 and 5 above: |third| in
        // [5, sqrt 125] from p, |third - second| in [3, sqrt 109] from q.
        let p = line(v2(0.0, 0.0), v2(10.0, 0.0));
        let q = line(v2(0.0, 2.0), v2(10.0, 2.0));
        let r = line(v2(0.0, 5.0), v2(10.0, 5.0));
        let pq = pairs([&p, &q, &r]);
        let second = [0, 2];
        assert!(at(pq, second, [0, 5]) && at(pq, second, [10, 2]));
        assert!(!at(pq, second, [4, 0]), "|third| = 4 < 5 from p");
        assert!(!at(pq, second, [12, 0]), "|third| = 12 > sqrt 125 from p");
        assert!(
            !at(pq, second, [11, 0]),
            "|third - second| = sqrt 125 > sqrt 109 from q"
        );
        assert!(!at(pq, [0, 1], [0, 5]), "|second| = 1 < 2 from p to q");
        // The roles are not interchangeable.
        assert!(!at(pairs([&q, &p, &r]), second, [0, 5]));
    }

    /// The pivot as the setup search chose it before [`PivotRanks`]:
    /// every order of the roles a sweep accepts (a symmetric pair in one
    /// order), sorted by preference then annulus width (stable), the first
    /// whose sweep is built.
    fn pivot_by_sorting(search: &SetupSearch<'_>, combo: [usize; 3]) -> Option<[usize; 3]> {
        let mut ranked = Vec::new();
        for roles in ROLES {
            let [p, q, _] = roles;
            let Some(kind) = PivotPair::of(&search.swept[combo[p]], &search.swept[combo[q]]) else {
                continue;
            };
            if kind.symmetric() && p > q {
                continue;
            }
            let (lo, hi) = annulus_sq(search.pair(combo[p], combo[q]));
            ranked.push((kind.preference(), hi - lo, roles));
        }
        ranked.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
        ranked.into_iter().map(|r| r.2).find(|&roles| {
            let [p, q, r] = roles.map(|k| combo[k]);
            let swept = [p, q, r].map(|i| &search.swept[i]);
            LocatorSweep::new(swept, p == q, search.pair(p, r).dmax).is_some()
        })
    }

    /// Random lines (some parallel or nearly so, some sharing a length, so
    /// that annuli tie) and arcs.
    fn ranking_segments(seed: u64, count: usize) -> Vec<Segment> {
        let mut rng = crate::test_rng::Xorshift::new(seed);
        let mut out = Vec::new();
        while out.len() < count {
            let a = v2(4.0 * rng.signed_unit(), 4.0 * rng.signed_unit());
            let kind = (rng.signed_unit().abs() * 5.0) as u8;
            let direction = v2(1.0 + rng.signed_unit(), 2.0 * rng.signed_unit());
            out.push(match kind {
                0 => arc(a, 0.5 + rng.signed_unit().abs(), rng.signed_unit(), 3.0),
                // A copy of the last segment moved, nearly parallel or parallel.
                1 | 2 if !out.is_empty() => {
                    let last: &Segment = &out[out.len() - 1];
                    let (p, q) = (last.point(last.s0), last.point(last.s1));
                    let tilt = if kind == 1 {
                        v2(0.0, 1e-6)
                    } else {
                        v2(0.0, 0.0)
                    };
                    line(p + a, q + a + tilt)
                }
                _ => line(a, a + direction),
            });
        }
        out
    }

    /// `body` run on the setup search of `segments` with the pivot table
    /// `ranks` (grid step 1, square plate).
    fn with_search<T>(
        segments: &[Segment],
        ranks: &PivotRanks,
        body: impl FnOnce(&SetupSearch<'_>) -> T,
    ) -> T {
        let swept: Vec<SweptSegment> = segments.iter().map(SweptSegment::of).collect();
        let pairs = PairTable::default();
        body(&SetupSearch {
            segments,
            swept: &swept,
            pairs: &pairs,
            ranks,
            grid_step: 1,
            pattern: Pattern::Square,
        })
    }

    /// Every combination of `n` segments: a <= b <= c, not one segment
    /// thrice.
    fn combinations(n: usize) -> impl Iterator<Item = [usize; 3]> {
        (0..n)
            .flat_map(move |a| (a..n).flat_map(move |b| (b..n).map(move |c| [a, b, c])))
            .filter(|&[a, _, c]| a != c)
    }

    #[test]
    fn pivot_ranks_choose_the_pivot_sorting_chose() {
        for seed in 1..40u64 {
            let segments = ranking_segments(seed, 9);
            let chosen = with_search(&segments, &PivotRanks::default(), |search| {
                let mut chosen = 0;
                for combo in combinations(segments.len()) {
                    let roles = search.pivot_roles(combo);
                    assert_eq!(
                        roles,
                        pivot_by_sorting(search, combo),
                        "seed {seed} {combo:?}"
                    );
                    chosen += usize::from(roles.is_some_and(|r| r != [0, 1, 2]));
                }
                chosen
            });
            assert!(chosen > 0, "seed {seed}: every pivot in the first order");
        }
    }

    /// Every setup (and the search's statistics) of every combination of
    /// `segments` that pivots (the others never read pivot points), on one
    /// scratch as a thread's chunk runs them, with the part's pivot table
    /// prepared by `prime` first.
    fn all_setups(
        segments: &[Segment],
        prime: impl FnOnce(&PivotRanks),
    ) -> (Vec<Setup>, SearchStats) {
        let ranks = PivotRanks::default();
        prime(&ranks);
        with_search(segments, &ranks, |search| {
            let (mut setups, mut stats) = (Vec::new(), SearchStats::default());
            let mut scratch = SetupScratch::default();
            for combo in combinations(segments.len()) {
                if search.pivot_roles(combo).is_none() {
                    continue;
                }
                let found = search.setups_of_combination(combo, &mut scratch, |s| setups.push(*s));
                stats.add(&found);
            }
            (setups, stats)
        })
    }

    #[test]
    fn shared_and_thread_pivot_points_give_the_same_setups() {
        let (mut found, mut arcs) = (0, 0);
        for seed in 1..7u64 {
            let segments: Vec<Segment> = ranking_segments(seed, 6)
                .iter()
                .map(|s| {
                    // Scaled up so that pivot pairs have lattice points.
                    let mut s = *s;
                    match &mut s.feature {
                        Feature::Line(line) => {
                            *line = LineFeature::new(line.origin * 3.0, line.u, line.n);
                            (s.s0, s.s1) = (s.s0 * 3.0, s.s1 * 3.0);
                        }
                        Feature::Arc(arc) => {
                            (arc.center, arc.radius) = (arc.center * 3.0, arc.radius * 3.0);
                            (s.s0, s.s1) = (s.s0 * 3.0, s.s1 * 3.0);
                        }
                    }
                    s
                })
                .collect();
            let count = segments.len();
            let shared = all_setups(&segments, |_| {});
            // Another lattice fixed the table first: every point in the
            // thread's cache.
            let local = all_setups(&segments, |ranks| {
                assert!(ranks.points(count, 2, Pattern::Square).is_some());
            });
            // Room for a few pairs only: some points in each.
            let mixed = all_setups(&segments, |ranks| {
                let table = ranks
                    .points(count, 1, Pattern::Square)
                    .expect("first lattice");
                let room = 40 * size_of::<LatticePivot>();
                table
                    .stored
                    .store(SHARED_PIVOT_BYTES - room, Ordering::Relaxed);
            });
            assert_eq!(shared, local, "seed {seed}");
            assert_eq!(shared, mixed, "seed {seed}");
            found += shared.0.len();
            arcs += shared
                .0
                .iter()
                .filter(|s| {
                    s.combo
                        .iter()
                        .any(|&k| matches!(segments[k].feature, Feature::Arc(_)))
                })
                .count();
        }
        assert!(
            found > 100 && arcs > 0,
            "{found} setups, {arcs} with an arc"
        );
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig {
            cases: 2000,
            failure_persistence: None,
            ..Default::default()
        })]

        /// The pivot keys order as (preference, area) does.
        #[test]
        fn pivot_keys_order_as_preference_then_area(
            preference in proptest::array::uniform2(0u8..2),
            scale in proptest::array::uniform2(-320i32..320),
            mantissa in proptest::array::uniform2(0.0f64..2.0),
        ) {
            // Zero, subnormal, huge and infinite widths as well as common ones.
            let area = [0, 1].map(|k| match scale[k] {
                -320 => 0.0,
                319 => f64::INFINITY,
                e => mantissa[k] * 2f64.powi(e),
            });
            let keys = [0, 1].map(|k| pivot_key(preference[k], area[k]));
            let expected = preference[0].cmp(&preference[1]).then(area[0].total_cmp(&area[1]));
            proptest::prop_assert_eq!(keys[0].cmp(&keys[1]), expected, "{:?} {:?}", preference, area);
        }

        /// Soundness of the check: three contacts on random lines and arcs,
        /// posed anywhere, always pass it.
        #[test]
        fn annuli_keep_every_posed_triple(
            o in proptest::array::uniform3((-6.0f64..6.0, -6.0f64..6.0)),
            to in proptest::array::uniform3((-6.0f64..6.0, -6.0f64..6.0)),
            kinds in proptest::array::uniform3(0u8..2),
            sweeps in proptest::array::uniform3(-6.0f64..6.0),
            fr in proptest::array::uniform3(0.0f64..1.0),
            theta in 0.0f64..std::f64::consts::TAU,
            shift in (-9.0f64..9.0, -9.0f64..9.0),
        ) {
            let seg = |k: usize| {
                let a = v2(o[k].0, o[k].1);
                if kinds[k] == 0 || sweeps[k].abs() < 1e-3 {
                    line(a, a + v2(to[k].0, to[k].1) + v2(0.5, 0.0))
                } else {
                    let r = 0.5 + v2(to[k].0, to[k].1).norm() / 2.0;
                    arc(a, r, to[k].1, sweeps[k])
                }
            };
            let segments = [seg(0), seg(1), seg(2)];
            let (sin, cos) = theta.sin_cos();
            let locs = [0, 1, 2].map(|k| {
                let p = segments[k].point(segments[k].s0 + fr[k] * (segments[k].s1 - segments[k].s0));
                rot(cos, sin, p) + v2(shift.0, shift.1)
            });
            let pq = pairs([&segments[0], &segments[1], &segments[2]]);
            proptest::prop_assert!(in_annuli(pq, &locs), "{segments:?} {locs:?}");
        }
    }
}
