//! The `fixplan` command line, built inside this package so that the
//! workspace integration tests can run it (Cargo only gives tests the path of
//! their own package's binaries). Same code as the `fixplan` binary.

fn main() {
    fixplan_coordinator::main()
}
