//! `fixplan bench --markdown`, the source of the README's speed table: its
//! counts must be those `fixplan solve --full-counts` reports, since a
//! table that drifted from the solver would mislead every reader of it.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use std::process::Command;

fn fixplan() -> Command {
    Command::new(env!("CARGO_BIN_EXE_fixplan-it"))
}

fn case(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples/cases")
        .join(name)
}

/// Runs `command`, which must succeed, and returns its standard output.
fn stdout_of(command: &mut Command) -> String {
    let out = command.output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// The cells of the Markdown row of `part`, without the leading `|`.
fn row_cells(table: &str, part: &str) -> Vec<String> {
    let row = table
        .lines()
        .find(|l| l.starts_with(&format!("| `{part}`")))
        .unwrap_or_else(|| panic!("no row for {part} in\n{table}"));
    row.trim_matches('|')
        .split('|')
        .map(|cell| cell.trim().replace(',', ""))
        .collect()
}

#[test]
fn markdown_rows_count_what_solve_counts() {
    let table = stdout_of(
        fixplan()
            .args(["bench", "--markdown", "--repeat", "1"])
            .arg(case("gluegun-28.json"))
            .arg(case("rectangle-mm.json")),
    );
    assert!(table.starts_with("| part | edges | segments |"), "{table}");
    for (name, edges) in [("gluegun-28", "28"), ("rectangle-mm", "4")] {
        let solved = stdout_of(
            fixplan()
                .args(["solve", "--full-counts"])
                .arg(case(&format!("{name}.json"))),
        );
        let v: serde_json::Value = serde_json::from_str(&solved).unwrap();
        let counts = &v["counts"];
        let cells = row_cells(&table, name);
        assert_eq!(cells[1], edges, "{name} edges");
        for (column, key) in [
            (2, "segments"),
            (3, "combinations"),
            (4, "setups"),
            (5, "candidates"),
            (6, "admissible"),
        ] {
            assert_eq!(cells[column], counts[key].to_string(), "{name} {key}");
        }
        assert!(
            cells[7].ends_with(" ms") && cells[8].ends_with(" ms"),
            "{cells:?}"
        );
    }
}

#[test]
fn top_k_only_leaves_the_full_columns_empty() {
    let table = stdout_of(
        fixplan()
            .args(["bench", "--markdown", "--top-k-only", "--repeat", "1"])
            .arg(case("rectangle-mm.json")),
    );
    let cells = row_cells(&table, "rectangle-mm");
    assert_eq!(
        (cells[6].as_str(), cells[7].as_str()),
        ("-", "-"),
        "{cells:?}"
    );
    assert!(cells[8].ends_with(" ms"), "{cells:?}");
    let refused = fixplan()
        .args(["bench", "--top-k-only", "--top-k", "0"])
        .arg(case("rectangle-mm.json"))
        .output()
        .unwrap();
    assert!(!refused.status.success());
    assert!(String::from_utf8_lossy(&refused.stderr).contains("--top-k 1 or more"));
}
