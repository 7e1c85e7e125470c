//! `fixplan bench`: where the time goes, per part, on one thread.
//!
//! Splits each part's enumeration into setup enumeration (lattice search and
//! pose solutions), clamp placement (form closure, candidates, mount search),
//! admissibility checks (clearance, plate fit) and the metric, and says how
//! much the pruning wastes: pose solutions computed per setup kept.

use anyhow::{Context, Result};
use fixplan_core::enumerate::Profile;
use fixplan_core::{prepare, Case, Counts, Kit, Params, Part, PreparedPart, Units};
use std::path::{Path, PathBuf};

/// One part to measure.
pub struct BenchPart {
    /// The name its row of the table goes under.
    pub id: String,
    /// The part prepared, or why it cannot be (its row says so).
    pub prep: Result<PreparedPart, String>,
}

/// The bundled bench cases (`examples/cases/*.json`), used when nothing else
/// is named.
pub fn default_cases() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/cases");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|d| {
            d.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "json"))
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// Reads case files (SPEC Appendix A); all fixtures are enumerated.
pub fn parts_from_cases(paths: &[PathBuf]) -> Result<Vec<BenchPart>> {
    paths
        .iter()
        .map(|p| {
            let text =
                std::fs::read_to_string(p).with_context(|| format!("reading {}", p.display()))?;
            let mut case: Case =
                serde_json::from_str(&text).with_context(|| format!("parsing {}", p.display()))?;
            case.params.top_k = 0;
            let id = p.file_stem().map_or_else(
                || p.display().to_string(),
                |s| s.to_string_lossy().into_owned(),
            );
            Ok(BenchPart {
                id,
                prep: prepare(&case.part(), &case.kit, &case.params, case.units)
                    .map_err(|e| e.to_string()),
            })
        })
        .collect()
}

/// Prepares catalogue parts against one kit; all fixtures are enumerated.
pub fn parts_from_catalog(
    parts: Vec<(String, Result<Part, String>)>,
    kit: &Kit,
    params: &Params,
    units: Units,
) -> Vec<BenchPart> {
    let params = Params {
        top_k: 0,
        ..params.clone()
    };
    parts
        .into_iter()
        .map(|(id, part)| BenchPart {
            id,
            prep: part.and_then(|p| prepare(&p, kit, &params, units).map_err(|e| e.to_string())),
        })
        .collect()
}

/// Best of `repeat` timed runs of one part on the current thread, with the
/// part's counts.
pub fn measure(prep: &PreparedPart, repeat: usize) -> (Profile, u64, Counts) {
    let n = prep.combination_count();
    let mut best: Option<(Profile, u64, Counts)> = None;
    for _ in 0..repeat.max(1) {
        // Untimed run for the wall clock (no clock reads in the inner loop)...
        let t = std::time::Instant::now();
        let res = prep.enumerate_range_serial(0..n);
        let wall = t.elapsed().as_nanos() as u64;
        // ...and a timed run for the split.
        let (_, profile) = prep.enumerate_range_profiled(0..n, true);
        if best.as_ref().is_none_or(|b| wall < b.1) {
            best = Some((profile, wall, res.counts));
        }
    }
    best.unwrap_or_default()
}

fn ms(ns: u64) -> f64 {
    ns as f64 / 1e6
}

/// Runs the measurements and prints the table.
pub fn run(parts: &[BenchPart], repeat: usize) {
    println!(
        "{:<22} {:>9} {:>8} {:>9} {:>8} {:>8} {:>8} {:>8} {:>10} {:>10}",
        "part",
        "wall ms",
        "setup%",
        "clamp%",
        "admit%",
        "metric%",
        "fixtures",
        "setups",
        "poses/set",
        "fixt/s"
    );
    for p in parts {
        let prep = match &p.prep {
            Ok(prep) => prep,
            Err(e) => {
                println!("{:<22} invalid: {e}", p.id);
                continue;
            }
        };
        let (profile, wall, c) = measure(prep, repeat);
        let t = profile.timing;
        let total = profile.total_ns.max(1) as f64;
        let setup_enum = profile.total_ns.saturating_sub(t.setups_ns);
        let clamp = t.setups_ns.saturating_sub(t.admissibility_ns + t.metric_ns);
        let pct = |x: u64| 100.0 * x as f64 / total;
        let per_setup = if c.setups > 0 {
            profile.search.pose_solutions as f64 / c.setups as f64
        } else {
            f64::NAN
        };
        let fps = c.admissible as f64 / (wall.max(1) as f64 / 1e9);
        println!(
            "{:<22} {:>9.2} {:>7.1}% {:>8.1}% {:>7.1}% {:>7.1}% {:>8} {:>8} {:>10.1} {:>10.0}",
            p.id,
            ms(wall),
            pct(setup_enum),
            pct(clamp),
            pct(t.admissibility_ns),
            pct(t.metric_ns),
            c.admissible,
            c.setups,
            per_setup,
            fps
        );
    }
}

/// `fixplan bench`: the parts of `catalog` with `kit`, or the case files
/// `cases` (the bundled bench cases when none), measured on one thread.
pub fn bench_main(
    cases: &[PathBuf],
    catalog: Option<&Path>,
    arcs: Option<fixplan_catalog::ArcMode>,
    kit: &str,
    repeat: usize,
) -> Result<()> {
    let parts = match catalog {
        Some(c) => {
            let cat = crate::run::load_catalog_arcs(c, arcs)?;
            let spec = fixplan_catalog::load_kit(kit, cat.units)?;
            let parts = cat
                .parts
                .into_iter()
                .map(|p| (p.id, p.part.map_err(|e| e.to_string())))
                .collect();
            parts_from_catalog(parts, &spec.kit, &spec.params, cat.units)
        }
        None if cases.is_empty() => parts_from_cases(&default_cases())?,
        None => parts_from_cases(cases)?,
    };
    run(&parts, repeat);
    Ok(())
}
