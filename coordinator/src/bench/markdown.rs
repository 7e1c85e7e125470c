//! `fixplan bench --markdown`: the README's speed table, as rows to paste
//! (or for `scripts/speed_table.py` to write in place), so the table's
//! figures always come from one command rather than from hand copies.

use super::parts::{Measured, PartMeasured};

/// The table's header: counts of SPEC 3-4, then the two modes' times.
pub fn print_header(top_k: usize) {
    println!(
        "| part | edges | segments | combinations | setups | candidates | admissible | full counts | top-{top_k} mode |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
}

/// One part's row. Counts come from the full run when there is one (it
/// counts admissible fixtures), else from the top-k run, whose setups and
/// candidates are the same (SPEC 4 counts them before any pruning by score).
pub fn print_part(part: &PartMeasured) {
    let Some(counted) = part.full.as_ref().or(part.fast.as_ref()) else {
        return;
    };
    let counts = &counted.result.counts;
    let admissible = part
        .full
        .as_ref()
        .and_then(|full| full.result.counts.admissible())
        .map_or_else(|| "-".to_string(), thousands);
    println!(
        "| `{}` | {} | {} | {} | {} | {} | {} | {} | {} |",
        part.id,
        thousands(part.edges as u64),
        thousands(counts.segments),
        thousands(counts.combinations),
        thousands(counts.setups),
        thousands(counts.candidates),
        admissible,
        wall(part.full.as_ref()),
        wall(part.fast.as_ref()),
    );
}

/// A mode's wall time with as many digits as the run-to-run noise leaves
/// meaningful: hundredths of a millisecond under 10 ms, tenths under 100,
/// whole milliseconds under a second, then seconds to two decimals.
fn wall(measured: Option<&Measured>) -> String {
    let Some(measured) = measured else {
        return "-".to_string();
    };
    let ms = measured.wall as f64 / 1e6;
    match ms {
        ms if ms < 10.0 => format!("{ms:.2} ms"),
        ms if ms < 100.0 => format!("{ms:.1} ms"),
        ms if ms < 1000.0 => format!("{ms:.0} ms"),
        ms => format!("{:.2} s", ms / 1000.0),
    }
}

/// `1311` as `1,311`: the README's tables group digits.
fn thousands(value: u64) -> String {
    let digits = value.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (index, digit) in digits.chars().enumerate() {
        if index > 0 && (digits.len() - index).is_multiple_of(3) {
            out.push(',');
        }
        out.push(digit);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::thousands;

    #[test]
    fn groups_digits_by_three() {
        assert_eq!(thousands(0), "0");
        assert_eq!(thousands(999), "999");
        assert_eq!(thousands(1311), "1,311");
        assert_eq!(thousands(5_808_149), "5,808,149");
        assert_eq!(thousands(100_000), "100,000");
    }
}
