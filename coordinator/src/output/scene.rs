//! `/fixplan/scene` messages: a `foxglove.SceneUpdate` per part showing the
//! plate around the fixture, the part in its pose and the best fixture, in
//! metres, frame `plate`. Entity ids are the same for every part, so each
//! part's scene replaces the previous one as Foxglove plays the file.
//!
//! Typed structs, not `serde_json::Value`: a `Value` per plate hole makes
//! the scene most of the coordinator's time in a distributed run
//! (docs/performance.md). Fields are declared in alphabetical order, the
//! order a `Value` map writes them in, which the file's bytes keep.

use crate::drawing::draw::{
    bounds, fixture_drawing, plate_holes, plate_outline, DrawnCircle, FixtureDrawing, PlateHole,
};
use crate::drawing::hole_contacts::hole_contact_label;
use crate::drawing::outline::{extent_points, flattened, moved};
use crate::output::messages::NS_PER_PART;
use fixplan_core::{FixtureReport, Kit, Point, Units, Vertex};
use serde::Serialize;
use std::cell::RefCell;

/// The frame every entity is drawn in: the plate, hole `[0, 0]` at the
/// origin, the same for every part so that scenes replace each other.
pub const FRAME: &str = "plate";

#[derive(Serialize, Clone, Copy)]
struct Color {
    a: f64,
    b: f64,
    g: f64,
    r: f64,
}

const fn color(red: f64, green: f64, blue: f64, alpha: f64) -> Color {
    Color {
        a: alpha,
        b: blue,
        g: green,
        r: red,
    }
}

#[derive(Serialize)]
struct Vec3 {
    x: f64,
    y: f64,
    z: f64,
}

#[derive(Serialize)]
struct Quat {
    w: f64,
    x: f64,
    y: f64,
    z: f64,
}

#[derive(Serialize)]
struct ScenePose {
    orientation: Quat,
    position: Vec3,
}

fn identity_pose(x: f64, y: f64, z: f64) -> ScenePose {
    ScenePose {
        orientation: Quat {
            w: 1.0,
            x: 0.0,
            y: 0.0,
            z: 0.0,
        },
        position: Vec3 { x, y, z },
    }
}

#[derive(Serialize)]
struct Time {
    nsec: u64,
    sec: u64,
}

#[derive(Serialize)]
struct SceneLine {
    color: Color,
    colors: [Color; 0],
    indices: [u32; 0],
    points: Vec<Vec3>,
    pose: ScenePose,
    scale_invariant: bool,
    thickness: f64,
    #[serde(rename = "type")]
    kind: u8,
}

#[derive(Serialize)]
struct Cylinder {
    bottom_scale: f64,
    color: Color,
    pose: ScenePose,
    size: Vec3,
    top_scale: f64,
}

#[derive(Serialize)]
struct Arrow {
    color: Color,
    head_diameter: f64,
    head_length: f64,
    pose: ScenePose,
    shaft_diameter: f64,
    shaft_length: f64,
}

#[derive(Serialize)]
struct Text {
    billboard: bool,
    color: Color,
    font_size: f64,
    pose: ScenePose,
    scale_invariant: bool,
    text: String,
}

/// The primitives of one entity (the kinds fixplan draws; the others stay
/// empty).
#[derive(Default)]
struct Shapes {
    arrows: Vec<Arrow>,
    cylinders: Vec<Cylinder>,
    lines: Vec<SceneLine>,
    texts: Vec<Text>,
}

#[derive(Serialize)]
struct SceneEntity<'a> {
    arrows: Vec<Arrow>,
    cubes: [(); 0],
    cylinders: Vec<Cylinder>,
    frame_id: &'a str,
    frame_locked: bool,
    id: &'a str,
    lifetime: Time,
    lines: Vec<SceneLine>,
    metadata: [(); 0],
    models: [(); 0],
    spheres: [(); 0],
    texts: Vec<Text>,
    timestamp: Time,
    triangles: [(); 0],
}

/// A `foxglove.SceneUpdate`.
#[derive(Serialize)]
pub struct SceneUpdate<'a> {
    deletions: [(); 0],
    entities: Vec<SceneEntity<'a>>,
}

struct Scene {
    m: f64,
    ns: u64,
    /// Largest distance between an arc and the chords that draw it
    /// (catalogue unit): `1e-3` of the part's size.
    chord_error: f64,
}

impl Scene {
    fn p3(&self, p: &Point, z: f64) -> Vec3 {
        Vec3 {
            x: p[0] * self.m,
            y: p[1] * self.m,
            z,
        }
    }

    fn loop_line(&self, pts: &[Point], thickness: f64, color: Color) -> SceneLine {
        SceneLine {
            color,
            colors: [],
            indices: [],
            points: pts.iter().map(|p| self.p3(p, 0.0)).collect(),
            pose: identity_pose(0.0, 0.0, 0.0),
            scale_invariant: true,
            thickness,
            kind: 1,
        }
    }

    /// A part outline as a closed line strip, arcs cut into short chords
    /// (Foxglove has no arc primitive); a polygon's points are its
    /// vertices, as before arcs.
    fn outline_line(&self, outline: &[Vertex], thickness: f64, color: Color) -> SceneLine {
        self.loop_line(&flattened(outline, self.chord_error), thickness, color)
    }

    fn disk(&self, circle: &DrawnCircle, height: f64, color: Color) -> Cylinder {
        let d = 2.0 * circle.radius * self.m;
        Cylinder {
            bottom_scale: 1.0,
            color,
            pose: identity_pose(
                circle.centre[0] * self.m,
                circle.centre[1] * self.m,
                height / 2.0,
            ),
            size: Vec3 {
                x: d,
                y: d,
                z: height,
            },
            top_scale: 1.0,
        }
    }

    fn arrow(&self, at: Point, dir: Point, len: f64, color: Color) -> Arrow {
        let a = dir[1].atan2(dir[0]) / 2.0;
        Arrow {
            color,
            head_diameter: len * 0.2,
            head_length: len * 0.3,
            pose: ScenePose {
                orientation: Quat {
                    w: a.cos(),
                    x: 0.0,
                    y: 0.0,
                    z: a.sin(),
                },
                position: self.p3(&at, 0.001),
            },
            shaft_diameter: len * 0.08,
            shaft_length: len * 0.7,
        }
    }

    fn text(&self, at: Point, text: String) -> Text {
        Text {
            billboard: true,
            color: color(1.0, 1.0, 1.0, 1.0),
            font_size: 14.0,
            pose: identity_pose(at[0] * self.m, at[1] * self.m, 0.01),
            scale_invariant: true,
            text,
        }
    }

    fn entity<'a>(&self, id: &'a str, shapes: Shapes) -> SceneEntity<'a> {
        SceneEntity {
            arrows: shapes.arrows,
            cubes: [],
            cylinders: shapes.cylinders,
            frame_id: FRAME,
            frame_locked: false,
            id,
            lifetime: Time { nsec: 0, sec: 0 },
            lines: shapes.lines,
            metadata: [],
            models: [],
            spheres: [],
            texts: shapes.texts,
            timestamp: Time {
                nsec: self.ns % 1_000_000_000,
                sec: self.ns / 1_000_000_000,
            },
            triangles: [],
        }
    }
}

/// Outline colour of the part.
const PART: Color = color(0.2, 0.6, 1.0, 1.0);
/// Outline colour of the access regions.
const ACCESS: Color = color(1.0, 0.55, 0.0, 1.0);

impl Scene {
    /// Without a fixture: the plate, as with one, and on it the part's
    /// outline and access regions centred on the plate (the part frame
    /// has no place on the plate) with the caption saying why there is no
    /// fixture; an empty fixture entity clears the previous part's.
    fn unplaced(
        &self,
        kit: &Kit,
        caption: &str,
        outline: &[Vertex],
        holes: &[Vec<Vertex>],
        access: &[Vec<Point>],
    ) -> Vec<SceneEntity<'static>> {
        let plate = plate_outline(kit);
        let middle = |b: Option<[Point; 2]>| {
            b.map(|[lo, hi]| [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0])
        };
        let to = middle(bounds(&plate)).unwrap_or([0.0, 0.0]);
        let from = middle(bounds(&extent_points(outline))).unwrap_or(to);
        let shift = |p: &Point| [p[0] - from[0] + to[0], p[1] - from[1] + to[1]];
        let outline = moved(outline, shift);
        let holes: Vec<Vec<Vertex>> = holes.iter().map(|h| moved(h, shift)).collect();
        let access: Vec<Vec<Point>> = access
            .iter()
            .map(|a| a.iter().map(shift).collect())
            .collect();
        let lines = std::iter::once(self.outline_line(&outline, 3.0, PART))
            .chain(holes.iter().map(|h| self.outline_line(h, 2.0, PART)))
            .chain(access.iter().map(|a| self.loop_line(a, 2.0, ACCESS)))
            .collect();
        let extent = bounds(&extent_points(&outline)).unwrap_or([to, to]);
        let texts = vec![self.text(extent[1], caption.to_string())];
        vec![
            self.plate(kit, extent),
            self.entity(
                "part",
                Shapes {
                    lines,
                    texts,
                    ..Shapes::default()
                },
            ),
            self.entity("fixture", Shapes::default()),
        ]
    }

    /// The disk of one plate hole: the same for every part of a run.
    fn hole_disk(&self, kit: &Kit, hole: &PlateHole) -> Cylinder {
        let hole_r = kit.locator_radius.min(0.3 * kit.spacing);
        let c = if hole.dowel {
            color(0.55, 0.55, 0.55, 1.0)
        } else {
            color(0.35, 0.35, 0.4, 1.0)
        };
        self.disk(
            &DrawnCircle {
                centre: hole.at,
                radius: hole_r,
            },
            0.0005,
            c,
        )
    }

    /// The plate: its edge and the holes within 1.5 spacings of the
    /// fixture's bounds `[lo, hi]` (a whole plate is hundreds of disks a
    /// part).
    fn plate(&self, kit: &Kit, extent: [Point; 2]) -> SceneEntity<'static> {
        let holes = plate_holes(kit)
            .filter(|h| near_fixture(kit, extent, h.at))
            .map(|h| self.hole_disk(kit, &h))
            .collect();
        self.plate_with(kit, holes)
    }

    /// The plate entity with these hole disks.
    fn plate_with(&self, kit: &Kit, holes: Vec<Cylinder>) -> SceneEntity<'static> {
        self.entity(
            "plate",
            Shapes {
                lines: vec![self.loop_line(&plate_outline(kit), 2.0, color(0.6, 0.6, 0.6, 1.0))],
                cylinders: holes,
                ..Shapes::default()
            },
        )
    }

    /// The part in its pose (outline and holes), access regions, and its
    /// rank, score and contacts in holes at
    /// `hi`, the fixture's top right corner.
    fn posed_part(
        &self,
        id: &str,
        drawing: &FixtureDrawing,
        hi: Point,
        fixture: &FixtureReport,
        segment_loops: &[usize],
    ) -> SceneEntity<'static> {
        let mut part_lines = vec![self.outline_line(&drawing.part, 3.0, PART)];
        part_lines.extend(
            drawing
                .holes
                .iter()
                .map(|h| self.outline_line(h, 2.0, PART)),
        );
        part_lines.extend(
            drawing
                .access
                .iter()
                .map(|a| self.loop_line(a, 2.0, ACCESS)),
        );
        let mut label = format!("{id}  rank {}  score {:.4}", fixture.rank, fixture.score);
        if let Some(l) = hole_contact_label(segment_loops, fixture) {
            label = format!("{label}  {l}");
        }
        self.entity(
            "part",
            Shapes {
                lines: part_lines,
                texts: vec![self.text(hi, label)],
                ..Shapes::default()
            },
        )
    }

    /// Locators, clamp (body, plunger, tip) and the contact normals.
    fn fixture(&self, kit: &Kit, drawing: &FixtureDrawing) -> SceneEntity<'static> {
        let steel = color(0.85, 0.85, 0.2, 1.0);
        let mut cylinders: Vec<Cylinder> = drawing
            .locators
            .iter()
            .map(|c| self.disk(c, 0.01, steel))
            .collect();
        cylinders.push(self.disk(&drawing.tip, 0.01, color(0.9, 0.2, 0.2, 1.0)));
        let arrows = drawing
            .contacts
            .iter()
            .map(|c| {
                self.arrow(
                    c.at,
                    c.normal,
                    0.6 * kit.spacing * self.m,
                    color(0.1, 0.9, 0.3, 1.0),
                )
            })
            .collect();
        self.entity(
            "fixture",
            Shapes {
                arrows,
                cylinders,
                lines: vec![
                    self.loop_line(&drawing.clamp_body, 2.0, color(0.9, 0.2, 0.2, 1.0)),
                    self.loop_line(&drawing.plunger, 2.0, color(0.9, 0.5, 0.5, 1.0)),
                ],
                ..Shapes::default()
            },
        )
    }
}

/// Whether the hole at `at` is drawn with a fixture of bounds `[lo, hi]`:
/// within 1.5 spacings of them.
fn near_fixture(kit: &Kit, [lo, hi]: [Point; 2], at: Point) -> bool {
    let l = kit.spacing;
    at[0] >= lo[0] - 1.5 * l
        && at[0] <= hi[0] + 1.5 * l
        && at[1] >= lo[1] - 1.5 * l
        && at[1] <= hi[1] + 1.5 * l
}

/// What the scene of a part shows: part `index` (its log time), its id,
/// the catalogue's unit, the kit, the outline and access regions (part
/// frame), and its best fixture or the caption saying why there is none.
#[derive(Clone, Copy)]
pub struct PartScene<'a> {
    /// Position in the catalogue.
    pub index: usize,
    /// Catalogue id.
    pub id: &'a str,
    /// The catalogue's unit.
    pub units: Units,
    /// The run's kit.
    pub kit: &'a Kit,
    /// The outline (as read, for an invalid part).
    pub outline: &'a [Vertex],
    /// Its holes (SPEC 9), drawn as thinner loops of the part's colour.
    pub holes: &'a [Vec<Vertex>],
    /// Access regions.
    pub access: &'a [Vec<Point>],
    /// The loop of every segment (SPEC 9.6; empty without holes), so the
    /// label names the contacts on a hole's wall.
    pub segment_loops: &'a [usize],
    /// The best fixture, or no fixture and why.
    pub best: Result<&'a FixtureReport, &'a str>,
}

/// The scene of part `index`: with a fixture, the part posed on the plate
/// with the best fixture; without, the plate and the outline centred on
/// it (for an invalid part, the outline as read) with `best`'s caption:
/// no fixture, or the error. Arcs are drawn as chords within `1e-3` of the
/// part's size (and 5 degrees of turn); contacts on arcs, as on lines, are
/// arrows along the reported inward normal.
pub fn scene_update(part: PartScene) -> SceneUpdate<'static> {
    let s = Scene::of(part.index, part.units, part.outline);
    let entities = match part.best {
        Err(caption) => s.unplaced(part.kit, caption, part.outline, part.holes, part.access),
        Ok(f) => {
            let d = fixture_drawing(part.kit, part.outline, part.holes, part.access, f);
            let extent = d.bounds();
            vec![
                s.plate(part.kit, extent),
                s.posed_part(part.id, &d, extent[1], f, part.segment_loops),
                s.fixture(part.kit, &d),
            ]
        }
    };
    SceneUpdate {
        deletions: [],
        entities,
    }
}

impl Scene {
    /// The scale and time of part `index`'s scene.
    fn of(index: usize, units: Units, outline: &[Vertex]) -> Scene {
        let size = bounds(&extent_points(outline))
            .map_or(0.0, |[lo, hi]| (hi[0] - lo[0]).max(hi[1] - lo[1]));
        Scene {
            m: units.mm_per_unit() / 1000.0,
            ns: index as u64 * NS_PER_PART,
            chord_error: 1e-3 * size,
        }
    }
}

/// The plate holes of one kit and unit as JSON, made once per thread: the
/// hole disks are most of a scene's bytes (hundreds of floats a part to
/// format) and the same for every part of a run, so a run copies them.
struct HoleCache {
    kit: Kit,
    m: f64,
    /// Each hole's centre (plate frame) and its disk's JSON.
    holes: Vec<(Point, Vec<u8>)>,
}

impl HoleCache {
    fn new(scene: &Scene, kit: &Kit) -> serde_json::Result<HoleCache> {
        let holes = plate_holes(kit)
            .map(|h| Ok((h.at, serde_json::to_vec(&scene.hole_disk(kit, &h))?)))
            .collect::<serde_json::Result<_>>()?;
        Ok(HoleCache {
            kit: kit.clone(),
            m: scene.m,
            holes,
        })
    }

    fn serves(&self, scene: &Scene, kit: &Kit) -> bool {
        self.m.to_bits() == scene.m.to_bits() && self.kit == *kit
    }
}

thread_local! {
    static HOLES: RefCell<Option<HoleCache>> = const { RefCell::new(None) };
}

/// What serde_json writes of a scene with a fixture before the first plate
/// hole: the plate is the first entity, and it has no arrows or cubes.
const BEFORE_HOLES: &[u8] = br#"{"deletions":[],"entities":[{"arrows":[],"cubes":[],"cylinders":["#;

/// The JSON of [`scene_update`], byte for byte, at a fraction of the cost:
/// the scene is serialised with no plate hole, and the holes near the
/// fixture are copied in from this thread's `HoleCache` where serde_json
/// would have written them.
pub fn scene_json(part: PartScene) -> serde_json::Result<Vec<u8>> {
    let whole = || serde_json::to_vec(&scene_update(part));
    let Ok(f) = part.best else {
        return whole();
    };
    let (id, kit) = (part.id, part.kit);
    let s = Scene::of(part.index, part.units, part.outline);
    let d = fixture_drawing(kit, part.outline, part.holes, part.access, f);
    let extent = d.bounds();
    let holeless = serde_json::to_vec(&SceneUpdate {
        deletions: [],
        entities: vec![
            s.plate_with(kit, Vec::new()),
            s.posed_part(id, &d, extent[1], f, part.segment_loops),
            s.fixture(kit, &d),
        ],
    })?;
    let Some(rest) = holeless.strip_prefix(BEFORE_HOLES) else {
        // Only if the layout of a scene changed: slower, still right.
        return whole();
    };
    HOLES.with_borrow_mut(|cache| {
        let c = match cache.take() {
            Some(c) if c.serves(&s, kit) => c,
            _ => HoleCache::new(&s, kit)?,
        };
        let mut out = Vec::with_capacity(holeless.len() + 64 * 1024);
        out.extend_from_slice(BEFORE_HOLES);
        let near = c
            .holes
            .iter()
            .filter(|(at, _)| near_fixture(kit, extent, *at));
        for (i, (_, json)) in near.enumerate() {
            if i > 0 {
                out.push(b',');
            }
            out.extend_from_slice(json);
        }
        out.extend_from_slice(rest);
        *cache = Some(c);
        Ok(out)
    })
}
