//! The `fixplan` binary: the command line of [`fixplan_coordinator::main`].

/// mimalloc rather than glibc's allocator: see the workspace manifest.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    fixplan_coordinator::main()
}
