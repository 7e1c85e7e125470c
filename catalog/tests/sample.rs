//! The shipped sample catalogues: they load, hold what the issue asks for,
//! and enumerate quickly with the built-in kits.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use fixplan_catalog::{load_catalog, load_kit};
use fixplan_core::{solve, Params, Status, Units};
use std::path::Path;
use std::time::Instant;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

#[test]
fn sample_catalogues_load_and_meet_the_brief() {
    let mm = load_catalog(&root().join("examples/catalog")).unwrap();
    let inch = load_catalog(&root().join("examples/catalog-inch/catalog.toml")).unwrap();
    assert_eq!(mm.units, Units::Mm);
    assert_eq!(inch.units, Units::In);
    for c in [&mm, &inch] {
        for p in &c.parts {
            assert!(p.part.is_ok(), "{:?}", p.part);
            for w in &p.warnings {
                println!("warning: {w}");
            }
        }
    }
    assert!(mm.parts.len() + inch.parts.len() >= 30);
    assert!(mm.parts.len() >= 30);
    let with_access = mm
        .parts
        .iter()
        .filter(|p| !p.part.as_ref().unwrap().access.is_empty())
        .count();
    assert!(with_access >= 3, "{with_access}");
    let ext = |e: &str| {
        mm.parts
            .iter()
            .filter(|p| p.file.as_ref().is_some_and(|f| f.extension().unwrap() == e))
            .count()
    };
    assert!(ext("dxf") >= 1 && ext("svg") >= 1 && ext("json") >= 1);
    let housing = mm.parts.iter().find(|p| p.id == "housing-3").unwrap();
    // Its bore is a hole of the part (SPEC 9), read without a warning.
    assert_eq!(
        housing.part.as_ref().unwrap().holes.len(),
        1,
        "{:?}",
        housing.warnings
    );
    assert!(!housing
        .warnings
        .iter()
        .any(|w| w.contains("inside the outline")));
}

fn run(catalog: &str, kit: &str) -> Vec<(String, Status, usize)> {
    let cat = load_catalog(&root().join(catalog)).unwrap();
    let spec = load_kit(kit, cat.units).unwrap();
    cat.parts
        .iter()
        .map(|p| {
            let part = p.part.as_ref().unwrap();
            let params = Params {
                top_k: p.top_k.unwrap_or(spec.params.top_k),
                wrenches: p.wrenches.clone().or(spec.params.wrenches.clone()),
                ..spec.params.clone()
            };
            let t = Instant::now();
            let r = solve(part, &spec.kit, &params, cat.units);
            let n = part.outline.len();
            println!(
                "{:<16} {:>3} edges {:?} {:?} in {:?}",
                p.id,
                n,
                r.status,
                r.counts.map(|c| c.admissible),
                t.elapsed()
            );
            (p.id.clone(), r.status, n)
        })
        .collect()
}

#[test]
fn sample_catalogue_enumerates_with_metric_kit() {
    let res = run("examples/catalog", "metric-25");
    let no_fix: Vec<_> = res
        .iter()
        .filter(|r| r.1 == Status::NoFixture)
        .map(|r| &r.0)
        .collect();
    assert!(no_fix.len() >= 2, "{no_fix:?}");
    for id in ["tiny-tab", "tiny-pin", "masked-plate"] {
        assert!(
            no_fix.iter().any(|n| *n == id),
            "{id} should have no fixture: {no_fix:?}"
        );
    }
    assert!(res.iter().all(|r| r.1 != Status::Invalid));
    assert!(res.iter().all(|r| r.2 <= 45), "{res:?}");
    let ok = res.iter().filter(|r| r.1 == Status::Ok).count();
    assert!(ok >= 25, "{res:?}");
}

#[test]
fn inch_catalogue_enumerates_with_paper_kit() {
    let res = run("examples/catalog-inch", "paper-inch");
    assert!(res
        .iter()
        .any(|r| r.0 == "in-tiny" && r.1 == Status::NoFixture));
    assert!(
        res.iter().filter(|r| r.1 == Status::Ok).count() >= 5,
        "{res:?}"
    );
}
