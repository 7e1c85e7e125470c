//! Clamp placement (SPEC section 4): candidate contacts where a plunger
//! axis crosses a segment's form-closure interval, then the mount search by
//! increasing extension with every admissibility test. The candidates of
//! a segment come from [`line_candidates`] or [`arc_candidates`], chosen
//! by its feature in `offer_setup_candidates`; [`arc_reach`] narrows an
//! arc segment's axis lines before the exact tests.

mod arc_candidates;
mod arc_reach;
mod axes;
mod line_candidates;
mod segment_reach;
pub(crate) use arc_reach::ClampWindow;
pub(crate) use segment_reach::SegmentReach;

use crate::checks::admissibility::{lap, Obstacles, Scratch};
use crate::checks::form_closure::{wrench, ForceCone, LocatorWrenches};
use crate::checks::plate::Placement;
use crate::geometry::rounding::{ceil_i64, floor_i64};
use crate::geometry::{rot90i, BORDERLINE, EPS, V2};
use crate::input::setting::Setting;
use crate::input::Pattern;
use crate::metric::{Locators, Metric, PartContact};
use crate::poses::pose::Pose;
use crate::results::ranking::{Fixture, TopK};
use crate::results::report::Counts;
use crate::segments::{arc_inward_normal, Feature, Segment};
use crate::setups::{lattice_point, Setup};
use nalgebra::Vector3;

/// Counts and best fixtures of one piece of work: one per thread, merged
/// at the end, so the inner loop shares nothing.
#[derive(Debug, Clone)]
pub struct Accumulator {
    /// SPEC section 4's counts so far.
    pub counts: Counts,
    /// The best fixtures so far.
    pub top: TopK,
    /// Lowest score admitted so far (for `--good-enough`).
    pub best_score: f64,
    /// Top-k mode: skip what cannot enter `top` (see [`Self::top_k_mode`]).
    prune: bool,
    /// What the work was (not part of the result).
    pub work: Work,
}

/// How much of the work a top-k mode skipped (for `fixplan bench`): it
/// depends on the order candidates come in, hence on how the work was
/// split, so it is a measurement, never part of a result.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Work {
    /// Setups whose locators alone score above the k-th fixture: their
    /// candidates were counted, not scored.
    pub setups_floored: u64,
    /// Candidates whose metric was computed (in full mode, those with a
    /// mount).
    pub scored: u64,
    /// ...of which the metric stopped early, above the k-th score.
    pub score_cut: u64,
    /// Candidates whose mount search (clearance, plate fit) ran.
    pub mount_searches: u64,
}

impl Work {
    /// Sums the work of pieces (threads, shards).
    pub fn add(&mut self, other: &Work) {
        self.setups_floored += other.setups_floored;
        self.scored += other.scored;
        self.score_cut += other.score_cut;
        self.mount_searches += other.mount_searches;
    }
}

impl Accumulator {
    /// Empty, keeping the best `top_k` fixtures (0: all), every candidate
    /// checked: the admissible count is exact.
    pub fn new(top_k: usize) -> Self {
        Accumulator {
            counts: Counts::default(),
            top: TopK::new(top_k),
            best_score: f64::INFINITY,
            prune: false,
            work: Work::default(),
        }
    }

    /// Keeps a fixture if it is among the best so far.
    fn keep(&mut self, f: Fixture) {
        self.best_score = self.best_score.min(f.score);
        self.top.push(f);
    }

    /// Empty, keeping the best `top_k` (> 0) and skipping the mount search
    /// of every candidate that cannot enter them: the fixtures are those
    /// of [`Self::new`], the admissible count is not counted.
    pub fn top_k_mode(top_k: usize) -> Self {
        let mut acc = Accumulator::new(top_k);
        acc.prune = top_k > 0;
        acc.counts.exact = !acc.prune;
        acc
    }
}

/// A candidate clamp contact.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Candidate {
    /// Segment the tip touches.
    pub segment: usize,
    /// Quarter turns of the clamp frame.
    pub rotation: u8,
    /// Axis line index: `e_k . m` for every mount of this candidate.
    pub line: i64,
    /// Tip centre (plate frame).
    pub q: V2,
    /// Inward normal (plate frame).
    pub f: V2,
    /// Smallest decision margin so far (segment, lambda, angle).
    pub margin: f64,
}

/// What every candidate of one setup shares.
struct SetupContext<'a> {
    setup: &'a Setup,
    /// Inward normals of the three locator contacts, plate frame.
    normals: [V2; 3],
    lw: LocatorWrenches,
    /// The clamp forces `lw` can balance: segments whose normals lie
    /// outside are dropped before their intervals are solved.
    cone: ForceCone,
    /// `cone` for line normals in the part frame ([`ForceCone::unposed`]).
    line_cone: ForceCone,
    /// `|t|_1` of the pose: the pose's share of every line's reach (the
    /// bound on `|tau|` the cone takes), added to the line's own share.
    t1: f64,
    /// Smallest decision margin of the setup itself (contacts, `det W`).
    base_margin: f64,
    /// Only this clamp rotation (re-deriving one fixture).
    only_rotation: Option<u8>,
    /// What the metric works out from the locators alone (their contacts
    /// in the part frame), shared by the locator floor and every
    /// candidate's score: worked out at the first candidate, as
    /// `count_only`, contacts included, so that a setup without
    /// candidates never poses them back into the part frame.
    metric_locators: std::cell::OnceCell<Locators>,
    /// Top-k mode, and the locators alone score above the k-th fixture:
    /// candidates are only counted. Worked out at the setup's first
    /// candidate (the k-th fixture cannot change before it), so setups
    /// without candidates, most of them, never pay for the floor.
    count_only: std::cell::Cell<Option<bool>>,
}

impl SetupContext<'_> {
    /// See `count_only`.
    fn count_only(&self, search: &ClampSearch, acc: &mut Accumulator, hint: &mut usize) -> bool {
        if let Some(weak) = self.count_only.get() {
            return weak;
        }
        let weak = acc.prune && search.locators_too_weak(self.metric_locators(search), acc, hint);
        self.count_only.set(Some(weak));
        weak
    }

    /// See `metric_locators`.
    fn metric_locators(&self, search: &ClampSearch) -> &Locators {
        self.metric_locators
            .get_or_init(|| search.metric.locators(&search.part_locators(self.setup)))
    }
}

/// The clamp mount the search settled on.
struct Mount {
    /// Lattice point of mount hole 0.
    m: [i64; 2],
    /// Extension.
    t: f64,
    /// Smallest clearance margin of body and plunger.
    clear_margin: f64,
    placement: Placement,
}

impl Mount {
    /// Before the search: a mount that ranks before any real one (the
    /// last key of a fixture's rank), for the best rank a candidate
    /// could reach.
    const LOWEST: Mount = Mount {
        m: [i64::MIN; 2],
        t: f64::NAN,
        clear_margin: f64::INFINITY,
        placement: Placement {
            rotation: 0,
            offset: [0, 0],
        },
    };
}

/// What the clamp search reads of a prepared part: the segments the tip
/// may touch, the setting (clamp, plate, angle, clearance), the metric
/// that scores fixtures and what the clamp must keep clear of.
#[derive(Clone, Copy)]
pub(crate) struct ClampSearch<'a> {
    /// The usable segments, numbered as combinations number them.
    pub(crate) segments: &'a [Segment],
    /// The kit and parameters in lattice units.
    pub(crate) setting: &'a Setting,
    /// Scores a fixture's four contacts.
    pub(crate) metric: &'a dyn Metric,
    /// Part, access regions and locators, for the clearance checks.
    pub(crate) obstacles: Obstacles<'a>,
    /// Each segment's [`SegmentReach`] (an arc's [`arc_reach::ArcReach`]), numbered as
    /// `segments`; empty, the search runs without its filters (a test's
    /// reference): arcs try every axis line across their circle, and no
    /// segment is dropped for its normal ([`ForceCone`]).
    pub(crate) reaches: &'a [SegmentReach],
    /// The directions the setting's angle test can accept.
    pub(crate) window: ClampWindow,
}

impl ClampSearch<'_> {
    /// Counts a setup, and every candidate and admissible fixture it gives.
    pub(crate) fn process_setup(
        &self,
        setup: &Setup,
        acc: &mut Accumulator,
        scratch: &mut Scratch,
    ) {
        let clock = scratch.timing.is_some().then(std::time::Instant::now);
        self.offer_setup_candidates(setup, acc, scratch, None);
        let ns = lap(clock);
        if let Some(t) = scratch.timing.as_mut() {
            t.setups_ns += ns;
        }
    }

    /// [`Self::process_setup`] for one clamp segment and rotation only: the
    /// same code path, so re-deriving a reported fixture (a coordinator
    /// checking a worker's result) gives it bit for bit, at a fraction of
    /// the cost. Counts cover that segment and rotation only.
    pub(crate) fn process_setup_for_clamp(
        &self,
        setup: &Setup,
        acc: &mut Accumulator,
        scratch: &mut Scratch,
        clamp_segment: usize,
        rotation: u8,
    ) {
        self.offer_setup_candidates(setup, acc, scratch, Some((clamp_segment, rotation)));
    }

    fn offer_setup_candidates(
        &self,
        setup: &Setup,
        acc: &mut Accumulator,
        scratch: &mut Scratch,
        only: Option<(usize, u8)>,
    ) {
        acc.counts.setups += 1;
        let pose = setup.pose;
        let locs = setup.locators.map(lattice_point);
        let mut normals = [V2::zeros(); 3];
        let mut ws = [Vector3::zeros(); 3];
        for k in 0..3 {
            normals[k] = self.plate_normal(setup.combo[k], &pose, locs[k]);
            ws[k] = wrench(locs[k], normals[k]);
        }
        let Some(lw) = LocatorWrenches::new(ws) else {
            return;
        };
        let cone = if self.reaches.is_empty() {
            ForceCone::open()
        } else {
            lw.force_cone()
        };
        let ctx = SetupContext {
            setup,
            normals,
            lw,
            cone,
            line_cone: cone.unposed(pose.cos, pose.sin),
            t1: pose.t.x.abs() + pose.t.y.abs(),
            base_margin: setup.margin.min(lw.det.abs() - EPS),
            only_rotation: only.map(|o| o.1),
            metric_locators: std::cell::OnceCell::new(),
            count_only: std::cell::Cell::new(None),
        };
        scratch.reset_pose();
        let range = match only {
            Some((j, _)) => j..j.saturating_add(1).min(self.segments.len()),
            None => 0..self.segments.len(),
        };
        for j in range {
            // Empty reaches: a test's reference search, without filters.
            let reach = self.reaches.get(j);
            if let Some(seg) = self.segments.get(j) {
                self.segment_candidates(&ctx, j, seg, reach, acc, scratch);
            }
        }
    }

    /// The candidates of segment `j`, by its feature; `reach` is its
    /// [`SegmentReach`] (`None`: no filter). A line whose normal the force
    /// cone excludes is dropped here, before the rest of the segment is
    /// read: most lines of most setups are.
    #[inline(always)]
    fn segment_candidates(
        &self,
        ctx: &SetupContext,
        j: usize,
        seg: &Segment,
        reach: Option<&SegmentReach>,
        acc: &mut Accumulator,
        scratch: &mut Scratch,
    ) {
        let (line_reach, piece) = match reach {
            Some(SegmentReach::Line(lr)) => (Some(lr), None),
            Some(SegmentReach::Arc(piece)) => (None, Some(piece)),
            None => (None, None),
        };
        match &seg.feature {
            Feature::Line(line) => {
                // No force along this normal completes form closure: the
                // interval would be empty, for every rotation. `|q0|_1 +
                // |dq|_1 |s|` bounds `|tau|` along the segment (see
                // `ForceCone::excludes`): rotating keeps a vector's length,
                // so `1.5 |v|_1` bounds the posed one's `|.|_1` (and `dq` is
                // a unit vector): the part's share is `lr.own`.
                if line_reach.is_some_and(|lr| ctx.line_cone.excludes(lr.n, ctx.t1 + lr.own)) {
                    return;
                }
                self.line_candidates(ctx, j, seg, line, acc, scratch);
            }
            Feature::Arc(arc) => self.arc_candidates(ctx, j, seg, (arc, piece), acc, scratch),
        }
    }

    /// Inward normal in the plate frame of a contact centred at `q` on
    /// segment `seg` of the posed part (SPEC 4 and 8.3).
    #[inline(always)]
    fn plate_normal(&self, seg: usize, pose: &Pose, q: V2) -> V2 {
        match &self.segments[seg].feature {
            Feature::Line(l) => -pose.rotate(l.n),
            Feature::Arc(a) => arc_inward_normal(pose.apply(a.center), a.radius, a.is_convex(), q),
        }
    }

    /// SPEC 4 (c): the push direction of rotation `k` against the inward
    /// normal `f`. `None` when the angle is too large, otherwise how far
    /// the cosine is from the limits (the decision margin).
    #[inline]
    fn angle_margin(&self, k: u8, f: V2) -> Option<f64> {
        self.angle_cos(k, f).map(|c| self.angle_cos_margin(c))
    }

    /// The test of [`Self::angle_margin`] alone: the cosine `d . f` when
    /// the angle passes (`c > eps` and `c >= cos_max_angle - eps`, as the
    /// one comparison of [`ClampWindow`]'s `pass`). The cosine is read off
    /// `f` ([`axes::along`]): a zero's sign aside it is the product, and a
    /// zero fails `c > eps` either way.
    #[inline(always)]
    fn angle_cos(&self, k: u8, f: V2) -> Option<f64> {
        let c = axes::along(k, f);
        (c >= self.window.pass).then_some(c)
    }

    /// The decision margin of [`Self::angle_margin`] from the cosine that
    /// passed: worked out only for a candidate that is scored.
    #[inline(always)]
    fn angle_cos_margin(&self, c: f64) -> f64 {
        let limit = self.setting.cos_max_angle;
        (c - limit.max(0.0)).abs().min(c - EPS)
    }

    /// Whether no candidate of a setup with these locators can enter the
    /// top-k held: the metric's floor for them is above the k-th score.
    fn locators_too_weak(
        &self,
        locators: &Locators,
        acc: &mut Accumulator,
        hint: &mut usize,
    ) -> bool {
        let bound = acc.top.score_bound();
        let weak = bound.is_finite() && self.metric.prepared_locators_exceed(locators, bound, hint);
        acc.work.setups_floored += weak as u64;
        weak
    }

    /// Counts a candidate, and the fixture if it is admissible.
    #[inline]
    fn offer(
        &self,
        ctx: &SetupContext,
        cand: &Candidate,
        acc: &mut Accumulator,
        scratch: &mut Scratch,
    ) {
        acc.counts.candidates += 1;
        if ctx.count_only(self, acc, &mut scratch.metric_hint) {
            return;
        }
        if acc.prune {
            return self.offer_top_k(ctx, cand, acc, scratch);
        }
        acc.work.mount_searches += 1;
        if let Some((mount, margin)) = self.admit(ctx.setup, cand, scratch) {
            let score = self.score(ctx, cand, scratch, f64::INFINITY);
            acc.work.scored += 1;
            acc.counts.admissible += 1;
            acc.keep(self.fixture(ctx, cand, score, &mount, margin));
        }
    }

    /// Top-k mode: the score first (it does not depend on the mount), and
    /// the mount search only if the candidate could enter the top-k, that
    /// is unless its score, then its key up to the mount, rank after the
    /// k-th fixture held. Those skipped would not have entered, so the
    /// top-k is the full enumeration's.
    fn offer_top_k(
        &self,
        ctx: &SetupContext,
        cand: &Candidate,
        acc: &mut Accumulator,
        scratch: &mut Scratch,
    ) {
        let bound = acc.top.score_bound();
        let score = self.score(ctx, cand, scratch, bound);
        acc.work.scored += 1;
        if score > bound {
            acc.work.score_cut += 1;
            return;
        }
        // Its rank with the smallest mount there is: whatever mount the
        // search finds ranks at or after it.
        let best_case = self.fixture(ctx, cand, score, &Mount::LOWEST, f64::INFINITY);
        if !acc.top.could_enter(&best_case) {
            return;
        }
        acc.work.mount_searches += 1;
        if let Some((mount, margin)) = self.admit(ctx.setup, cand, scratch) {
            acc.keep(self.fixture(ctx, cand, score, &mount, margin));
        }
    }

    /// Whether a candidate is admissible: the tip must clear the locators,
    /// then the first mount of [`Self::first_mount`] decides. The mount
    /// and the smallest decision margin so far, or `None`.
    fn admit(
        &self,
        setup: &Setup,
        cand: &Candidate,
        scratch: &mut Scratch,
    ) -> Option<(Mount, f64)> {
        let locs = setup.locators.map(lattice_point);
        let mut margin = cand.margin;
        for l in &locs {
            let d = (cand.q - *l).norm() - 2.0 * self.obstacles.locator_radius;
            if d < -EPS {
                return None;
            }
            margin = margin.min(d.abs());
        }
        let mount = self.first_mount(setup, cand, scratch)?;
        let c = &self.setting.clamp;
        let t_margin = (mount.t - c.t_min).min(c.t_max - mount.t).abs();
        let margin = margin.min(mount.clear_margin).min(t_margin);
        Some((mount, margin))
    }

    /// The fixture a candidate makes with its score and mount.
    fn fixture(
        &self,
        ctx: &SetupContext,
        cand: &Candidate,
        score: f64,
        mount: &Mount,
        margin: f64,
    ) -> Fixture {
        let (setup, normals) = (ctx.setup, &ctx.normals);
        let pose = setup.pose;
        Fixture {
            score,
            segments: setup.combo,
            locators: setup.locators,
            theta: pose.theta,
            t: [pose.t.x, pose.t.y],
            clamp_segment: cand.segment,
            rotation: cand.rotation,
            mount: mount.m,
            extension: mount.t,
            contact: [cand.q.x, cand.q.y],
            normals: [
                [normals[0].x, normals[0].y],
                [normals[1].x, normals[1].y],
                [normals[2].x, normals[2].y],
                [cand.f.x, cand.f.y],
            ],
            // No finite score means the metric's solve found the contacts
            // not in form closure where the clamp test found them in it:
            // the two disagree only within rounding (W nearly singular).
            borderline: margin < BORDERLINE || !score.is_finite(),
            placement: mount.placement.clone(),
        }
    }

    /// The mount search of SPEC 4: mounts on the candidate's axis line by
    /// increasing extension, the first whose holes, clearances and plate
    /// fit all pass. SPEC fixes this order so every implementation reports
    /// the same mount.
    #[inline]
    fn first_mount(&self, setup: &Setup, cand: &Candidate, scratch: &mut Scratch) -> Option<Mount> {
        let k = cand.rotation;
        let d = axes::push_direction(k);
        let dq = d.dot(&cand.q);
        let c = &self.setting.clamp;
        let m_hi = floor_i64(dq - c.t_min + EPS);
        let m_lo = ceil_i64(dq - c.t_max - EPS);
        let di = rot90i(k, [1, 0]);
        let ei = rot90i(k, [0, 1]);
        let mut along = m_hi;
        while along >= m_lo {
            let t = dq - along as f64;
            let m = [
                cand.line * ei[0] + along * di[0],
                cand.line * ei[1] + along * di[1],
            ];
            along -= 1;
            if !self.mount_holes_free(setup, k, m) {
                continue;
            }
            let clock = scratch.timing.is_some().then(std::time::Instant::now);
            let clear = scratch.clamp_clear(&self.obstacles, setup, k, m, t);
            let placement = clear.and_then(|_| {
                let pts = scratch.plate_points(&setup.locators, c, k, m);
                let s = &self.setting;
                crate::checks::plate::fit(pts, s.cols, s.rows, s.pattern)
            });
            let ns = lap(clock);
            if let Some(tm) = scratch.timing.as_mut() {
                tm.admissibility_ns += ns;
            }
            if let (Some(clear_margin), Some(placement)) = (clear, placement) {
                return Some(Mount {
                    m,
                    t,
                    clear_margin,
                    placement,
                });
            }
        }
        None
    }

    /// Whether the clamp (rotation `k`, mount `m`) can be bolted down: no
    /// mount hole on a locator, each on a hole of the kind it needs.
    #[inline]
    fn mount_holes_free(&self, setup: &Setup, k: u8, m: [i64; 2]) -> bool {
        self.setting.clamp.holes.iter().all(|h| {
            let p = rot90i(k, h.offset);
            let p = [p[0] + m[0], p[1] + m[1]];
            !setup.locators.contains(&p)
                && (self.setting.pattern == Pattern::Square || h.kind.accepts(p[0], p[1]))
        })
    }

    /// The locator contacts in the part frame, where the metric scores
    /// them so that a score does not depend on where the part sits on
    /// the plate.
    fn part_locators(&self, setup: &Setup) -> [PartContact; 3] {
        let pose = setup.pose;
        [0, 1, 2]
            .map(|i| self.part_contact(&pose, lattice_point(setup.locators[i]), setup.combo[i]))
    }

    #[inline]
    fn part_contact(&self, pose: &Pose, q: V2, seg: usize) -> PartContact {
        let q = pose.inverse_apply(q);
        PartContact {
            q,
            f: self.segments[seg].inward_normal(q),
        }
    }

    /// The metric's score of the four contacts (exact when at most
    /// `bound`, otherwise above it, see [`crate::metric::Metric::score_bounded`]);
    /// the locators' part of the solve is the setup's, worked out once.
    #[inline]
    fn score(
        &self,
        ctx: &SetupContext,
        cand: &Candidate,
        scratch: &mut Scratch,
        bound: f64,
    ) -> f64 {
        let clamp = self.part_contact(&ctx.setup.pose, cand.q, cand.segment);
        let clock = scratch.timing.is_some().then(std::time::Instant::now);
        let score = self
            .metric
            .score_with_locators(
                ctx.metric_locators(self),
                &clamp,
                bound,
                &mut scratch.metric_hint,
            )
            .unwrap_or(f64::INFINITY);
        let ns = lap(clock);
        if let Some(tm) = scratch.timing.as_mut() {
            tm.metric_ns += ns;
        }
        score
    }
}
