//! `cargo +nightly fuzz run parse_part` (from catalog/): arbitrary bytes
//! into every part parser and the validation after it; any panic is a bug.
#![no_main]

use fixplan_catalog::{read_raw, validate_part, Format, ReadOptions};
use fixplan_core::Units;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // The first byte picks the format and units, so the fuzzer can steer.
    let Some((&sel, bytes)) = data.split_first() else {
        return;
    };
    let format = match sel % 3 {
        0 => Format::Dxf,
        1 => Format::Svg,
        _ => Format::Json,
    };
    let units = if sel & 4 == 0 { Units::Mm } else { Units::In };
    let opts = ReadOptions::new(units);
    if let Ok(raw) = read_raw(bytes, format, &opts) {
        let _ = validate_part(raw, units);
    }
});
