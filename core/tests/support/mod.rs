//! Shared test support: kits, shapes, random polygons and the brute-force
//! enumerator that the pruned enumeration must equal.
#![allow(dead_code)]

use fixplan_core::admissibility::Scratch;
use fixplan_core::clamp::Accumulator;
use fixplan_core::combinations::combinations_in;
use fixplan_core::geometry::v2;
use fixplan_core::input::{Clamp, HoleKind, Kit, MountHole, Params, Part, Pattern, Units};
use fixplan_core::{prepare, PartialResult, PreparedPart};

/// The paper-like kit in lattice units (spacing 1): 0.25 locators, toggle clamp.
pub fn kit(pattern: Pattern) -> Kit {
    let s = 1.0 / 0.75;
    let sc = |p: &[[f64; 2]]| p.iter().map(|q| [q[0] * s, q[1] * s]).collect::<Vec<_>>();
    Kit {
        spacing: 1.0,
        cols: 18,
        rows: 18,
        pattern,
        locator_radius: 0.25 * s,
        clamp: Clamp {
            mount_holes: vec![
                MountHole {
                    offset: [0, 0],
                    kind: HoleKind::Dowel,
                },
                MountHole {
                    offset: [1, 0],
                    kind: HoleKind::Tapped,
                },
            ],
            axis_offset: 0.0,
            travel: [1.5 * s, 2.75 * s],
            body: sc(&[[-0.4, -0.4], [1.2, -0.4], [1.2, 0.4], [-0.4, 0.4]]),
            plunger: sc(&[[-2.5, -0.12], [-0.25, -0.12], [-0.25, 0.12], [-2.5, 0.12]]),
        },
    }
}

pub fn params(max_angle: f64, grid_step: u32) -> Params {
    Params {
        max_clamp_angle_deg: max_angle,
        edge_trim: Some(0.05),
        min_clearance: Some(0.05),
        grid_step,
        top_k: 0,
        wrenches: None,
    }
}

pub fn part(outline: &[[f64; 2]], access: &[Vec<[f64; 2]>]) -> Part {
    Part {
        outline: outline.iter().map(|&p| p.into()).collect(),
        access: access.to_vec(),
    }
}

pub fn prep(p: &Part, k: &Kit, pr: &Params) -> PreparedPart {
    prepare(p, k, pr, Units::Mm).expect("valid test input")
}

/// Star-shaped polygon around `centre`: always simple.
pub fn star(centre: [f64; 2], angles: &[f64], radii: &[f64]) -> Vec<[f64; 2]> {
    let mut a: Vec<(f64, f64)> = angles.iter().copied().zip(radii.iter().copied()).collect();
    a.sort_by(|x, y| x.0.total_cmp(&y.0));
    a.dedup_by(|x, y| (x.0 - y.0).abs() < 0.05);
    a.iter()
        .map(|&(t, r)| [centre[0] + r * t.cos(), centre[1] + r * t.sin()])
        .collect()
}

pub fn l_shape() -> Vec<[f64; 2]> {
    vec![
        [0., 0.],
        [4.3, 0.],
        [4.3, 1.7],
        [1.6, 1.7],
        [1.6, 4.1],
        [0., 4.1],
    ]
}

pub fn t_shape() -> Vec<[f64; 2]> {
    vec![
        [1.9, 0.],
        [3.3, 0.],
        [3.3, 3.],
        [5.2, 3.],
        [5.2, 4.4],
        [0., 4.4],
        [0., 3.],
        [1.9, 3.],
    ]
}

pub fn notched() -> Vec<[f64; 2]> {
    vec![
        [0., 0.],
        [2.1, 0.],
        [2.1, 0.9],
        [2.9, 0.9],
        [2.9, 0.],
        [5.0, 0.],
        [5.0, 3.2],
        [3.4, 3.6],
        [0., 3.2],
    ]
}

/// No pruning: every canonical `L2` and every `L3` within the grown part's
/// diameter, for every combination.
pub fn brute_force(p: &PreparedPart) -> PartialResult {
    // The part lies in its box (arcs included) and every segment within
    // the locator radius of the part.
    let b = p.outline().aabb();
    let pts = [b.min, b.max, v2(b.min.x, b.max.y), v2(b.max.x, b.min.y)];
    let mut diam: f64 = 0.0;
    for a in &pts {
        for b in &pts {
            diam = diam.max((a - b).norm());
        }
    }
    let diam = diam + 2.0 * p.locator_radius() + 1.0;
    let d = diam.ceil() as i64;
    let mut acc = Accumulator::new(0);
    let mut scratch = Scratch::default();
    let n = p.segments().len();
    for (_, combo) in combinations_in(n, 0..u64::MAX) {
        acc.counts.combinations += 1;
        for i in 1..=d {
            for j in 0..=d {
                let l2 = [i, j];
                if ((i * i + j * j) as f64) > diam * diam || !p.locator_point_allowed(l2) {
                    continue;
                }
                for x in -d..=d {
                    for y in -d..=d {
                        let l3 = [x, y];
                        if ((x * x + y * y) as f64) > diam * diam || !p.locator_point_allowed(l3) {
                            continue;
                        }
                        p.setups_for_locators(combo, l2, l3, |s| {
                            p.process_setup(s, &mut acc, &mut scratch)
                        });
                    }
                }
            }
        }
    }
    acc.counts.segments = n as u64;
    let count = p.combination_count();
    PartialResult {
        range: 0..count,
        counts: acc.counts,
        fixtures: acc.top.into_sorted(),
    }
}
