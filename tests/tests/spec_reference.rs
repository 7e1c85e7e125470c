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

type Key = (Vec<u64>, Vec<Vec<i64>>, u64, u64, Vec<i64>, i64);

fn fixtures(v: &Value) -> BTreeMap<Key, (f64, bool)> {
    let mut m = BTreeMap::new();
    for f in v["fixtures"].as_array().unwrap() {
        let theta = f["pose"]["theta_deg"]
            .as_f64()
            .or(f["theta_deg"].as_f64())
            .unwrap();
        let key: Key = (
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
        let (ours, theirs) = (solve(&path), reference(&path));
        let name = case.file_name().unwrap().to_string_lossy();
        compared += agree(&name, &ours, &theirs, false);
    }
    assert!(compared > 5000, "only {compared} fixtures compared");
}

fn solve(path: &Path) -> Value {
    run(Command::new(env!("CARGO_BIN_EXE_fixplan-it"))
        .arg("solve")
        .arg(path))
}

fn reference(path: &Path) -> Value {
    run(Command::new("python3")
        .arg(repo().join("scripts/spec_reference.py"))
        .arg(path))
}

/// Whether our result and the reference's agree as far as SPEC lets two
/// implementations differ; the number of fixtures compared. With
/// `borderline_counts`, setups and candidates may also differ by the
/// fixtures one side alone finds (all borderline, checked): a tangential
/// setup, such as two locators at the ends of a bore's diameter, counts
/// its candidates on one side only.
fn agree(name: &str, ours: &Value, theirs: &Value, borderline_counts: bool) -> usize {
    let mut compared = 0;
    if theirs.get("segment_kinds").is_some() {
        assert_eq!(
            ours["segment_kinds"], theirs["segment_kinds"],
            "{name}: segment kinds"
        );
    }
    for k in ["segments", "combinations"] {
        assert_eq!(ours["counts"][k], theirs["counts"][k], "{name}: {k}");
    }
    let (a, b) = (fixtures(ours), fixtures(theirs));
    // admissible counts may differ only by fixtures one side alone finds,
    // and each of those must be borderline (checked below)
    let one_sided = a.keys().filter(|k| !b.contains_key(*k)).count()
        + b.keys().filter(|k| !a.contains_key(*k)).count();
    let slack = if borderline_counts {
        one_sided as f64
    } else {
        0.0
    };
    for k in ["setups", "candidates"] {
        let (x, y) = (
            ours["counts"][k].as_f64().unwrap(),
            theirs["counts"][k].as_f64().unwrap(),
        );
        assert!(
            (x - y).abs() <= 0.01 * x.max(y) + slack,
            "{name}: {k} {x} vs {y}"
        );
    }
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
    compared
}

/// SPEC 9: every case of `scripts/spec_cases_holes/` (washers, a plate
/// with a bore, a window plate, a narrow slot, a bore near an edge, a
/// frame whose clamp body fits its window, a flange with bolt holes, a
/// slot listed both ways, four invalid parts). Invalid parts give the
/// reference's message; valid ones the same segments, loops and fixtures.
#[test]
fn the_independent_python_reading_agrees_on_parts_with_holes() {
    if Command::new("python3").arg("--version").output().is_err() {
        eprintln!("skipped: no python3 on this machine");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut cases: Vec<PathBuf> = std::fs::read_dir(repo().join("scripts/spec_cases_holes"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    cases.sort();
    assert_eq!(cases.len(), 14, "the hole cases");
    let paths: Vec<PathBuf> = cases
        .iter()
        .map(|c| with_all_fixtures(c, dir.path()))
        .collect();
    // The reference takes seconds a case: two at a time (CI's two cores).
    let half = paths.len().div_ceil(2);
    let theirs: Vec<Value> = std::thread::scope(|s| {
        let parts: Vec<_> = paths
            .chunks(half)
            .map(|chunk| {
                s.spawn(move || {
                    chunk
                        .iter()
                        .map(|p| {
                            any_status(
                                Command::new("python3")
                                    .arg(repo().join("scripts/spec_reference.py"))
                                    .arg(p),
                            )
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        parts.into_iter().flat_map(|h| h.join().unwrap()).collect()
    });
    let (mut compared, mut invalid, mut on_holes) = (0, 0, 0);
    for (path, theirs) in paths.iter().zip(&theirs) {
        let ours = any_status(
            Command::new(env!("CARGO_BIN_EXE_fixplan-it"))
                .arg("solve")
                .arg(path),
        );
        let name = path.file_name().unwrap().to_string_lossy();
        assert_eq!(ours["status"], theirs["status"], "{name}: status");
        if theirs["status"] == "invalid" {
            let (a, b) = (
                ours["error"].as_str().unwrap(),
                theirs["error"].as_str().unwrap(),
            );
            assert!(a.ends_with(b), "{name}: {a:?} vs {b:?}");
            invalid += 1;
            continue;
        }
        assert_eq!(
            ours["segment_loops"], theirs["segment_loops"],
            "{name}: segment loops"
        );
        compared += agree(&name, &ours, theirs, true);
        let loops = ours["segment_loops"].as_array().unwrap();
        let on_hole = |s: &Value| loops[s.as_u64().unwrap() as usize].as_u64().unwrap() > 0;
        on_holes += ours["fixtures"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|f| {
                f["segments"].as_array().unwrap().iter().any(on_hole)
                    || on_hole(&f["clamp"]["segment"])
            })
            .count();
    }
    assert_eq!(invalid, 4);
    assert!(
        compared > 10000 && on_holes > 3000,
        "only {compared} fixtures compared, {on_holes} on hole walls"
    );
}

/// A result whatever the exit code (invalid parts exit non-zero).
fn any_status(cmd: &mut Command) -> Value {
    let out = cmd.output().expect("runs");
    serde_json::from_slice(&out.stdout).expect("JSON result")
}
