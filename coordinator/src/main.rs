fn main() {
    fixplan_coordinator::cli::main()
}
