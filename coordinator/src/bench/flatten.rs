//! `fixplan bench --compare-flatten`: what exact arcs cost against the
//! same part flattened into chords.
//!
//! Issue 32 asks exact arcs to cost no more than twice their flattened
//! outline, in time and in time per setup kept; this measures both on one
//! thread in top-k mode, the flattened part read as `--arcs flatten` reads
//! it in `run` (the default chord tolerance of the part's units). Parts
//! without arcs are skipped: both readings are the same part.

use super::parts::BenchPart;
use anyhow::{Context, Result};
use fixplan_catalog::{read_json, validate_part, ArcMode, ReadOptions};
use fixplan_core::{prepare, Case, EnumerateOptions, Part, PartialResult, PreparedPart};
use std::path::{Path, PathBuf};

/// One part read both ways.
pub struct FlattenPair {
    /// The exact reading (its id names the row).
    pub exact: BenchPart,
    /// The flattened reading.
    pub flat: BenchPart,
}

/// Arcs among the prepared part's edges (outline and holes).
fn arc_count(prep: &PreparedPart) -> usize {
    prep.outline().edges().iter().filter(|e| e.is_arc()).count()
}

/// Whether any edge of the part (outline or hole) is an arc.
fn has_arcs(part: &Part) -> bool {
    part.outline
        .iter()
        .chain(part.holes.iter().flatten())
        .any(|v| v.bulge != 0.0)
}

/// The case files with arcs, each with its part flattened by the JSON
/// reader at the default chord tolerance of the case's units.
pub fn pairs_from_cases(paths: &[PathBuf]) -> Result<Vec<FlattenPair>> {
    let mut out = Vec::new();
    for p in paths {
        let bytes = std::fs::read(p).with_context(|| format!("reading {}", p.display()))?;
        let mut case: Case =
            serde_json::from_slice(&bytes).with_context(|| format!("parsing {}", p.display()))?;
        let part = case.part();
        if !has_arcs(&part) {
            continue;
        }
        case.params.top_k = 0;
        let id = p.file_stem().map_or_else(
            || p.display().to_string(),
            |s| s.to_string_lossy().into_owned(),
        );
        let opts = ReadOptions {
            arcs: ArcMode::Flatten,
            ..ReadOptions::new(case.units)
        };
        let flat_part = read_json(&bytes, &opts)
            .map_err(|e| e.to_string())
            .and_then(|raw| validate_part(raw, case.units).map_err(|e| e.to_string()));
        let prep = |part: Result<Part, String>| {
            part.and_then(|p| {
                prepare(&p, &case.kit, &case.params, case.units).map_err(|e| e.to_string())
            })
        };
        out.push(FlattenPair {
            exact: BenchPart {
                id: id.clone(),
                prep: prep(Ok(part)),
            },
            flat: BenchPart {
                id,
                prep: prep(flat_part.map(|(p, _)| p)),
            },
        });
    }
    Ok(out)
}

/// The catalogue's parts with arcs, read exact and flattened, against the
/// kit `kit`.
pub fn pairs_from_catalog(catalog: &Path, kit: &str) -> Result<Vec<FlattenPair>> {
    let read = |mode| super::parts::parts_from_catalog_file(catalog, Some(mode), kit);
    let exact = read(ArcMode::Exact)?;
    let flat = read(ArcMode::Flatten)?;
    if exact.len() != flat.len() {
        anyhow::bail!("the catalogue read flattened has another number of parts");
    }
    Ok(exact
        .into_iter()
        .zip(flat)
        .filter(|(e, _)| e.prep.as_ref().map_or(true, |p| arc_count(p) > 0))
        .map(|(exact, flat)| FlattenPair { exact, flat })
        .collect())
}

/// One reading measured: the fastest of `repeat` untimed runs.
struct TimedReading {
    wall: u64,
    result: PartialResult,
}

fn time_top_k(prep: &PreparedPart, top_k: usize, repeat: usize) -> TimedReading {
    let prep = prep.with_top_k(top_k, false);
    let n = prep.combination_count();
    let once = || {
        // Without the part's tables, as a run starts (see `parts::measure`).
        let fresh = prep.with_fresh_tables();
        let t = std::time::Instant::now();
        let result = fresh
            .enumerate(0..n, EnumerateOptions::this_thread())
            .result;
        TimedReading {
            wall: t.elapsed().as_nanos() as u64,
            result,
        }
    };
    super::parts::fastest(repeat, once, |t| t.wall)
}

/// Microseconds per setup kept (`-` with none).
fn per_setup(reading: &TimedReading) -> String {
    match reading.result.counts.setups {
        0 => "-".into(),
        s => format!("{:.2}", reading.wall as f64 / 1e3 / s as f64),
    }
}

fn ratio(numerator: f64, denominator: f64) -> String {
    if denominator > 0.0 {
        format!("{:.2}x", numerator / denominator)
    } else {
        "-".into()
    }
}

fn print_header() {
    println!(
        "{:<40} {:>6} {:>7} | {:>9} {:>10} {:>9} {:>8} | {:>9} {:>10} {:>9} {:>8} | {:>7} {:>7} {:>7} {:>7}",
        "part",
        "edges",
        "usable",
        "setups",
        "candidates",
        "ms",
        "us/set",
        "setups",
        "candidates",
        "ms",
        "us/set",
        "time",
        "us/set",
        "setups",
        "cands"
    );
    println!(
        "{:<40} {:>6} {:>7} | {:^39} | {:^39} | {:^31}",
        "", "(arcs)", "ex/fl", "exact", "flattened", "ratios exact/flattened"
    );
}

/// Prints one row. `usable` shows the usable segments (SPEC 2) of both
/// readings: a chord shorter than the trim and the locator leaves no usable
/// segment, so flattening can drop an arc from the problem altogether
/// rather than approximate it, and the ratios compare two problems of
/// different sizes (more combinations, and more segments for the clamp to
/// try at every setup, exact).
fn print_pair(
    pair: [&PreparedPart; 2],
    exact_run: &TimedReading,
    flat_run: &TimedReading,
    id: &str,
) {
    let [exact, flat] = pair;
    let (edges, arcs) = (exact.outline().edges().len(), arc_count(exact));
    let usable = format!("{}/{}", exact.segments().len(), flat.segments().len());
    let (ec, fc) = (&exact_run.result.counts, &flat_run.result.counts);
    let us = |t: &TimedReading| t.wall as f64 / 1e3 / t.result.counts.setups.max(1) as f64;
    println!(
        "{:<40} {:>6} {:>7} | {:>9} {:>10} {:>9.2} {:>8} | {:>9} {:>10} {:>9.2} {:>8} | {:>7} {:>7} {:>7} {:>7}",
        id,
        format!("{edges}({arcs})"),
        usable,
        ec.setups,
        ec.candidates,
        exact_run.wall as f64 / 1e6,
        per_setup(exact_run),
        fc.setups,
        fc.candidates,
        flat_run.wall as f64 / 1e6,
        per_setup(flat_run),
        ratio(exact_run.wall as f64, flat_run.wall as f64),
        ratio(us(exact_run), us(flat_run)),
        ratio(ec.setups as f64, fc.setups as f64),
        ratio(ec.candidates as f64, fc.candidates as f64),
    );
}

/// Measures every pair in top-`top_k` mode on this thread and prints the
/// table: per reading setups kept, candidates, wall time and time per
/// setup kept; then the ratios exact/flattened.
pub fn run(pairs: &[FlattenPair], repeat: usize, top_k: usize) {
    print_header();
    for p in pairs {
        let (exact, flat) = match (&p.exact.prep, &p.flat.prep) {
            (Ok(e), Ok(f)) => (e, f),
            (Err(e), _) | (_, Err(e)) => {
                println!("{:<40} invalid: {e}", p.exact.id);
                continue;
            }
        };
        let e = time_top_k(exact, top_k, repeat);
        let f = time_top_k(flat, top_k, repeat);
        print_pair([exact, flat], &e, &f, &p.exact.id);
    }
}

/// `fixplan bench --compare-flatten`: the parts with arcs of `catalog`
/// (with `kit`) or of the case files `cases` (the bundled bench cases when
/// none), exact against flattened, in top-`top_k` mode.
pub fn bench_main(
    cases: &[PathBuf],
    catalog: Option<&Path>,
    kit: &str,
    repeat: usize,
    top_k: usize,
) -> Result<()> {
    if top_k == 0 {
        anyhow::bail!("--compare-flatten measures the top-k mode: give --top-k 1 or more");
    }
    let pairs = match catalog {
        Some(c) => pairs_from_catalog(c, kit)?,
        None if cases.is_empty() => pairs_from_cases(&super::parts::default_cases())?,
        None => pairs_from_cases(cases)?,
    };
    run(&pairs, repeat, top_k);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Of the bundled cases only `bracket-arcs` has arcs; its flattened
    /// reading is a polygon with more edges (chords replace each arc).
    #[test]
    fn cases_pair_arc_parts_with_their_polygons() {
        let pairs = pairs_from_cases(&super::super::parts::default_cases()).unwrap();
        let ids: Vec<&str> = pairs.iter().map(|p| p.exact.id.as_str()).collect();
        assert_eq!(ids, ["bracket-arcs"]);
        let exact = pairs[0].exact.prep.as_ref().unwrap();
        let flat = pairs[0].flat.prep.as_ref().unwrap();
        assert!(arc_count(exact) > 0);
        assert_eq!(arc_count(flat), 0);
        assert!(flat.outline().edges().len() > exact.outline().edges().len());
    }

    /// examples/real/catalog.toml names every file of the real-files test
    /// set, and reads every part its expected.json lists; the one part
    /// whose hole SPEC 9.1 refuses (drawn tangent to the outline) is that
    /// part's error.
    #[test]
    fn real_set_catalogue_reads_the_whole_set() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let expected: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(root.join("catalog/tests/real/expected.json")).unwrap(),
        )
        .unwrap();
        let want: usize = expected["files"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| f["parts"].as_array().unwrap().len())
            .sum();
        let cat = crate::run::load_catalog_arcs(
            &root.join("examples/real/catalog.toml"),
            Some(ArcMode::Exact),
        )
        .unwrap();
        assert_eq!(cat.parts.len(), want);
        let refused: Vec<(&str, String)> = cat
            .parts
            .iter()
            .filter_map(|p| Some((p.id.as_str(), p.part.as_ref().err()?.to_string())))
            .collect();
        assert_eq!(refused.len(), 1, "{refused:?}");
        assert_eq!(refused[0].0, "qcad_m4_hex_head_top_view_dxf");
        assert!(
            refused[0].1.contains("hole 0 touches the outline"),
            "{refused:?}"
        );
    }
}
