//! Plain log lines on standard error, with the time since start and the
//! process role (`coordinator`, `worker NAME`).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::OnceLock;
use std::time::Instant;

static START: OnceLock<Instant> = OnceLock::new();
static QUIET: AtomicBool = AtomicBool::new(false);

/// Only warnings from now on.
pub fn set_quiet(q: bool) {
    QUIET.store(q, Ordering::SeqCst);
}

/// Starts the clock (idempotent).
pub fn init() {
    START.get_or_init(Instant::now);
}

pub fn line(level: &str, role: &str, msg: &str) {
    if level == "INFO" && QUIET.load(Ordering::SeqCst) {
        return;
    }
    let t = START.get_or_init(Instant::now).elapsed().as_secs_f64();
    // Not `eprintln!`: a closed stderr must not panic a worker or the
    // coordinator in the middle of a run.
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "[{t:9.3}s {level} {role}] {msg}");
}

#[macro_export]
macro_rules! info {
    ($role:expr, $($arg:tt)*) => { $crate::log::line("INFO", &$role, &format!($($arg)*)) };
}

#[macro_export]
macro_rules! warn {
    ($role:expr, $($arg:tt)*) => { $crate::log::line("WARN", &$role, &format!($($arg)*)) };
}
