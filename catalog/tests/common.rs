//! Helpers shared by the integration tests (included with `mod common`).
#![allow(dead_code, missing_docs)] // test helpers, documented where they are used
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use fixplan_catalog::{ArcMode, ReadOptions};
use fixplan_core::Units;
use std::path::{Path, PathBuf};

/// Read options of an mm catalogue, arcs exact (the default).
pub fn opts_mm() -> ReadOptions {
    ReadOptions::new(Units::Mm)
}

/// Arcs flattened, as fixplan read them before exact arcs.
pub fn flat_mm() -> ReadOptions {
    ReadOptions {
        arcs: ArcMode::Flatten,
        ..opts_mm()
    }
}

/// DXF group code/value pairs as file text.
pub fn dxf_text(pairs: &[(i32, &str)]) -> String {
    pairs
        .iter()
        .map(|(c, v)| format!("{c:>3}\n{v}\n"))
        .collect()
}

/// An R12 ENTITIES section around `body` code pairs.
pub fn r12(body: &[(i32, &str)]) -> String {
    let mut v = vec![(0, "SECTION"), (2, "ENTITIES")];
    v.extend_from_slice(body);
    v.extend_from_slice(&[(0, "ENDSEC"), (0, "EOF")]);
    dxf_text(&v)
}
use std::sync::atomic::{AtomicUsize, Ordering};

/// A LINE entity on `layer` from `a` to `b`.
pub fn line(
    layer: &'static str,
    a: [&'static str; 2],
    b: [&'static str; 2],
) -> Vec<(i32, &'static str)> {
    vec![
        (0, "LINE"),
        (8, layer),
        (10, a[0]),
        (20, a[1]),
        (11, b[0]),
        (21, b[1]),
    ]
}

/// An ARC entity on layer 0: centre, radius, start and end angles (degrees).
pub fn arc_entity(
    centre: [&'static str; 2],
    radius: &'static str,
    a0: &'static str,
    a1: &'static str,
) -> Vec<(i32, &'static str)> {
    vec![
        (0, "ARC"),
        (8, "0"),
        (10, centre[0]),
        (20, centre[1]),
        (40, radius),
        (50, a0),
        (51, a1),
    ]
}

/// A test's scratch directory, removed with everything in it when the
/// test is done (also when it fails): tests leave nothing behind in /tmp.
pub struct TempDir(PathBuf);

impl std::ops::Deref for TempDir {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for TempDir {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A fresh directory under the system temp dir, unique per call.
pub fn temp_dir(tag: &str) -> TempDir {
    static N: AtomicUsize = AtomicUsize::new(0);
    let d = std::env::temp_dir().join(format!(
        "fixplan-catalog-{tag}-{}-{}",
        std::process::id(),
        N.fetch_add(1, Ordering::SeqCst)
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    TempDir(d)
}

pub fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    if let Some(parent) = p.parent() {
        std::fs::create_dir_all(parent).unwrap();
    }
    std::fs::write(&p, text).unwrap();
    p
}

pub fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name)
}

pub fn bbox<P: std::ops::Index<usize, Output = f64>>(pts: &[P]) -> [f64; 4] {
    let mut b = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
    for p in pts {
        b[0] = b[0].min(p[0]);
        b[1] = b[1].min(p[1]);
        b[2] = b[2].max(p[0]);
        b[3] = b[3].max(p[1]);
    }
    b
}

pub fn area<P: std::ops::Index<usize, Output = f64>>(points: &[P]) -> f64 {
    let n = points.len();
    (0..n)
        .map(|i| points[i][0] * points[(i + 1) % n][1] - points[(i + 1) % n][0] * points[i][1])
        .sum::<f64>()
        / 2.0
}

pub fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}
