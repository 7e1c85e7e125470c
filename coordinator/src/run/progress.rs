//! Progress of a run: a bar on a terminal (parts done/total, fixtures found,
//! elapsed, ETA), one plain line per part otherwise; and the final summary.

use super::outcome::PartOutcome;
use fixplan_core::Status;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// Totals of a run, for the summary table.
#[derive(Debug, Clone, PartialEq)]
pub struct Totals {
    /// Parts with fixtures.
    pub ok: usize,
    /// Valid parts no fixture of the kit holds.
    pub no_fixture: usize,
    /// Parts that could not be read or prepared.
    pub invalid: usize,
    /// Parts whose solve failed (a solver panic), the run going on.
    pub failed: usize,
    /// Parts whose estimated work is beyond `--part-budget`.
    pub over_budget: usize,
    /// Admissible fixtures found, over all parts; `None` once a part did
    /// not count them (top-k mode).
    pub admissible: Option<u64>,
    /// Fixtures kept in the rankings (top-k per part).
    pub kept: usize,
    /// Parts taken from an interrupted run's file.
    pub resumed: usize,
}

impl Default for Totals {
    fn default() -> Self {
        Totals {
            ok: 0,
            no_fixture: 0,
            invalid: 0,
            failed: 0,
            over_budget: 0,
            admissible: Some(0),
            kept: 0,
            resumed: 0,
        }
    }
}

impl Totals {
    /// Parts done, whatever their outcome.
    pub fn parts(&self) -> usize {
        self.ok + self.no_fixture + self.invalid + self.failed + self.over_budget
    }

    /// Counts one part.
    pub fn add(&mut self, status: Status, admissible: Option<u64>, kept: usize) {
        match status {
            Status::Ok => self.ok += 1,
            Status::NoFixture => self.no_fixture += 1,
            Status::Invalid => self.invalid += 1,
            Status::Failed => self.failed += 1,
            Status::OverBudget => self.over_budget += 1,
        }
        self.admissible = self.admissible.zip(admissible).map(|(a, b)| a + b);
        self.kept += kept;
    }

    /// The fixtures found so far, for a person: the admissible count, or
    /// the kept ones when a part ran in top-k mode.
    fn found(&self) -> String {
        match self.admissible {
            Some(a) => format!("{a} fixtures found"),
            None => format!("{} fixtures kept", self.kept),
        }
    }
}

/// What a person watching a run sees: a bar on a terminal, plain lines in
/// a log, nothing with `--quiet`.
pub struct Progress {
    bar: Option<ProgressBar>,
    total: usize,
    start: Instant,
    /// Parts counted so far.
    pub totals: Totals,
    quiet: bool,
}

impl Progress {
    /// A bar if stderr is a terminal, plain lines otherwise (none if quiet).
    pub fn new(total: usize, quiet: bool) -> Progress {
        let bar = (!quiet && std::io::stderr().is_terminal()).then(|| {
            let b = ProgressBar::with_draw_target(Some(total as u64), ProgressDrawTarget::stderr());
            let style = ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {bar:30} {pos}/{len} parts  {msg}  ETA {eta}",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar());
            b.set_style(style);
            b.enable_steady_tick(Duration::from_millis(200));
            b
        });
        Progress {
            bar,
            total,
            start: Instant::now(),
            totals: Totals::default(),
            quiet,
        }
    }

    /// A line above the bar (or on its own without one).
    pub fn log(&self, line: &str) {
        if self.quiet {
            return;
        }
        match &self.bar {
            Some(b) => b.println(line),
            None => say(format_args!("{line}")),
        }
    }

    /// Parts already in the file when resuming.
    pub fn resumed(&mut self, status: Status, admissible: Option<u64>, kept: usize) {
        self.totals.add(status, admissible, kept);
        self.totals.resumed += 1;
        if let Some(b) = &self.bar {
            b.inc(1);
            b.reset_eta();
        }
    }

    /// Counts a written part and shows it.
    pub fn part_done(&mut self, outcome: &PartOutcome) {
        self.totals
            .add(outcome.status, outcome.admissible, outcome.kept);
        let done = self.totals.parts();
        match &self.bar {
            Some(b) => {
                if matches!(
                    outcome.status,
                    Status::Invalid | Status::Failed | Status::OverBudget
                ) {
                    let word = crate::view::show::status_word(outcome.status);
                    b.println(format!(
                        "{word}: {}",
                        outcome.error.as_deref().unwrap_or("?")
                    ));
                }
                b.set_message(self.totals.found());
                b.inc(1);
            }
            None if !self.quiet => {
                let what = match outcome.status {
                    Status::Ok => match outcome.admissible {
                        Some(a) => format!("ok, {a} fixtures"),
                        None => format!("ok, top {}", outcome.kept),
                    },
                    Status::NoFixture => "no fixture".to_string(),
                    Status::Invalid | Status::Failed | Status::OverBudget => format!(
                        "{}: {}",
                        crate::view::show::status_word(outcome.status),
                        outcome.error.as_deref().unwrap_or("?")
                    ),
                };
                say(format_args!(
                    "[{done}/{}] {}: {what}  ({} so far, {:.1} s)",
                    self.total,
                    outcome.id,
                    self.totals.found(),
                    self.start.elapsed().as_secs_f64()
                ));
            }
            None => {}
        }
    }

    /// Clears the bar before the summary is printed.
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }

    /// Time since the run started.
    pub fn elapsed(&self) -> Duration {
        self.start.elapsed()
    }
}

/// The terminal line of a part searched with `--grid-steps` or
/// `--good-enough`: what each step found, where the part stopped.
pub fn progress_line(outcome: &PartOutcome) -> Option<String> {
    let mut parts = Vec::new();
    for s in outcome.steps.iter().flatten() {
        let best = s.best_score.map_or("-".into(), |b| format!("{b:.4}"));
        let added = s.added.map_or("?".into(), |a| a.to_string());
        parts.push(format!(
            "step {}: +{added} fixtures, best {best}",
            s.grid_step
        ));
    }
    if let Some(h) = outcome.stopped_at {
        parts.push(format!("good enough at combination {h}"));
    }
    (!parts.is_empty()).then(|| format!("{}: {}", outcome.id, parts.join(" | ")))
}

/// The summary table printed at the end of a run.
pub fn summary_table(totals: &Totals, elapsed: Duration, output: &str) -> String {
    let mut s = String::new();
    let row = |s: &mut String, k: &str, v: String| s.push_str(&format!("  {k:<22} {v:>12}\n"));
    s.push_str(&format!(
        "fixplan run: {} parts -> {output}\n",
        totals.parts()
    ));
    row(&mut s, "ok", totals.ok.to_string());
    row(&mut s, "no_fixture", totals.no_fixture.to_string());
    row(&mut s, "invalid", totals.invalid.to_string());
    // Only when there are some: the table of a run where every part
    // finished stays as it was.
    if totals.failed > 0 {
        row(&mut s, "failed", totals.failed.to_string());
    }
    if totals.over_budget > 0 {
        row(&mut s, "over_budget", totals.over_budget.to_string());
    }
    let found = totals
        .admissible
        .map_or("not counted".into(), |a| a.to_string());
    row(&mut s, "fixtures found", found);
    row(&mut s, "fixtures kept (top-k)", totals.kept.to_string());
    if totals.resumed > 0 {
        row(&mut s, "resumed from file", totals.resumed.to_string());
    }
    row(&mut s, "time", format!("{:.2} s", elapsed.as_secs_f64()));
    s
}

/// A line on standard error. A closed stderr (`fixplan run 2>&1 | head`)
/// must not stop the run: `eprintln!` would panic, so the error is dropped.
fn say(args: std::fmt::Arguments) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "{args}");
}
