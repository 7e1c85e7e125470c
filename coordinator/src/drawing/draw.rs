//! The geometry of a fixture as it stands on the physical plate, in the
//! catalogue's unit with hole `[0, 0]` at the origin: what the SVG pictures
//! and the Foxglove scene both draw.

use super::outline::{extent_points, moved};
use fixplan_core::{FixtureReport, Kit, Pattern, Point, Vertex};

/// A circle as drawn (a locator, the clamp tip, a hole): centre and
/// radius.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DrawnCircle {
    /// Centre, plate frame.
    pub centre: Point,
    /// Radius, catalogue unit.
    pub radius: f64,
}

/// A contact as drawn: where the part is touched and the inward normal
/// there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactMark {
    /// Where the locator or clamp tip touches the part's edge.
    pub at: Point,
    /// Unit normal into the part: the direction the contact pushes.
    pub normal: Point,
}

/// A plate hole: position (plate frame) and whether it is a dowel hole.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlateHole {
    /// Column, as the placement's `[col, row]` names it.
    pub col: i64,
    /// Row.
    pub row: i64,
    /// Centre, plate frame.
    pub at: Point,
    /// A dowel hole takes a locator; the others are tapped (alternating
    /// pattern), and are drawn differently.
    pub dowel: bool,
}

/// Everything to draw for one fixture, in plate coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct FixtureDrawing {
    /// The part's outline in its pose: vertices moved, bulges unchanged
    /// (the pose and the plate's turn are rotations, never reflections).
    pub part: Vec<Vertex>,
    /// The part's holes (SPEC 9) in its pose, in order, as the outline.
    pub holes: Vec<Vec<Vertex>>,
    /// The access regions in the part's pose (nothing may cover them).
    pub access: Vec<Vec<Point>>,
    /// Locators 1-3, in the order the report lists them.
    pub locators: [DrawnCircle; 3],
    /// The clamp body at its mount and rotation.
    pub clamp_body: Vec<Point>,
    /// The plunger, moved out by the clamp's extension.
    pub plunger: Vec<Point>,
    /// The plunger's tip, where the clamp touches the part.
    pub tip: DrawnCircle,
    /// Locators 1-3 then the clamp.
    pub contacts: Vec<ContactMark>,
    /// Holes used by the clamp mount.
    pub clamp_holes: Vec<Point>,
}

fn rot(theta: f64, p: Point) -> Point {
    let (s, c) = theta.sin_cos();
    [c * p[0] - s * p[1], s * p[0] + c * p[1]]
}

fn rot90(k: u32, p: Point) -> Point {
    match (k / 90) % 4 {
        0 => p,
        1 => [-p[1], p[0]],
        2 => [-p[0], -p[1]],
        _ => [p[1], -p[0]],
    }
}

fn add(a: Point, b: Point) -> Point {
    [a[0] + b[0], a[1] + b[1]]
}

/// The plate holes: `(col, row)` at `(col, row) * spacing`.
pub fn plate_holes(kit: &Kit) -> impl Iterator<Item = PlateHole> + '_ {
    let l = kit.spacing;
    (0..kit.rows as i64).flat_map(move |row| {
        (0..kit.cols as i64).map(move |col| PlateHole {
            col,
            row,
            at: [col as f64 * l, row as f64 * l],
            dowel: kit.pattern == Pattern::Square || (col + row).rem_euclid(2) == 0,
        })
    })
}

/// The plate rectangle (hole centres plus half a spacing all round).
pub fn plate_outline(kit: &Kit) -> Vec<Point> {
    let l = kit.spacing;
    let (w, h) = ((kit.cols as f64 - 0.5) * l, (kit.rows as f64 - 0.5) * l);
    vec![[-0.5 * l, -0.5 * l], [w, -0.5 * l], [w, h], [-0.5 * l, h]]
}

/// Places a reported fixture on the plate: the canonical frame is rotated
/// by the placement rotation and moved so that locator 1 sits in its hole.
/// `holes` are the part's (SPEC 9), drawn with its outline.
pub fn fixture_drawing(
    kit: &Kit,
    outline: &[Vertex],
    holes: &[Vec<Vertex>],
    access: &[Vec<Point>],
    fixture: &FixtureReport,
) -> FixtureDrawing {
    let l = kit.spacing;
    let r = kit.locator_radius;
    let off = fixture.placement.locators[0];
    let off = [off[0] as f64 * l, off[1] as f64 * l];
    let place = |p: Point| add(rot90(fixture.placement.rotation_deg, p), off);
    let place_dir = |d: Point| rot90(fixture.placement.rotation_deg, d);
    let theta = fixture.pose.theta_deg.to_radians();
    let pose = |p: &Point| place(add(rot(theta, *p), [fixture.pose.x, fixture.pose.y]));
    let k = fixture.clamp.rotation_deg;
    let mount = [
        fixture.clamp.mount[0] as f64 * l,
        fixture.clamp.mount[1] as f64 * l,
    ];
    let clamp_pt = |p: &Point, t: f64| place(add(mount, rot90(k, [p[0] + t, p[1]])));
    let locators = fixture.locators.map(|p| DrawnCircle {
        centre: place([p[0] as f64 * l, p[1] as f64 * l]),
        radius: r,
    });
    let contacts = fixture
        .contacts
        .iter()
        .map(|c| {
            let n = place_dir(c.normal);
            let centre = place(c.point);
            ContactMark {
                at: [centre[0] + r * n[0], centre[1] + r * n[1]],
                normal: n,
            }
        })
        .collect();
    FixtureDrawing {
        part: moved(outline, pose),
        holes: holes.iter().map(|h| moved(h, pose)).collect(),
        access: access
            .iter()
            .map(|a| a.iter().map(pose).collect())
            .collect(),
        locators,
        clamp_body: kit.clamp.body.iter().map(|p| clamp_pt(p, 0.0)).collect(),
        plunger: kit
            .clamp
            .plunger
            .iter()
            .map(|p| clamp_pt(p, fixture.clamp.extension))
            .collect(),
        tip: DrawnCircle {
            centre: place(fixture.clamp.contact),
            radius: r,
        },
        contacts,
        clamp_holes: fixture
            .placement
            .clamp_holes
            .iter()
            .map(|h| [h[0] as f64 * l, h[1] as f64 * l])
            .collect(),
    }
}

/// Bounding box `[min, max]` of the points; `None` if there are none.
pub fn bounds<'a>(pts: impl IntoIterator<Item = &'a Point>) -> Option<[Point; 2]> {
    let mut it = pts
        .into_iter()
        .filter(|p| p[0].is_finite() && p[1].is_finite());
    let first = *it.next()?;
    let mut b = [first, first];
    for p in it {
        b[0] = [b[0][0].min(p[0]), b[0][1].min(p[1])];
        b[1] = [b[1][0].max(p[0]), b[1][1].max(p[1])];
    }
    Some(b)
}

impl FixtureDrawing {
    /// Bounding box of everything drawn (part with its arcs, clamp,
    /// locators).
    pub fn bounds(&self) -> [Point; 2] {
        let mut pts: Vec<Point> = extent_points(&self.part);
        pts.extend(self.clamp_body.iter().copied());
        pts.extend(self.plunger.iter().copied());
        for a in &self.access {
            pts.extend(a.iter().copied());
        }
        for c in self.locators.iter().chain(std::iter::once(&self.tip)) {
            let [x, y] = c.centre;
            pts.push([x - c.radius, y - c.radius]);
            pts.push([x + c.radius, y + c.radius]);
        }
        bounds(&pts).unwrap_or([[0.0, 0.0], [1.0, 1.0]])
    }
}
