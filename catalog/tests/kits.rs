//! Kits: built-in, TOML files, unit conversion, validation through core.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

mod common;
use common::*;
use fixplan_catalog::kit::{parse_kit_toml, write_kit_toml};
use fixplan_catalog::{builtin_kit_names, load_kit};
use fixplan_core::{Pattern, Units};
use std::path::Path;

#[test]
fn builtin_kits_load_in_both_units() {
    assert_eq!(builtin_kit_names(), &["paper-inch", "metric-25"]);
    let p = load_kit("paper-inch", Units::In).unwrap();
    assert_eq!(p.kit.spacing, 0.75);
    assert_eq!(
        (p.kit.cols, p.kit.rows, p.kit.pattern),
        (18, 18, Pattern::Alternating)
    );
    assert_eq!(p.kit.locator_radius, 0.25);
    assert_eq!(p.params.edge_trim, Some(0.04));
    let pm = load_kit("paper-inch", Units::Mm).unwrap();
    assert!(close(pm.kit.spacing, 19.05, 1e-12));
    assert!(close(pm.kit.locator_radius, 6.35, 1e-12));
    assert!(close(pm.kit.clamp.travel[1], 2.75 * 25.4, 1e-12));
    assert!(close(pm.kit.clamp.body[1][0], 1.2 * 25.4, 1e-12));
    assert_eq!(pm.params.edge_trim, Some(1.0));
    let m = load_kit("metric-25", Units::Mm).unwrap();
    assert_eq!((m.kit.spacing, m.kit.pattern), (25.0, Pattern::Square));
    let mi = load_kit("metric-25", Units::In).unwrap();
    assert!(close(mi.kit.spacing, 25.0 / 25.4, 1e-15));
    assert!(close(mi.params.min_clearance.unwrap(), 1.0 / 25.4, 1e-15));
}

const KIT: &str = r#"
name = "shop"
units = "in"
spacing = 1.0
cols = 12
rows = 10
pattern = "alternating"
locator_radius = 0.25
[clamp]
mount_holes = [[0, 0, "dowel"], [1, 0, "tapped"]]
axis_offset = 0.1
travel = [1.5, 2.5]
body = [[-0.4, -0.4], [1.2, -0.4], [1.2, 0.4], [-0.4, 0.4]]
plunger = [[-2.5, -0.1], [-0.25, -0.1], [-0.25, 0.1], [-2.5, 0.1]]
[params]
max_clamp_angle_deg = 60
edge_trim = 0.05
top_k = 4
wrenches = [[0.0, -10.0, 2.0]]
"#;

#[test]
fn kit_file_converts_every_length() {
    let d = temp_dir("kit");
    let f = write(&d, "shop.toml", KIT);
    let k = load_kit(f.to_str().unwrap(), Units::Mm).unwrap();
    assert_eq!(k.name, "shop");
    assert_eq!(k.kit.spacing, 25.4);
    assert!(close(k.kit.clamp.axis_offset, 2.54, 1e-12));
    assert!(close(k.kit.clamp.plunger[0][1], -2.54, 1e-12));
    assert!(close(k.params.edge_trim.unwrap(), 1.27, 1e-12));
    // Not given: SPEC's default in the target unit.
    assert_eq!(k.params.min_clearance, Some(1.0));
    assert_eq!(k.params.max_clamp_angle_deg, 60.0);
    assert_eq!(k.params.top_k, 4);
    // Torque is force x length.
    assert!(close(
        k.params.wrenches.as_ref().unwrap()[0][2],
        50.8,
        1e-12
    ));
    assert_eq!(k.params.wrenches.as_ref().unwrap()[0][1], -10.0);
}

#[test]
fn kit_toml_round_trip() {
    let (kit, params, units, name) = parse_kit_toml(KIT, Path::new("k.toml")).unwrap();
    let text = write_kit_toml(name.as_deref().unwrap(), &kit, &params, units);
    let (kit2, params2, units2, name2) = parse_kit_toml(&text, Path::new("k2.toml")).unwrap();
    assert_eq!((kit, params, units, name), (kit2, params2, units2, name2));
}

fn kit_error(text: &str) -> String {
    let d = temp_dir("badkit");
    let f = write(&d, "bad.toml", text);
    load_kit(f.to_str().unwrap(), Units::In)
        .unwrap_err()
        .to_string()
}

#[test]
fn bad_kits_name_the_file_and_problem() {
    let e = kit_error(&KIT.replace("locator_radius = 0.25", "locator_radius = 0.8"));
    assert!(
        e.contains("bad.toml") && e.contains("locator_radius 0.8 is too large"),
        "{e}"
    );
    let e = kit_error(&KIT.replace("travel = [1.5, 2.5]", "travel = [3.0, 2.5]"));
    assert!(e.contains("travel min 3 is above max 2.5"), "{e}");
    let e = kit_error(&KIT.replace(
        "body = [[-0.4, -0.4], [1.2, -0.4], [1.2, 0.4], [-0.4, 0.4]]",
        "body = []",
    ));
    assert!(e.contains("clamp body polygon"), "{e}");
    let e = kit_error(&KIT.replace(
        "plunger = [[-2.5, -0.1], [-0.25, -0.1], [-0.25, 0.1], [-2.5, 0.1]]",
        "plunger = [[0, 0], [1, 1], [1, 0], [0, 1]]",
    ));
    assert!(
        e.contains("clamp plunger polygon edge 0 crosses edge 2"),
        "{e}"
    );
    let e = kit_error(&KIT.replace("units = \"in\"", "units = \"yards\""));
    assert!(e.contains("unknown units \"yards\""), "{e}");
    let e = kit_error(&KIT.replace("max_clamp_angle_deg = 60", "max_clamp_angle_deg = 120"));
    assert!(e.contains("max_clamp_angle_deg"), "{e}");
    let e = kit_error(&KIT.replace("cols = 12", "colz = 12"));
    assert!(e.contains("colz"), "{e}");
    let e = load_kit("no-such-kit", Units::Mm).unwrap_err().to_string();
    assert!(e.contains("paper-inch") && e.contains("metric-25"), "{e}");
}

/// The metric-25 kit as a [`fixplan_core::Kit`], to spoil one field of.
fn metric_25() -> fixplan_core::Kit {
    fixplan_catalog::kit::builtin_kit(fixplan_catalog::kit::METRIC_25)
        .unwrap()
        .0
}

#[test]
fn a_plate_of_too_many_holes_is_refused_with_the_limit() {
    use fixplan_catalog::kit_limits::check_kit_sizes;
    let mut kit = metric_25();
    assert_eq!(check_kit_sizes(&kit), Ok(()));
    kit.rows = 100_000_000;
    let e = check_kit_sizes(&kit).unwrap_err();
    assert!(
        e.contains("2000000000 holes") && e.contains("100000"),
        "{e}"
    );
}

#[test]
fn clamp_lengths_beyond_the_plate_are_refused() {
    use fixplan_catalog::kit_limits::check_kit_sizes;
    let base = metric_25();
    let mut kit = base.clone();
    kit.clamp.axis_offset = -1e300;
    let e = check_kit_sizes(&kit).unwrap_err();
    assert!(e.contains("axis_offset -1e300"), "{e}");
    let mut kit = base.clone();
    kit.clamp.travel[1] = 1e12;
    assert!(check_kit_sizes(&kit).unwrap_err().contains("travel[1]"));
    let mut kit = base.clone();
    kit.clamp.body[2][0] = f64::INFINITY;
    assert!(check_kit_sizes(&kit).unwrap_err().contains("body vertex 2"));
    let mut kit = base;
    kit.clamp.mount_holes[1].offset = [0, i64::MIN];
    assert!(check_kit_sizes(&kit).unwrap_err().contains("mount hole"));
}
