//! The part poses that put three given locators on three grown-edge lines
//! (SPEC section 3): `A cos(theta) + B sin(theta) = C` and back-substitution.

use crate::geometry::angle_set::wrap_angle;
use crate::geometry::{cross, rot, V2};

/// A rigid placement of the part: plate point = `R(theta) p + t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// In `[0, 2 pi)`, so equal poses compare equal in the ranking key.
    pub theta: f64,
    /// `cos(theta)`, kept from the solve rather than recomputed, so every
    /// use of the pose rotates by exactly the same matrix.
    pub cos: f64,
    /// `sin(theta)`, see `cos`.
    pub sin: f64,
    /// Translation, lattice units.
    pub t: V2,
}

impl Pose {
    /// Plate point of a part point.
    #[inline]
    pub fn apply(&self, p: V2) -> V2 {
        rot(self.cos, self.sin, p) + self.t
    }

    /// Plate-frame direction of a part-frame direction (normals, edges).
    #[inline]
    pub fn rotate(&self, vector: V2) -> V2 {
        rot(self.cos, self.sin, vector)
    }

    /// Part-frame point of a plate point.
    #[inline]
    pub fn inverse_apply(&self, q: V2) -> V2 {
        crate::geometry::rot_t(self.cos, self.sin, q - self.t)
    }
}

/// A grown-edge line `n . p = c` in the part frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Line {
    /// Outward unit normal.
    pub n: V2,
    /// Offset along `n`.
    pub c: f64,
}

/// Up to two poses; degenerate configurations (all normals parallel, or a
/// locator triangle that leaves the angle free) give none.
pub fn solve_poses(lines: &[Line; 3], locs: &[V2; 3]) -> ([Pose; 2], usize) {
    solve_poses_at_angles(lines, locs, |_| true)
}

/// [`solve_poses`] keeping only the roots whose angle (in `[0, 2 pi)`)
/// passes `keep`, which is asked before the translation is worked out: the
/// setup search knows the angles at which two of the contacts stay on
/// their segments and skips the rest.
pub fn solve_poses_at_angles(
    lines: &[Line; 3],
    locs: &[V2; 3],
    keep: impl Fn(f64) -> bool,
) -> ([Pose; 2], usize) {
    let empty = Pose {
        theta: 0.0,
        cos: 1.0,
        sin: 0.0,
        t: V2::zeros(),
    };
    let mut out = [empty; 2];
    let [n1, n2, n3] = [lines[0].n, lines[1].n, lines[2].n];
    // Weights with sum_k lam_k n_k = 0 (cofactors of the 3x3 determinant).
    let lam = [cross(n2, n3), cross(n3, n1), cross(n1, n2)];
    if lam.iter().all(|&x| x.abs() <= crate::geometry::EPS) {
        return (out, 0);
    }
    let mut a = 0.0;
    let mut b = 0.0;
    let mut c = 0.0;
    for k in 0..3 {
        let n = lines[k].n;
        let l = locs[k];
        a += lam[k] * n.dot(&l);
        b += lam[k] * cross(n, l);
        c += lam[k] * lines[k].c;
    }
    let r = a.hypot(b);
    if r <= crate::geometry::EPS {
        return (out, 0);
    }
    // |C| = R within eps is a double root, one pose: a tangent (touching)
    // configuration that rounding would otherwise split into two poses a
    // hair apart, or lose. Beyond it, no pose.
    let gap = r - c.abs();
    if gap < -crate::geometry::EPS {
        return (out, 0);
    }
    let phi = b.atan2(a);
    let (thetas, count) = if gap <= crate::geometry::EPS {
        let t = if c >= 0.0 {
            phi
        } else {
            phi + std::f64::consts::PI
        };
        ([t, t], 1)
    } else {
        let delta = (c / r).clamp(-1.0, 1.0).acos();
        ([phi - delta, phi + delta], 2)
    };
    // Back-substitute with the best-conditioned pair of lines.
    let pairs = [(0usize, 1usize, 2usize), (1, 2, 0), (0, 2, 1)];
    let (i, j, _) = pairs
        .iter()
        .copied()
        .max_by(|x, y| lam[x.2].abs().total_cmp(&lam[y.2].abs()))
        .unwrap_or((0, 1, 2));
    let det = cross(lines[i].n, lines[j].n);
    let mut kept = 0;
    for &th in thetas.iter().take(count) {
        let theta = wrap_angle(th);
        if !keep(theta) {
            continue;
        }
        let (s, co) = theta.sin_cos();
        // n_k . w = n_k . (R^T L_k) - c_k
        let e = |k: usize| {
            let n = lines[k].n;
            co * n.dot(&locs[k]) + s * cross(n, locs[k]) - lines[k].c
        };
        let (ei, ej) = (e(i), e(j));
        let (ni, nj) = (lines[i].n, lines[j].n);
        let w = V2::new((ei * nj.y - ej * ni.y) / det, (ni.x * ej - nj.x * ei) / det);
        out[kept] = Pose {
            theta,
            cos: co,
            sin: s,
            t: rot(co, s, w),
        };
        kept += 1;
    }
    (out, kept)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v2;

    #[test]
    fn recovers_a_known_pose() {
        // Three lines of a triangle-ish part, a known pose, locators placed
        // on the posed lines: the solver must find that pose among its roots.
        let lines = [
            Line {
                n: v2(0., -1.),
                c: 0.5,
            },
            Line {
                n: v2(1., 0.),
                c: 3.0,
            },
            Line {
                n: v2(-0.6, 0.8),
                c: 1.0,
            },
        ];
        let truth = Pose {
            theta: 0.7,
            cos: 0.7f64.cos(),
            sin: 0.7f64.sin(),
            t: v2(1.3, -0.4),
        };
        let pts = [
            v2(1.0, -0.5),
            v2(3.0, 1.2),
            v2(-0.6 + 0.8 * 2.0, 0.8 + 0.6 * 2.0),
        ];
        for (l, p) in lines.iter().zip(pts) {
            assert!((l.n.dot(&p) - l.c).abs() < 1e-12);
        }
        let locs = pts.map(|p| truth.apply(p));
        let (poses, k) = solve_poses(&lines, &locs);
        assert!(k >= 1);
        let hit = poses[..k]
            .iter()
            .any(|p| (p.theta - 0.7).abs() < 1e-9 && (p.t - truth.t).norm() < 1e-9);
        assert!(hit, "{poses:?}");
        for p in &poses[..k] {
            for (l, loc) in lines.iter().zip(locs) {
                assert!((l.n.dot(&p.inverse_apply(loc)) - l.c).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn tangent_configuration_is_one_pose() {
        // A unit-width slot between lines y = 0 (normal down) and y = 1
        // (normal up) plus x = 0: locators (0,0) and (0,1) can only touch
        // both slot walls when the part is not turned, a double root.
        let lines = [
            Line {
                n: v2(0., -1.),
                c: 0.0,
            },
            Line {
                n: v2(0., 1.),
                c: 1.0,
            },
            Line {
                n: v2(-1., 0.),
                c: 0.0,
            },
        ];
        let (poses, k) = solve_poses(&lines, &[v2(0., 0.), v2(0., 1.), v2(-1e-3, 0.5)]);
        assert_eq!(k, 1, "{poses:?}");
        // Closer than the lines: no pose; farther: the part tilts either way.
        let (_, k) = solve_poses(&lines, &[v2(0., 0.), v2(0., 1.0 - 1e-6), v2(-1e-3, 0.5)]);
        assert_eq!(k, 0);
        let (_, k) = solve_poses(&lines, &[v2(0., 0.), v2(0., 1.0 + 1e-3), v2(-1e-3, 0.5)]);
        assert_eq!(k, 2);
    }

    #[test]
    fn parallel_normals_are_degenerate() {
        let lines = [
            Line {
                n: v2(0., -1.),
                c: 0.0,
            },
            Line {
                n: v2(0., -1.),
                c: 0.0,
            },
            Line {
                n: v2(0., 1.),
                c: 2.0,
            },
        ];
        let (_, k) = solve_poses(&lines, &[v2(0., 0.), v2(1., 0.), v2(0., 2.)]);
        assert_eq!(k, 0);
    }
}
