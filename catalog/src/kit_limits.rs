//! The sizes and numbers of a kit checked before anything is built from
//! them. Core's rules (SPEC section 1) say what a kit may be; these say
//! what fixplan can hold: a plate of at most [`MAX_PLATE_HOLES`] holes
//! (`rows = 100000000` passed core's check and then hung the lattice
//! walks), and clamp lengths within the plate's scale (an `axis_offset`
//! of `-1e300` is finite, and meaningless on a plate some metres across).

use fixplan_core::Kit;

/// Most holes a plate may have. The largest modular plates have a few
/// thousand (a 1.5 x 1 m table at 25 mm: 60 x 40); a hundred thousand
/// holes (e.g. 316 x 316) is far beyond any, and every lattice walk stays
/// bounded.
pub const MAX_PLATE_HOLES: u64 = 100_000;

/// The plate's scale: its width plus its height, in the kit's unit. Any
/// length of the clamp beyond it cannot meet the plate's holes.
pub fn plate_scale(kit: &Kit) -> f64 {
    kit.spacing * (f64::from(kit.cols) + f64::from(kit.rows))
}

/// Checks the plate's size and that every clamp length is a finite number
/// within [`plate_scale`]; the message names the field and the bound.
pub fn check_kit_sizes(kit: &Kit) -> Result<(), String> {
    let holes = u64::from(kit.cols) * u64::from(kit.rows);
    if holes > MAX_PLATE_HOLES {
        return Err(format!(
            "plate of {} x {} holes has {holes} holes; fixplan handles plates of at most {MAX_PLATE_HOLES}",
            kit.cols, kit.rows
        ));
    }
    let scale = plate_scale(kit);
    if !scale.is_finite() {
        return Err(format!(
            "spacing {} makes a plate of {} x {} holes too large to measure",
            kit.spacing, kit.cols, kit.rows
        ));
    }
    let c = &kit.clamp;
    let within = |x: f64| x.is_finite() && x.abs() <= scale;
    let bound = |what: String, x: f64| {
        format!(
            "clamp {what} {x:e} is outside the plate's scale: a finite number within \u{b1}{scale} (spacing x (cols + rows))"
        )
    };
    if !within(c.axis_offset) {
        return Err(bound("axis_offset".into(), c.axis_offset));
    }
    for (i, t) in c.travel.iter().enumerate() {
        if !within(*t) {
            return Err(bound(format!("travel[{i}]"), *t));
        }
    }
    for (name, poly) in [("body", &c.body), ("plunger", &c.plunger)] {
        for (i, p) in poly.iter().enumerate() {
            if let Some(x) = p.iter().find(|x| !within(**x)) {
                return Err(bound(format!("{name} vertex {i}"), *x));
            }
        }
    }
    let reach = u64::from(kit.cols.max(kit.rows));
    if let Some(h) = c
        .mount_holes
        .iter()
        .find(|h| h.offset.iter().any(|o| o.unsigned_abs() > reach))
    {
        return Err(format!(
            "clamp mount hole {:?} is farther than the plate's {reach} holes from mount hole 0",
            h.offset
        ));
    }
    Ok(())
}
