//! CPU clocks, for the coordinator's figures: time it spent computing,
//! not waiting or preempted.

/// CPU time of `clock` in microseconds (0 if the clock cannot be read).
fn micros(clock: libc::clockid_t) -> u64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime only writes the struct it is given.
    if unsafe { libc::clock_gettime(clock, &mut t) } != 0 {
        return 0;
    }
    t.tv_sec as u64 * 1_000_000 + t.tv_nsec as u64 / 1000
}

/// CPU time of the calling thread.
pub fn thread_micros() -> u64 {
    micros(libc::CLOCK_THREAD_CPUTIME_ID)
}

/// CPU time of this process, all its threads (finished ones too).
pub fn process_micros() -> u64 {
    micros(libc::CLOCK_PROCESS_CPUTIME_ID)
}

/// `CLOCK_MONOTONIC` in microseconds: the clock `perf record -k
/// CLOCK_MONOTONIC` stamps its samples with, to profile a stretch of a
/// run (`fixplan bench-coordinator` prints its measured runs' bounds).
pub fn monotonic_micros() -> u64 {
    micros(libc::CLOCK_MONOTONIC)
}
