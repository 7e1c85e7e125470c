//! DXF drawings as CAD programs write them: splines, blocks placed by
//! INSERT (nested, mirrored, arrays), zero-length and repeated entities,
//! holes on the chords of round ends, open loops that are gaps and open
//! loops that are not, sheets of parts, layer selection and the reader's
//! limits. Files are written here, in R12 and R2000 forms where they
//! differ.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

mod common;
use common::*;
use fixplan_catalog::{
    load_catalog, load_catalog_with, parse_part, Catalog, Format, HoleMode, LoadOptions,
    ReadOptions,
};
use fixplan_core::parts::mass_properties;
use fixplan_core::Units;

/// Group code/value pairs; values are anything printable.
fn ent(pairs: &[(i32, &dyn std::fmt::Display)]) -> String {
    pairs
        .iter()
        .map(|(c, v)| format!("{c:>3}\n{v}\n"))
        .collect()
}

fn line_e(layer: &str, a: [f64; 2], b: [f64; 2]) -> String {
    ent(&[
        (0, &"LINE"),
        (8, &layer),
        (10, &a[0]),
        (20, &a[1]),
        (11, &b[0]),
        (21, &b[1]),
    ])
}

/// A closed LWPOLYLINE of `[x, y, bulge]` vertices (R2000).
fn lwpoly(layer: &str, vertices: &[[f64; 3]]) -> String {
    let mut s = ent(&[
        (0, &"LWPOLYLINE"),
        (100, &"AcDbEntity"),
        (8, &layer),
        (100, &"AcDbPolyline"),
        (90, &vertices.len()),
        (70, &1),
    ]);
    for p in vertices {
        s += &ent(&[(10, &p[0]), (20, &p[1]), (42, &p[2])]);
    }
    s
}

/// A closed R12 POLYLINE of straight edges.
fn r12_poly(layer: &str, points: &[[f64; 2]]) -> String {
    let mut s = ent(&[(0, &"POLYLINE"), (8, &layer), (66, &1), (70, &1)]);
    for p in points {
        s += &ent(&[(0, &"VERTEX"), (8, &layer), (10, &p[0]), (20, &p[1])]);
    }
    s + &ent(&[(0, &"SEQEND"), (8, &layer)])
}

fn circle_e(layer: &str, centre: [f64; 2], radius: f64) -> String {
    ent(&[
        (0, &"CIRCLE"),
        (8, &layer),
        (10, &centre[0]),
        (20, &centre[1]),
        (40, &radius),
    ])
}

/// An INSERT: block, insertion point, x/y scale, rotation (degrees).
fn insert_e(layer: &str, block: &str, at: [f64; 2], scale: [f64; 2], rot: f64) -> String {
    ent(&[
        (0, &"INSERT"),
        (8, &layer),
        (2, &block),
        (10, &at[0]),
        (20, &at[1]),
        (41, &scale[0]),
        (42, &scale[1]),
        (50, &rot),
    ])
}

fn block(name: &str, base: [f64; 2], body: &str) -> String {
    ent(&[
        (0, &"BLOCK"),
        (8, &"0"),
        (2, &name),
        (70, &0),
        (10, &base[0]),
        (20, &base[1]),
        (3, &name),
    ]) + body
        + &ent(&[(0, &"ENDBLK"), (8, &"0")])
}

/// A whole file: R2000 header (`$ACADVER` AC1015, `$INSUNITS` mm) unless
/// `r12`, then blocks and entities.
fn drawing(r12: bool, blocks: &str, entities: &str) -> String {
    let mut s = String::new();
    if !r12 {
        s += &ent(&[
            (0, &"SECTION"),
            (2, &"HEADER"),
            (9, &"$ACADVER"),
            (1, &"AC1015"),
            (9, &"$INSUNITS"),
            (70, &4),
            (0, &"ENDSEC"),
        ]);
    }
    if !blocks.is_empty() {
        s += &ent(&[(0, &"SECTION"), (2, &"BLOCKS")]);
        s += blocks;
        s += &ent(&[(0, &"ENDSEC")]);
    }
    s += &ent(&[(0, &"SECTION"), (2, &"ENTITIES")]);
    s += entities;
    s + &ent(&[(0, &"ENDSEC"), (0, &"EOF")])
}

fn square_lines(layer: &str, x: f64, y: f64, side: f64) -> String {
    let c = [[x, y], [x + side, y], [x + side, y + side], [x, y + side]];
    (0..4)
        .map(|i| line_e(layer, c[i], c[(i + 1) % 4]))
        .collect()
}

fn read(text: &str) -> Result<(fixplan_core::Part, Vec<String>), String> {
    parse_part(text.as_bytes(), Format::Dxf, &opts_mm()).map_err(|e| e.to_string())
}

fn area_of(part: &fixplan_core::Part) -> f64 {
    mass_properties(&part.outline).area.abs()
}

fn vertex_box(part: &fixplan_core::Part) -> [f64; 4] {
    let pts: Vec<[f64; 2]> = part.outline.iter().map(|v| [v.x, v.y]).collect();
    bbox(&pts)
}

/// A quadratic spline from (20, 20) over (10, 30) to (0, 20), the top of a
/// 20 mm square drawn with LINEs.
fn spline_top(weights: &str) -> String {
    let mut s = ent(&[
        (0, &"SPLINE"),
        (5, &"2A"),
        (100, &"AcDbEntity"),
        (8, &"0"),
        (100, &"AcDbSpline"),
        (70, &8),
        (71, &2),
        (72, &6),
        (73, &3),
        (74, &0),
    ]);
    for k in [0, 0, 0, 1, 1, 1] {
        s += &ent(&[(40, &k)]);
    }
    s += weights;
    for p in [[20.0, 20.0], [10.0, 30.0], [0.0, 20.0]] {
        s += &ent(&[(10, &p[0]), (20, &p[1]), (30, &0)]);
    }
    s
}

fn three_sides() -> String {
    line_e("0", [0.0, 20.0], [0.0, 0.0])
        + &line_e("0", [0.0, 0.0], [20.0, 0.0])
        + &line_e("0", [20.0, 0.0], [20.0, 20.0])
}

#[test]
fn a_spline_edge_is_flattened_within_the_chord_tolerance() {
    let (p, w) = read(&drawing(false, "", &(three_sides() + &spline_top("")))).unwrap();
    // 400 for the square, 2/3 of the control triangle (100) above it.
    let a = area_of(&p);
    assert!((a - (400.0 + 200.0 / 3.0)).abs() < 0.6, "{a}");
    let b = vertex_box(&p);
    assert!(close(b[3], 25.0, 0.05), "the curve's top is 25: {b:?}");
    assert!(p.outline.len() > 10);
    assert!(w.is_empty(), "{w:?}");
    // Equal weights change nothing.
    let weighted = spline_top(&ent(&[(41, &2), (41, &2), (41, &2)]));
    let (q, _) = read(&drawing(false, "", &(three_sides() + &weighted))).unwrap();
    assert!((area_of(&q) - a).abs() < 1e-9);
}

#[test]
fn a_spline_without_control_points_is_named_and_the_loop_says_so() {
    let fit_only = ent(&[
        (0, &"SPLINE"),
        (5, &"3B"),
        (100, &"AcDbEntity"),
        (8, &"VISIBLE"),
        (100, &"AcDbSpline"),
        (70, &8),
        (71, &3),
        (74, &2),
        (11, &20),
        (21, &20),
        (31, &0),
        (11, &0),
        (21, &20),
        (31, &0),
    ]);
    let e = read(&drawing(false, "", &(three_sides() + &fit_only))).unwrap_err();
    assert!(e.contains("open loop"), "{e}");
    assert!(
        e.contains("runs into SPLINE #4 (handle 3B) on layer VISIBLE"),
        "{e}"
    );
    assert!(!e.contains("a gap"), "{e}");
}

#[test]
fn open_loops_tell_a_gap_from_a_stray_line() {
    // A 0.5 mm gap at one corner.
    let gap = line_e("0", [0.0, 0.0], [20.0, 0.0])
        + &line_e("0", [20.0, 0.0], [20.0, 20.0])
        + &line_e("0", [20.0, 20.0], [0.0, 20.0])
        + &line_e("0", [0.0, 20.0], [0.0, 0.5]);
    let e = read(&drawing(true, "", &gap)).unwrap_err();
    assert!(
        e.contains("a gap in the outline") && e.contains("0.5 mm away"),
        "{e}"
    );
    // A closed square and a centre line far from it.
    let stray = square_lines("0", 0.0, 0.0, 20.0) + &line_e("CENTER", [50.0, 0.0], [50.0, 40.0]);
    let e = read(&drawing(true, "", &stray)).unwrap_err();
    assert!(e.contains("LINE #5 on layer CENTER"), "{e}");
    assert!(
        e.contains("no other entity ends near it") && e.contains("ignore_layers"),
        "{e}"
    );
    assert!(!e.contains("a gap"), "{e}");
}

#[test]
fn zero_length_and_repeated_entities_are_dropped_with_a_warning() {
    let body = square_lines("0", 0.0, 0.0, 20.0)
        + &line_e("0", [-2.0, 2.0], [-2.0, 2.0])
        + &line_e("0", [20.0, 0.0], [0.0, 0.0])
        + &circle_e("0", [10.0, 10.0], 3.0)
        + &circle_e("0", [10.0, 10.0], 3.0);
    let (p, w) = read(&drawing(true, "", &body)).unwrap();
    assert!(close(area_of(&p), 400.0, 1e-9));
    assert!(
        w.iter()
            .any(|m| m.contains("LINE #5") && m.contains("zero length")),
        "{w:?}"
    );
    assert!(
        w.iter()
            .any(|m| m.contains("LINE #6") && m.contains("repeats LINE #1")),
        "{w:?}"
    );
    assert!(
        w.iter()
            .any(|m| m.contains("CIRCLE #8") && m.contains("repeats CIRCLE #7")),
        "{w:?}"
    );
}

#[test]
fn holes_centred_on_round_ends_are_inside_either_way_round() {
    // A link 40 between centres, ends of radius 10, holes of radius 4 on
    // the end centres; drawn along x and along y.
    for vertical in [false, true] {
        let m = |x: f64, y: f64, b: f64| if vertical { [-y, x, b] } else { [x, y, b] };
        let link = lwpoly(
            "0",
            &[
                m(0.0, -10.0, 0.0),
                m(40.0, -10.0, 1.0),
                m(40.0, 10.0, 0.0),
                m(0.0, 10.0, 1.0),
            ],
        );
        let c0 = m(0.0, 0.0, 0.0);
        let c1 = m(40.0, 0.0, 0.0);
        let body = link + &circle_e("0", [c0[0], c0[1]], 4.0) + &circle_e("0", [c1[0], c1[1]], 4.0);
        let (p, w) = read(&drawing(false, "", &body)).unwrap_or_else(|e| panic!("{vertical}: {e}"));
        let want = 800.0 + std::f64::consts::PI * 100.0;
        assert!(close(area_of(&p), want, 1e-9));
        // The two bores are the part's holes (SPEC 9), with no warning.
        assert_eq!(p.holes.len(), 2, "{w:?}");
        assert!(!w.iter().any(|m| m.contains("a loop inside")), "{w:?}");
    }
}

/// Block SQ: a 10 mm square about base point (5, 5) and a hole.
fn sq_block(r12: bool) -> String {
    let square = if r12 {
        r12_poly("0", &[[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]])
    } else {
        lwpoly(
            "0",
            &[
                [0.0, 0.0, 0.0],
                [10.0, 0.0, 0.0],
                [10.0, 10.0, 0.0],
                [0.0, 10.0, 0.0],
            ],
        )
    };
    block(
        "SQ",
        [5.0, 5.0],
        &(square + &circle_e("0", [5.0, 5.0], 2.0)),
    )
}

#[test]
fn inserts_place_their_blocks_in_r12_and_r2000_files() {
    for r12 in [true, false] {
        let body = insert_e("PART", "SQ", [100.0, 50.0], [2.0, 2.0], 90.0);
        let (p, w) = read(&drawing(r12, &sq_block(r12), &body)).unwrap();
        assert!(close(area_of(&p), 400.0, 1e-9), "r12 {r12}");
        let b = vertex_box(&p);
        for (got, want) in b.iter().zip([90.0, 40.0, 110.0, 60.0]) {
            assert!(close(*got, want, 1e-9), "r12 {r12}: {b:?}");
        }
        // The hole's first point (7, 5) is 2 right of the base: doubled
        // and turned, 4 above the insertion point. Block entities on layer
        // 0 take the INSERT's layer.
        assert_eq!(p.holes.len(), 1, "r12 {r12}: {w:?}");
        let first = p.holes[0][0];
        assert!(
            close(first.x, 100.0, 1e-9) && close(first.y, 54.0, 1e-9),
            "{first:?}"
        );
        let ignoring = ReadOptions {
            holes: HoleMode::Ignore,
            ..opts_mm()
        };
        let text = drawing(r12, &sq_block(r12), &body);
        let (_, w) = parse_part(text.as_bytes(), Format::Dxf, &ignoring).unwrap();
        let hole = w.iter().find(|m| m.contains("a loop inside")).unwrap();
        assert!(hole.contains("near (100, 54) mm"), "{hole}");
        assert!(
            hole.contains("of block SQ of INSERT #1 on layer PART"),
            "{hole}"
        );
    }
}

#[test]
fn nested_and_mirrored_inserts() {
    // A half disc right of the y axis; mirrored in x it lies left of it.
    let half = line_e("0", [0.0, 10.0], [0.0, -10.0])
        + &ent(&[
            (0, &"ARC"),
            (8, &"0"),
            (10, &0),
            (20, &0),
            (40, &10),
            (50, &-90),
            (51, &90),
        ]);
    let blocks = block("HALF", [0.0, 0.0], &half)
        + &block(
            "OUTER",
            [0.0, 0.0],
            &insert_e("0", "HALF", [0.0, 0.0], [-1.0, 1.0], 0.0),
        );
    let body = insert_e("0", "OUTER", [30.0, 0.0], [1.0, 1.0], 0.0);
    let (p, _) = read(&drawing(false, &blocks, &body)).unwrap();
    let mp = mass_properties(&p.outline);
    assert!(close(mp.area.abs(), 50.0 * std::f64::consts::PI, 1e-9));
    let cx = 30.0 - 40.0 / (3.0 * std::f64::consts::PI);
    assert!(close(mp.centroid.x, cx, 1e-9), "{}", mp.centroid.x);
    assert!(
        p.outline.iter().any(|v| v.bulge != 0.0),
        "the arc stays exact"
    );
    // A stretched insert makes the arc elliptic: flattened, area scaled.
    let body = insert_e("0", "HALF", [0.0, 0.0], [2.0, 1.0], 0.0);
    let (q, _) = read(&drawing(false, &blocks, &body)).unwrap();
    assert!(q.outline.iter().all(|v| v.bulge == 0.0));
    // Chords within 0.05 mm of a 48 mm curve lose at most about 2 mm².
    let a = area_of(&q);
    assert!(
        a < 100.0 * std::f64::consts::PI && a > 100.0 * std::f64::consts::PI - 2.0,
        "{a}"
    );
}

#[test]
fn a_block_that_contains_itself_is_over_the_depth_limit() {
    let blocks = block(
        "LOOP",
        [0.0, 0.0],
        &(square_lines("0", 0.0, 0.0, 1.0) + &insert_e("0", "LOOP", [0.0, 0.0], [1.0, 1.0], 0.0)),
    );
    let body = insert_e("0", "LOOP", [0.0, 0.0], [1.0, 1.0], 0.0);
    let e = read(&drawing(false, &blocks, &body)).unwrap_err();
    assert!(e.contains("block_depth") && e.contains("[limits]"), "{e}");
    // A missing block is named in the warnings.
    let body =
        square_lines("0", 0.0, 0.0, 5.0) + &insert_e("0", "NOPE", [0.0, 0.0], [1.0, 1.0], 0.0);
    let (_, w) = read(&drawing(false, "", &body)).unwrap();
    assert!(
        w.iter()
            .any(|m| m.contains("INSERT #5") && m.contains("block NOPE")),
        "{w:?}"
    );
}

/// A MINSERT of block SQ: 3 columns 30 apart, plus a single square below.
fn sheet_text() -> String {
    let arr = insert_e("0", "SQ", [100.0, 50.0], [1.0, 1.0], 0.0) + &ent(&[(70, &3), (44, &30)]);
    drawing(
        false,
        &sq_block(false),
        &(arr + &square_lines("0", 0.0, 0.0, 5.0)),
    )
}

#[test]
fn many_outlines_are_refused_with_the_options_named() {
    let e = read(&sheet_text()).unwrap_err();
    assert!(e.contains("more than one outline"), "{e}");
    assert!(e.contains("sheet = true") && e.contains("--sheet"), "{e}");
    assert!(
        e.contains("layers = [...]") && e.contains("ignore_layers"),
        "{e}"
    );
}

fn ids(cat: &Catalog) -> Vec<String> {
    cat.parts.iter().map(|p| p.id.clone()).collect()
}

#[test]
fn a_sheet_gives_every_outer_loop_as_a_part_in_position_order() {
    let d = temp_dir("sheet");
    write(&d, "parts/sheet.dxf", &sheet_text());
    write(
        &d,
        "catalog.toml",
        "name = \"s\"\nunits = \"mm\"\n[[part]]\nid = \"plate\"\nfile = \"parts/sheet.dxf\"\nsheet = true\nquantity = 7\n",
    );
    let cat = load_catalog(&d).unwrap();
    assert_eq!(ids(&cat), ["plate#1", "plate#2", "plate#3", "plate#4"]);
    let first = cat.parts[0].part.as_ref().unwrap();
    assert!(close(area_of(first), 25.0, 1e-9), "the low square first");
    let xs: Vec<f64> = cat.parts[1..]
        .iter()
        .map(|p| vertex_box(p.part.as_ref().unwrap())[0])
        .collect();
    assert_eq!(xs, [95.0, 125.0, 155.0]);
    assert!(cat.parts.iter().all(|p| p.quantity == 7.0));
    // Each array square keeps its own hole.
    assert_eq!(cat.parts[2].part.as_ref().unwrap().holes.len(), 1);
    // Without `sheet`, the caller's option does the same; a directory too.
    write(
        &d,
        "catalog.toml",
        "name = \"s\"\nunits = \"mm\"\n[[part]]\nid = \"plate\"\nfile = \"parts/sheet.dxf\"\n",
    );
    assert!(load_catalog(&d).unwrap().parts[0].part.is_err());
    let opts = LoadOptions {
        sheet: Some(true),
        ..LoadOptions::default()
    };
    assert_eq!(load_catalog_with(&d, &opts).unwrap().parts.len(), 4);
    let cat = load_catalog_with(&d.join("parts"), &opts).unwrap();
    assert_eq!(ids(&cat), ["sheet#1", "sheet#2", "sheet#3", "sheet#4"]);
}

#[test]
fn layers_select_the_part_in_a_drawing() {
    // A border around the part, and a dimension line.
    let body = square_lines("OUTLINE", 10.0, 10.0, 20.0)
        + &r12_poly(
            "BORDER",
            &[[0.0, 0.0], [297.0, 0.0], [297.0, 210.0], [0.0, 210.0]],
        )
        + &line_e("DIM", [10.0, 5.0], [30.0, 5.0]);
    let d = temp_dir("layers");
    write(&d, "parts/drawing.dxf", &drawing(true, "", &body));
    let manifest = |extra: &str| {
        format!("name = \"l\"\nunits = \"mm\"\n{extra}\n[[part]]\nid = \"p\"\nfile = \"parts/drawing.dxf\"\n")
    };
    write(&d, "catalog.toml", &manifest(""));
    let e = load_catalog(&d).unwrap().parts[0]
        .part
        .clone()
        .unwrap_err()
        .to_string();
    assert!(e.contains("LINE #6 on layer DIM"), "{e}");
    for extra in [
        "layers = [\"outline\"]",
        "ignore_layers = [\"BORDER\", \"dim\"]",
    ] {
        write(&d, "catalog.toml", &manifest(extra));
        let cat = load_catalog(&d).unwrap();
        let p = cat.parts[0]
            .part
            .as_ref()
            .unwrap_or_else(|e| panic!("{extra}: {e}"));
        assert!(close(area_of(p), 400.0, 1e-9), "{extra}");
        assert!(
            cat.parts[0]
                .warnings
                .iter()
                .any(|w| w.contains("were not read")),
            "{extra}"
        );
    }
    // An entry's own layers win over the catalogue's.
    write(
        &d,
        "catalog.toml",
        "name = \"l\"\nunits = \"mm\"\nlayers = [\"BORDER\"]\n[[part]]\nid = \"p\"\nfile = \"parts/drawing.dxf\"\nlayers = [\"OUTLINE\"]\n",
    );
    let cat = load_catalog(&d).unwrap();
    assert!(close(
        area_of(cat.parts[0].part.as_ref().unwrap()),
        400.0,
        1e-9
    ));
}

#[test]
fn limits_refuse_big_files_with_the_key_to_raise() {
    let d = temp_dir("limits");
    write(
        &d,
        "parts/sq.dxf",
        &drawing(true, "", &square_lines("0", 0.0, 0.0, 5.0)),
    );
    let manifest = |limits: &str| {
        format!("name = \"l\"\nunits = \"mm\"\n[limits]\n{limits}\n[[part]]\nid = \"p\"\nfile = \"parts/sq.dxf\"\n")
    };
    for (limits, key) in [
        ("entities = 3", "entities = ..."),
        ("file_bytes = 100", "file_bytes = ..."),
        ("vertices = 6", "vertices = ..."),
    ] {
        write(&d, "catalog.toml", &manifest(limits));
        let e = load_catalog(&d).unwrap().parts[0]
            .part
            .clone()
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("over the limit") && e.contains(key),
            "{limits}: {e}"
        );
    }
    write(&d, "catalog.toml", &manifest("entities = 4"));
    assert!(load_catalog(&d).unwrap().parts[0].part.is_ok());
    write(&d, "catalog.toml", &manifest("rows = 4"));
    let e = load_catalog(&d).unwrap_err().to_string();
    assert!(e.contains("unknown limit \"rows\""), "{e}");
    // The same limits apply to bytes handed to the reader.
    let mut o = ReadOptions::new(Units::Mm);
    o.limits.file_bytes = 10;
    let text = drawing(true, "", &square_lines("0", 0.0, 0.0, 5.0));
    let e = parse_part(text.as_bytes(), Format::Dxf, &o)
        .unwrap_err()
        .to_string();
    assert!(e.contains("file_bytes"), "{e}");
}

#[cfg(unix)]
#[test]
fn a_fifo_or_a_directory_is_refused_without_being_opened() {
    let d = temp_dir("fifo");
    let fifo = d.join("pipe.dxf");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    std::fs::create_dir_all(d.join("dir.dxf")).unwrap();
    write(
        &d,
        "catalog.toml",
        "name = \"f\"\nunits = \"mm\"\n[[part]]\nid = \"pipe\"\nfile = \"pipe.dxf\"\n[[part]]\nid = \"dir\"\nfile = \"dir.dxf\"\n",
    );
    // Opening the FIFO for reading would block this test for ever.
    let cat = load_catalog(&d.join("catalog.toml")).unwrap();
    if made.is_ok_and(|s| s.success()) {
        let e = cat.parts[0].part.clone().unwrap_err().to_string();
        assert!(
            e.contains("a FIFO") && e.contains("not a regular file"),
            "{e}"
        );
    }
    let e = cat.parts[1].part.clone().unwrap_err().to_string();
    assert!(e.contains("a directory"), "{e}");
}

/// In a directory catalogue too, a FIFO named like a part file is a part
/// error naming the file, not skipped in silence (nor opened: that would
/// block); the good part beside it is read.
#[cfg(unix)]
#[test]
fn a_fifo_in_a_directory_catalogue_is_a_part_error() {
    let d = temp_dir("fifo-dir");
    write(
        &d,
        "good.json",
        "{\"part\": [[0, 0], [90, 0], [90, 40], [0, 40]]}",
    );
    let fifo = d.join("pipe.json");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        eprintln!("no mkfifo here: nothing to test");
        return;
    }
    let cat = load_catalog(&d).unwrap();
    let ids: Vec<&str> = cat.parts.iter().map(|p| p.id.as_str()).collect();
    assert_eq!(ids, ["good", "pipe"]);
    assert!(cat.parts[0].part.is_ok());
    let e = cat.parts[1].part.clone().unwrap_err().to_string();
    assert!(
        e.contains("pipe.json") && e.contains("a FIFO") && e.contains("not a regular file"),
        "{e}"
    );
}
