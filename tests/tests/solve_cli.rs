//! `fixplan solve`: SPEC Appendix A in and out, and clear failures.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use std::process::Command;

fn fixplan() -> Command {
    Command::new(env!("CARGO_BIN_EXE_fixplan-it"))
}

fn cases() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/cases")
}

#[test]
fn solves_the_appendix_example() {
    let out = fixplan()
        .arg("solve")
        .arg(cases().join("rectangle-mm.json"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["status"], "ok");
    let fixtures = v["fixtures"].as_array().unwrap();
    assert!(
        !fixtures.is_empty() && fixtures.len() <= 3,
        "top_k 3 in the case file"
    );
    assert_eq!(fixtures[0]["rank"], 1);
    assert_eq!(fixtures[0]["locators"][0], serde_json::json!([0, 0]));
    // Top-k mode: the admissible count is left out, and said to be.
    let counts = &v["counts"];
    assert_eq!(counts["counts_exact"], false);
    assert!(counts.get("admissible").is_none(), "{counts}");
    // --full-counts: the same fixtures, every count.
    let out = fixplan()
        .arg("solve")
        .arg("--full-counts")
        .arg(cases().join("rectangle-mm.json"))
        .output()
        .unwrap();
    let full: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(full["fixtures"], v["fixtures"]);
    let counts = &full["counts"];
    assert!(counts.get("counts_exact").is_none(), "{counts}");
    assert!(counts["admissible"].as_u64().unwrap() >= fixtures.len() as u64);
    assert!(counts["candidates"].as_u64() >= counts["admissible"].as_u64());
    assert_eq!(counts["candidates"], v["counts"]["candidates"]);
}

fn solve_text(name: &str, text: &str) -> (i32, serde_json::Value) {
    let dir = std::env::temp_dir().join(format!("fixplan-solve-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.json"));
    std::fs::write(&path, text).unwrap();
    let out = fixplan().arg("solve").arg(&path).output().unwrap();
    std::fs::remove_dir_all(&dir).ok();
    let v = serde_json::from_slice(&out.stdout).unwrap_or(serde_json::Value::Null);
    (out.status.code().unwrap_or(-1), v)
}

#[test]
fn invalid_inputs_say_what_and_where_without_panicking() {
    let base = std::fs::read_to_string(cases().join("rectangle-mm.json")).unwrap();
    let bow = base.replace(
        "[[0,0],[80,0],[80,50],[0,50]]",
        "[[0,0],[80,50],[80,0],[0,50]]",
    );
    let (code, v) = solve_text("bowtie", &bow);
    assert_eq!(code, 2);
    assert_eq!(v["status"], "invalid");
    let msg = v["error"].as_str().unwrap();
    assert!(msg.contains("edge 0 crosses edge 2 at (40, 25)"), "{msg}");

    let big = base.replace("\"locator_radius\": 6.35", "\"locator_radius\": 15.0");
    let (code, v) = solve_text("radius", &big);
    assert_eq!(code, 2);
    assert!(
        v["error"].as_str().unwrap().contains("locator_radius"),
        "{v}"
    );

    let (code, v) = solve_text("garbage", "{\"units\": \"mm\", \"part\": 3");
    assert_eq!(code, 2);
    assert_eq!(v["status"], "invalid");

    let travel = base.replace("[37.0, 70.0]", "[70.0, 37.0]");
    let (code, v) = solve_text("travel", &travel);
    assert_eq!(code, 2);
    assert!(v["error"].as_str().unwrap().contains("travel"), "{v}");
}

#[test]
fn a_part_smaller_than_the_lattice_has_no_fixture() {
    let base = std::fs::read_to_string(cases().join("rectangle-mm.json")).unwrap();
    let tiny = base
        .replace(
            "[[0,0],[80,0],[80,50],[0,50]]",
            "[[0,0],[12,0],[12,8],[0,8]]",
        )
        .replace("\"access\": [[[10,40],[30,40],[30,60],[10,60]]],", "");
    let (code, v) = solve_text("tiny", &tiny);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["status"], "no_fixture");
    assert_eq!(v["fixtures"].as_array().unwrap().len(), 0);
}
