//! Locator setups (SPEC section 3): for a segment combination, the lattice
//! points for locators 2 and 3 and the part poses that touch all three.
//!
//! Pruning: `L2` must lie in the annulus of distances between segments a and
//! b. When a and b are lines, `L3` comes from the region segment c sweeps
//! while `L1` and `L2` stay on them (`locator_sweep.rs`), and poses are
//! worked out only at the angles that keep contacts 1 and 2 on their
//! segments; otherwise `L3` comes from the annuli (a,c) around `L1` and
//! (b,c) around `L2`. Only lattice points and angles that cannot give a
//! setup are skipped, so the set found is exactly SPEC's; the brute-force
//! test enumerates without pruning.

use crate::contact_pose::solve_contact_poses;
use crate::geometry::{v2, V2};
use crate::input::Pattern;
use crate::locator_sweep::{LineSweep, SweepScratch};
use crate::pose::{solve_poses_where, Line, Pose};
use crate::prepare::{PairBounds, PreparedPart};
use crate::segments::{Feature, Segment};

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

impl PreparedPart {
    /// Whether `p` is a lattice offset allowed for locators 2 and 3 (grid step
    /// and, on alternating plates, dowel-hole parity).
    #[inline]
    pub fn locator_point_allowed(&self, p: [i64; 2]) -> bool {
        p[0].rem_euclid(self.setting.grid_step) == 0
            && p[1].rem_euclid(self.setting.grid_step) == 0
            && (self.setting.pattern == Pattern::Square || (p[0] + p[1]).rem_euclid(2) == 0)
    }

    /// Setups of one combination with the given `L2`, `L3` (`L1` = origin),
    /// with no pruning: the building block that pruned and brute-force
    /// enumerations share. Returns the number of pose solutions computed
    /// (kept or not), for the pruning statistics.
    pub fn setups_for_locators(
        &self,
        combo: [usize; 3],
        l2: [i64; 2],
        l3: [i64; 2],
        visit: impl FnMut(&Setup),
    ) -> usize {
        self.setups_for_locators_where(combo, l2, l3, |_| true, visit)
    }

    /// [`Self::setups_for_locators`] solving, on three lines, only the
    /// poses whose angle passes `keep` (arcs ignore it).
    fn setups_for_locators_where(
        &self,
        combo: [usize; 3],
        l2: [i64; 2],
        l3: [i64; 2],
        keep: impl Fn(f64) -> bool,
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
            let (poses, count) = solve_poses_where(&[a, b, c], &locs, keep);
            for pose in &poses[..count] {
                self.visit_pose(combo, &segs, locs_i, &locs, pose, false, &mut visit);
            }
            return count;
        }
        self.curved_setups(combo, &segs, locs_i, &locs, &mut visit)
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
        visit: &mut impl FnMut(&Setup),
    ) -> usize {
        let poses = solve_contact_poses(&segs.map(|s| s.contact()), locs);
        for p in poses.iter() {
            self.visit_pose(combo, segs, locators, locs, &p.pose, p.tangential, visit);
        }
        poses.len()
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
    /// region of [`crate::locator_sweep`].
    pub fn setups_of_combination(
        &self,
        combo: [usize; 3],
        mut visit: impl FnMut(&Setup),
    ) -> SearchStats {
        let mut stats = SearchStats::default();
        let [a, b, c] = combo;
        let ab = self.pair(a, b);
        let ac = self.pair(a, c);
        let bc = self.pair(b, c);
        let g = self.setting.grid_step;
        let (lo2, hi2) = annulus_sq(ab);
        let imax = ab.dmax.floor() as i64 + 1;
        let segs = combo.map(|i| &self.segments[i]);
        let sweep = LineSweep::new(
            segs,
            [self.directions[a], self.directions[b]],
            a == b,
            ac.dmax,
        );
        let mut scratch = SweepScratch::default();
        // L2 in Q = {i > 0, j >= 0}.
        let mut i = g;
        while i <= imax {
            let mut j = 0;
            while j <= imax {
                let l2 = [i, j];
                let d2 = (i * i + j * j) as f64;
                if d2 > hi2 {
                    break;
                }
                if d2 >= lo2 && self.locator_point_allowed(l2) {
                    let listed = sweep.as_ref().is_some_and(|sw| {
                        sw.for_each_third_locator(l2, g, &mut scratch, |l3, angles| {
                            let keep = |t: f64| angles.contains(t);
                            self.solve_triple(combo, l2, l3, keep, &mut stats, &mut visit)
                        })
                    });
                    if !listed {
                        self.third_locators(combo, l2, ac, bc, &mut stats, &mut visit);
                    }
                }
                j += g;
            }
            i += g;
        }
        stats
    }

    /// Solves one locator triple that survived pruning, with statistics.
    #[inline]
    fn solve_triple(
        &self,
        combo: [usize; 3],
        l2: [i64; 2],
        l3: [i64; 2],
        keep: impl Fn(f64) -> bool,
        stats: &mut SearchStats,
        visit: &mut impl FnMut(&Setup),
    ) {
        if l3 != [0, 0] && l3 != l2 && self.locator_point_allowed(l3) {
            stats.locator_triples += 1;
            stats.pose_solutions +=
                self.setups_for_locators_where(combo, l2, l3, keep, &mut *visit) as u64;
        }
    }

    /// `L3` from the annuli around `L1` and `L2`: arcs, and lines the
    /// sweep does not handle.
    fn third_locators(
        &self,
        combo: [usize; 3],
        l2: [i64; 2],
        ac: PairBounds,
        bc: PairBounds,
        stats: &mut SearchStats,
        visit: &mut impl FnMut(&Setup),
    ) {
        let g = self.setting.grid_step;
        let (lo_a, hi_a) = annulus_sq(ac);
        let (lo_b, hi_b) = annulus_sq(bc);
        let p2 = v2(l2[0] as f64, l2[1] as f64);
        let x_lo = (-ac.dmax).max(p2.x - bc.dmax) - 1.0;
        let x_hi = ac.dmax.min(p2.x + bc.dmax) + 1.0;
        let mut x = (x_lo / g as f64).floor() as i64 * g;
        while (x as f64) <= x_hi {
            let xf = x as f64;
            // y range from the outer circle around the origin and around L2.
            let ra = hi_a - xf * xf;
            let rb = hi_b - (xf - p2.x) * (xf - p2.x);
            if ra >= 0.0 && rb >= 0.0 {
                let (ya, yb) = (ra.sqrt(), rb.sqrt());
                let y_lo = (-ya).max(p2.y - yb);
                let y_hi = ya.min(p2.y + yb);
                let mut y = (y_lo / g as f64).floor() as i64 * g;
                while (y as f64) <= y_hi {
                    let l3 = [x, y];
                    let da = (x * x + y * y) as f64;
                    let q = v2(xf, y as f64) - p2;
                    let db = q.norm_squared();
                    if da >= lo_a && da <= hi_a && db >= lo_b && db <= hi_b {
                        self.solve_triple(combo, l2, l3, |_| true, stats, visit);
                    }
                    y += g;
                }
            }
            x += g;
        }
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
    pub fn add(&mut self, o: &SearchStats) {
        self.locator_triples += o.locator_triples;
        self.pose_solutions += o.pose_solutions;
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
