//! Every format: DXF (R12 and R2000, other tools' files, bulges, LINE/ARC
//! chains, units), SVG (commands, transforms, units, access), JSON. What
//! is about flattening curves reads with `arcs = "flatten"`; exact arcs
//! are in `arcs.rs`.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

mod common;
use common::*;
use fixplan_catalog::{parse_part, read_raw, Format, LengthUnit, ReadOptions};
use fixplan_core::Units;

#[test]
fn dxf_r12_polyline_with_bulges_and_line_access() {
    let bytes = std::fs::read(fixture("r12_bulge_polyline.dxf")).unwrap();
    let mut o = flat_mm();
    o.chord_tolerance = 0.01;
    let (part, warnings) = parse_part(&bytes, Format::Dxf, &o).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    // Half circle of radius 10 on the right: x reaches 70.
    let b = bbox(&part.outline);
    assert!(close(b[2], 70.0, 0.01), "{b:?}");
    assert!(close(b[0], 0.0, 1e-9) || b[0] < 0.0);
    // Bulge -tan(pi/8): a clockwise quarter arc from (0,20) to (0,0),
    // centre (10, 10): it cuts into the part, x stays >= 0 ... up to 10 - r.
    assert!(b[0] >= -1e-9 && b[0] < 1e-6, "{b:?}");
    // 60x20 rectangle + half disc (pi*100/2) - the quarter-arc segment
    // cut from the left side (r^2 (pi/4 - 1/2), r = 10 sqrt 2).
    let r2: f64 = 200.0;
    let expected = 1200.0 + std::f64::consts::PI * 50.0 - r2 * (std::f64::consts::FRAC_PI_4 - 0.5);
    assert!(
        close(area(&part.outline).abs(), expected, 3.0),
        "{}",
        area(&part.outline)
    );
    assert_eq!(part.access.len(), 1);
    assert!(close(area(&part.access[0]).abs(), 300.0, 1e-9));
}

#[test]
fn dxf_r2000_inches_crlf_paper_space_hole_and_keepout() {
    let bytes = std::fs::read(fixture("r2000_inch_crlf.dxf")).unwrap();
    let (part, warnings) = parse_part(&bytes, Format::Dxf, &opts_mm()).unwrap();
    // $INSUNITS = 1: 3 in wide = 76.2 mm; the paper-space title block is
    // not the part even though it is larger.
    let b = bbox(&part.outline);
    assert!(close(b[2] - b[0], 76.2, 1e-9), "{b:?}");
    assert_eq!(part.access.len(), 1, "layer KeepOut, any case");
    assert!(close(bbox(&part.access[0])[0], 12.7, 1e-9));
    // The CIRCLE inside the outline is the part's hole (SPEC 9).
    assert_eq!(part.holes.len(), 1, "{warnings:?}");
    assert!(
        part.holes[0].iter().all(|v| v.bulge == 1.0),
        "{:?}",
        part.holes
    );
    // Read into an inch catalogue, the same file is in inches.
    let (p_in, _) = parse_part(&bytes, Format::Dxf, &ReadOptions::new(Units::In)).unwrap();
    assert!(close(bbox(&p_in.outline)[2], 3.0, 1e-12));
}

#[test]
fn dxf_line_arc_chain_joins_in_any_order_and_direction() {
    let mut body = Vec::new();
    body.extend(line("0", ["30", "25"], ["-30", "25"]));
    body.extend(arc_entity(["30", "0"], "25", "270", "90"));
    body.extend(line("0", ["30", "-25"], ["-30", "-25"])); // reversed
    body.extend(arc_entity(["-30", "0"], "25", "90", "270"));
    let mut o = flat_mm();
    o.chord_tolerance = 0.05;
    let (part, w) = parse_part(r12(&body).as_bytes(), Format::Dxf, &o).unwrap();
    assert!(w.is_empty(), "{w:?}");
    let b = bbox(&part.outline);
    assert!(close(b[0], -55.0, 0.06) && close(b[2], 55.0, 0.06), "{b:?}");
    let exact = 60.0 * 50.0 + std::f64::consts::PI * 625.0;
    assert!(close(area(&part.outline).abs(), exact, 15.0));
    // Chord error: every edge midpoint is within tolerance of the arc.
    let n = part.outline.len();
    assert!(n > 40, "{n}");
}

#[test]
fn dxf_chord_tolerance_controls_flattening() {
    let body = vec![(0, "CIRCLE"), (8, "0"), (10, "0"), (20, "0"), (40, "30")];
    let text = r12(&body);
    let mut coarse = flat_mm();
    coarse.chord_tolerance = 1.0;
    let mut fine = flat_mm();
    fine.chord_tolerance = 0.01;
    let (a, _) = parse_part(text.as_bytes(), Format::Dxf, &coarse).unwrap();
    let (b, _) = parse_part(text.as_bytes(), Format::Dxf, &fine).unwrap();
    assert!(
        a.outline.len() < 15 && b.outline.len() > 100,
        "{} {}",
        a.outline.len(),
        b.outline.len()
    );
    for p in &a.outline {
        assert!(close(p[0].hypot(p[1]), 30.0, 1e-9));
    }
}

#[test]
fn dxf_insunits_cm_and_unitless_fallback() {
    let body = dxf_text(&[
        (0, "SECTION"),
        (2, "HEADER"),
        (9, "$ACADVER"),
        (1, "AC1015"),
        (9, "$INSUNITS"),
        (70, "5"),
        (0, "ENDSEC"),
        (0, "SECTION"),
        (2, "ENTITIES"),
        (0, "LWPOLYLINE"),
        (8, "0"),
        (90, "3"),
        (70, "1"),
        (10, "0"),
        (20, "0"),
        (10, "4"),
        (20, "0"),
        (10, "0"),
        (20, "3"),
        (0, "ENDSEC"),
        (0, "EOF"),
    ]);
    let (p, _) = parse_part(body.as_bytes(), Format::Dxf, &opts_mm()).unwrap();
    assert_eq!(p.outline[1], [40.0, 0.0]);
    // Unitless: the fallback (e.g. a manifest entry's units) applies.
    let unitless = body.replace("$INSUNITS\n 70\n5\n", "$INSUNITS\n 70\n0\n");
    let mut o = opts_mm();
    o.fallback = LengthUnit::In;
    let (p, _) = parse_part(unitless.as_bytes(), Format::Dxf, &o).unwrap();
    assert_eq!(p.outline[1], [4.0 * 25.4, 0.0]);
}

#[test]
fn dxf_mirrored_extrusion_flips_x() {
    let body = vec![
        (0, "CIRCLE"),
        (8, "0"),
        (10, "50"),
        (20, "0"),
        (40, "10"),
        (210, "0"),
        (220, "0"),
        (230, "-1"),
    ];
    let (p, _) = parse_part(r12(&body).as_bytes(), Format::Dxf, &opts_mm()).unwrap();
    let b = bbox(&p.outline);
    assert!(close(b[0], -60.0, 1e-9) && close(b[2], -40.0, 0.1), "{b:?}");
}

#[test]
fn svg_inkscape_style_file() {
    let bytes = std::fs::read(fixture("inkscape_style.svg")).unwrap();
    let (part, warnings) = parse_part(&bytes, Format::Svg, &opts_mm()).unwrap();
    // width 100mm over a 200-unit viewBox: half a millimetre per unit; the
    // layer is translated by (10, 10); y is negated.
    let b = bbox(&part.outline);
    assert!(close(b[0], 5.0, 1e-9) && close(b[2], 85.0, 1e-9), "{b:?}");
    assert!(close(b[3], -5.0, 1e-9) && close(b[1], -55.0, 1e-9), "{b:?}");
    assert_eq!(part.access.len(), 1, "id keepout-1");
    assert!(close(bbox(&part.access[0])[3], 0.0, 1e-9));
    // The circle with id "bore" is the part's hole (SPEC 9).
    assert_eq!(part.holes.len(), 1, "{warnings:?}");
    // The rounded corner (a cubic) is flattened, not dropped.
    assert!(part.outline.len() > 5);
}

/// A file in mm, one user unit a millimetre (a file without a size is in
/// CSS px, with a warning).
fn svg_doc(body: &str) -> String {
    format!("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"1000mm\" height=\"1000mm\" viewBox=\"0 0 1000 1000\">{body}</svg>")
}

fn svg_part(body: &str) -> fixplan_core::Part {
    parse_part(svg_doc(body).as_bytes(), Format::Svg, &opts_mm())
        .unwrap_or_else(|e| panic!("{e}"))
        .0
}

fn svg_flat(body: &str) -> fixplan_core::Part {
    parse_part(svg_doc(body).as_bytes(), Format::Svg, &flat_mm())
        .unwrap_or_else(|e| panic!("{e}"))
        .0
}

#[test]
fn svg_y_axis_is_negated() {
    let p = svg_part(r#"<polygon points="0,0 10,0 10,20"/>"#);
    assert_eq!(p.outline, vec![[0.0, 0.0], [10.0, 0.0], [10.0, -20.0]]);
}

#[test]
fn svg_path_absolute_and_relative_commands_agree() {
    let abs = svg_part(r#"<path d="M 10 10 L 50 10 H 60 V 40 L 10 40 Z"/>"#);
    let rel = svg_part(r#"<path d="m10,10 l40,0 h10 v30 l-50,0 z"/>"#);
    assert_eq!(abs.outline, rel.outline);
    // Implicit lineto after moveto, numbers glued by signs and dots.
    let glued = svg_part(r#"<path d="M10-10 50-10 60-10 60-40 10-40z"/>"#);
    assert_eq!(
        glued.outline.len(),
        4,
        "collinear 50,-10 merged: {:?}",
        glued.outline
    );
    let dots = svg_part(r#"<path d="M0 0h10.5.5v10H0z"/>"#);
    // h10.5 then an implicit h.5: (10.5, 0) is mid-edge and merged.
    assert_eq!(dots.outline.len(), 4, "{:?}", dots.outline);
    assert_eq!(dots.outline[1], [11.0, 0.0]);
}

#[test]
fn svg_curves_and_arcs_are_flattened_within_tolerance() {
    // A circle made of two arcs (A), radius 20.
    let p = svg_flat(r#"<path d="M 0 0 A 20 20 0 0 1 40 0 A 20 20 0 0 1 0 0 Z"/>"#);
    for q in &p.outline {
        assert!(close((q[0] - 20.0).hypot(q[1]), 20.0, 1e-9), "{q:?}");
    }
    assert!(p.outline.len() > 20);
    // Relative arc with flags glued: a1 1 0 011 1 style.
    let g = svg_flat(r#"<path d="M0,0 h10 a5,5 0 1,1 0,10 h-10 z"/>"#);
    assert!(close(bbox(&g.outline)[2], 15.0, 0.06));
    // Cubic (C, S) and quadratic (Q, T) curves stay within their hulls.
    let c =
        svg_part(r#"<path d="M0,0 C0,-10 20,-10 20,0 S40,10 40,0 L40,30 Q20,40 0,30 T-10,20 Z"/>"#);
    let b = bbox(&c.outline);
    assert!(b[2] <= 40.0 + 1e-9 && b[0] > -20.0, "{b:?}");
    assert!(b[1] < -30.0, "Q bulges below y = -30: {b:?}");
    assert!(c.outline.len() > 12);
}

#[test]
fn svg_transforms_compose_on_groups_and_elements() {
    let p = svg_part(
        r#"<g transform="translate(100,0)"><g transform="rotate(90)">
           <rect x="0" y="0" width="10" height="20" transform="scale(2)"/></g></g>"#,
    );
    // scale(2): 20x40; rotate 90: (x, y) -> (-y, x), so x in [-40, 0] and
    // y in [0, 20]; translate +100 in x; then y negated.
    let b = bbox(&p.outline);
    let want = [60.0, -20.0, 100.0, 0.0];
    assert!((0..4).all(|i| close(b[i], want[i], 1e-12)), "{b:?}");
    let m = svg_part(r#"<polygon transform="matrix(1 0 0 1 5 -5)" points="0,0 10,0 0,10"/>"#);
    assert_eq!(m.outline[0], [5.0, 5.0]);
    let r = svg_part(r#"<polygon transform="rotate(180 5 5)" points="0,0 10,0 0,10"/>"#);
    assert!(close(r.outline[0][0], 10.0, 1e-12) && close(r.outline[0][1], -10.0, 1e-12));
}

#[test]
fn svg_access_by_class_id_and_group() {
    let p = svg_part(
        r#"<rect width="100" height="50"/>
           <rect class="fill access" x="10" y="-5" width="5" height="10"/>
           <polygon id="KEEPOUT-2" points="50,45 60,45 60,55"/>
           <g class="keepout"><circle cx="90" cy="25" r="15"/></g>"#,
    );
    assert_eq!(p.access.len(), 3);
}

#[test]
fn svg_physical_units() {
    let inches = r#"<svg xmlns="http://www.w3.org/2000/svg" width="2in" height="1in" viewBox="0 0 20 10"><rect width="20" height="10"/></svg>"#;
    let (p, _) = parse_part(inches.as_bytes(), Format::Svg, &opts_mm()).unwrap();
    assert!(close(bbox(&p.outline)[2], 50.8, 1e-9));
    let (p, _) = parse_part(inches.as_bytes(), Format::Svg, &ReadOptions::new(Units::In)).unwrap();
    assert!(close(bbox(&p.outline)[2], 2.0, 1e-12));
    // No viewBox with a physical width: user units are CSS pixels.
    let px = r#"<svg xmlns="http://www.w3.org/2000/svg" width="96mm"><rect width="96" height="48"/></svg>"#;
    let (p, _) = parse_part(px.as_bytes(), Format::Svg, &opts_mm()).unwrap();
    assert!(close(bbox(&p.outline)[2], 25.4, 1e-9));
}

#[test]
fn json_appendix_a_case_file_and_plain_part() {
    let case = std::fs::read(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../examples/cases/rectangle-mm.json"),
    )
    .unwrap();
    let (p, _) = parse_part(&case, Format::Json, &opts_mm()).unwrap();
    assert_eq!(p.outline.len(), 4);
    assert_eq!(p.access.len(), 1);
    let inch = br#"{"units": "in", "part": [[0,0],[1,0],[0,1]]}"#;
    let (p, _) = parse_part(inch, Format::Json, &opts_mm()).unwrap();
    assert_eq!(p.outline[1], [25.4, 0.0]);
    // core's own Part serialisation reads too.
    let core = br#"{"outline": [[0,0],[1,0],[0,1]], "access": []}"#;
    assert!(parse_part(core, Format::Json, &opts_mm()).is_ok());
}

#[test]
fn raw_reading_keeps_the_file_order() {
    let raw = read_raw(
        svg_doc(r#"<polygon points="0,0 0,10 10,10 10,0"/>"#).as_bytes(),
        Format::Svg,
        &opts_mm(),
    )
    .unwrap();
    assert_eq!(raw.outline[1], [0.0, -10.0]);
}
