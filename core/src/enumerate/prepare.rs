//! A part made ready for enumeration: validated, in lattice units, with its
//! segments and per-pair bounds computed once. A prepared part is what a
//! worker caches (by digest) and what every shard of the part shares.
//!
//! [`PreparedPart`] owns what the stages share and is the one way in: its
//! methods hand each stage ([`SetupSearch`], [`ClampSearch`], the shard
//! loop of [`Stages`]) the pieces that stage reads.

use crate::checks::admissibility::{Obstacles, Scratch};
use crate::clamp::{Accumulator, ClampSearch, ClampWindow, SegmentReach};
use crate::enumerate::combinations::combination_count;
use crate::enumerate::shards::{EnumerateOptions, Enumeration, PartialResult, Stages};
use crate::geometry::polygon::validate_polygon;
use crate::geometry::{Aabb, V2};
use crate::input::setting::{scale, top_k_mode, Setting};
use crate::input::validate::{check_grid_step, PrepareError, MAX_EXTENT};
use crate::input::{Kit, MountHole, Params, Part, Units};
use crate::metric::{MaxForceMetric, Metric, WrenchListMetric};
use crate::outline::{validate_holes, Edge, Outline, Vertex};
use crate::segments::{usable_segments, PairTable, Segment};
use crate::setups::{Allowed, PivotRanks, SearchStats, Setup, SetupScratch, SetupSearch};
use crate::sweeps::SweptSegment;
use std::ops::Range;
use std::sync::Arc;

/// A part ready for enumeration: the part, kit and parameters validated and
/// converted to lattice units, with everything that does not depend on the
/// combination range computed once (usable segments, their pair bounds, the
/// metric).
///
/// It exists so that work on one part is split without repeating that
/// preparation: a worker caches it by the digest of its inputs, and every
/// shard of the part enumerates a range of combinations against the same
/// value ([`Self::enumerate_range`]). [`prepare`] is deterministic, so a
/// worker and the coordinator that prepare the same inputs hold the same
/// part bit for bit.
///
/// It depends on the part (outline and access regions), on the kit's
/// spacing and locator radius, on the edge trim and on the wrenches (the
/// geometry), and on the rest of the kit and parameters (plate, clamp,
/// angle, clearance, grid step, top-k: the setting). A study or a
/// coarse-to-fine search changes only the setting: [`Self::with_kit`] and
/// [`Self::with_grid_step`] give the part [`prepare`] would without
/// deriving the geometry again.
#[derive(Debug, Clone)]
pub struct PreparedPart {
    /// Catalogue units per lattice unit.
    spacing: f64,
    /// Locator (and clamp tip) radius, lattice units.
    r: f64,
    /// Edge trim, lattice units (kept to check [`Self::with_kit`]).
    trim: f64,
    /// `params.wrenches` (kept to check [`Self::with_kit`]).
    wrenches: Option<Vec<[f64; 3]>>,
    /// CCW outline, lattice units.
    outline: Outline,
    /// Bounding box of the outline (part frame), arcs included.
    outline_box: Aabb,
    access: Vec<Vec<V2>>,
    segments: Vec<Segment>,
    metric: Arc<dyn Metric>,
    /// Distance range of every two segments, computed on the first
    /// enumeration and shared by clones.
    pairs: PairTable,
    /// How every two segments rank as a pivot, computed with `pairs` and
    /// shared by clones.
    pivot_ranks: PivotRanks,
    /// Each segment as the setup sweep uses it, so that choosing a
    /// combination's pivot costs no trig per combination.
    swept: Vec<SweptSegment>,
    /// What the clamp search reads of each segment (an arc's piece of
    /// circle, a line's share of its contacts' reach).
    reaches: Vec<SegmentReach>,
    setting: Setting,
}

/// Validates and converts a part, kit and parameters into lattice units and
/// computes everything that does not depend on the combination range.
pub fn prepare(
    part: &Part,
    kit: &Kit,
    params: &Params,
    units: Units,
) -> Result<PreparedPart, PrepareError> {
    let setting = Setting::new(kit, params, units)?;
    let l = kit.spacing;
    let (outline, access) = lattice_polygons(part, l)?;
    let r = kit.locator_radius / l;
    let trim = params.edge_trim_or_default(units) / l;
    let segments = usable_segments(&outline, &access, r, trim);
    let swept = segments.iter().map(SweptSegment::of).collect();
    let reaches = segments.iter().map(SegmentReach::of).collect();
    let metric = metric(params.wrenches.as_deref(), &outline, l);
    Ok(PreparedPart {
        spacing: l,
        r,
        trim,
        wrenches: params.wrenches.clone(),
        outline_box: outline.aabb(),
        outline,
        access,
        segments,
        metric,
        pairs: PairTable::default(),
        pivot_ranks: PivotRanks::default(),
        swept,
        reaches,
        setting,
    })
}

/// The part region (outline CCW, holes CW) and access regions,
/// validated, in lattice units.
fn lattice_polygons(part: &Part, l: f64) -> Result<(Outline, Vec<Vec<V2>>), PrepareError> {
    // Validate in the user's unit so error coordinates are the user's.
    Outline::new(&part.outline).map_err(PrepareError::Outline)?;
    let holes = validate_holes(&part.outline, &part.holes).map_err(PrepareError::Hole)?;
    // A bulge is an angle: scaling leaves it as it is, and keeps a loop's
    // orientation.
    let lattice = |vs: &[Vertex]| -> Vec<Vertex> {
        vs.iter()
            .map(|v| Vertex::new(v.x / l, v.y / l, v.bulge))
            .collect()
    };
    let mut outline = Outline::new(&lattice(&part.outline)).map_err(PrepareError::Outline)?;
    if !holes.is_empty() {
        outline = outline.with_holes(holes.iter().map(|h| lattice(h)).collect());
    }
    let mut access = Vec::with_capacity(part.access.len());
    for (index, a) in part.access.iter().enumerate() {
        let at = |source| PrepareError::Access { index, source };
        validate_polygon(a).map_err(at)?;
        access.push(validate_polygon(&scale(a, l)).map_err(at)?);
    }
    // Lattice coordinates are enumerated as integers: keep them far from
    // overflow (a part 10^6 spacings across is 25 km on a 25 mm plate).
    // An arc reaches beyond its end points (a bulge of 1e9 on a 10 mm
    // chord is a circle of radius 2.5e9 mm): its whole circle counts.
    let arcs = outline.edges().iter().filter_map(|e| match e {
        Edge::Arc(arc) => Some(arc.center.x.abs().max(arc.center.y.abs()) + arc.radius),
        Edge::Line { .. } => None,
    });
    let extent = outline
        .points()
        .iter()
        .chain(access.iter().flatten())
        .fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()));
    let extent = arcs.fold(extent, f64::max);
    if extent > MAX_EXTENT {
        return Err(PrepareError::TooLarge {
            extent,
            limit: MAX_EXTENT,
        });
    }
    Ok((outline, access))
}

/// The user's wrenches, or SPEC 6's default about the true region's
/// centroid (SPEC 8.1: arcs included).
fn metric(wrenches: Option<&[[f64; 3]]>, outline: &Outline, l: f64) -> Arc<dyn Metric> {
    match wrenches {
        Some(ws) => Arc::new(WrenchListMetric::new(ws, l)),
        None => {
            let mass = outline.mass_properties();
            Arc::new(MaxForceMetric::new(
                mass.centroid,
                mass.radius_of_gyration(),
            ))
        }
    }
}

/// Bitwise float equality: `-0.0` and `0.0` can round differently later,
/// and the study's cache key tells them apart too.
fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits()
}

impl PreparedPart {
    /// `prepare(part, kit, params, units)` for the part this was prepared
    /// from, reusing its segments, pair bounds and metric: only the
    /// setting (plate, clamp, angle, clearance, grid step, top-k) is
    /// converted again. A study solves one part with many kits this way.
    ///
    /// Precondition: `kit` and `params` keep the geometry, that is the
    /// same spacing, locator radius, edge trim (after defaults) and
    /// wrenches, bit for bit. This is checked, not assumed: otherwise the
    /// answer is [`PrepareError::OtherGeometry`] (after the kit and
    /// parameter errors a [`prepare`] would report first).
    pub fn with_kit(
        &self,
        kit: &Kit,
        params: &Params,
        units: Units,
    ) -> Result<PreparedPart, PrepareError> {
        let setting = Setting::new(kit, params, units)?;
        let l = kit.spacing;
        let wrenches_same = match (&self.wrenches, &params.wrenches) {
            (None, None) => true,
            (Some(a), Some(b)) => {
                a.len() == b.len()
                    && a.iter()
                        .flatten()
                        .zip(b.iter().flatten())
                        .all(|(x, y)| same(*x, *y))
            }
            _ => false,
        };
        let differs = [
            (!same(l, self.spacing), "lattice spacing"),
            (!same(kit.locator_radius / l, self.r), "locator radius"),
            (
                !same(params.edge_trim_or_default(units) / l, self.trim),
                "edge trim",
            ),
            (!wrenches_same, "wrenches"),
        ];
        if let Some((_, what)) = differs.iter().find(|d| d.0) {
            return Err(PrepareError::OtherGeometry(what));
        }
        Ok(PreparedPart {
            setting,
            ..self.clone()
        })
    }

    /// The part with locators 2 and 3 on multiples of `step`: what
    /// [`prepare`] gives with `params.grid_step = step`, for a coarse-to-fine
    /// search that runs several steps on one part. Step 0 is refused as
    /// [`crate::validate_params`] refuses it.
    pub fn with_grid_step(&self, step: u32) -> Result<PreparedPart, PrepareError> {
        check_grid_step(step)?;
        let mut p = self.clone();
        p.setting.grid_step = step as i64;
        Ok(p)
    }

    /// The part keeping the best `top_k` (0: all), in top-k mode unless
    /// `full_counts`: what [`prepare`] gives with those parameters, for a
    /// bench that measures both modes on one part.
    pub fn with_top_k(&self, top_k: usize, full_counts: bool) -> PreparedPart {
        let mut p = self.clone();
        p.setting.top_k = top_k;
        p.setting.prune_to_top_k = top_k_mode(top_k, full_counts);
        p
    }

    /// The part with its tables worked out on first use (pair bounds,
    /// pivot ranks and points) not yet worked out: clones share them, so a
    /// bench that enumerates one part again and again would time them
    /// once only, where a run pays them for every part. The answers are
    /// the same.
    pub fn with_fresh_tables(&self) -> PreparedPart {
        PreparedPart {
            pairs: PairTable::default(),
            pivot_ranks: PivotRanks::default(),
            ..self.clone()
        }
    }

    /// The usable segments (SPEC section 2), in the order that numbers
    /// combinations and fixtures: a fixture's segment indices point here.
    #[inline]
    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }

    /// The loop of every segment (SPEC 9.6: 0 the outline, `k + 1` hole
    /// `k`), empty for a part without holes.
    pub fn segment_loops(&self) -> Vec<usize> {
        if !self.outline.has_holes() {
            return Vec::new();
        }
        self.segments
            .iter()
            .map(|s| self.outline.loop_of_edge(s.edge))
            .collect()
    }

    /// The CCW outline in lattice units, the frame of the segments and of
    /// the part contacts a metric scores.
    #[inline]
    pub fn outline(&self) -> &Outline {
        &self.outline
    }

    /// Locator (and clamp tip) radius in lattice units: the distance from
    /// the part edge to the grown edge the segments lie on.
    #[inline]
    pub fn locator_radius(&self) -> f64 {
        self.r
    }

    /// Cosine of the largest angle between the plunger axis and a clamped
    /// edge's inward normal.
    #[inline]
    pub fn cos_max_angle(&self) -> f64 {
        self.setting.cos_max_angle
    }

    /// How many fixtures a result keeps (0: all); merging shards needs it.
    #[inline]
    pub fn top_k(&self) -> usize {
        self.setting.top_k
    }

    /// Whether results count admissible fixtures: not in top-k mode
    /// (`top_k > 0` without `full_counts`), which skips the mount search
    /// of candidates that cannot enter the top-k.
    #[inline]
    pub fn counts_exact(&self) -> bool {
        !self.setting.prune_to_top_k
    }

    /// The grid step locators 2 and 3 are enumerated at.
    #[inline]
    pub fn grid_step(&self) -> u32 {
        self.setting.grid_step as u32
    }
    /// Catalogue units per lattice unit: what a report multiplies by.
    #[inline]
    pub(crate) fn spacing(&self) -> f64 {
        self.spacing
    }

    /// The clamp's mount holes in its frame, for placing a fixture's
    /// holes on the plate.
    #[inline]
    pub(crate) fn clamp_holes(&self) -> &[MountHole] {
        &self.setting.clamp.holes
    }

    /// The setup search over this part's segments and lattice.
    fn setup_search(&self) -> SetupSearch<'_> {
        SetupSearch {
            segments: &self.segments,
            swept: &self.swept,
            pairs: &self.pairs,
            ranks: &self.pivot_ranks,
            grid_step: self.setting.grid_step,
            pattern: self.setting.pattern,
        }
    }

    /// The clamp search against this part, its setting and its metric.
    pub(crate) fn clamp_search(&self) -> ClampSearch<'_> {
        ClampSearch {
            segments: &self.segments,
            setting: &self.setting,
            metric: &*self.metric,
            obstacles: Obstacles {
                outline: &self.outline,
                outline_box: &self.outline_box,
                access: &self.access,
                locator_radius: self.r,
                clamp: &self.setting.clamp,
                min_clearance: self.setting.min_clearance,
            },
            reaches: &self.reaches,
            window: ClampWindow::new(self.setting.cos_max_angle),
        }
    }

    /// Both searches, as the shard loop runs them.
    fn stages(&self) -> Stages<'_> {
        Stages {
            setups: self.setup_search(),
            clamp: self.clamp_search(),
        }
    }

    /// Whether `p` is a lattice offset allowed for locators 2 and 3 (grid step
    /// and, on alternating plates, dowel-hole parity).
    #[inline]
    pub fn locator_point_allowed(&self, p: [i64; 2]) -> bool {
        self.setup_search().locator_point_allowed(p)
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
        self.setup_search()
            .setups_for_locators(combo, l2, l3, Allowed::ALL, visit)
    }

    /// Every setup of one combination, pruned by annuli and by the region
    /// the third segment sweeps (SPEC 3 allows any pruning that keeps the
    /// set).
    pub fn setups_of_combination(
        &self,
        combo: [usize; 3],
        visit: impl FnMut(&Setup),
    ) -> SearchStats {
        self.setup_search()
            .setups_of_combination(combo, &mut SetupScratch::default(), visit)
    }

    /// Counts a setup, and every candidate and admissible fixture it gives.
    pub fn process_setup(&self, setup: &Setup, acc: &mut Accumulator, scratch: &mut Scratch) {
        self.clamp_search().process_setup(setup, acc, scratch);
    }

    /// [`Self::process_setup`] for one clamp segment and rotation only: the
    /// same code path, so re-deriving a reported fixture (a coordinator
    /// checking a worker's result) gives it bit for bit, at a fraction of
    /// the cost. Counts cover that segment and rotation only.
    pub fn process_setup_for_clamp(
        &self,
        setup: &Setup,
        acc: &mut Accumulator,
        scratch: &mut Scratch,
        clamp_segment: usize,
        rotation: u8,
    ) {
        self.clamp_search()
            .process_setup_for_clamp(setup, acc, scratch, clamp_segment, rotation);
    }

    /// Size of the combination space, the range shards are cut from.
    pub fn combination_count(&self) -> u64 {
        combination_count(self.segments.len())
    }

    /// Enumerates the combinations with indices in `range` (clipped to
    /// the part) as `options` say: on the rayon pool or this thread, to
    /// the end or to the first good-enough fixture, timed or not. Any
    /// split of a range merges ([`crate::merge`]) to the same result.
    pub fn enumerate(&self, range: Range<u64>, options: EnumerateOptions<'_>) -> Enumeration {
        self.stages().enumerate(range, options)
    }

    /// `range` on the rayon pool, every combination:
    /// [`Self::enumerate`] with the default options.
    pub fn enumerate_range(&self, range: Range<u64>) -> PartialResult {
        self.enumerate(range, EnumerateOptions::default()).result
    }

    /// The whole part.
    pub fn enumerate_all(&self) -> PartialResult {
        self.enumerate_range(0..self.combination_count())
    }
}
