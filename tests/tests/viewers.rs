//! What Foxglove Studio and Lichtblick show of fixplan's files.
//!
//! The viewers' own JSON-schema parser on real files: a sample run, a
//! `--grid-steps` run and a study, made by `fixplan-it`, handed channel by
//! channel and message by message to `parseChannel` of Foxglove Studio
//! 1.48.0 (`tests/viewer-parser/check.mjs`, run with node). Fails on any
//! channel the viewer refuses, any message it cannot decode, and any
//! decoded field its datatypes do not describe. Needs node and the npm
//! package that holds the parser (`npm ci` in `tests/viewer-parser`, which
//! `.ci/run` does, and this test does when it is missing); without node
//! at all it says so and skips.
//!
//! The layout `docs/foxglove-layout.json`: its 3D camera frames the plate
//! of every scene of the sample run.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use fixplan_tests::ok;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::process::Command;

fn fixplan() -> Command {
    Command::new(env!("CARGO_BIN_EXE_fixplan-it"))
}

fn tools() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("viewer-parser")
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Every channel (with its schema) and every message of the MCAP file
/// `path`, as `check.mjs` reads them (bytes in hex).
fn dump(path: &Path) -> Value {
    let bytes = std::fs::read(path).unwrap();
    let summary = mcap::Summary::read(&bytes).unwrap().expect("summary");
    let mut channels: Vec<_> = summary.channels.values().collect();
    channels.sort_by_key(|c| c.id);
    let channels: Vec<Value> = channels
        .iter()
        .map(|c| {
            let s = c.schema.as_ref().expect("schema");
            json!({"id": c.id, "topic": c.topic, "messageEncoding": c.message_encoding,
                   "schema": {"name": s.name, "encoding": s.encoding, "data": hex(&s.data)}})
        })
        .collect();
    let messages: Vec<Value> = mcap::MessageStream::new(&bytes)
        .unwrap()
        .map(|m| {
            let m = m.unwrap();
            json!({"channel": m.channel.id, "sequence": m.sequence, "data": hex(&m.data)})
        })
        .collect();
    let name = path.file_name().unwrap().to_string_lossy();
    json!({"name": name, "channels": channels, "messages": messages})
}

/// Whether `node` runs here; the reason to skip when it does not.
fn node_missing() -> Option<String> {
    match Command::new("node").arg("--version").output() {
        Ok(o) if o.status.success() => None,
        Ok(o) => Some(format!("node --version failed: {o:?}")),
        Err(e) => Some(format!("node not found: {e}")),
    }
}

/// Installs the parser's npm package (pinned by `package-lock.json`) if
/// it is not there yet.
fn install_parser() {
    let installed = tools().join("node_modules/@foxglove/studio-base/package.json");
    if installed.exists() {
        return;
    }
    ok(Command::new("npm")
        .args(["ci", "--ignore-scripts", "--no-audit", "--no-fund"])
        .current_dir(tools())
        .output()
        .expect("npm (needed to install the viewers' parser)"));
}

#[test]
fn the_viewers_parser_reads_every_channel_and_message() {
    if let Some(why) = node_missing() {
        eprintln!("SKIPPED: the viewers' parser needs node: {why}");
        return;
    }
    install_parser();
    let dir = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| {
        ok(fixplan()
            .args(args)
            .current_dir(dir.path())
            .output()
            .unwrap())
    };
    run(&["run", "-o", "sample.mcap"]);
    run(&["run", "-o", "refined.mcap", "--grid-steps", "2,1"]);
    run(&[
        "study",
        "--kit",
        "metric-25",
        "--kit",
        "paper-inch",
        "-o",
        "study.mcap",
    ]);
    let files: Vec<Value> = ["sample.mcap", "refined.mcap", "study.mcap"]
        .iter()
        .map(|f| dump(&dir.path().join(f)))
        .collect();
    let messages: usize = files
        .iter()
        .map(|f| f["messages"].as_array().unwrap().len())
        .sum();
    let dump_path = dir.path().join("dump.json");
    std::fs::write(&dump_path, json!({ "files": files }).to_string()).unwrap();
    let out = Command::new("node")
        .arg(tools().join("check.mjs"))
        .arg(&dump_path)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    eprintln!("{stdout}{}", String::from_utf8_lossy(&out.stderr));
    assert!(
        out.status.success(),
        "the viewers' parser refused:\n{stdout}"
    );
    // One line per channel, every message decoded.
    let decoded: usize = stdout
        .lines()
        .filter_map(|l| l.split(", ").nth(1)?.strip_suffix(" messages decoded"))
        .map(|n| n.parse::<usize>().unwrap())
        .sum();
    assert_eq!(decoded, messages);
    for topic in [
        "/fixplan/run",
        "/fixplan/part",
        "/fixplan/fixtures",
        "/fixplan/scene",
    ] {
        assert!(stdout.contains(&format!("sample.mcap {topic} ")), "{topic}");
    }
    assert!(stdout.contains("study.mcap /fixplan/study_summary "));
}

/// Every point a scene draws (metres, plate frame): line points, the
/// corners of cylinders, arrow and text anchors; the scene's entities
/// are all drawn with an identity frame pose.
fn scene_points(scene: &Value) -> Vec<[f64; 2]> {
    let xy = |p: &Value| [p["x"].as_f64().unwrap(), p["y"].as_f64().unwrap()];
    let list = |v: &Value| v.as_array().unwrap().clone();
    let mut points = Vec::new();
    for e in list(&scene["entities"]) {
        for line in list(&e["lines"]) {
            points.extend(list(&line["points"]).iter().map(xy));
        }
        for c in list(&e["cylinders"]) {
            let [x, y] = xy(&c["pose"]["position"]);
            let (w, h) = (
                c["size"]["x"].as_f64().unwrap(),
                c["size"]["y"].as_f64().unwrap(),
            );
            points.push([x - w / 2.0, y - h / 2.0]);
            points.push([x + w / 2.0, y + h / 2.0]);
        }
        for shape in list(&e["arrows"]).iter().chain(&list(&e["texts"])) {
            points.push(xy(&shape["pose"]["position"]));
        }
    }
    points
}

/// The layout's 3D panel looks straight down (orthographic) on the plate
/// frame and frames the sample run's plate: the square it shows (the
/// panel's height is `distance` metres; it is wider than high) centred on
/// `targetOffset` holds everything every scene of the run draws, and the
/// plate fills most of it. Every scene, with a fixture or without, draws
/// the plate.
#[test]
fn the_layout_camera_frames_every_scene_of_the_sample_run() {
    let layout = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/foxglove-layout.json");
    let layout: Value = serde_json::from_str(&std::fs::read_to_string(layout).unwrap()).unwrap();
    let panel = &layout["configById"]["3D!fixplan"];
    assert_eq!(panel["followTf"], "plate");
    assert_eq!(panel["topics"]["/fixplan/scene"]["visible"], true);
    let camera = &panel["cameraState"];
    assert_eq!(camera["perspective"], false);
    assert_eq!(camera["phi"].as_f64(), Some(0.0));
    assert_eq!(camera["thetaOffset"].as_f64(), Some(0.0));
    let distance = camera["distance"].as_f64().unwrap();
    let target = [0, 1].map(|i| camera["targetOffset"][i].as_f64().unwrap());
    for (id, topic) in [
        ("RawMessages!fixplanpart", "/fixplan/part"),
        ("RawMessages!fixplanfixtures", "/fixplan/fixtures"),
    ] {
        assert_eq!(layout["configById"][id]["topicPath"], topic);
    }
    let dir = tempfile::tempdir().unwrap();
    ok(fixplan()
        .arg("run")
        .current_dir(dir.path())
        .output()
        .unwrap());
    let bytes = std::fs::read(dir.path().join("results.mcap")).unwrap();
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    let mut scenes = 0;
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        if m.channel.topic != "/fixplan/scene" {
            continue;
        }
        scenes += 1;
        let scene: Value = serde_json::from_slice(&m.data).unwrap();
        let plate = &scene["entities"][0];
        assert_eq!(plate["id"], "plate");
        assert_eq!(plate["lines"][0]["points"].as_array().unwrap().len(), 4);
        for p in scene_points(&scene) {
            for i in 0..2 {
                (lo[i], hi[i]) = (lo[i].min(p[i]), hi[i].max(p[i]));
            }
        }
    }
    assert!(scenes > 0);
    let half = distance / 2.0;
    for i in 0..2 {
        assert!(
            lo[i] >= target[i] - half && hi[i] <= target[i] + half,
            "axis {i}: scenes span {} to {} m, the camera shows {} to {} m",
            lo[i],
            hi[i],
            target[i] - half,
            target[i] + half
        );
        assert!(
            hi[i] - lo[i] > 0.75 * distance,
            "axis {i}: the plate is small in the view"
        );
    }
}
