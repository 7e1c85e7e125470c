//! `/fixplan/scene` messages: a `foxglove.SceneUpdate` per part showing the
//! plate around the fixture, the part in its pose and the best fixture, in
//! metres, frame `plate`. Entity ids are the same for every part, so each
//! part's scene replaces the previous one as Foxglove plays the file.

use crate::draw::{bounds, fixture_drawing, plate_holes, plate_outline, Circle};
use crate::messages::NS_PER_PART;
use fixplan_core::{FixtureReport, Kit, Point, Units};
use serde_json::{json, Value};

pub const FRAME: &str = "plate";

struct Scene {
    m: f64,
    stamp: Value,
}

fn color(r: f64, g: f64, b: f64, a: f64) -> Value {
    json!({"r": r, "g": g, "b": b, "a": a})
}

fn identity_pose(x: f64, y: f64, z: f64) -> Value {
    json!({"position": {"x": x, "y": y, "z": z}, "orientation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}})
}

impl Scene {
    fn p3(&self, p: &Point, z: f64) -> Value {
        json!({"x": p[0] * self.m, "y": p[1] * self.m, "z": z})
    }

    fn loop_line(&self, pts: &[Point], thickness_px: f64, c: Value) -> Value {
        json!({"type": 1, "pose": identity_pose(0.0, 0.0, 0.0), "thickness": thickness_px,
               "scale_invariant": true,
               "points": pts.iter().map(|p| self.p3(p, 0.0)).collect::<Vec<_>>(),
               "color": c, "colors": [], "indices": []})
    }

    fn disk(&self, c: &Circle, height: f64, col: Value) -> Value {
        let d = 2.0 * c.r * self.m;
        json!({"pose": identity_pose(c.c[0] * self.m, c.c[1] * self.m, height / 2.0),
               "size": {"x": d, "y": d, "z": height},
               "bottom_scale": 1.0, "top_scale": 1.0, "color": col})
    }

    fn arrow(&self, at: Point, dir: Point, len: f64, col: Value) -> Value {
        let a = dir[1].atan2(dir[0]) / 2.0;
        json!({"pose": {"position": self.p3(&at, 0.001),
                        "orientation": {"x": 0.0, "y": 0.0, "z": a.sin(), "w": a.cos()}},
               "shaft_length": len * 0.7, "shaft_diameter": len * 0.08,
               "head_length": len * 0.3, "head_diameter": len * 0.2, "color": col})
    }

    fn text(&self, at: Point, text: &str) -> Value {
        json!({"pose": identity_pose(at[0] * self.m, at[1] * self.m, 0.01), "billboard": true,
               "font_size": 14.0, "scale_invariant": true, "color": color(1.0, 1.0, 1.0, 1.0),
               "text": text})
    }

    fn entity(&self, id: &str, fields: Value) -> Value {
        let mut e = json!({"timestamp": self.stamp, "frame_id": FRAME, "id": id,
            "lifetime": {"sec": 0, "nsec": 0}, "frame_locked": false, "metadata": [],
            "arrows": [], "cubes": [], "spheres": [], "cylinders": [], "lines": [],
            "triangles": [], "texts": [], "models": []});
        if let (Some(o), Some(f)) = (e.as_object_mut(), fields.as_object()) {
            for (k, v) in f {
                o.insert(k.clone(), v.clone());
            }
        }
        e
    }
}

/// The scene of part `index`: with a fixture, the part posed on the plate
/// with the best fixture; without, the outline alone in the part frame.
pub fn scene_update(
    index: usize,
    id: &str,
    units: Units,
    kit: &Kit,
    outline: &[Point],
    access: &[Vec<Point>],
    best: Option<&FixtureReport>,
) -> Value {
    let ns = index as u64 * NS_PER_PART;
    let s = Scene {
        m: units.mm_per_unit() / 1000.0,
        stamp: json!({"sec": ns / 1_000_000_000, "nsec": ns % 1_000_000_000}),
    };
    let part_col = color(0.2, 0.6, 1.0, 1.0);
    let access_col = color(1.0, 0.55, 0.0, 1.0);
    let mut entities = Vec::new();
    let Some(f) = best else {
        let lines: Vec<Value> = std::iter::once(s.loop_line(outline, 3.0, part_col))
            .chain(
                access
                    .iter()
                    .map(|a| s.loop_line(a, 2.0, access_col.clone())),
            )
            .collect();
        let at = bounds(outline).map(|b| b[1]).unwrap_or([0.0, 0.0]);
        entities.push(s.entity(
            "part",
            json!({"lines": lines, "texts": [s.text(at, &format!("{id}: no fixture"))]}),
        ));
        entities.push(s.entity("plate", json!({})));
        entities.push(s.entity("fixture", json!({})));
        return json!({"deletions": [], "entities": entities});
    };
    let d = fixture_drawing(kit, outline, access, f);
    let l = kit.spacing;
    let [lo, hi] = d.bounds();
    let hole_r = kit.locator_radius.min(0.3 * l);
    let holes: Vec<Value> = plate_holes(kit)
        .filter(|h| {
            h.at[0] >= lo[0] - 1.5 * l
                && h.at[0] <= hi[0] + 1.5 * l
                && h.at[1] >= lo[1] - 1.5 * l
                && h.at[1] <= hi[1] + 1.5 * l
        })
        .map(|h| {
            let c = if h.dowel {
                color(0.55, 0.55, 0.55, 1.0)
            } else {
                color(0.35, 0.35, 0.4, 1.0)
            };
            s.disk(&Circle { c: h.at, r: hole_r }, 0.0005, c)
        })
        .collect();
    entities.push(s.entity(
        "plate",
        json!({"lines": [s.loop_line(&plate_outline(kit), 2.0, color(0.6, 0.6, 0.6, 1.0))],
               "cylinders": holes}),
    ));
    let mut part_lines = vec![s.loop_line(&d.part, 3.0, part_col)];
    part_lines.extend(
        d.access
            .iter()
            .map(|a| s.loop_line(a, 2.0, access_col.clone())),
    );
    entities.push(s.entity(
        "part",
        json!({"lines": part_lines,
               "texts": [s.text(hi, &format!("{id}  rank {}  score {:.4}", f.rank, f.score))]}),
    ));
    let steel = color(0.85, 0.85, 0.2, 1.0);
    let mut cyl: Vec<Value> = d
        .locators
        .iter()
        .map(|c| s.disk(c, 0.01, steel.clone()))
        .collect();
    cyl.push(s.disk(&d.tip, 0.01, color(0.9, 0.2, 0.2, 1.0)));
    let arrows: Vec<Value> = d
        .contacts
        .iter()
        .map(|c| s.arrow(c.at, c.normal, 0.6 * l * s.m, color(0.1, 0.9, 0.3, 1.0)))
        .collect();
    entities.push(s.entity(
        "fixture",
        json!({"cylinders": cyl, "arrows": arrows,
               "lines": [s.loop_line(&d.clamp_body, 2.0, color(0.9, 0.2, 0.2, 1.0)),
                         s.loop_line(&d.plunger, 2.0, color(0.9, 0.5, 0.5, 1.0))]}),
    ));
    json!({"deletions": [], "entities": entities})
}
