//! `fixplan bench`: where the time goes, per part, on one thread.
//!
//! Splits each part's enumeration into setup enumeration (lattice search and
//! pose solutions), clamp placement (form closure, candidates, mount search),
//! admissibility checks (clearance, plate fit) and the metric, and says how
//! much the pruning wastes: pose solutions computed per setup kept. Each
//! part runs twice: full counts, then top-k mode, which must find the same
//! fixtures with less work (scored, mount searches, setups floored).

use anyhow::{Context, Result};
use fixplan_core::{
    prepare, Case, EnumerateOptions, Kit, Params, Part, PartialResult, PreparedPart, Profile, Units,
};
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

/// [`parts_from_catalog`] of the catalogue at `catalog` (read with `arcs`)
/// against the kit `kit`.
pub fn parts_from_catalog_file(
    catalog: &Path,
    arcs: Option<fixplan_catalog::ArcMode>,
    kit: &str,
) -> Result<Vec<BenchPart>> {
    let cat = crate::run::load_catalog_arcs(catalog, arcs)?;
    let spec = fixplan_catalog::load_kit(kit, cat.units)?;
    let parts = cat
        .parts
        .into_iter()
        .map(|p| (p.id, p.part.map_err(|e| e.to_string())))
        .collect();
    Ok(parts_from_catalog(
        parts,
        &spec.kit,
        &spec.params,
        cat.units,
    ))
}

/// One mode of one part, measured.
#[derive(Debug, Clone)]
pub struct Measured {
    /// Where the time and the work went (timed run).
    pub profile: Profile,
    /// Wall time of the fastest untimed run, nanoseconds.
    pub wall: u64,
    /// The result of that run.
    pub result: PartialResult,
}

/// Best of `repeat` timed runs of one part on the current thread, with the
/// part's result. Each run starts without the part's tables
/// ([`PreparedPart::with_fresh_tables`]): a run works them out once per
/// part, and so does each measured run.
pub fn measure(prep: &PreparedPart, repeat: usize) -> Measured {
    let once = || {
        let n = prep.combination_count();
        let fresh = prep.with_fresh_tables();
        // Untimed run for the wall clock (no clock reads in the inner loop)...
        let t = std::time::Instant::now();
        let result = fresh
            .enumerate(0..n, EnumerateOptions::this_thread())
            .result;
        let wall = t.elapsed().as_nanos() as u64;
        // ...and a timed run for the split.
        let timed = EnumerateOptions {
            timed: true,
            ..EnumerateOptions::this_thread()
        };
        let profile = prep.enumerate(0..n, timed).profile;
        Measured {
            profile,
            wall,
            result,
        }
    };
    fastest(repeat, once, |m| m.wall)
}

/// The run of `once` with the smallest `wall` of `repeat` (at least one).
pub fn fastest<T>(repeat: usize, once: impl Fn() -> T, wall: impl Fn(&T) -> u64) -> T {
    let mut best = once();
    for _ in 1..repeat {
        let m = once();
        if wall(&m) < wall(&best) {
            best = m;
        }
    }
    best
}

fn ms(ns: u64) -> f64 {
    ns as f64 / 1e6
}

const HEADER: [&str; 13] = [
    "part",
    "mode",
    "wall ms",
    "setup%",
    "clamp%",
    "admit%",
    "metric%",
    "fixtures",
    "setups",
    "poses/set",
    "scored",
    "mounts",
    "floored",
];

fn print_row(cells: &[String]) {
    println!(
        "{:<22} {:<8} {:>9} {:>7} {:>7} {:>7} {:>8} {:>9} {:>8} {:>9} {:>9} {:>9} {:>8}",
        cells[0],
        cells[1],
        cells[2],
        cells[3],
        cells[4],
        cells[5],
        cells[6],
        cells[7],
        cells[8],
        cells[9],
        cells[10],
        cells[11],
        cells[12]
    );
}

/// One row: the time split, the counts (admissible fixtures only when
/// counted: `-` in top-k mode) and the work counters.
fn row(id: &str, mode: &str, measured: &Measured) -> Vec<String> {
    let (profile, c) = (&measured.profile, &measured.result.counts);
    let t = profile.timing;
    let total = profile.total_ns.max(1) as f64;
    let setup_enum = profile.total_ns.saturating_sub(t.setups_ns);
    let clamp = t.setups_ns.saturating_sub(t.admissibility_ns + t.metric_ns);
    let pct = |x: u64| format!("{:.1}%", 100.0 * x as f64 / total);
    // No setup kept: nothing to divide by.
    let per_setup = if c.setups > 0 {
        format!(
            "{:.1}",
            profile.search.pose_solutions as f64 / c.setups as f64
        )
    } else {
        "-".into()
    };
    let w = profile.work;
    vec![
        id.to_string(),
        mode.to_string(),
        format!("{:.2}", ms(measured.wall)),
        pct(setup_enum),
        pct(clamp),
        pct(t.admissibility_ns),
        pct(t.metric_ns),
        c.admissible().map_or("-".into(), |a| a.to_string()),
        c.setups.to_string(),
        per_setup,
        w.scored.to_string(),
        w.mount_searches.to_string(),
        w.setups_floored.to_string(),
    ]
}

/// One part's two measurements: full counts (unless skipped) and top-k
/// mode (unless `top_k` is 0).
pub struct PartMeasured {
    /// The part's row name.
    pub id: String,
    /// Outline and hole edges of the prepared part.
    pub edges: usize,
    /// Every fixture counted, or `None` when skipped (`--top-k-only`).
    pub full: Option<Measured>,
    /// The top-k mode, or `None` when `top_k` is 0.
    pub fast: Option<Measured>,
}

/// What `run` measures and how it prints it.
#[derive(Debug, Clone, Copy)]
pub struct BenchPlan {
    /// Runs per mode; the fastest counts.
    pub repeat: usize,
    /// The top-k mode's k (0: full counts only).
    pub top_k: usize,
    /// Skip the full enumeration: parts whose full counts take minutes.
    pub top_k_only: bool,
}

/// Measures one prepared part in both modes; the top-k mode must find the
/// full run's first `top_k` fixtures bit for bit, since a faster mode that
/// finds other fixtures is a bug, not a speed-up.
fn measure_part(id: &str, prep: &PreparedPart, plan: BenchPlan) -> Result<PartMeasured> {
    let full = (!plan.top_k_only).then(|| measure(&prep.with_top_k(plan.top_k, true), plan.repeat));
    let fast = (plan.top_k > 0).then(|| measure(&prep.with_top_k(plan.top_k, false), plan.repeat));
    if let (Some(full), Some(fast)) = (&full, &fast) {
        if fast.result.fixtures != full.result.fixtures {
            anyhow::bail!("{id}: the top-{} mode found other fixtures", plan.top_k);
        }
    }
    Ok(PartMeasured {
        id: id.to_string(),
        edges: prep.outline().edges().len(),
        full,
        fast,
    })
}

/// The time split table's header.
pub fn print_split_header() {
    print_row(&HEADER.map(String::from));
}

/// The time split table: per part, full counts then top-k mode and the
/// speed-up between them.
pub fn print_split(measured: &PartMeasured, top_k: usize) {
    if let Some(full) = &measured.full {
        print_row(&row(&measured.id, "full", full));
    }
    if let Some(fast) = &measured.fast {
        print_row(&row(&measured.id, &format!("top-{top_k}"), fast));
    }
    if let (Some(full), Some(fast)) = (&measured.full, &measured.fast) {
        let speedup = full.wall as f64 / fast.wall.max(1) as f64;
        println!("{:<22} {:<8} {:>8.1}x", "", "speed-up", speedup);
    }
}

/// Runs the measurements and hands each part to `print` as soon as it is
/// measured (a long bench shows its rows as it goes): per part, all
/// fixtures with full counts, then (when `top_k > 0`) the top-k mode,
/// checked to find the first `top_k` fixtures of the full run bit for bit.
pub fn run(
    parts: &[BenchPart],
    plan: BenchPlan,
    mut print: impl FnMut(&PartMeasured),
) -> Result<()> {
    for p in parts {
        let prep = match &p.prep {
            Ok(prep) => prep,
            Err(e) => {
                println!("{:<22} invalid: {e}", p.id);
                continue;
            }
        };
        print(&measure_part(&p.id, prep, plan)?);
    }
    Ok(())
}

/// `fixplan bench`: the parts of `catalog` with `kit`, or the case files
/// `cases` (the bundled bench cases when none), measured on one thread,
/// as `plan` says, each part given to `print`.
pub fn bench_main(
    cases: &[PathBuf],
    catalog: Option<&Path>,
    arcs: Option<fixplan_catalog::ArcMode>,
    kit: &str,
    plan: BenchPlan,
    print: impl FnMut(&PartMeasured),
) -> Result<()> {
    let parts = match catalog {
        Some(c) => parts_from_catalog_file(c, arcs, kit)?,
        None if cases.is_empty() => parts_from_cases(&default_cases())?,
        None => parts_from_cases(cases)?,
    };
    run(&parts, plan, print)
}
