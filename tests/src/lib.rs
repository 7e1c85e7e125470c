//! Workspace-level integration tests of fixplan: the command line end to
//! end (`solve`, `run`, `show`, `export`, `render`, `study`), MCAP files read
//! back by our reader and by Python's, resume after SIGKILL, and the cluster
//! (coordinator plus worker processes on this host over zenoh and iceoryx2,
//! failures, network namespaces). The tests run `fixplan-it`, this package's
//! build of the `fixplan` command line.
