//! Every validation error names the file, the part and the place; an
//! invalid part never stops the others.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

mod common;
use common::*;
use fixplan_catalog::{
    load_catalog, load_catalog_with, parse_part, EntryProblem, Format, LoadOptions, ParseError,
    PartErrorKind, ReadError, ReadOptions,
};
use fixplan_core::Units;

fn part_err(cat: &fixplan_catalog::Catalog, id: &str) -> String {
    cat.parts
        .iter()
        .find(|p| p.id == id)
        .unwrap_or_else(|| panic!("no part {id}"))
        .part
        .as_ref()
        .expect_err(id)
        .to_string()
}

const DXF_OPEN: &str = "  0\nSECTION\n  2\nENTITIES\n  0\nLINE\n  8\n0\n 10\n0\n 20\n0\n 11\n10\n 21\n0\n  0\nLINE\n  8\n0\n 10\n10\n 20\n0\n 11\n10\n 21\n10\n  0\nENDSEC\n  0\nEOF\n";
const DXF_EMPTY: &str = "  0\nSECTION\n  2\nENTITIES\n  0\nTEXT\n  8\n0\n 10\n0\n 20\n0\n 40\n1\n  1\nhello\n  0\nENDSEC\n  0\nEOF\n";
const DXF_MILES: &str = "  0\nSECTION\n  2\nHEADER\n  9\n$ACADVER\n  1\nAC1015\n  9\n$INSUNITS\n 70\n3\n  0\nENDSEC\n  0\nSECTION\n  2\nENTITIES\n  0\nCIRCLE\n  8\n0\n 10\n0\n 20\n0\n 40\n1\n  0\nENDSEC\n  0\nEOF\n";
const DXF_TWO: &str = "  0\nSECTION\n  2\nENTITIES\n  0\nCIRCLE\n  8\n0\n 10\n0\n 20\n0\n 40\n10\n  0\nCIRCLE\n  8\n0\n 10\n50\n 20\n0\n 40\n5\n  0\nENDSEC\n  0\nEOF\n";
const DXF_NAN: &str = "  0\nSECTION\n  2\nENTITIES\n  0\nLWPOLYLINE\n  8\n0\n 90\n3\n 70\n1\n 10\n0\n 20\n0\n 10\nnan\n 20\n0\n 10\n5\n 20\n5\n  0\nENDSEC\n  0\nEOF\n";

/// One entry per error case, in the order the test checks them.
const ERRORS_MANIFEST: &str = r#"
name = "errors"
units = "mm"

[[part]]
id = "bracket-7"
outline = [[0, 0], [30, 0], [30, 10], [12.5, 10], [12.5, -5], [20, 3], [0, 3]]

[[part]]
id = "two-points"
outline = [[0, 0], [1, 0]]

[[part]]
id = "flat"
outline = [[0, 0], [1, 0], [2, 0], [3, 0]]

[[part]]
id = "touching"
outline = [[0, 0], [10, 0], [5, 5], [10, 10], [0, 10], [5, 5]]

[[part]]
id = "dups"
outline = [[0, 0], [10, 0], [10, 0], [10, 10], [0, 10], [0, 0]]

[[part]]
id = "not-finite"
outline = [[0, 0], [10, 0], [nan, 10]]

[[part]]
id = "bad-access"
outline = [[0, 0], [10, 0], [10, 10], [0, 10]]
access = [[[0, 0], [5, 5], [5, 0], [0, 5]]]

[[part]]
id = "open"
file = "parts/open.dxf"

[[part]]
id = "empty"
file = "parts/empty.dxf"

[[part]]
id = "miles"
file = "parts/miles.dxf"

[[part]]
id = "two"
file = "parts/two.dxf"

[[part]]
id = "nan-dxf"
file = "parts/nan.dxf"

[[part]]
id = "garbage"
file = "parts/garbage.svg"

[[part]]
id = "open-svg"
file = "parts/open.svg"

[[part]]
id = "bad-json"
file = "parts/bad.json"

[[part]]
id = "missing"
file = "parts/missing.dxf"

[[part]]
id = "txt"
file = "parts/notes.txt"

[[part]]
id = "both"
file = "parts/good.json"
outline = [[0, 0], [1, 0], [0, 1]]

[[part]]
id = "good"
file = "parts/good.json"
quantity = 12.0

[[part]]
id = "good"
file = "parts/good.json"

[[part]]
id = "cm"
file = "parts/good.json"
units = "furlong"

[[part]]
id = "typo"
fil = "parts/good.json"

[[part]]
id = "good-inch"
outline = [[0, 0], [1, 0], [1, 1]]
units = "in"
"#;

fn manifest_dir() -> TempDir {
    let d = temp_dir("errors");
    write(&d, "parts/open.dxf", DXF_OPEN);
    write(&d, "parts/empty.dxf", DXF_EMPTY);
    write(&d, "parts/miles.dxf", DXF_MILES);
    write(&d, "parts/two.dxf", DXF_TWO);
    write(&d, "parts/nan.dxf", DXF_NAN);
    write(&d, "parts/garbage.svg", "<svg><path d='M 0 0 L'/>");
    write(
        &d,
        "parts/open.svg",
        "<svg xmlns='http://www.w3.org/2000/svg'><path d='M 0 0 L 10 0 L 10 10'/></svg>",
    );
    write(&d, "parts/bad.json", "{\"part\": [[0, 0], [1]]}");
    write(
        &d,
        "parts/good.json",
        "{\"part\": [[0, 0], [40, 0], [40, 30]]}",
    );
    write(&d, "parts/notes.txt", "not a part");
    write(&d, "catalog.toml", ERRORS_MANIFEST);
    d
}

#[test]
fn each_error_names_part_file_and_place() {
    let cat = load_catalog(&manifest_dir()).unwrap();
    assert_eq!(cat.parts.len(), 23);
    let e = part_err(&cat, "bracket-7");
    assert!(e.starts_with("bracket-7: outline: edge "), "{e}");
    assert!(e.contains(" crosses edge ") && e.ends_with(" mm"), "{e}");
    assert_eq!(
        e,
        "bracket-7: outline: edge 0 crosses edge 3 at (12.5, 0) mm"
    );
    assert!(part_err(&cat, "two-points").contains("at least 3"));
    let flat = part_err(&cat, "flat");
    assert!(
        flat.contains("zero area") || flat.contains("crosses"),
        "{flat}"
    );
    let t = part_err(&cat, "touching");
    assert!(
        t.contains("vertex 2 and vertex 5 are the same point (5, 5) mm"),
        "{t}"
    );
    assert!(part_err(&cat, "not-finite").contains("vertex 2 has a non-finite coordinate"));
    let a = part_err(&cat, "bad-access");
    assert!(
        a.starts_with("bad-access: access constraint 0: edge 0 crosses edge 2"),
        "{a}"
    );
    let o = part_err(&cat, "open");
    assert!(o.starts_with("open (parts/open.dxf): open loop:"), "{o}");
    assert!(o.contains("(0, 0)") && o.contains("(10, 10)"), "{o}");
    assert!(part_err(&cat, "empty").contains("no closed loop"));
    assert!(part_err(&cat, "miles").contains("unknown units"));
    assert!(part_err(&cat, "two").contains("more than one outline"));
    assert!(
        part_err(&cat, "nan-dxf").contains("non-finite"),
        "{}",
        part_err(&cat, "nan-dxf")
    );
    assert!(part_err(&cat, "garbage").contains("not a readable SVG"));
    assert!(part_err(&cat, "open-svg").contains("open loop"));
    assert!(part_err(&cat, "bad-json").contains("vertex 1"));
    assert!(part_err(&cat, "missing").contains("cannot read"));
    assert!(part_err(&cat, "txt").contains("unknown file type"));
    assert!(part_err(&cat, "both").contains("either file or outline"));
    assert!(part_err(&cat, "cm").contains("unknown units \"furlong\""));
    assert!(
        part_err(&cat, "typo").contains("typo: manifest entry 22"),
        "{}",
        part_err(&cat, "typo")
    );
    // Duplicate ids: the first stands, the second is reported.
    let goods: Vec<_> = cat.parts.iter().filter(|p| p.id == "good").collect();
    assert!(goods[0].part.is_ok());
    assert_eq!(goods[0].quantity, 12.0);
    let dup = goods[1].part.as_ref().unwrap_err();
    assert!(dup.to_string().contains("duplicate id"));
    assert!(matches!(
        dup.kind,
        PartErrorKind::Entry(EntryProblem::DuplicateId {
            entry: 20,
            first: 19
        })
    ));
    // Repairs are warnings, and the part is usable.
    let dups = cat.parts.iter().find(|p| p.id == "dups").unwrap();
    assert_eq!(dups.part.as_ref().unwrap().outline.len(), 4);
    assert_eq!(dups.warnings.len(), 2, "{:?}", dups.warnings);
    assert!(dups.warnings[0].starts_with("dups: outline: vertex 2 repeats vertex 1 at (10, 0) mm"));
    // Inline outline in inches, converted.
    let gi = cat.parts.iter().find(|p| p.id == "good-inch").unwrap();
    assert_eq!(gi.part.as_ref().unwrap().outline[1], [25.4, 0.0]);
}

#[test]
fn catalogue_level_errors() {
    let d = temp_dir("cat-errors");
    let m = write(&d, "catalog.toml", "name = \"x\"\nunits = \"cm\"\n");
    let e = load_catalog(&m).unwrap_err().to_string();
    assert!(e.contains("unknown units \"cm\""), "{e}");
    let m = write(&d, "catalog.toml", "name = \"x\"\n");
    assert!(load_catalog(&m)
        .unwrap_err()
        .to_string()
        .contains("no units"));
    let m = write(&d, "catalog.toml", "units = \"mm\"\npartz = 1\n");
    assert!(load_catalog(&m)
        .unwrap_err()
        .to_string()
        .contains("unknown manifest field"));
    let m = write(&d, "catalog.toml", "units = [\n");
    assert!(load_catalog(&m)
        .unwrap_err()
        .to_string()
        .contains("not a readable manifest"));
    assert!(load_catalog(&d.join("nope")).is_err());
    let m = write(&d, "catalog.toml", "units = \"mm\"\nchord_tolerance = -1\n");
    assert!(load_catalog(&m)
        .unwrap_err()
        .to_string()
        .contains("chord_tolerance"));
}

#[test]
fn plain_directory_sorted_by_name_with_units_option() {
    let d = temp_dir("dir");
    write(&d, "b.json", "{\"part\": [[0, 0], [2, 0], [0, 2]]}");
    write(
        &d,
        "a.svg",
        "<svg xmlns='http://www.w3.org/2000/svg'><rect width='3' height='1'/></svg>",
    );
    write(&d, "c.dxf", DXF_OPEN);
    write(&d, "readme.md", "ignored");
    let cat = load_catalog(&d).unwrap();
    let ids: Vec<_> = cat.parts.iter().map(|p| p.id.as_str()).collect();
    assert_eq!(ids, ["a", "b", "c"]);
    assert_eq!(cat.units, Units::Mm);
    assert!(cat.parts[2].part.is_err() && cat.parts[0].part.is_ok());
    let opts = LoadOptions {
        units: Some(Units::In),
        ..Default::default()
    };
    let cat = load_catalog_with(&d, &opts).unwrap();
    assert_eq!(cat.units, Units::In);
    assert_eq!(cat.parts[1].part.as_ref().unwrap().outline[1], [2.0, 0.0]);
}

#[test]
fn bad_read_options_are_errors_not_panics() {
    let mut o = ReadOptions::new(Units::Mm);
    o.chord_tolerance = 0.0;
    let e = parse_part(b"{}", Format::Json, &o).unwrap_err();
    assert!(e.to_string().contains("chord tolerance"));
    assert_eq!(e, ParseError::Read(ReadError::ChordTolerance(0.0)));
}
