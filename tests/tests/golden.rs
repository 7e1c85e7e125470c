//! Byte-for-byte guard of refactors: a fixed polygon catalogue of 44 parts,
//! generated here (no file on disk but the goldens), run on a square plate
//! (`metric-25`) and an alternating one (`paper-inch`), must give the very
//! fixtures channel and `export --json` output committed in
//! `tests/golden/`. The goldens were written before the coordinator was
//! reorganised; a change to them is a change of behaviour, to be explained
//! in its commit. `FIXPLAN_BLESS=1 cargo test --test golden` rewrites them.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use fixplan_tests::{fixtures_channel, ok};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

fn fixplan() -> Command {
    Command::new(env!("CARGO_BIN_EXE_fixplan-it"))
}

fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("golden")
}

/// A small deterministic generator (64-bit LCG), so the catalogue does not
/// depend on a crate's random stream.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        // Quarter-millimetre grid: exact in TOML and in binary.
        ((lo + (hi - lo) * self.next()) * 4.0).round() / 4.0
    }
}

type PolygonPoints = Vec<[f64; 2]>;

/// A star-shaped polygon around the origin: angles increasing, radii
/// random, so it is always simple.
fn star(g: &mut Lcg, n: usize, rmin: f64, rmax: f64) -> PolygonPoints {
    (0..n)
        .map(|i| {
            let a = std::f64::consts::TAU * (i as f64 + 0.3 * g.next()) / n as f64;
            let r = g.range(rmin, rmax);
            [
                ((r * a.cos()) * 4.0).round() / 4.0,
                ((r * a.sin()) * 4.0).round() / 4.0,
            ]
        })
        .collect()
}

fn ell(w: f64, h: f64, t: f64) -> PolygonPoints {
    vec![[0.0, 0.0], [w, 0.0], [w, t], [t, t], [t, h], [0.0, h]]
}

fn tee(w: f64, h: f64, t: f64) -> PolygonPoints {
    let a = (w - t) / 2.0;
    vec![
        [a, 0.0],
        [a + t, 0.0],
        [a + t, h - t],
        [w, h - t],
        [w, h],
        [0.0, h],
        [0.0, h - t],
        [a, h - t],
    ]
}

fn notched(w: f64, h: f64, nw: f64, nd: f64) -> PolygonPoints {
    let x0 = (w - nw) / 2.0;
    vec![
        [0.0, 0.0],
        [w, 0.0],
        [w, h],
        [x0 + nw, h],
        [x0 + nw, h - nd],
        [x0, h - nd],
        [x0, h],
        [0.0, h],
    ]
}

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> PolygonPoints {
    vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
}

/// 44 parts: rectangles, L, T, notched and star shapes of many sizes, some
/// listed clockwise, eight with access regions, one self-crossing, one too
/// small to hold.
fn parts() -> Vec<(String, PolygonPoints, Vec<PolygonPoints>)> {
    let mut g = Lcg(0x0601_de11);
    let mut v = Vec::new();
    for i in 0..8 {
        let (w, h) = (g.range(40.0, 160.0), g.range(30.0, 120.0));
        let mut o = rect(0.0, 0.0, w, h);
        if i % 3 == 1 {
            o.reverse();
        }
        let access = if i % 4 == 2 {
            vec![rect(w * 0.25, h * 0.6, w * 0.5, h + 20.0)]
        } else {
            vec![]
        };
        v.push((format!("rect-{i}"), o, access));
    }
    for i in 0..8 {
        let (w, h) = (g.range(60.0, 140.0), g.range(50.0, 120.0));
        let t = g.range(12.0, 30.0);
        let access = if i % 4 == 3 {
            vec![rect(-10.0, -10.0, t + 5.0, t + 5.0)]
        } else {
            vec![]
        };
        v.push((format!("ell-{i}"), ell(w, h, t), access));
    }
    for i in 0..6 {
        let (w, h) = (g.range(70.0, 140.0), g.range(60.0, 110.0));
        let t = g.range(15.0, 30.0);
        let mut o = tee(w, h, t);
        if i % 2 == 1 {
            o.reverse();
        }
        v.push((format!("tee-{i}"), o, vec![]));
    }
    for i in 0..6 {
        let (w, h) = (g.range(80.0, 150.0), g.range(50.0, 100.0));
        let (nw, nd) = (g.range(20.0, 40.0), g.range(10.0, 30.0));
        let access = if i % 3 == 0 {
            vec![rect(w * 0.8, -15.0, w + 15.0, h * 0.3)]
        } else {
            vec![]
        };
        v.push((format!("notch-{i}"), notched(w, h, nw, nd), access));
    }
    for i in 0..14 {
        let n = 5 + (i % 6);
        let o = star(&mut g, n, 30.0, 75.0);
        let access = if i % 5 == 4 {
            vec![rect(-10.0, -10.0, 10.0, 10.0)]
        } else {
            vec![]
        };
        v.push((format!("star-{i}"), o, access));
    }
    v.push((
        "bowtie".into(),
        vec![[0.0, 0.0], [50.0, 50.0], [50.0, 0.0], [0.0, 50.0]],
        vec![],
    ));
    v.push((
        "tiny".into(),
        vec![[0.0, 0.0], [3.0, 0.0], [0.0, 3.0]],
        vec![],
    ));
    v
}

fn toml_points(o: &PolygonPoints) -> String {
    let pts: Vec<String> = o.iter().map(|p| format!("[{}, {}]", p[0], p[1])).collect();
    format!("[{}]", pts.join(", "))
}

fn write_manifest(dir: &Path) -> PathBuf {
    let mut s = String::from("name = \"golden\"\nunits = \"mm\"\n\n");
    for (id, outline, access) in parts() {
        writeln!(
            s,
            "[[part]]\nid = \"{id}\"\noutline = {}",
            toml_points(&outline)
        )
        .unwrap();
        if !access.is_empty() {
            let a: Vec<String> = access.iter().map(toml_points).collect();
            writeln!(s, "access = [{}]", a.join(", ")).unwrap();
        }
        s.push('\n');
    }
    let p = dir.join("catalog.toml");
    std::fs::write(&p, s).unwrap();
    p
}

/// Compares `got` with the golden file `name`, or writes it when blessing.
fn check_golden(name: &str, got: &[u8]) {
    let path = golden_dir().join(name);
    if std::env::var_os("FIXPLAN_BLESS").is_some() {
        std::fs::create_dir_all(golden_dir()).unwrap();
        std::fs::write(&path, got).unwrap();
        return;
    }
    let want = std::fs::read(&path)
        .unwrap_or_else(|e| panic!("{}: {e} (FIXPLAN_BLESS=1 writes it)", path.display()));
    if want != got {
        let (w, g) = (String::from_utf8_lossy(&want), String::from_utf8_lossy(got));
        let line = w
            .lines()
            .zip(g.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(w.lines().count().min(g.lines().count()));
        panic!(
            "{} differs from this run at line {} ({} vs {} lines):\n  golden: {:.300}\n  now:    {:.300}",
            path.display(),
            line + 1,
            w.lines().count(),
            g.lines().count(),
            w.lines().nth(line).unwrap_or("<end>"),
            g.lines().nth(line).unwrap_or("<end>"),
        );
    }
}

/// The fixtures channel of a run of the golden catalogue with `kit`,
/// keeping 5 fixtures per part, one JSON line per part; `extra` arguments.
fn fixtures_lines(dir: &Path, kit: &str, extra: &[&str]) -> (Vec<u8>, PathBuf) {
    let catalog = write_manifest(dir);
    let results = dir.join(format!("golden{}.mcap", extra.len()));
    ok(fixplan()
        .args(["run", "-q", "--threads", "2", "--top-k", "5", "--kit", kit])
        .args(extra)
        .arg("--catalog")
        .arg(&catalog)
        .arg("-o")
        .arg(&results)
        .output()
        .unwrap());
    let mut fixtures = Vec::new();
    for m in fixtures_channel(&results) {
        fixtures.extend_from_slice(&m);
        fixtures.push(b'\n');
    }
    (fixtures, results)
}

/// The goldens hold full counts (`--full-counts`, as before the top-k
/// mode); the default top-k mode must give the very same lines but for
/// the counts, which leave `admissible` out and say so (`exact` false in
/// the fixtures channel). `*.fixtures.jsonl` is the fixtures channel as
/// the results file holds it; `*.export.jsonl` is `fixplan export
/// --json`, SPEC Appendix A's format.
fn run_kit(kit: &str) {
    let dir = tempfile::tempdir().unwrap();
    let (fixtures, results) = fixtures_lines(dir.path(), kit, &["--full-counts"]);
    check_golden(&format!("{kit}.fixtures.jsonl"), &fixtures);
    let export = ok(fixplan()
        .arg("export")
        .arg(&results)
        .arg("--json")
        .output()
        .unwrap());
    check_golden(&format!("{kit}.export.jsonl"), &export.stdout);
    let (fast, _) = fixtures_lines(dir.path(), kit, &[]);
    let lines = |b: &[u8]| -> Vec<serde_json::Value> {
        let text = String::from_utf8(b.to_vec()).unwrap();
        text.lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect()
    };
    let (full, fast) = (lines(&fixtures), lines(&fast));
    assert_eq!(full.len(), fast.len());
    for (mut a, b) in full.into_iter().zip(fast) {
        if let Some(c) = a.get_mut("counts").and_then(|c| c.as_object_mut()) {
            c.remove("admissible");
            c.insert("exact".into(), false.into());
        }
        assert_eq!(a, b, "top-k mode against full counts");
    }
}

#[test]
fn square_plate_matches_golden() {
    run_kit("metric-25");
}

#[test]
fn alternating_plate_matches_golden() {
    run_kit("paper-inch");
}
