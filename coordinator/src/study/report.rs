//! The study as text: the terminal table and the CSV (one row per kit, for
//! a spreadsheet).

use super::messages::StudyReport;

fn opt(value: Option<f64>, prec: usize) -> String {
    value.map_or("-".into(), |v| format!("{v:.prec$}"))
}

/// The terminal table: a row per kit, then the parts no kit holds and the
/// work shared.
pub fn table(rep: &StudyReport) -> String {
    let w = rep
        .kits
        .iter()
        .map(|k| k.name.chars().count())
        .max()
        .unwrap_or(3)
        .max(3);
    let mut s = format!(
        "{:>3}  {:<w$}  {:>7}  {:>6}  {:>9}  {:>7}  {:>7}  {:>6}  {:>7}  {:>7}\n",
        "#", "kit", "held", "held%", "qty held%", "median", "p90", "no fix", "invalid", "time s"
    );
    for k in &rep.kits {
        s.push_str(&format!(
            "{:>3}  {:<w$}  {:>7}  {:>5.1}%  {:>8.1}%  {:>7}  {:>7}  {:>6}  {:>7}  {:>7.2}\n",
            k.index + 1,
            k.name,
            format!("{}/{}", k.held, k.parts),
            k.held_pct,
            k.held_quantity_pct,
            opt(k.median_score, 4),
            opt(k.p90_score, 4),
            k.no_fixture,
            k.invalid,
            k.time_ms / 1e3
        ));
    }
    let sm = &rep.summary;
    if sm.unheld.is_empty() {
        s.push_str("every part is held by at least one kit\n");
    } else {
        s.push_str(&format!(
            "parts no kit holds ({}): {}\n",
            sm.unheld.len(),
            sm.unheld.join(", ")
        ));
    }
    s.push_str(&format!(
        "work: {} part runs, {} enumerated, {} shared ({} same kit, {} no fixture on a larger plate); {:.2} s\n",
        sm.part_runs,
        sm.enumerated,
        sm.shared_same_kit + sm.shared_larger_plate,
        sm.shared_same_kit,
        sm.shared_larger_plate,
        sm.elapsed_ms / 1e3
    ));
    s
}

fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// One row per kit, for a spreadsheet (names with commas or quotes quoted).
pub fn csv(rep: &StudyReport) -> String {
    let mut s = String::from(
        "index,kit,base,sweep,parts,held,held_pct,held_quantity_pct,median_score,p90_score,no_fixture,invalid,time_ms,enumerated,shared\n",
    );
    let num = |x: Option<f64>| x.map_or(String::new(), |v| format!("{v}"));
    for k in &rep.kits {
        s.push_str(&format!(
            "{},{},{},{},{},{},{:.3},{:.3},{},{},{},{},{:.3},{},{}\n",
            k.index + 1,
            csv_field(&k.name),
            csv_field(&k.base),
            csv_field(k.sweep.as_deref().unwrap_or("")),
            k.parts,
            k.held,
            k.held_pct,
            k.held_quantity_pct,
            num(k.median_score),
            num(k.p90_score),
            k.no_fixture,
            k.invalid,
            k.time_ms,
            k.enumerated,
            k.shared
        ));
    }
    s
}
