//! `fixplan solve CASE.json`: one part, SPEC Appendix A in and out.

use fixplan_core::{solve_case, Case, SolveResult, Status};
use std::io::Write;
use std::path::Path;

/// Reads and solves a case file (`full_counts` over the file's own
/// `params.full_counts`). Every failure becomes an `invalid` result naming
/// the file and the problem, never a panic.
pub fn solve_file(path: &Path, full_counts: bool) -> SolveResult {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) => return SolveResult::invalid(format!("{}: cannot read: {e}", path.display())),
    };
    let mut case: Case = match serde_json::from_str(&text) {
        Ok(c) => c,
        Err(e) => return SolveResult::invalid(format!("{}: {e}", path.display())),
    };
    case.params.full_counts |= full_counts;
    let mut res = solve_case(&case);
    if res.status == Status::Invalid {
        if let Some(m) = res.error.take() {
            res.error = Some(format!("{}: {m}", path.display()));
        }
    }
    res
}

/// `fixplan solve`: prints the result JSON; exit code 2 for an invalid
/// part, so scripts can tell a bad input from a part with no fixture.
pub fn solve_main(case: &Path, threads: Option<usize>, full_counts: bool) -> anyhow::Result<()> {
    if let Some(n) = threads {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()?;
    }
    let res = solve_file(case, full_counts);
    // Written, not printed: `fixplan solve CASE | head` closes the pipe,
    // which `println!` turns into a panic and `main` into a quiet exit.
    let mut out = std::io::stdout().lock();
    writeln!(out, "{}", serde_json::to_string_pretty(&res)?)?;
    out.flush()?;
    if res.status == Status::Invalid {
        std::process::exit(2);
    }
    Ok(())
}
