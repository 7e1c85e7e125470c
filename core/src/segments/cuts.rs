//! Where a grown edge crosses the level curves at a distance from an
//! edge (SPEC 8.2): circles about end points, lines parallel to straight
//! edges, circles concentric with arcs. Between two consecutive crossings
//! the distance to that edge stays on one side of the level, which is what
//! lets the segment code test one point per piece.

use super::segment::Feature;
use crate::geometry::arc::{circle_circle, GrownArc};
use crate::geometry::{cross, v2, V2};
use crate::outline::Edge;

/// Parameters where the grown edge `f` crosses the curves at distance
/// `rho` from edge `edge` (in no particular order).
pub(super) fn edge_cuts(f: &Feature, edge: &Edge, rho: f64, cuts: &mut Vec<f64>) {
    far_edge_cuts(f, edge, rho, cuts);
    circle_cuts(f, edge.start(), rho, cuts);
    circle_cuts(f, edge.end(), rho, cuts);
}

/// The crossings of [`edge_cuts`] that can lie on a grown edge farther than
/// `rho` from `edge`: those with the lines along a straight edge and the
/// circles about an arc's centre, which run on past the edge. The circles
/// about its end points cannot reach the grown edge; their crossings with
/// its line or circle fall outside the grown edge and would be dropped.
pub(super) fn far_edge_cuts(f: &Feature, edge: &Edge, rho: f64, cuts: &mut Vec<f64>) {
    match edge {
        Edge::Line { a, b } => {
            let d = b - a;
            let len = d.norm();
            if len > 0.0 {
                let m = v2(-d.y, d.x) / len;
                line_cuts(f, a + m * rho, d, cuts);
                line_cuts(f, a - m * rho, d, cuts);
            }
        }
        Edge::Arc(arc) => {
            circle_cuts(f, arc.center, arc.radius + rho, cuts);
            if arc.radius - rho > 0.0 {
                circle_cuts(f, arc.center, arc.radius - rho, cuts);
            }
        }
    }
}

/// Parameters where `f` meets the circle `(c, rad)`.
fn circle_cuts(f: &Feature, c: V2, rad: f64, cuts: &mut Vec<f64>) {
    match f {
        Feature::Line(l) => {
            let w = l.origin - c;
            let bh = l.u.dot(&w);
            let disc = bh * bh - (w.norm_squared() - rad * rad);
            if disc >= 0.0 {
                let sq = disc.sqrt();
                cuts.extend([-bh - sq, -bh + sq]);
            }
        }
        Feature::Arc(a) => {
            for &p in circle_circle(a.center, a.radius, c, rad, 0.0).as_slice() {
                cuts.push(a.param_of(p));
            }
        }
    }
}

/// Parameters where `f` meets the line through `p` along `d`.
fn line_cuts(f: &Feature, p: V2, d: V2, cuts: &mut Vec<f64>) {
    match f {
        Feature::Line(l) => {
            let den = cross(l.u, d);
            if den != 0.0 {
                cuts.push(cross(p - l.origin, d) / den);
            }
        }
        Feature::Arc(a) => line_circle_cuts(a, p, d, cuts),
    }
}

fn line_circle_cuts(a: &GrownArc, p: V2, d: V2, cuts: &mut Vec<f64>) {
    let len2 = d.norm_squared();
    if len2 == 0.0 {
        return;
    }
    let t0 = (a.center - p).dot(&d) / len2;
    let foot = p + d * t0;
    let h2 = (foot - a.center).norm_squared();
    let w2 = a.radius * a.radius - h2;
    if w2 < 0.0 {
        return;
    }
    let w = (w2 / len2).sqrt();
    for t in [t0 - w, t0 + w] {
        cuts.push(a.param_of(p + d * t));
    }
}
