//! Exact circular arcs (SPEC 8): DXF bulges (LWPOLYLINE, POLYLINE/VERTEX),
//! ARC and CIRCLE entities, SVG `A` commands with equal radii under a
//! similarity and `<circle>`, JSON and inline `[x, y, bulge]` vertices; the
//! `arcs = "flatten"` option (manifest, load options) and its errors.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

mod common;
use common::*;
use fixplan_catalog::{
    load_catalog, load_catalog_with, parse_part, ArcMode, Format, LoadOptions, ReadOptions,
};
use fixplan_core::parts::{mass_properties, Outline};
use fixplan_core::{Part, Vertex};
use std::f64::consts::{FRAC_PI_4, PI};

fn exact() -> ReadOptions {
    opts_mm()
}

fn flat() -> ReadOptions {
    flat_mm()
}

fn v(x: f64, y: f64, b: f64) -> Vertex {
    Vertex::new(x, y, b)
}

fn read(text: &str, format: Format, opts: &ReadOptions) -> Part {
    let (p, w) = parse_part(text.as_bytes(), format, opts).unwrap_or_else(|e| panic!("{e}"));
    assert!(w.is_empty(), "{w:?}");
    p
}

/// Area of the true region (arcs included), unsigned.
fn true_area(part: &Part) -> f64 {
    mass_properties(&part.outline).area.abs()
}

/// Bounding box of the true curves (a fine flattening).
fn true_bbox(part: &Part) -> [f64; 4] {
    let pts: Vec<[f64; 2]> = Outline::new(&part.outline)
        .unwrap()
        .flatten(1e-7)
        .iter()
        .map(|q| [q.x, q.y])
        .collect();
    bbox(&pts)
}

fn arcs(part: &Part) -> usize {
    part.outline.iter().filter(|v| v.is_arc()).count()
}

fn dxf(pairs: &[(i32, &str)]) -> String {
    r12(pairs)
}

#[test]
fn dxf_r12_polyline_vertex_bulges_are_exact() {
    let bytes = std::fs::read(fixture("r12_bulge_polyline.dxf")).unwrap();
    let (part, _) = parse_part(&bytes, Format::Dxf, &exact()).unwrap();
    assert_eq!(
        part.outline,
        vec![
            v(0.0, 0.0, 0.0),
            v(60.0, 0.0, 1.0),
            v(60.0, 20.0, 0.0),
            v(0.0, 20.0, -0.41421356)
        ]
    );
    // The file's bulge -0.41421356 is tan(pi/8) to 8 digits.
    let r2: f64 = 200.0;
    let want = 1200.0 + PI * 50.0 - r2 * (FRAC_PI_4 - 0.5);
    assert!(close(true_area(&part), want, 1e-5), "{}", true_area(&part));
    // Access constraints stay polygons.
    assert_eq!(part.access.len(), 1);
}

#[test]
fn dxf_lwpolyline_bulges_are_exact_and_mirrored_with_the_extrusion() {
    let body = [
        (0, "LWPOLYLINE"),
        (8, "0"),
        (90, "4"),
        (70, "1"),
        (10, "0"),
        (20, "0"),
        (10, "40"),
        (20, "0"),
        (42, "1"),
        (10, "40"),
        (20, "20"),
        (10, "0"),
        (20, "20"),
        (42, "-0.5"),
    ];
    let p = read(&dxf(&body), Format::Dxf, &exact());
    assert_eq!(
        p.outline,
        vec![
            v(0.0, 0.0, 0.0),
            v(40.0, 0.0, 1.0),
            v(40.0, 20.0, 0.0),
            v(0.0, 20.0, -0.5)
        ]
    );
    let b = true_bbox(&p);
    assert!(close(b[2], 50.0, 1e-9), "a half disc of radius 10: {b:?}");
    // Extrusion (0, 0, -1): x mirrored, so every arc turns the other way.
    let mut mirrored = body.to_vec();
    mirrored.extend([(210, "0"), (220, "0"), (230, "-1")]);
    let m = read(&dxf(&mirrored), Format::Dxf, &exact());
    assert_eq!(m.outline[1], v(-40.0, 0.0, -1.0));
    assert_eq!(m.outline[3], v(0.0, 20.0, 0.5));
    assert!(close(true_area(&m), true_area(&p), 1e-9));
    // Flattened, the same drawing is a polygon within the chord tolerance.
    let f = read(&dxf(&body), Format::Dxf, &flat());
    assert_eq!(arcs(&f), 0);
    assert!(f.outline.len() > 20);
    assert!(close(true_area(&f), true_area(&p), 2.0));
}

#[test]
fn dxf_arcs_joined_backwards_keep_exact_bulges() {
    // The first LINE runs against the arcs, so both ARCs are appended
    // reversed: clockwise half circles, bulge -1.
    let mut body = line("0", ["-30", "25"], ["30", "25"]);
    body.extend(arc_entity(["30", "0"], "25", "270", "90"));
    body.extend(line("0", ["30", "-25"], ["-30", "-25"]));
    body.extend(arc_entity(["-30", "0"], "25", "90", "270"));
    let p = read(&dxf(&body), Format::Dxf, &exact());
    assert_eq!(p.outline.len(), 4, "{:?}", p.outline);
    assert_eq!(arcs(&p), 2);
    for q in p.outline.iter().filter(|q| q.is_arc()) {
        assert!(close(q.bulge, -1.0, 1e-12), "{q:?}");
    }
    assert!(close(true_area(&p), 3000.0 + PI * 625.0, 1e-9));
    let b = true_bbox(&p);
    assert!(close(b[0], -55.0, 1e-6) && close(b[2], 55.0, 1e-6), "{b:?}");
    // Flattened: a polygon close to it (the reader's former output).
    let f = read(&dxf(&body), Format::Dxf, &flat());
    assert_eq!(arcs(&f), 0);
    assert!(f.outline.len() > 40);
}

#[test]
fn dxf_circle_is_two_half_arcs() {
    let body = [(0, "CIRCLE"), (8, "0"), (10, "5"), (20, "0"), (40, "30")];
    let p = read(&dxf(&body), Format::Dxf, &exact());
    assert_eq!(p.outline, vec![v(35.0, 0.0, 1.0), v(-25.0, 0.0, 1.0)]);
    assert!(close(true_area(&p), PI * 900.0, 1e-9));
    // A full ARC (start = end angle) and an ELLIPSE with equal axes are
    // circles too.
    let full = [
        (0, "ARC"),
        (8, "0"),
        (10, "0"),
        (20, "0"),
        (40, "10"),
        (50, "90"),
        (51, "90"),
    ];
    let a = read(&dxf(&full), Format::Dxf, &exact());
    assert_eq!(a.outline.len(), 2, "{:?}", a.outline);
    assert!(close(true_area(&a), PI * 100.0, 1e-9));
    let ellipse = [
        (0, "ELLIPSE"),
        (8, "0"),
        (10, "0"),
        (20, "0"),
        (11, "0"),
        (21, "12"),
        (40, "1"),
        (41, "0"),
        (42, "6.283185307179586"),
    ];
    let e = read(&dxf(&ellipse), Format::Dxf, &exact());
    assert_eq!(e.outline.len(), 2, "{:?}", e.outline);
    assert!(close(true_area(&e), PI * 144.0, 1e-9));
    // A true ellipse is flattened.
    let squashed: Vec<_> = ellipse
        .iter()
        .map(|&(c, s)| if c == 40 { (c, "0.5") } else { (c, s) })
        .collect();
    let s = read(&dxf(&squashed), Format::Dxf, &exact());
    assert_eq!(arcs(&s), 0);
    assert!(s.outline.len() > 20);
}

/// A file in mm (one user unit a millimetre), so that it reads without a
/// warning about its scale.
fn svg(body: &str) -> String {
    format!("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"1000mm\" height=\"1000mm\" viewBox=\"0 0 1000 1000\">{body}</svg>")
}

#[test]
fn svg_circular_arcs_are_exact_and_turn_with_the_y_flip() {
    // Sweep flag 1 is clockwise on screen (y down): counter-clockwise in
    // SVG's own coordinates, clockwise in the part's (y up).
    let p = read(
        &svg(r#"<path d="M 0 0 A 20 20 0 0 1 40 0 A 20 20 0 0 1 0 0 Z"/>"#),
        Format::Svg,
        &exact(),
    );
    assert_eq!(p.outline.len(), 2);
    for q in &p.outline {
        assert!(close(q.bulge, -1.0, 1e-12), "{q:?}");
    }
    assert!(close(true_area(&p), PI * 400.0, 1e-9));
    // A slot end drawn with a relative large-arc command.
    let g = read(
        &svg(r#"<path d="M0,0 h10 a5,5 0 1,1 0,10 h-10 z"/>"#),
        Format::Svg,
        &exact(),
    );
    assert_eq!(arcs(&g), 1);
    assert!(close(true_area(&g), 100.0 + 12.5 * PI, 1e-9));
    assert!(close(true_bbox(&g)[2], 15.0, 1e-9));
    // A minor arc: a quarter circle, bulge tan(pi / 8).
    let q = read(
        &svg(r#"<path d="M0,0 H10 A10,10 0 0,1 0,10 Z"/>"#),
        Format::Svg,
        &exact(),
    );
    let b = q.outline.iter().find(|v| v.is_arc()).unwrap().bulge;
    assert!(close(b.abs(), (PI / 8.0).tan(), 1e-12), "{b}");
    assert!(close(true_area(&q), 25.0 * PI, 1e-9));
}

#[test]
fn svg_circle_and_round_ellipse_are_two_half_arcs() {
    let p = read(
        &svg(r#"<circle cx="10" cy="10" r="5"/>"#),
        Format::Svg,
        &exact(),
    );
    assert_eq!(p.outline, vec![v(15.0, -10.0, -1.0), v(5.0, -10.0, -1.0)]);
    let e = read(
        &svg(r#"<ellipse cx="0" cy="0" rx="5" ry="5"/>"#),
        Format::Svg,
        &exact(),
    );
    assert_eq!(e.outline.len(), 2);
    let flat_e = read(
        &svg(r#"<ellipse cx="0" cy="0" rx="5" ry="3"/>"#),
        Format::Svg,
        &exact(),
    );
    assert_eq!(arcs(&flat_e), 0);
}

#[test]
fn svg_arcs_under_similarities_stay_exact() {
    let slot = r#"<path d="M0 0 h10 a5 5 0 0 1 0 10 h-10 z"/>"#;
    let plain = read(&svg(slot), Format::Svg, &exact());
    let want = 100.0 + 12.5 * PI;
    assert!(close(true_area(&plain), want, 1e-9));
    // Uniform scale, rotation, translation, and a reflection (which turns
    // the arc the other way): the area scales by 4, the arc stays convex.
    for t in [
        "scale(2) rotate(30) translate(3 4)",
        "scale(-2 2) rotate(30)",
        "matrix(0 2 2 0 5 5)",
    ] {
        let p = read(
            &svg(&format!(r#"<g transform="{t}">{slot}</g>"#)),
            Format::Svg,
            &exact(),
        );
        assert_eq!(arcs(&p), 1, "{t}");
        assert!(
            close(true_area(&p), 4.0 * want, 1e-9),
            "{t}: {}",
            true_area(&p)
        );
        // Same region as the flattened reading, within the chord error.
        let f = read(
            &svg(&format!(r#"<g transform="{t}">{slot}</g>"#)),
            Format::Svg,
            &flat(),
        );
        assert_eq!(arcs(&f), 0);
        assert!(close(true_area(&f), 4.0 * want, 1.5), "{t}");
    }
    // A non-uniform scale or a skew makes the circle an ellipse: flattened.
    for t in ["scale(2 1)", "skewX(10)"] {
        let p = read(
            &svg(&format!(r#"<g transform="{t}">{slot}</g>"#)),
            Format::Svg,
            &exact(),
        );
        assert_eq!(arcs(&p), 0, "{t}");
    }
    // An elliptical arc is flattened.
    let e = read(
        &svg(r#"<path d="M0 0 h10 a5 3 0 0 1 0 10 h-10 z"/>"#),
        Format::Svg,
        &exact(),
    );
    assert_eq!(arcs(&e), 0);
}

#[test]
fn json_reads_bulge_vertices_and_flattens_them_on_request() {
    let text = r#"{"part": [[0, 0], [40, 0, 1], [40, 20], [0, 20]]}"#;
    let p = read(text, Format::Json, &exact());
    assert_eq!(p.outline[1], v(40.0, 0.0, 1.0));
    assert!(close(true_area(&p), 800.0 + 50.0 * PI, 1e-9));
    let f = read(text, Format::Json, &flat());
    assert_eq!(arcs(&f), 0);
    assert!(f.outline.len() > 15, "{}", f.outline.len());
    let e = parse_part(br#"{"part": [[0, 0, 1, 2]]}"#, Format::Json, &exact()).unwrap_err();
    assert!(
        e.to_string()
            .contains("vertex 0 is not an [x, y] or [x, y, bulge] list"),
        "{e}"
    );
}

const ARC_MANIFEST: &str = r#"
name = "arcs"
units = "mm"
ARCS

[[part]]
id = "slot"
outline = [[0, 0], [40, 0, 1], [40, 20], [0, 20, 1]]

[[part]]
id = "boss"
file = "boss.dxf"
"#;

/// The manifest's path, and its directory (kept alive by the caller).
fn arc_catalogue(arcs_line: &str) -> (std::path::PathBuf, TempDir) {
    let d = temp_dir("arcs");
    write(
        &d,
        "boss.dxf",
        &dxf(&[(0, "CIRCLE"), (8, "0"), (10, "0"), (20, "0"), (40, "10")]),
    );
    let m = write(&d, "catalog.toml", &ARC_MANIFEST.replace("ARCS", arcs_line));
    (m, d)
}

#[test]
fn manifest_arcs_option_and_load_options_override() {
    let count = |c: &fixplan_catalog::Catalog| -> Vec<(usize, usize)> {
        c.parts
            .iter()
            .map(|p| {
                let p = p.part.as_ref().unwrap();
                (p.outline.len(), arcs(p))
            })
            .collect()
    };
    let (m, _dir) = arc_catalogue("");
    let exact_cat = load_catalog(&m).unwrap();
    assert_eq!(count(&exact_cat), [(4, 2), (2, 2)]);
    let slot = exact_cat.parts[0].part.as_ref().unwrap();
    assert!(close(true_area(slot), 800.0 + 100.0 * PI, 1e-9));
    let (m, _dir) = arc_catalogue("arcs = \"flatten\"");
    let flat_cat = load_catalog(&m).unwrap();
    for (n, a) in count(&flat_cat) {
        assert!(n > 20 && a == 0, "{n} {a}");
    }
    // The caller's choice wins over the manifest's, both ways.
    let o = LoadOptions {
        arcs: Some(ArcMode::Exact),
        ..Default::default()
    };
    assert_eq!(count(&load_catalog_with(&m, &o).unwrap()), [(4, 2), (2, 2)]);
    let (m, _dir) = arc_catalogue("arcs = \"EXACT\"");
    let o = LoadOptions {
        arcs: Some(ArcMode::Flatten),
        ..Default::default()
    };
    assert!(count(&load_catalog_with(&m, &o).unwrap())
        .iter()
        .all(|&(_, a)| a == 0));
    // The flattened circle is what the reader always made of it.
    let mut old = flat();
    old.chord_tolerance = 0.05;
    let direct = read(
        &dxf(&[(0, "CIRCLE"), (8, "0"), (10, "0"), (20, "0"), (40, "10")]),
        Format::Dxf,
        &old,
    );
    assert_eq!(flat_cat.parts[1].part.as_ref().unwrap(), &direct);
}

#[test]
fn manifest_arcs_errors_are_clear() {
    let (m, _dir) = arc_catalogue("arcs = \"chords\"");
    let e = load_catalog(&m).unwrap_err().to_string();
    assert!(
        e.contains("arcs = \"chords\": expected \"exact\"") && e.contains("\"flatten\""),
        "{e}"
    );
    let (m, _dir) = arc_catalogue("arcs = true");
    let e = load_catalog(&m).unwrap_err().to_string();
    assert!(e.contains("arcs true is not a string"), "{e}");
    assert_eq!("flatten".parse::<ArcMode>(), Ok(ArcMode::Flatten));
    assert!("round"
        .parse::<ArcMode>()
        .unwrap_err()
        .contains("expected \"exact\" or \"flatten\""));
}

#[test]
fn invalid_arc_outlines_name_the_part_and_place() {
    let d = temp_dir("arc-errors");
    let m = write(
        &d,
        "catalog.toml",
        r#"
name = "bad-arcs"
units = "mm"

[[part]]
id = "bulge-crossing"
outline = [[0, 0], [3, 0, -1], [3, 10], [0, 10]]

[[part]]
id = "one-arc-vertex"
outline = [[0, 0, 1]]
"#,
    );
    let cat = load_catalog(&m).unwrap();
    let err = |i: usize| cat.parts[i].part.as_ref().unwrap_err().to_string();
    // A clockwise half circle on the right side swings through the left one.
    assert!(
        err(0).starts_with("bulge-crossing: outline: edge "),
        "{}",
        err(0)
    );
    assert!(
        err(0).contains("crosses edge") && err(0).ends_with(" mm"),
        "{}",
        err(0)
    );
    assert_eq!(
        err(1),
        "one-arc-vertex: outline: has 1 vertices; an outline with arcs needs at least 2"
    );
}

#[test]
fn svg_rounded_rect_corners_are_exact_quarter_arcs() {
    let quarter = (PI / 8.0).tan();
    let p = read(
        &svg(r#"<rect x="0" y="0" width="100" height="60" rx="10"/>"#),
        Format::Svg,
        &exact(),
    );
    assert_eq!(p.outline.len(), 8);
    assert_eq!(arcs(&p), 4);
    for q in p.outline.iter().filter(|q| q.is_arc()) {
        assert!(close(q.bulge.abs(), quarter, 1e-12), "{q:?}");
    }
    assert!(close(true_area(&p), 6000.0 - (4.0 - PI) * 100.0, 1e-9));
    let b = true_bbox(&p);
    assert!(close(b[0], 0.0, 1e-9) && close(b[2], 100.0, 1e-9), "{b:?}");
    // `ry` alone serves for both; a radius over half a side is cut to it,
    // and the sides it leaves no room for are left out (no doubled vertex).
    let alone = read(
        &svg(r#"<rect width="100" height="60" ry="10"/>"#),
        Format::Svg,
        &exact(),
    );
    assert_eq!(alone.outline, p.outline);
    let stadium = read(
        &svg(r#"<rect width="100" height="60" rx="45" ry="30"/>"#),
        Format::Svg,
        &exact(),
    );
    let round = read(
        &svg(r#"<rect width="100" height="60" rx="30"/>"#),
        Format::Svg,
        &exact(),
    );
    assert_eq!(round.outline.len(), 6);
    assert_eq!(arcs(&round), 4);
    assert!(close(true_area(&round), 40.0 * 60.0 + 900.0 * PI, 1e-9));
    // Elliptical corners (and `arcs = "flatten"`) are flattened.
    assert_eq!(arcs(&stadium), 0);
    assert!(stadium.outline.len() > 20);
    let flat_p = read(
        &svg(r#"<rect width="100" height="60" rx="10"/>"#),
        Format::Svg,
        &flat(),
    );
    assert_eq!(arcs(&flat_p), 0);
    // Chords inside the arcs, each at most the chord tolerance (0.05 mm)
    // away along the four quarter arcs (15.7 mm each).
    let flat_area = mass_properties(&flat_p.outline).area.abs();
    let lost = true_area(&p) - flat_area;
    assert!(lost > 0.0 && lost < 4.0 * 15.8 * 0.05, "{lost}");
    // No radius: the four corners as before.
    let sharp = read(
        &svg(r#"<rect width="100" height="60"/>"#),
        Format::Svg,
        &exact(),
    );
    assert_eq!(sharp.outline.len(), 4);
    // A negative width is the same rectangle drawn from its other corner.
    let back = read(
        &svg(r#"<rect x="100" width="-100" height="60" rx="10"/>"#),
        Format::Svg,
        &exact(),
    );
    assert!(close(true_area(&back), true_area(&p), 1e-9));
    assert!(close(true_bbox(&back)[0], 0.0, 1e-9));
    // `nan` and `inf` parse as floats, but are no lengths.
    for bad in [r#"rx="nan""#, r#"ry="inf""#] {
        let text = svg(&format!(r#"<rect width="100" height="60" {bad}/>"#));
        let e = parse_part(text.as_bytes(), Format::Svg, &exact()).unwrap_err();
        assert!(e.to_string().contains(bad), "{e}");
    }
}
