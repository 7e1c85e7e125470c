//! `run_catalog` on catalogues built in memory: the results file does not
//! depend on threads or shard size, invalid parts do not stop the run, and
//! every channel reads back.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use fixplan_catalog::{Catalog, CatalogPart};
use fixplan_coordinator::Backend;
use fixplan_coordinator::{render, show};
use fixplan_coordinator::{run_catalog, RunOptions};
use fixplan_coordinator::{PartRecord, ResultsFile};
use fixplan_core::{Part, Status, Units, Vertex};
use std::path::{Path, PathBuf};

use fixplan_coordinator::run_parts;
use fixplan_coordinator::{merge_files, Slice};
use fixplan_tests::{catalog, channels, fixtures_channel, part};

fn opts(out: &Path, threads: usize, shard: Option<u64>) -> RunOptions {
    RunOptions {
        catalog: PathBuf::from("mem"),
        kit: "case-kit".into(),
        top_k: Some(5),
        full_counts: false,
        output: out.to_path_buf(),
        resume: false,
        shard_size: shard,
        quiet: true,
        search: Default::default(),
        backend: Backend::Embedded {
            threads: Some(threads),
        },
        arcs: None,
    }
}

#[test]
fn same_bytes_whatever_threads_and_shards() {
    let dir = tempfile::tempdir().unwrap();
    let (cat, spec) = catalog();
    let a = dir.path().join("a.mcap");
    let b = dir.path().join("b.mcap");
    let c = dir.path().join("c.mcap");
    let t = run_catalog(&cat, &spec, &opts(&a, 1, Some(1))).unwrap();
    run_catalog(&cat, &spec, &opts(&b, 2, None)).unwrap();
    run_catalog(&cat, &spec, &opts(&c, 3, Some(7))).unwrap();
    assert_eq!(t.parts(), 6);
    assert_eq!(t.invalid, 2, "{t:?}");
    assert!(t.ok >= 3, "{t:?}");
    assert_eq!(t.no_fixture, 1, "{t:?}");
    let fa = fixtures_channel(&a);
    assert_eq!(fa.len(), 6);
    assert_eq!(fa, fixtures_channel(&b));
    assert_eq!(fa, fixtures_channel(&c));
    assert!(!dir.path().join("a.mcap.partial").exists());
}

#[test]
fn invalid_parts_carry_their_message() {
    let dir = tempfile::tempdir().unwrap();
    let (cat, spec) = catalog();
    let out = dir.path().join("r.mcap");
    run_catalog(&cat, &spec, &opts(&out, 2, None)).unwrap();
    let f = ResultsFile::open(&out).unwrap();
    let mut recs = Vec::new();
    f.for_each_part(|_, m| {
        recs.push(PartRecord::decode(&m).unwrap());
        true
    })
    .unwrap();
    let ids: Vec<_> = recs.iter().map(|r| r.part.id.clone()).collect();
    assert_eq!(ids, ["rect", "ell", "bowtie", "broken", "tiny", "hex"]);
    let bow = &recs[2];
    assert_eq!(Status::from(bow.part.status), Status::Invalid);
    let msg = bow.part.error.clone().unwrap();
    assert!(msg.starts_with("bowtie: "), "{msg}");
    assert!(msg.contains("cross"), "{msg}");
    assert_eq!(
        recs[3].fixtures.error.as_deref(),
        Some("broken: outline: edge 0 crosses edge 2 at (25, 25) mm")
    );
    assert_eq!(Status::from(recs[4].part.status), Status::NoFixture);
    assert_eq!(Status::from(recs[0].part.status), Status::Ok);
    assert_eq!(recs[0].fixtures.fixtures.len(), 5);
}

/// A 60 x 40 plate whose right end is an arc of this bulge: 1 a half
/// circle, -3 a bite so deep it crosses the left edge (invalid).
fn arc_part(id: &str, bulge: f64) -> CatalogPart {
    let outline = [
        [0.0, 0.0, 0.0],
        [60.0, 0.0, bulge],
        [60.0, 40.0, 0.0],
        [0.0, 40.0, 0.0],
    ];
    CatalogPart {
        part: Ok(Part {
            outline: outline.map(Vertex::from).to_vec(),
            holes: vec![],
            access: vec![],
        }),
        ..part(id, vec![])
    }
}

/// Parts with arcs through a run, `show` and `render`: the pictures draw
/// the arc with an SVG arc command (the invalid part's too, as read), and
/// `show` names the arcs and the contacts on them.
#[test]
fn arc_parts_through_show_and_render() {
    let dir = tempfile::tempdir().unwrap();
    let (_, spec) = catalog();
    let cat = Catalog {
        name: "arcs".into(),
        units: Units::Mm,
        source: PathBuf::from("mem"),
        parts: vec![arc_part("half-round", 1.0), arc_part("bitten", -3.0)],
    };
    let out = dir.path().join("r.mcap");
    let t = run_catalog(&cat, &spec, &opts(&out, 2, None)).unwrap();
    assert_eq!((t.ok, t.invalid), (1, 1), "{t:?}");

    let mut text = Vec::new();
    show(&out, None, 3, &mut text).unwrap();
    let text = String::from_utf8(text).unwrap();
    for want in [
        "== half-round [ok]",
        "   arcs: outline edges 1 of 4; segments 1 of 4 (marked * below)",
        " on arc segment 1: centre (",
        "== bitten [invalid]",
        "   arcs: outline edges 1 of 4\n",
    ] {
        assert!(text.contains(want), "{want:?} not in\n{text}");
    }

    let pics = dir.path().join("pics");
    assert_eq!(render(&out, &pics, None, 1).unwrap(), 2);
    let svg = std::fs::read_to_string(pics.join("0000-half-round-rank01.svg")).unwrap();
    // Half circle: large-arc 0; bulge > 0 turns clockwise on screen: sweep 0.
    assert!(
        svg.contains("<path d=\"M") && svg.contains(" 0 0 0 "),
        "{svg}"
    );
    let svg = std::fs::read_to_string(pics.join("0001-bitten.svg")).unwrap();
    // 4 atan(3) is over half a circle (large-arc 1); bulge < 0: sweep 1.
    assert!(
        svg.contains("<path d=\"M") && svg.contains(" 0 1 1 "),
        "{svg}"
    );
}

/// A catalogue in three slices, one run each (as three coordinators),
/// merged in any order: the whole run's fixtures and scenes, byte for
/// byte. A missing slice, or one given twice, is refused.
#[test]
fn slices_merge_into_the_whole_run() {
    let dir = tempfile::tempdir().unwrap();
    let (cat, spec) = catalog();
    let whole = dir.path().join("whole.mcap");
    run_catalog(&cat, &spec, &opts(&whole, 2, None)).unwrap();
    let slices: Vec<PathBuf> = (1..=3)
        .map(|k| {
            let out = dir.path().join(format!("slice-{k}.mcap"));
            let parts = Slice { k, n: 3 }.parts(cat.parts.len());
            let t = run_parts(&cat, &spec, &opts(&out, 1, None), parts.clone()).unwrap();
            assert_eq!(t.parts(), parts.len());
            out
        })
        .collect();
    let merged = dir.path().join("merged.mcap");
    let order = [slices[2].clone(), slices[0].clone(), slices[1].clone()];
    let m = merge_files(&order, &merged).unwrap();
    assert_eq!((m.files, m.parts), (3, cat.parts.len()));
    assert_eq!(channels(&merged), channels(&whole));

    let bad = dir.path().join("bad.mcap");
    let missing = merge_files(&slices[..2], &bad).unwrap_err().to_string();
    assert!(missing.contains("a slice is missing"), "{missing}");
    let twice = [slices[0].clone(), slices[1].clone(), slices[1].clone()];
    let again = merge_files(&twice, &bad).unwrap_err().to_string();
    assert!(again.contains("comes again"), "{again}");
    assert!(!bad.exists() && !dir.path().join("bad.mcap.partial").exists());
}
