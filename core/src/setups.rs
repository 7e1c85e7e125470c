//! Locator setups (SPEC section 3): for a segment combination, the lattice
//! points for locators 2 and 3 and the part poses that touch all three.
//!
//! Pruning: two of the three segments are the pivot, one locator at the
//! origin, the other at every lattice point of their annulus (up to
//! quarter turns), and the third locator only in the region the third
//! segment sweeps while the pivot's contacts stay on their segments
//! ([`crate::sweeps`]); on three lines, poses are worked out only at the
//! angles that keep the pivot's contacts on their segments. The pivot is
//! two lines when the combination has two (of the pairs of lines, the one
//! with the thinnest annulus: the region is built once per lattice point
//! of that annulus, so the pair with the fewest points costs least), else
//! a line and an arc (again the thinnest such pair), so the arc is only
//! swept, never solved for at every point of its annuli. Each triple is
//! then moved to SPEC's canonical frame (`L1` at the origin, `L2` in the
//! quadrant `Q`) and solved there, so a setup's numbers never depend on
//! which pair pivoted. Without a pivot (three arcs, or nearly parallel
//! lines the sweep refuses), `L2` comes from the annulus (a, b) and `L3`
//! from the annuli (a, c) around `L1` and (b, c) around `L2`. Only lattice
//! points and angles that cannot give a setup are skipped, so the set
//! found is exactly SPEC's; the brute-force tests enumerate without
//! pruning.

use crate::geometry::angle_set::{wrap_angle, AngleSet};
use crate::geometry::{v2, V2};
use crate::input::Pattern;
use crate::poses::contact_pose::solve_contact_poses_at_angles;
use crate::poses::pose::{solve_poses_at_angles, Line, Pose};
use crate::segments::{Feature, PairBounds, PairTable, Segment};
use crate::sweeps::{LocatorSweep, PivotPoint, SweepScratch, SweptSegment};
use rustc_hash::FxHashMap;
use std::f64::consts::FRAC_PI_2;

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
    /// Locators 2 and 3 lie on multiples of this.
    pub(crate) grid_step: i64,
    /// Alternating plates take locators on dowel holes only.
    pub(crate) pattern: Pattern,
}

impl SetupSearch<'_> {
    /// Whether `p` is a lattice offset allowed for locators 2 and 3 (grid step
    /// and, on alternating plates, dowel-hole parity).
    #[inline]
    pub(crate) fn locator_point_allowed(&self, p: [i64; 2]) -> bool {
        p[0].rem_euclid(self.grid_step) == 0
            && p[1].rem_euclid(self.grid_step) == 0
            && (self.pattern == Pattern::Square || (p[0] + p[1]).rem_euclid(2) == 0)
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
        let lines = segs.map(|s| match s.feature {
            Feature::Line(l) => Some(Line { n: l.n, c: l.c }),
            Feature::Arc(_) => None,
        });
        if let [Some(a), Some(b), Some(c)] = lines {
            // Polygons: SPEC 3's closed form, as before arcs.
            let (poses, count) = solve_poses_at_angles(&[a, b, c], &locs, |t| allowed.keeps(t));
            for pose in &poses[..count] {
                self.visit_pose(combo, &segs, locs_i, &locs, pose, false, &mut visit);
            }
            return count;
        }
        self.curved_setups(combo, &segs, locs_i, &locs, allowed, &mut visit)
    }

    /// [`Self::setups_for_locators`] when a segment is an arc (SPEC 8.4),
    /// kept out of line so the polygon loop stays as small as it was.
    #[inline(never)]
    fn curved_setups(
        &self,
        combo: [usize; 3],
        segs: &[&Segment; 3],
        locators: [[i64; 2]; 3],
        locs: &[V2; 3],
        allowed: Allowed<'_>,
        visit: &mut impl FnMut(&Setup),
    ) -> usize {
        // The sweep places `L3` in its region without the annuli, which
        // cost nothing next to an arc pose solution: about one swept
        // triple in seven of `bracket-arcs` is dropped here.
        if allowed.angles.is_some() && !self.in_annuli(combo, locs) {
            return 0;
        }
        let contacts = segs.map(|s| s.contact());
        let poses = solve_contact_poses_at_angles(&contacts, locs, &|lo, hi| allowed.meets(lo, hi));
        for p in poses.iter() {
            self.visit_pose(combo, segs, locators, locs, &p.pose, p.tangential, visit);
        }
        poses.len()
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
        match self.pivot(combo) {
            Some(pivot) => self.swept_setups(combo, &pivot, scratch, &mut stats, &mut visit),
            None => self.annulus_setups(combo, &mut stats, &mut visit),
        }
        stats
    }

    /// The two lines of the combination the sweep turns the part about,
    /// `a` and `b` when both are lines. With one arc the sweep still
    /// applies, pivoting on the other two segments: the arc then only has
    /// to be swept (chords), never solved for at every lattice point of
    /// its annuli.
    fn pivot(&self, combo: [usize; 3]) -> Option<Pivot<'_>> {
        const LINE_PAIRS: [[usize; 3]; 3] = [[0, 1, 2], [0, 2, 1], [1, 2, 0]];
        // Line first, arc second: every order, the combination's order
        // says nothing about which is which.
        const LINE_ARC: [[usize; 3]; 6] = [
            [0, 1, 2],
            [0, 2, 1],
            [1, 0, 2],
            [1, 2, 0],
            [2, 0, 1],
            [2, 1, 0],
        ];
        self.thinnest_pivot(combo, &LINE_PAIRS, true)
            .or_else(|| self.thinnest_pivot(combo, &LINE_ARC, false))
    }

    /// Of the role orders whose sweep applies (two lines when `lines`,
    /// else a line then an arc), the one with the thinnest pivot annulus.
    /// Orders are ranked by their annulus first, so a sweep is built only
    /// for the winner (and the next ones when nearly parallel lines refuse
    /// it).
    fn thinnest_pivot(
        &self,
        combo: [usize; 3],
        orders: &[[usize; 3]],
        lines: bool,
    ) -> Option<Pivot<'_>> {
        let is_line = |k: usize| self.swept[combo[k]].is_line();
        let (table, nseg) = (self.pair_table(), self.segments.len());
        let pair = |a: usize, b: usize| table[a * nseg + b];
        let mut ranked = [(f64::INFINITY, [0usize; 3]); 6];
        let mut n = 0;
        for &roles in orders {
            let [p, q, _] = roles;
            if !is_line(p) || is_line(q) != lines {
                continue;
            }
            let (lo, hi) = annulus_sq(pair(combo[p], combo[q]));
            // Insertion keeps the first of equal areas first.
            let mut k = n;
            while k > 0 && ranked[k - 1].0 > hi - lo {
                ranked[k] = ranked[k - 1];
                k -= 1;
            }
            ranked[k] = (hi - lo, roles);
            n += 1;
        }
        ranked[..n].iter().find_map(|&(_, roles)| {
            let [p, q, r] = roles.map(|k| combo[k]);
            let swept = [p, q, r].map(|i| &self.swept[i]);
            let sweep = LocatorSweep::new(swept, p == q, pair(p, r).dmax)?;
            Some(Pivot { roles, sweep })
        })
    }

    /// Setups by the sweep: the pivot's first locator at the origin, its
    /// second at every lattice point `d` of `Q = {i > 0, j >= 0}` in their
    /// annulus that leaves the part some angle, the third segment's
    /// locator in the swept region.
    fn swept_setups(
        &self,
        combo: [usize; 3],
        pivot: &Pivot<'_>,
        scratch: &mut SetupScratch,
        stats: &mut SearchStats,
        visit: &mut impl FnMut(&Setup),
    ) {
        let [p, q, r] = pivot.roles.map(|k| combo[k]);
        let g = self.grid_step;
        let SetupScratch { sweep, pivots } = scratch;
        for (d, pt) in pivots.points(p, q, |out| self.pivot_points(&pivot.sweep, p, q, out)) {
            let d = *d;
            let listed = pivot
                .sweep
                .for_each_third_locator(pt, g, sweep, |e, angles| {
                    self.solve_placed(combo, pivot, d, e, angles, stats, visit)
                });
            if !listed {
                let (pr, qr) = (self.pair(p, r), self.pair(q, r));
                annulus_points(d, pr, qr, g, |e| {
                    self.solve_placed(combo, pivot, d, e, None, stats, visit)
                });
            }
        }
    }

    /// The lattice points `d` of `Q` in the annulus of the pivot pair
    /// `(p, q)` at which some angle keeps both contacts on their segments.
    fn pivot_points(
        &self,
        sweep: &LocatorSweep<'_>,
        p: usize,
        q: usize,
        out: &mut Vec<LatticePivot>,
    ) {
        self.quadrant_points(self.pair(p, q), |d| {
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
        let imax = pair.dmax.floor() as i64 + 1;
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

    /// Solves the triple with the pivot's locators at `0` and `d` and the
    /// third at `e`, after moving it to the canonical frame: `L1` at the
    /// origin, turned by quarter turns (which map the lattice onto itself)
    /// until `L2` lies in `Q`. Each setup has exactly one placement with
    /// `d` in `Q`, so each is solved once. `angles` (pivot frame) lets
    /// three lines work out only the poses the sweep allows.
    #[allow(clippy::too_many_arguments)] // one lattice triple, unpacked
    fn solve_placed(
        &self,
        combo: [usize; 3],
        pivot: &Pivot<'_>,
        d: [i64; 2],
        e: [i64; 2],
        angles: Option<&AngleSet>,
        stats: &mut SearchStats,
        visit: &mut impl FnMut(&Setup),
    ) {
        let mut placed = [[0i64; 2]; 3];
        let [p, q, r] = pivot.roles;
        (placed[p], placed[q], placed[r]) = ([0, 0], d, e);
        let o = placed[0];
        let (l2, l3) = (sub(placed[1], o), sub(placed[2], o));
        if l2 == [0, 0] {
            return;
        }
        let turns = quarter_turns_into_q(l2);
        let (l2, l3) = (quarter_turn(l2, turns), quarter_turn(l3, turns));
        // `d` was checked; any other L2 is a difference of checked points
        // turned, which keeps grid step and dowel parity, but say so here
        // rather than rely on it.
        if l2 != d && !self.locator_point_allowed(l2) {
            return;
        }
        let allowed = Allowed { angles, turns };
        self.solve_triple(combo, l2, l3, allowed, stats, visit);
    }

    /// Setups when no pair of lines can pivot (two or three arcs, or nearly
    /// parallel lines): `L2` in the annulus (a, b), `L3` in the annuli
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

    /// Whether the canonical angle `t` is allowed.
    fn keeps(&self, t: f64) -> bool {
        self.angles.is_none_or(|a| {
            a.contains(if self.turns == 0 {
                t
            } else {
                wrap_angle(t - self.back())
            })
        })
    }

    /// Whether some canonical angle of `[lo, hi]` is allowed.
    fn meets(&self, lo: f64, hi: f64) -> bool {
        let back = self.back();
        self.angles.is_none_or(|a| a.meets(lo - back, hi - back))
    }
}

/// A combination's roles for the sweep: `roles[0]`, `roles[1]` (positions
/// in the combination) are the two lines it pivots on, `roles[2]` the
/// segment it sweeps.
struct Pivot<'s> {
    roles: [usize; 3],
    sweep: LocatorSweep<'s>,
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

/// Most pivot points kept per thread (about 180 bytes each, 6 MB in all;
/// `housing-57` keeps 1,043, scaled 3x 13,677): beyond, the cache starts
/// over, so a huge part costs time, never unbounded memory.
const PIVOT_CACHE_POINTS: usize = 1 << 15;

/// The pivot points of each pivot pair: the same pair pivots many
/// combinations (every third segment whose pairs with it are wider), and
/// its points (two `acos` bands per lattice point of the annulus) do not
/// depend on the third segment.
#[derive(Debug, Default)]
struct PivotCache {
    /// Where each pair's points lie in `points`.
    pairs: FxHashMap<(usize, usize), std::ops::Range<usize>>,
    /// Every pair's points, one after the other: one allocation for all.
    points: Vec<LatticePivot>,
}

impl PivotCache {
    fn points(
        &mut self,
        p: usize,
        q: usize,
        push: impl FnOnce(&mut Vec<LatticePivot>),
    ) -> &[LatticePivot] {
        let range = match self.pairs.get(&(p, q)) {
            Some(r) => r.clone(),
            None => {
                if self.points.len() > PIVOT_CACHE_POINTS {
                    self.pairs.clear();
                    self.points.clear();
                }
                let start = self.points.len();
                push(&mut self.points);
                let r = start..self.points.len();
                self.pairs.insert((p, q), r.clone());
                r
            }
        };
        &self.points[range]
    }
}

fn sub(a: [i64; 2], b: [i64; 2]) -> [i64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

/// `p` turned by `turns` quarter turns counterclockwise.
fn quarter_turn(p: [i64; 2], turns: u8) -> [i64; 2] {
    (0..turns).fold(p, |[x, y], _| [-y, x])
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
    let mut x = (x_lo / grid_step as f64).floor() as i64 * grid_step;
    while (x as f64) <= x_hi {
        let xf = x as f64;
        // y range from the outer circle around the origin and around L2.
        let ra = hi_a - xf * xf;
        let rb = hi_b - (xf - p2.x) * (xf - p2.x);
        if ra >= 0.0 && rb >= 0.0 {
            let (ya, yb) = (ra.sqrt(), rb.sqrt());
            let y_lo = (-ya).max(p2.y - yb);
            let y_hi = ya.min(p2.y + yb);
            let mut y = (y_lo / grid_step as f64).floor() as i64 * grid_step;
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
fn annulus_sq(p: PairBounds) -> (f64, f64) {
    let lo = (p.dmin - ANNULUS_SLACK).max(0.0);
    let hi = p.dmax + ANNULUS_SLACK;
    (lo * lo, hi * hi)
}

/// Plate position of a lattice point.
#[inline]
pub fn lattice_point(p: [i64; 2]) -> V2 {
    v2(p[0] as f64, p[1] as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::arc::GrownArc;
    use crate::geometry::rot;
    use crate::segments::LineFeature;

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
    fn pairs(s: [&Segment; 3]) -> [[PairBounds; 3]; 3] {
        s.map(|a| s.map(|b| PairBounds::between(a, b)))
    }

    /// `L1` at the origin, `L2 = d`, `L3 = e`.
    fn at(pairs: [[PairBounds; 3]; 3], d: [i64; 2], e: [i64; 2]) -> bool {
        in_annuli(pairs, &[v2(0.0, 0.0), lattice_point(d), lattice_point(e)])
    }

    #[test]
    fn annuli_reject_distances_no_segments_have() {
        // p along the x axis, q and r parallel to it 2 and 5 above: |e| in
        // [5, sqrt 125] from p, |e - d| in [3, sqrt 109] from q.
        let p = line(v2(0.0, 0.0), v2(10.0, 0.0));
        let q = line(v2(0.0, 2.0), v2(10.0, 2.0));
        let r = line(v2(0.0, 5.0), v2(10.0, 5.0));
        let pq = pairs([&p, &q, &r]);
        let d = [0, 2];
        assert!(at(pq, d, [0, 5]) && at(pq, d, [10, 2]));
        assert!(!at(pq, d, [4, 0]), "|e| = 4 < 5 from p");
        assert!(!at(pq, d, [12, 0]), "|e| = 12 > sqrt 125 from p");
        assert!(!at(pq, d, [11, 0]), "|e - d| = sqrt 125 > sqrt 109 from q");
        assert!(!at(pq, [0, 1], [0, 5]), "|d| = 1 < 2 from p to q");
        // The roles are not interchangeable.
        assert!(!at(pairs([&q, &p, &r]), d, [0, 5]));
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig {
            cases: 2000,
            failure_persistence: None,
            ..Default::default()
        })]

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
            let s = [seg(0), seg(1), seg(2)];
            let (sin, cos) = theta.sin_cos();
            let locs = [0, 1, 2].map(|k| {
                let p = s[k].point(s[k].s0 + fr[k] * (s[k].s1 - s[k].s0));
                rot(cos, sin, p) + v2(shift.0, shift.1)
            });
            let pq = pairs([&s[0], &s[1], &s[2]]);
            proptest::prop_assert!(in_annuli(pq, &locs), "{s:?} {locs:?}");
        }
    }
}
