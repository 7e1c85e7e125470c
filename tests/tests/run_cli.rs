//! `fixplan run`, `show`, `export` and `render` through the built binary:
//! the sample catalogue, export against `solve`, resume after a real
//! SIGKILL, invalid parts, and the MCAP file read back channel by channel
//! (Rust reader here, Python's `mcap` package when it is installed).
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use fixplan_coordinator::ResultsFile;
use fixplan_coordinator::{KitField, ParamsField, StatusName};
use fixplan_coordinator::{
    PartMsg, METADATA_RUN, NS_PER_PART, TOPIC_FIXTURES, TOPIC_PART, TOPIC_RUN, TOPIC_SCENE,
};
use fixplan_tests::ok;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

#[path = "support/schema_check.rs"]
mod schema_check;

fn fixplan() -> Command {
    Command::new(env!("CARGO_BIN_EXE_fixplan-it"))
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// A manifest of inline parts in `dir`.
fn manifest(dir: &Path, units: &str, parts: &[(&str, Vec<[f64; 2]>)]) -> PathBuf {
    let mut s = format!("name = \"test\"\nunits = \"{units}\"\n\n");
    for (id, pts) in parts {
        s.push_str(&format!(
            "[[part]]\nid = \"{id}\"\noutline = {}\n\n",
            serde_json::to_string(pts).unwrap()
        ));
    }
    let p = dir.join("catalog.toml");
    std::fs::write(&p, s).unwrap();
    p
}

fn small_parts() -> Vec<(&'static str, Vec<[f64; 2]>)> {
    vec![
        (
            "plate",
            vec![[0.0, 0.0], [80.0, 0.0], [80.0, 50.0], [0.0, 50.0]],
        ),
        (
            "ell",
            vec![
                [0.0, 0.0],
                [90.0, 0.0],
                [90.0, 30.0],
                [30.0, 30.0],
                [30.0, 70.0],
                [0.0, 70.0],
            ],
        ),
        (
            "bowtie",
            vec![[0.0, 0.0], [50.0, 50.0], [50.0, 0.0], [0.0, 50.0]],
        ),
        (
            "hex",
            vec![
                [30.0, 0.0],
                [70.0, 0.0],
                [95.0, 40.0],
                [70.0, 80.0],
                [30.0, 80.0],
                [5.0, 40.0],
            ],
        ),
        ("tiny", vec![[0.0, 0.0], [3.0, 0.0], [0.0, 3.0]]),
    ]
}

/// The gluegun outline (bench case), in mm, scaled by `1 + i/100`: parts
/// that take a noticeable fraction of a second each.
fn gluegun_parts(n: usize) -> Vec<(String, Vec<[f64; 2]>)> {
    let case: Value = serde_json::from_str(
        &std::fs::read_to_string(repo().join("examples/cases/gluegun-28.json")).unwrap(),
    )
    .unwrap();
    let pts: Vec<[f64; 2]> = serde_json::from_value(case["part"].clone()).unwrap();
    (0..n)
        .map(|i| {
            let s = 25.4 * (1.0 + i as f64 / 100.0);
            (
                format!("g{i:02}"),
                pts.iter().map(|p| [p[0] * s, p[1] * s]).collect(),
            )
        })
        .collect()
}

fn export_lines(results: &Path) -> Vec<Value> {
    let out = ok(fixplan()
        .arg("export")
        .arg(results)
        .arg("--json")
        .output()
        .unwrap());
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

fn run_small(dir: &Path) -> (PathBuf, Output) {
    let cat = manifest(dir, "mm", &small_parts());
    let res = dir.join("r.mcap");
    let out = fixplan()
        .args(["run", "--kit", "metric-25", "--top-k", "4", "--catalog"])
        .arg(&cat)
        .arg("-o")
        .arg(&res)
        .output()
        .unwrap();
    (res, ok(out))
}

/// `fixplan run` on the bundled sample catalogue: every message valid
/// against its channel's embedded schema, scene messages against the
/// official `foxglove.SceneUpdate` too, and no object schema without
/// `properties` (what the viewers' schema parser needs).
#[test]
fn every_message_of_a_sample_run_validates_against_its_schema() {
    let dir = tempfile::tempdir().unwrap();
    ok(fixplan()
        .arg("run")
        .current_dir(dir.path())
        .output()
        .unwrap());
    let res = dir.path().join("results.mcap");
    let parts = export_lines(&res).len();
    assert!(parts > 0);
    let counts = schema_check::validate_every_message(&std::fs::read(&res).unwrap());
    let expected: BTreeMap<String, usize> = [
        (TOPIC_RUN, 1),
        (TOPIC_PART, parts),
        (TOPIC_FIXTURES, parts),
        (TOPIC_SCENE, parts),
    ]
    .into_iter()
    .map(|(t, n)| (t.to_string(), n))
    .collect();
    assert_eq!(counts, expected);
}

#[test]
fn runs_the_sample_catalogue_by_default() {
    let sample = repo().join("examples/catalog/catalog.toml");
    assert!(
        sample.is_file(),
        "the sample catalogue {} is missing",
        sample.display()
    );
    let dir = tempfile::tempdir().unwrap();
    // No --catalog, no --kit, no -o: the sample with metric-25 into results.mcap.
    let out = ok(fixplan()
        .arg("run")
        .current_dir(dir.path())
        .output()
        .unwrap());
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("fixtures found"), "{stdout}");
    let res = dir.path().join("results.mcap");
    assert!(res.is_file());
    assert!(!dir.path().join("results.mcap.partial").exists());
    let lines = export_lines(&res);
    let file = ResultsFile::open(&res).unwrap();
    let mut ids = Vec::new();
    let c = file
        .for_each_part(|_, m| {
            ids.push(m.decode::<PartMsg>().unwrap().id);
            true
        })
        .unwrap();
    assert!(c.complete);
    assert_eq!(c.run.kit_name, "metric-25");
    assert_eq!(c.run.catalog.parts, lines.len());
    assert_eq!(ids.len(), lines.len());
    assert!(
        lines.iter().any(|l| l["status"] == "ok"),
        "no part of the sample has a fixture"
    );
    let shown = ok(fixplan().arg("show").arg(&res).output().unwrap());
    assert!(String::from_utf8_lossy(&shown.stdout).contains(&ids[0]));
}

/// Each exported line equals `fixplan solve` on a case file made of the
/// part, the run's kit and parameters.
#[test]
fn export_matches_solve_for_each_part() {
    let dir = tempfile::tempdir().unwrap();
    let (res, _) = run_small(dir.path());
    let file = ResultsFile::open(&res).unwrap();
    let mut parts = Vec::new();
    let c = file
        .for_each_part(|_, m| {
            parts.push(m.decode::<PartMsg>().unwrap());
            true
        })
        .unwrap();
    let lines = export_lines(&res);
    assert_eq!(lines.len(), 5);
    for (p, line) in parts.iter().zip(&lines) {
        assert_eq!(line["part"], p.id.as_str());
        let mut expected = line.clone();
        expected.as_object_mut().unwrap().remove("part");
        if p.status == StatusName::Invalid {
            assert!(line["error"].as_str().unwrap().contains(&p.id), "{line}");
            continue;
        }
        let case = serde_json::json!({"units": p.units, "part": p.outline(), "access": p.access(),
            "kit": c.run.kit(), "params": c.run.params()});
        let case_path = dir.path().join(format!("{}.json", p.id));
        std::fs::write(&case_path, case.to_string()).unwrap();
        let solved = ok(fixplan().arg("solve").arg(&case_path).output().unwrap());
        let solved: Value = serde_json::from_slice(&solved.stdout).unwrap();
        assert_eq!(solved, expected, "part {}", p.id);
    }
}

#[test]
fn invalid_parts_are_reported_while_the_others_finish() {
    let dir = tempfile::tempdir().unwrap();
    // A directory catalogue: two good JSON parts and a broken one.
    let cat = dir.path().join("parts");
    std::fs::create_dir(&cat).unwrap();
    let write = |name: &str, v: Value| std::fs::write(cat.join(name), v.to_string()).unwrap();
    write(
        "a-plate.json",
        serde_json::json!({"part": [[0,0],[80,0],[80,50],[0,50]]}),
    );
    write(
        "b-bowtie.json",
        serde_json::json!({"part": [[0,0],[50,50],[50,0],[0,50]]}),
    );
    write(
        "c-ell.json",
        serde_json::json!({"part": [[0,0],[90,0],[90,30],[30,30],[30,70],[0,70]]}),
    );
    std::fs::write(cat.join("d-garbage.json"), "{not json").unwrap();
    let res = dir.path().join("r.mcap");
    let out = ok(fixplan()
        .args(["run", "--kit", "metric-25", "--catalog"])
        .arg(&cat)
        .arg("-o")
        .arg(&res)
        .output()
        .unwrap());
    let stderr = String::from_utf8_lossy(&out.stderr);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stderr.contains("b-bowtie") && stderr.contains("cross"),
        "{stderr}"
    );
    assert!(stderr.contains("d-garbage"), "{stderr}");
    assert!(
        stdout.contains("invalid                           2"),
        "{stdout}"
    );
    let lines = export_lines(&res);
    let status: Vec<_> = lines
        .iter()
        .map(|l| (l["part"].clone(), l["status"].clone()))
        .collect();
    assert_eq!(
        status,
        [
            ("a-plate".into(), "ok".into()),
            ("b-bowtie".into(), "invalid".into()),
            ("c-ell".into(), "ok".into()),
            ("d-garbage".into(), "invalid".into())
        ]
    );
    let err = lines[1]["error"].as_str().unwrap();
    assert!(err.contains("b-bowtie") && err.contains("edge"), "{err}");
}

fn complete_parts(partial: &Path) -> usize {
    match ResultsFile::open(partial) {
        Ok(f) => f
            .for_each_part(|_, _| true)
            .map(|c| c.parts.len())
            .unwrap_or(0),
        Err(_) => 0,
    }
}

#[test]
fn resumes_after_sigkill() {
    let dir = tempfile::tempdir().unwrap();
    // Enough parts that the run cannot finish between two polls below.
    let parts = gluegun_parts(40);
    let refs: Vec<(&str, Vec<[f64; 2]>)> =
        parts.iter().map(|(i, p)| (i.as_str(), p.clone())).collect();
    let cat = manifest(dir.path(), "mm", &refs);
    let res = dir.path().join("r.mcap");
    let partial = dir.path().join("r.mcap.partial");
    let base = |threads: &str, out: &Path| {
        let mut c = fixplan();
        c.args([
            "run",
            "--kit",
            "metric-25",
            "--threads",
            threads,
            "--catalog",
        ])
        .arg(&cat)
        .arg("-o")
        .arg(out);
        c
    };
    let mut child = base("1", &res)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    let mut done_before_kill = 0;
    while t0.elapsed() < Duration::from_secs(120) {
        done_before_kill = complete_parts(&partial);
        if done_before_kill >= 2 {
            break;
        }
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before it could be killed"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    // SIGKILL: no chance to clean up.
    unsafe {
        libc::kill(child.id() as i32, libc::SIGKILL);
    }
    let status = child.wait().unwrap();
    assert!(!status.success());
    assert!(!res.exists(), "killed run must not leave a finished file");
    let after_kill = complete_parts(&partial);
    assert!(
        after_kill >= done_before_kill && after_kill < parts.len(),
        "{after_kill} parts in the partial file"
    );
    assert!(mcap::Summary::read(&std::fs::read(&partial).unwrap())
        .ok()
        .flatten()
        .is_none());

    let out = ok(base("2", &res).arg("--resume").output().unwrap());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(&format!("{after_kill} parts already done")),
        "{stderr}"
    );
    // No finished part was redone: the log names only the others.
    for (id, _) in &parts[..after_kill] {
        assert!(
            !stderr.contains(&format!("] {id}:")),
            "{id} redone:\n{stderr}"
        );
    }
    for (id, _) in &parts[after_kill..] {
        assert!(
            stderr.contains(&format!("] {id}:")),
            "{id} missing:\n{stderr}"
        );
    }
    assert!(res.is_file() && !partial.exists());

    // Each part exactly once, and the same rankings as an uninterrupted run.
    let reference = dir.path().join("ref.mcap");
    ok(base("2", &reference).output().unwrap());
    let got = export_lines(&res);
    let ids: Vec<_> = got
        .iter()
        .map(|l| l["part"].as_str().unwrap().to_string())
        .collect();
    let want: Vec<_> = parts.iter().map(|(i, _)| i.clone()).collect();
    assert_eq!(ids, want);
    assert_eq!(got, export_lines(&reference));
    // The fixtures and scene channels are the same bytes.
    assert_eq!(fixtures_and_scenes(&res), fixtures_and_scenes(&reference));
}

/// Each part's fixtures and scene messages, in file order: what two runs
/// of one catalogue write byte for byte alike (only part messages carry
/// timings).
fn fixtures_and_scenes(results: &Path) -> Vec<(Vec<u8>, Vec<u8>)> {
    let mut v = Vec::new();
    ResultsFile::open(results)
        .unwrap()
        .for_each_part(|_, m| {
            v.push((
                m.get(TOPIC_FIXTURES).unwrap().to_vec(),
                m.get(TOPIC_SCENE).unwrap().to_vec(),
            ));
            true
        })
        .unwrap();
    v
}

/// A run of the sample catalogue cut after its 12th part (between two
/// chunks, as a kill leaves it) and resumed by worker processes: the parts
/// with arcs on both sides of the cut (housing-1 and -2 kept, housing-3,
/// the flanges, keyhole-plate, lever and bracket-svg redone) come out as
/// in the uninterrupted run, byte for byte.
#[test]
fn resumes_a_run_of_parts_with_arcs_through_workers() {
    let dir = tempfile::tempdir().unwrap();
    let whole = dir.path().join("whole.mcap");
    ok(fixplan()
        .args(["run", "-q", "--threads", "2", "-o"])
        .arg(&whole)
        .output()
        .unwrap());
    let bytes = std::fs::read(&whole).unwrap();
    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    let mut starts: Vec<u64> = summary
        .chunk_indexes
        .iter()
        .map(|c| c.chunk_start_offset)
        .collect();
    starts.sort_unstable();
    // The run message's chunk, then one chunk per part.
    let kept = 12;
    let cut = starts[1 + kept] as usize;
    let res = dir.path().join("r.mcap");
    let partial = dir.path().join("r.mcap.partial");
    std::fs::write(&partial, &bytes[..cut]).unwrap();
    assert_eq!(complete_parts(&partial), kept);

    let out = ok(fixplan()
        .args(["run", "--resume", "--workers", "1", "--threads", "1", "-o"])
        .arg(&res)
        .output()
        .unwrap());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(&format!("{kept} parts already done")),
        "{stderr}"
    );
    let got = export_lines(&res);
    let arcs = |lines: &[Value]| {
        lines
            .iter()
            .filter(|l| l["segment_kinds"].to_string().contains("arc"))
            .count()
    };
    assert!(arcs(&got[..kept]) >= 2 && arcs(&got[kept..]) >= 5);
    assert_eq!(got, export_lines(&whole));
    assert_eq!(fixtures_and_scenes(&res), fixtures_and_scenes(&whole));
}

#[test]
fn resume_refuses_a_different_run() {
    let dir = tempfile::tempdir().unwrap();
    let (res, _) = run_small(dir.path());
    // Pretend the finished file was interrupted, then resume with other params.
    std::fs::rename(&res, dir.path().join("r.mcap.partial")).unwrap();
    let out = fixplan()
        .args([
            "run",
            "--kit",
            "metric-25",
            "--top-k",
            "3",
            "--resume",
            "--catalog",
        ])
        .arg(dir.path().join("catalog.toml"))
        .arg("-o")
        .arg(&res)
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("different run"));
    // With the same parameters everything is taken from the file.
    let out = ok(fixplan()
        .args([
            "run",
            "--kit",
            "metric-25",
            "--top-k",
            "4",
            "--resume",
            "--catalog",
        ])
        .arg(dir.path().join("catalog.toml"))
        .arg("-o")
        .arg(&res)
        .output()
        .unwrap());
    assert!(String::from_utf8_lossy(&out.stderr).contains("5 parts already done"));
    assert_eq!(export_lines(&res).len(), 5);
}

/// The `fixplan.run` metadata record names the kit and the catalogue, as
/// the run message does.
#[test]
fn run_metadata_names_kit_and_catalogue() {
    let dir = tempfile::tempdir().unwrap();
    let (res, _) = run_small(dir.path());
    let bytes = std::fs::read(&res).unwrap();
    let summary = mcap::Summary::read(&bytes).unwrap().expect("summary");
    assert_eq!(summary.metadata_indexes.len(), 1);
    let index = &summary.metadata_indexes[0];
    assert_eq!(index.name, METADATA_RUN);
    let m = mcap::read::metadata(&bytes, index).unwrap().metadata;
    let file = ResultsFile::open(&res).unwrap();
    let c = file.for_each_part(|_, _| true).unwrap();
    assert_eq!(m["tool"], "fixplan");
    assert_eq!(m["kit_name"], "metric-25");
    assert_eq!(m["catalog_digest"], c.run.catalog.digest);
    assert_eq!(m["catalog_name"], c.run.catalog.name);
    assert_eq!(m["catalog_units"], "mm");
    assert_eq!(m["catalog_parts"], "5");
    let kit: KitField = serde_json::from_str(&m["kit"]).unwrap();
    assert_eq!(kit, c.run.kit);
    let params: ParamsField = serde_json::from_str(&m["params"]).unwrap();
    assert_eq!(params.top_k, 4);
}

/// The file read back with the `mcap` crate: summary, indexes, zstd chunks,
/// four channels with JSON Schemas, every message valid JSON.
#[test]
fn mcap_reads_back_channel_by_channel() {
    let dir = tempfile::tempdir().unwrap();
    let (res, _) = run_small(dir.path());
    let bytes = std::fs::read(&res).unwrap();
    let summary = mcap::Summary::read(&bytes).unwrap().expect("summary");
    assert!(!summary.chunk_indexes.is_empty());
    assert!(summary
        .chunk_indexes
        .iter()
        .all(|c| c.compression == "zstd"));
    let mut topics: BTreeMap<String, (String, String, String)> = BTreeMap::new();
    for ch in summary.channels.values() {
        let s = ch.schema.as_ref().expect("schema");
        assert_eq!(s.encoding, "jsonschema");
        let schema: Value = serde_json::from_slice(&s.data).expect("schema is JSON");
        assert_eq!(schema["title"], s.name.as_str());
        topics.insert(
            ch.topic.clone(),
            (
                s.name.clone(),
                s.encoding.clone(),
                ch.message_encoding.clone(),
            ),
        );
    }
    let names: Vec<_> = topics
        .iter()
        .map(|(t, (s, _, e))| format!("{t} {s} {e}"))
        .collect();
    assert_eq!(
        names,
        [
            "/fixplan/fixtures fixplan.Fixtures json",
            "/fixplan/part fixplan.Part json",
            "/fixplan/run fixplan.Run json",
            "/fixplan/scene foxglove.SceneUpdate json"
        ]
    );
    let stats = summary.stats.as_ref().expect("statistics");
    assert_eq!(stats.message_count, 1 + 3 * 5);
    // Channel by channel, through the chunk indexes (seeking reader path).
    let mut per_topic: BTreeMap<String, Vec<Value>> = BTreeMap::new();
    for ci in &summary.chunk_indexes {
        for m in summary.stream_chunk(&bytes, ci).unwrap() {
            let m = m.unwrap();
            let v: Value = serde_json::from_slice(&m.data).unwrap();
            per_topic
                .entry(m.channel.topic.clone())
                .or_default()
                .push(v);
        }
    }
    assert_eq!(per_topic["/fixplan/run"].len(), 1);
    assert_eq!(per_topic["/fixplan/run"][0]["kit_name"], "metric-25");
    for t in ["/fixplan/part", "/fixplan/fixtures", "/fixplan/scene"] {
        assert_eq!(per_topic[t].len(), 5, "{t}");
    }
    let part = &per_topic["/fixplan/part"][1];
    assert_eq!(part["id"], "ell");
    assert_eq!(part["outline"].as_array().unwrap().len(), 6);
    let fx = &per_topic["/fixplan/fixtures"][0];
    assert_eq!(fx["fixtures"].as_array().unwrap().len(), 4);
    assert!(fx["fixtures"][0]["placement"]["locators"].is_array());
    let scene = &per_topic["/fixplan/scene"][0];
    let ids: Vec<_> = scene["entities"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["id"].clone())
        .collect();
    assert_eq!(ids, ["plate", "part", "fixture"]);
    let part_entity = &scene["entities"][1];
    assert_eq!(part_entity["frame_id"], "plate");
    assert_eq!(part_entity["lines"][0]["type"], 1);
    assert_eq!(
        part_entity["lines"][0]["points"].as_array().unwrap().len(),
        4
    );
    // log time = part index, in seconds.
    let mut times = Vec::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        if m.channel.topic == TOPIC_FIXTURES {
            times.push(m.log_time);
        }
    }
    assert_eq!(times, (0..5).map(|i| i * NS_PER_PART).collect::<Vec<_>>());
}

/// A reader written by others: Python's `mcap` package reads every channel.
#[test]
fn python_mcap_reader_reads_every_channel() {
    let probe = Command::new("python3")
        .args(["-c", "import mcap.reader"])
        .output();
    if !matches!(probe, Ok(ref o) if o.status.success()) {
        eprintln!("SKIPPED: python3 with the `mcap` package is not available (pip install mcap)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (res, _) = run_small(dir.path());
    let script = r#"
import json, sys
from mcap.reader import make_reader
counts = {}
with open(sys.argv[1], "rb") as f:
    reader = make_reader(f)
    summary = reader.get_summary()
    assert summary is not None and summary.statistics.message_count == 16
    for schema, channel, message in reader.iter_messages():
        assert schema.encoding == "jsonschema" and channel.message_encoding == "json"
        json.loads(schema.data)
        json.loads(message.data)
        counts[channel.topic] = counts.get(channel.topic, 0) + 1
print(json.dumps(counts, sort_keys=True))
"#;
    let out = ok(Command::new("python3")
        .args(["-c", script])
        .arg(&res)
        .output()
        .unwrap());
    let counts: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(
        counts,
        serde_json::json!({"/fixplan/fixtures": 5, "/fixplan/part": 5, "/fixplan/run": 1, "/fixplan/scene": 5})
    );
}

#[test]
fn show_and_render() {
    let dir = tempfile::tempdir().unwrap();
    let (res, _) = run_small(dir.path());
    let out = ok(fixplan()
        .arg("show")
        .arg(&res)
        .args(["--part", "ell", "--top", "2"])
        .output()
        .unwrap());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("== ell [ok]") && text.contains("rank") && text.contains("2 more kept"),
        "{text}"
    );
    assert!(!text.contains("hex"));
    let out = ok(fixplan().arg("show").arg(&res).output().unwrap());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("== bowtie [invalid]") && text.contains("== tiny [no_fixture]"),
        "{text}"
    );

    let pics = dir.path().join("pics");
    ok(fixplan()
        .arg("render")
        .arg(&res)
        .arg("--out")
        .arg(&pics)
        .args(["--top", "2"])
        .output()
        .unwrap());
    let mut files: Vec<String> = std::fs::read_dir(&pics)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    assert_eq!(
        files,
        [
            "0000-plate-rank01.svg",
            "0000-plate-rank02.svg",
            "0001-ell-rank01.svg",
            "0001-ell-rank02.svg",
            "0002-bowtie.svg",
            "0003-hex-rank01.svg",
            "0003-hex-rank02.svg",
            "0004-tiny.svg",
            "index.html"
        ]
    );
    let svg = std::fs::read_to_string(pics.join("0001-ell-rank01.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    assert!(svg.contains("score") && svg.contains(">L3<"));
    let html = std::fs::read_to_string(pics.join("index.html")).unwrap();
    assert!(html.contains("0003-hex-rank02.svg") && html.contains("edge 0 crosses edge 2"));

    let err = fixplan()
        .arg("show")
        .arg(&res)
        .args(["--part", "nope"])
        .output()
        .unwrap();
    assert!(!err.status.success());
}

#[test]
fn help_teaches_the_options() {
    let out = ok(fixplan().args(["run", "--help"]).output().unwrap());
    let text = String::from_utf8_lossy(&out.stdout);
    for flag in [
        "--catalog",
        "--kit",
        "--top-k",
        "--threads",
        "--output",
        "--resume",
        "metric-25",
    ] {
        assert!(text.contains(flag), "{flag} missing from:\n{text}");
    }
}

/// `fixplan run ... 2>&1 | head -1`: the reader goes away after one line;
/// the run must still finish its file and exit cleanly (it used to panic
/// on the closed stderr and then wait forever for its own threads).
#[test]
fn a_closed_terminal_pipe_neither_hangs_nor_loses_the_file() {
    use std::io::{BufRead, BufReader};
    let dir = tempfile::tempdir().unwrap();
    for extra in [&["--threads", "1"][..], &["--workers", "1"][..]] {
        let out = dir
            .path()
            .join(format!("{}.mcap", extra[0].trim_start_matches('-')));
        let mut child = fixplan()
            .args(["run", "-o"])
            .arg(&out)
            .args(extra)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut first = String::new();
        BufReader::new(child.stderr.take().unwrap())
            .read_line(&mut first)
            .unwrap();
        assert!(first.starts_with("fixplan run"), "{first}");
        drop(child.stdout.take()); // both ends closed, like `head` exiting
        let until = Instant::now() + Duration::from_secs(60);
        let status = loop {
            if let Some(s) = child.try_wait().unwrap() {
                break s;
            }
            if Instant::now() > until {
                let _ = child.kill();
                panic!("fixplan run {extra:?} hung after its output was closed");
            }
            std::thread::sleep(Duration::from_millis(20));
        };
        assert!(status.success(), "{extra:?}: {status:?}");
        assert!(
            ResultsFile::open(&out).is_ok(),
            "{extra:?}: no results file"
        );
    }
}

/// An invalid part's message, scene and picture show the outline that was
/// read, with the error as caption (a user sees what is wrong, not nothing).
#[test]
fn an_invalid_part_shows_what_was_read() {
    let dir = tempfile::tempdir().unwrap();
    let (res, _) = run_small(dir.path());
    let file = ResultsFile::open(&res).unwrap();
    let mut seen = 0;
    file.for_each_part(|_, m| {
        let part: PartMsg = m.decode().unwrap();
        if part.id != "bowtie" {
            return true;
        }
        seen += 1;
        assert_eq!(part.status, StatusName::Invalid);
        assert_eq!(
            part.outline(),
            fixplan_core::Part::polygon(&[[0.0, 0.0], [50.0, 50.0], [50.0, 0.0], [0.0, 50.0]])
                .outline
        );
        let error = part.error.clone().unwrap();
        assert!(error.starts_with("bowtie: "), "{error}");
        let scene: Value = serde_json::from_slice(m.get(TOPIC_SCENE).unwrap()).unwrap();
        // The plate is drawn (its edge and holes), then the part.
        let plate = &scene["entities"][0];
        assert_eq!(plate["id"], "plate");
        assert_eq!(plate["lines"][0]["points"].as_array().unwrap().len(), 4);
        assert!(!plate["cylinders"].as_array().unwrap().is_empty());
        let part_entity = &scene["entities"][1];
        assert_eq!(part_entity["texts"][0]["text"], error.as_str());
        assert_eq!(
            part_entity["lines"][0]["points"].as_array().unwrap().len(),
            4
        );
        true
    })
    .unwrap();
    assert_eq!(seen, 1);
    let pics = dir.path().join("pics");
    ok(fixplan()
        .arg("render")
        .arg(&res)
        .args(["--part", "bowtie", "--out"])
        .arg(&pics)
        .output()
        .unwrap());
    let svg = std::fs::read_dir(&pics)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| p.extension().is_some_and(|x| x == "svg"))
        .unwrap();
    let svg = std::fs::read_to_string(svg).unwrap();
    assert!(svg.contains("<polygon"), "{svg}");
    assert!(svg.contains("edge 0 crosses edge 2"), "{svg}");
}

/// `fixplan run --sheet` on a drawing of two plates: without the flag the
/// file is refused with a message that names it; with it each plate is a
/// part of its own, `id#1` from the left.
#[test]
fn the_sheet_flag_reads_every_outer_loop_as_a_part() {
    let dir = tempfile::tempdir().unwrap();
    let cat = dir.path().join("parts");
    std::fs::create_dir(&cat).unwrap();
    std::fs::write(
        cat.join("sheet.svg"),
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="300mm" height="100mm" viewBox="0 0 300 100">
  <rect x="10" y="10" width="80" height="50"/>
  <rect x="150" y="10" width="90" height="50"/>
</svg>"#,
    )
    .unwrap();
    let run = |sheet: bool, name: &str| {
        let res = dir.path().join(name);
        let mut cmd = fixplan();
        cmd.args(["run", "-q", "--top-k", "1", "--catalog"])
            .arg(&cat)
            .arg("-o")
            .arg(&res);
        if sheet {
            cmd.arg("--sheet");
        }
        ok(cmd.output().unwrap());
        export_lines(&res)
    };
    let one = run(false, "one.mcap");
    assert_eq!(one.len(), 1);
    assert_eq!(one[0]["part"], "sheet");
    assert_eq!(one[0]["status"], "invalid");
    let err = one[0]["error"].as_str().unwrap();
    assert!(
        err.contains("more than one outline") && err.contains("--sheet"),
        "{err}"
    );
    let parts: Vec<(Value, Value)> = run(true, "sheet.mcap")
        .iter()
        .map(|l| (l["part"].clone(), l["status"].clone()))
        .collect();
    assert_eq!(
        parts,
        [
            ("sheet#1".into(), "ok".into()),
            ("sheet#2".into(), "ok".into())
        ]
    );
}
