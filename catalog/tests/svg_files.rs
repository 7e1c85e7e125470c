//! The SVG reader on files as drawing programs write them: DOCTYPEs and
//! entities (and the attacks they allow), outlines drawn as separate open
//! paths, SVG's length rules, Inkscape's layers, and the bounds on what a
//! file can make the reader do.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

mod common;

use common::{area, bbox, close, opts_mm, temp_dir, write};
use fixplan_catalog::{
    parse_part, read_raw, Format, LengthUnit, ParseError, ReadError, ReadOptions, SvgError,
};
use fixplan_core::Units;

fn load(text: &str, opts: &ReadOptions) -> Result<(fixplan_core::Part, Vec<String>), String> {
    parse_part(text.as_bytes(), Format::Svg, opts).map_err(|e| e.to_string())
}

fn load_mm(text: &str) -> (fixplan_core::Part, Vec<String>) {
    load(text, &opts_mm()).unwrap_or_else(|e| panic!("{e}"))
}

fn refusal(text: &str) -> String {
    match load(text, &opts_mm()) {
        Ok(p) => panic!("loaded: {p:?}"),
        Err(e) => e,
    }
}

fn svg_error(text: &str) -> SvgError {
    match read_raw(text.as_bytes(), Format::Svg, &opts_mm()) {
        Err(ReadError::Svg(e)) => e,
        other => panic!("{other:?}"),
    }
}

const HEAD: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="100mm" viewBox="0 0 100 100">"#;

fn mm_doc(body: &str) -> String {
    format!("{HEAD}{body}</svg>")
}

// ---- DOCTYPE and entities ----

#[test]
fn the_w3c_doctype_reads() {
    let text = format!(
        "<?xml version=\"1.0\" standalone=\"no\"?>\n<!DOCTYPE svg PUBLIC \"-//W3C//DTD SVG 1.1//EN\" \"http://www.w3.org/Graphics/SVG/1.1/DTD/svg11.dtd\">\n{}",
        mm_doc(r#"<rect width="40" height="20"/>"#)
    );
    let (p, w) = load_mm(&text);
    assert!(close(area(&p.outline).abs(), 800.0, 1e-9));
    assert!(w.is_empty(), "{w:?}");
}

#[test]
fn illustrator_style_internal_entities_read() {
    let text = r#"<?xml version="1.0" encoding="utf-8"?>
<!-- Generator: Adobe Illustrator 16.0.0, SVG Export Plug-In -->
<!DOCTYPE svg PUBLIC "-//W3C//DTD SVG 1.1//EN" "http://www.w3.org/Graphics/SVG/1.1/DTD/svg11.dtd" [
	<!ENTITY ns_extend "http://ns.adobe.com/Extensibility/1.0/">
	<!ENTITY ns_ai "http://ns.adobe.com/AdobeIllustrator/10.0/">
	<!ENTITY w "40">
]>
<svg xmlns:x="&ns_extend;" xmlns:i="&ns_ai;" xmlns="http://www.w3.org/2000/svg" width="100mm" height="100mm" viewBox="0 0 100 100">
  <rect width="&w;" height="20"/>
</svg>"#;
    let (p, _) = load_mm(text);
    assert!(close(bbox(&p.outline)[2], 40.0, 1e-12));
}

#[test]
fn billion_laughs_is_refused_before_expansion() {
    let mut dtd = String::from("<!ENTITY lol0 \"lollollollollollollollollollol\">\n");
    for i in 1..10 {
        let refs = format!("&lol{};", i - 1).repeat(10);
        dtd.push_str(&format!("<!ENTITY lol{i} \"{refs}\">\n"));
    }
    let text = format!(
        "<?xml version=\"1.0\"?>\n<!DOCTYPE svg [\n{dtd}]>\n{}",
        mm_doc(r#"<rect width="40" height="20"/><text>&lol9;</text>"#)
    );
    let e = refusal(&text);
    assert!(
        e.contains("entity expansion") && e.contains("1048576"),
        "{e}"
    );
    // Quadratic growth: one entity of 255 references to a long one, used
    // many times (what the parser's own guard lets through).
    let long = "x".repeat(4000);
    let refs = "&big;".repeat(250);
    let uses = "&wide;".repeat(2000);
    let text = format!(
        "<!DOCTYPE svg [<!ENTITY big \"{long}\"><!ENTITY wide \"{refs}\">]>{}",
        mm_doc(&format!(
            r#"<rect width="40" height="20"/><text>{uses}</text>"#
        ))
    );
    assert!(refusal(&text).contains("entity expansion"));
}

#[test]
fn entity_loops_are_refused() {
    let text = format!(
        "<!DOCTYPE svg [<!ENTITY a \"&b;\"><!ENTITY b \"&a;\">]>{}",
        mm_doc(r#"<rect width="40" height="20"/><text>&a;</text>"#)
    );
    assert!(refusal(&text).contains("refers to itself"));
}

#[test]
fn external_entities_are_never_read() {
    // A file that would give a valid part if it were read in.
    let dir = temp_dir("svg-xxe");
    let inner = write(&dir, "inner.xml", r#"<rect width="40" height="20"/>"#);
    let uri = format!("file://{}", inner.display());
    let text = format!(
        "<!DOCTYPE svg [<!ENTITY xxe SYSTEM \"{uri}\">]>{}",
        mm_doc("&xxe;")
    );
    let e = refusal(&text);
    assert!(
        e.contains("external SYSTEM") && e.contains("inner.xml"),
        "{e}"
    );
    let passwd = format!(
        "<!DOCTYPE svg [<!ENTITY xxe PUBLIC \"-//X//Y\" \"file:///etc/passwd\">]>{}",
        mm_doc(r#"<rect width="40" height="20"/><text>&xxe;</text>"#)
    );
    let e = refusal(&passwd);
    assert!(e.contains("/etc/passwd") && !e.contains("root:"), "{e}");
    // Declared but not used: nothing to read, the file loads.
    let unused = format!(
        "<!DOCTYPE svg [<!ENTITY xxe SYSTEM \"file:///etc/passwd\">]>{}",
        mm_doc(r#"<rect width="40" height="20"/>"#)
    );
    assert!(load(&unused, &opts_mm()).is_ok());
}

// ---- Open paths joined ----

#[test]
fn separate_open_paths_join_into_the_outline() {
    // Inkscape style: four strokes, one of them drawn backwards, an arc
    // kept exact across the joins.
    let text = mm_doc(
        r#"<path d="M 0,0 H 60"/>
           <path d="m 60,0 v 30"/>
           <path d="M 0,30 H 30 A 15 15 0 0 0 60 30"/>
           <path d="M 0,30 0,0"/>"#,
    );
    let (p, w) = load_mm(&text);
    assert!(w.is_empty(), "{w:?}");
    let b = bbox(&p.outline);
    assert!(
        close(b[2] - b[0], 60.0, 1e-12) && close(b[3] - b[1], 30.0, 1e-12),
        "{b:?}"
    );
    let raw = read_raw(text.as_bytes(), Format::Svg, &opts_mm()).unwrap();
    assert_eq!(raw.outline.len(), 5, "{:?}", raw.outline);
    assert_eq!(
        raw.outline
            .iter()
            .filter(|v| close(v.bulge.abs(), 1.0, 1e-12))
            .count(),
        1
    );
    // <line> and open <polyline> pieces within the join tolerance (5 um).
    let (p, _) = load_mm(&mm_doc(
        r#"<line x1="0" y1="0" x2="50" y2="0"/>
           <polyline points="50.004,0 50,20 0,20"/>
           <line x1="0" y1="20" x2="0" y2="0.003"/>"#,
    ));
    assert!(close(area(&p.outline).abs(), 1000.0, 0.5));
}

#[test]
fn an_arc_joined_from_open_paths_stays_exact() {
    let text = mm_doc(r#"<path d="M 0,0 H 40"/><path d="M 40,0 A 20 20 0 0 0 0 0"/>"#);
    let raw = read_raw(text.as_bytes(), Format::Svg, &opts_mm()).unwrap();
    assert_eq!(raw.outline.len(), 2, "{:?}", raw.outline);
    assert!(raw.outline.iter().any(|v| close(v.bulge.abs(), 1.0, 1e-12)));
}

#[test]
fn a_gap_is_named_with_its_ends() {
    let e = refusal(&mm_doc(
        r#"<path d="M 0,0 H 50 V 20"/><path d="M 50.5,20 H 0 V 0"/>"#,
    ));
    assert!(e.starts_with("open loop:"), "{e}");
    assert!(e.contains("a gap of 0.5") && e.contains("(50, 20)"), "{e}");
}

#[test]
fn an_open_line_alone_is_not_called_a_gap() {
    let e = refusal(&mm_doc(r#"<path d="M 0,0 L 50,0 L 50,40"/>"#));
    assert!(e.contains("no gap") && e.contains("open line"), "{e}");
    assert!(!e.contains("a gap of"), "{e}");
}

#[test]
fn open_linework_inside_the_outline_is_ignored_with_a_warning() {
    let (p, w) = load_mm(&mm_doc(
        r#"<rect width="80" height="40"/><line x1="40" y1="5" x2="40" y2="35"/>"#,
    ));
    assert_eq!(p.outline.len(), 4);
    assert!(w.iter().any(|m| m.contains("open linework")), "{w:?}");
    // Outside the outline it is an error: which part is meant is a guess.
    let e = refusal(&mm_doc(
        r#"<rect width="80" height="40"/><line x1="90" y1="5" x2="95" y2="35"/>"#,
    ));
    assert!(e.contains("open loop"), "{e}");
}

#[test]
fn open_access_paths_join_too() {
    let (p, _) = load_mm(&mm_doc(
        r#"<rect width="80" height="40"/>
           <g class="access"><path d="M 10,10 H 20 V 20"/><path d="M 20,20 H 10 V 10"/></g>"#,
    ));
    assert_eq!(p.access.len(), 1);
}

// ---- Units ----

fn rect_width_mm(root_attrs: &str, opts: &ReadOptions) -> (f64, Vec<String>) {
    let text = format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" {root_attrs}><rect width="100" height="50"/></svg>"#
    );
    let (p, w) = load(&text, opts).unwrap_or_else(|e| panic!("{root_attrs}: {e}"));
    let b = bbox(&p.outline);
    (b[2] - b[0], w)
}

#[test]
fn unitless_and_px_widths_are_css_pixels_with_a_warning() {
    for attrs in [
        r#"width="100" height="50" viewBox="0 0 100 50""#,
        r#"width="100px" height="50px" viewBox="0 0 100 50""#,
        r#"width="200" viewBox="0 0 200 100""#,
        r#"width="100""#,
    ] {
        let (w, warnings) = rect_width_mm(attrs, &opts_mm());
        assert!(close(w, 100.0 * 25.4 / 96.0, 1e-9), "{attrs}: {w}");
        assert!(
            warnings.iter().any(|m| m.contains("no physical unit")
                && m.contains("0.264583 mm")
                && m.contains("96 per inch")),
            "{attrs}: {warnings:?}"
        );
    }
}

#[test]
fn physical_units_by_their_definitions() {
    let cases = [
        (r#"width="100mm" viewBox="0 0 100 50""#, 100.0),
        (r#"width="10cm" viewBox="0 0 100 50""#, 100.0),
        (r#"width="400Q" viewBox="0 0 100 50""#, 100.0),
        (r#"width="1in" viewBox="0 0 100 50""#, 25.4),
        (r#"width="72pt" viewBox="0 0 100 50""#, 25.4),
        (r#"width="6pc" viewBox="0 0 100 50""#, 25.4),
        // Height alone gives the scale when there is no width.
        (r#"height="5cm" viewBox="0 0 100 50""#, 100.0),
        // A physical width without viewBox: user units are px.
        (r#"width="100mm""#, 100.0 * 25.4 / 96.0),
    ];
    for (attrs, want) in cases {
        let (w, warnings) = rect_width_mm(attrs, &opts_mm());
        assert!(close(w, want, 1e-9), "{attrs}: {w}");
        assert!(warnings.is_empty(), "{attrs}: {warnings:?}");
    }
    let (w, _) = rect_width_mm(
        r#"width="1in" viewBox="0 0 100 50""#,
        &ReadOptions::new(Units::In),
    );
    assert!(close(w, 1.0, 1e-12));
}

#[test]
fn no_size_is_css_pixels_too_and_says_so() {
    for attrs in [
        "",
        r#"width="100%" viewBox="0 0 100 50""#,
        r#"viewBox="0 0 400 200""#,
    ] {
        let (w, warnings) = rect_width_mm(attrs, &opts_mm());
        assert!(close(w, 100.0 * 25.4 / 96.0, 1e-9), "{attrs}: {w}");
        assert!(
            warnings
                .iter()
                .any(|m| m.contains("no physical unit") && m.contains("0.264583 mm")),
            "{attrs}: {warnings:?}"
        );
    }
}

#[test]
fn a_manifest_units_choice_replaces_pixels() {
    let inch = ReadOptions {
        fallback: LengthUnit::In,
        ..opts_mm()
    };
    let (w, warnings) = rect_width_mm(r#"width="100" viewBox="0 0 100 50""#, &inch);
    assert!(close(w, 2540.0, 1e-9), "{w}");
    assert!(
        warnings.iter().any(|m| m.contains("units = \"in\"")),
        "{warnings:?}"
    );
    let (w, _) = rect_width_mm("", &inch);
    assert!(close(w, 2540.0, 1e-9), "{w}");
    // In an inch catalogue, mm chosen for a file without a size.
    let mm_in_inch = ReadOptions {
        fallback: LengthUnit::Mm,
        ..ReadOptions::new(Units::In)
    };
    let (w, _) = rect_width_mm("", &mm_in_inch);
    assert!(close(w, 100.0 / 25.4, 1e-12), "{w}");
}

#[test]
fn old_inkscape_pixels_are_90_to_the_inch() {
    let (w, warnings) = rect_width_mm(
        r#"xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" inkscape:version="0.48.4 r9939" width="100" height="50""#,
        &opts_mm(),
    );
    assert!(close(w, 100.0 * 25.4 / 90.0, 1e-9), "{w}");
    assert!(
        warnings.iter().any(|m| m.contains("90 per inch")),
        "{warnings:?}"
    );
}

#[test]
fn an_uneven_stretch_is_refused_and_a_bad_viewbox_named() {
    let e = svg_error(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="100mm" viewBox="0 0 100 50" preserveAspectRatio="none"><rect width="10" height="10"/></svg>"#,
    );
    assert!(matches!(e, SvgError::Stretched { .. }), "{e}");
    let e = svg_error(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" viewBox="0 0 0 50"><rect width="10" height="10"/></svg>"#,
    );
    assert_eq!(e, SvgError::BadViewBox);
}

// ---- Inkscape files ----

#[test]
fn inkscape_layers_hidden_layers_and_own_elements() {
    let text = r##"<?xml version="1.0" encoding="UTF-8" standalone="no"?>
<!DOCTYPE svg PUBLIC "-//W3C//DTD SVG 1.1//EN" "http://www.w3.org/Graphics/SVG/1.1/DTD/svg11.dtd">
<svg
   width="210mm" height="297mm" viewBox="0 0 210 297" version="1.1" id="svg8"
   inkscape:version="1.2.2 (b0a8486541, 2022-12-01)"
   sodipodi:docname="plate.svg"
   xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape"
   xmlns:sodipodi="http://sodipodi.sourceforge.net/DTD/sodipodi-0.dtd"
   xmlns="http://www.w3.org/2000/svg" xmlns:svg="http://www.w3.org/2000/svg">
  <sodipodi:namedview id="base" inkscape:document-units="mm" showgrid="false"/>
  <defs id="defs2"/>
  <g inkscape:label="Outline" inkscape:groupmode="layer" id="layer1" transform="translate(-10,-20)">
    <path style="fill:none;stroke:#000000;stroke-width:0.26" d="m 20,30 h 80" id="path10"/>
    <path style="fill:none;stroke:#000000" d="m 100,30 v 40 h -80" id="path12"/>
    <path style="fill:none;stroke:#000000" d="M 20,70 V 30" id="path14"/>
    <circle id="hole" cx="60" cy="50" r="5"/>
  </g>
  <g inkscape:label="Construction" inkscape:groupmode="layer" id="layer2" style="display:none">
    <rect x="-500" y="-500" width="2000" height="2000"/>
  </g>
  <inkscape:path d="M 0,0 H 1000 V 1000 Z"/>
</svg>"##;
    let (p, w) = load_mm(text);
    let b = bbox(&p.outline);
    let want = [10.0, -50.0, 90.0, -10.0];
    assert!((0..4).all(|i| close(b[i], want[i], 1e-9)), "{b:?}");
    assert!(
        w.iter()
            .any(|m| m.contains("layer2") && m.contains("hidden")),
        "{w:?}"
    );
    // The circle inside the outline is the part's hole (SPEC 9), kept
    // without a warning.
    assert_eq!(p.holes.len(), 1, "{w:?}");
    assert!(!w.iter().any(|m| m.contains("hole")), "{w:?}");
}

#[test]
fn a_nested_viewport_is_named() {
    let (_, w) = load_mm(&mm_doc(
        r#"<svg x="10" width="50" viewBox="0 0 10 10"><rect width="80" height="40"/></svg>"#,
    ));
    assert!(w.iter().any(|m| m.contains("nested viewport")), "{w:?}");
}

// ---- Limits ----

fn limit_error(text: &str, what: &str) {
    let e = refusal(text);
    assert!(
        e.contains("more than") && e.contains(what) && e.contains("limit"),
        "{e}"
    );
}

#[test]
fn deep_nesting_is_bounded_not_a_stack_overflow() {
    let n = 200_000;
    let text = format!(
        "{HEAD}{}<rect width=\"1\" height=\"1\"/>{}</svg>",
        "<g>".repeat(n),
        "</g>".repeat(n)
    );
    limit_error(&text, "levels of nested groups");
    // Within the bound it reads.
    let text = format!(
        "{HEAD}{}<rect width=\"1\" height=\"1\"/>{}</svg>",
        "<g>".repeat(900),
        "</g>".repeat(900)
    );
    assert!(load(&text, &opts_mm()).is_ok());
}

#[test]
fn element_and_attribute_counts_are_bounded() {
    limit_error(&mm_doc(&"<g/>".repeat(500_001)), "elements");
    // A quote in a comment hides nothing from the count.
    let hiding = format!("<!-- it's -->{}<!-- ' -->", "<g/>".repeat(500_001));
    limit_error(&mm_doc(&hiding), "elements");
    let attrs: String = (0..2_000_001).map(|i| format!(" a{i}=\"\"")).collect();
    limit_error(&mm_doc(&format!("<g{attrs}/>")), "attributes");
}

#[test]
fn path_commands_and_vertices_are_bounded() {
    let d = format!("M0 0{}", " l1 0".repeat(2_000_001));
    limit_error(&mm_doc(&format!("<path d=\"{d}\"/>")), "path commands");
    // Curves flattened at a tiny tolerance: each cubic is 1024 chords.
    let fine = ReadOptions {
        chord_tolerance: 1e-12,
        ..opts_mm()
    };
    let d = format!("M0 0{}", " c10 20 20 20 30 0".repeat(2_100));
    match load(&mm_doc(&format!("<path d=\"{d}\"/>")), &fine) {
        Err(e) => assert!(e.contains("vertices") && e.contains("limit"), "{e}"),
        Ok(_) => panic!("read"),
    }
}

#[test]
fn file_size_is_bounded() {
    let big = format!("{HEAD}{}</svg>", " ".repeat(33 << 20));
    let e = parse_part(big.as_bytes(), Format::Svg, &opts_mm()).unwrap_err();
    assert!(
        matches!(e, ParseError::Read(ReadError::Svg(SvgError::TooBig { .. }))),
        "{e}"
    );
    assert!(e.to_string().contains("bytes"), "{e}");
}
