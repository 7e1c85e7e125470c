//! The default size of every thread pool the `fixplan` binary starts
//! (embedded runs, studies, local workers): this host's cores.

/// This host's cores, or 1 when the system will not say.
pub fn cores() -> usize {
    std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1)
}
