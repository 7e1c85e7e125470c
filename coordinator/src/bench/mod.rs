//! Measurements, not tests: `fixplan bench` (where one part's enumeration
//! spends its time, on one thread) and `fixplan bench-cluster` (catalogue
//! throughput and the coordinator's share with local workers), `fixplan
//! bench-coordinator` (the coordinator's ceiling, with replayed results).
//! Uses `job`, `cluster` and `run`.

pub mod ceiling;
pub mod cluster;
pub mod parts;
pub mod replay;
pub mod replay_workers;
