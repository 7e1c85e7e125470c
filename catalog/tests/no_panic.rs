//! Arbitrary bytes into every parser: an error at worst, never a panic.
//! (The same property runs much longer under cargo-fuzz: catalog/fuzz/.)
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use fixplan_catalog::{read_raw, validate_part, Format, ReadOptions};
use fixplan_core::Units;
use proptest::prelude::*;

fn all_formats(bytes: &[u8]) {
    for format in [Format::Dxf, Format::Svg, Format::Json] {
        for units in [Units::Mm, Units::In] {
            let opts = ReadOptions::new(units);
            if let Ok(raw) = read_raw(bytes, format, &opts) {
                let _ = validate_part(raw, units);
            }
        }
    }
}

/// Text that looks enough like each format to reach deep into the parsers.
fn dxf_like() -> impl Strategy<Value = String> {
    let code = prop::sample::select(vec![0, 8, 10, 20, 11, 21, 40, 42, 50, 51, 70, 90, 210, 230]);
    let value = prop::sample::select(vec![
        "LINE",
        "ARC",
        "CIRCLE",
        "LWPOLYLINE",
        "POLYLINE",
        "VERTEX",
        "SEQEND",
        "ELLIPSE",
        "ACCESS",
        "0",
        "1",
        "-1",
        "1e308",
        "nan",
        "inf",
        "3.5",
        "1e-300",
        "360",
        "-0.4142",
    ]);
    prop::collection::vec((code, value), 0..40).prop_map(|pairs| {
        let mut s = String::from("  0\nSECTION\n  2\nENTITIES\n");
        for (c, v) in pairs {
            s.push_str(&format!("{c:>3}\n{v}\n"));
        }
        s.push_str("  0\nENDSEC\n  0\nEOF\n");
        s
    })
}

fn svg_like() -> impl Strategy<Value = String> {
    let tok = prop::sample::select(vec![
        "M", "m", "L", "l", "H", "h", "V", "v", "C", "c", "S", "s", "Q", "q", "T", "t", "A", "a",
        "Z", "z", "0", "1", "-5", ".5", "1e9", "1e400", "10", ",", " ", "3.2.1", "-", "e",
    ]);
    let tr = prop::sample::select(vec![
        "",
        "scale(0)",
        "scale(1e300)",
        "rotate(45 1 1)",
        "matrix(0 0 0 0 0 0)",
        "translate(1)",
        "skewX(90)",
        "bogus(",
        "scale(nan)",
    ]);
    (prop::collection::vec(tok, 0..60), tr).prop_map(|(toks, t)| {
        format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"1e-9mm\" viewBox=\"0 0 1e-300 1\"><g transform=\"{t}\"><path class=\"access\" d=\"M0 0 h1 v1z\"/><path d=\"{}\"/></g></svg>",
            toks.concat()
        )
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..512)) {
        all_formats(&bytes);
    }

    #[test]
    fn dxf_shaped_text_never_panics(text in dxf_like()) {
        all_formats(text.as_bytes());
    }

    #[test]
    fn svg_shaped_text_never_panics(text in svg_like()) {
        all_formats(text.as_bytes());
    }

    #[test]
    fn json_shaped_text_never_panics(
        nums in prop::collection::vec(prop::sample::select(vec!["0", "-1", "1e308", "1e-320", "2.5", "null", "\"x\"", "[]"]), 0..20),
        units in prop::sample::select(vec!["\"mm\"", "\"in\"", "\"cm\"", "\"au\"", "3"]),
    ) {
        let pts: Vec<String> = nums.chunks(2).map(|c| format!("[{}]", c.join(","))).collect();
        let text = format!("{{\"units\": {units}, \"part\": [{}], \"access\": [[{}]]}}", pts.join(","), pts.join(","));
        all_formats(text.as_bytes());
    }
}
