//! Validation and normalisation of input polygons (SPEC 1 and 7).
//!
//! Errors carry the offending indices and coordinates so that a catalogue
//! report can say "edge 4 crosses edge 9 at (12.5, 3.0)".

use crate::geometry::{cross, orientation, signed_area, v2, V2};
use thiserror::Error;

/// Which of SPEC 1's conditions a polygon breaks, and where; indices are
/// the input's own (before CCW normalisation) so the user finds them.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum PolygonError {
    /// Fewer than 3 vertices (the count).
    #[error("has {0} vertices; a polygon needs at least 3")]
    TooFewVertices(usize),
    /// A NaN or infinite coordinate.
    #[error("vertex {index} has a non-finite coordinate")]
    NonFinite {
        /// The vertex.
        index: usize,
    },
    /// Two vertices coincide.
    #[error("vertex {first} and vertex {second} are the same point ({x}, {y})")]
    RepeatedVertex {
        /// The earlier vertex.
        first: usize,
        /// The later vertex.
        second: usize,
        /// Their x.
        x: f64,
        /// Their y.
        y: f64,
    },
    /// Two edges touch or cross (adjacent edges: fold back on each other).
    #[error("edge {first} crosses edge {second} at ({x}, {y})")]
    SelfIntersection {
        /// The earlier edge.
        first: usize,
        /// The later edge.
        second: usize,
        /// x of a point they share.
        x: f64,
        /// y of a point they share.
        y: f64,
    },
    /// No inside: no contact normal or metric is defined.
    #[error("has zero area")]
    ZeroArea,
}

/// Checks SPEC 1's conditions on a polygon and returns it counter-clockwise
/// (a clockwise `(v0, ..., v(n-1))` becomes `(v0, v(n-1), ..., v1)`).
pub fn validate_polygon(points: &[[f64; 2]]) -> Result<Vec<V2>, PolygonError> {
    let n = points.len();
    if n < 3 {
        return Err(PolygonError::TooFewVertices(n));
    }
    if let Some(index) = points
        .iter()
        .position(|p| !p[0].is_finite() || !p[1].is_finite())
    {
        return Err(PolygonError::NonFinite { index });
    }
    let pts: Vec<V2> = points.iter().map(|p| v2(p[0], p[1])).collect();
    for i in 0..n {
        for j in i + 1..n {
            if pts[i] == pts[j] {
                return Err(PolygonError::RepeatedVertex {
                    first: i,
                    second: j,
                    x: pts[i].x,
                    y: pts[i].y,
                });
            }
        }
    }
    if let Some((i, j, p)) = first_self_intersection(&pts) {
        return Err(PolygonError::SelfIntersection {
            first: i,
            second: j,
            x: p.x,
            y: p.y,
        });
    }
    let area = signed_area(&pts);
    let scale = pts
        .iter()
        .fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()));
    if area.abs() <= 1e-12 * scale * scale.max(1e-300) || area == 0.0 {
        return Err(PolygonError::ZeroArea);
    }
    Ok(if area < 0.0 { ccw_of_cw(&pts) } else { pts })
}

/// SPEC's normalisation of a clockwise list: keep `v0`, reverse the rest.
pub fn ccw_of_cw(pts: &[V2]) -> Vec<V2> {
    let mut out = Vec::with_capacity(pts.len());
    out.push(pts[0]);
    out.extend(pts[1..].iter().rev());
    out
}

/// First pair of non-adjacent edges that touch, or adjacent edges that
/// overlap (fold back on each other), with a point they share.
pub fn first_self_intersection(pts: &[V2]) -> Option<(usize, usize, V2)> {
    let n = pts.len();
    for i in 0..n {
        let (a, b) = (pts[i], pts[(i + 1) % n]);
        for j in i + 1..n {
            let (c, d) = (pts[j], pts[(j + 1) % n]);
            let adjacent = j == i + 1 || (i == 0 && j == n - 1);
            if adjacent {
                // Adjacent edges share one vertex; they intersect wrongly only
                // when they fold back over each other (collinear, opposite).
                let (shared, other_a, other_b) = if j == i + 1 { (b, a, d) } else { (a, b, c) };
                let u = other_a - shared;
                let w = other_b - shared;
                if orientation(shared, other_a, other_b) == 0.0 && u.dot(&w) > 0.0 {
                    let p = if u.norm_squared() < w.norm_squared() {
                        other_a
                    } else {
                        other_b
                    };
                    return Some((i, j, p));
                }
                continue;
            }
            if let Some(p) = intersection_point(a, b, c, d) {
                return Some((i, j, p));
            }
        }
    }
    None
}

/// A point shared by closed segments `[a,b]` and `[c,d]`, if any.
fn intersection_point(a: V2, b: V2, c: V2, d: V2) -> Option<V2> {
    if !crate::geometry::segments_intersect(a, b, c, d) {
        return None;
    }
    let r = b - a;
    let s = d - c;
    let den = cross(r, s);
    if den != 0.0 {
        let t = cross(c - a, s) / den;
        return Some(a + r * t.clamp(0.0, 1.0));
    }
    // Collinear overlap: report an endpoint that lies on the other segment.
    for p in [c, d, a, b] {
        if crate::geometry::point_segment_dist2(p, a, b) == 0.0
            && crate::geometry::point_segment_dist2(p, c, d) == 0.0
        {
            return Some(p);
        }
    }
    Some(a)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clockwise_is_normalised_keeping_v0() {
        let cw = [[0., 0.], [0., 1.], [1., 1.], [1., 0.]];
        let ccw = validate_polygon(&cw).unwrap();
        assert_eq!(ccw, vec![v2(0., 0.), v2(1., 0.), v2(1., 1.), v2(0., 1.)]);
    }

    #[test]
    fn fold_back_is_decided_exactly() {
        // `a` and `b` lie beyond `s` in nearly one direction: floats put
        // the three on one line (cross product 0), exactly they are not
        // (-3e-16), so edges 0 and 1 do not fold back over each other.
        let (a, s, b) = (
            v2(3.2552814678154287, 7.424325672893026),
            v2(1.772112589385827, 5.844608707784413),
            v2(3.348228321856763, 7.523322978134513),
        );
        assert_eq!(cross(a - s, b - s), 0.0);
        let c = v2(-4.0, 12.0);
        assert!(!matches!(
            first_self_intersection(&[a, s, b, c]),
            Some((0, 1, _))
        ));
        // An exact fold-back is still one.
        let folded = [v2(0., 0.), v2(2., 0.), v2(1., 0.), v2(1., 5.)];
        assert!(matches!(first_self_intersection(&folded), Some((0, 1, _))));
    }

    #[test]
    fn errors_name_the_place() {
        assert_eq!(
            validate_polygon(&[[0., 0.], [1., 0.]]),
            Err(PolygonError::TooFewVertices(2))
        );
        assert_eq!(
            validate_polygon(&[[0., 0.], [f64::NAN, 0.], [1., 1.]]),
            Err(PolygonError::NonFinite { index: 1 })
        );
        let bow = [[0., 0.], [2., 2.], [2., 0.], [0., 2.]];
        let e = validate_polygon(&bow).unwrap_err();
        assert_eq!(
            e,
            PolygonError::SelfIntersection {
                first: 0,
                second: 2,
                x: 1.0,
                y: 1.0
            }
        );
        assert_eq!(e.to_string(), "edge 0 crosses edge 2 at (1, 1)");
        assert!(matches!(
            validate_polygon(&[[0., 0.], [1., 0.], [2., 0.]]),
            Err(PolygonError::SelfIntersection { .. }) | Err(PolygonError::ZeroArea)
        ));
        assert!(matches!(
            validate_polygon(&[[0., 0.], [1., 0.], [1., 1.], [1., 0.]]),
            Err(PolygonError::RepeatedVertex {
                first: 1,
                second: 3,
                ..
            })
        ));
    }
}
