//! Choosing the part among the loops of a drawing: one outline with the
//! loops inside it (its holes), or, for a sheet, every outer loop as a
//! part of its own. Loops of a drawing do not cross, so they nest: a loop's
//! parent is the smallest loop around it, and a loop at even depth is an
//! outline, one at odd depth a hole of its parent. A loop inside a hole of
//! a single part is no material (a counterbore's drawn step, text, a
//! centre mark): it is dropped with a warning.

use super::curves::{fmt_pt, P};
use super::join::pt;
use super::region::{aabb_within, contains, loop_aabb, loop_area, loop_inside};
use crate::part::raw::{HoleMode, RawPart};
use fixplan_core::parts::{v2, Aabb};
use fixplan_core::{Units, Vertex};

/// Why the loops of a drawing do not make one part.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OutlinePickError {
    /// No closed loop at all, or only access loops: nothing to hold.
    #[error("no closed loop: {}", if *.only_access { "only access/keepout loops, no part outline" } else { "the file has no closed outline" })]
    NoClosedLoop {
        /// The drawing has access/keepout loops, just no outline.
        only_access: bool,
    },
    /// A loop outside the largest one: two parts in one file (a sheet), or
    /// a drawing with a border or title block; which one is meant cannot
    /// be guessed.
    #[error("more than one outline: {label} near {} {} lies outside the largest loop; put one part per file, or read every outer loop as a part of its own (`sheet = true` in the manifest, `fixplan run --sheet`), or read only the part's layers (`layers = [...]` or `ignore_layers = [...]` in the manifest) of a drawing with a border, title block or dimensions", fmt_pt(*.near), .units.label())]
    MoreThanOne {
        /// The other loop, as the reader names it.
        label: String,
        /// Its first point, catalogue units.
        near: [f64; 2],
        /// The catalogue's units.
        units: Units,
    },
}

/// How the loops of a drawing nest.
struct Nesting {
    /// Each loop's parent, the smallest loop around it.
    parent: Vec<Option<usize>>,
    /// How many loops are around each loop.
    depth: Vec<usize>,
}

/// The nesting of `loops` (the smallest enclosing loop is found among the
/// larger ones, boxes first, so a sheet of many parts stays cheap).
fn nest(loops: &[(Vec<Vertex>, String)], areas: &[f64], boxes: &[Aabb]) -> Nesting {
    let n = loops.len();
    let mut order: Vec<usize> = (0..n).collect();
    // Largest first; equal areas in file order, so the result is the
    // same however the loops were found.
    order.sort_by(|&i, &j| areas[j].total_cmp(&areas[i]).then(i.cmp(&j)));
    let mut parent = vec![None; n];
    let mut depth = vec![0; n];
    for (k, &i) in order.iter().enumerate() {
        for &j in order[..k].iter().rev() {
            if aabb_within(&boxes[i], &boxes[j]) && loop_inside(&loops[i].0, &loops[j].0) {
                parent[i] = Some(j);
                depth[i] = depth[j] + 1;
                break;
            }
        }
    }
    Nesting { parent, depth }
}

/// The holes a part keeps of `loops` (each with the name messages give
/// it): all of them with [`HoleMode::Keep`]; none with
/// [`HoleMode::Ignore`], each with the warning fixplan gave before holes.
pub(crate) fn keep_holes(
    mode: HoleMode,
    loops: Vec<(Vec<Vertex>, String)>,
    warnings: &mut Vec<String>,
    units: Units,
) -> Vec<Vec<Vertex>> {
    match mode {
        HoleMode::Keep => loops.into_iter().map(|(l, _)| l).collect(),
        HoleMode::Ignore => {
            warnings.extend(loops.iter().map(|(l, label)| hole_warning(label, l, units)));
            Vec::new()
        }
    }
}

fn hole_warning(label: &str, hole_loop: &[Vertex], units: Units) -> String {
    format!(
        "{label} near {} {} is a loop inside the outline (a hole or pocket); ignored: fixtures hold the outer outline only",
        fmt_pt(hole_loop.first().map(|v| pt(*v)).unwrap_or_default()),
        units.label()
    )
}

/// A loop inside hole `hole` of the part: no material, so not the part's.
fn in_hole_warning(label: &str, inner: &[Vertex], hole: usize, units: Units) -> String {
    format!(
        "{label} near {} {} lies inside hole {hole} (a drawn counterbore, text or mark); ignored",
        fmt_pt(inner.first().map(|v| pt(*v)).unwrap_or_default()),
        units.label()
    )
}

/// The largest loop is the part and the loops directly inside it its
/// holes, in file order (with [`HoleMode::Ignore`]: none, a warning for
/// every loop inside it, as before holes); loops inside a hole are dropped
/// with a warning; loops outside it mean the file holds more than one
/// part, which is ambiguous.
pub(crate) fn pick_outline(
    mut loops: Vec<(Vec<Vertex>, String)>,
    access: Vec<Vec<P>>,
    mut warnings: Vec<String>,
    units: Units,
    mode: HoleMode,
) -> Result<RawPart, OutlinePickError> {
    if loops.is_empty() {
        return Err(OutlinePickError::NoClosedLoop {
            only_access: !access.is_empty(),
        });
    }
    let areas: Vec<f64> = loops.iter().map(|(l, _)| loop_area(l)).collect();
    let boxes: Vec<Aabb> = loops.iter().map(|(l, _)| loop_aabb(l)).collect();
    let outer_i = (0..loops.len())
        .max_by(|&i, &j| areas[i].total_cmp(&areas[j]))
        .unwrap_or(0);
    let nesting = nest(&loops, &areas, &boxes);
    let outer = &loops[outer_i].0;
    let mut inside = Vec::new();
    for (i, (l, label)) in loops.iter().enumerate() {
        if i == outer_i || l.is_empty() {
            continue;
        }
        if !(aabb_within(&boxes[i], &boxes[outer_i]) && loop_inside(l, outer)) {
            return Err(OutlinePickError::MoreThanOne {
                label: label.clone(),
                near: pt(l[0]),
                units,
            });
        }
        inside.push(i);
    }
    let hole_i: Vec<usize> = inside
        .iter()
        .copied()
        .filter(|&i| nesting.parent[i] == Some(outer_i))
        .collect();
    let holes = if mode == HoleMode::Ignore {
        let all = inside.iter().map(|&i| loops[i].clone()).collect();
        keep_holes(mode, all, &mut warnings, units)
    } else {
        warn_in_holes(&loops, &nesting, &inside, &hole_i, &mut warnings, units);
        hole_i
            .iter()
            .map(|&i| std::mem::take(&mut loops[i].0))
            .collect()
    };
    let outer = std::mem::take(&mut loops[outer_i].0);
    Ok(RawPart {
        outline: outer,
        access,
        warnings,
        holes,
    })
}

/// A warning for each loop of `inside` that is no hole (not in `hole_i`),
/// naming the hole it lies in (numbered as in `hole_i`).
fn warn_in_holes(
    loops: &[(Vec<Vertex>, String)],
    nesting: &Nesting,
    inside: &[usize],
    hole_i: &[usize],
    warnings: &mut Vec<String>,
    units: Units,
) {
    for &i in inside {
        if hole_i.contains(&i) {
            continue;
        }
        let mut up = i;
        while let Some(p) = nesting.parent[up] {
            if let Some(k) = hole_i.iter().position(|&h| h == p) {
                let (l, label) = &loops[i];
                warnings.push(in_hole_warning(label, l, k, units));
                break;
            }
            up = p;
        }
    }
}

/// Every outer loop of a sheet as a part of its own, each with the loops
/// directly inside it as its holes (with [`HoleMode::Ignore`]: none, a
/// warning each) and the access
/// loops that start inside it (else the part whose box is nearest), in
/// sheet order: by the bottom edge of each part's bounding box, then its
/// left edge (rows of a nested sheet from the bottom, each from the left),
/// then larger first and file order. A loop inside a hole of a part (a
/// small part nested in a big one's cut-out) is a part too. The reader's
/// own warnings go to every part.
pub(crate) fn pick_outlines(
    loops: Vec<(Vec<Vertex>, String)>,
    access: Vec<Vec<P>>,
    warnings: Vec<String>,
    units: Units,
    mode: HoleMode,
) -> Result<Vec<RawPart>, OutlinePickError> {
    if loops.is_empty() {
        return Err(OutlinePickError::NoClosedLoop {
            only_access: !access.is_empty(),
        });
    }
    let areas: Vec<f64> = loops.iter().map(|(l, _)| loop_area(l)).collect();
    let boxes: Vec<Aabb> = loops.iter().map(|(l, _)| loop_aabb(l)).collect();
    let nesting = nest(&loops, &areas, &boxes);
    let mut outers: Vec<usize> = (0..loops.len())
        .filter(|&i| nesting.depth[i].is_multiple_of(2) && !loops[i].0.is_empty())
        .collect();
    outers.sort_by(|&i, &j| {
        let (a, b) = (&boxes[i], &boxes[j]);
        a.min
            .y
            .total_cmp(&b.min.y)
            .then(a.min.x.total_cmp(&b.min.x))
            .then(areas[j].total_cmp(&areas[i]))
            .then(i.cmp(&j))
    });
    let mut parts: Vec<RawPart> = outers
        .iter()
        .map(|&o| {
            let mut w = warnings.clone();
            let inside = (0..loops.len())
                .filter(|&i| nesting.parent[i] == Some(o))
                .map(|i| loops[i].clone())
                .collect();
            let holes = keep_holes(mode, inside, &mut w, units);
            RawPart {
                outline: loops[o].0.clone(),
                access: Vec::new(),
                warnings: w,
                holes,
            }
        })
        .collect();
    for a in access {
        let Some(&first) = a.first() else { continue };
        let q = v2(first[0], first[1]);
        let home = outers
            .iter()
            .position(|&o| contains(&loops[o].0, q))
            .or_else(|| {
                (0..outers.len()).min_by(|&i, &j| {
                    box_distance(&boxes[outers[i]], q)
                        .total_cmp(&box_distance(&boxes[outers[j]], q))
                })
            });
        if let Some(k) = home {
            parts[k].access.push(a);
        }
    }
    Ok(parts)
}

fn box_distance(aabb: &Aabb, point: fixplan_core::parts::V2) -> f64 {
    let dx = (aabb.min.x - point.x).max(point.x - aabb.max.x).max(0.0);
    let dy = (aabb.min.y - point.y).max(point.y - aabb.max.y).max(0.0);
    dx.hypot(dy)
}
