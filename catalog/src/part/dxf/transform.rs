//! The placement of a block's entities by the INSERT that references it:
//! a 2D affine map, composed through nested blocks.

use super::super::outline::{flatten_vertices, P};
use fixplan_core::outline::Vertex;

/// `x' = m[0] x + m[1] y + m[2]`, `y' = m[3] x + m[4] y + m[5]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Transform {
    m: [f64; 6],
}

/// Relative size under which two axis lengths are equal and axes square.
const SIMILAR_REL: f64 = 1e-9;

impl Transform {
    pub const ID: Transform = Transform {
        m: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0],
    };

    /// The map of an INSERT (and of one cell of a MINSERT array): the
    /// block's base point to the origin, scaled, moved by the cell's
    /// offset along the block's axes, rotated by `rotation_deg`, moved to
    /// `location`, then mirrored in x when the insert's extrusion is
    /// (0, 0, -1) (`flip`).
    pub fn insert(
        base: P,
        scale: [f64; 2],
        offset: P,
        rotation_deg: f64,
        location: P,
        flip: bool,
    ) -> Transform {
        let (s, c) = rotation_deg.to_radians().sin_cos();
        let [sx, sy] = scale;
        // R S, and R (offset - S base) + location.
        let tx = offset[0] - sx * base[0];
        let ty = offset[1] - sy * base[1];
        let mut m = [
            c * sx,
            -s * sy,
            c * tx - s * ty + location[0],
            s * sx,
            c * sy,
            s * tx + c * ty + location[1],
        ];
        if flip {
            m[0] = -m[0];
            m[1] = -m[1];
            m[2] = -m[2];
        }
        Transform { m }
    }

    /// `self` first, then `outer`.
    pub fn then(self, outer: Transform) -> Transform {
        let a = outer.m;
        let b = self.m;
        Transform {
            m: [
                a[0] * b[0] + a[1] * b[3],
                a[0] * b[1] + a[1] * b[4],
                a[0] * b[2] + a[1] * b[5] + a[2],
                a[3] * b[0] + a[4] * b[3],
                a[3] * b[1] + a[4] * b[4],
                a[3] * b[2] + a[4] * b[5] + a[5],
            ],
        }
    }

    pub fn apply(&self, p: P) -> P {
        let m = self.m;
        [
            m[0] * p[0] + m[1] * p[1] + m[2],
            m[3] * p[0] + m[4] * p[1] + m[5],
        ]
    }

    /// The longest a unit vector can become, for tolerances in block
    /// units (the larger axis length bounds it within a factor sqrt 2).
    pub fn max_scale(&self) -> f64 {
        let m = self.m;
        m[0].hypot(m[3]).max(m[1].hypot(m[4]))
    }

    fn det(&self) -> f64 {
        self.m[0] * self.m[4] - self.m[1] * self.m[3]
    }

    /// Whether circles stay circles: square axes of equal length.
    pub fn is_similarity(&self) -> bool {
        let m = self.m;
        let (l1, l2) = (m[0].hypot(m[3]), m[1].hypot(m[4]));
        let dot = m[0] * m[1] + m[3] * m[4];
        l1 > 0.0
            && (l1 - l2).abs() <= SIMILAR_REL * l1
            && dot.abs() <= SIMILAR_REL * l1 * l2
            && self.det().is_finite()
    }

    /// The vertices mapped: positions moved, bulges kept, negated by a
    /// mirroring map (it turns every arc the other way). A map that is no
    /// similarity would make arcs elliptic, so the caller flattens them
    /// first; this flattens any that remain within `tol` (block units).
    pub fn vertices(&self, pts: Vec<Vertex>, closed: bool, tol: f64) -> Vec<Vertex> {
        if *self == Transform::ID {
            return pts;
        }
        let pts = if self.is_similarity() || !pts.iter().any(Vertex::is_arc) {
            pts
        } else {
            flatten_vertices(&pts, closed, tol)
        };
        let mirror = self.det() < 0.0;
        pts.into_iter()
            .map(|v| {
                let q = self.apply([v.x, v.y]);
                let b = if mirror && v.bulge != 0.0 {
                    -v.bulge
                } else {
                    v.bulge
                };
                Vertex::new(q[0], q[1], b)
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: P, b: P) -> bool {
        (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12
    }

    #[test]
    fn inserts_scale_rotate_and_move_about_the_base_point() {
        let t = Transform::insert([1.0, 1.0], [2.0, 2.0], [0.0, 0.0], 90.0, [10.0, 0.0], false);
        // (2, 1) is 1 right of the base; doubled, turned to point up.
        assert!(close(t.apply([2.0, 1.0]), [10.0, 2.0]));
        assert!(t.is_similarity());
        let mirrored = Transform::insert([0.0; 2], [-1.0, 1.0], [0.0; 2], 0.0, [0.0; 2], false);
        let v = mirrored.vertices(vec![Vertex::new(1.0, 0.0, 0.5)], false, 0.1);
        assert_eq!((v[0].x, v[0].bulge), (-1.0, -0.5));
        // An array cell moves along the block's rotated axes.
        let cell = Transform::insert([0.0; 2], [1.0, 1.0], [5.0, 0.0], 90.0, [0.0; 2], false);
        assert!(close(cell.apply([0.0, 0.0]), [0.0, 5.0]));
        let nested = cell.then(t);
        assert!(close(nested.apply([0.0, 0.0]), t.apply([0.0, 5.0])));
    }

    #[test]
    fn a_stretching_insert_flattens_arcs() {
        let t = Transform::insert([0.0; 2], [2.0, 1.0], [0.0; 2], 0.0, [0.0; 2], false);
        assert!(!t.is_similarity());
        let half = vec![Vertex::new(1.0, 0.0, 1.0), Vertex::new(-1.0, 0.0, 0.0)];
        let v = t.vertices(half, false, 0.01);
        assert!(v.len() > 3 && v.iter().all(|q| q.bulge == 0.0));
        assert!(close([v[0].x, v[0].y], [2.0, 0.0]));
    }
}
