//! `fixplan study`, `run --grid-steps` and `run --good-enough` through the
//! built binary, checked against plain `fixplan run` calls read back with
//! `fixplan export --json`.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use fixplan_catalog::kit::write_kit_toml;
use fixplan_coordinator::StepField;
use fixplan_coordinator::{read_mcap, StudyKitMsg};
use fixplan_core::{Counts, FixtureReport, Kit, Params, Units};
use fixplan_tests::ok;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

#[path = "support/schema_check.rs"]
mod schema_check;

fn fixplan() -> Command {
    Command::new(env!("CARGO_BIN_EXE_fixplan-it"))
}

/// Parts of the sample catalogue (inline copies) with quantities: some
/// held by both kits, one held only on a big enough plate, tiny ones that
/// nothing holds, and an invalid one.
const CATALOG: &str = r#"name = "study-test"
units = "mm"

[[part]]
id = "bracket-2"
outline = [[0, 0], [100, 0], [100, 20], [35, 20], [35, 70], [0, 70]]
quantity = 2400.0

[[part]]
id = "l-profile-1"
outline = [[0, 0], [80, 0], [80, 15], [15, 15], [15, 60], [0, 60]]
quantity = 5000.0

[[part]]
id = "z-clip"
outline = [[0, 0], [60, 0], [60, 30], [100, 30], [100, 45], [45, 45], [45, 15], [0, 15]]

[[part]]
id = "plate-120"
outline = [[0, 0], [120, 0], [120, 70], [0, 70]]
quantity = 300.0

[[part]]
id = "tiny-tab"
outline = [[0, 0], [5, 0], [5, 4], [0, 4]]
quantity = 10.0

[[part]]
id = "bowtie"
outline = [[0, 0], [50, 50], [50, 0], [0, 50]]
"#;

fn setup(dir: &Path) -> PathBuf {
    let p = dir.join("catalog.toml");
    std::fs::write(&p, CATALOG).unwrap();
    p
}

fn export(results: &Path) -> Vec<Value> {
    let out = ok(fixplan()
        .args(["export", "--json"])
        .arg(results)
        .output()
        .unwrap());
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

/// `/fixplan/part` messages of a results file, by part id.
fn part_msgs(results: &Path) -> BTreeMap<String, Value> {
    let bytes = std::fs::read(results).unwrap();
    let mut out = BTreeMap::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        if m.channel.topic == "/fixplan/part" {
            let v: Value = serde_json::from_slice(&m.data).unwrap();
            out.insert(v["id"].as_str().unwrap().to_string(), v);
        }
    }
    out
}

fn fixtures_channel(results: &Path) -> Vec<Vec<u8>> {
    let bytes = std::fs::read(results).unwrap();
    mcap::MessageStream::new(&bytes)
        .unwrap()
        .map(|m| m.unwrap())
        .filter(|m| m.channel.topic == "/fixplan/fixtures")
        .map(|m| m.data.to_vec())
        .collect()
}

fn median(s: &[f64]) -> Option<f64> {
    let n = s.len();
    if n == 0 {
        None
    } else if n % 2 == 1 {
        Some(s[n / 2])
    } else {
        Some((s[n / 2 - 1] + s[n / 2]) / 2.0)
    }
}

fn p90(s: &[f64]) -> Option<f64> {
    // Nearest rank: the smallest value with at least 90% of the values at
    // or below it.
    (1..=s.len())
        .find(|&r| r as f64 >= 0.9 * s.len() as f64)
        .map(|r| s[r - 1])
}

/// Runs `fixplan run` with a study kit written as a kit file (top_k 10, not
/// the study's 1) and checks the study's numbers for that kit.
fn check_against_run(dir: &Path, catalog: &Path, k: &StudyKitMsg, quantities: &[f64]) {
    let mut params = Params::from(&k.params);
    params.top_k = 10;
    let kit_file = dir.join(format!("kit-{}.toml", k.index));
    std::fs::write(
        &kit_file,
        write_kit_toml(&k.name, &Kit::from(&k.kit), &params, Units::Mm),
    )
    .unwrap();
    let out = dir.join(format!("run-{}.mcap", k.index));
    ok(fixplan()
        .args(["run", "-q", "--catalog"])
        .arg(catalog)
        .arg("--kit")
        .arg(&kit_file)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap());
    let lines = export(&out);
    assert_eq!(lines.len(), k.results.len());
    let mut held = 0;
    let mut held_q = 0.0;
    let mut scores = Vec::new();
    let mut no_fixture = 0;
    let mut invalid = 0;
    for ((line, row), q) in lines.iter().zip(&k.results).zip(quantities) {
        assert_eq!(line["part"], row.id.as_str());
        let status = line["status"].as_str().unwrap();
        assert_eq!(
            serde_json::to_value(row.status).unwrap(),
            status,
            "{} {}",
            k.name,
            row.id
        );
        let counts = serde_json::to_value(row.counts.as_ref().map(Counts::from)).unwrap();
        assert_eq!(
            line.get("counts").cloned().unwrap_or(Value::Null),
            counts,
            "{} {} (shared: {:?})",
            k.name,
            row.id,
            row.shared
        );
        let best = line["fixtures"]
            .get(0)
            .map(|f| f["score"].as_f64().unwrap());
        assert_eq!(best, row.best_score, "{} {}", k.name, row.id);
        match status {
            "ok" => {
                held += 1;
                held_q += q;
                scores.push(best.unwrap());
            }
            "no_fixture" => no_fixture += 1,
            _ => invalid += 1,
        }
    }
    scores.sort_by(f64::total_cmp);
    let total_q: f64 = quantities.iter().sum();
    assert_eq!(k.held, held, "{}", k.name);
    assert_eq!(k.no_fixture, no_fixture);
    assert_eq!(k.invalid, invalid);
    assert!((k.held_quantity_pct - 100.0 * held_q / total_q).abs() < 1e-9);
    assert!((k.held_pct - 100.0 * held as f64 / lines.len() as f64).abs() < 1e-9);
    assert_eq!(k.median_score, median(&scores), "{}", k.name);
    assert_eq!(k.p90_score, p90(&scores), "{}", k.name);
}

/// Every message of a study file (kits of a sweep) valid against its
/// channel's embedded schema, and no object schema without `properties`.
#[test]
fn every_message_of_a_study_validates_against_its_schema() {
    let dir = tempfile::tempdir().unwrap();
    let catalog = setup(dir.path());
    let mcap_path = dir.path().join("study.mcap");
    ok(fixplan()
        .args(["study", "--catalog"])
        .arg(&catalog)
        .args(["--kit", "metric-25", "--kit", "paper-inch"])
        .args(["--sweep", "plate=4x4,20x20"])
        .arg("-o")
        .arg(&mcap_path)
        .output()
        .unwrap());
    let counts = schema_check::validate_every_message(&std::fs::read(&mcap_path).unwrap());
    let kits = read_mcap(&mcap_path).unwrap().0.len();
    assert!(kits > 2, "{kits} kits");
    let expected: BTreeMap<String, usize> = [
        ("/fixplan/study".to_string(), kits),
        ("/fixplan/study_summary".to_string(), 1),
    ]
    .into_iter()
    .collect();
    assert_eq!(counts, expected);
}

#[test]
fn study_agrees_with_separate_runs() {
    let dir = tempfile::tempdir().unwrap();
    let catalog = setup(dir.path());
    let mcap_path = dir.path().join("study.mcap");
    let csv = dir.path().join("study.csv");
    let svg = dir.path().join("study.svg");
    // metric-25 is 20x20: the sweep's 20x20 point is the same kit (shared),
    // and 4x4 is dominated by 20x20 (no-fixture parts are not enumerated).
    let out = ok(fixplan()
        .args(["study", "--catalog"])
        .arg(&catalog)
        .args(["--kit", "metric-25", "--kit", "paper-inch"])
        .args(["--sweep", "plate=4x4,20x20; locator_radius=6 mm"])
        .arg("-o")
        .arg(&mcap_path)
        .arg("--csv")
        .arg(&csv)
        .arg("--chart")
        .arg(&svg)
        .output()
        .unwrap());
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(
        table.contains("metric-25{plate=4x4, locator_radius=6}"),
        "{table}"
    );
    assert!(table.contains("parts no kit holds"), "{table}");
    let (kits, summary) = read_mcap(&mcap_path).unwrap();
    let summary = summary.unwrap();
    assert_eq!(kits.len(), 6);
    assert!(summary.shared_same_kit >= 6, "{summary:?}");
    assert!(summary.shared_larger_plate >= 2, "{summary:?}");
    assert!(summary.unheld.contains(&"tiny-tab".to_string()));
    assert!(summary.unheld.contains(&"bowtie".to_string()));
    let quantities = [2400.0, 5000.0, 1.0, 300.0, 10.0, 1.0];
    for k in &kits {
        check_against_run(dir.path(), &catalog, k, &quantities);
    }
    // CSV: a header and one row per kit; the chart is an SVG naming each kit.
    let csv = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(csv.lines().count(), 7);
    assert!(csv.starts_with("index,kit,base,sweep,parts,held"));
    let svg = std::fs::read_to_string(&svg).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    for k in &kits {
        assert!(svg.contains(&k.name), "{}", k.name);
    }
    // Sharing changes no number.
    let plain = dir.path().join("noshare.mcap");
    ok(fixplan()
        .args(["study", "-q", "--no-share", "--catalog"])
        .arg(&catalog)
        .args(["--kit", "metric-25", "--kit", "paper-inch"])
        .args(["--sweep", "plate=4x4,20x20; locator_radius=6 mm"])
        .arg("-o")
        .arg(&plain)
        .output()
        .unwrap());
    let (kits2, s2) = read_mcap(&plain).unwrap();
    assert_eq!(s2.unwrap().enumerated, 36);
    let strip = |ks: &[StudyKitMsg]| -> Vec<Value> {
        ks.iter()
            .map(|k| {
                let mut v = serde_json::to_value(k).unwrap();
                v["time_ms"] = Value::Null;
                v["enumerated"] = Value::Null;
                v["shared"] = Value::Null;
                for r in v["results"].as_array_mut().unwrap() {
                    r["ms"] = Value::Null;
                    r.as_object_mut().unwrap().remove("shared");
                }
                v
            })
            .collect()
    };
    assert_eq!(strip(&kits), strip(&kits2));
}

#[test]
fn study_on_workers_matches_embedded() {
    let dir = tempfile::tempdir().unwrap();
    let catalog = setup(dir.path());
    let run = |extra: &[&str], out: &Path| {
        ok(fixplan()
            .args(["study", "-q", "--catalog"])
            .arg(&catalog)
            .args(["--kit", "metric-25", "--sweep", "plate=4x4,12x12"])
            .args(extra)
            .arg("-o")
            .arg(out)
            .output()
            .unwrap());
        let (kits, _) = read_mcap(out).unwrap();
        kits.into_iter()
            .map(|k| {
                k.results
                    .into_iter()
                    .map(|r| (r.id, r.status, r.counts, r.best_score, r.shared))
                    .collect::<Vec<_>>()
            })
            .collect::<Vec<_>>()
    };
    let a = run(&[], &dir.path().join("a.mcap"));
    let b = run(&["--workers", "2"], &dir.path().join("b.mcap"));
    assert_eq!(a, b);
}

#[test]
fn study_rejects_bad_sweeps_before_any_work() {
    let out = fixplan()
        .args(["study", "--kit", "metric-25", "--sweep", "travel=30 mm"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("metric-25{travel=30}") && err.contains("travel min 60 is above max 30"),
        "{err}"
    );
    let out = fixplan()
        .args(["study", "--sweep", "radius=4"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown key \"radius\""));
}

fn kit_with_step(dir: &Path, step: u32) -> PathBuf {
    let spec = fixplan_catalog::load_kit("metric-25", Units::Mm).unwrap();
    let mut params = spec.params.clone();
    params.grid_step = step;
    let p = dir.join(format!("kit-step{step}.toml"));
    std::fs::write(
        &p,
        write_kit_toml("metric-25", &spec.kit, &params, Units::Mm),
    )
    .unwrap();
    p
}

fn without_rank(f: &Value) -> String {
    let mut f = f.clone();
    f["rank"] = Value::Null;
    f.to_string()
}

#[test]
fn coarse_to_fine_steps_are_nested_and_the_finest_is_a_plain_run() {
    let dir = tempfile::tempdir().unwrap();
    let catalog = setup(dir.path());
    let steps = [4u32, 2, 1];
    let mut plain = Vec::new();
    for s in steps {
        let out = dir.path().join(format!("step{s}.mcap"));
        ok(fixplan()
            .args(["run", "-q", "--top-k", "0", "--catalog"])
            .arg(&catalog)
            .arg("--kit")
            .arg(kit_with_step(dir.path(), s))
            .arg("-o")
            .arg(&out)
            .output()
            .unwrap());
        plain.push(out);
    }
    let refined = dir.path().join("refined.mcap");
    ok(fixplan()
        .args([
            "run",
            "-q",
            "--top-k",
            "0",
            "--grid-steps",
            "4,2,1",
            "--catalog",
        ])
        .arg(&catalog)
        .args(["--kit", "metric-25", "-o"])
        .arg(&refined)
        .output()
        .unwrap());
    // The fixtures channel is the finest step's, byte for byte.
    assert_eq!(fixtures_channel(&refined), fixtures_channel(&plain[2]));
    let exports: Vec<Vec<Value>> = plain.iter().map(|p| export(p)).collect();
    let parts = part_msgs(&refined);
    let mut grew = false;
    for (i, line) in exports[0].iter().enumerate() {
        let id = line["part"].as_str().unwrap();
        if line["status"] == "invalid" {
            continue;
        }
        // Subset: every fixture of step 4 is one of step 2, and of step 1.
        for w in 0..2 {
            let coarse: Vec<String> = exports[w][i]["fixtures"]
                .as_array()
                .unwrap()
                .iter()
                .map(without_rank)
                .collect();
            let fine: std::collections::BTreeSet<String> = exports[w + 1][i]["fixtures"]
                .as_array()
                .unwrap()
                .iter()
                .map(without_rank)
                .collect();
            for f in &coarse {
                assert!(
                    fine.contains(f),
                    "{id}: a step-{} fixture is missing at step {}",
                    steps[w],
                    steps[w + 1]
                );
            }
            grew |= fine.len() > coarse.len();
        }
        // The per-step summary matches the plain runs at each step.
        let refine = parts[id]["refine"].as_array().unwrap();
        assert_eq!(refine.len(), 3);
        let mut prev_adm = 0;
        for (w, st) in refine.iter().enumerate() {
            let e = &exports[w][i];
            // The step as the part message writes it, in the export's form.
            let step: StepField = serde_json::from_value(st.clone()).unwrap();
            assert_eq!(step.grid_step, steps[w]);
            let counts = serde_json::to_value(Counts::from(&step.counts)).unwrap();
            assert_eq!(counts, e["counts"], "{id} step {}", steps[w]);
            let adm = e["counts"]["admissible"].as_u64().unwrap();
            assert_eq!(step.added, Some(adm - prev_adm));
            prev_adm = adm;
            let best = step.best.as_ref().map(FixtureReport::from);
            match e["fixtures"].get(0) {
                Some(f) => {
                    assert_eq!(&serde_json::to_value(best).unwrap(), f);
                    assert_eq!(st["best_score"], f["score"]);
                }
                None => assert!(best.is_none()),
            }
        }
    }
    assert!(grew, "no refinement added anything: the test shows nothing");
}

#[test]
fn good_enough_stops_early_with_a_good_fixture() {
    let dir = tempfile::tempdir().unwrap();
    let catalog = setup(dir.path());
    let full = dir.path().join("full.mcap");
    ok(fixplan()
        .args(["run", "-q", "--top-k", "0", "--catalog"])
        .arg(&catalog)
        .arg("-o")
        .arg(&full)
        .output()
        .unwrap());
    let full = export(&full);
    let bracket = full.iter().find(|l| l["part"] == "bracket-2").unwrap();
    let scores: Vec<f64> = bracket["fixtures"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["score"].as_f64().unwrap())
        .collect();
    // A threshold that the best fixture meets easily: the median score.
    let threshold = scores[scores.len() / 2];
    let combos = bracket["counts"]["combinations"].as_u64().unwrap();
    let mut fixtures = Vec::new();
    for threads in ["1", "2"] {
        let out = dir.path().join(format!("ge{threads}.mcap"));
        ok(fixplan()
            .args([
                "run",
                "-q",
                "--top-k",
                "0",
                "--threads",
                threads,
                "--catalog",
            ])
            .arg(&catalog)
            .args(["--good-enough", &threshold.to_string(), "-o"])
            .arg(&out)
            .output()
            .unwrap());
        let parts = part_msgs(&out);
        let p = &parts["bracket-2"];
        assert_eq!(p["status"], "ok");
        assert_eq!(p["stopped"], "good_enough");
        let at = p["stopped_at"].as_u64().unwrap();
        let lines = export(&out);
        let l = lines.iter().find(|l| l["part"] == "bracket-2").unwrap();
        let done = l["counts"]["combinations"].as_u64().unwrap();
        assert_eq!(done, at + 1);
        assert!(done < combos, "stopped at {at} of {combos}");
        assert!(l["fixtures"][0]["score"].as_f64().unwrap() <= threshold);
        // A part no fixture holds runs to the end and says nothing.
        let tiny = &parts["tiny-tab"];
        assert!(tiny.get("stopped").is_none());
        fixtures.push(fixtures_channel(&out));
    }
    assert_eq!(fixtures[0], fixtures[1], "depends on the thread count");
    // Through workers: the same stop, the same bytes.
    let mut stops = Vec::new();
    for extra in [&["--threads", "1"][..], &["--workers", "2"][..]] {
        let out = dir.path().join(format!("gw{}.mcap", extra[0]));
        ok(fixplan()
            .args([
                "run",
                "-q",
                "--top-k",
                "0",
                "--shard-size",
                "7",
                "--catalog",
            ])
            .arg(&catalog)
            .args(extra)
            .args(["--good-enough", &threshold.to_string(), "-o"])
            .arg(&out)
            .output()
            .unwrap());
        let parts = part_msgs(&out);
        let mut s: Vec<(String, Value, Value)> = parts
            .iter()
            .map(|(id, p)| (id.clone(), p["stopped"].clone(), p["stopped_at"].clone()))
            .collect();
        s.sort_by(|a, b| a.0.cmp(&b.0));
        stops.push(s);
        fixtures.push(fixtures_channel(&out));
    }
    assert_eq!(stops[0], stops[1]);
    assert!(
        stops[1].iter().any(|s| s.1 == "good_enough"),
        "{:?}",
        stops[1]
    );
    assert_eq!(fixtures[0], fixtures[2]);
    assert_eq!(
        fixtures[2], fixtures[3],
        "workers differ from the embedded run"
    );
}

#[test]
fn grid_steps_on_workers_match_embedded() {
    let dir = tempfile::tempdir().unwrap();
    let catalog = setup(dir.path());
    // Plain, and with a threshold every fixture meets: then each part that
    // has one stops at the coarse step and the fine step is dropped.
    for search in [&[][..], &["--good-enough", "1e9"][..]] {
        let mut got = Vec::new();
        for extra in [&[][..], &["--workers", "2"][..]] {
            let out = dir
                .path()
                .join(format!("w{}g{}.mcap", extra.len(), search.len()));
            ok(fixplan()
                .args(["run", "-q", "--grid-steps", "2,1", "--catalog"])
                .arg(&catalog)
                .args(search)
                .args(extra)
                .arg("-o")
                .arg(&out)
                .output()
                .unwrap());
            let parts: Vec<Value> = part_msgs(&out)
                .into_values()
                .map(|mut p| {
                    for s in p["refine"].as_array_mut().into_iter().flatten() {
                        s["enumerate_ms"] = Value::Null;
                    }
                    serde_json::json!([p["refine"], p["stopped"], p["stopped_at"]])
                })
                .collect();
            got.push((fixtures_channel(&out), parts));
        }
        assert_eq!(got[0], got[1], "{search:?}");
        if !search.is_empty() {
            let one_step = got[0]
                .1
                .iter()
                .filter(|p| p[0].as_array().is_some_and(|r| r.len() == 1) && p[1] == "good_enough")
                .count();
            assert!(one_step > 0, "no part stopped at the coarse step");
        }
    }
}
