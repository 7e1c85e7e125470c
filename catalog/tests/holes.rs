//! Parts with holes (SPEC 9) through the catalogue: the loops inside a
//! drawing's outline are its holes, in file order; loops inside a hole are
//! dropped with a warning; JSON parts, inline manifest parts and case files
//! give `holes`; `holes = "ignore"` reads the solid outline as before; the
//! writers keep holes; a hole in the wrong place is refused by name.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

mod common;

use common::{opts_mm, temp_dir, write};
use fixplan_catalog::{
    load_catalog, load_catalog_with, parse_part, write_dxf, write_json, write_svg, Format,
    HoleMode, LoadOptions, ReadOptions,
};
use fixplan_core::{Part, Units, Vertex};

/// A 100 x 60 plate with a round bore (diameter 20 at (30, 30)) and a
/// square window, listed in that order.
fn plate() -> Part {
    let square = [[60.0, 20.0], [85.0, 20.0], [85.0, 45.0], [60.0, 45.0]];
    Part {
        outline: [[0.0, 0.0], [100.0, 0.0], [100.0, 60.0], [0.0, 60.0]]
            .map(Vertex::from)
            .to_vec(),
        holes: vec![
            vec![Vertex::new(20.0, 30.0, 1.0), Vertex::new(40.0, 30.0, 1.0)],
            square.map(Vertex::from).to_vec(),
        ],
        access: Vec::new(),
    }
}

/// [`plate`] drawn with a counterbore's step (a circle inside the bore):
/// no material, so no hole of the part.
fn plate_with_counterbore() -> Part {
    let mut p = plate();
    p.holes.push(vec![
        Vertex::new(26.0, 30.0, 1.0),
        Vertex::new(34.0, 30.0, 1.0),
    ]);
    p
}

fn ignoring() -> ReadOptions {
    ReadOptions {
        holes: HoleMode::Ignore,
        ..opts_mm()
    }
}

fn text(format: Format, part: &Part) -> String {
    match format {
        Format::Dxf => write_dxf(part, Units::Mm),
        Format::Svg => write_svg(part, Units::Mm),
        Format::Json => write_json(part, Units::Mm),
    }
}

#[test]
fn drawn_loops_inside_the_outline_are_its_holes_in_order() {
    for format in [Format::Dxf, Format::Svg] {
        let t = text(format, &plate_with_counterbore());
        let (p, w) = parse_part(t.as_bytes(), format, &opts_mm()).unwrap();
        assert_eq!(p.holes, plate().holes, "{format:?}");
        assert_eq!(p.outline, plate().outline, "{format:?}");
        // The counterbore's circle: dropped, naming the bore it lies in.
        assert_eq!(w.len(), 1, "{format:?}: {w:?}");
        assert!(
            w[0].contains("lies inside hole 0") && w[0].contains("near (26, 30) mm"),
            "{format:?}: {w:?}"
        );
    }
}

#[test]
fn ignoring_holes_reads_the_solid_outline_with_the_old_warnings() {
    for format in [Format::Dxf, Format::Svg, Format::Json] {
        let t = text(format, &plate_with_counterbore());
        let (p, w) = parse_part(t.as_bytes(), format, &ignoring()).unwrap();
        assert!(p.holes.is_empty(), "{format:?}");
        assert_eq!(p.outline, plate().outline, "{format:?}");
        // One warning per loop inside the outline, counterbore included.
        let dropped = w.iter().filter(|m| m.contains("a loop inside the outline"));
        assert_eq!(dropped.count(), 3, "{format:?}: {w:?}");
    }
}

#[test]
fn writers_keep_holes_and_parts_without_holes_are_written_as_before() {
    for format in [Format::Dxf, Format::Svg, Format::Json] {
        let t = text(format, &plate());
        let (p, w) = parse_part(t.as_bytes(), format, &opts_mm()).unwrap();
        assert_eq!(p, plate(), "{format:?}: {w:?}");
        let solid = Part {
            holes: Vec::new(),
            ..plate()
        };
        let t = text(format, &solid);
        assert!(!t.contains("hole") && !t.contains("HOLES"), "{t}");
    }
}

#[test]
fn json_and_case_files_give_holes_beside_the_part() {
    // SPEC Appendix A's example: a round hole of diameter 10 at (25, 20).
    let case = r#"{"units": "mm", "part": [[0,0],[80,0],[80,50],[0,50]],
        "holes": [[[20,20,1],[30,20,1]]], "kit": {}, "params": {}}"#;
    let (p, w) = parse_part(case.as_bytes(), Format::Json, &opts_mm()).unwrap();
    assert_eq!(
        p.holes,
        vec![vec![
            Vertex::new(20.0, 20.0, 1.0),
            Vertex::new(30.0, 20.0, 1.0)
        ]]
    );
    assert!(w.is_empty(), "{w:?}");
    // Units apply to holes too.
    let inch =
        r#"{"units": "in", "part": [[0,0],[4,0],[4,2],[0,2]], "holes": [[[1,1],[2,1],[2,1.5]]]}"#;
    let (p, _) = parse_part(inch.as_bytes(), Format::Json, &opts_mm()).unwrap();
    assert_eq!(p.holes[0][1], Vertex::from([50.8, 25.4]));
    let bad = r#"{"part": [[0,0],[4,0],[4,2]], "holes": [[[1,1],[2,1],"x"]]}"#;
    let e = parse_part(bad.as_bytes(), Format::Json, &opts_mm()).unwrap_err();
    assert!(e.to_string().starts_with("hole 0: vertex 2 "), "{e}");
    let bad = r#"{"part": [[0,0],[4,0],[4,2]], "holes": 3}"#;
    let e = parse_part(bad.as_bytes(), Format::Json, &opts_mm()).unwrap_err();
    assert!(e.to_string().contains("\"holes\" is not a list"), "{e}");
}

#[test]
fn a_hole_in_the_wrong_place_is_refused_naming_the_part_and_the_hole() {
    let d = temp_dir("holes");
    let cat = |holes: &str| {
        let toml = format!(
            "name = \"h\"\nunits = \"mm\"\n[[part]]\nid = \"p\"\noutline = [[0,0],[100,0],[100,60],[0,60]]\nholes = {holes}\n"
        );
        let path = write(&d, "catalog.toml", &toml);
        load_catalog(&path).unwrap().parts.remove(0)
    };
    let ok = cat("[[[20,30,1],[40,30,1]], [[60,20],[85,20],[85,45],[60,45]]]");
    assert_eq!(ok.part.unwrap().holes, plate().holes);
    // Where a hole lies is core's judgement (SPEC 9.1), in core's words,
    // the unit after the coordinates.
    let refused = |holes: &str| cat(holes).part.unwrap_err().to_string();
    let e = refused("[[[20,30,1],[40,30,1]], [[160,20],[185,20],[185,45]]]");
    assert_eq!(e, "p: hole 1 lies outside the outline");
    let e = refused("[[[10,10],[50,10],[50,50],[10,50]], [[20,20],[30,20],[30,30]]]");
    assert!(e.contains("hole 1 lies inside hole 0"), "{e}");
    let e = refused("[[[90,20],[110,20],[110,40],[90,40]]]");
    assert!(
        e.contains("hole 0 crosses the outline at (100, 20) mm"),
        "{e}"
    );
    let e = refused("[[[40,10],[100,15],[40,20]]]");
    assert!(
        e.contains("hole 0 touches the outline at (100, 15) mm"),
        "{e}"
    );
    let e = refused("[[[10,10],[30,10],[30,30],[10,30]], [[30,20],[50,20],[50,40]]]");
    assert!(e.contains("hole 1 touches hole 0 at (30, 20) mm"), "{e}");
    let crossed = cat("[[[10,10],[50,50],[50,10],[10,50]]]");
    let e = crossed.part.unwrap_err().to_string();
    assert!(e.contains("hole 0: edge 0 crosses edge 2"), "{e}");
    // Holes go with an inline outline only.
    let path = write(
        &d,
        "catalog.toml",
        "name = \"h\"\nunits = \"mm\"\n[[part]]\nid = \"f\"\nfile = \"x.dxf\"\nholes = [[[1,1],[2,1],[2,2]]]\n",
    );
    let e = load_catalog(&path).unwrap().parts[0]
        .part
        .as_ref()
        .unwrap_err()
        .to_string();
    assert!(e.contains("holes go with an inline outline"), "{e}");
}

#[test]
fn the_manifest_and_the_caller_choose_whether_holes_are_read() {
    let d = temp_dir("holes-mode");
    write(&d, "parts/plate.dxf", &write_dxf(&plate(), Units::Mm));
    let holes_of = |cat: fixplan_catalog::Catalog| cat.parts[0].part.as_ref().unwrap().holes.len();
    let manifest = |extra: &str| {
        write(
            &d,
            "catalog.toml",
            &format!("name = \"h\"\nunits = \"mm\"\n{extra}[[part]]\nid = \"p\"\nfile = \"parts/plate.dxf\"\n"),
        )
    };
    assert_eq!(holes_of(load_catalog(&manifest("")).unwrap()), 2);
    let ignore = manifest("holes = \"ignore\"\n");
    let cat = load_catalog(&ignore).unwrap();
    assert_eq!(
        cat.parts[0].warnings.len(),
        2,
        "{:?}",
        cat.parts[0].warnings
    );
    assert_eq!(holes_of(cat), 0);
    let keep = LoadOptions {
        holes: Some(HoleMode::Keep),
        ..LoadOptions::default()
    };
    assert_eq!(holes_of(load_catalog_with(&ignore, &keep).unwrap()), 2);
    let e = load_catalog(&manifest("holes = \"drop\"\n")).unwrap_err();
    assert!(e.to_string().contains("expected \"keep\""), "{e}");
    // A directory: the caller's choice alone.
    let ignore = LoadOptions {
        holes: Some(HoleMode::Ignore),
        ..LoadOptions::default()
    };
    assert_eq!(
        holes_of(load_catalog_with(&d.join("parts"), &ignore).unwrap()),
        0
    );
    assert_eq!(holes_of(load_catalog(&d.join("parts")).unwrap()), 2);
}
