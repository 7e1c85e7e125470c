//! A part with an arc through every view: a 60 x 40 plate whose right end
//! is a half circle (centre `(60, 20)`, radius 20), solved with the
//! `metric-25` kit.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use super::picture::{fixture_svg, part_svg};
use super::show::print_part;
use crate::drawing::draw::{bounds, fixture_drawing, plate_outline};
use crate::drawing::hole_contacts::hole_contact_label;
use crate::drawing::outline::extent_points;
use crate::output::fields::{CountsField, HoleLoopField, UnitsName, VertexField};
use crate::output::messages::{
    test_run_msg, FixturesMsg, PartMsg, RunMsg, SolveTiming, TimingField,
};
use crate::output::reader::PartRecord;
use crate::output::scene::{scene_update, PartScene};
use fixplan_core::{
    solve, FixtureReport, Part, Point, SegmentKind, SolveResult, Status, Units, Vertex,
};
use serde_json::Value;

const CENTRE: Point = [60.0, 20.0];
const R: f64 = 20.0;

fn arc_plate() -> Vec<Vertex> {
    [
        [0.0, 0.0, 0.0],
        [60.0, 0.0, 1.0],
        [60.0, 40.0, 0.0],
        [0.0, 40.0, 0.0],
    ]
    .map(Vertex::from)
    .to_vec()
}

fn run_msg() -> RunMsg {
    test_run_msg("arcs", 1, "")
}

/// The record a run writes for `outline`, solved with the run's kit.
fn record(run: &RunMsg, id: &str, outline: Vec<Vertex>) -> PartRecord {
    holed_record(run, id, outline, Vec::new())
}

/// [`record`] of a part with holes (SPEC 9).
fn holed_record(
    run: &RunMsg,
    id: &str,
    outline: Vec<Vertex>,
    holes: Vec<Vec<Vertex>>,
) -> PartRecord {
    let part = Part {
        outline,
        holes,
        access: Vec::new(),
    };
    let result: SolveResult = solve(&part, &run.kit(), &run.params(), Units::Mm);
    PartRecord {
        part: PartMsg {
            index: 0,
            id: id.into(),
            file: None,
            status: result.status.into(),
            error: result.error.clone(),
            warnings: Vec::new(),
            units: UnitsName::Mm,
            quantity: 1.0,
            outline: part.outline.iter().map(VertexField::from).collect(),
            holes: part.holes.iter().map(HoleLoopField::from).collect(),
            access: Vec::new(),
            counts: result.counts.as_ref().map(CountsField::from),
            fixtures: result.fixtures.len(),
            best_score: result.fixtures.first().map(|f| f.score),
            timing: TimingField::from(&SolveTiming::default()),
            refine: None,
            stopped: None,
            stopped_at: None,
        },
        fixtures: FixturesMsg::of_result(id, &result),
    }
}

fn dist(a: Point, b: Point) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// The numbers after each `cmd` letter of an SVG path's data.
fn path_numbers(data: &str, cmd: char) -> Vec<Vec<f64>> {
    data.split(cmd)
        .skip(1)
        .map(|rest| {
            let end = rest
                .find(|c: char| c.is_ascii_alphabetic())
                .unwrap_or(rest.len());
            rest[..end]
                .split([',', ' '])
                .filter(|t| !t.is_empty())
                .map(|t| t.parse().unwrap())
                .collect()
        })
        .collect()
}

/// The data of the part's path (the arrow marker is a path too).
fn part_path(svg: &str) -> &str {
    let paths: Vec<&str> = svg
        .split("<path d=\"")
        .skip(1)
        .map(|rest| rest.split('"').next().unwrap())
        .filter(|d| d.contains(" A"))
        .collect();
    assert_eq!(paths.len(), 1, "{svg}");
    paths[0]
}

#[test]
fn the_arc_part_has_fixtures_touching_its_arc() {
    let run = run_msg();
    let rec = record(&run, "half-round", arc_plate());
    let r = &rec.fixtures.result();
    assert_eq!(r.status, Status::Ok, "{r:?}");
    assert!(r.segment_kinds.contains(&SegmentKind::Arc));
    let on_arc = |s: usize| r.segment_kinds[s] == SegmentKind::Arc;
    assert!(
        r.fixtures
            .iter()
            .any(|f| f.segments.iter().any(|&s| on_arc(s)) || on_arc(f.clamp.segment)),
        "no fixture touches the arc"
    );
}

#[test]
fn pictures_draw_arcs_as_svg_arcs() {
    let run = run_msg();
    let rec = record(&run, "half-round", arc_plate());
    let result = rec.fixtures.result();
    let f = &result.fixtures[0];
    for svg in [part_svg(&rec), fixture_svg(&run, &rec, f)] {
        let d = part_path(&svg);
        assert!(d.starts_with('M') && d.ends_with(" Z"), "{d}");
        // The bottom edge (60 long) scales the picture: the arc's radius
        // is a third of it, half circle (large-arc 0), bulge > 0 turning
        // clockwise on a y-down screen (sweep 0).
        let m = &path_numbers(d, 'M')[0];
        let l = &path_numbers(d, 'L')[0];
        let a = &path_numbers(d, 'A')[0];
        let k = dist([m[0], m[1]], [l[0], l[1]]) / 60.0;
        assert!((a[0] - R * k).abs() < 0.01 && a[0] == a[1], "{d}");
        assert_eq!(a[2..5], [0.0, 0.0, 0.0], "{d}");
        assert!(
            (dist([l[0], l[1]], [a[5], a[6]]) - 40.0 * k).abs() < 0.02,
            "{d}"
        );
    }
    // The part-only picture is in the part frame and wide enough for the
    // arc's far point (x = 80), not just for the vertices (x = 60).
    let svg = part_svg(&rec);
    let d = part_path(&svg);
    let (m, l) = (&path_numbers(d, 'M')[0], &path_numbers(d, 'L')[0]);
    let k = (l[0] - m[0]) / 60.0;
    let width: f64 = svg
        .split("width=\"")
        .nth(1)
        .unwrap()
        .split('"')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(m[0] + 80.0 * k < width - 20.0, "{width} {k} {m:?}");
}

#[test]
fn contacts_on_the_arc_touch_it_along_its_normal() {
    let run = run_msg();
    let rec = record(&run, "half-round", arc_plate());
    let r = &rec.fixtures.result();
    let mut on_arc = 0;
    for f in &r.fixtures {
        let d = fixture_drawing(&run.kit(), &rec.part.outline(), &[], &[], f);
        assert_eq!(d.part[1].bulge, 1.0);
        // Half circle: the posed centre is the midpoint of its ends.
        let (a, b) = (d.part[1], d.part[2]);
        let c = [(a.x + b.x) / 2.0, (a.y + b.y) / 2.0];
        let segs = [f.segments[0], f.segments[1], f.segments[2], f.clamp.segment];
        for (s, contact) in segs.iter().zip(&d.contacts) {
            if r.segment_kinds[*s] != SegmentKind::Arc {
                continue;
            }
            on_arc += 1;
            assert!((dist(contact.at, c) - R).abs() < 1e-6, "{contact:?}");
            let inward = [(c[0] - contact.at[0]) / R, (c[1] - contact.at[1]) / R];
            assert!(dist(inward, contact.normal) < 1e-6, "{contact:?}");
        }
    }
    assert!(on_arc > 0);
}

/// The scene's part entity.
fn scene_part(scene: &Value) -> &Value {
    scene["entities"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["id"] == "part")
        .unwrap()
}

/// The points of the part entity's outline line, in mm.
fn scene_outline(scene: &Value) -> Vec<Point> {
    scene_part(scene)["lines"][0]["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            [
                p["x"].as_f64().unwrap() * 1000.0,
                p["y"].as_f64().unwrap() * 1000.0,
            ]
        })
        .collect()
}

#[test]
fn the_scene_draws_arcs_as_fine_line_strips_on_the_circle() {
    let run = run_msg();
    let rec = record(&run, "half-round", arc_plate());
    let result = rec.fixtures.result();
    let f = &result.fixtures[0];
    let outline = &rec.part.outline();
    let kit = run.kit();
    let shown = |best| PartScene {
        index: 0,
        id: "half-round",
        units: Units::Mm,
        kit: &kit,
        outline,
        holes: &[],
        access: &[],
        segment_loops: &[],
        best,
    };
    let placed = scene_update(shown(Ok(f)));
    let alone = scene_update(shown(Err("none")));
    // Without a fixture the part is drawn centred on the plate.
    let middle = |b: [Point; 2]| [(b[0][0] + b[1][0]) / 2.0, (b[0][1] + b[1][1]) / 2.0];
    let plate_middle = middle(bounds(&plate_outline(&kit)).unwrap());
    let part_middle = middle(bounds(&extent_points(outline)).unwrap());
    let shifted = |p: Point| {
        [
            p[0] + plate_middle[0] - part_middle[0],
            p[1] + plate_middle[1] - part_middle[1],
        ]
    };
    let d = fixture_drawing(&kit, outline, &[], &[], f);
    let posed_centre = [
        (d.part[1].x + d.part[2].x) / 2.0,
        (d.part[1].y + d.part[2].y) / 2.0,
    ];
    for (scene, c, far) in [
        (
            placed,
            posed_centre,
            [
                (d.part[0].x + d.part[3].x) / 2.0,
                (d.part[0].y + d.part[3].y) / 2.0,
            ],
        ),
        (alone, shifted(CENTRE), shifted([0.0, 20.0])),
    ] {
        let pts = scene_outline(&serde_json::to_value(&scene).unwrap());
        // Four vertices and at least 36 chords on the half circle.
        assert!(pts.len() >= 4 + 35, "{}", pts.len());
        for p in &pts[2..pts.len() - 2] {
            assert!((dist(*p, c) - R).abs() < 1e-6, "{p:?}");
            // On the far side of the centre from the plate's left end.
            let (u, v) = ([p[0] - c[0], p[1] - c[1]], [far[0] - c[0], far[1] - c[1]]);
            assert!(u[0] * v[0] + u[1] * v[1] < 0.0, "{p:?}");
        }
    }
}

#[test]
fn show_names_arc_segments_and_their_contacts() {
    let run = run_msg();
    let rec = record(&run, "half-round", arc_plate());
    let mut out = Vec::new();
    print_part(&rec, 0, &mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    assert!(
        text.contains("arcs: outline edges 1 of 4; segments 1 of 4 (marked * below)"),
        "{text}"
    );
    assert!(
        text.contains("1*") && text.contains("on arc segment 1: centre ("),
        "{text}"
    );

    let square = [[0.0, 0.0], [60.0, 0.0], [60.0, 40.0], [0.0, 40.0]].map(Vertex::from);
    let rec = record(&run, "plate", square.to_vec());
    let mut out = Vec::new();
    print_part(&rec, 0, &mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    assert!(!text.contains("arc") && !text.contains('*'), "{text}");
}

/// The midpoint of an SVG arc `A r,r 0 large sweep x2,y2` from `(x1, y1)`,
/// by the SVG specification's conversion to centre form (implementation
/// notes, B.2.4), so that the flags are checked against their meaning.
fn svg_arc_midpoint(start: Point, radius: f64, large: bool, sweep: bool, end: Point) -> Point {
    let (hx, hy) = ((start[0] - end[0]) / 2.0, (start[1] - end[1]) / 2.0);
    let r2 = radius * radius;
    let h2 = hx * hx + hy * hy;
    let sign = if large != sweep { 1.0 } else { -1.0 };
    let coef = sign * ((r2 - h2) / h2).max(0.0).sqrt();
    let radius = radius.max(h2.sqrt());
    let c = [
        coef * hy + (start[0] + end[0]) / 2.0,
        -coef * hx + (start[1] + end[1]) / 2.0,
    ];
    let angle = |p: Point| (p[1] - c[1]).atan2(p[0] - c[0]);
    let (t1, t2) = (angle(start), angle(end));
    let tau = std::f64::consts::TAU;
    let mut dt = (t2 - t1).rem_euclid(tau);
    if !sweep {
        dt -= tau;
    }
    let t = t1 + dt / 2.0;
    [c[0] + radius * t.cos(), c[1] + radius * t.sin()]
}

/// The part-only picture of a plate whose right end has bulge `bulge`:
/// the SVG arc's midpoint is where the true arc's midpoint (`mid`, part
/// frame) lands on screen.
#[test]
fn svg_arc_flags_put_the_arc_on_the_right_side() {
    let run = run_msg();
    for (bulge, mid) in [
        (1.0, [80.0, 20.0]),
        (-2.0, [20.0, 20.0]),
        (0.25, [65.0, 20.0]),
    ] {
        let mut outline = arc_plate();
        outline[1].bulge = bulge;
        let rec = record(&run, "bulged", outline);
        let svg = part_svg(&rec);
        let d = part_path(&svg);
        let (m, l, a) = (
            &path_numbers(d, 'M')[0],
            &path_numbers(d, 'L')[0],
            &path_numbers(d, 'A')[0],
        );
        let k = (l[0] - m[0]) / 60.0;
        let want = [m[0] + mid[0] * k, m[1] - mid[1] * k];
        let got = svg_arc_midpoint([l[0], l[1]], a[0], a[3] == 1.0, a[4] == 1.0, [a[5], a[6]]);
        assert!(
            dist(got, want) < 0.05,
            "bulge {bulge}: {got:?} != {want:?} in {d}"
        );
    }
}

/// The scene as a run writes it (plate holes copied from a per-thread
/// cache) is the serialised [`scene_update`], byte for byte: with and
/// without a fixture, in two units, and again once the cache is warm.
#[test]
fn the_scene_json_is_the_serialised_scene_update() {
    use crate::output::scene::scene_json;
    let run = run_msg();
    let rec = record(&run, "half-round", arc_plate());
    let result = rec.fixtures.result();
    let f = &result.fixtures[0];
    let outline = &rec.part.outline();
    let kit = run.kit();
    let (inch, _) = fixplan_catalog::kit::builtin_kit("paper-inch").unwrap();
    for _warm in 0..2 {
        for (units, kit) in [(Units::Mm, &kit), (Units::In, &inch)] {
            for best in [Ok(f), Err("half-round: no fixture")] {
                let p = PartScene {
                    index: 7,
                    id: "half-round",
                    units,
                    kit,
                    outline,
                    holes: &[],
                    access: &[],
                    segment_loops: &[],
                    best,
                };
                let want = serde_json::to_vec(&scene_update(p)).unwrap();
                let got = scene_json(p).unwrap();
                assert_eq!(
                    String::from_utf8(got).unwrap(),
                    String::from_utf8(want).unwrap()
                );
            }
        }
    }
}

/// A part without a fixture is drawn on its plate: the plate's edge and
/// the holes around the part, the part's outline within the edge, and the
/// caption; the fixture entity is empty (it clears the previous part's).
#[test]
fn a_scene_without_a_fixture_shows_the_plate() {
    let run = run_msg();
    let kit = run.kit();
    let outline = arc_plate();
    let scene = scene_update(PartScene {
        index: 0,
        id: "half-round",
        units: Units::Mm,
        kit: &kit,
        outline: &outline,
        holes: &[],
        access: &[],
        segment_loops: &[],
        best: Err("half-round: no fixture"),
    });
    let scene = serde_json::to_value(&scene).unwrap();
    let entities = scene["entities"].as_array().unwrap();
    let ids: Vec<&str> = entities.iter().map(|e| e["id"].as_str().unwrap()).collect();
    assert_eq!(ids, ["plate", "part", "fixture"]);
    let metres = |p: &Value| [p["x"].as_f64().unwrap(), p["y"].as_f64().unwrap()];
    let edge: Vec<Point> = (entities[0]["lines"][0]["points"].as_array().unwrap())
        .iter()
        .map(metres)
        .collect();
    let want: Vec<Point> = plate_outline(&kit)
        .iter()
        .map(|p| [p[0] / 1000.0, p[1] / 1000.0])
        .collect();
    assert_eq!(edge, want);
    let holes = entities[0]["cylinders"].as_array().unwrap().len();
    assert!(
        holes > 0 && holes < (kit.cols * kit.rows) as usize,
        "{holes}"
    );
    let [lo, hi] = bounds(&edge).unwrap();
    let drawn = scene_outline(&scene);
    assert!(drawn.len() > 4);
    for p in drawn {
        let p = [p[0] / 1000.0, p[1] / 1000.0];
        assert!(
            p[0] > lo[0] && p[0] < hi[0] && p[1] > lo[1] && p[1] < hi[1],
            "{p:?}"
        );
    }
    assert_eq!(entities[1]["texts"][0]["text"], "half-round: no fixture");
    assert_eq!(entities[2]["lines"].as_array().unwrap().len(), 0);
}

/// A 60 x 40 plate with a round bore and a square window (SPEC 9).
fn holed_plate(run: &RunMsg) -> PartRecord {
    let square = [[0.0, 0.0], [60.0, 0.0], [60.0, 40.0], [0.0, 40.0]].map(Vertex::from);
    let holes = vec![
        vec![Vertex::new(10.0, 20.0, 1.0), Vertex::new(20.0, 20.0, 1.0)],
        [[35.0, 10.0], [50.0, 10.0], [50.0, 30.0], [35.0, 30.0]]
            .map(Vertex::from)
            .to_vec(),
    ];
    holed_record(run, "holed", square.to_vec(), holes)
}

/// The Foxglove scene of [`holed_plate`]'s record, as JSON, with the given
/// segment loops and best fixture.
fn holed_scene(
    run: &RunMsg,
    rec: &PartRecord,
    segment_loops: &[usize],
    best: Result<&FixtureReport, &str>,
) -> Value {
    let (kit, outline, holes) = (run.kit(), rec.part.outline(), rec.part.holes());
    serde_json::to_value(scene_update(PartScene {
        index: 0,
        id: "holed",
        units: Units::Mm,
        kit: &kit,
        outline: &outline,
        holes: &holes,
        access: &[],
        segment_loops,
        best,
    }))
    .unwrap()
}

#[test]
fn pictures_show_and_the_scene_draw_the_holes() {
    let run = run_msg();
    let rec = holed_plate(&run);
    let result = rec.fixtures.result();
    let f = &result.fixtures[0];
    for svg in [part_svg(&rec), fixture_svg(&run, &rec, f)] {
        // One region: the outline then each hole, even-odd filled, the
        // bore as two arcs.
        let region: Vec<&str> = svg
            .lines()
            .filter(|l| l.contains("fill-rule=\"evenodd\""))
            .collect();
        assert_eq!(region.len(), 1, "{svg}");
        assert_eq!(region[0].matches('M').count(), 3, "{}", region[0]);
        assert_eq!(region[0].matches(" A").count(), 2, "{}", region[0]);
    }
    let solid = record(&run, "solid", holed_plate(&run).part.outline());
    assert!(!part_svg(&solid).contains("evenodd"));
    let mut out = Vec::new();
    print_part(&rec, 0, &mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    assert!(
        text.contains("holes: 2 (edges of hole 0, 1, ...: 2, 4)"),
        "{text}"
    );
    for best in [Ok(f), Err("none")] {
        let scene = holed_scene(&run, &rec, &result.segment_loops, best);
        let lines = scene_part(&scene)["lines"].as_array().unwrap();
        assert_eq!(lines.len(), 3, "outline and two holes");
        // The window is a line loop of its four corners.
        assert_eq!(lines[2]["points"].as_array().unwrap().len(), 4);
    }
}

/// A contact on a hole's wall is named by its hole (SPEC 9.6's
/// `segment_loops`) in the picture's caption, in `show` and in the scene.
#[test]
fn contacts_on_a_hole_wall_are_labelled_with_the_hole() {
    let run = run_msg();
    let mut rec = holed_plate(&run);
    // Core numbers the loops: the bore (radius 5) is too small for a
    // locator and offers no segment; the window (hole 1) offers some.
    let loops = rec.fixtures.segment_loops.clone();
    assert_eq!(loops.len(), rec.fixtures.segment_kinds.len());
    assert!(loops.contains(&2) && !loops.contains(&1), "{loops:?}");
    // Put L2 of the best fixture on hole 3's wall, everything else on the
    // outline, and every view says so.
    let f = rec.fixtures.result().fixtures[0].clone();
    let mut moved = vec![0; loops.len()];
    moved[f.segments[1]] = 4;
    rec.fixtures.segment_loops = moved.clone();
    assert!(hole_contact_label(&moved, &f)
        .unwrap()
        .starts_with("L2 in hole 3"));
    assert!(fixture_svg(&run, &rec, &f).contains("L2 in hole 3"));
    let mut out = Vec::new();
    print_part(&rec, 1, &mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    assert!(text.contains("L2 in hole 3"), "{text}");
    let scene = holed_scene(&run, &rec, &moved, Ok(&f));
    let label = scene_part(&scene)["texts"][0]["text"].as_str().unwrap();
    assert!(label.contains("L2 in hole 3"), "{label}");
    // No label for a fixture all on the outline.
    assert_eq!(hole_contact_label(&vec![0; loops.len()], &f), None);
}
