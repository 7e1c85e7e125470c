//! part -> file -> part, for each format and both units: the writers are
//! exact inverses of the readers.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use fixplan_catalog::{parse_part, write_dxf, write_json, write_svg, Format, ReadOptions};
use fixplan_core::{Part, Units};
use proptest::prelude::*;

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

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]
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
