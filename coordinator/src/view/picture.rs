//! The SVG pictures of `fixplan render`: one per fixture (plate holes,
//! part in its pose, access regions shaded, locators, clamp body and
//! plunger at its extension, contact points and normals, score in the
//! caption), or one of the part alone when it has no fixture. Hand-written
//! SVG: small files that open in any browser and stay the same byte for
//! byte. A part's arcs are exact SVG arcs (`A` path commands); a polygon
//! part is a `polygon`, as before arcs.

use super::svg::escape;
use crate::drawing::draw::{bounds, fixture_drawing, plate_holes, plate_outline, FixtureDrawing};
use crate::drawing::hole_contacts::hole_contact_label;
use crate::drawing::outline::{extent_points, has_arcs, vertex_points};
use crate::output::messages::RunMsg;
use crate::output::reader::PartRecord;
use fixplan_core::parts::{edges_of, Edge};
use fixplan_core::{Counts, FixtureReport, Kit, Point, Status, Vertex};
use std::fmt::Write as _;

const WIDTH: f64 = 760.0;
const PAD: f64 = 20.0;
const CAPTION: f64 = 80.0;

/// Maps plate coordinates (y up) to SVG pixels (y down).
struct View {
    x0: f64,
    y1: f64,
    k: f64,
    w: f64,
    h: f64,
}

impl View {
    fn new(bounds: [Point; 2]) -> View {
        let (dx, dy) = (
            (bounds[1][0] - bounds[0][0]).max(1e-9),
            (bounds[1][1] - bounds[0][1]).max(1e-9),
        );
        let k = (WIDTH - 2.0 * PAD) / dx.max(dy * 1.0);
        let w = dx * k + 2.0 * PAD;
        let h = dy * k + 2.0 * PAD;
        View {
            x0: bounds[0][0],
            y1: bounds[1][1],
            k,
            w: w.max(WIDTH),
            h,
        }
    }

    fn p(&self, p: Point) -> (f64, f64) {
        (
            (p[0] - self.x0) * self.k + PAD,
            (self.y1 - p[1]) * self.k + PAD,
        )
    }

    fn points(&self, pts: &[Point]) -> String {
        pts.iter()
            .map(|&q| {
                let (x, y) = self.p(q);
                format!("{x:.2},{y:.2}")
            })
            .collect::<Vec<_>>()
            .join(" ")
    }

    fn polygon(&self, out: &mut String, pts: &[Point], style: &str) {
        let _ = writeln!(out, r#"<polygon points="{}" {style}/>"#, self.points(pts));
    }

    /// A part outline: a `polygon` when every edge is straight (the
    /// pictures of polygon parts stay byte for byte), else a `path` with an
    /// exact `A` command per arc.
    fn outline(&self, out: &mut String, outline: &[Vertex], style: &str) {
        if !has_arcs(outline) {
            return self.polygon(out, &vertex_points(outline), style);
        }
        let _ = writeln!(out, r#"<path d="{}" {style}/>"#, self.path(outline));
    }

    /// A part's region: its outline alone as [`View::outline`] draws it
    /// (so pictures of parts without holes stay byte for byte), else one
    /// `path` of the outline and every hole with `fill-rule="evenodd"`,
    /// so the holes show the plate through the part.
    fn region(&self, out: &mut String, outline: &[Vertex], holes: &[Vec<Vertex>], style: &str) {
        if holes.is_empty() {
            return self.outline(out, outline, style);
        }
        let mut d = self.path(outline);
        for h in holes.iter().filter(|h| h.len() >= 2) {
            d.push(' ');
            d.push_str(&self.path(h));
        }
        let _ = writeln!(out, r#"<path d="{d}" fill-rule="evenodd" {style}/>"#);
    }

    /// The path data of a closed outline of lines and arcs. y points down
    /// in SVG, so an arc turning counter-clockwise in the plate frame
    /// (`bulge > 0`) turns clockwise on screen: sweep flag 0; the large-arc
    /// flag is set when the arc turns more than half a circle.
    fn path(&self, outline: &[Vertex]) -> String {
        let mut d = String::new();
        let edges = edges_of(outline);
        for (i, e) in edges.iter().enumerate() {
            if i == 0 {
                let (x, y) = self.p([e.start().x, e.start().y]);
                let _ = write!(d, "M{x:.2},{y:.2}");
            }
            let (x, y) = self.p([e.end().x, e.end().y]);
            match e {
                // `Z` draws the last straight edge.
                Edge::Line { .. } if i + 1 == edges.len() => {}
                Edge::Line { .. } => {
                    let _ = write!(d, " L{x:.2},{y:.2}");
                }
                Edge::Arc(arc) => {
                    let r = arc.radius * self.k;
                    let large = u8::from(arc.bulge.abs() > 1.0);
                    let sweep = u8::from(arc.bulge < 0.0);
                    let _ = write!(d, " A{r:.2},{r:.2} 0 {large} {sweep} {x:.2},{y:.2}");
                }
            }
        }
        d.push_str(" Z");
        d
    }

    fn circle(&self, out: &mut String, centre: Point, radius: f64, style: &str) {
        let (x, y) = self.p(centre);
        let _ = writeln!(
            out,
            r#"<circle cx="{x:.2}" cy="{y:.2}" r="{:.2}" {style}/>"#,
            radius * self.k
        );
    }
}

fn header(view: &View) -> String {
    let h = view.h + CAPTION;
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w:.0}\" height=\"{h:.0}\" viewBox=\"0 0 {w:.0} {h:.0}\" \
         font-family=\"sans-serif\">\n<defs><marker id=\"arrow\" viewBox=\"0 0 10 10\" refX=\"9\" refY=\"5\" \
         markerWidth=\"6\" markerHeight=\"6\" orient=\"auto-start-reverse\"><path d=\"M0,0 L10,5 L0,10 z\" \
         fill=\"#138a36\"/></marker>\n<pattern id=\"hatch\" patternUnits=\"userSpaceOnUse\" width=\"8\" height=\"8\" \
         patternTransform=\"rotate(45)\"><rect width=\"8\" height=\"8\" fill=\"#ffb347\" fill-opacity=\"0.35\"/>\
         <line x1=\"0\" y1=\"0\" x2=\"0\" y2=\"8\" stroke=\"#e07b00\" stroke-width=\"2\"/></pattern></defs>\n\
         <rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
        w = view.w
    )
}

fn caption(out: &mut String, view: &View, lines: &[String]) {
    for (i, l) in lines.iter().enumerate() {
        let _ = writeln!(
            out,
            r##"<text x="{PAD}" y="{:.1}" font-size="{}" fill="#222">{}</text>"##,
            view.h + 18.0 + 20.0 * i as f64,
            if i == 0 { 15 } else { 12 },
            escape(l)
        );
    }
}

/// The SVG of one fixture of a part: the plate around it, the part in its
/// pose, clamp, locators and contact normals, and a caption with the
/// numbers a machinist sets the fixture up by.
pub fn fixture_svg(run: &RunMsg, rec: &PartRecord, fixture: &FixtureReport) -> String {
    let kit = &run.kit();
    let (outline, holes, access) = (rec.part.outline(), rec.part.holes(), rec.part.access());
    let d: FixtureDrawing = fixture_drawing(kit, &outline, &holes, &access, fixture);
    let l = kit.spacing;
    let [lo, hi] = d.bounds();
    let b = [
        [lo[0] - 0.8 * l, lo[1] - 0.8 * l],
        [hi[0] + 0.8 * l, hi[1] + 0.8 * l],
    ];
    let v = View::new(b);
    let mut s = header(&v);
    let hole_r = (0.18 * l).min(kit.locator_radius);
    draw_plate(&mut s, &v, kit, b, hole_r);
    draw_part(&mut s, &v, &d);
    draw_clamp(&mut s, &v, &d, hole_r);
    draw_locators(&mut s, &v, &d);
    draw_contacts(&mut s, &v, &d, l);
    caption(&mut s, &v, &fixture_caption(rec, fixture));
    s.push_str("</svg>\n");
    s
}

/// Plate: edge and the holes within `b` (dowel filled, tapped as rings).
fn draw_plate(svg: &mut String, view: &View, kit: &Kit, bounds: [Point; 2], hole_r: f64) {
    view.polygon(
        svg,
        &plate_outline(kit),
        r##"fill="#eef0f3" stroke="#9aa3ad" stroke-width="1.5""##,
    );
    for h in plate_holes(kit) {
        if h.at[0] < bounds[0][0]
            || h.at[0] > bounds[1][0]
            || h.at[1] < bounds[0][1]
            || h.at[1] > bounds[1][1]
        {
            continue;
        }
        let style = if h.dowel {
            r##"fill="#b9c0c8" stroke="#7d8893" stroke-width="1""##
        } else {
            r##"fill="none" stroke="#7d8893" stroke-width="1.2" stroke-dasharray="2,2""##
        };
        view.circle(svg, h.at, hole_r, style);
    }
}

/// Part in its pose (with its holes) and its access regions, hatched.
fn draw_part(svg: &mut String, view: &View, drawing: &FixtureDrawing) {
    view.region(
        svg,
        &drawing.part,
        &drawing.holes,
        r##"fill="#cfe3f7" fill-opacity="0.9" stroke="#1f5fa8" stroke-width="2""##,
    );
    for a in &drawing.access {
        view.polygon(
            svg,
            a,
            r##"fill="url(#hatch)" stroke="#e07b00" stroke-width="1.5""##,
        );
    }
}

/// Clamp: body, plunger at its extension, tip; mount holes marked.
fn draw_clamp(svg: &mut String, view: &View, drawing: &FixtureDrawing, hole_r: f64) {
    view.polygon(
        svg,
        &drawing.clamp_body,
        r##"fill="#d9443a" fill-opacity="0.22" stroke="#b0271f" stroke-width="1.5""##,
    );
    view.polygon(
        svg,
        &drawing.plunger,
        r##"fill="#d9443a" fill-opacity="0.55" stroke="#b0271f" stroke-width="1.2""##,
    );
    view.circle(
        svg,
        drawing.tip.centre,
        drawing.tip.radius,
        r##"fill="#e8776f" stroke="#b0271f" stroke-width="1.5""##,
    );
    for h in &drawing.clamp_holes {
        view.circle(svg, *h, hole_r * 0.6, r##"fill="#b0271f""##);
    }
}

/// Locators with labels L1 to L3 (the caption's order).
fn draw_locators(svg: &mut String, view: &View, drawing: &FixtureDrawing) {
    for (i, c) in drawing.locators.iter().enumerate() {
        view.circle(
            svg,
            c.centre,
            c.radius,
            r##"fill="#4a4f57" stroke="#1d2025" stroke-width="1.5""##,
        );
        let (x, y) = view.p(c.centre);
        let _ = writeln!(
            svg,
            r#"<text x="{x:.1}" y="{:.1}" font-size="12" fill="white" text-anchor="middle">L{}</text>"#,
            y + 4.0,
            i + 1
        );
    }
}

/// Contacts: points and inward normals, `0.6 l` long.
fn draw_contacts(svg: &mut String, view: &View, drawing: &FixtureDrawing, l: f64) {
    for c in &drawing.contacts {
        let (x, y) = view.p(c.at);
        let e = [
            c.at[0] + 0.6 * l * c.normal[0],
            c.at[1] + 0.6 * l * c.normal[1],
        ];
        let (ex, ey) = view.p(e);
        let _ = writeln!(
            svg,
            r##"<line x1="{x:.2}" y1="{y:.2}" x2="{ex:.2}" y2="{ey:.2}" stroke="#138a36" stroke-width="2" marker-end="url(#arrow)"/>"##
        );
        let _ = writeln!(
            svg,
            r##"<circle cx="{x:.2}" cy="{y:.2}" r="3.5" fill="#138a36"/>"##
        );
    }
}

/// Rank and score (and the contacts in holes); pose and clamp setting;
/// the plate holes used.
fn fixture_caption(rec: &PartRecord, fixture: &FixtureReport) -> [String; 3] {
    let u = rec.part.units.text();
    let holes = |h: &[[i64; 2]]| {
        h.iter()
            .map(|p| format!("({},{})", p[0], p[1]))
            .collect::<Vec<_>>()
            .join(" ")
    };
    // Top-k mode did not count the fixtures a rank is out of.
    let of = (rec.part.counts.as_ref())
        .map_or(Some(0), |c| Counts::from(c).admissible())
        .map_or(String::new(), |a| format!(" of {a}"));
    // Contacts on a hole's wall (SPEC 9), e.g. "L2 in hole 3".
    let in_holes = hole_contact_label(&rec.fixtures.segment_loops, fixture)
        .map_or(String::new(), |l| format!(" — {l}"));
    [
        format!(
            "{} — rank {}{of} — score {:.4}{}{in_holes}",
            rec.part.id,
            fixture.rank,
            fixture.score,
            if fixture.borderline {
                " (borderline)"
            } else {
                ""
            }
        ),
        format!(
            "pose x {:.2} {u}, y {:.2} {u}, theta {:.2}°; clamp rotation {}°, extension {:.2} {u}",
            fixture.pose.x,
            fixture.pose.y,
            fixture.pose.theta_deg,
            fixture.clamp.rotation_deg,
            fixture.clamp.extension,
        ),
        format!(
            "plate holes [col,row]: locators {}, clamp {}{}",
            holes(&fixture.placement.locators),
            holes(&fixture.placement.clamp_holes),
            if fixture.placement.rotation_deg != 0 {
                " (plate turned 90°)"
            } else {
                ""
            }
        ),
    ]
}

/// The SVG of a part without a fixture: its outline, holes and the reason.
pub fn part_svg(rec: &PartRecord) -> String {
    let p = &rec.part;
    let (outline, holes, access) = (p.outline(), p.holes(), p.access());
    let mut pts = extent_points(&outline);
    for a in &access {
        pts.extend(a.iter().copied());
    }
    // No outline (it could not be read): a caption alone.
    let v = match bounds(&pts) {
        Some(b) => {
            let m = 0.08 * (b[1][0] - b[0][0]).max(b[1][1] - b[0][1]).max(1e-9);
            View::new([[b[0][0] - m, b[0][1] - m], [b[1][0] + m, b[1][1] + m]])
        }
        None => View {
            x0: 0.0,
            y1: 0.0,
            k: 1.0,
            w: WIDTH,
            h: 10.0,
        },
    };
    let mut s = header(&v);
    if outline.len() >= 2 {
        v.region(
            &mut s,
            &outline,
            &holes,
            r##"fill="#cfe3f7" stroke="#1f5fa8" stroke-width="2""##,
        );
    }
    for a in &access {
        v.polygon(
            &mut s,
            a,
            r##"fill="url(#hatch)" stroke="#e07b00" stroke-width="1.5""##,
        );
    }
    let status = Status::from(p.status);
    let why = match status {
        Status::NoFixture => "no fixture of this kit holds this part".to_string(),
        _ => p.error.clone().unwrap_or_default(),
    };
    caption(
        &mut s,
        &v,
        &[format!("{} — {:?}", p.id, status).to_lowercase(), why],
    );
    s.push_str("</svg>\n");
    s
}
