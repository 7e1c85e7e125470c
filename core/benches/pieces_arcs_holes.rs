//! The pieces that exact arcs and holes added: the contact pose solver by
//! kind of contact triple (the closed forms of two lines and a circle, the
//! general elimination of line-circle-circle and three circles) and the
//! preparation of a plate with holes, against the same plate solid.
//! `cargo bench -p fixplan-core --bench pieces_arcs_holes`.
// criterion_main! generates an undocumented `main`.
#![allow(missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion};
use fixplan_core::parts::{solve_contact_poses, v2, Circle, Contact, Line, V2};
use fixplan_core::{prepare, Case, Part, Vertex};
use std::hint::black_box;

/// A part pose `(theta, w)` and three locators: every contact triple below
/// passes through the part-frame points of this one pose, so each solve
/// has at least one solution to find, as a real setup does.
const THETA: f64 = 0.3;
const W: [f64; 2] = [0.4, -0.2];
const LOCATORS: [[f64; 2]; 3] = [[0.0, 0.0], [3.0, 1.0], [1.0, 4.0]];

/// Where locator `index` lies in the part frame at the pose above
/// (`p = R(theta)^T L - w`, the solver's convention).
fn contact_point(index: usize) -> V2 {
    let (sin, cos) = THETA.sin_cos();
    let [x, y] = LOCATORS[index];
    v2(cos * x + sin * y - W[0], -sin * x + cos * y - W[1])
}

/// A grown line through the pose's contact `index`, of outward normal at
/// `angle`.
fn line_through(index: usize, angle: f64) -> Contact {
    let normal = v2(angle.cos(), angle.sin());
    let point = contact_point(index);
    Contact::Line(Line {
        n: normal,
        c: normal.x * point.x + normal.y * point.y,
    })
}

/// A grown circle of `radius` through the pose's contact `index`, its
/// centre in direction `angle` from it.
fn circle_through(index: usize, angle: f64, radius: f64) -> Contact {
    let point = contact_point(index);
    Contact::Circle(Circle {
        centre: v2(
            point.x + radius * angle.cos(),
            point.y + radius * angle.sin(),
        ),
        radius,
    })
}

fn contact_poses(c: &mut Criterion) {
    let locators = LOCATORS.map(|[x, y]| v2(x, y));
    let triples = [
        (
            "two_crossing_lines_and_a_circle",
            [
                line_through(0, -1.2),
                line_through(1, 0.4),
                circle_through(2, 2.0, 1.5),
            ],
        ),
        (
            "two_parallel_lines_and_a_circle",
            [
                line_through(0, -1.2),
                line_through(1, -1.2 + std::f64::consts::PI),
                circle_through(2, 2.0, 1.5),
            ],
        ),
        (
            "a_line_and_two_circles",
            [
                line_through(0, -1.2),
                circle_through(1, 0.7, 2.5),
                circle_through(2, 2.0, 1.5),
            ],
        ),
        (
            "three_circles",
            [
                circle_through(0, -2.0, 1.0),
                circle_through(1, 0.7, 2.5),
                circle_through(2, 2.0, 1.5),
            ],
        ),
    ];
    let mut group = c.benchmark_group("contact_poses");
    for (name, contacts) in triples {
        assert!(
            !solve_contact_poses(&contacts, &locators).is_empty(),
            "{name}: the pose it was built from must be found"
        );
        group.bench_function(name, |b| {
            b.iter(|| solve_contact_poses(black_box(&contacts), black_box(&locators)))
        });
    }
    group.finish();
}

/// A loop of straight edges or a circle (two half-circle bulges).
fn rectangle(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Vertex> {
    [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
        .map(|[x, y]| Vertex { x, y, bulge: 0.0 })
        .to_vec()
}

fn round_hole(cx: f64, cy: f64, radius: f64) -> Vec<Vertex> {
    vec![
        Vertex {
            x: cx - radius,
            y: cy,
            bulge: 1.0,
        },
        Vertex {
            x: cx + radius,
            y: cy,
            bulge: 1.0,
        },
    ]
}

/// A plate like the real set's keyboard plates: 200 x 80 mm with 4 x 12
/// square cutouts of 12 mm and 8 bolt holes of 1.1 mm radius, none of which
/// fits the kit's 6.35 mm locator, so they offer no segment: issue 30 asks
/// such holes to cost next to nothing.
fn switch_plate() -> Part {
    let mut holes = Vec::new();
    for row in 0..4 {
        for col in 0..12 {
            let (x, y) = (6.0 + 16.0 * col as f64, 6.0 + 18.0 * row as f64);
            holes.push(rectangle(x, y, x + 12.0, y + 12.0));
        }
    }
    for bolt in 0..8 {
        holes.push(round_hole(13.0 + 24.0 * bolt as f64, 77.0, 1.1));
    }
    Part {
        outline: rectangle(0.0, 0.0, 200.0, 80.0),
        holes,
        access: Vec::new(),
    }
}

fn prepare_with_holes(c: &mut Criterion) {
    let bracket = std::fs::read_to_string(format!(
        "{}/../examples/cases/bracket-arcs.json",
        env!("CARGO_MANIFEST_DIR")
    ))
    .expect("bench case");
    let case: Case = serde_json::from_str(&bracket).expect("valid case");
    let holed = switch_plate();
    let solid = Part {
        holes: Vec::new(),
        ..holed.clone()
    };
    let mut group = c.benchmark_group("prepare_switch_plate");
    for (name, part) in [("with_56_holes", &holed), ("solid", &solid)] {
        prepare(part, &case.kit, &case.params, case.units).expect("a valid plate");
        group.bench_function(name, |b| {
            b.iter(|| prepare(black_box(part), &case.kit, &case.params, case.units))
        });
    }
    group.finish();
}

criterion_group!(benches, contact_poses, prepare_with_holes);
criterion_main!(benches);
