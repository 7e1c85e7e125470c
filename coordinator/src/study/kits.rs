//! The kits of a study: each `--kit` as listed, then each listed kit
//! crossed with every point of the `--sweep`, all checked before any work.

use super::sweep::{apply, point_label, Sweep};
use anyhow::{bail, Context, Result};
use fixplan_catalog::{load_kit, KitSpec};
use fixplan_core::{Params, Units};

/// One kit of a study.
#[derive(Debug, Clone)]
pub struct StudyKit {
    /// The kit and its parameters, as solved (a sweep point applied).
    pub spec: KitSpec,
    /// The listed kit it comes from.
    pub base: String,
    /// The sweep point applied, if any.
    pub sweep: Option<String>,
}

/// The kits of a study: each listed kit, then each listed kit crossed with
/// every sweep point. A bad kit or sweep point is an error here, so a
/// study stops before any part is solved.
pub fn study_kits(names: &[String], sweep: Option<&str>, units: Units) -> Result<Vec<StudyKit>> {
    if names.is_empty() {
        bail!("fixplan study needs at least one --kit");
    }
    let sweep = sweep.map(|s| Sweep::parse(s, units)).transpose()?;
    let mut out = Vec::new();
    let mut bases = Vec::new();
    for n in names {
        let spec = load_kit(n, units)?;
        fixplan_core::validate_kit(&spec.kit).with_context(|| format!("kit {}", spec.name))?;
        out.push(StudyKit {
            base: spec.name.clone(),
            sweep: None,
            spec: spec.clone(),
        });
        bases.push(spec);
    }
    if let Some(sw) = &sweep {
        for b in &bases {
            for p in sw.points() {
                out.push(StudyKit {
                    spec: apply(b, &p)?,
                    base: b.name.clone(),
                    sweep: Some(point_label(&p)),
                });
            }
        }
    }
    Ok(out)
}

/// The parameters each kit is solved with: its own, with `top_k` fixtures
/// kept (default 1: the statistics need only the best one, and the counts
/// and best score do not depend on top-k), in top-k mode unless
/// `full_counts` (or the kit's own `full_counts`).
pub fn solve_params(kits: &[StudyKit], top_k: Option<usize>, full_counts: bool) -> Vec<Params> {
    kits.iter()
        .map(|k| {
            let mut p = k.spec.params.clone();
            p.top_k = top_k.unwrap_or(1);
            p.full_counts |= full_counts;
            p
        })
        .collect()
}
