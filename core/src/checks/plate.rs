//! Does a fixture fit on the plate, and where does it go (SPEC 4 and 5).

use crate::geometry::rot90i;
use crate::input::Pattern;

/// Where every module goes: hole `[column, row]` on the plate.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Placement {
    /// Quarter turns applied to the canonical frame (0 or 1).
    pub rotation: u8,
    /// Lattice translation applied after the rotation.
    pub offset: [i64; 2],
}

impl Placement {
    /// The plate hole under canonical lattice point `p`.
    pub fn hole(&self, p: [i64; 2]) -> [i64; 2] {
        let q = rot90i(self.rotation, p);
        [q[0] + self.offset[0], q[1] + self.offset[1]]
    }
}

/// The placement of the lattice points `pts` (canonical frame, `pts[0]` on a
/// dowel hole) on a `cols x rows` plate, trying rotation 0 then 90 degrees;
/// among valid translations the most centred one, so that the picture and
/// the shop floor agree on one answer.
pub fn fit(pts: &[[i64; 2]], cols: i64, rows: i64, pattern: Pattern) -> Option<Placement> {
    for rotation in 0..2u8 {
        let mut lo = [i64::MAX; 2];
        let mut hi = [i64::MIN; 2];
        for &p in pts {
            let q = rot90i(rotation, p);
            for k in 0..2 {
                lo[k] = lo[k].min(q[k]);
                hi[k] = hi[k].max(q[k]);
            }
        }
        let slack = [(cols - 1) - (hi[0] - lo[0]), (rows - 1) - (hi[1] - lo[1])];
        if slack[0] < 0 || slack[1] < 0 {
            continue;
        }
        let mut off = [-lo[0] + slack[0] / 2, -lo[1] + slack[1] / 2];
        if pattern == Pattern::Alternating && (off[0] + off[1]).rem_euclid(2) != 0 {
            // Move one step along an axis that has room (keeps dowel holes on
            // dowel holes); with no room either way this rotation fails.
            let mut fixed = false;
            for k in [1usize, 0] {
                if slack[k] > 0 {
                    let max_off = -lo[k] + slack[k];
                    off[k] += if off[k] < max_off { 1 } else { -1 };
                    fixed = true;
                    break;
                }
            }
            if !fixed {
                continue;
            }
        }
        return Some(Placement {
            rotation,
            offset: off,
        });
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fits_within_and_respects_parity() {
        let pts = [[0, 0], [3, 1], [-1, 4]];
        let p = fit(&pts, 18, 18, Pattern::Alternating).unwrap();
        for q in pts {
            let h = p.hole(q);
            assert!((0..18).contains(&h[0]) && (0..18).contains(&h[1]));
        }
        assert_eq!((p.hole([0, 0])[0] + p.hole([0, 0])[1]) % 2, 0);
    }

    #[test]
    fn rotates_when_needed_and_fails_when_too_big() {
        // 5 wide, 2 high: does not fit a 3 x 6 plate unrotated, fits rotated.
        let pts = [[0, 0], [4, 0], [4, 1]];
        let p = fit(&pts, 3, 6, Pattern::Square).unwrap();
        assert_eq!(p.rotation, 1);
        assert!(fit(&pts, 3, 4, Pattern::Square).is_none());
    }

    #[test]
    fn exact_fit_with_wrong_parity_fails_on_alternating() {
        // Exactly 2 x 2 holes. Unrotated the only translation is (0, 1), odd,
        // with no room to fix it; rotated by 90 degrees it is (0, 0).
        let pts = [[0, 0], [1, 0], [0, -1]];
        assert_eq!(fit(&pts, 2, 2, Pattern::Alternating).unwrap().rotation, 1);
        assert!(fit(&pts, 2, 2, Pattern::Square).is_some());
    }
}
