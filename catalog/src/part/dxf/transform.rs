//! The placement of a block's entities by the INSERT that references it:
//! an [`Affine`] map (the readers' one type of map), composed through
//! nested blocks.

use super::super::outline::{flatten_vertices, Affine, P};
use fixplan_core::Vertex;

/// The map of an INSERT (and of one cell of a MINSERT array): the block's
/// base point to the origin, scaled, moved by the cell's offset along the
/// block's axes, rotated by `rotation_deg`, moved to `location`, then
/// mirrored in x when the insert's extrusion is (0, 0, -1) (`flip`).
pub(super) fn insert(
    base: P,
    scale: [f64; 2],
    offset: P,
    rotation_deg: f64,
    location: P,
    flip: bool,
) -> Affine {
    let (s, c) = rotation_deg.to_radians().sin_cos();
    let [sx, sy] = scale;
    // R S, and R (offset - S base) + location.
    let tx = offset[0] - sx * base[0];
    let ty = offset[1] - sy * base[1];
    let mut m = [
        c * sx,
        s * sx,
        -s * sy,
        c * sy,
        c * tx - s * ty + location[0],
        s * tx + c * ty + location[1],
    ];
    if flip {
        m[0] = -m[0];
        m[2] = -m[2];
        m[4] = -m[4];
    }
    Affine(m)
}

/// A block's loop or piece placed by `xf`. Arcs stay arcs under a
/// similarity; under a stretching map they would be elliptic, so they are
/// flattened first, within `tol` (block units).
pub(super) fn place(xf: Affine, pts: Vec<Vertex>, closed: bool, tol: f64) -> Vec<Vertex> {
    if xf == Affine::ID {
        return pts;
    }
    let pts = if xf.is_similarity() || !pts.iter().any(Vertex::is_arc) {
        pts
    } else {
        flatten_vertices(&pts, closed, tol)
    };
    xf.vertices(pts)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: P, b: P) -> bool {
        (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12
    }

    #[test]
    fn inserts_scale_rotate_and_move_about_the_base_point() {
        let t = insert([1.0, 1.0], [2.0, 2.0], [0.0, 0.0], 90.0, [10.0, 0.0], false);
        // (2, 1) is 1 right of the base; doubled, turned to point up.
        assert!(close(t.apply([2.0, 1.0]), [10.0, 2.0]));
        assert!(t.is_similarity());
        let mirrored = insert([0.0; 2], [-1.0, 1.0], [0.0; 2], 0.0, [0.0; 2], false);
        let v = place(mirrored, vec![Vertex::new(1.0, 0.0, 0.5)], false, 0.1);
        assert_eq!((v[0].x, v[0].bulge), (-1.0, -0.5));
        // An array cell moves along the block's rotated axes.
        let cell = insert([0.0; 2], [1.0, 1.0], [5.0, 0.0], 90.0, [0.0; 2], false);
        assert!(close(cell.apply([0.0, 0.0]), [0.0, 5.0]));
        let nested = t.mul(cell);
        assert!(close(nested.apply([0.0, 0.0]), t.apply([0.0, 5.0])));
    }

    #[test]
    fn a_stretching_insert_flattens_arcs() {
        let t = insert([0.0; 2], [2.0, 1.0], [0.0; 2], 0.0, [0.0; 2], false);
        assert!(!t.is_similarity());
        let half = vec![Vertex::new(1.0, 0.0, 1.0), Vertex::new(-1.0, 0.0, 0.0)];
        let v = place(t, half, false, 0.01);
        assert!(v.len() > 3 && v.iter().all(|q| q.bulge == 0.0));
        assert!(close([v[0].x, v[0].y], [2.0, 0.0]));
    }
}
