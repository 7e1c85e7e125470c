//! A run that died stays dead once (issue 31): a part that kills the
//! process (an abort, as a stack overflow or the OOM killer would) is
//! known to the next `--resume` from the run's journal, solved alone
//! there, and answered `failed` after its second death; the run then
//! completes and every other part is byte-identical to an uninterrupted
//! run's, including the one that was in flight beside it.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use fixplan_tests::{fixtures_channel, ok};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn fixplan() -> Command {
    Command::new(env!("CARGO_BIN_EXE_fixplan-it"))
}

/// The gluegun bench case's outline in mm: a part that takes a good
/// fraction of a second, so it is still being solved on the other thread
/// when the killer starts.
fn gluegun() -> String {
    let case: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/cases/gluegun-28.json"),
        )
        .unwrap(),
    )
    .unwrap();
    let pts: Vec<[f64; 2]> = serde_json::from_value(case["part"].clone()).unwrap();
    let mm: Vec<[f64; 2]> = pts.iter().map(|p| [p[0] * 25.4, p[1] * 25.4]).collect();
    serde_json::to_string(&mm).unwrap()
}

/// Six parts, `killer` fourth, a slow one before it.
fn manifest(dir: &Path) -> PathBuf {
    let glue = gluegun();
    let parts: [(&str, &str); 6] = [
        ("plate", "[[0, 0], [80, 0], [80, 50], [0, 50]]"),
        (
            "ell",
            "[[0, 0], [90, 0], [90, 30], [30, 30], [30, 70], [0, 70]]",
        ),
        ("glue", &glue),
        ("killer", "[[0, 0], [60, 0], [60, 40], [0, 40]]"),
        (
            "hex",
            "[[30, 0], [70, 0], [95, 40], [70, 80], [30, 80], [5, 40]]",
        ),
        ("bar", "[[0, 0], [120, 0], [120, 20], [0, 20]]"),
    ];
    let mut s = String::from("name = \"journal\"\nunits = \"mm\"\n\n");
    for (id, outline) in parts {
        s.push_str(&format!("[[part]]\nid = \"{id}\"\noutline = {outline}\n\n"));
    }
    let path = dir.join("catalog.toml");
    std::fs::write(&path, s).unwrap();
    path
}

/// `fixplan run` of `catalog` into `out` with `extra`, to be started.
fn run_command(catalog: &Path, out: &Path, extra: &[&str]) -> Command {
    let mut command = fixplan();
    command
        .args(["run", "--kit", "metric-25", "--threads", "2", "--catalog"])
        .arg(catalog)
        .arg("-o")
        .arg(out)
        .args(extra);
    command
}

fn run(catalog: &Path, out: &Path, extra: &[&str]) -> Output {
    run_command(catalog, out, extra).output().unwrap()
}

/// The part lines of `fixplan export --json`.
fn export(path: &Path) -> Vec<serde_json::Value> {
    let mut printed = Vec::new();
    fixplan_coordinator::export_json(path, None, &mut printed).unwrap();
    printed
        .split(|&b| b == b'\n')
        .filter(|l| !l.is_empty())
        .map(|l| serde_json::from_slice(l).unwrap())
        .collect()
}

#[test]
fn a_part_that_kills_the_run_twice_is_failed_and_the_rest_is_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    let catalog = manifest(dir.path());
    let clean = dir.path().join("clean.mcap");
    ok(run(&catalog, &clean, &["-q"]));
    let out = dir.path().join("r.mcap");
    let journal = dir.path().join("r.mcap.journal");
    let fault = ["-q", "--fault", "abort-on:killer"];
    let first = run(&catalog, &out, &fault);
    assert!(!first.status.success(), "the fault did not kill the run");
    assert!(!out.exists() && journal.exists());
    // Resumed: killer is a suspect, solved alone, and kills it again.
    let second = run(&catalog, &out, &[&fault[..], &["--resume"]].concat());
    assert!(!second.status.success(), "the suspect was not solved again");
    let told = String::from_utf8_lossy(&second.stderr);
    assert!(
        told.contains("part #3 killer was being solved when the run died (1 of 1 deaths"),
        "{told}"
    );
    // Third time: answered failed without being solved; the run completes.
    let third = ok(run(&catalog, &out, &[&fault[..], &["--resume"]].concat()));
    let told = String::from_utf8_lossy(&third.stderr);
    assert!(told.contains("answered failed, not solved again"), "{told}");
    assert!(out.exists() && !journal.exists(), "{told}");
    let parts = export(&out);
    let killer = &parts[3];
    assert_eq!(killer["part"], "killer");
    assert_eq!(killer["status"], "failed");
    let error = killer["error"].as_str().unwrap();
    // Its first death was beside glue (unless glue's thread had not
    // started it yet), its second alone.
    assert!(
        error.contains("killed the process twice while being solved")
            && (error.contains("died 2 times, 1 of them alone")
                || error.contains("died 2 times, 2 of them alone")),
        "{error}"
    );
    let (got, want) = (fixtures_channel(&out), fixtures_channel(&clean));
    assert_eq!(got.len(), want.len());
    for (i, (g, w)) in got.iter().zip(&want).enumerate() {
        if i != 3 {
            assert_eq!(g, w, "part #{i} differs from the uninterrupted run");
        }
    }
}

/// A journal that is not a journal (garbage, another run's) only costs
/// its protection: the resume says what it ignored and gives the
/// uninterrupted run's bytes.
#[test]
fn a_damaged_journal_changes_no_result() {
    let dir = tempfile::tempdir().unwrap();
    let catalog = manifest(dir.path());
    let clean = dir.path().join("clean.mcap");
    ok(run(&catalog, &clean, &["-q"]));
    let out = dir.path().join("d.mcap");
    let first = run(&catalog, &out, &["-q", "--fault", "abort-on:hex"]);
    assert!(!first.status.success());
    let journal = dir.path().join("d.mcap.journal");
    let mut bytes = std::fs::read(&journal).unwrap();
    let len = bytes.len();
    for (k, b) in bytes.iter_mut().enumerate().skip(len / 3) {
        *b = (k * 7919 % 251) as u8;
    }
    bytes.extend_from_slice(b"start 99 \"nope\"\ndone x\n\xff\xfe\n");
    std::fs::write(&journal, bytes).unwrap();
    let resumed = ok(run(&catalog, &out, &["-q", "--resume"]));
    let told = String::from_utf8_lossy(&resumed.stderr);
    assert!(told.contains("lines ignored"), "{told}");
    assert_eq!(fixtures_channel(&out), fixtures_channel(&clean));
}

/// Starts a resumable run of `catalog` into `out` with `extra`, waits
/// until its journal's session `session` (0 for the first run) shows part
/// #2 (glue) started, sends it `signal` (`-INT`, `-TERM`) and returns
/// what it did.
fn signalled_at_glue(
    (catalog, out): (&Path, &Path),
    extra: &[&str],
    session: usize,
    signal: &str,
) -> Output {
    let mut child = run_command(catalog, out, extra)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let journal = out.with_extension("mcap.journal");
    // A bound on a hang, not a speed test: the run reaches glue in well
    // under a second.
    let until = std::time::Instant::now() + std::time::Duration::from_secs(120);
    loop {
        let text = std::fs::read_to_string(&journal).unwrap_or_default();
        let ours = text.split("session ").nth(session + 1).unwrap_or_default();
        if ours.lines().any(|l| l.starts_with("start 2 ")) {
            break;
        }
        assert!(child.try_wait().unwrap().is_none(), "the run ended early");
        if std::time::Instant::now() > until {
            let _ = child.kill();
            let _ = child.wait();
            panic!("the run did not start glue within 120 s");
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let sent = Command::new("kill")
        .arg(signal)
        .arg(child.id().to_string())
        .status()
        .unwrap();
    assert!(sent.success());
    child.wait_with_output().unwrap()
}

/// Ctrl-C (or SIGTERM) is not a death: the run stops with 130 (143), its
/// journal ends `end interrupted`, and a part interrupted twice is solved
/// at the third go like any other, byte-identical to an uninterrupted run.
#[test]
fn a_part_interrupted_twice_is_not_failed() {
    let dir = tempfile::tempdir().unwrap();
    let catalog = manifest(dir.path());
    let clean = dir.path().join("clean.mcap");
    ok(run(&catalog, &clean, &["-q"]));
    let out = dir.path().join("s.mcap");
    let stall = ["-q", "--fault", "stall-on:glue"];
    let first = signalled_at_glue((&catalog, &out), &stall, 0, "-INT");
    let told = String::from_utf8_lossy(&first.stderr);
    assert_eq!(first.status.code(), Some(130), "{told}");
    assert!(told.contains("resume with"), "{told}");
    let journal = std::fs::read_to_string(dir.path().join("s.mcap.journal")).unwrap();
    assert!(journal.ends_with("\nend interrupted\n"), "{journal}");
    assert!(!out.exists() && dir.path().join("s.mcap.partial").exists());
    let resumed = [&stall[..], &["--resume"]].concat();
    let second = signalled_at_glue((&catalog, &out), &resumed, 1, "-TERM");
    let told = String::from_utf8_lossy(&second.stderr);
    assert_eq!(second.status.code(), Some(143), "{told}");
    assert!(
        !told.contains("died"),
        "an interrupt read as a death: {told}"
    );
    let third = ok(run(&catalog, &out, &["-q", "--resume"]));
    let told = String::from_utf8_lossy(&third.stderr);
    assert!(
        !told.contains("died"),
        "an interrupt read as a death: {told}"
    );
    assert!(export(&out).iter().all(|p| p["status"] != "failed"));
    assert_eq!(fixtures_channel(&out), fixtures_channel(&clean));
}

/// `--fault abort-on:ID` acts where a part's solve starts in the run's
/// own process, which `--workers` never does: the combination is refused
/// at start, naming why, rather than running without the fault.
#[test]
fn a_run_fault_with_workers_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.mcap");
    for fault in ["abort-on:bracket-1", "stall-on:bracket-1"] {
        let got = fixplan()
            .args(["run", "-q", "--workers", "2", "--fault", fault, "-o"])
            .arg(&out)
            .env_remove("RUST_LOG")
            .stdin(std::process::Stdio::null())
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&got.stderr);
        assert!(!got.status.success(), "{fault}: {err}");
        assert!(err.contains("--workers"), "{fault}: {err}");
        assert!(!out.exists() && !dir.path().join("out.mcap.partial").exists());
    }
}
