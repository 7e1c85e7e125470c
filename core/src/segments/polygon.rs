//! The segments of a polygon (SPEC section 2): grown edges cut by
//! capsules around the other edges and by the access regions. Outlines
//! without arcs take this path, the one fixplan had before arcs, so their
//! segments stay bit for bit what they were; it is the fast path
//! [`super::usable_segments`] picks, and has only lines, so it chooses
//! nothing by feature. Its interval helpers ([`slab`], [`complement`])
//! serve the general cut too.

use super::segment::{Feature, LineFeature, Segment};
use crate::geometry::{cross, point_in_polygon, v2, EPS, V2};

/// The segments of a CCW polygon with access constraints, all in lattice
/// units: grow by `r`, keep the true boundary, keep away from access
/// regions, trim `trim` at both ends.
pub(super) fn polygon_segments(part: &[V2], access: &[Vec<V2>], r: f64, trim: f64) -> Vec<Segment> {
    let n = part.len();
    let mut out = Vec::new();
    for i in 0..n {
        let a = part[i];
        let b = part[(i + 1) % n];
        let len = (b - a).norm();
        let u = (b - a) / len;
        let nrm = v2(u.y, -u.x);
        let origin = a + nrm * r;
        let mut removed: Vec<(f64, f64)> = Vec::new();
        // Points closer than r - eps to the part (trims concave vertices and
        // places where the part comes back near itself).
        for j in 0..n {
            if j == i {
                continue;
            }
            if let Some(iv) = capsule_interval(origin, u, part[j], part[(j + 1) % n], r - EPS) {
                removed.push(iv);
            }
        }
        // Points closer than r (strict, i.e. r - eps) to a filled access region.
        for poly in access {
            removed.extend(polygon_interval(origin, u, poly, r - EPS));
        }
        for (lo, hi) in complement(&mut removed, 0.0, len) {
            let (s0, s1) = (lo + trim, hi - trim);
            if s1 - s0 > EPS {
                out.push(Segment {
                    edge: i,
                    s0,
                    s1,
                    feature: Feature::Line(LineFeature::new(origin, u, nrm)),
                });
            }
        }
    }
    out
}

/// Open parameter interval of the line `origin + s u` (|u| = 1) that lies within
/// distance `rho` of the segment `[a, b]` (a capsule, hence one interval).
pub(super) fn capsule_interval(origin: V2, u: V2, a: V2, b: V2, rho: f64) -> Option<(f64, f64)> {
    if rho <= 0.0 {
        return None;
    }
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    let mut add = |iv: Option<(f64, f64)>| {
        if let Some((l, h)) = iv {
            if l < h {
                lo = lo.min(l);
                hi = hi.max(h);
            }
        }
    };
    add(disk_interval(origin, u, a, rho));
    add(disk_interval(origin, u, b, rho));
    let ab = b - a;
    let l = ab.norm();
    if l > 0.0 {
        let e = ab / l;
        let m = v2(-e.y, e.x);
        // |(p(s) - a) . m| < rho and 0 < (p(s) - a) . e < l
        let strip_m = slab(m.dot(&(origin - a)), m.dot(&u), -rho, rho);
        let strip_e = slab(e.dot(&(origin - a)), e.dot(&u), 0.0, l);
        if let (Some((l1, h1)), Some((l2, h2))) = (strip_m, strip_e) {
            add(Some((l1.max(l2), h1.min(h2))));
        }
    }
    (lo < hi).then_some((lo, hi))
}

/// `{ s : lo < p0 + s dp < hi }`.
pub(super) fn slab(p0: f64, dp: f64, lo: f64, hi: f64) -> Option<(f64, f64)> {
    if dp == 0.0 {
        return (p0 > lo && p0 < hi).then_some((f64::NEG_INFINITY, f64::INFINITY));
    }
    let (x, y) = ((lo - p0) / dp, (hi - p0) / dp);
    Some((x.min(y), x.max(y)))
}

/// `{ s : |origin + s u - c| < rho }` for a unit `u`.
fn disk_interval(origin: V2, u: V2, c: V2, rho: f64) -> Option<(f64, f64)> {
    let w = origin - c;
    let bh = u.dot(&w);
    let disc = bh * bh - (w.norm_squared() - rho * rho);
    if disc <= 0.0 {
        return None;
    }
    let sq = disc.sqrt();
    Some((-bh - sq, -bh + sq))
}

/// Parameter intervals of the line within distance `rho` of a filled polygon.
pub(super) fn polygon_interval(origin: V2, u: V2, poly: &[V2], rho: f64) -> Vec<(f64, f64)> {
    let m = poly.len();
    let mut out = Vec::new();
    let mut crossings = Vec::new();
    for j in 0..m {
        let (a, b) = (poly[j], poly[(j + 1) % m]);
        if let Some(iv) = capsule_interval(origin, u, a, b, rho) {
            out.push(iv);
        }
        let d = b - a;
        let den = cross(u, d);
        if den != 0.0 {
            let s = cross(a - origin, d) / den;
            let t = cross(a - origin, u) / den;
            if (0.0..=1.0).contains(&t) {
                crossings.push(s);
            }
        }
    }
    crossings.sort_by(f64::total_cmp);
    for w in crossings.windows(2) {
        let mid = origin + u * (0.5 * (w[0] + w[1]));
        if w[1] > w[0] && point_in_polygon(mid, poly) {
            out.push((w[0], w[1]));
        }
    }
    out
}

/// The closed pieces of `[0, len]` not covered by the open intervals.
pub(super) fn complement(removed: &mut [(f64, f64)], start: f64, len: f64) -> Vec<(f64, f64)> {
    removed.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut pieces = Vec::new();
    let mut cur = start;
    for &(lo, hi) in removed.iter() {
        if lo > cur {
            pieces.push((cur, lo.min(len)));
        }
        cur = cur.max(hi);
        if cur >= len {
            break;
        }
    }
    if cur < len {
        pieces.push((cur, len));
    }
    pieces.retain(|(a, b)| b > a);
    pieces
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts(p: &[[f64; 2]]) -> Vec<V2> {
        p.iter().map(|q| v2(q[0], q[1])).collect()
    }

    #[test]
    fn square_gives_four_trimmed_segments() {
        let sq = pts(&[[0., 0.], [4., 0.], [4., 4.], [0., 4.]]);
        let s = polygon_segments(&sq, &[], 0.25, 0.1);
        assert_eq!(s.len(), 4);
        for (i, seg) in s.iter().enumerate() {
            assert_eq!(seg.edge, i);
            assert!((seg.s0 - 0.1).abs() < 1e-12 && (seg.s1 - 3.9).abs() < 1e-12);
        }
        let Feature::Line(line) = s[0].feature else {
            panic!("a polygon has line segments only");
        };
        assert!((line.origin - v2(0., -0.25)).norm() < 1e-12);
        assert!((line.c - 0.25).abs() < 1e-12);
    }

    #[test]
    fn concave_vertex_is_trimmed() {
        // L shape: concave vertex at (2, 2).
        let l = pts(&[[0., 0.], [4., 0.], [4., 2.], [2., 2.], [2., 4.], [0., 4.]]);
        let r = 0.5;
        let s = polygon_segments(&l, &[], r, 0.0);
        // Edge 2 runs (4,2)->(2,2); its grown line y = 2.5 meets edge 3's
        // grown line x = 2.5 at s = 1.5 from its start (4, 2.5).
        let e2 = s.iter().find(|g| g.edge == 2).unwrap();
        assert!((e2.s1 - 1.5).abs() < 1e-6, "{e2:?}");
        let e3 = s.iter().find(|g| g.edge == 3).unwrap();
        assert!((e3.s0 - 0.5).abs() < 1e-6, "{e3:?}");
    }

    #[test]
    fn narrow_slot_removes_both_walls() {
        // A slot of width 0.4 < 2r cut into a block: its walls cannot be touched.
        let p = pts(&[
            [0., 0.],
            [6., 0.],
            [6., 4.],
            [3.2, 4.],
            [3.2, 1.],
            [2.8, 1.],
            [2.8, 4.],
            [0., 4.],
        ]);
        let s = polygon_segments(&p, &[], 0.25, 0.0);
        assert!(
            s.iter().all(|g| g.edge != 3 && g.edge != 4 && g.edge != 5),
            "{s:?}"
        );
    }

    #[test]
    fn access_region_splits_an_edge() {
        let sq = pts(&[[0., 0.], [6., 0.], [6., 4.], [0., 4.]]);
        let acc = vec![pts(&[[2., -2.], [3., -2.], [3., -1.], [2., -1.]])];
        // The grown bottom edge y = -0.25 passes 0.75 from the region: r = 0.25
        // keeps it whole; with r = 1.0 it touches it and is cut on (1, 4).
        let s = polygon_segments(&sq, &acc, 0.25, 0.0);
        assert_eq!(s.iter().filter(|g| g.edge == 0).count(), 1);
        let s = polygon_segments(&sq, &acc, 1.0, 0.0);
        let bottom: Vec<_> = s.iter().filter(|g| g.edge == 0).collect();
        assert_eq!(bottom.len(), 2);
        assert!((bottom[0].s1 - 1.0).abs() < 1e-6 && (bottom[1].s0 - 4.0).abs() < 1e-6);
    }

    #[test]
    fn large_access_region_containing_the_line_removes_it() {
        let sq = pts(&[[0., 0.], [6., 0.], [6., 4.], [0., 4.]]);
        let acc = vec![pts(&[[-10., -5.], [10., -5.], [10., -0.1], [-10., -0.1]])];
        let s = polygon_segments(&sq, &acc, 0.25, 0.0);
        assert!(s.iter().all(|g| g.edge != 0));
    }
}
