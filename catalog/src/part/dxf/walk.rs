//! Going through a drawing's entities: INSERTs exploded into their blocks'
//! entities (placed by their transforms, through nested blocks, MINSERT
//! arrays cell by cell), the layer selection applied, zero-length and
//! duplicate entities dropped, every entity that cannot be used named,
//! and the reader's limits counted.

use super::super::outline::{dist, reversed, Affine, Piece, P};
use super::super::raw::{LayerFilter, LimitExceeded, Limits, ReadOptions};
use super::entities::{entity_name, entity_shape, ocs_flip, Curves, EntityShape};
use super::error::DxfError;
use super::transform;
use dxf::entities::{Entity, EntityType, Insert};
use dxf::{Block, Drawing};
use fixplan_core::Vertex;
use std::collections::{HashMap, HashSet};

pub(super) fn is_access_layer(layer: &str) -> bool {
    let l = layer.trim();
    l.eq_ignore_ascii_case("access") || l.eq_ignore_ascii_case("keepout")
}

/// The loops and pieces of one kind of layer (part or access), file units.
#[derive(Default)]
pub(super) struct Layer {
    pub loops: Vec<(Vec<Vertex>, String)>,
    pub pieces: Vec<Piece>,
    /// Entities not read, with the points they are known to pass through,
    /// so that an open loop ending on one can name it.
    pub ignored: Vec<(String, Vec<P>)>,
}

/// Everything the entities of a drawing gave, still in file units.
#[derive(Default)]
pub(super) struct DxfFindings {
    pub part: Layer,
    pub access: Layer,
    pub warnings: Vec<String>,
}

/// Where an entity sits: the chain of INSERTs above it (empty at the top)
/// and the layer an entity on layer `0` takes (a block's entities on
/// layer 0 are drawn on the layer of the INSERT).
#[derive(Clone)]
struct Place {
    path: String,
    layer: Option<String>,
    xf: Affine,
    depth: usize,
}

/// The state of one pass over a drawing.
pub(super) struct DxfWalk<'a> {
    blocks: HashMap<String, &'a Block>,
    opts: &'a ReadOptions,
    limits: Limits,
    /// Chord tolerance, file units.
    tol: f64,
    /// Join tolerance, file units: what counts as zero length, and the grid
    /// duplicates are compared on.
    join_tol: f64,
    entities: usize,
    vertices: usize,
    skipped: usize,
    layers_seen: HashSet<String>,
    /// Each loop and piece read so far by its rounded vertices, with its
    /// label, to drop repeats.
    seen: HashMap<Vec<(i64, i64, i64)>, String>,
    pub found: DxfFindings,
}

fn limit(what: String, limit: usize, key: &'static str) -> DxfError {
    DxfError::Limit(LimitExceeded {
        what,
        limit: limit as u64,
        key,
    })
}

impl<'a> DxfWalk<'a> {
    pub fn new(drawing: &'a Drawing, opts: &'a ReadOptions, tol: f64, join_tol: f64) -> Self {
        let mut blocks = HashMap::new();
        for b in drawing.blocks() {
            // Block names are not case sensitive in AutoCAD; the first
            // definition stands.
            blocks.entry(b.name.to_ascii_lowercase()).or_insert(b);
        }
        DxfWalk {
            blocks,
            opts,
            limits: opts.limits,
            tol,
            join_tol,
            entities: 0,
            vertices: 0,
            skipped: 0,
            layers_seen: HashSet::new(),
            seen: HashMap::new(),
            found: DxfFindings::default(),
        }
    }

    /// Reads the drawing's model-space entities; `number` numbers them from 1 in
    /// file order, as messages do.
    pub fn run(&mut self, drawing: &Drawing) -> Result<(), DxfError> {
        let top = Place {
            path: String::new(),
            layer: None,
            xf: Affine::ID,
            depth: 0,
        };
        for (k, e) in drawing.entities().enumerate() {
            if e.common.is_in_paper_space {
                continue;
            }
            self.entity(e, k + 1, &top)?;
        }
        self.layer_warnings();
        Ok(())
    }

    fn layer_warnings(&mut self) {
        let f = &self.opts.layers;
        for l in &f.read {
            if !self.layers_seen.contains(&LayerFilter::key(l)) {
                self.found.warnings.push(format!(
                    "layer {l} (named in layers) has no entities in this drawing"
                ));
            }
        }
        if self.skipped > 0 {
            self.found.warnings.push(format!(
                "{} entities on layers left out by layers / ignore_layers were not read",
                self.skipped
            ));
        }
    }

    fn entity(&mut self, entity: &Entity, number: usize, at: &Place) -> Result<(), DxfError> {
        self.entities += 1;
        if self.entities > self.limits.entities {
            return Err(limit(
                format!(
                    "a drawing of more than {} entities (exploded blocks included)",
                    self.limits.entities
                ),
                self.limits.entities,
                "entities",
            ));
        }
        let own = entity.common.layer.as_str();
        let layer = match &at.layer {
            Some(inherited) if own.trim() == "0" => inherited.clone(),
            _ => own.to_string(),
        };
        self.layers_seen.insert(LayerFilter::key(&layer));
        let name = entity_name(&entity.specific);
        let handle = if entity.common.handle.is_empty() {
            String::new()
        } else {
            format!(" (handle {})", entity.common.handle.as_string())
        };
        let label = format!("{name} #{number}{} on layer {layer}", at.path);
        let warn_label = format!("{name} #{number}{handle}{} on layer {layer}", at.path);
        if let EntityType::Insert(ins) = &entity.specific {
            if self.opts.layers.ignores(&layer) {
                self.skipped += 1;
                return Ok(());
            }
            let inner = Place {
                path: format!(" of INSERT #{number}{}", at.path),
                layer: Some(layer),
                ..at.clone()
            };
            return self.insert(ins, &warn_label, inner, at);
        }
        let access = is_access_layer(&layer);
        if !self.opts.layers.reads(&layer, access) {
            self.skipped += 1;
            return Ok(());
        }
        let similar = at.xf.is_similarity();
        let scale = at.xf.max_scale();
        let curves = Curves {
            tol: self.tol / scale,
            // Access constraints are polygons; arcs under a stretching
            // insert are elliptic.
            flatten: self.opts.arcs.flatten() || access || !similar,
            spline_pieces: self.limits.spline_pieces,
        };
        let shape = entity_shape(&entity.specific, curves);
        let dest = if access {
            &mut self.found.access
        } else {
            &mut self.found.part
        };
        let (pts, closed) = match shape {
            EntityShape::Closed(p) => (p, true),
            EntityShape::Open(p) => (p, false),
            EntityShape::Ignored(why, pts) => {
                self.found
                    .warnings
                    .push(format!("{warn_label} {why}; ignored"));
                let pts = pts.into_iter().map(|p| at.xf.apply(p)).collect();
                dest.ignored.push((warn_label, pts));
                return Ok(());
            }
            EntityShape::Limit(l) => return Err(DxfError::Limit(l)),
            EntityShape::Nothing => return Ok(()),
        };
        self.keep(pts, closed, access, (label, warn_label), at, curves.tol)
    }

    /// Adds an entity's loop or piece (block coordinates) to its layer,
    /// placed by `at`, unless it has zero length or repeats one read
    /// before; `labels` are its name in loops and in warnings.
    fn keep(
        &mut self,
        pts: Vec<Vertex>,
        closed: bool,
        access: bool,
        labels: (String, String),
        at: &Place,
        tol: f64,
    ) -> Result<(), DxfError> {
        let (label, warn_label) = labels;
        self.vertices += pts.len();
        if self.vertices > self.limits.vertices {
            return Err(limit(
                format!(
                    "more than {} vertices in all (curves flattened)",
                    self.limits.vertices
                ),
                self.limits.vertices,
                "vertices",
            ));
        }
        if pts.len() < 2 && !closed {
            return Ok(());
        }
        let pts = transform::place(at.xf, pts, closed, tol);
        let first = pts.first().map(|v| [v.x, v.y]).unwrap_or_default();
        if pts.iter().all(|v| dist([v.x, v.y], first) <= self.join_tol) {
            self.found.warnings.push(format!(
                "{warn_label} has zero length (all its points within the join tolerance); dropped"
            ));
            return Ok(());
        }
        let key = self.key(&pts, closed);
        if let Some(earlier) = self.seen.get(&key) {
            self.found
                .warnings
                .push(format!("{warn_label} repeats {earlier} exactly; dropped"));
            return Ok(());
        }
        self.seen.insert(key, label.clone());
        let dest = if access {
            &mut self.found.access
        } else {
            &mut self.found.part
        };
        if closed {
            dest.loops.push((pts, label));
        } else {
            dest.pieces.push(Piece { pts, label });
        }
        Ok(())
    }

    /// Explodes an INSERT (`at` is where the INSERT itself sits, `inner`
    /// where its block's entities do, less the transform).
    fn insert(
        &mut self,
        ins: &Insert,
        warn_label: &str,
        inner: Place,
        at: &Place,
    ) -> Result<(), DxfError> {
        let Some(block) = self.blocks.get(&ins.name.to_ascii_lowercase()).copied() else {
            self.found.warnings.push(format!(
                "{warn_label} refers to block {}, which the file does not define; ignored",
                ins.name
            ));
            return Ok(());
        };
        if block.is_xref() {
            self.found.warnings.push(format!(
                "{warn_label} refers to block {}, an external reference to another file; ignored",
                ins.name
            ));
            return Ok(());
        }
        let d = &ins.extrusion_direction;
        let Some(flip) = ocs_flip(d.x, d.y, d.z) else {
            self.found
                .warnings
                .push(format!("{warn_label} is not in the XY plane; ignored"));
            return Ok(());
        };
        if at.depth + 1 > self.limits.block_depth {
            return Err(limit(
                format!(
                    "{warn_label}: blocks nested more than {} deep (or a block that contains itself)",
                    self.limits.block_depth
                ),
                self.limits.block_depth,
                "block_depth",
            ));
        }
        let cols = i32::from(ins.column_count.max(1));
        let rows = i32::from(ins.row_count.max(1));
        // An array of empty cells costs time too: count every cell.
        let cells = usize::try_from(rows * cols).unwrap_or(usize::MAX);
        let cost = cells.saturating_mul(block.entities.len().max(1));
        if self.entities.saturating_add(cost) > self.limits.entities {
            return Err(limit(
                format!(
                    "{warn_label}: an array of {cells} copies of block {}, more than {} entities in all",
                    block.name, self.limits.entities
                ),
                self.limits.entities,
                "entities",
            ));
        }
        let base = [block.base_point.x, block.base_point.y];
        for r in 0..rows {
            for c in 0..cols {
                let offset = [
                    f64::from(c) * ins.column_spacing,
                    f64::from(r) * ins.row_spacing,
                ];
                let xf = at.xf.mul(transform::insert(
                    base,
                    [ins.x_scale_factor, ins.y_scale_factor],
                    offset,
                    ins.rotation,
                    [ins.location.x, ins.location.y],
                    flip,
                ));
                let cell = if rows * cols > 1 {
                    format!(" (row {}, column {})", r + 1, c + 1)
                } else {
                    String::new()
                };
                let place = Place {
                    path: format!(" of block {}{cell}{}", block.name, inner.path),
                    xf,
                    depth: at.depth + 1,
                    ..inner.clone()
                };
                for (i, e) in block.entities.iter().enumerate() {
                    self.entity(e, i + 1, &place)?;
                }
            }
        }
        Ok(())
    }

    /// The rounded vertices of a loop or piece, the same whichever way
    /// round (and for a loop wherever it starts) it was drawn.
    fn key(&self, pts: &[Vertex], closed: bool) -> Vec<(i64, i64, i64)> {
        let grid = if self.join_tol > 0.0 {
            self.join_tol
        } else {
            1e-9
        };
        let q = |v: &Vertex| {
            (
                (v.x / grid).round() as i64,
                (v.y / grid).round() as i64,
                (v.bulge * 1e9).round() as i64,
            )
        };
        let fwd: Vec<_> = pts.iter().map(q).collect();
        let back: Vec<_> = if closed {
            fixplan_core::parts::ccw_of_cw_outline(pts)
                .iter()
                .map(q)
                .collect()
        } else {
            reversed(pts).iter().map(q).collect()
        };
        if !closed {
            return fwd.min(back);
        }
        // A loop from its smallest vertex, either way round.
        let rot = |v: Vec<(i64, i64, i64)>| {
            let k = (0..v.len()).min_by_key(|&i| (v[i].0, v[i].1)).unwrap_or(0);
            let mut r = v[k..].to_vec();
            r.extend_from_slice(&v[..k]);
            r
        };
        rot(fwd).min(rot(back))
    }
}
