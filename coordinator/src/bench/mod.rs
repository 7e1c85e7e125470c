//! Measurements, not tests: `fixplan bench` (where one part's enumeration
//! spends its time, on one thread) and `fixplan bench-cluster` (catalogue
//! throughput and the coordinator's share with local workers), `fixplan
//! bench-coordinator` (the coordinator's ceiling, with replayed results);
//! `fixplan bench --compare-flatten` (exact arcs against flattened ones),
//! `fixplan bench --markdown` (the README's speed table).
//! Uses `job`, `cluster` and `run`.

pub(crate) mod ceiling;
pub(crate) mod cluster;
pub(crate) mod flatten;
pub(crate) mod markdown;
pub(crate) mod parts;
pub(crate) mod replay;
pub(crate) mod replay_workers;

use anyhow::Result;
use fixplan_catalog::ArcMode;
use std::path::PathBuf;

/// `fixplan bench`'s arguments.
#[derive(clap::Args, Debug)]
pub struct PartsBenchArgs {
    /// Case files (SPEC Appendix A).
    pub cases: Vec<PathBuf>,
    /// Measure a catalogue instead (with --kit).
    #[arg(long, value_name = "DIR|catalog.toml")]
    pub catalog: Option<PathBuf>,
    /// Kit for --catalog.
    #[arg(long, value_name = "NAME|kit.toml", default_value = "metric-25")]
    pub kit: String,
    /// Runs per part; the fastest counts.
    #[arg(long, default_value_t = 3)]
    pub repeat: usize,
    /// Circular arcs of a --catalog's parts: `exact` or `flatten`
    /// (default: the manifest's `arcs`, else exact).
    #[arg(long, value_name = "exact|flatten")]
    pub arcs: Option<ArcMode>,
    /// The top-k mode's k, measured after the full enumeration (and
    /// checked to find its first k fixtures); 0 measures the full
    /// enumeration only.
    #[arg(long, value_name = "N", default_value_t = 10)]
    pub top_k: usize,
    /// Each part with arcs (of the cases, or of --catalog) solved with
    /// exact arcs and flattened at the default chord tolerance (as
    /// `run --arcs flatten`), top-k mode only, with the ratios
    /// exact/flattened of time, time per setup kept, setups and
    /// candidates. `usable` gives both readings' usable segments: chords
    /// too short to hold a locator are not usable, so a flattened part can
    /// lose its arcs altogether and be a smaller problem. The real-files
    /// test set is the catalogue examples/real/catalog.toml.
    #[arg(long)]
    pub compare_flatten: bool,
    /// Print the README's speed table (counts, full-count and top-k
    /// times) as Markdown rows instead of the time split;
    /// `scripts/speed_table.py` writes it into the README.
    #[arg(long, conflicts_with = "compare_flatten")]
    pub markdown: bool,
    /// Measure the top-k mode only, not the full counts: for the big
    /// cases (examples/cases/large), whose full enumeration takes minutes.
    #[arg(long, conflicts_with = "compare_flatten")]
    pub top_k_only: bool,
}

/// `fixplan bench`: the time split per part, or with `--compare-flatten`
/// exact arcs against flattened ones.
pub fn bench_main(args: &PartsBenchArgs) -> Result<()> {
    let catalog = args.catalog.as_deref();
    if args.compare_flatten {
        flatten::bench_main(&args.cases, catalog, &args.kit, args.repeat, args.top_k)
    } else {
        if args.top_k_only && args.top_k == 0 {
            anyhow::bail!("--top-k-only measures the top-k mode: give --top-k 1 or more");
        }
        let plan = parts::BenchPlan {
            repeat: args.repeat,
            top_k: args.top_k,
            top_k_only: args.top_k_only,
        };
        let (cases, arcs, kit) = (&args.cases, args.arcs, &args.kit);
        if args.markdown {
            markdown::print_header(args.top_k);
            parts::bench_main(cases, catalog, arcs, kit, plan, markdown::print_part)
        } else {
            parts::print_split_header();
            parts::bench_main(cases, catalog, arcs, kit, plan, |measured| {
                parts::print_split(measured, args.top_k)
            })
        }
    }
}
