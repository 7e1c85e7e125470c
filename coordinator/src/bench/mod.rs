//! Measurements, not tests: `fixplan bench` (where one part's enumeration
//! spends its time, on one thread) and `fixplan bench-cluster` (catalogue
//! throughput and the coordinator's share with local workers), `fixplan
//! bench-coordinator` (the coordinator's ceiling, with replayed results).
//! Uses `job`, `cluster` and `run`.

pub(crate) mod ceiling;
pub(crate) mod cluster;
pub(crate) mod parts;
pub(crate) mod replay;
pub(crate) mod replay_workers;
