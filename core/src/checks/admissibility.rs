//! Collision and clearance of the clamp body and plunger against the posed
//! part, the access regions and the locators (SPEC section 4, admissible
//! fixture). Reuses buffers across candidates: the inner loop allocates
//! nothing once warm.

use crate::geometry::{
    polygon_clearance_below, polygon_disk_clearance, rot90, rot90i, v2, Aabb, BORDERLINE, EPS, V2,
};
use crate::input::setting::ClampGeom;
use crate::outline::Outline;
use crate::setups::{lattice_point, Setup};

/// Where the time goes, when asked (`fixplan bench`); nanoseconds.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Timing {
    /// Inside setups: form closure, candidates and the mount search,
    /// including the two below.
    pub setups_ns: u64,
    /// Clearance and plate-fit checks.
    pub admissibility_ns: u64,
    /// Quality metric.
    pub metric_ns: u64,
}

impl Timing {
    /// Sums the timings of pieces of work (threads, shards).
    pub fn add(&mut self, other: &Timing) {
        self.setups_ns += other.setups_ns;
        self.admissibility_ns += other.admissibility_ns;
        self.metric_ns += other.metric_ns;
    }
}

/// What a clamp must keep clear of, in lattice units and the part frame:
/// the part, its access regions and the locators, and the clamp itself.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Obstacles<'a> {
    /// The part's CCW outline.
    pub(crate) outline: &'a Outline,
    /// Bounding box of the outline, arcs included.
    pub(crate) outline_box: &'a Aabb,
    /// The access regions, CCW.
    pub(crate) access: &'a [Vec<V2>],
    /// Locator radius.
    pub(crate) locator_radius: f64,
    /// The clamp's body, plunger and mount holes.
    pub(crate) clamp: &'a ClampGeom,
    /// Smallest clearance allowed.
    pub(crate) min_clearance: f64,
}

/// Nanoseconds since `t`, when timing.
#[inline]
pub(crate) fn lap(t: Option<std::time::Instant>) -> u64 {
    t.map_or(0, |t| t.elapsed().as_nanos() as u64)
}

/// Per-thread buffers.
#[derive(Debug, Default, Clone)]
pub struct Scratch {
    /// Collect [`Timing`] (off by default: it costs a clock read per step).
    pub timing: Option<Timing>,
    /// The metric's state between candidates (see
    /// [`crate::metric::Metric::score_bounded`]).
    pub(crate) metric_hint: usize,
    posed: bool,
    part: Vec<V2>,
    part_box: Option<Aabb>,
    access: Vec<Vec<V2>>,
    access_box: Vec<Aabb>,
    body: Vec<V2>,
    plunger: Vec<V2>,
    /// A clamp polygon moved into the part frame (parts with arcs or
    /// holes).
    local: Vec<V2>,
    pts: Vec<[i64; 2]>,
}

impl Scratch {
    /// Forget the posed part: a new setup begins. Crate-private because the
    /// posed-part cache is only right if this is called at every setup.
    pub(crate) fn reset_pose(&mut self) {
        self.posed = false;
    }

    fn ensure_posed(&mut self, obstacles: &Obstacles, setup: &Setup) {
        if self.posed {
            return;
        }
        let pose = setup.pose;
        self.part.clear();
        self.part_box = None;
        // A part with arcs or holes is checked in its own frame (see
        // `curved_part_clearance`): only polygons are posed here.
        if obstacles.outline.is_polygon() {
            let pts = obstacles.outline.points();
            self.part.extend(pts.iter().map(|&p| pose.apply(p)));
            self.part_box = Some(Aabb::of(&self.part));
        }
        self.access.resize(obstacles.access.len(), Vec::new());
        self.access_box.clear();
        for (dst, src) in self.access.iter_mut().zip(obstacles.access) {
            dst.clear();
            dst.extend(src.iter().map(|&p| pose.apply(p)));
            self.access_box.push(Aabb::of(dst));
        }
        self.posed = true;
    }

    /// Smallest clearance margin of body and plunger (rotation `k`, mount
    /// `m`, extension `t`) against part, access regions and locators, or
    /// `None` when one is closer than `min_clearance` or overlaps.
    pub(crate) fn clamp_clear(
        &mut self,
        obstacles: &Obstacles,
        setup: &Setup,
        k: u8,
        m: [i64; 2],
        t: f64,
    ) -> Option<f64> {
        self.ensure_posed(obstacles, setup);
        let mv = lattice_point(m);
        let c = obstacles.clamp;
        self.body.clear();
        self.body.extend(c.body.iter().map(|&p| rot90(k, p) + mv));
        self.plunger.clear();
        self.plunger
            .extend(c.plunger.iter().map(|&p| rot90(k, p + v2(t, 0.0)) + mv));
        let need = obstacles.min_clearance;
        let locs = setup.locators.map(lattice_point);
        let mut margin = f64::INFINITY;
        let curved = !obstacles.outline.is_polygon();
        for poly in [&self.body, &self.plunger] {
            let bb = Aabb::of(poly);
            if curved {
                let d = curved_part_clearance(obstacles, &setup.pose, poly, &mut self.local, need)?;
                margin = margin.min(d);
            }
            let part = if curved {
                None
            } else {
                Some((&self.part, self.part_box.as_ref()?))
            };
            let regions = part
                .into_iter()
                .chain(self.access.iter().zip(self.access_box.iter()));
            for (obst, obox) in regions {
                let gap = bb.gap(obox);
                if gap - need > BORDERLINE {
                    margin = margin.min(gap - need);
                    continue;
                }
                let d = polygon_clearance_below(poly, obst, need + BORDERLINE)?;
                if d < need - EPS {
                    return None;
                }
                margin = margin.min((d - need).abs());
            }
            for l in &locs {
                let d = polygon_disk_clearance(poly, *l, obstacles.locator_radius)?;
                if d < need - EPS {
                    return None;
                }
                margin = margin.min((d - need).abs());
            }
        }
        Some(margin)
    }

    /// Locators and clamp mount holes, for the plate fit.
    pub(crate) fn plate_points(
        &mut self,
        locators: &[[i64; 2]; 3],
        c: &ClampGeom,
        k: u8,
        m: [i64; 2],
    ) -> &[[i64; 2]] {
        self.pts.clear();
        self.pts.extend_from_slice(locators);
        self.pts.extend(c.holes.iter().map(|h| {
            let p = rot90i(k, h.offset);
            [p[0] + m[0], p[1] + m[1]]
        }));
        &self.pts
    }
}

/// The clearance margin of a clamp polygon (plate frame) against a part
/// with arcs or holes (measured to the material, SPEC 9.4), or `None`
/// when it is closer than `need` or overlaps. The
/// polygon is moved into the part frame, where the exact curves are, rather
/// than the part onto the plate: distances do not change under a rigid
/// motion, and the few polygon vertices are cheaper to move than the arcs.
fn curved_part_clearance(
    obstacles: &Obstacles,
    pose: &crate::poses::pose::Pose,
    poly: &[V2],
    local: &mut Vec<V2>,
    need: f64,
) -> Option<f64> {
    local.clear();
    local.extend(poly.iter().map(|&p| pose.inverse_apply(p)));
    let gap = Aabb::of(local).gap(obstacles.outline_box);
    if gap - need > BORDERLINE {
        return Some(gap - need);
    }
    // Only a clearance up to the borderline band above `need` changes a
    // decision (rejection, borderline flag): farther edges cost a box test.
    let d = obstacles
        .outline
        .polygon_clearance_below(local, need + BORDERLINE)?;
    if d < need - EPS {
        return None;
    }
    Some((d - need).abs())
}
