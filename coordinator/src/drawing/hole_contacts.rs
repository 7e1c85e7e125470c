//! Which contacts of a fixture stand on a hole's wall (SPEC 9.6's
//! `segment_loops`), named as a machinist reads them ("L2 in hole 3"), for
//! the pictures, `show` and the Foxglove scene alike.

use fixplan_core::FixtureReport;

/// The names of the contacts, in the order of a fixture's segments: the
/// three locators, then the clamp.
pub const CONTACT_NAMES: [&str; 4] = ["L1", "L2", "L3", "clamp"];

/// The hole (its index in the input) of each contact of `fixture`, `None` on
/// the outline; all `None` for a part without holes (`segment_loops`
/// empty).
pub fn contact_holes(segment_loops: &[usize], fixture: &FixtureReport) -> [Option<usize>; 4] {
    let on = [
        fixture.segments[0],
        fixture.segments[1],
        fixture.segments[2],
        fixture.clamp.segment,
    ];
    on.map(|s| segment_loops.get(s).and_then(|&l| l.checked_sub(1)))
}

/// `"L2 in hole 3, clamp in hole 0"` for the contacts of `fixture` on a hole's
/// wall; `None` when every contact is on the outline.
pub fn hole_contact_label(segment_loops: &[usize], fixture: &FixtureReport) -> Option<String> {
    let named: Vec<String> = CONTACT_NAMES
        .iter()
        .zip(contact_holes(segment_loops, fixture))
        .filter_map(|(name, hole)| hole.map(|k| format!("{name} in hole {k}")))
        .collect();
    (!named.is_empty()).then(|| named.join(", "))
}
