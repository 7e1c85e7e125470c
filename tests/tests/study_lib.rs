//! The exactness of the study's work sharing, at the library level: a
//! prepared part grafted with another kit's plate, clamp and parameters is
//! the part `prepare` gives for that kit; a grid step set on a prepared
//! part is the one `prepare` gives; the statistics' percentiles.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use fixplan_catalog::load_catalog;
use fixplan_coordinator::default_catalog;
use fixplan_coordinator::{median, nearest_rank, study_kits};
use fixplan_core::prepare;

#[test]
fn graft_equals_a_fresh_prepare() {
    let cat = load_catalog(&default_catalog()).unwrap();
    // Variants that keep the geometry (spacing, radius, trim) and change
    // everything else a sweep can change.
    let kits = study_kits(
        &["metric-25".into()],
        Some("plate=6x9; travel=40..80 mm; max_clamp_angle=60; min_clearance=0.5; grid_step=1,3"),
        cat.units,
    )
    .unwrap();
    let base = &kits[0].spec;
    let mut checked = 0;
    for cp in &cat.parts {
        let Ok(part) = &cp.part else { continue };
        let Ok(b) = prepare(part, &base.kit, &base.params, cat.units) else {
            continue;
        };
        for k in &kits[1..] {
            let mut params = k.spec.params.clone();
            params.top_k = 3;
            let g = b.with_kit(&k.spec.kit, &params, cat.units).unwrap();
            let f = prepare(part, &k.spec.kit, &params, cat.units).unwrap();
            assert_eq!(
                format!("{g:?}"),
                format!("{f:?}"),
                "{} {}",
                cp.id,
                k.spec.name
            );
            checked += 1;
        }
        for step in [2, 4] {
            let mut params = base.params.clone();
            params.grid_step = step;
            let f = prepare(part, &base.kit, &params, cat.units).unwrap();
            assert_eq!(
                format!("{:?}", b.with_grid_step(step).unwrap()),
                format!("{f:?}")
            );
        }
    }
    assert!(checked > 40, "{checked}");
}

#[test]
fn percentiles() {
    assert_eq!(median(&[]), None);
    assert_eq!(median(&[3.0]), Some(3.0));
    assert_eq!(median(&[1.0, 2.0, 4.0, 8.0]), Some(3.0));
    assert_eq!(nearest_rank(&[], 90.0), None);
    let v: Vec<f64> = (1..=10).map(f64::from).collect();
    assert_eq!(nearest_rank(&v, 90.0), Some(9.0));
    assert_eq!(nearest_rank(&v[..5], 90.0), Some(5.0));
    assert_eq!(nearest_rank(&[7.0], 90.0), Some(7.0));
}
