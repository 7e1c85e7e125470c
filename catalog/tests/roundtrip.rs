//! part -> file -> part, for each format and both units: the writers are
//! exact inverses of the readers, arcs included.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use fixplan_catalog::{parse_part, write_dxf, write_json, write_svg, Format, ReadOptions};
use fixplan_core::parts::validate_outline;
use fixplan_core::{Part, Units, Vertex};
use proptest::prelude::*;

/// A part with every kind of arc: a convex fillet (bulge tan(pi/8)), a
/// concave notch, a large arc (|b| > 1) and a half circle.
fn arc_sample() -> Part {
    let v = Vertex::new;
    Part {
        holes: Vec::new(),
        outline: vec![
            v(0.0, 0.0, 0.0),
            v(100.0, 0.0, 0.41421356237309503),
            v(110.0, 10.0, 0.0),
            v(110.0, 40.0, 1.0),
            v(110.0, 60.0, 0.0),
            v(70.0, 60.0, -0.5),
            v(40.0, 60.0, 0.0),
            v(0.0, 60.0, 0.0),
            v(0.0, 40.0, 2.5),
            v(0.0, 30.0, 0.0),
        ],
        access: vec![vec![[10.0, 35.0], [30.0, 35.0], [30.0, 50.0], [10.0, 50.0]]],
    }
}

fn sample() -> Part {
    Part {
        access: vec![vec![[10.0, 35.0], [30.0, 35.0], [30.0, 50.0], [10.0, 50.0]]],
        ..Part::polygon(&[
            [0.0, 0.0],
            [120.25, 0.0],
            [120.25, 40.0],
            [80.0, 40.0],
            [60.125, 62.5],
            [0.0, 40.0],
        ])
    }
}

fn round_trip(part: &Part, units: Units, format: Format) -> Part {
    let text = match format {
        Format::Dxf => write_dxf(part, units),
        Format::Svg => write_svg(part, units),
        Format::Json => write_json(part, units),
    };
    let (p, w) = parse_part(text.as_bytes(), format, &ReadOptions::new(units))
        .unwrap_or_else(|e| panic!("{format:?}: {e}\n{text}"));
    assert!(w.is_empty(), "{w:?}");
    p
}

#[test]
fn each_format_round_trips_exactly() {
    for units in [Units::Mm, Units::In] {
        for format in [Format::Dxf, Format::Svg, Format::Json] {
            assert_eq!(
                round_trip(&sample(), units, format),
                sample(),
                "{format:?} {units:?}"
            );
        }
    }
}

#[test]
fn arc_parts_round_trip_exactly() {
    let part = arc_sample();
    assert!(validate_outline(&part.outline).is_ok());
    for units in [Units::Mm, Units::In] {
        for format in [Format::Dxf, Format::Svg, Format::Json] {
            assert_eq!(
                round_trip(&part, units, format),
                part,
                "{format:?} {units:?}"
            );
        }
    }
    // The files say arcs in their own words.
    assert!(write_dxf(&part, Units::Mm).contains(" 42\n0.41421356237309503\n"));
    assert!(write_svg(&part, Units::Mm).contains(" A 10.0,10.0 0 0 0 110.0,-10.0"));
    assert!(write_json(&part, Units::Mm).contains("0.41421356237309503"));
    // A circle: two half arcs.
    let circle = Part {
        outline: vec![Vertex::new(30.0, 5.0, 1.0), Vertex::new(-10.0, 5.0, 1.0)],
        holes: Vec::new(),
        access: Vec::new(),
    };
    for format in [Format::Dxf, Format::Svg, Format::Json] {
        assert_eq!(round_trip(&circle, Units::Mm, format), circle, "{format:?}");
    }
}

#[test]
fn files_written_in_inches_read_into_mm() {
    let inch = Part::polygon(&[[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]);
    for (format, text) in [
        (Format::Dxf, write_dxf(&inch, Units::In)),
        (Format::Svg, write_svg(&inch, Units::In)),
        (Format::Json, write_json(&inch, Units::In)),
    ] {
        let (p, _) = parse_part(text.as_bytes(), format, &ReadOptions::new(Units::Mm)).unwrap();
        assert_eq!(p.outline[2], [50.8, 25.4], "{format:?}");
    }
}

/// Random star-shaped polygons (always simple): vertices at increasing
/// angles with random radii.
fn star_polygon() -> impl Strategy<Value = Vec<[f64; 2]>> {
    prop::collection::vec((0.2f64..1.0, 5.0f64..100.0), 3..24).prop_map(|v| {
        let n = v.len();
        v.iter()
            .enumerate()
            .map(|(i, (jitter, r))| {
                let a = (i as f64 + 0.5 * jitter) / n as f64 * std::f64::consts::TAU;
                [r * a.cos() + 200.0, r * a.sin() - 50.0]
            })
            .collect()
    })
}

/// Random star polygons with random bulges on some edges (convex and
/// concave, up to a quarter turn each way); invalid draws are skipped.
fn arc_outline() -> impl Strategy<Value = Vec<Vertex>> {
    star_polygon().prop_flat_map(|pts| {
        let n = pts.len();
        (
            Just(pts),
            prop::collection::vec(prop_oneof![Just(0.0), -0.4f64..0.4], n),
        )
            .prop_map(|(pts, bulges)| {
                pts.iter()
                    .zip(bulges)
                    .map(|(p, b)| Vertex::new(p[0], p[1], b))
                    .collect()
            })
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]
    #[test]
    fn random_arc_parts_round_trip(outline in arc_outline(), inch in any::<bool>()) {
        let units = if inch { Units::In } else { Units::Mm };
        let part = Part {
            outline,
            holes: Vec::new(),
            access: Vec::new(),
        };
        // Skip invalid draws and those that validation repairs (collinear
        // vertices between straight edges).
        let repaired = || {
            parse_part(write_dxf(&part, units).as_bytes(), Format::Dxf, &ReadOptions::new(units))
                .map_or(true, |(_, w)| !w.is_empty())
        };
        prop_assume!(validate_outline(&part.outline).is_ok() && !repaired());
        for format in [Format::Dxf, Format::Svg, Format::Json] {
            prop_assert_eq!(&round_trip(&part, units, format), &part);
        }
    }

    #[test]
    fn random_parts_round_trip(outline in star_polygon(), inch in any::<bool>()) {
        let units = if inch { Units::In } else { Units::Mm };
        let part = Part::polygon(&outline);
        // Skip the rare draw that validation repairs (collinear vertices).
        if parse_part(write_json(&part, units).as_bytes(), Format::Json, &ReadOptions::new(units))
            .is_ok_and(|(p, w)| w.is_empty() && p == part)
        {
            for format in [Format::Dxf, Format::Svg] {
                prop_assert_eq!(&round_trip(&part, units, format), &part);
            }
        }
    }
}
