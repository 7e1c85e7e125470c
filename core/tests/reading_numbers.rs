//! Input numbers are read correctly rounded, as std's `str::parse` reads
//! them, in every build. serde_json's default parse may miss a number of
//! 16 or 17 digits by one ulp, and whether it did depended on the build:
//! jsonschema, a dev-dependency of the tests crate, turns serde_json's
//! `float_roundtrip` on, so `cargo test` builds read bracket-flattened's
//! outline one way and `cargo build` builds another, and six of its ten
//! scores differed in the last digit. The workspace now asks for
//! `float_roundtrip` itself; this test fails in any build without it
//! (`cargo test -p fixplan-core`, whose graph has no jsonschema).
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use fixplan_core::Case;

/// The numbers of a JSON text without strings, in order, read by std.
fn numbers(text: &str) -> Vec<f64> {
    text.split(|c: char| !(c.is_ascii_digit() || matches!(c, '.' | '-' | '+' | 'e' | 'E')))
        .filter(|token| !token.is_empty())
        .map(|token| token.parse().unwrap())
        .collect()
}

/// The text of the `"part"` array of a case file, brackets included.
fn part_text(text: &str) -> &str {
    let key = text.find("\"part\"").unwrap();
    let open = key + text[key..].find('[').unwrap();
    let mut depth = 0;
    for (i, c) in text[open..].char_indices() {
        match c {
            '[' => depth += 1,
            ']' => {
                depth -= 1;
                if depth == 0 {
                    return &text[open..=open + i];
                }
            }
            _ => {}
        }
    }
    panic!("the part array is not closed")
}

/// serde_json's default reading of a decimal (without `float_roundtrip`):
/// the digits as an integer, then one division by a power of ten.
fn naive(token: &str) -> Option<f64> {
    let (whole, fraction) = token.split_once('.')?;
    let digits: u64 = format!("{whole}{fraction}").parse().ok()?;
    let scale = 10f64.powi(i32::try_from(fraction.len()).ok()?);
    #[allow(clippy::cast_precision_loss)] // the rounding is the point
    Some(digits as f64 / scale)
}

#[test]
fn case_outlines_are_read_as_std_reads_them() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/cases");
    let mut naive_misses = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "json") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let case: Case = serde_json::from_str(&text).unwrap();
        let part = part_text(&text);
        let vertices: Vec<&str> = part[1..part.len() - 1]
            .split(']')
            .filter(|v| v.contains('['))
            .collect();
        assert_eq!(vertices.len(), case.part.len(), "{}", path.display());
        for (written, read) in vertices.iter().zip(&case.part) {
            let want = numbers(written);
            let got = [read.x, read.y, read.bulge];
            for (w, g) in want.iter().zip(got) {
                assert_eq!(w.to_bits(), g.to_bits(), "{}: {written}", path.display());
            }
            naive_misses += written
                .split(|c: char| c == '[' || c == ',' || c.is_whitespace())
                .filter_map(|token| Some((token.parse::<f64>().ok()?, naive(token)?)))
                .filter(|(std_read, naive_read)| std_read.to_bits() != naive_read.to_bits())
                .count();
        }
    }
    // The example cases hold numbers the default parse misreads
    // (bracket-flattened's chords), so this test can tell the two apart.
    assert!(naive_misses > 0);
}
