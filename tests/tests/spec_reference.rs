//! A second, independent reading of SPEC: `scripts/spec_reference.py` was
//! written from SPEC.md alone (without looking at the Rust code) and must
//! find the same fixtures. Counts may differ only by setups within rounding
//! of a decision boundary; fixture sets must match except for fixtures either
//! side flags as borderline, and scores must agree closely.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn with_all_fixtures(case: &Path, dir: &Path) -> PathBuf {
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(case).unwrap()).unwrap();
    v["params"]["top_k"] = 0.into();
    let out = dir.join(case.file_name().unwrap());
    std::fs::write(&out, v.to_string()).unwrap();
    out
}

fn run(cmd: &mut Command) -> Value {
    let out = cmd.output().expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON result")
}

type ReferenceKey = (Vec<u64>, Vec<Vec<i64>>, u64, u64, Vec<i64>, i64);

fn fixtures(v: &Value) -> BTreeMap<ReferenceKey, (f64, bool)> {
    let mut m = BTreeMap::new();
    for f in v["fixtures"].as_array().unwrap() {
        let theta = f["pose"]["theta_deg"]
            .as_f64()
            .or(f["theta_deg"].as_f64())
            .unwrap();
        let key: ReferenceKey = (
            serde_json::from_value(f["segments"].clone()).unwrap(),
            serde_json::from_value(f["locators"].clone()).unwrap(),
            f["clamp"]["segment"].as_u64().unwrap(),
            f["clamp"]["rotation_deg"].as_u64().unwrap(),
            serde_json::from_value(f["clamp"]["mount"].clone()).unwrap(),
            (theta * 1e4).round() as i64,
        );
        m.insert(
            key,
            (
                // a (borderline, nearly singular) fixture may have no finite
                // score: JSON null; it then only passes as borderline
                f["score"].as_f64().unwrap_or(f64::INFINITY),
                f["borderline"].as_bool().unwrap(),
            ),
        );
    }
    m
}

#[test]
fn the_independent_python_reading_finds_the_same_fixtures() {
    if Command::new("python3").arg("--version").output().is_err() {
        eprintln!("skipped: no python3 on this machine");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        repo().join("examples/cases/rectangle-mm.json"),
        repo().join("examples/cases/gluegun-28.json"),
        repo().join("scripts/spec_cases/l-shape.json"),
        repo().join("scripts/spec_cases/notched-alt-access.json"),
        repo().join("scripts/spec_cases/pentagon-90.json"),
        // SPEC 8: outlines with circular arcs
        repo().join("scripts/spec_cases/arc-fillet-rect.json"),
        repo().join("scripts/spec_cases/arc-d-shape.json"),
        repo().join("scripts/spec_cases/arc-stadium.json"),
        repo().join("scripts/spec_cases/arc-notch-access.json"),
        repo().join("scripts/spec_cases/arc-keyhole.json"),
        repo().join("examples/cases/bracket-arcs.json"),
    ];
    let mut compared = 0;
    for case in &cases {
        let path = with_all_fixtures(case, dir.path());
        let ours = run(Command::new(env!("CARGO_BIN_EXE_fixplan-it"))
            .arg("solve")
            .arg(&path));
        let theirs = run(Command::new("python3")
            .arg(repo().join("scripts/spec_reference.py"))
            .arg(&path));
        let name = case.file_name().unwrap().to_string_lossy();
        if theirs.get("segment_kinds").is_some() {
            assert_eq!(
                ours["segment_kinds"], theirs["segment_kinds"],
                "{name}: segment kinds"
            );
        }
        for k in ["segments", "combinations"] {
            assert_eq!(ours["counts"][k], theirs["counts"][k], "{name}: {k}");
        }
        for k in ["setups", "candidates"] {
            let (a, b) = (
                ours["counts"][k].as_f64().unwrap(),
                theirs["counts"][k].as_f64().unwrap(),
            );
            assert!((a - b).abs() <= 0.01 * a.max(b), "{name}: {k} {a} vs {b}");
        }
        let (a, b) = (fixtures(&ours), fixtures(&theirs));
        // admissible counts may differ only by fixtures one side alone finds,
        // and each of those must be borderline (checked below)
        let one_sided = a.keys().filter(|k| !b.contains_key(*k)).count()
            + b.keys().filter(|k| !a.contains_key(*k)).count();
        let (na, nb) = (
            ours["counts"]["admissible"].as_u64().unwrap(),
            theirs["counts"]["admissible"].as_u64().unwrap(),
        );
        assert!(
            na.abs_diff(nb) <= one_sided as u64,
            "{name}: admissible {na} vs {nb}"
        );
        for (k, (sa, ba)) in &a {
            assert!(
                sa.is_finite() || *ba,
                "{name}: no score, not borderline: {k:?}"
            );
            match b.get(k) {
                Some((sb, bb)) => {
                    assert!(
                        (sa - sb).abs() <= 1e-6 * sa.abs().max(1.0) || *ba || *bb,
                        "{name}: score {sa} vs {sb} for {k:?}"
                    );
                    compared += 1;
                }
                None => assert!(*ba, "{name}: only we find {k:?}"),
            }
        }
        for (k, (_, bb)) in &b {
            assert!(
                a.contains_key(k) || *bb,
                "{name}: only the reference finds {k:?}"
            );
        }
    }
    assert!(compared > 5000, "only {compared} fixtures compared");
}
