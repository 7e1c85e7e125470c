//! One part end to end, and the conversion of lattice-unit fixtures into the
//! reported form (catalogue unit, degrees, plate placement).

use crate::enumerate::prepare::{prepare, PreparedPart};
use crate::enumerate::shards::PartialResult;
use crate::input::{Case, Kit, Params, Part, Units};
use crate::results::ranking::Fixture;
use crate::results::report::{
    ClampReport, ContactReport, FixtureReport, PlacementReport, PoseReport, SolveResult, Status,
};

/// Enumerates a part completely; invalid input becomes `status: invalid`.
pub fn solve(part: &Part, kit: &Kit, params: &Params, units: Units) -> SolveResult {
    match prepare(part, kit, params, units) {
        Ok(prep) => {
            let res = prep.enumerate_all();
            report(&prep, &res)
        }
        Err(e) => SolveResult::invalid(e.to_string()),
    }
}

/// [`solve`] of a case file, for `fixplan solve` and the reference tests.
pub fn solve_case(case: &Case) -> SolveResult {
    solve(&case.part(), &case.kit, &case.params, case.units)
}

/// The reported result of a (merged) partial result covering the whole part.
pub fn report(prep: &PreparedPart, res: &PartialResult) -> SolveResult {
    let fixtures: Vec<FixtureReport> = res
        .fixtures
        .iter()
        .enumerate()
        .map(|(i, f)| fixture_report(prep, f, i + 1))
        .collect();
    SolveResult {
        // Not the admissible count: top-k mode does not count it, and a
        // part with an admissible fixture has one in its top-k.
        status: if !res.fixtures.is_empty() {
            Status::Ok
        } else {
            Status::NoFixture
        },
        error: None,
        counts: Some(res.counts),
        segment_kinds: prep.segments().iter().map(|s| s.kind()).collect(),
        segment_loops: prep.segment_loops(),
        fixtures,
    }
}

/// One fixture in the reported form: lattice lengths times the spacing,
/// radians to degrees, and the clamp's holes placed on the plate.
pub fn fixture_report(prep: &PreparedPart, f: &Fixture, rank: usize) -> FixtureReport {
    let l = prep.spacing();
    let sc = |p: [f64; 2]| [p[0] * l, p[1] * l];
    let mut contacts: Vec<ContactReport> = (0..3)
        .map(|i| ContactReport {
            point: [f.locators[i][0] as f64 * l, f.locators[i][1] as f64 * l],
            normal: f.normals[i],
        })
        .collect();
    contacts.push(ContactReport {
        point: sc(f.contact),
        normal: f.normals[3],
    });
    let clamp_holes = prep
        .clamp_holes()
        .iter()
        .map(|h| {
            let p = crate::geometry::rot90i(f.rotation, h.offset);
            f.placement.hole([p[0] + f.mount[0], p[1] + f.mount[1]])
        })
        .collect();
    FixtureReport {
        rank,
        score: f.score,
        segments: f.segments,
        locators: f.locators,
        pose: PoseReport {
            x: f.t[0] * l,
            y: f.t[1] * l,
            theta_deg: f.theta.to_degrees(),
        },
        clamp: ClampReport {
            segment: f.clamp_segment,
            rotation_deg: 90 * f.rotation as u32,
            mount: f.mount,
            extension: f.extension * l,
            contact: sc(f.contact),
        },
        borderline: f.borderline,
        contacts,
        placement: PlacementReport {
            rotation_deg: 90 * f.placement.rotation as u32,
            locators: f.locators.map(|p| f.placement.hole(p)),
            clamp_holes,
        },
    }
}
