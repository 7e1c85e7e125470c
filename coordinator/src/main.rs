//! The `fixplan` binary: the command line of [`fixplan_coordinator::cli`].

fn main() {
    fixplan_coordinator::cli::main()
}
