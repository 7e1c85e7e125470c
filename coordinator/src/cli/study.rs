//! Command-line arguments of `fixplan study` and of `--grid-steps` /
//! `--good-enough` on `fixplan run`.

use super::cluster::RunClusterArgs;
use crate::job::budget::{DEFAULT_PART_FIXTURES, DEFAULT_PART_SETUPS};
use crate::job::search::{parse_grid_steps, SearchError, SearchOptions};
use crate::study::{study_main, StudyOptions, StudyReport};
use anyhow::Result;
use clap::Args;
use fixplan_catalog::ArcMode;
use std::path::PathBuf;

/// `fixplan study --help`.
pub const STUDY_HELP: &str = "\
Compare kits on a catalogue: which kit to buy, which clamp to add.

Runs every part of the catalogue against every kit: each --kit, and each
--kit crossed with every point of --sweep. For each kit it reports the parts
held (count, and share weighted by each part's `quantity`, parts per year),
the median and 90th percentile of the best score over the parts held (lower
is better; median of an even count = mean of the two middle values, p90 =
nearest rank), the parts no fixture of the kit holds, the invalid ones and
the time; then the parts that no kit holds. Output: a table here, and on
request CSV (--csv), an SVG chart (--chart) and an MCAP file (-o, channels
/fixplan/study and /fixplan/study_summary, JSON with JSON Schemas).

Each (kit, part) goes through the same per-part path as `fixplan run`, in
this process or, with --workers N, through the coordinator and N worker
processes. Work is shared only where that is exact: a kit given twice is
solved once; a part is prepared once per (locator radius, spacing, edge
trim); a part with no fixture on a plate has none on a smaller plate of an
otherwise equal kit, so that run is skipped (--no-share solves everything).

SWEEP GRAMMAR (--sweep \"CLAUSE; CLAUSE; ...\", the points are the Cartesian
product of the clauses):
  CLAUSE  KEY=ITEM,ITEM,... [UNIT]
  ITEM    a number                 4
          A..B                     5 evenly spaced values, A and B included
          A..B/N                   N evenly spaced values (N >= 2)
          A..B:S                   A, A+S, A+2S, ... up to B
  UNIT    mm or in, once at the end of the clause, for length keys;
          converted to the catalogue's unit (default: the catalogue's unit)
  KEYS    locator_radius, spacing, edge_trim, min_clearance   lengths
          plate            COLSxROWS holes (or N for NxN), no ranges
          travel           MAX (keeps the kit's minimum) or MIN..MAX, no ranges
          max_clamp_angle  degrees (optional unit deg), e.g. 30..90:15
          grid_step        whole number >= 1
Every point is checked like a kit file (e.g. the locator radius against the
spacing, travel MIN <= MAX); a bad point stops the study before any work.

EXAMPLES
  fixplan study --kit metric-25 --kit paper-inch --chart study.svg
  fixplan study --kit metric-25 \\
      --sweep \"locator_radius=4,6,8 mm; plate=12x12,20x20; travel=50..70,60..92 mm\" \\
      --csv study.csv -o study.mcap --workers 2";

/// `fixplan study`.
#[derive(Args, Debug, Clone)]
pub struct StudyArgs {
    /// The catalogue (default: the bundled sample catalogue).
    #[arg(long, value_name = "DIR|catalog.toml")]
    pub catalog: Option<PathBuf>,
    /// A kit to compare: a built-in name (`paper-inch`, `metric-25`) or a kit
    /// TOML file (repeatable; default: metric-25).
    #[arg(long = "kit", value_name = "NAME|kit.toml")]
    pub kits: Vec<String>,
    /// Kit variants: each --kit crossed with every point (see SWEEP GRAMMAR).
    #[arg(long, value_name = "SWEEP")]
    pub sweep: Option<String>,
    /// Fixtures kept per part (default 1; counts and best scores do not
    /// depend on it).
    #[arg(long, value_name = "N")]
    pub top_k: Option<usize>,
    /// Count every part's admissible fixtures. Off, a study runs in top-k
    /// mode (it needs the best fixture only), several times faster on
    /// big parts, and its counts leave `admissible` out.
    #[arg(long)]
    pub full_counts: bool,
    /// Threads (default: all cores).
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// The study as MCAP (/fixplan/study, /fixplan/study_summary).
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// One CSV row per kit.
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// An SVG chart: share of parts held and best scores, per kit.
    #[arg(long, value_name = "FILE")]
    pub chart: Option<PathBuf>,
    /// Solve every (kit, part) on its own, sharing nothing (to check that
    /// the sharing changes no number).
    #[arg(long)]
    pub no_share: bool,
    /// No table.
    #[arg(short, long)]
    pub quiet: bool,
    /// A (kit, part) keeping more than N fixtures is `over_budget`, as in
    /// `fixplan run --part-fixtures` (same default; it only bites with
    /// `--top-k` 0 or above N).
    #[arg(long, value_name = "N", default_value_t = DEFAULT_PART_FIXTURES)]
    pub part_fixtures: u64,
    /// Circular arcs of the parts: `exact` (SPEC 8) or `flatten` (chords
    /// within the catalogue's chord tolerance, for comparison). Default:
    /// the manifest's `arcs`, else exact.
    #[arg(long, value_name = "exact|flatten")]
    pub arcs: Option<ArcMode>,
    /// `--workers N`: the study through a cluster.
    #[command(flatten)]
    pub cluster: RunClusterArgs,
}

/// The value of `--grid-steps` (a newtype, so clap takes `4,2,1` as one
/// value).
#[derive(Debug, Clone, PartialEq)]
pub struct GridSteps(pub Vec<u32>);

fn parse_steps(s: &str) -> Result<GridSteps, SearchError> {
    parse_grid_steps(s).map(GridSteps)
}

/// `--grid-steps` and `--good-enough` of `fixplan run`.
#[derive(Args, Debug, Clone, Default)]
pub struct SearchArgs {
    /// Coarse-to-fine: a full enumeration at each grid step, coarse to fine,
    /// each a multiple of the next (e.g. `4,2,1`). Locators 2 and 3 sit at
    /// multiples of the step from locator 1, so a coarse step is fast and
    /// its fixtures are a subset of the next step's. The part channel gets
    /// `refine`: per step the counts, the best fixture and score, the
    /// fixtures it added; the fixtures channel holds the finest step's
    /// result, the same bytes as a plain run at that step.
    #[arg(long, value_name = "S1,S2,...", value_parser = parse_steps)]
    pub grid_steps: Option<GridSteps>,
    /// Stop each part at the first segment combination (in combination
    /// order) that admits a fixture scoring SCORE or better: the part's
    /// status stays `ok`, its part message says `"stopped": "good_enough"`
    /// and `stopped_at` (the combination index), and its fixtures are those
    /// of combinations 0..=stopped_at, whatever the threads or workers.
    /// With --grid-steps, a hit at a coarse step ends the part.
    #[arg(long, value_name = "SCORE")]
    pub good_enough: Option<f64>,
    /// Give up on a part whose estimated work, segment combinations x
    /// segments (the same on every machine), is beyond COST: its status is
    /// `over_budget` with the estimate, and the run goes on. Checked
    /// before preparing too, on the edge tests preparing does (outline
    /// edges x all edges, a sound lower bound). The default, 10^11,
    /// passes parts of about 700 segments.
    #[arg(long, value_name = "COST", default_value_t = DEFAULT_PART_BUDGET)]
    pub part_budget: u64,
    /// Stop a part (each grid step of it) once it has more than N setups
    /// (SPEC's `setups` count): its status is `over_budget`, and the run
    /// goes on. Deterministic: the same parts stop whatever the threads or
    /// workers. The default, 10^7, is seconds to minutes of a core and 17
    /// times the largest example part (`housing-57-x3`); raise it for
    /// huge parts.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_PART_SETUPS)]
    pub part_setups: u64,
    /// Stop a part (each grid step of it) once it keeps more than N
    /// fixtures: with `--top-k 0` (or a part's `top_k = 0`) a part keeps
    /// every admissible fixture, and a big part on a big plate has
    /// millions. Its status is `over_budget`, no fixture of it is written,
    /// and the run goes on. Deterministic: the same parts stop whatever
    /// the threads or workers. Only bites when top-k is 0 or above N. A
    /// kept fixture costs about 2.6 KB at the peak of a run (shard
    /// results, merge, report and chunk: 11.4 GB max RSS for the 4.38 M
    /// fixtures of `housing-57` x3 with `--top-k 0`, 1.07 GB for the
    /// 413 k of x2), so the default, 250,000, keeps a part under about
    /// 650 MB, well under 2 GiB.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_PART_FIXTURES)]
    pub part_fixtures: u64,
    /// Stop a part still enumerating after S seconds of wall clock: its
    /// status is `over_budget`. NOT deterministic (it depends on the
    /// machine and its load); default: no time limit.
    #[arg(long, value_name = "S")]
    pub part_seconds: Option<f64>,
}

/// `--part-budget`'s default, in segment combinations x segments.
pub const DEFAULT_PART_BUDGET: u64 = 100_000_000_000;

impl SearchArgs {
    /// The search of every part of the run.
    pub fn options(&self) -> SearchOptions {
        SearchOptions {
            grid_steps: self.grid_steps.as_ref().map(|g| g.0.clone()),
            good_enough: self.good_enough,
            part_budget: Some(self.part_budget),
            part_setups: Some(self.part_setups),
            part_fixtures: Some(self.part_fixtures),
            part_seconds: self.part_seconds,
        }
    }
}

/// `fixplan study`.
pub fn study_cli_main(a: &StudyArgs, default_catalog: PathBuf) -> Result<StudyReport> {
    let opts = StudyOptions {
        catalog: a.catalog.clone().unwrap_or(default_catalog),
        kits: if a.kits.is_empty() {
            vec!["metric-25".into()]
        } else {
            a.kits.clone()
        },
        sweep: a.sweep.clone(),
        top_k: a.top_k,
        full_counts: a.full_counts,
        threads: a.threads,
        output: a.output.clone(),
        csv: a.csv.clone(),
        chart: a.chart.clone(),
        no_share: a.no_share,
        quiet: a.quiet,
        arcs: a.arcs,
        part_fixtures: Some(a.part_fixtures),
    };
    let copts = a.cluster.options(a.threads);
    study_main(&opts, copts.as_ref())
}
