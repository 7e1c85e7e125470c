//! Hostile inputs (issue 31), fuzzed with a fixed seed: damaged results
//! files are never read as sound ones and `--resume` keeps no damaged
//! part; mutated part files, kits and manifests end in an error or a
//! status, never a panic, and the good parts beside them are unharmed.
//! Work is bounded by `--part-budget` and `--part-setups` (deterministic
//! units), not by a clock. `FIXPLAN_FUZZ_SCALE=N` runs N times as many cases (default 1:
//! a few seconds).
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use fixplan_catalog::{load_catalog_with, load_kit, LoadOptions};
use fixplan_coordinator::partial_path;
use fixplan_coordinator::Backend;
use fixplan_coordinator::SearchOptions;
use fixplan_coordinator::{export_json, show};
use fixplan_coordinator::{run_catalog, RunOptions};
use fixplan_coordinator::{PartMessages, ResultsFile};
use fixplan_core::{Status, Units};
use fixplan_tests::{catalog, fixtures_channel};
use std::path::{Path, PathBuf};

/// Cases per test, times `FIXPLAN_FUZZ_SCALE`.
fn scaled(n: usize) -> usize {
    let scale = std::env::var("FIXPLAN_FUZZ_SCALE")
        .ok()
        .and_then(|s| s.parse::<usize>().ok())
        .unwrap_or(1);
    n * scale.max(1)
}

/// A small deterministic generator (xorshift64*): the same cases on every
/// machine.
struct FuzzRng(u64);

impl FuzzRng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

fn opts(out: &Path, budget: Option<u64>) -> RunOptions {
    RunOptions {
        catalog: PathBuf::from("mem"),
        kit: "case-kit".into(),
        top_k: Some(5),
        full_counts: false,
        output: out.to_path_buf(),
        resume: false,
        shard_size: None,
        quiet: true,
        search: SearchOptions {
            part_budget: budget,
            ..SearchOptions::default()
        },
        backend: Backend::Embedded { threads: Some(2) },
        arcs: None,
    }
}

/// The parts of a results file's bytes as the reader hands them out.
fn read(
    bytes: &[u8],
) -> (
    Result<fixplan_coordinator::Contents, String>,
    Vec<PartMessages>,
) {
    let file = ResultsFile::from_bytes("fuzzed.mcap".into(), bytes.to_vec());
    let mut parts = Vec::new();
    let c = file.for_each_part(|_, m| {
        parts.push(m);
        true
    });
    (c.map_err(|e| e.to_string()), parts)
}

/// One damaged copy of `sound`.
fn damage(sound: &[u8], rng: &mut FuzzRng) -> (String, Vec<u8>) {
    let mut b = sound.to_vec();
    let at = 8 + rng.below(b.len() - 8);
    let what = match rng.below(5) {
        0 => {
            let bit = rng.below(8);
            b[at] ^= 1 << bit;
            format!("bit {bit} of byte {at} flipped")
        }
        1 => {
            b[at] = 0xFF;
            format!("byte {at} set to 0xff")
        }
        2 => {
            let end = (at + 8).min(b.len());
            for x in &mut b[at..end] {
                *x = rng.next() as u8;
            }
            format!("bytes {at}..{end} smashed")
        }
        3 => {
            b.truncate(at);
            format!("cut at byte {at}")
        }
        _ => {
            b.remove(at);
            format!("byte {at} removed")
        }
    };
    (what, b)
}

#[test]
fn damaged_results_files_never_read_as_sound() {
    let dir = tempfile::tempdir().unwrap();
    let (cat, spec) = catalog();
    let out = dir.path().join("sound.mcap");
    run_catalog(&cat, &spec, &opts(&out, None)).unwrap();
    let sound = std::fs::read(&out).unwrap();
    let (c, original) = read(&sound);
    let c = c.unwrap();
    assert!(c.complete && c.damage.is_empty() && original.len() == 6);
    // The header record's length with its top byte set: the crate's
    // reader panicked on it.
    let mut header = sound.clone();
    header[9 + 7] = 0xFF;
    assert!(read(&header)
        .0
        .unwrap_err()
        .contains("not a fixplan results file"));
    let mut rng = FuzzRng(31);
    let mut told = 0;
    for case in 0..scaled(600) {
        let (what, bytes) = damage(&sound, &mut rng);
        let (contents, parts) = read(&bytes);
        for p in &parts {
            assert_eq!(
                Some(p),
                original.get(p.index),
                "case {case} ({what}): part #{} handed out changed",
                p.index
            );
        }
        let Ok(contents) = contents else {
            told += 1;
            continue;
        };
        let indices: Vec<usize> = parts.iter().map(|p| p.index).collect();
        if contents.damage.is_empty() {
            // Nothing said: then nothing may be missing, except the tail
            // of what reads as an interrupted run.
            let prefix: Vec<usize> = (0..indices.len()).collect();
            assert_eq!(
                indices, prefix,
                "case {case} ({what}): a part lost without a word"
            );
            assert!(
                !contents.complete || indices.len() == original.len(),
                "case {case} ({what}): a complete file missing parts without a word"
            );
        } else {
            told += 1;
        }
        if case % 20 == 0 && !contents.damage.is_empty() {
            let path = dir.path().join("damaged.mcap");
            std::fs::write(&path, &bytes).unwrap();
            let mut printed = Vec::new();
            let e = export_json(&path, None, &mut printed)
                .unwrap_err()
                .to_string();
            assert!(e.contains("damaged.mcap") && e.contains("byte"), "{e}");
            assert_eq!(
                String::from_utf8(printed).unwrap().lines().count(),
                parts.len(),
                "case {case} ({what}): export prints the sound parts"
            );
            let e = show(&path, None, 3, &mut Vec::new())
                .unwrap_err()
                .to_string();
            assert!(e.contains("damaged.mcap") && e.contains("byte"), "{e}");
        }
    }
    assert!(
        told > scaled(600) / 2,
        "only {told} damaged files were told"
    );
}

/// Which parts are `over_budget` depends on the budgets: a file written
/// with other budgets is another run, which `--resume` refuses rather
/// than keep its parts; with the same budgets it resumes.
#[test]
fn resume_with_other_budgets_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (cat, spec) = catalog();
    let out = dir.path().join("r.mcap");
    let with = |setups| {
        let mut o = opts(&out, Some(2_000_000));
        o.search.part_setups = Some(setups);
        o.resume = true;
        o
    };
    run_catalog(&cat, &spec, &with(1_000)).unwrap();
    let sound = std::fs::read(&out).unwrap();
    for (setups, same) in [(1_000, true), (2_000, false)] {
        std::fs::write(partial_path(&out), &sound).unwrap();
        let resumed = run_catalog(&cat, &spec, &with(setups));
        match resumed {
            Ok(_) => assert!(same, "budget {setups}: resumed another run"),
            Err(e) => {
                assert!(!same, "budget {setups}: {e:#}");
                assert!(format!("{e:#}").contains("different run"), "{e:#}");
            }
        }
    }
}

#[test]
fn resume_keeps_no_damaged_part() {
    let dir = tempfile::tempdir().unwrap();
    let (cat, spec) = catalog();
    let whole = dir.path().join("whole.mcap");
    run_catalog(&cat, &spec, &opts(&whole, None)).unwrap();
    let want = fixtures_channel(&whole);
    let sound = std::fs::read(&whole).unwrap();
    let mut rng = FuzzRng(7);
    for case in 0..scaled(12) {
        let (what, bytes) = damage(&sound, &mut rng);
        let out = dir.path().join(format!("r{case}.mcap"));
        std::fs::write(partial_path(&out), &bytes).unwrap();
        let o = RunOptions {
            resume: true,
            ..opts(&out, None)
        };
        match run_catalog(&cat, &spec, &o) {
            Ok(_) => assert_eq!(fixtures_channel(&out), want, "case {case} ({what})"),
            // Only a file of another run may stop a resume.
            Err(e) => panic!("case {case} ({what}): {e:#}"),
        }
    }
}

/// A manifest of two good inline parts around `entry`, in `dir`.
fn manifest(dir: &Path, name: &str, entry: &str) -> PathBuf {
    let path = dir.join(format!("{name}.toml"));
    let text = format!(
        "name = \"h\"\nunits = \"mm\"\n\n[[part]]\nid = \"good-a\"\noutline = [[0, 0], [90, 0], [90, 40], [0, 40]]\n\n[[part]]\nid = \"bad\"\n{entry}\n\n[[part]]\nid = \"good-b\"\noutline = [[0, 0], [80, 0], [80, 15], [15, 15], [15, 60], [0, 60]]\n"
    );
    std::fs::write(&path, text).unwrap();
    path
}

/// Runs a manifest with the kit and a budget; the good parts' fixtures.
fn run_manifest(path: &Path, out: &Path) -> Vec<(String, Status, Vec<u8>)> {
    run_manifest_with(path, &opts(out, Some(2_000_000)))
}

/// [`run_manifest`] with these options: every part's id, status and
/// fixtures channel.
fn run_manifest_with(path: &Path, o: &RunOptions) -> Vec<(String, Status, Vec<u8>)> {
    let out = &o.output;
    let cat = load_catalog_with(path, &LoadOptions::default()).unwrap();
    let spec = load_kit("metric-25", cat.units).unwrap();
    run_catalog(&cat, &spec, o).unwrap();
    let mut v = Vec::new();
    ResultsFile::open(out)
        .unwrap()
        .for_each_part(|_, m| {
            let r = fixplan_coordinator::PartRecord::decode(&m).unwrap();
            let f = m.get(fixplan_coordinator::TOPIC_FIXTURES);
            v.push((r.part.id, r.part.status.into(), f.unwrap().to_vec()));
            true
        })
        .unwrap();
    v
}

/// A part many plates across (a catalogue entry in inches read as mm)
/// has millions of setups in a few combinations: the setup budget stops
/// it inside the enumeration, with the same verdict at any thread count
/// and shard size, and the good parts beside it are the clean run's.
#[test]
fn a_part_bigger_than_the_plate_stops_at_its_setup_budget() {
    let dir = tempfile::tempdir().unwrap();
    let clean = manifest(
        dir.path(),
        "clean",
        "outline = [[0, 0], [60, 0], [60, 30], [0, 30]]",
    );
    let big = manifest(
        dir.path(),
        "big",
        "outline = [[0, 0], [1500, 0], [1500, 300], [0, 300]]",
    );
    let with = |out: &str, threads, shard_size, setups| {
        let mut o = opts(&dir.path().join(out), None);
        o.backend = Backend::Embedded {
            threads: Some(threads),
        };
        o.shard_size = shard_size;
        o.search.part_setups = Some(setups);
        o
    };
    let want = run_manifest_with(&clean, &with("clean.mcap", 2, None, 1_000_000));
    let good = |v: &[(String, Status, Vec<u8>)]| {
        v.iter()
            .filter(|p| p.0.starts_with("good"))
            .cloned()
            .collect::<Vec<_>>()
    };
    for (threads, shard_size) in [(1, None), (2, None), (2, Some(1))] {
        let out = format!("big-{threads}-{shard_size:?}.mcap");
        let got = run_manifest_with(&big, &with(&out, threads, shard_size, 20_000));
        assert_eq!(good(&got), good(&want), "{threads} threads: good parts");
        let bad = got.iter().find(|p| p.0 == "bad").unwrap();
        assert_eq!(bad.1, Status::OverBudget, "{threads} threads");
    }
}

/// Numbers that broke parts and kits. No mid-size one (1e4): a part a
/// hundred plates across takes seconds to reach its setup budget
/// ([`a_part_bigger_than_the_plate_stops_at_its_setup_budget`] has one).
const HOSTILE_NUMBERS: [&str; 8] = [
    "1e9",
    "-1e9",
    "1e-320",
    "1e300",
    "-1e300",
    "0",
    "-0.0",
    "123456789012",
];

#[test]
fn hostile_parts_end_in_a_status_and_spare_the_good_ones() {
    let dir = tempfile::tempdir().unwrap();
    let clean = run_manifest(
        &manifest(
            dir.path(),
            "clean",
            "outline = [[0, 0], [60, 0], [60, 30], [0, 30]]",
        ),
        &dir.path().join("clean.mcap"),
    );
    let good = |v: &[(String, Status, Vec<u8>)]| {
        v.iter()
            .filter(|p| p.0.starts_with("good"))
            .cloned()
            .collect::<Vec<_>>()
    };
    let mut entries: Vec<(String, String)> = vec![
        (
            "bulge-1e9".into(),
            "outline = [[0, 0, 1e9], [10, 0], [5, 5]]".into(),
        ),
        (
            "bulge-neg".into(),
            "outline = [[0, 0, -1e9], [10, 0], [5, 5]]".into(),
        ),
        (
            "bulge-tiny".into(),
            "outline = [[0, 0, 1e-320], [10, 0], [5, 5]]".into(),
        ),
        ("far".into(), "outline = [[0, 0], [1e12, 0], [0, 1]]".into()),
    ];
    let nested = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\">{}<path d=\"M0 0 h90 v40 h-90 Z\"/>{}</svg>",
        "<g>".repeat(200_000),
        "</g>".repeat(200_000)
    );
    std::fs::write(dir.path().join("nested.svg"), nested).unwrap();
    entries.push(("nested-svg".into(), "file = \"nested.svg\"".into()));
    let dxf = "0\nSECTION\n2\nENTITIES\n0\nLWPOLYLINE\n8\n0\n90\n3\n70\n1\n10\n0\n20\n0\n42\n-1e9\n10\n10\n20\n0\n10\n5\n20\n5\n0\nENDSEC\n0\nEOF\n";
    std::fs::write(dir.path().join("bulge.dxf"), dxf).unwrap();
    entries.push(("dxf-bulge".into(), "file = \"bulge.dxf\"".into()));
    // 20,000 vertices: over --part-budget before it is prepared (preparing
    // allocates segments squared).
    let ring: Vec<[f64; 2]> = (0..20_000)
        .map(|i| {
            let a = i as f64 * std::f64::consts::TAU / 20_000.0;
            [50.0 * a.cos(), 50.0 * a.sin()]
        })
        .collect();
    let ring = serde_json::json!({ "part": ring }).to_string();
    std::fs::write(dir.path().join("ring.json"), ring).unwrap();
    let got = run_manifest(
        &manifest(dir.path(), "ring", "file = \"ring.json\""),
        &dir.path().join("ring.mcap"),
    );
    assert_eq!(good(&got), good(&clean), "ring: the good parts changed");
    let ring = got.iter().find(|p| p.0 == "bad").unwrap();
    assert_eq!(ring.1, Status::OverBudget);
    // Mutated numbers in the sample parts.
    let parts = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/catalog/parts");
    let mut rng = FuzzRng(42);
    let mut sources: Vec<PathBuf> = std::fs::read_dir(&parts)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    sources.sort();
    for case in 0..scaled(16) {
        let src = &sources[rng.below(sources.len())];
        let text = std::fs::read_to_string(src).unwrap();
        let numbers: Vec<(usize, usize)> = number_spans(&text);
        let mut t = text.clone();
        if let Some(&(s, e)) = numbers.get(rng.below(numbers.len())) {
            t.replace_range(s..e, HOSTILE_NUMBERS[rng.below(HOSTILE_NUMBERS.len())]);
        }
        let ext = src.extension().unwrap().to_str().unwrap();
        let name = format!("m{case}.{ext}");
        std::fs::write(dir.path().join(&name), t).unwrap();
        entries.push((format!("mutated-{case}"), format!("file = \"{name}\"")));
    }
    for (name, entry) in &entries {
        let got = run_manifest(
            &manifest(dir.path(), name, entry),
            &dir.path().join(format!("{name}.mcap")),
        );
        assert_eq!(good(&got), good(&clean), "{name}: the good parts changed");
        let bad = got.iter().find(|p| p.0 == "bad");
        if let Some(bad) = bad {
            assert!(bad.1 != Status::Failed, "{name}: the solver failed on it");
        }
    }
}

/// Byte ranges of the decimal numbers of `text`.
fn number_spans(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut spans = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i].is_ascii_digit() {
            let s = i;
            while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
                i += 1;
            }
            spans.push((s, i));
        } else {
            i += 1;
        }
    }
    spans
}

#[test]
fn hostile_kits_are_refused_with_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let base = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/hostile/kit-base.toml"),
    )
    .unwrap();
    assert!(base.contains("rows = 20") && base.contains("axis_offset = 0.0"));
    let cases = [
        ("rows = 20", "rows = 100000000", "holes"),
        ("cols = 20", "cols = 4294967295", "holes"),
        ("axis_offset = 0.0", "axis_offset = -1e300", "axis_offset"),
        ("travel = [60.0, 92.0]", "travel = [60.0, 1e308]", "travel"),
        ("spacing = 25.0", "spacing = 1e308", "spacing"),
    ];
    for (old, new, field) in cases {
        let path = dir.path().join("kit.toml");
        std::fs::write(&path, base.replace(old, new)).unwrap();
        let e = load_kit(path.to_str().unwrap(), Units::Mm)
            .unwrap_err()
            .to_string();
        assert!(e.contains(field), "{new}: {e}");
    }
    // Every number of the kit replaced by each hostile one: an error or a
    // kit, never a panic.
    let spans = number_spans(&base);
    for &(s, e) in spans.iter().take(scaled(40)) {
        for n in HOSTILE_NUMBERS {
            let mut t = base.clone();
            t.replace_range(s..e, n);
            let path = dir.path().join("kit.toml");
            std::fs::write(&path, t).unwrap();
            let _ = load_kit(path.to_str().unwrap(), Units::Mm);
        }
    }
}
