use anyhow::Result;
use clap::{Parser, Subcommand};
use fixplan_coordinator::solve_cmd::solve_file;
use fixplan_core::Status;
use std::path::PathBuf;

/// Design modular fixtures for planar parts: every fixture of three round
/// locators and one sliding clamp on a lattice plate that holds the part in
/// form closure, ranked by quality (Brost & Goldberg 1996, as in SPEC.md).
#[derive(Parser)]
#[command(name = "fixplan", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Solve one part from a case file (SPEC Appendix A) and print the
    /// ranked fixtures as JSON. `params.top_k: 0` prints all of them.
    ///
    /// Exit code 0 for `ok` and `no_fixture`, 2 for `invalid`.
    Solve {
        /// Case file: units, part, access, kit, params.
        case: PathBuf,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
    },
}

fn main() -> Result<()> {
    let cli = Cli::parse();
    match cli.cmd {
        Cmd::Solve { case, threads } => {
            if let Some(n) = threads {
                rayon::ThreadPoolBuilder::new().num_threads(n).build_global()?;
            }
            let res = solve_file(&case);
            println!("{}", serde_json::to_string_pretty(&res)?);
            if res.status == Status::Invalid {
                std::process::exit(2);
            }
        }
    }
    Ok(())
}
